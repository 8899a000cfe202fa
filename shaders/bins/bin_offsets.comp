#version 450
// The band's bin offsets (bin_scan.glsl says where it stands).

#extension GL_EXT_control_flow_attributes : require

#include "bin_scan.glsl"

layout(local_size_x = SCAN_GROUP_SIZE) in;

// The counts of the band's blocks become offsets in place, so each block once: the
// invocations past the band convert the block past the frame's instead, which nothing reads
// (the arrays keep one), so that the step runs without a branch. The counts are read through
// the texel view: no invocation reads a word another writes.
void writeBinOffsets() {
    uint count = g_counters.bandCount;
    uint i = gl_GlobalInvocationID.x;
    uint listed = g_rasterBins[g_counters.bandFirst + min(i, count - 1u)];
    uint block = i < count ? listed : u_push.binsX * u_push.binsY;
    uint first = block * BINS_PER_BLOCK;
    uint offset = blockStart(block);
    [[unroll]] for (uint tile = 0u; tile < TILES_PER_BLOCK; tile++) {
        for (uint k = 0u; k < SLABS; k++) {
            uint bin = first + tile * SLABS + k;
            uint binCount = texelFetch(u_binCountTexels, int(bin)).r;
            g_binEnds[bin] = offset;
            offset += binCount;
        }
    }
}

void main() {
    writeBinOffsets();
}
