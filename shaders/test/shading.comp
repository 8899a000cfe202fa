#version 450
// Test only: evaluates the shared shading function on a table of inputs so a host test can
// compare it with the Rust implementation.

#include "interface_scene.glsl"
#include "shading.glsl"

layout(local_size_x = 64) in;

struct ShadingCase {
    vec4 vertexColour;
    vec4 texel;
    vec4 normal;            // xyz
    uint materialIndex;
    uint pad0;
    uint pad1;
    uint pad2;
};

struct ShadingResult {
    vec4 radiance;          // xyz
    vec4 transmittance;     // xyz
    vec4 opaque;            // xyz colour, w: 1 kept, 0 discarded
};

layout(set = 0, binding = 0, std140) uniform FrameBlock { FrameInfo u_frame; };
layout(set = 0, binding = 1, std430) readonly buffer MaterialBlock { Material g_materials[]; };
layout(set = 0, binding = 2, std430) readonly buffer CaseBlock { ShadingCase g_cases[]; };
layout(set = 0, binding = 3, std430) writeonly buffer ResultBlock { ShadingResult g_results[]; };

layout(push_constant) uniform PushBlock { uint count; } u_push;

void main() {
    uint i = gl_GlobalInvocationID.x;
    if (i >= u_push.count) {
        return;
    }
    ShadingCase c = g_cases[i];
    Material m = g_materials[c.materialIndex];
    vec3 radiance;
    vec3 transmittance;
    shadeTransparent(m, u_frame, c.vertexColour, c.texel, c.normal.xyz, radiance, transmittance);
    vec3 colour;
    bool kept = shadeOpaque(m, u_frame, c.vertexColour, c.texel, c.normal.xyz, colour);
    g_results[i].radiance = vec4(radiance, 0.0);
    g_results[i].transmittance = vec4(transmittance, 0.0);
    g_results[i].opaque = vec4(colour, kept ? 1.0 : 0.0);
}
