#version 450
// Builds the opaque depth pyramid (depth_pyramid.glsl) in one dispatch: level 0 from the
// opaque depth, one invocation per cell; then the workgroup that finishes last builds every
// level above, one level after another.

#extension GL_EXT_control_flow_attributes : require

#include "bins_bindings.glsl"
#include "depth_pyramid.glsl"
#include "last_group.glsl"

#define PYRAMID_GROUP_SIZE 256
layout(local_size_x = PYRAMID_GROUP_SIZE) in;

// A gather of four texels costs about as much as one fetch on lavapipe, so level 0 gathers each
// 2x2 quad of its cell. Where the frame ends mid-cell, the quads past it move back onto its
// last row and column, which leaves the farthest depth unchanged: the depth image may be
// larger than the frame (a renderer draws smaller frames into its top-left corner), and what
// lies past the frame is not this frame's.
void buildLevelZero() {
    uint cell = gl_GlobalInvocationID.x;
    if (cell >= u_push.binsX * u_push.binsY) {
        return;
    }
    vec2 origin = vec2(cell % u_push.binsX, cell / u_push.binsX) * BIN_SIZE;
    vec2 texelSize = 1.0 / vec2(textureSize(u_opaqueDepth, 0));
    // The corner between the frame's last two texels (or the only one's, with the clamp-to-
    // edge sampler repeating it) along each side.
    vec2 lastCorner = max(vec2(u_push.width, u_push.height) - 1.0, vec2(0.0));
    float farthest = 0.0;
    [[unroll]] for (int y = 0; y < BIN_SIZE; y += 2) {
        [[unroll]] for (int x = 0; x < BIN_SIZE; x += 2) {
            // The shared corner of texels (x, y) .. (x + 1, y + 1): half a texel from any
            // other choice, so rounding cannot move the gather.
            vec2 corner = min(origin + vec2(x + 1, y + 1), lastCorner);
            vec4 quad = opaqueDepthGather(corner, texelSize);
            farthest = max(farthest, max(max(quad.x, quad.y), max(quad.z, quad.w)));
        }
    }
    g_depthPyramid[cell] = farthest;
}

// Read from the buffer, not the texel view: cells other workgroups wrote in this dispatch.
float builtCell(uint levelOffset, uvec2 size, ivec2 cell) {
    return g_depthPyramid[levelOffset + uint(cell.y) * size.x + uint(cell.x)];
}

void buildUpperLevels() {
    uvec2 size = uvec2(u_push.binsX, u_push.binsY);
    uint offset = 0u;
    while (size.x > 1u || size.y > 1u) {
        uvec2 parent = pyramidParentSize(size);
        uint parentOffset = offset + size.x * size.y;
        for (uint i = gl_LocalInvocationID.x; i < parent.x * parent.y; i += PYRAMID_GROUP_SIZE) {
            ivec2 lo = ivec2(i % parent.x, i / parent.x) * 2;
            ivec2 hi = min(lo + 1, ivec2(size) - 1);
            g_depthPyramid[parentOffset + i] =
                max(max(builtCell(offset, size, lo), builtCell(offset, size, ivec2(hi.x, lo.y))),
                    max(builtCell(offset, size, ivec2(lo.x, hi.y)), builtCell(offset, size, hi)));
        }
        // The next level reads what other invocations wrote.
        memoryBarrierBuffer();
        barrier();
        offset = parentOffset;
        size = parent;
    }
}

void main() {
    buildLevelZero();
    if (lastGroupDone(GROUPS_DONE_PYRAMID)) {
        buildUpperLevels();
    }
}
