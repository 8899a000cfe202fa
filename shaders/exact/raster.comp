#version 450
// Bin raster: one invocation per pixel, rows of BIN_SIZE pixels; no shared memory and no
// barriers. Each row has its own bin: the list of triangles that may cover it, and a row is
// what subgroup operations (votes, broadcasts, reductions) must see. So a workgroup is one
// row on devices whose subgroups are wider than a row (most GPUs: 32 or 64; one subgroup
// then holds the whole workgroup), and a whole 8x8 block where subgroups are exactly a row
// wide (lavapipe on AVX2), whose subgroups take consecutive invocations, so each is one row.
// The host requires subgroups of at least BIN_SIZE.
//
// Each pixel keeps, as it walks its row's triangles, the SELECT_SIZE nearest fragments behind
// the last one it composited, sorted in registers by a fully unrolled insertion (constant
// indices only). All invocations walk the row's list in step, a stretch at a time: the
// entries of one depth slab (bin_lists.glsl; shallow frames have one slab, the whole list).
// After each stretch a pixel shades and composites, front to back, the fragments it keeps
// that are nearer than the next slab's floor and than any fragment it had to drop: nothing
// still unwalked or dropped can come before them. A sweep is a walk down the list; it ends
// at the list's end, where a pixel that dropped nothing is done, or after the first stretch
// in which some pixel of the row had to drop a fragment. The row then sweeps again from the
// first slab a pixel may still need a fragment of: past the leading slabs whose farthest
// fragment every pixel has passed, so that a fragment dropped in one slab costs a walk over
// about that slab, not over the rest of the list (100,000 random one-triangle draws at
// 160x120, where many pixels hold more fragments in some slab than their selection: from
// 9x to about 2x blend's time).
// So a deep pixel needs room for the fragments of about one slab, not all of its own: at
// 1280x720, particles (60 deep) take 3 sweeps of 16, where selecting the 24 nearest per
// pass and compositing only at the pass's end took 7-8 % longer, with a threshold or
// without. Transmittance under the threshold ends a pixel at once.
// Order is exact by construction: fragments are ranked by (view depth, draw, quad,
// triangle) like the CPU reference, so no pixel is ever out of order.
//
// On CPU drivers such as lavapipe an `if` does not branch: both sides run under a mask, so
// cost is the code inside each loop times its iterations, and only loop exits save work.
// Shading therefore runs in its own loop of at most SELECT_SIZE iterations per stretch
// instead of inside the walk (measured 1.5-9x slower there). Those drivers test a loop's
// exit at the end of each iteration, so a `for` or `while` runs its body once more, masked,
// after its last lanes leave at the top: every loop here is a do-while (behind an `if` where
// it may run no iteration), which took up to a third off the shallow scenes' rasters. Those
// drivers also end a shader's loops silently after 65535 iterations in all; the raster
// counts against LOOP_BUDGET and hands what is left of a row to a continuation dispatch of
// this same shader (CONTINUATION); see PARTIAL_WALKS for where a row stops.

#extension GL_EXT_shader_explicit_arithmetic_types_int64 : require
#extension GL_KHR_shader_subgroup_ballot : require
#extension GL_KHR_shader_subgroup_arithmetic : require
#extension GL_KHR_shader_subgroup_vote : require
#extension GL_EXT_control_flow_attributes : require

#include "scene_bindings_compute.glsl"
#include "bins_bindings.glsl"
#include "raster.glsl"
#include "bin_lists.glsl"
#include "texture_sampler.glsl"
#include "shading.glsl"
#include "bin_fragment.glsl"

// The first dispatch of a band covers the rows of the band's blocks with a non-empty bin
// (g_rasterBins from g_counters.bandFirst; blocks with none keep the opaque colour):
// gl_WorkGroupSize.y rows per workgroup (RASTER_ROWS: BIN_SIZE or 1),
// BIN_SIZE / gl_WorkGroupSize.y workgroups down each block. Continuations have one workgroup
// per resumed row.
layout(local_size_x = BIN_SIZE, local_size_y_id = RASTER_ROWS_ID) in;

// The raster's own constants (interface_specialization.glsl): CONTINUATION, this dispatch
// resumes the items of a resume list; SELECT_SIZE, the fragments a pixel keeps. Larger means
// fewer sweeps for deep pixels, but a longer insertion for every triangle walked: the host
// starts at 8 and moves to DEEP_SELECT_SIZE (features.rs) when pixels needed several sweeps.

// A fragment's rank as one number: view depth bits (positive floats order like their bits),
// then the order key. One 64-bit compare instead of three 32-bit ones in the insertion.
uint64_t fragmentKey(uint depthBits, uint order) {
    return (uint64_t(depthBits) << 32) | uint64_t(order);
}

