// Software texture sampling for compute stages, operation for operation like
// Texture::sample in crates/translucid/src/scene/texture.rs (whose doc states the rules): the
// texture's sampler word (SAMPLER_* in interface_bins.glsl) picks the wrap mode of each axis,
// the mag and min filters and the mipmap mode; sRGB is decoded by table before filtering.
// Texels are packed RGBA8 in u_texels; u_srgbToLinear is the decode table.
#ifndef TRANSLUCID_TEXTURE_SAMPLER_GLSL
#define TRANSLUCID_TEXTURE_SAMPLER_GLSL

#extension GL_EXT_shader_explicit_arithmetic_types_int64 : require

vec4 decodeTexel(uint packed, bool srgb) {
    uvec4 c = uvec4(packed & 0xFFu, (packed >> 8) & 0xFFu, (packed >> 16) & 0xFFu, packed >> 24);
    precise vec4 unorm = vec4(c) / 255.0;
    if (srgb) {
        return vec4(texelFetch(u_srgbToLinear, int(c.x)).r, texelFetch(u_srgbToLinear, int(c.y)).r,
                    texelFetch(u_srgbToLinear, int(c.z)).r, unorm.w);
    }
    return unorm;
}

// floor(c) (an integer, saturated like a float-to-i64 cast) modulo `period`, in [0, period).
// Coordinates within 2^31 take a 32-bit remainder, which a GPU runs several times faster than
// a 64-bit one; only absurd texture coordinates pay for 64 bits.
uint wrappedIndex(float c, int64_t i, uint period) {
    if (abs(c) < 2147483648.0) {
        int r = int(c) % int(period);
        return uint(r < 0 ? r + int(period) : r);
    }
    int64_t r = i % int64_t(period);
    return uint(r < 0 ? r + int64_t(period) : r);
}

// Texel coordinate c = floor(c) and the one after it, wrapped into [0, size) by `mode`
// (SAMPLER_WRAP_*). One remainder by the mirrored period serves every mode: repeat and mirror
// both read it, and clamping needs none. (The period fits 32 bits for any image a device can
// create.)
uvec2 wrapPair(float c, uint size, uint mode) {
    // Saturate like a float-to-i64 cast, with room for + 1.
    int64_t i = int64_t(clamp(c, -4.0e18, 4.0e18));
    uint period = 2u * size;
    uint p0 = wrappedIndex(c, i, period);
    uint p1 = p0 + 1u == period ? 0u : p0 + 1u;
    uvec2 repeated = uvec2(p0 >= size ? p0 - size : p0, p1 >= size ? p1 - size : p1);
    uvec2 mirrored = uvec2(p0 < size ? p0 : period - 1u - p0, p1 < size ? p1 : period - 1u - p1);
    int64_t last = int64_t(size) - 1;
    uvec2 clamped = uvec2(uint(clamp(i, 0l, last)), uint(clamp(i + 1, 0l, last)));
    return mode == SAMPLER_WRAP_CLAMP_TO_EDGE ? clamped
         : (mode == SAMPLER_WRAP_MIRRORED_REPEAT ? mirrored : repeated);
}

// One level, bilinear or nearest (its texel alone, weighted 1).
vec4 sampleLevel(BinTexture t, uint level, vec2 uv, bool linear) {
    uint first = t.firstTexel;
    uint w = t.width;
    uint h = t.height;
    for (uint i = 0u; i < level; i++) {
        first += w * h;
        w = max(w >> 1, 1u);
        h = max(h >> 1, 1u);
    }
    float shift = linear ? 0.5 : 0.0;
    precise float u = uv.x * float(w) - shift;
    precise float v = uv.y * float(h) - shift;
    float fi = floor(u);
    float fj = floor(v);
    precise float fa = u - fi;
    precise float fb = v - fj;
    float a = linear ? fa : 0.0;
    float b = linear ? fb : 0.0;
    uvec2 i = wrapPair(fi, w, (t.samplerBits >> SAMPLER_WRAP_S_SHIFT) & SAMPLER_WRAP_MASK);
    uvec2 j = wrapPair(fj, h, (t.samplerBits >> SAMPLER_WRAP_T_SHIFT) & SAMPLER_WRAP_MASK);
    bool srgb = t.srgb != 0u;
    vec4 t00 = decodeTexel(texelFetch(u_texels, int(first + j.x * w + i.x)).r, srgb);
    vec4 t10 = decodeTexel(texelFetch(u_texels, int(first + j.x * w + i.y)).r, srgb);
    vec4 t01 = decodeTexel(texelFetch(u_texels, int(first + j.y * w + i.x)).r, srgb);
    vec4 t11 = decodeTexel(texelFetch(u_texels, int(first + j.y * w + i.y)).r, srgb);
    precise vec4 r = (t00 * (1.0 - a) + t10 * a) * (1.0 - b) + (t01 * (1.0 - a) + t11 * a) * b;
    return r;
}

