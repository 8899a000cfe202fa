#version 450
// Unsorted blending: each fragment composites over what is behind it, in submission order.
// Output 0 is premultiplied radiance L, output 1 the per-channel transmittance T; the blend
// state computes dst = L + T * dst (dual-source), which is "over" for polychrome T.

#include "mesh_fragment.glsl"
#include "shading.glsl"

layout(location = 0, index = 0) out vec4 o_radiance;
layout(location = 0, index = 1) out vec4 o_transmittance;

void main() {
    DrawInfo d = g_draws[u_push.drawIndex];
    Material m = g_materials[d.materialIndex];
    vec3 radiance;
    vec3 transmittance;
    shadeTransparent(m, u_frame, v_colour, sampleBaseTexture(m), fragmentNormal(d), radiance,
                     transmittance);
    o_radiance = vec4(radiance, 0.0);
    o_transmittance = vec4(transmittance, 1.0);
}
