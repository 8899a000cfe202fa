#version 450
// Binning, pass 2: exclusive prefix sum of the (bin, slab) counts into list offsets, so that
// each bin's list holds its slabs near to far. Three kinds of dispatch (SCAN_STEP):
// 0. every invocation sums the counts of one block (BIN_SIZE rows of SLABS slabs) into
//    g_blockTotals; then the workgroup that finishes last (last_group.glsl) turns the block
//    totals into block offsets in place (each invocation scans a contiguous run of blocks;
//    the runs' sums are scanned in shared memory), lists the blocks with a non-empty bin, in
//    block order, for the raster, and plans the first band;
// then, for each band of listed blocks whose lists fit the capacity together (one band when
// the frame fits; the host records one when the last frame fitted with room to spare, else a
// few, and fill and raster follow each):
// 2. one invocation plans the band (planBand), but for the first;
// 1. every invocation turns the bin counts of one listed block of the band into offsets, in
//    place, from its block offset less the band's. Only those bins are read: fill appends to
//    bins with entries, and the raster walks the listed blocks (the lamp's scan took 0.5 ms
//    for every block at 1280x720).
// Steps 0 and 1 take whole workgroups of blocks (the arrays are padded, the padding's counts
// stay zero; see writeBinOffsets for step 1), so they run without a branch: on CPU drivers
// such as lavapipe straight-line loads and stores are vector operations, but per-lane loops
// inside control flow. One workgroup scanning every bin was single-threaded there.

#extension GL_EXT_control_flow_attributes : require

#include "bins_bindings.glsl"
#include "bin_lists.glsl"
#include "last_group.glsl"

layout(local_size_x = SCAN_GROUP_SIZE) in;

#include "interface_specialization.glsl"

const uint BINS_PER_BLOCK = BIN_SIZE * SLABS;

shared uint s_runTotals[SCAN_GROUP_SIZE];
shared uint s_runListed[SCAN_GROUP_SIZE];

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

void planBand();

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
    [[unroll]] for (uint row = 0u; row < BIN_SIZE; row++) {
        for (uint k = 0u; k < SLABS; k++) {
            uint bin = first + row * SLABS + k;
            uint binCount = texelFetch(u_binCountTexels, int(bin)).r;
            g_binEnds[bin] = offset;
            offset += binCount;
        }
    }
}

// Where the lists of listed blocks [0, i) end: listed block i's offset, or every entry.
uint listEnd(uint i, uint listed) {
    return i < listed ? g_blockTotals[g_rasterBins[i]] : g_counters.binEntryCount;
}

// The next band: the most listed blocks from bandNext on whose lists fit the capacity
// together (all of them when the frame fits). A block that alone does not fit is skipped,
// its pixels left as they are, and counted. A band with blocks drops the rows the previous
// one left on its pending list (u_push.resumeList), counted, since they cannot resume once
// the lists are refilled; a band without keeps them, and its continuations resume them.
void planBand() {
    if (gl_LocalInvocationID.x != 0u) {
        return;
    }
    uint listed = g_counters.listedBlocks;
    uint capacity = g_counters.binEntryCapacity;
    uint start = g_counters.bandNext;
    uint count = 0u;
    if (start < listed) {
        uint base = listEnd(start, listed);
        if (listEnd(start + 1u, listed) - base > capacity) {
            g_counters.skippedBlocks += 1u;
            g_counters.bandNext = start + 1u;
        } else {
            // The last end within the capacity, by bisection.
            uint lo = start + 1u;
            uint hi = listed;
            while (lo < hi) {
                uint mid = (lo + hi + 1u) / 2u;
                if (listEnd(mid, listed) - base <= capacity) {
                    lo = mid;
                } else {
                    hi = mid - 1u;
                }
            }
            count = lo - start;
            // A workgroup a block, u_push.groupsX to a row: past one row the band ends on a
            // whole row, and the next band takes the rest.
            if (count > u_push.groupsX) {
                count -= count % u_push.groupsX;
                lo = start + count;
            }
            g_counters.bandNext = lo;
            g_counters.bandBase = base;
            g_counters.bandFirstBlock = g_rasterBins[start];
            g_counters.bandLastBlock = g_rasterBins[lo - 1u];
            g_counters.bands += 1u;
        }
    }
    if (count > 0u) {
        uint pending = u_push.resumeList * 4u;
        g_counters.abandonedRows += g_dispatch[pending + 3u];
        g_dispatch[pending] = 0u;
        g_dispatch[pending + 2u] = 1u;
        g_dispatch[pending + 3u] = 0u;
    }
    g_counters.bandFirst = start;
    g_counters.bandCount = count;
    uvec2 rasterGroups = splitGroups(count);
    g_dispatch[DISPATCH_RASTER_BINS * 4u] = rasterGroups.x;
    g_dispatch[DISPATCH_RASTER_BINS * 4u + 2u] = max(rasterGroups.y, 1u);
    g_dispatch[DISPATCH_BIN_OFFSETS * 4u] = (count + SCAN_GROUP_SIZE - 1u) / SCAN_GROUP_SIZE;
    uint fill = DISPATCH_BAND_FILL * 4u;
    uint binning = DISPATCH_BINNING * 4u;
    g_dispatch[fill] = count > 0u ? g_dispatch[binning] : 0u;
    g_dispatch[fill + 1u] = g_dispatch[binning + 1u];
    g_dispatch[fill + 2u] = g_dispatch[binning + 2u];
}

void main() {
    if (SCAN_STEP == 0u) {
        sumBlock();
        if (lastGroupDone(GROUPS_DONE_SCAN)) {
            scanBlocks();
        }
    } else if (SCAN_STEP == 1u) {
        writeBinOffsets();
    } else {
        planBand();
    }
}
