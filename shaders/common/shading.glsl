// The shading function of every method; mirrors crates/translucid/src/shading.rs exactly
// (a test compares them). Needs layout.glsl.
#ifndef TRANSLUCID_SHADING_GLSL
#define TRANSLUCID_SHADING_GLSL

#include "layout.glsl"

vec3 shadeLighting(Material m, FrameInfo f, vec3 normal) {
    if ((m.flags & MATERIAL_LIT) == 0u) {
        return vec3(1.0);
    }
    float len2 = dot(normal, normal);
    vec3 n = len2 > 0.0 ? normal * inversesqrt(len2) : vec3(0.0);
    return f.ambient.rgb + f.lightColour.rgb * abs(dot(n, f.lightDirection.xyz));
}

vec4 shadeBaseColour(Material m, vec4 vertexColour, vec4 texel) {
    return m.baseColour * vertexColour * texel;
}

// Premultiplied radiance L (out radiance) and per-channel transmittance T (out transmittance).
void shadeTransparent(Material m, FrameInfo f, vec4 vertexColour, vec4 texel, vec3 normal,
                      out vec3 radiance, out vec3 transmittance) {
    vec4 base = shadeBaseColour(m, vertexColour, texel);
    float a = clamp(base.a, 0.0, 1.0);
    vec3 lit = shadeLighting(m, f, normal);
    float t = m.tintTransmission.w;
    float r = m.reflectance;
    radiance = a * ((1.0 - t) * base.rgb * lit + t * r * lit);
    transmittance = clamp(vec3(1.0 - a) + a * t * (1.0 - r) * m.tintTransmission.rgb * base.rgb,
                          vec3(0.0), vec3(1.0));
}

// Opaque colour; false when the alpha cutoff discards the fragment.
bool shadeOpaque(Material m, FrameInfo f, vec4 vertexColour, vec4 texel, vec3 normal,
                 out vec3 colour) {
    vec4 base = shadeBaseColour(m, vertexColour, texel);
    colour = base.rgb * shadeLighting(m, f, normal);
    return !(m.alphaCutoff >= 0.0 && base.a < m.alphaCutoff);
}

#endif
