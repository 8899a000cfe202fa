#version 450
// Binning, pass 2: exclusive prefix sum of the (bin, slab) counts into offsets, so that each
// bin's list holds its slabs near to far, by one workgroup:
// each invocation sums a contiguous run of bins, the runs' sums are scanned in shared memory,
// then each invocation writes its run's offsets. Blocks with a non-empty bin are listed for
// the raster, which runs one workgroup per listed block (runs are whole blocks).

#include "exact_bindings.glsl"
#include "exact_bins.glsl"

#define SCAN_SIZE 256
layout(local_size_x = SCAN_SIZE) in;

shared uint s_runTotals[SCAN_SIZE];

void main() {
    uint blocks = u_push.binsX * u_push.binsY;
    uint perBlock = BIN_SIZE * SLABS;
    uint bins = blocks * perBlock;
    uint run = (blocks + SCAN_SIZE - 1u) / SCAN_SIZE * perBlock;
    uint first = gl_LocalInvocationID.x * run;
    uint last = min(first + run, bins);
    uint sum = 0u;
    for (uint b = first; b < last; b++) {
        sum += texelFetch(u_binCountTexels, int(b)).r;
    }
    s_runTotals[gl_LocalInvocationID.x] = sum;
    barrier();
    if (gl_LocalInvocationID.x == 0u) {
        uint total = 0u;
        for (uint i = 0u; i < SCAN_SIZE; i++) {
            uint t = s_runTotals[i];
            s_runTotals[i] = total;
            total += t;
        }
    }
    barrier();
    uint offset = s_runTotals[gl_LocalInvocationID.x];
    uint blockEntries = 0u;
    for (uint b = first; b < last; b++) {
        uint count = texelFetch(u_binCountTexels, int(b)).r;
        g_binOffsets[b] = offset;
        offset += count;
        blockEntries += count;
        if (b % perBlock == perBlock - 1u) {
            if (blockEntries > 0u) {
                uint slot = atomicAdd(g_dispatch[DISPATCH_RASTER_BINS * 4u], 1u);
                g_rasterBins[slot] = b / perBlock;
            }
            blockEntries = 0u;
        }
    }
}
