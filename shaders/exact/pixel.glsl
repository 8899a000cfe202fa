// What the exact raster keeps of a pixel and of its row while it walks the row's list.
#ifndef TRANSLUCID_EXACT_PIXEL_GLSL
#define TRANSLUCID_EXACT_PIXEL_GLSL

#extension GL_EXT_shader_explicit_arithmetic_types_int64 : require

#include "selection.glsl"

// One pixel: what it has composited, how far in the frame's order, and what it counts.
struct Pixel {
    vec3 radiance;
    vec3 transmittance;
    // Fragments up to and including doneKey are composited (0: none yet; no fragment has
    // depth 0), and every fragment nearer than `passed`, which may be further on: a stretch
    // that ends with nothing to composite still passes its part of the order.
    uint64_t doneKey;
    uint64_t passed;
    // Finished pixels wait for the rest of their row, so that a row is suspended and
    // resumed whole.
    bool finished;
    // The nearest fragment this sweep found but could not keep (NO_KEY: none).
    uint64_t dropped;
    uint sweeps;
    uint fragments;
    // Fragments the pixel's first sweep found, all of them unless it had to drop some: its
    // depth, whatever the threshold.
    uint firstFound;
};

Pixel freshPixel() {
    return Pixel(vec3(0.0), vec3(1.0), 0ul, 0ul, false, NO_KEY, 0u, 0u, 0u);
}

// One row, the same in all its pixels (subgroup-uniform).
struct Row {
    // Loop iterations spent, against LOOP_BUDGET, and whether the row ran out.
    uint spent;
    bool outOfBudget;
    // A row is suspended inside a sweep and resumed there, with its pixels' selections: at
    // the stretch its search for a slab started from (resumeCursor), at list entry
    // resumeEntry.
    bool resumeSweep;
    uint resumeCursor;
    uint resumeEntry;
    // The leading slabs that every pixel still at work has composited entirely, which sweeps
    // skip: a number that only grows, since what pixels have composited does.
    uint skip;
};

Row freshRow() {
    return Row(0u, false, false, 0u, 0u, 0u);
}

#endif
