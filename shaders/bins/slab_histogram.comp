#version 450
// Deep frames, before the bin count: every triangle adds the bins it may enter to the
// histogram bucket of its nearest depth, and widens that bucket's ranges of nearest depth
// bits and order keys. The workgroup that finishes last plans the slabs from it
// (slab_plan.glsl).

#extension GL_KHR_shader_subgroup_arithmetic : require
#extension GL_KHR_shader_subgroup_basic : require
#extension GL_KHR_shader_subgroup_vote : require

#include "bins_bindings.glsl"
#include "bin_lists.glsl"
#include "last_group.glsl"
#include "slab_plan.glsl"

layout(local_size_x = BINNING_GROUP_SIZE) in;

// A triangle weighs at most this many bins, so that a subgroup's sum fits 32 bits (a larger
// one covers more than 2^24 bins: its slab is then a little fuller than planned).
const uint MOST_WEIGHT = 1u << 24;

void addToHistogram() {
    uint ti = binningTriangle();
    uint lo = g_counters.depthLo;
    uint range = slabRange(lo, g_counters.depthHi);
    bool listed = false;
    uint bucket = 0u;
    uint bits = 0u;
    uint weight = 0u;
    // Records sit at their triangles' order keys, two per quad; culled ones are holes with
    // empty bounds. Each triangle counts once, for its first binning lane of the first
    // slice (the dispatch is binning's, which may slice its rows: bin_lists.glsl).
    if (ti < 2u * u_push.itemCount && binningLane() == 0 && gl_GlobalInvocationID.y == 0u) {
        BinTriangle t = loadTriangle(ti);
        ivec4 r = binRect(t.bounds);
        listed = r.y <= r.w && r.x <= r.z;
        bits = triangleDepthBits(t).x;
        bucket = bucketOf(bits, lo, range);
        // The bins of its bounds: tileColumns narrows them, but costs more than the count
        // does.
        weight = listed ? min(uint(r.w - r.y + 1) * uint(r.z - r.x + 1), MOST_WEIGHT) : 0u;
    }
    // One set of atomics per subgroup and bucket, nearest bucket first (bin_count.comp does
    // the same for the slabs' farthest depths, and says why).
    bool pending = listed;
    if (subgroupAny(pending)) do {
        uint k = subgroupMin(pending ? bucket : 0xFFFFFFFFu);
        bool mine = pending && bucket == k;
        uint sum = subgroupAdd(mine ? weight : 0u);
        uint nearestLeast = subgroupMin(mine ? bits : 0xFFFFFFFFu);
        uint nearestMost = subgroupMax(mine ? bits : 0u);
        uint orderLeast = subgroupMin(mine ? ti : 0xFFFFFFFFu);
        uint orderMost = subgroupMax(mine ? ti : 0u);
        if (subgroupElect()) {
            uint before = atomicAdd(g_counters.bucketWeightLo[k], sum);
            if (before + sum < before) {
                atomicAdd(g_counters.bucketWeightHi[k], 1u);
            }
            atomicMax(g_counters.bucketNearestLeast[k], ~nearestLeast);
            atomicMax(g_counters.bucketNearestMost[k], nearestMost);
            atomicMax(g_counters.bucketOrderLeast[k], ~orderLeast);
            atomicMax(g_counters.bucketOrderMost[k], orderMost);
        }
        pending = pending && !mine;
    } while (subgroupAny(pending));
}

void main() {
    addToHistogram();
    if (lastGroupDone(GROUPS_DONE_SLABS) && gl_LocalInvocationIndex == 0u) {
        planSlabs();
    }
}
