// Deep frames, after the slab histogram (slab_histogram.comp, whose last workgroup plans): where
// each slab starts (bin_lists.glsl). Slab s starts where the histogram's running sum of bin
// entries reaches s / SLABS of the frame's, so that slabs hold about as many entries each.
// Within the bucket where it does, the start is placed in proportion: between the bucket's
// least and most nearest depth bits, or, where all its triangles share one depth, between its
// least and most order keys. One invocation: MAX_SLABS buckets and SLABS slabs, each looked at
// once.
#ifndef TRANSLUCID_SLAB_PLAN_GLSL
#define TRANSLUCID_SLAB_PLAN_GLSL

#extension GL_EXT_shader_explicit_arithmetic_types_int64 : require

#include "bins_bindings.glsl"
#include "bin_lists.glsl"

uint64_t bucketWeight(uint b) {
    return (uint64_t(g_counters.bucketWeightHi[b]) << 32) | uint64_t(g_counters.bucketWeightLo[b]);
}

// The key a fraction `part` (0 to 1) into bucket b's weight: at `part` 1, past every
// triangle of the bucket.
uint64_t keyWithin(uint b, float part) {
    uint least = ~g_counters.bucketNearestLeast[b];
    uint most = g_counters.bucketNearestMost[b];
    uint orderLeast = ~g_counters.bucketOrderLeast[b];
    uint orderMost = g_counters.bucketOrderMost[b];
    uint64_t span = uint64_t(most - least) + 1ul;
    uint64_t depthBits = uint64_t(least);
    uint64_t order = 0ul;
    if (most == least) {
        span = uint64_t(orderMost - orderLeast) + 1ul;
        order = uint64_t(orderLeast);
    }
    uint64_t step = min(uint64_t(float(span) * part), span);
    if (most == least) {
        order += step;
    } else {
        depthBits += step;
    }
    // Past the bucket's last order key: the next depth's first.
    if (order > 0xFFFFFFFFul) {
        depthBits += 1ul;
        order = 0ul;
    }
    return (min(depthBits, 0xFFFFFFFFul) << 32) | order;
}

void planSlabs() {
    uint64_t total = 0ul;
    for (uint b = 0u; b < MAX_SLABS; b++) {
        total += bucketWeight(b);
    }
    g_counters.slabFloorBits[0] = 0u;
    g_counters.slabFloorOrder[0] = 0u;
    uint64_t floorKey = 0ul;
    uint b = 0u;
    uint64_t before = 0ul;
    uint64_t weight = bucketWeight(0u);
    for (uint s = 1u; s < SLABS; s++) {
        // At most 2^24 a triangle, for fewer than 2^22 triangle records: the product fits.
        uint64_t target = total * uint64_t(s) / uint64_t(SLABS);
        while (b + 1u < MAX_SLABS && before + weight < target) {
            before += weight;
            b++;
            weight = bucketWeight(b);
        }
        if (weight > 0ul && target > before) {
            float part = float(target - before) / float(weight);
            floorKey = max(floorKey, keyWithin(b, part));
        }
        g_counters.slabFloorBits[s] = uint(floorKey >> 32);
        g_counters.slabFloorOrder[s] = uint(floorKey);
    }
}

#endif
