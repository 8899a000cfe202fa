// The opaque depth pyramid: the farthest opaque depth over ever larger cells, so that setup can
// drop a triangle that lies wholly behind the opaque layer with at most four reads. Level 0 has
// a cell per BIN_SIZE x BIN_SIZE block; each level above halves both sides (rounding up), a
// cell holding the farthest of the up to 2x2 cells under it; the last level is one cell.
// Levels are stored one after another in g_depthPyramid, rows left to right.
#ifndef TRANSLUCID_DEPTH_PYRAMID_GLSL
#define TRANSLUCID_DEPTH_PYRAMID_GLSL

#include "bins_bindings.glsl"

#extension GL_EXT_control_flow_attributes : require

// Cells across and down of the level after one of `size`.
uvec2 pyramidParentSize(uvec2 size) {
    return (size + 1u) >> 1;
}

// Read through the texel view: setup reads cells under a branch, where storage-buffer loads
// cost a loop over the lanes on CPU drivers.
float pyramidCell(uint levelOffset, uvec2 size, ivec2 cell) {
    return texelFetch(u_depthPyramidTexels, int(levelOffset + uint(cell.y) * size.x + uint(cell.x))).r;
}

// The farthest opaque depth over the non-empty pixel rectangle [x, z) x [y, w): the level
// whose cells split it at most once along each side, and its (up to) four cells there.
// The level is found by a fixed number of selects, not a loop whose length differs between
// invocations: such a loop gave wrong results on lavapipe 22.3 (LLVM 15).
float farthestOpaque(ivec4 rect) {
    ivec2 lo = rect.xy >> BIN_SHIFT;
    ivec2 hi = (rect.zw - 1) >> BIN_SHIFT;
    uvec2 size = uvec2(u_push.binsX, u_push.binsY);
    uint offset = 0u;
    [[unroll]] for (int level = 1; level < PYRAMID_MAX_LEVELS; level++) {
        bool up = hi.x - lo.x > 1 || hi.y - lo.y > 1;
        offset += up ? size.x * size.y : 0u;
        size = up ? pyramidParentSize(size) : size;
        lo = up ? lo >> 1 : lo;
        hi = up ? hi >> 1 : hi;
    }
    return max(max(pyramidCell(offset, size, lo), pyramidCell(offset, size, ivec2(hi.x, lo.y))),
               max(pyramidCell(offset, size, ivec2(lo.x, hi.y)), pyramidCell(offset, size, hi)));
}

#endif
