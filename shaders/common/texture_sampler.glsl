// Software texture sampling for compute stages, operation for operation like
// Texture::sample in crates/translucid/src/scene/texture.rs: REPEAT addressing, texel centres
// at +0.5, bilinear within a level, linear between levels, sRGB decoded by table before
// filtering. Texels are packed RGBA8 in u_texels; u_srgbToLinear is the decode table.
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

uint wrapCoord(float c, uint size) {
    // Saturate like a float-to-i64 cast before the Euclidean remainder.
    int64_t i = int64_t(clamp(c, -4.0e18, 4.0e18));
    int64_t s = int64_t(size);
    int64_t r = i % s;
    return uint(r < 0 ? r + s : r);
}

vec4 sampleLevel(ExactTexture t, uint level, vec2 uv) {
    uint first = t.firstTexel;
    uint w = t.width;
    uint h = t.height;
    for (uint i = 0u; i < level; i++) {
        first += w * h;
        w = max(w >> 1, 1u);
        h = max(h >> 1, 1u);
    }
    precise float u = uv.x * float(w) - 0.5;
    precise float v = uv.y * float(h) - 0.5;
    float fi = floor(u);
    float fj = floor(v);
    precise float a = u - fi;
    precise float b = v - fj;
    uint i0 = wrapCoord(fi, w);
    uint j0 = wrapCoord(fj, h);
    uint i1 = (i0 + 1u) % w;
    uint j1 = (j0 + 1u) % h;
    bool srgb = t.srgb != 0u;
    vec4 t00 = decodeTexel(texelFetch(u_texels, int(first + j0 * w + i0)).r, srgb);
    vec4 t10 = decodeTexel(texelFetch(u_texels, int(first + j0 * w + i1)).r, srgb);
    vec4 t01 = decodeTexel(texelFetch(u_texels, int(first + j1 * w + i0)).r, srgb);
    vec4 t11 = decodeTexel(texelFetch(u_texels, int(first + j1 * w + i1)).r, srgb);
    precise vec4 r = (t00 * (1.0 - a) + t10 * a) * (1.0 - b) + (t01 * (1.0 - a) + t11 * a) * b;
    return r;
}

vec4 sampleTexture(ExactTexture t, vec2 uv, float lod) {
    float top = float(t.levels - 1u);
    float l = lod > 0.0 ? min(lod, top) : 0.0;
    float level = floor(l);
    precise float blend = l - level;
    uint d = uint(level);
    vec4 lower = sampleLevel(t, d, uv);
    if (blend == 0.0 || d >= t.levels - 1u) {
        return lower;
    }
    precise vec4 r = lower * (1.0 - blend) + sampleLevel(t, d + 1u, uv) * blend;
    return r;
}

#endif
