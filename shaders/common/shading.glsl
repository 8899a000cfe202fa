// The shading function of every method; mirrors crates/translucid/src/shading.rs exactly
// (a test compares them). Needs interface_scene.glsl.
#ifndef TRANSLUCID_SHADING_GLSL
#define TRANSLUCID_SHADING_GLSL

#include "interface_scene.glsl"
#include "colour.glsl"

// v divided by its largest component, or zero when it has no direction (zero, NaN or
// infinite): a vector at any scale brought to one where squares and cross products neither
// underflow nor overflow (shading::to_unit_scale).
vec3 toUnitScale(vec3 v) {
    float largest = max(max(abs(v.x), abs(v.y)), abs(v.z));
    return largest > 0.0 && !isinf(largest) ? v / largest : vec3(0.0);
}

// v at unit length, or zero when it has no direction, at any scale (shading::unit_or_zero).
vec3 unitOrZero(vec3 v) {
    vec3 scaled = toUnitScale(v);
    float length2 = dot(scaled, scaled);
    return length2 > 0.0 ? scaled * inversesqrt(length2) : vec3(0.0);
}

// The face normal of a triangle with edges e1 and e2, at any scale (shading::face_normal).
vec3 faceNormal(vec3 e1, vec3 e2) {
    return cross(toUnitScale(e1), toUnitScale(e2));
}

vec3 shadeLighting(Material m, FrameInfo f, vec3 normal) {
    if ((m.flags & MATERIAL_LIT) == 0u) {
        return vec3(1.0);
    }
    vec3 n = unitOrZero(normal);
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
    radiance = a * min((1.0 - t) * base.rgb * lit + t * r * lit, vec3(MAX_COLOUR));
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
