// Descriptor set 1 of the exact method's stages (set 0 is the scene's: frame, draws, materials).
#ifndef TRANSLUCID_EXACT_BINDINGS_GLSL
#define TRANSLUCID_EXACT_BINDINGS_GLSL

#include "exact_layout.glsl"

layout(set = 1, binding = 0, std430) readonly buffer VertexBlock { float g_vertexData[]; };
layout(set = 1, binding = 1, std430) readonly buffer QuadBlock { uvec4 g_quads[]; };
layout(set = 1, binding = 2, std430) readonly buffer ExactDrawBlock { ExactDraw g_exactDraws[]; };
layout(set = 1, binding = 3, std430) buffer TriangleBlock { ExactTriangle g_triangles[]; };
layout(set = 1, binding = 4, std430) buffer HomogeneousBlock { ExactHomogeneous g_homogeneous[]; };
layout(set = 1, binding = 5, std430) buffer CounterBlock { ExactCounters g_counters; };
layout(set = 1, binding = 6, std430) buffer BinCountBlock { uint g_binCounts[]; };
layout(set = 1, binding = 7, std430) buffer BinOffsetBlock { uint g_binOffsets[]; };
layout(set = 1, binding = 8, std430) buffer BinCursorBlock { uint g_binCursors[]; };
layout(set = 1, binding = 9, std430) buffer BinEntryBlock { uint g_binEntries[]; };
layout(set = 1, binding = 10, std430) readonly buffer TextureBlock { ExactTexture g_textures[]; };
layout(set = 1, binding = 11, std430) readonly buffer TexelBlock { uint g_texels[]; };
layout(set = 1, binding = 12, std430) readonly buffer SrgbBlock { float g_srgbToLinear[256]; };
layout(set = 1, binding = 13) uniform sampler2D u_opaqueDepth;
layout(set = 1, binding = 14, rgba16f) uniform image2D u_colour;

layout(push_constant) uniform ExactPush {
    uint itemCount;         // transparent quads in all draws
    uint drawCount;         // transparent draws
    uint width;
    uint height;
    uint binsX;
    uint binsY;
    float threshold;        // stop once every channel's transmittance is below this; 0: exact
    uint pad0;
} u_push;

// Position of vertex v.
vec3 vertexPosition(uint v) {
    uint o = v * 12u;
    return vec3(g_vertexData[o], g_vertexData[o + 1u], g_vertexData[o + 2u]);
}

vec3 vertexNormal(uint v) {
    uint o = v * 12u + 3u;
    return vec3(g_vertexData[o], g_vertexData[o + 1u], g_vertexData[o + 2u]);
}

vec2 vertexUv(uint v) {
    uint o = v * 12u + 6u;
    return vec2(g_vertexData[o], g_vertexData[o + 1u]);
}

vec4 vertexColour(uint v) {
    uint o = v * 12u + 8u;
    return vec4(g_vertexData[o], g_vertexData[o + 1u], g_vertexData[o + 2u], g_vertexData[o + 3u]);
}

// The vertices of sub-triangle `sub` of quad q: (q0, q1, q2) or (q0, q2, q3).
uvec3 quadTriangle(uvec4 q, uint sub) {
    return sub == 0u ? q.xyz : q.xzw;
}

#endif
