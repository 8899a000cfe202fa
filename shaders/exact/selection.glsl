// The exact raster's selection: the SELECT_SIZE nearest fragments a pixel found behind the
// last one it composited, kept sorted in registers as fragment keys alone (a key's low half,
// the order key, is its triangle's record). Every index is a constant (fully unrolled).
#ifndef TRANSLUCID_EXACT_SELECTION_GLSL
#define TRANSLUCID_EXACT_SELECTION_GLSL

#extension GL_EXT_shader_explicit_arithmetic_types_int64 : require
#extension GL_EXT_control_flow_attributes : require

#include "interface_specialization.glsl"

// A fragment's rank as one number: view depth bits (positive floats order like their bits),
// then the order key. One 64-bit compare instead of three 32-bit ones in the insertion.
uint64_t fragmentKey(uint depthBits, uint order) {
    return (uint64_t(depthBits) << 32) | uint64_t(order);
}

// No fragment: past every key.
const uint64_t NO_KEY = 0xFFFFFFFFFFFFFFFFul;

void clearSelection(out uint64_t selection[SELECT_SIZE]) {
    [[unroll]] for (int k = 0; k < SELECT_SIZE; k++) {
        selection[k] = NO_KEY;
    }
}

// Inserts `key` (NO_KEY: no fragment), dropping the last: each slot takes its left
// neighbour, the new key, or keeps its own, whichever is in the middle (keys are distinct but
// for NO_KEY), walking right to left (left neighbours are still unchanged). NO_KEY sorts
// before no slot. `dropped` keeps the nearest key that fell out of a full selection: the
// larger of the new key and the last.
void insertFragment(inout uint64_t selection[SELECT_SIZE], inout uint64_t dropped, uint64_t key) {
    dropped = min(dropped, max(key, selection[SELECT_SIZE - 1]));
    [[unroll]] for (int k = SELECT_SIZE - 1; k > 0; k--) {
        selection[k] = max(selection[k - 1], min(key, selection[k]));
    }
    selection[0] = min(selection[0], key);
}

// Takes the nearest key off: shifts the selection left (SELECT_SIZE moves; picking slot i by
// selects instead would need the kept slots compacted before the next insertions).
void takeNearest(inout uint64_t selection[SELECT_SIZE]) {
    [[unroll]] for (int k = 0; k < SELECT_SIZE - 1; k++) {
        selection[k] = selection[k + 1];
    }
    selection[SELECT_SIZE - 1] = NO_KEY;
}

#endif
