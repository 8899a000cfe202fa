#version 450
// Binning, pass 1: every triangle adds one to the count of its depth slab in each bin it may
// cover, and widens its slab's farthest depth and largest order key in the frame. (The
// frame's entry count is the scan's total: block_scan.comp writes it.)

#extension GL_KHR_shader_subgroup_arithmetic : require
#extension GL_KHR_shader_subgroup_basic : require
#extension GL_KHR_shader_subgroup_vote : require

#include "bins_bindings.glsl"
#include "bin_lists.glsl"
#include "bin_tally.glsl"

layout(local_size_x = BINNING_GROUP_SIZE) in;

// Counts the entries of triangle record ti on the invocation's rows.
void countTriangle(uint ti) {
    BinTriangle t = loadTriangle(ti);
    ivec4 r = binRect(t.bounds);
    ivec2 rows = sliceRows(r);
    uvec2 depth = triangleDepthBits(t);
    uint slab = slabOf(depth.x, ti);
    // Do-whiles (raster.comp says why) over the invocation's tile rows and each one's run
    // of blocks.
    int ty = rows.x + binningLane();
    if (ty <= rows.y) do {
        ivec2 run = tileColumns(t, ty, r.xz);
        int bx = run.x;
        if (bx <= run.y) do {
            uint b = binIndex(bx, ty) * SLABS + slab;
            if (!TALLIED || !tallyEntry(b)) {
                atomicAdd(g_binEnds[b], 1u);
            }
        } while (++bx <= run.y);
    } while ((ty += int(ROW_LANES)) <= rows.y);
    // The slabs' farthest depths take one atomic per subgroup and slab: one per triangle made
    // them the most contended words of the frame (binning a 100k-triangle mesh took twice
    // as long to count as to fill). So the subgroup takes its triangles' slabs one at a time,
    // nearest first, each lane reporting once (a row of lanes on one triangle: its first
    // lane). With one slab the raster needs none (raster.comp), and even one contended atomic
    // per subgroup was a fifth of the count.
    if (SLABS > 1u) {
        bool pending = r.y <= r.w && binningLane() == 0;
        if (subgroupAny(pending)) do {
            uint k = subgroupMin(pending ? slab : 0xFFFFFFFFu);
            uint farthest = subgroupMax(pending && slab == k ? depth.y : 0u);
            uint last = subgroupMax(pending && slab == k ? ti : 0u);
            if (subgroupElect()) {
                atomicMax(g_counters.slabFarthest[k], farthest);
                atomicMax(g_counters.slabLastOrder[k], last);
            }
            pending = pending && slab != k;
        } while (subgroupAny(pending));
    }
}

void main() {
    if (TALLIED) {
        clearTally();
    }
    uint ti = binningTriangle();
    // Records sit at their triangles' order keys, two per quad; culled ones are holes with
    // empty bounds, which enter no bin.
    if (ti < 2u * u_push.itemCount) {
        countTriangle(ti);
    }
    if (TALLIED) {
        flushTally();
    }
}
