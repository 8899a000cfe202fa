// The bins a triangle's bounds touch.
#ifndef TRANSLUCID_EXACT_BINS_GLSL
#define TRANSLUCID_EXACT_BINS_GLSL

#include "exact_layout.glsl"

// Inclusive bin rectangle (bx0, by0, bx1, by1) of a non-empty pixel rectangle.
ivec4 binRect(ivec4 bounds) {
    return ivec4(bounds.x >> BIN_SHIFT, bounds.y >> BIN_SHIFT, (bounds.z - 1) >> BIN_SHIFT,
                 (bounds.w - 1) >> BIN_SHIFT);
}

#endif