const uint64_t NO_KEY = 0xFFFFFFFFFFFFFFFFul;

// Rows of deep frames (SLABS > 1) and of continuations are suspended wherever their budget
// runs out, even inside a stretch too long for one budget, and resumed there with their
// pixels' selections. Rows of a shallow frame's first dispatch are suspended only between
// stretches and start a new sweep when resumed (NEW_SWEEP): saving selections costs every
// row (the code runs masked when not taken) some 5 % of a textured scene's raster. A
// shallow row whose stretch no budget holds is suspended before walking it, and the
// continuations walk it in parts (reported as OVERFLOW_CROWDED_BIN: later frames take slabs).
const bool PARTIAL_WALKS = SLABS > 1u || CONTINUATION;

// Loop iterations a stretch's shading of `fragments` fragments may take, counted
// generously: the shading loop and the software sampler's mip loops.
uint shadingIterations(uint fragments) {
    return 4u + fragments * (TEXTURES ? 40u : 2u);
}

// Where slab k of the row's list (at `bin`) ends and slab k + 1 starts. Filling left every
// (bin, slab) offset at the end of its part of the list.
uint slabEnd(uint bin, uint k) {
    return g_binEnds[bin + k];
}

uint slabStart(uint bin, uint first, uint k) {
    return k == 0u ? first : g_binEnds[bin + k - 1u];
}

// A key no fragment of slab k's triangles passes, anywhere in the frame: their farthest
// depth bits and largest order key. With one slab, binning keeps none; none is needed, since
// a row whose pixels have all passed every fragment has finished.
uint64_t slabFarthestKey(uint k) {
    uint slab = min(k, SLABS - 1u);
    return SLABS > 1u ? (uint64_t(g_counters.slabFarthest[slab]) << 32) |
                            uint64_t(g_counters.slabLastOrder[slab])
                      : NO_KEY;
}

