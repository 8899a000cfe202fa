#version 450
// Binning, pass 3: every triangle writes its index into its depth slab's part of the list of
// each bin it may cover.
// Runs once per band, entering only the band's bins (bandRows, bandColumns), whose offsets
// the band's scan step placed within the capacity.

#include "bins_bindings.glsl"
#include "bin_lists.glsl"
#include "bin_tally.glsl"

layout(local_size_x = BINNING_GROUP_SIZE) in;

// The entries of triangle record ti on the invocation's rows: tallied (`place` false), or
// written at their places in the lists.
void fillTriangle(uint ti, bool place) {
    BinTriangle t = loadTriangle(ti);
    ivec4 r = binRect(t.bounds);
    ivec2 rows = bandRows(sliceRows(r));
    uint capacity = g_counters.binEntryCapacity;
    uint slab = slabOf(triangleDepthBits(t).x, ti);
    // Do-whiles (raster.comp says why) over the invocation's tile rows and each one's run
    // of blocks.
    int ty = rows.x + binningLane();
    if (ty <= rows.y) do {
        ivec2 run = bandColumns(ty, tileColumns(t, ty, r.xz));
        int bx = run.x;
        if (bx <= run.y) do {
            uint b = binIndex(bx, ty) * SLABS + slab;
            if (place) {
                uint slot = nextPlace(b);
                if (slot < capacity) {
                    g_binEntries[slot] = ti;
                } else {
                    atomicOr(g_counters.overflow, OVERFLOW_BAND_LISTS);
                }
            } else {
                tallyEntry(b);
            }
        } while (++bx <= run.y);
    } while ((ty += int(ROW_LANES)) <= rows.y);
}

void main() {
    uint ti = binningTriangle();
    // Records sit at their triangles' order keys, two per quad; culled ones are holes with
    // empty bounds, which enter no bin.
    bool listed = ti < 2u * u_push.itemCount;
    // With a tally the walk runs twice: once to tally the workgroup's entries and reserve
    // their places, once to write them there.
    if (TALLIED) {
        clearTally();
        if (listed) {
            fillTriangle(ti, false);
        }
        reserveTally();
    }
    if (listed) {
        fillTriangle(ti, true);
    }
}
