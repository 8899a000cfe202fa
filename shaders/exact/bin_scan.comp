#version 450
// Binning, pass 2: exclusive prefix sum of the (bin, slab) counts into list offsets, so that
// each bin's list holds its slabs near to far. Three dispatches (SCAN_STEP):
// 0. every invocation sums the counts of one block (BIN_SIZE rows of SLABS slabs) into
//    g_blockTotals;
// 1. one workgroup turns the block totals into block offsets in place (each invocation scans
//    a contiguous run of blocks; the runs' sums are scanned in shared memory) and lists the
//    blocks with a non-empty bin for the raster;
// 2. every invocation writes the bin offsets of one listed block, starting from its block
//    offset. Only those bins are read: fill appends to bins with entries, and the raster
//    walks the listed blocks (the lamp's scan took 0.5 ms for every block at 1280x720).
// Steps 0 and 2 take whole workgroups of blocks (the arrays are padded, the padding's counts
// stay zero; step 2's last workgroup repeats the last listed block), so they run without a
// branch: on CPU drivers such as lavapipe straight-line loads and stores are vector
// operations, but per-lane loops inside control flow. One workgroup scanning every bin was
// single-threaded there.

#extension GL_KHR_shader_subgroup_ballot : require
#extension GL_EXT_control_flow_attributes : require

#include "exact_bindings.glsl"
#include "exact_bins.glsl"

layout(local_size_x = SCAN_GROUP_SIZE) in;

layout(constant_id = 0) const uint SCAN_STEP = 0u;

const uint BINS_PER_BLOCK = BIN_SIZE * SLABS;

shared uint s_runTotals[SCAN_GROUP_SIZE];

// The per-block loops are unrolled over the block's rows; over the slabs of each row only
// where the driver chooses to (deep frames have up to MAX_SLABS, too many to unroll).
void sumBlock() {
    uint block = gl_GlobalInvocationID.x;
    uint first = block * BINS_PER_BLOCK;
    uint total = 0u;
    [[unroll]] for (uint row = 0u; row < BIN_SIZE; row++) {
        for (uint k = 0u; k < SLABS; k++) {
            total += texelFetch(u_binCountTexels, int(first + row * SLABS + k)).r;
        }
    }
    g_blockTotals[block] = total;
}

void scanBlocks() {
    uint blocks = u_push.binsX * u_push.binsY;
    uint run = (blocks + SCAN_GROUP_SIZE - 1u) / SCAN_GROUP_SIZE;
    uint first = gl_LocalInvocationID.x * run;
    uint sum = 0u;
    for (uint i = 0u; i < run; i++) {
        sum += first + i < blocks ? texelFetch(u_blockTotalTexels, int(first + i)).r : 0u;
    }
    s_runTotals[gl_LocalInvocationID.x] = sum;
    barrier();
    if (gl_LocalInvocationID.x == 0u) {
        uint total = 0u;
        for (uint i = 0u; i < SCAN_GROUP_SIZE; i++) {
            uint t = s_runTotals[i];
            s_runTotals[i] = total;
            total += t;
        }
        // Every bin's count summed: the entries the frame needs, which the host checks
        // against the list's capacity.
        g_counters.binEntryCount = total;
    }
    barrier();
    uint offset = s_runTotals[gl_LocalInvocationID.x];
    // The same number of iterations for every invocation, so that the listing below can
    // take one atomic per subgroup.
    for (uint i = 0u; i < run; i++) {
        uint block = first + i;
        bool inside = block < blocks;
        uint total = inside ? texelFetch(u_blockTotalTexels, int(block)).r : 0u;
        if (inside) {
            g_blockTotals[block] = offset;
        }
        offset += total;
        bool listed = total > 0u;
        uvec4 ballot = subgroupBallot(listed);
        uint count = subgroupBallotBitCount(ballot);
        uint slot = 0u;
        if (subgroupElect() && count > 0u) {
            slot = atomicAdd(g_dispatch[DISPATCH_RASTER_BINS * 4u], count);
        }
        slot = subgroupBroadcastFirst(slot) + subgroupBallotExclusiveBitCount(ballot);
        if (listed) {
            g_rasterBins[slot] = block;
        }
    }
    // Every invocation has listed its blocks: size step 2 to them.
    memoryBarrierBuffer();
    barrier();
    if (gl_LocalInvocationID.x == 0u) {
        uint listed = atomicAdd(g_dispatch[DISPATCH_RASTER_BINS * 4u], 0u);  // an atomic read
        g_dispatch[DISPATCH_BIN_OFFSETS * 4u] = (listed + SCAN_GROUP_SIZE - 1u) / SCAN_GROUP_SIZE;
    }
}

void writeBinOffsets() {
    uint listed = g_dispatch[DISPATCH_RASTER_BINS * 4u];
    uint block = g_rasterBins[min(gl_GlobalInvocationID.x, listed - 1u)];
    uint first = block * BINS_PER_BLOCK;
    uint offset = texelFetch(u_blockTotalTexels, int(block)).r;
    [[unroll]] for (uint row = 0u; row < BIN_SIZE; row++) {
        for (uint k = 0u; k < SLABS; k++) {
            uint bin = first + row * SLABS + k;
            g_binOffsets[bin] = offset;
            offset += texelFetch(u_binCountTexels, int(bin)).r;
        }
    }
}

void main() {
    if (SCAN_STEP == 0u) {
        sumBlock();
    } else if (SCAN_STEP == 1u) {
        scanBlocks();
    } else {
        writeBinOffsets();
    }
}
