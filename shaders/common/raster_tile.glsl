// Where a bin raster's invocation is. A raster workgroup is RASTER_GROUP_SIZE invocations in
// x, whole rows of BIN_SIZE pixels of one block in row order: one tile (bin_lists.glsl), or
// the whole block where a tile is one row (subgroups of 8: lavapipe), so that each subgroup,
// consecutive invocations, holds one tile. One dimension, so that a device can be held to
// full subgroups (gpu::pipeline), whose size must divide the workgroup's x.
#ifndef TRANSLUCID_RASTER_TILE_GLSL
#define TRANSLUCID_RASTER_TILE_GLSL

#include "bin_lists.glsl"

layout(local_size_x_id = RASTER_GROUP_SIZE_ID) in;

// Pixels of a tile: a suspended tile's states take this many slots.
const uint TILE_PIXELS = uint(BIN_SIZE) * TILE_ROWS;

// The invocation's pixel column in its block, and its row within the workgroup's rows.
uint laneColumn() {
    return gl_LocalInvocationID.x & uint(BIN_SIZE - 1);
}

uint laneRow() {
    return gl_LocalInvocationID.x >> BIN_SHIFT;
}

// Pixel rows of a block a workgroup covers.
uint groupRows() {
    return gl_WorkGroupSize.x >> BIN_SHIFT;
}

// The invocation's pixel among its tile's, for pixel row `row` of the block.
uint tileLane(uint row) {
    return (row & (TILE_ROWS - 1u)) * uint(BIN_SIZE) + laneColumn();
}

#endif
