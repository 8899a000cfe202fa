#version 450
// The bins' block scan, and the first band's plan (bin_scan.glsl says where it stands).

#extension GL_EXT_control_flow_attributes : require

#include "bin_scan.glsl"
#include "last_group.glsl"

layout(local_size_x = SCAN_GROUP_SIZE) in;

shared uint s_runTotals[SCAN_GROUP_SIZE];
shared uint s_runListed[SCAN_GROUP_SIZE];

// The per-block loops are unrolled over the block's tiles; over the slabs of each only
// where the driver chooses to (deep frames have up to MAX_SLABS, too many to unroll).
void sumBlock() {
    uint block = gl_GlobalInvocationID.x;
    uint first = block * BINS_PER_BLOCK;
    uint total = 0u;
    [[unroll]] for (uint tile = 0u; tile < TILES_PER_BLOCK; tile++) {
        for (uint k = 0u; k < SLABS; k++) {
            total += texelFetch(u_binCountTexels, int(first + tile * SLABS + k)).r;
        }
    }
    g_blockTotals[block] = total;
}

void scanBlocks() {
    uint blocks = u_push.binsX * u_push.binsY;
    uint run = (blocks + SCAN_GROUP_SIZE - 1u) / SCAN_GROUP_SIZE;
    uint first = gl_LocalInvocationID.x * run;
    uint sum = 0u;
    uint listed = 0u;
    for (uint i = 0u; i < run; i++) {
        // Blocks past the frame's, up to whole workgroups, have a total of 0 (sumBlock).
        uint total = g_blockTotals[first + i];
        sum += total;
        listed += total > 0u ? 1u : 0u;
    }
    s_runTotals[gl_LocalInvocationID.x] = sum;
    s_runListed[gl_LocalInvocationID.x] = listed;
    barrier();
    if (gl_LocalInvocationID.x == 0u) {
        uint total = 0u;
        uint listedTotal = 0u;
        for (uint i = 0u; i < SCAN_GROUP_SIZE; i++) {
            uint t = s_runTotals[i];
            s_runTotals[i] = total;
            total += t;
            uint l = s_runListed[i];
            s_runListed[i] = listedTotal;
            listedTotal += l;
        }
        // Every bin's count summed: the entries the frame needs. Past the capacity the frame
        // is rasterized in bands (planBand) and the host grows the list for later frames.
        g_counters.binEntryCount = total;
        if (total > g_counters.binEntryCapacity) {
            g_counters.overflow |= OVERFLOW_BIN_ENTRIES;
        }
        g_counters.listedBlocks = listedTotal;
        g_dispatch[DRAW_COMPOSITE * 4u + 1u] = listedTotal;
    }
    barrier();
    uint offset = s_runTotals[gl_LocalInvocationID.x];
    uint slot = s_runListed[gl_LocalInvocationID.x];
    // Listed in block order, so that a band is a run of the list and of the lists' entries.
    for (uint i = 0u; i < run; i++) {
        uint block = first + i;
        bool inside = block < blocks;
        uint total = g_blockTotals[block];
        if (inside) {
            g_blockTotals[block] = offset;
        }
        offset += total;
        if (total > 0u) {
            g_rasterBins[slot] = block;
            slot++;
        }
    }
    // The first band, once every block is listed and has its offset.
    memoryBarrierBuffer();
    barrier();
    planBand();
}

void main() {
    sumBlock();
    if (lastGroupDone(GROUPS_DONE_SCAN)) {
        scanBlocks();
    }
}
