// The rasterization rules of crates/translucid/src/raster.rs, operation for operation, so that
// the exact method covers the same samples as the CPU reference and interpolates the same
// values. `precise` keeps the compiler from fusing multiply-adds the reference does not fuse.
#ifndef TRANSLUCID_RASTER_GLSL
#define TRANSLUCID_RASTER_GLSL

#include "bins_layout.glsl"

#define SUBPIXEL_BITS 8
#define HALF_PIXEL 128
#define GUARD_BAND 1048576.0

// mvp * (p, 1) as ((c0 x + c1 y) + c2 z) + c3.
vec4 clipPosition(mat4 mvp, vec3 p) {
    precise vec4 r = ((mvp[0] * p.x + mvp[1] * p.y) + mvp[2] * p.z) + mvp[3];
    return r;
}

// (x_fb, y_fb, z_ndc) of a clip-space vertex.
vec3 viewportTransform(vec4 clip, vec2 size) {
    precise float x = (clip.x / clip.w * 0.5 + 0.5) * size.x;
    precise float y = (clip.y / clip.w * 0.5 + 0.5) * size.y;
    precise float z = clip.z / clip.w;
    return vec3(x, y, z);
}

int64_t snapCoord(float v) {
    precise float s = v * 256.0 + 0.5;
    return int64_t(floor(s));
}

// Sample positions fit 32 bits (x < 2^16, 8 sub-pixel bits), and so do a and b: products of
// two sign-extended 32-bit values compile to one 32x32->64 multiply on x86, where a full
// 64-bit product is emulated (exact either way; 1-3 % of the raster on lavapipe).
int64_t edgeAt(int a, int b, int64_t c, uint x, uint y) {
    int px = (int(x) << SUBPIXEL_BITS) + HALF_PIXEL;
    int py = (int(y) << SUBPIXEL_BITS) + HALF_PIXEL;
    return int64_t(a) * int64_t(px) + int64_t(b) * int64_t(py) + c;
}

bool ownsTies(int64_t a, int64_t b) {
    return a > 0 || (a == 0 && b > 0);
}

struct RasterSample {
    vec3 barycentric;
    float zNdc;
    float viewDepth;
};

bool depthClip(float z) {
    return z >= 0.0 && z <= 1.0;
}

// Coverage of a fixed-point triangle at pixel (x, y): the three edge values, and whether the
// sample is inside under the tie rule.
bool coversFixed(BinTriangle t, uint x, uint y, out i64vec3 e) {
    e.x = edgeAt(t.edgeA.x, t.edgeB.x, t.edgeC.x, x, y);
    e.y = edgeAt(t.edgeA.y, t.edgeB.y, t.edgeC.y, x, y);
    e.z = edgeAt(t.edgeA.z, t.edgeB.z, t.edgeC.z, x, y);
    int ties = t.edgeA.w;
    return e.x + int64_t(ties & 1) > 0 && e.y + int64_t((ties >> 1) & 1) > 0 &&
           e.z + int64_t((ties >> 2) & 1) > 0;
}

// Interpolation of a covered fixed-point sample from its edge values; false when the depth
// clip discards it.
bool interpolateFixed(BinTriangle t, i64vec3 e, out RasterSample s) {
    precise float l0 = float(e.x) * t.zNdc.w;
    precise float l1 = float(e.y) * t.zNdc.w;
    precise float l2 = float(e.z) * t.zNdc.w;
    precise float z = (l0 * t.zNdc.x + l1 * t.zNdc.y) + l2 * t.zNdc.z;
    precise float q0 = l0 * t.invW.x;
    precise float q1 = l1 * t.invW.y;
    precise float q2 = l2 * t.invW.z;
    precise float depth = 1.0 / ((q0 + q1) + q2);
    precise vec3 b = vec3(q0 * depth, q1 * depth, q2 * depth);
    s.barycentric = b;
    s.zNdc = z;
    s.viewDepth = depth;
    return depthClip(z);
}

bool sampleFixed(BinTriangle t, uint x, uint y, out RasterSample s) {
    i64vec3 e;
    return coversFixed(t, x, y, e) && interpolateFixed(t, e, s);
}

double lineAt(dvec4 line, uint x, uint y) {
    precise double v = (line.x * (double(x) + 0.5) + line.y * (double(y) + 0.5)) + line.z;
    return v;
}

bool homogeneousEdgeCovers(BinHomogeneous h, int k, dvec4 line, uint x, uint y) {
    if (((h.fixedA.w >> k) & 1) != 0) {
        int64_t e = edgeAt(h.fixedA[k], h.fixedB[k], h.fixedC[k], x, y);
        return e + int64_t((h.fixedB.w >> k) & 1) > 0;
    }
    double v = lineAt(line, x, y);
    return v > 0.0 || (v == 0.0 && (line.x > 0.0 || (line.x == 0.0 && line.y > 0.0)));
}

bool sampleHomogeneous(BinHomogeneous h, uint x, uint y, out RasterSample s) {
    if (!homogeneousEdgeCovers(h, 0, h.line0, x, y) || !homogeneousEdgeCovers(h, 1, h.line1, x, y) ||
        !homogeneousEdgeCovers(h, 2, h.line2, x, y)) {
        return false;
    }
    precise double e0 = lineAt(h.line0, x, y) * h.zInvDet.w;
    precise double e1 = lineAt(h.line1, x, y) * h.zInvDet.w;
    precise double e2 = lineAt(h.line2, x, y) * h.zInvDet.w;
    precise double sum = (e0 + e1) + e2;
    if (!(sum > 0.0)) {
        return false;
    }
    precise double depth = 1.0 / sum;
    precise double z = (e0 * h.zInvDet.x + e1 * h.zInvDet.y) + e2 * h.zInvDet.z;
    s.barycentric = vec3(float(e0 * depth), float(e1 * depth), float(e2 * depth));
    s.zNdc = float(z);
    s.viewDepth = float(depth);
    return depthClip(s.zNdc);
}

#endif
