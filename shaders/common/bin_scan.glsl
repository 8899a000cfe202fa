// The scan of the bins' counts into list offsets (binning, pass 2), in three shaders:
// 1. block_scan.comp: every invocation sums the counts of one block (TILES_PER_BLOCK bins of
//    SLABS slabs) into g_blockTotals; then the workgroup that finishes last (last_group.glsl)
//    turns the block totals into block offsets in place (each invocation scans a contiguous
//    run of blocks; the runs' sums are scanned in shared memory), lists the blocks with a
//    non-empty bin, in block order, for the raster, and plans the first band;
// then, for each band of listed blocks whose lists fit the capacity together (one band when
// the frame fits; the host records one when the last frame fitted with room to spare, else a
// few, and fill and raster follow each):
// 2. band_plan.comp plans the band (planBand), but for the first;
// 3. bin_offsets.comp: every invocation turns the bin counts of one listed block of the band
//    into offsets, in place, from its block offset less the band's. Only those bins are
//    read: fill appends to bins with entries, and the raster walks the listed blocks (the
//    lamp's scan took 0.5 ms for every block at 1280x720).
// Steps 1 and 3 take whole workgroups of blocks (the arrays are padded, the padding's counts
// stay zero; see bin_offsets.comp), so they run without a branch: on CPU drivers such as
// lavapipe straight-line loads and stores are vector operations, but per-lane loops inside
// control flow. One workgroup scanning every bin was single-threaded there. Each list holds
// its bin's slabs near to far.
#ifndef TRANSLUCID_BIN_SCAN_GLSL
#define TRANSLUCID_BIN_SCAN_GLSL

#include "bins_bindings.glsl"
#include "bin_lists.glsl"

const uint BINS_PER_BLOCK = TILES_PER_BLOCK * SLABS;

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

#endif