// Texture t at uv and level of detail lod: magnified (lod <= 0, or NaN) with the mag filter
// at level 0; minified with the min filter at the levels the mipmap mode picks.
vec4 sampleTexture(BinTexture t, vec2 uv, float lod) {
    bool magnified = !(lod > 0.0);
    bool linear = (t.samplerBits & (magnified ? SAMPLER_MAG_LINEAR : SAMPLER_MIN_LINEAR)) != 0u;
    uint mip = magnified ? SAMPLER_MIP_NONE : (t.samplerBits >> SAMPLER_MIP_SHIFT) & SAMPLER_MIP_MASK;
    float l = magnified ? 0.0 : min(lod, float(t.levels - 1u));
    // Vulkan's nearest level is ceil(lod + 0.5) - 1: halves round down.
    float nearest = ceil(l + 0.5) - 1.0;
    float below = floor(l);
    precise float between = l - below;
    float level = mip == SAMPLER_MIP_LINEAR ? below : (mip == SAMPLER_MIP_NEAREST ? nearest : 0.0);
    float blend = mip == SAMPLER_MIP_LINEAR ? between : 0.0;
    uint d = uint(level);
    vec4 lower = sampleLevel(t, d, uv, linear);
    if (blend == 0.0 || d >= t.levels - 1u) {
        return lower;
    }
    precise vec4 r = lower * (1.0 - blend) + sampleLevel(t, d + 1u, uv, linear) * blend;
    return r;
}

// The base texture of a material: texture `index`, whose record is `t`, at uv and level of
// detail lod. In software, bit for bit the reference's (sampleTexture). Where the raster
// samples in hardware (HARDWARE_SAMPLING, defined by the variants the host picks on GPUs:
// docs/gpu.md), the texture's own image and sampler at the same level, as the graphics
// passes sample it: filtering within the driver's precision of the reference's. The lanes
// of a tile may each want another texture, and indexing the array by a lane's own index
// is an optional feature (lavapipe lacks it): each slot is a branch of its own, with a
// constant index, which a GPU skips where no lane of the subgroup takes it (written out,
// so that it costs the loop budget nothing).
#ifdef HARDWARE_SAMPLING
#include "interface_texture_array.glsl"

// Texel coordinates from 2^20 on (or NaN) keep the software sampler: there a float
// coordinate resolves an eighth of a texel or less, and what the reference's wrap makes of
// its rounded coordinate is not what a hardware sampler's makes (72/255 off at 2^31).
const float HARDWARE_TEXELS = 1048576.0;
#endif

vec4 sampleBaseTexture(int index, BinTexture t, vec2 uv, float lod) {
#ifdef HARDWARE_SAMPLING
    vec2 texels = abs(uv) * vec2(t.width, t.height);
    if (!(max(texels.x, texels.y) < HARDWARE_TEXELS)) {
        return sampleTexture(t, uv, lod);
    }
    // Magnified where lod <= 0 or NaN, as in sampleTexture.
    float level = lod > 0.0 ? lod : 0.0;
    vec4 texel = vec4(1.0);
    [[unroll]] for (int slot = 0; slot < int(TEXTURE_ARRAY_SLOTS); slot++) {
        if (index == slot) {
            texel = textureLod(u_textureArray[slot], uv, level);
        }
    }
    return texel;
#else
    return sampleTexture(t, uv, lod);
#endif
}

#endif
