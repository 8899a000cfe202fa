#version 450
// Test only: the software sampler (texture_sampler.glsl) and a hardware sampler on a table of
// cases, so that a host test can hold both to values worked out by hand.

#extension GL_EXT_shader_explicit_arithmetic_types_int64 : require

#include "bin_triangle.glsl"

layout(local_size_x = 64) in;

struct SamplerCase {
    vec2 uv;
    float lod;
    uint pad;
};

layout(set = 0, binding = 0) uniform usamplerBuffer u_texels;
layout(set = 0, binding = 1) uniform samplerBuffer u_srgbToLinear;
layout(set = 0, binding = 2, std430) readonly buffer TextureBlock { BinTexture g_textures[]; };
layout(set = 0, binding = 3, std430) readonly buffer CaseBlock { SamplerCase g_cases[]; };
// Two results a case: the software sampler's, then the hardware's.
layout(set = 0, binding = 4, std430) writeonly buffer ResultBlock { vec4 g_results[]; };
layout(set = 0, binding = 5) uniform sampler2D u_hardware;

layout(push_constant) uniform PushBlock {
    uint caseIndex;
    uint textureIndex;
} u_push;

#include "texture_sampler.glsl"

void main() {
    // One case a dispatch: each has its own texture and hardware sampler.
    if (gl_GlobalInvocationID.x != 0u) {
        return;
    }
    SamplerCase c = g_cases[u_push.caseIndex];
    g_results[2u * u_push.caseIndex] = sampleTexture(g_textures[u_push.textureIndex], c.uv, c.lod);
    g_results[2u * u_push.caseIndex + 1u] = textureLod(u_hardware, c.uv, c.lod);
}
