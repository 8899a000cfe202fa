#version 450
// Binning, pass 3: every triangle writes its index into its depth slab's part of the list of
// each bin it may cover.
// Entries past the capacity are dropped and flagged: the host renders the frame again with a
// list as large as the count says.

#include "exact_bindings.glsl"
#include "exact_bins.glsl"

layout(local_size_x = BINNING_GROUP_SIZE) in;

void main() {
    uint ti = binningTriangle();
    uint lo = g_counters.depthLo;
    uint range = slabRange(lo, g_counters.depthHi);
    // Records sit at their triangles' order keys, two per quad; culled ones are holes with
    // empty bounds, which enter no bin.
    if (ti >= 2u * u_push.itemCount) {
        return;
    }
    ExactTriangle t = loadTriangle(ti);
    ivec4 r = binRect(t.bounds);
    ivec2 rows = sliceRows(r);
    uint capacity = g_counters.binEntryCapacity;
    uint slab = slabOf(triangleDepthBits(t).x, lo, range);
    // Do-whiles (raster.comp says why) over the invocation's rows and each row's run of
    // blocks.
    int by = rows.x + binningLane();
    if (by <= rows.y) do {
        ivec2 run = rowColumns(t, by, r.xz);
        int bx = run.x;
        if (bx <= run.y) do {
            uint b = binIndex(bx, by) * SLABS + slab;
            uint slot = atomicAdd(g_binOffsets[b], 1u);
            if (slot < capacity) {
                g_binEntries[slot] = ti;
            } else {
                atomicOr(g_counters.overflow, OVERFLOW_BIN_ENTRIES);
            }
        } while (++bx <= run.y);
    } while ((by += int(ROW_LANES)) <= rows.y);
}
