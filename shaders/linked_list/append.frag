#version 450
// The linked_list method's first pass: every transparent fragment nearer than the opaque
// layer (tested before the shader runs, so hidden ones append nothing) is shaded and pushed
// onto its pixel's list. A fragment that finds the pool full is blended at once, unsorted,
// over the opaque layer (dual-source "over", as blend.frag): the tail the resolve then
// composites the sorted ones over.

#define ORDER_DEPTH
#include "mesh_fragment.glsl"
#include "shading.glsl"
#include "linked_list.glsl"

layout(early_fragment_tests) in;

layout(location = 0, index = 0) out vec4 o_radiance;
layout(location = 0, index = 1) out vec4 o_transmittance;

void main() {
    DrawInfo d = g_draws[u_push.drawIndex];
    Material m = g_materials[d.materialIndex];
    vec3 radiance;
    vec3 transmittance;
    shadeTransparent(m, u_frame, v_colour, sampleBaseTexture(m), fragmentNormal(d), radiance,
                     transmittance);
    uint node = atomicAdd(g_list.fragments, 1u);
    if (node < g_list.capacity) {
        uint at = node * NODE_WORDS;
        setNodeWord(at, packHalf2x16(radiance.rg));
        setNodeWord(at + 1u, packHalf2x16(vec2(radiance.b, transmittance.r)));
        setNodeWord(at + 2u, packHalf2x16(transmittance.gb));
        setNodeWord(at + NODE_DEPTH, floatBitsToUint(fragmentOrderDepth()));
        setNodeWord(at + 4u, u_push.drawIndex);
        setNodeWord(at + 5u, uint(gl_PrimitiveID));
        setNodeWord(at + NODE_NEXT,
                    atomicExchange(g_heads[headIndex(uvec2(gl_FragCoord.xy))], node));
        // Nothing blended now: the resolve composites it in order.
        o_radiance = vec4(0.0);
        o_transmittance = vec4(1.0);
    } else {
        o_radiance = vec4(radiance, 0.0);
        o_transmittance = vec4(transmittance, 1.0);
    }
}
