#version 450
// Accumulation, every output summed by an ADD blend, per channel: weighted radiance, weighted
// opacity, and absorbance -ln T (the revealage is its exponential: a sum instead of a product
// keeps every attachment's blend the same, which needs no independentBlend feature).

#include "mesh_fragment.glsl"
#include "shading.glsl"
#include "wboit.glsl"

layout(location = 0) out vec4 o_radiance;
layout(location = 1) out vec4 o_opacity;
layout(location = 2) out vec4 o_absorbance;

void main() {
    DrawInfo d = g_draws[u_push.drawIndex];
    Material m = g_materials[d.materialIndex];
    vec3 radiance;
    vec3 transmittance;
    shadeTransparent(m, u_frame, v_colour, sampleBaseTexture(m), fragmentNormal(d), radiance,
                     transmittance);
    vec3 alpha = 1.0 - transmittance;
    float w = wboitWeight(alpha, gl_FragCoord.z);
    o_radiance = vec4(w * radiance, 0.0);
    o_opacity = vec4(w * alpha, 0.0);
    o_absorbance = vec4(-log(max(transmittance, vec3(WBOIT_MIN_TRANSMITTANCE))), 0.0);
}
