// The rasterization rules of crates/translucid/src/raster.rs, operation for operation, for
// every shader that must cover or order samples as the CPU reference does: the exact
// method's setup and raster, and the mesh pipelines' order depth (mesh_fragment.glsl).
// `precise` keeps the compiler from fusing multiply-adds the reference does not fuse.
#ifndef TRANSLUCID_RASTER_RULES_GLSL
#define TRANSLUCID_RASTER_RULES_GLSL

#extension GL_EXT_shader_explicit_arithmetic_types_int64 : require

#include "interface_raster.glsl"
#include "rounded_division.glsl"

// view_projection * model, column by column as clipPosition (raster::model_view_projection).
mat4 modelViewProjection(mat4 viewProjection, mat4 model) {
    precise mat4 r;
    for (int j = 0; j < 4; j++) {
        r[j] = ((viewProjection[0] * model[j].x + viewProjection[1] * model[j].y) +
                viewProjection[2] * model[j].z) +
               viewProjection[3] * model[j].w;
    }
    return r;
}

// mvp * (p, 1) as ((c0 x + c1 y) + c2 z) + c3.
vec4 clipPosition(mat4 mvp, vec3 p) {
    precise vec4 r = ((mvp[0] * p.x + mvp[1] * p.y) + mvp[2] * p.z) + mvp[3];
    return r;
}

// (x_fb, y_fb, z_ndc) of a clip-space vertex.
vec3 viewportTransform(vec4 clip, vec2 size) {
    precise float x = (quotient(clip.x, clip.w) * 0.5 + 0.5) * size.x;
    precise float y = (quotient(clip.y, clip.w) * 0.5 + 0.5) * size.y;
    precise float z = quotient(clip.z, clip.w);
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

// The exponent e of a finite m >= 0: 2^e <= m < 2^(e+1), or -127 when m is 0 or subnormal
// (raster::exponent_of).
int exponentOf(float m) {
    return int((floatBitsToUint(m) >> 23) & 0xFFu) - 127;
}

// 2^k, for k in [-126, 127].
float powerOfTwo(int k) {
    return uintBitsToFloat(uint(k + 127) << 23);
}

// v * 2^k for k in [-127, 127], exact when the result is normal (raster::scale_by_power_of_two).
float scaleByPowerOfTwo(float v, int k) {
    precise float r = v * powerOfTwo(k / 2) * powerOfTwo(k - k / 2);
    return r;
}

struct RasterSample {
    vec3 barycentric;
    float zNdc;
    float viewDepth;
};

bool depthClip(float z) {
    return z >= 0.0 && z <= 1.0;
}

// Interpolation of a fixed-point sample from its edge values `e`: the vertices' device
// depths and the inverse of the doubled area in `zNdcInvArea`, their 1 / w in `invW`.
RasterSample interpolateEdges(i64vec3 e, vec4 zNdcInvArea, vec3 invW) {
    precise float l0 = float(e.x) * zNdcInvArea.w;
    precise float l1 = float(e.y) * zNdcInvArea.w;
    precise float l2 = float(e.z) * zNdcInvArea.w;
    precise float z = (l0 * zNdcInvArea.x + l1 * zNdcInvArea.y) + l2 * zNdcInvArea.z;
    precise float q0 = l0 * invW.x;
    precise float q1 = l1 * invW.y;
    precise float q2 = l2 * invW.z;
    // Rounding may carry an interpolated depth a little past the vertices' range; clamped
    // back (1 / w here, before the one division), every fragment of a triangle whose
    // vertices share a depth has exactly that depth, and none is nearer than the nearest
    // vertex, which is where the bins place the triangle (bin_lists.glsl).
    precise float inverse = min(max((q0 + q1) + q2, min(min(invW.x, invW.y), invW.z)),
                                max(max(invW.x, invW.y), invW.z));
    precise float depth = quotient(1.0, inverse);
    precise vec3 b = vec3(q0 * depth, q1 * depth, q2 * depth);
    RasterSample s;
    s.barycentric = b;
    s.zNdc = min(max(z, min(min(zNdcInvArea.x, zNdcInvArea.y), zNdcInvArea.z)),
                 max(max(zNdcInvArea.x, zNdcInvArea.y), zNdcInvArea.z));
    s.viewDepth = depth;
    return s;
}

#endif