void main() {
    // Loads first, outside all control flow: CPU drivers load uniform values once for the
    // subgroup there, but once per lane after a branch (an early return counts).
    FrameInfo frame = u_frame;
    uint resumeCapacity = g_counters.resumeCapacity;
    uint itemCapacity = g_counters.resumeItemCapacity;
    uint block;
    uint row;
    uint stateSlot = NO_STATE;
    if (CONTINUATION) {
        // The list's last row of workgroups may run past its items (see the suspension).
        uint index = linearWorkGroup();
        if (index >= g_dispatch[u_push.resumeList * 4u + 3u]) {
            return;
        }
        uint item = g_resumeItems[u_push.resumeList * itemCapacity + index];
        block = item / BIN_SIZE;
        row = item % BIN_SIZE;
        stateSlot = index < resumeCapacity ? index : NO_STATE;
    } else {
        block = g_rasterBins[g_counters.bandFirst + linearWorkGroup()];
        row = gl_WorkGroupID.y * gl_WorkGroupSize.y + gl_LocalInvocationID.y;
    }
    // The row's own bin: its slabs' parts of the list, near to far, each ending where the
    // next starts (slabEnd).
    uint bin = (block * BIN_SIZE + row) * SLABS;
    uint first = binStart(block, row, bin);
    uint end = g_binEnds[bin + SLABS - 1u];
    uint x = (block % u_push.binsX) * BIN_SIZE + gl_LocalInvocationID.x;
    uint y = (block / u_push.binsX) * BIN_SIZE + row;
    if (x >= u_push.width || y >= u_push.height) {
        return;
    }
    float opaqueDepth = opaqueDepthAt(ivec2(x, y));

    vec3 radiance = vec3(0.0);
    vec3 transmittance = vec3(1.0);
    // Fragments up to and including doneKey are composited (0: none yet; no fragment has
    // depth 0), and every fragment nearer than `passed`, which may be further on: a stretch
    // that ends with nothing to composite still passes its part of the order.
    uint64_t doneKey = 0ul;
    uint64_t passed = 0ul;
    // Finished pixels wait for the rest of their row, so that a row is suspended and resumed
    // whole.
    bool finished = false;
    // The selection, kept from one stretch to the next within a sweep: fragment keys alone,
    // since a key's low half, the order key, is its triangle's record.
    uint64_t selKey[SELECT_SIZE];
    [[unroll]] for (int k = 0; k < SELECT_SIZE; k++) {
        selKey[k] = NO_KEY;
    }
    // The nearest fragment this sweep found but could not keep (NO_KEY: none).
    uint64_t dropped = NO_KEY;
    // A row is suspended inside a sweep and resumed there, with its pixels' selections: at
    // the stretch its search for a slab started from (resumeCursor), at list entry
    // resumeEntry. Uniform across the row.
    bool resumeSweep = false;
    uint resumeCursor = 0u;
    uint resumeEntry = 0u;
    // A resumed row without a saved state starts over (its pixels are untouched so far).
    if (CONTINUATION && stateSlot != NO_STATE) {
        uint slot = u_push.resumeList * resumeCapacity + stateSlot;
        ExactPixelState state = g_pixelStates[slot * BIN_SIZE + gl_LocalInvocationID.x];
        radiance = state.radiance.xyz;
        transmittance = state.transmittance.xyz;
        doneKey = fragmentKey(state.done.x, state.done.y);
        passed = doneKey;
        finished = state.done.z != 0u;
        // Rows saved between sweeps start a new one.
        resumeSweep = state.sweep.x != NEW_SWEEP;
        resumeCursor = state.sweep.x;
        resumeEntry = state.sweep.y;
        dropped = resumeSweep ? packUint2x32(state.sweep.zw) : NO_KEY;
        [[unroll]] for (int k = 0; k < SELECT_SIZE; k++) {
            selKey[k] = resumeSweep ? packUint2x32(state.selection[k]) : NO_KEY;
        }
    }
    uint sweeps = 0u;
    uint fragments = 0u;
    // Fragments the pixel's first sweep found, all of them unless it had to drop some: its
    // depth, whatever the threshold.
    uint firstFound = 0u;
    // Uniform across the subgroup: every pixel of a row walks the same list.
    uint spent = 0u;
    bool outOfBudget = false;
    bool suspended = false;

    // The leading slabs that every pixel still at work has composited entirely, which sweeps
    // skip: a number that only grows, since what pixels have composited does.
    uint skip = 0u;
    bool opaqueEnough = false;

    // Sweeps of the list, each a loop over its stretches. What a sweep does at its start and
    // end is outside the stretch loop, where it runs once a sweep: inside, it ran masked in
    // every stretch (an `if` never branches on CPU drivers).
    do {
        // What every pixel of the row has passed, as two 32-bit minima.
        uvec2 own = unpackUint2x32(finished ? NO_KEY : passed);
        uint high = subgroupMin(own.y);
        uint64_t rowPassed = packUint2x32(uvec2(subgroupMin(own.y == high ? own.x : ~0u), high));
        if (SLABS > 1u && skip < SLABS && slabFarthestKey(skip) < rowPassed) do {
            skip++;
            spent++;
        } while (skip < SLABS && slabFarthestKey(skip) < rowPassed);
        // This sweep's first stretch: the first slab with entries from `skip` on (none: an
        // empty stretch), or, for a resumed row, where it was suspended.
        uint slab = resumeSweep ? resumeCursor : skip;
        uint from = slab < SLABS ? slabStart(bin, first, slab) : end;
        uint to = slab < SLABS ? slabEnd(bin, slab) : end;
        if (SLABS > 1u && from == to && to < end) do {
            slab++;
            to = slabEnd(bin, slab);
            spent++;
        } while (to == from);
        from = resumeSweep ? resumeEntry : from;
        sweeps += finished || resumeSweep ? 0u : 1u;
        resumeSweep = false;
        // Where this sweep suspends the row, if it does, is the only resumption point from
        // here on: pixels that finish before it must not keep the one they were resumed at.
        resumeCursor = 0u;
        resumeEntry = 0u;
        bool nextFound = false;
        // The sweep ended before the list did, for a fragment some pixel of the row dropped.
        bool endedEarly = false;
        // A pixel leaves the stretch loop once it is finished, the row once all are or the
        // sweep is over. (Its own exit: a vote would be a loop over the lanes.)
        if (!finished) do {
            // Every entry of the stretch is of one slab, so its floor is the stretch's.
            uint64_t floorKey = slabFloorKey(min(slab, SLABS - 1u));
            // The entries of this stretch the budget has room for, after its shading and the
            // search for the next slab: all of them, but for rows whose lists are very long. A row that cannot walk them all
            // walks what it can and is suspended below, before compositing anything.
            uint shadeCost = shadingIterations(uint(SELECT_SIZE));
            uint room = LOOP_BUDGET - min(spent + shadeCost + SLABS, LOOP_BUDGET);
            bool partial = to - from > room;
            if (partial && !PARTIAL_WALKS) {
                outOfBudget = true;
                break;
            }
            uint walkTo = partial ? from + room : to;
            spent += walkTo - from;
            uint found = 0u;
            // Each step fetches the next step's entry, so that its triangle's fetches need not
            // wait for it (3 % of deep rasters). Clamped, so no fetch falls past the list's end
            // (the last step re-reads its own entry).
            uint last = max(end, 1u) - 1u;
            uint nextEntry = texelFetch(u_binEntryTexels, int(min(from, last))).r;
            uint e = from;
            if (e < walkTo) do {
                // The same entry for the whole row. (A broadcast would tell a GPU compiler so, but
                // on CPU drivers it is a loop over the lanes: 3 % of the raster.)
                uint entry = nextEntry;
                nextEntry = texelFetch(u_binEntryTexels, int(min(e + 1u, last))).r;
                // A pixel that dropped a fragment nearer than this slab's floor can composite
                // nothing from here on in this sweep, so its walk ends (the row's when every
                // pixel's has). (A per-pixel break, since a loop ends when no lane is left in it;
                // a vote would be another loop over the lanes.)
                if (finished || dropped < floorKey) {
                    break;
                }
                uint ti = entry;
                BinTriangle t = loadTriangle(ti);
                RasterSample s;
                bool take = coverSample(t, x, y, s);
                uint64_t key = fragmentKey(floatBitsToUint(s.viewDepth), t.order);
                take = take && !finished && s.zNdc < opaqueDepth && key > doneKey;
                found += take ? 1u : 0u;
                key = take ? key : NO_KEY;
                // Insert, dropping the last: each slot takes its left neighbour, the new key, or
                // keeps its own, whichever is in the middle (keys are distinct but for NO_KEY),
                // walking right to left (left neighbours are still unchanged). A fragment not
                // taken has NO_KEY, which sorts before no slot. What falls out of a full
                // selection is the larger of the new key and the last.
                dropped = min(dropped, max(key, selKey[SELECT_SIZE - 1]));
                [[unroll]] for (int k = SELECT_SIZE - 1; k > 0; k--) {
                    selKey[k] = max(selKey[k - 1], min(key, selKey[k]));
                }
                selKey[0] = min(selKey[0], key);
                e++;
            } while (e < walkTo);
            if (partial) {
                outOfBudget = true;
                resumeCursor = slab;
                resumeEntry = walkTo;
                break;
            }
            firstFound += sweeps == 1u && !CONTINUATION ? found : 0u;
            // The next stretch: the next slab with entries, if the list goes on. Whatever a
            // pixel keeps nearer than its floor is final.
            nextFound = SLABS > 1u && to < end;
            uint next = slab;
            uint nextTo = to;
            if (nextFound) do {
                next++;
                nextTo = slabEnd(bin, next);
                spent++;
            } while (nextTo == to);
            uint64_t limit = nextFound ? slabFloorKey(next) : NO_KEY;
            // Composite, nearest first, what nothing unwalked or dropped can come before:
            // slot 0, then shift the selection left (SELECT_SIZE moves; picking slot i by
            // selects instead would need the kept slots compacted before the next stretch's
            // insertions).
            uint64_t final = min(limit, dropped);
            uint composited = 0u;
            if (selKey[0] < final && !finished) do {
                uint ti = uint(selKey[0]);
                BinTriangle t = loadShadingTriangle(ti);
                RasterSample s;
                sampleTriangle(t, x, y, s);
                vec3 l;
                vec3 tr;
                shadeFragment(t, x, y, s, frame, l, tr);
                radiance += transmittance * l;
                transmittance *= tr;
                doneKey = selKey[0];
                composited++;
                opaqueEnough = u_push.threshold > 0.0 &&
                               all(lessThan(transmittance, vec3(u_push.threshold)));
                [[unroll]] for (int k = 0; k < SELECT_SIZE - 1; k++) {
                    selKey[k] = selKey[k + 1];
                }
                selKey[SELECT_SIZE - 1] = NO_KEY;
            } while (selKey[0] < final && !opaqueEnough);
            fragments += composited;
            passed = max(passed, final);
            // What the shading loop took: the same for the whole row, so that all of it
            // agrees on when to suspend.
            spent += shadingIterations(subgroupMax(composited));
            finished = finished || opaqueEnough;
            slab = next;
            from = to;
            to = nextTo;
            // Only for a fragment dropped before the next slab: a pixel that dropped only
            // fragments past it has composited all it can here, walks on, and ends the sweep
            // where it could composite no more. (Ending for any drop, a pixel whose kept
            // fragments all lay past the next slab composited nothing, and the next sweep
            // ended in the same place: tilted stacks never finished.)
            endedEarly = nextFound && subgroupAny(dropped < limit);
        } while (nextFound && !finished && !endedEarly);
        // Pixels that left early (finished) did not see the rest: the row's budget and
        // whether it ran out are the row's.
        outOfBudget = subgroupAny(outOfBudget);
        spent = subgroupMax(spent);
        // Pixels that finished earlier in the sweep did not reach the suspension.
        if (PARTIAL_WALKS) {
            resumeCursor = subgroupMax(resumeCursor);
            resumeEntry = subgroupMax(resumeEntry);
        }
        // The sweep is over, unless the row was suspended in it: a pixel that dropped nothing
        // in a sweep down to the list's end has composited everything.
        finished = finished || (!outOfBudget && !endedEarly && dropped == NO_KEY);
        if (!PARTIAL_WALKS || !outOfBudget) {
            dropped = NO_KEY;
            [[unroll]] for (int k = 0; k < SELECT_SIZE; k++) {
                selKey[k] = NO_KEY;
            }
        }
    } while (!outOfBudget && subgroupAny(!finished));
    // After the loop, so that the suspension's code, which runs masked whenever it is not
    // taken (an `if` never branches on CPU drivers), runs once a row, not once a stretch.
    if (!PARTIAL_WALKS && outOfBudget && spent == 0u && subgroupElect()) {
        // Not even one stretch fits a fresh budget: the row is suspended as it is, and the
        // continuations, which walk lists in parts, go through it. Later frames move to
        // slabs, where the first dispatch does too.
        atomicOr(g_counters.overflow, OVERFLOW_CROWDED_BIN);
        atomicAdd(g_counters.crowdedRows, 1u);
    }
    if (outOfBudget) {
        uint outList = u_push.resumeList ^ 1u;
        uint command = outList * 4u;
        uint slot = NO_STATE;
        if (subgroupElect()) {
            // Every row of the frame has room on a list; its state may not. The fourth word
            // counts the list's rows, which take the state slots in their order; its
            // dispatch is a workgroup a row, u_push.groupsX to a row of workgroups in x and
            // the rest in z, so that lists past 65535 rows dispatch.
            uint item = atomicAdd(g_dispatch[command + 3u], 1u);
            atomicMax(g_dispatch[command], min(item + 1u, u_push.groupsX));
            atomicMax(g_dispatch[command + 2u], item / u_push.groupsX + 1u);
            slot = item;
            if (slot >= resumeCapacity) {
                // The row starts over when resumed; the host grows the states for later
                // frames.
                atomicOr(g_counters.overflow, OVERFLOW_RESUME);
                atomicMax(g_counters.resumeNeeded, slot + 1u);
                atomicAdd(g_counters.restartedRows, 1u);
                slot = NO_STATE;
            }
            g_resumeItems[outList * itemCapacity + item] = block * BIN_SIZE + row;
        }
        slot = subgroupBroadcastFirst(slot);
        // A row without a state starts over: what it composited here is counted then.
        fragments = slot == NO_STATE ? 0u : fragments;
        if (slot != NO_STATE) {
            uint state = (outList * resumeCapacity + slot) * BIN_SIZE + gl_LocalInvocationID.x;
            g_pixelStates[state].radiance = vec4(radiance, 0.0);
            g_pixelStates[state].transmittance = vec4(transmittance, 0.0);
            g_pixelStates[state].done =
                uvec4(unpackUint2x32(doneKey).yx, finished ? 1u : 0u, 0u);
            if (PARTIAL_WALKS) {
                g_pixelStates[state].sweep =
                    uvec4(resumeCursor, resumeEntry, unpackUint2x32(dropped));
                [[unroll]] for (int k = 0; k < SELECT_SIZE; k++) {
                    g_pixelStates[state].selection[k] = unpackUint2x32(selKey[k]);
                }
            } else {
                g_pixelStates[state].sweep = uvec4(NEW_SWEEP, 0u, 0u, 0u);
            }
        }
        suspended = true;
    }
    // A resumed pixel writes what earlier dispatches gathered too.
    if ((fragments > 0u || CONTINUATION) && !suspended) {
        writePixel(ivec2(x, y), radiance, transmittance);
    }
    // Statistics: one atomic per subgroup, not per pixel, in the workgroup's slot.
    uint subgroupFragments = subgroupAdd(fragments);
    uint subgroupSweeps = subgroupMax(sweeps);
    uint subgroupFound = subgroupAdd(firstFound);
    uint slot = (gl_WorkGroupID.x % STATISTICS_SLOTS) * 16u;
    if (subgroupElect()) {
        atomicAdd(g_counters.statistics[slot], subgroupFragments);
        atomicMax(g_counters.statistics[slot + 1u], subgroupSweeps);
        atomicAdd(g_counters.statistics[slot + 2u], subgroupFound);
    }
}
