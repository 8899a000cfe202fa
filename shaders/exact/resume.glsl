// The exact raster's suspended rows: the resume lists (the bins', interface_bins_set.glsl)
// and the states of their pixels (exact's binding, interface_exact.glsl).
//
// Rows of deep frames (SLABS > 1) and of continuations are suspended wherever their budget
// runs out, even inside a stretch too long for one budget, and resumed there with their
// pixels' selections. Rows of a shallow frame's first dispatch are suspended only between
// stretches and start a new sweep when resumed (NEW_SWEEP): saving selections costs every
// row (the code runs masked when not taken) some 5 % of a textured scene's raster. A
// shallow row whose stretch no budget holds is suspended before walking it, and the
// continuations walk it in parts (reported as OVERFLOW_CROWDED_BIN: later frames take slabs).
#ifndef TRANSLUCID_EXACT_RESUME_GLSL
#define TRANSLUCID_EXACT_RESUME_GLSL

#extension GL_KHR_shader_subgroup_ballot : require

#include "bins_bindings.glsl"
#include "bin_lists.glsl"
#include "interface_exact.glsl"
#include "pixel.glsl"
#include "raster_tile.glsl"

const bool PARTIAL_WALKS = SLABS > 1u || CONTINUATION;

// The pixel row of a block this invocation rasterizes: one of the band's listed blocks (the
// first dispatch), or the tile of the next item of resume list u_push.resumeList (a
// continuation, a workgroup a tile), with its state slot (NO_STATE: it starts over). False
// for a continuation's workgroup past the list's items (its last row of workgroups may run
// past them; see suspendRow).
bool rowToRaster(uint itemCapacity, uint resumeCapacity, out uint block, out uint row,
                 out uint stateSlot) {
    stateSlot = NO_STATE;
    if (CONTINUATION) {
        uint index = linearWorkGroup();
        if (index >= g_dispatch[u_push.resumeList * 4u + 3u]) {
            return false;
        }
        uint item = g_resumeItems[u_push.resumeList * itemCapacity + index];
        block = item / TILES_PER_BLOCK;
        row = (item % TILES_PER_BLOCK) * TILE_ROWS + laneRow();
        stateSlot = index < resumeCapacity ? index : NO_STATE;
    } else {
        block = g_rasterBins[g_counters.bandFirst + linearWorkGroup()];
        row = gl_WorkGroupID.y * groupRows() + laneRow();
    }
    return true;
}

// Where a resumed tile's pixel (on pixel row `row` of its block) left off, from state slot
// `stateSlot` of the list it resumes.
void resumePixel(uint stateSlot, uint resumeCapacity, uint row, inout Pixel p,
                 inout uint64_t selection[SELECT_SIZE], inout Row r) {
    uint slot = u_push.resumeList * resumeCapacity + stateSlot;
    ExactPixelState state = g_pixelStates[slot * TILE_PIXELS + tileLane(row)];
    p.radiance = state.radiance.xyz;
    p.transmittance = state.transmittance.xyz;
    p.doneKey = fragmentKey(state.done.x, state.done.y);
    p.passed = p.doneKey;
    p.finished = state.done.z != 0u;
    // Rows saved between sweeps start a new one.
    r.resumeSweep = state.sweep.x != NEW_SWEEP;
    r.resumeCursor = state.sweep.x;
    r.resumeEntry = state.sweep.y;
    p.dropped = r.resumeSweep ? packUint2x32(state.sweep.zw) : NO_KEY;
    [[unroll]] for (int k = 0; k < SELECT_SIZE; k++) {
        selection[k] = r.resumeSweep ? packUint2x32(state.selection[k]) : NO_KEY;
    }
}

// Puts the tile (that of pixel row `row` of `block`) on the other resume list for the next
// continuation, with its pixels' states where it finds a state slot. A tile without one
// starts over: what it composited here is counted then (p.fragments is zeroed).
void suspendRow(inout Pixel p, uint64_t selection[SELECT_SIZE], Row r, uint block, uint row,
                uint itemCapacity, uint resumeCapacity) {
    uint outList = u_push.resumeList ^ 1u;
    uint command = outList * 4u;
    uint slot = NO_STATE;
    if (subgroupElect()) {
        // Every row of the frame has room on a list; its state may not. The fourth word
        // counts the list's rows, which take the state slots in their order; its dispatch is
        // a workgroup a row, u_push.groupsX to a row of workgroups in x and the rest in z, so
        // that lists past 65535 rows dispatch.
        uint item = atomicAdd(g_dispatch[command + 3u], 1u);
        atomicAdd(g_counters.suspendedRows, 1u);
        atomicMax(g_dispatch[command], min(item + 1u, u_push.groupsX));
        atomicMax(g_dispatch[command + 2u], item / u_push.groupsX + 1u);
        slot = item;
        if (slot >= resumeCapacity) {
            // The row starts over when resumed; the host grows the states for later frames.
            atomicOr(g_counters.overflow, OVERFLOW_RESUME);
            atomicMax(g_counters.resumeNeeded, slot + 1u);
            atomicAdd(g_counters.restartedRows, 1u);
            slot = NO_STATE;
        }
        g_resumeItems[outList * itemCapacity + item] =
            block * TILES_PER_BLOCK + (row >> TILE_SHIFT);
    }
    slot = subgroupBroadcastFirst(slot);
    p.fragments = slot == NO_STATE ? 0u : p.fragments;
    if (slot != NO_STATE) {
        uint state = (outList * resumeCapacity + slot) * TILE_PIXELS + tileLane(row);
        g_pixelStates[state].radiance = vec4(p.radiance, 0.0);
        g_pixelStates[state].transmittance = vec4(p.transmittance, 0.0);
        g_pixelStates[state].done = uvec4(unpackUint2x32(p.doneKey).yx, p.finished ? 1u : 0u, 0u);
        if (PARTIAL_WALKS) {
            g_pixelStates[state].sweep =
                uvec4(r.resumeCursor, r.resumeEntry, unpackUint2x32(p.dropped));
            [[unroll]] for (int k = 0; k < SELECT_SIZE; k++) {
                g_pixelStates[state].selection[k] = unpackUint2x32(selection[k]);
            }
        } else {
            g_pixelStates[state].sweep = uvec4(NEW_SWEEP, 0u, 0u, 0u);
        }
    }
}

#endif
