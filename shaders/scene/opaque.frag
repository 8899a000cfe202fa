#version 450
// The opaque layer: depth-tested, depth-writing, shaded with the shared function.

#include "mesh_fragment.glsl"
#include "shading.glsl"

layout(location = 0) out vec4 o_colour;

void main() {
    DrawInfo d = g_draws[u_push.drawIndex];
    Material m = g_materials[d.materialIndex];
    vec3 colour;
    if (!shadeOpaque(m, u_frame, v_colour, sampleBaseTexture(m), fragmentNormal(d), colour)) {
        discard;
    }
    o_colour = vec4(colour, 1.0);
}
