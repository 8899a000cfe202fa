// The rasterization rules of crates/translucid/src/raster.rs applied to the bins' triangle
// records (raster_rules.glsl holds the rules themselves), so that the exact method covers the
// same samples as the CPU reference and interpolates the same values.
#ifndef TRANSLUCID_RASTER_GLSL
#define TRANSLUCID_RASTER_GLSL

#include "bin_triangle.glsl"

#include "raster_rules.glsl"

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
    s = interpolateEdges(e, t.zNdc, t.invW.xyz);
    return depthClip(s.zNdc);
}

bool sampleFixed(BinTriangle t, uint x, uint y, out RasterSample s) {
    i64vec3 e;
    return coversFixed(t, x, y, e) && interpolateFixed(t, e, s);
}

float lineAt(vec4 line, uint x, uint y) {
    precise float v = (line.x * (float(x) + 0.5) + line.y * (float(y) + 0.5)) + line.z;
    return v;
}

bool homogeneousEdgeCovers(BinHomogeneous h, int k, vec4 line, uint x, uint y) {
    if (((h.fixedA.w >> k) & 1) != 0) {
        int64_t e = edgeAt(h.fixedA[k], h.fixedB[k], h.fixedC[k], x, y);
        return e + int64_t((h.fixedB.w >> k) & 1) > 0;
    }
    float v = lineAt(line, x, y);
    return v > 0.0 || (v == 0.0 && (line.x > 0.0 || (line.x == 0.0 && line.y > 0.0)));
}

// A sample on the homogeneous path, from the lines of the vertices scaled by 2^-e
// (raster.rs: the weights' sum is 2^e / w).
bool sampleHomogeneous(BinHomogeneous h, uint x, uint y, out RasterSample s) {
    if (!homogeneousEdgeCovers(h, 0, h.line0, x, y) || !homogeneousEdgeCovers(h, 1, h.line1, x, y) ||
        !homogeneousEdgeCovers(h, 2, h.line2, x, y)) {
        return false;
    }
    precise float e0 = lineAt(h.line0, x, y) * h.zInvDet.w;
    precise float e1 = lineAt(h.line1, x, y) * h.zInvDet.w;
    precise float e2 = lineAt(h.line2, x, y) * h.zInvDet.w;
    precise float sum = (e0 + e1) + e2;
    if (!(sum > 0.0)) {
        return false;
    }
    precise float d = quotient(1.0, sum);
    precise float z = (e0 * h.zInvDet.x + e1 * h.zInvDet.y) + e2 * h.zInvDet.z;
    precise vec3 b = vec3(e0 * d, e1 * d, e2 * d);
    s.barycentric = b;
    s.zNdc = z;
    s.viewDepth = scaleByPowerOfTwo(d, int(h.line0.w));
    return depthClip(s.zNdc);
}

#endif
