// The body of the exact bin raster; shaders/exact/raster.comp and raster_sampled.comp sample
// textures in software and in hardware (HARDWARE_SAMPLING: texture_sampler.glsl).
//
// Bin raster: one invocation per pixel, tiles of BIN_SIZE pixels across and TILE_ROWS rows
// down; no shared memory and no barriers. Each tile has its own bin: the list of triangles
// that may cover it, and a tile is what subgroup operations (votes, broadcasts, reductions)
// must see: it is one subgroup (bin_lists.glsl, raster_tile.glsl). Below, "the row" is the
// tile: one row of pixels where subgroups are 8 lanes. The host requires subgroups of at
// least BIN_SIZE, and holds the device to the size the tiles are made for where it can.
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
// it may run no iteration; the GPU variant's shading loop, which exits by vote, excepted),
// which took up to a third off the shallow scenes' rasters. Those drivers also end a
// shader's loops silently after 65535 iterations in all; the raster counts against
// LOOP_BUDGET (the device's: under that limit there, larger on GPUs) and hands what is left
// of a row to a continuation dispatch of this same shader (CONTINUATION; resume.glsl, where
// PARTIAL_WALKS says where a row stops).
//
// On GPUs (BRANCHING) a loop ends where the whole tile agrees (a vote), not lane by lane,
// and pixels off the frame's edge stay in as finished pixels instead of returning: every
// subgroup operation then runs with the whole tile, in uniform control flow, and the row's
// values (its budget, where it suspends, whether a sweep ends early) are the tile's
// without relying on lanes reconverging after a loop they left one by one, which Vulkan
// does not promise (VK_KHR_shader_maximal_reconvergence would; glslang 11 cannot ask for
// it). A GPU runs a subgroup until its last lane is done anyway; a CPU driver, where a vote
// is a loop over the lanes, keeps the per-lane exits.
//
// main reads as the walk: find the row and its list, resume its pixels, then sweeps
// (beginSweep) of stretches (walkStretch, nextStretch, compositeFinal) until every pixel is
// finished or the budget runs out (endSweep); suspend the row or write its pixels.

#extension GL_EXT_shader_explicit_arithmetic_types_int64 : require
#extension GL_KHR_shader_subgroup_ballot : require
#extension GL_KHR_shader_subgroup_arithmetic : require
#extension GL_KHR_shader_subgroup_vote : require
#extension GL_EXT_control_flow_attributes : require

#include "scene_bindings_compute.glsl"
#include "bins_bindings.glsl"
#include "raster.glsl"
#include "bin_lists.glsl"
#include "raster_tile.glsl"
#include "texture_sampler.glsl"
#include "shading.glsl"
#include "bin_fragment.glsl"
#include "selection.glsl"
#include "pixel.glsl"
#include "resume.glsl"

// The first dispatch of a band covers the tiles of the band's blocks with a non-empty bin
// (g_rasterBins from g_counters.bandFirst; blocks with none keep the opaque colour):
// groupRows() rows per workgroup (raster_tile.glsl), BIN_SIZE / groupRows() workgroups down
// each block. Continuations have one workgroup per resumed tile.

// The raster's own constants (interface_specialization.glsl): CONTINUATION, this dispatch
// resumes the items of a resume list; SELECT_SIZE, the fragments a pixel keeps. Larger means
// fewer sweeps for deep pixels, but a longer insertion for every triangle walked: the host
// starts at 8 and moves to DEEP_SELECT_SIZE (methods/exact/depth.rs) when pixels needed
// several sweeps.

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

// A sweep's start: the slabs every pixel has passed skipped, then its first stretch, the
// entries [from, to) of `slab` (the first slab with entries from r.skip on; none: an empty
// stretch), or, for a resumed row, where it was suspended.
void beginSweep(Pixel p, inout Row r, uint bin, uint first, uint end, out uint slab,
                out uint from, out uint to) {
    // What every pixel of the row has passed, as two 32-bit minima.
    uvec2 own = unpackUint2x32(p.finished ? NO_KEY : p.passed);
    uint high = subgroupMin(own.y);
    uint64_t rowPassed = packUint2x32(uvec2(subgroupMin(own.y == high ? own.x : ~0u), high));
    if (SLABS > 1u && r.skip < SLABS && slabFarthestKey(r.skip) < rowPassed) do {
        r.skip++;
        r.spent++;
    } while (r.skip < SLABS && slabFarthestKey(r.skip) < rowPassed);
    slab = r.resumeSweep ? r.resumeCursor : r.skip;
    from = slab < SLABS ? slabStart(bin, first, slab) : end;
    to = slab < SLABS ? slabEnd(bin, slab) : end;
    if (SLABS > 1u && from == to && to < end) do {
        slab++;
        to = slabEnd(bin, slab);
        r.spent++;
    } while (to == from);
    from = r.resumeSweep ? r.resumeEntry : from;
}

// Walks list entries [from, walkTo) of the row, every pixel in step, inserting the fragments
// it may still composite into its selection; the fragments it found.
uint walkStretch(inout Pixel p, inout uint64_t selection[SELECT_SIZE], uint64_t floorKey,
                 uint from, uint walkTo, uint end, uint x, uint y, float opaqueDepth) {
    uint found = 0u;
    // Each step fetches the next step's entry, so that its triangle's fetches need not wait
    // for it (3 % of deep rasters). Clamped, so no fetch falls past the list's end (the last
    // step re-reads its own entry).
    uint last = max(end, 1u) - 1u;
    uint nextEntry = walkedEntry(from, last);
    uint e = from;
    bool walking = true;
    if (e < walkTo) do {
        // The same entry for the whole row: a broadcast tells a GPU compiler so (one load and
        // one triangle's fetches for the subgroup); on CPU drivers it is a loop over the lanes
        // (3 % of the raster there).
        uint entry = BRANCHING ? subgroupBroadcastFirst(nextEntry) : nextEntry;
        nextEntry = walkedEntry(e + 1u, last);
        // A pixel that dropped a fragment nearer than this slab's floor can composite
        // nothing from here on in this sweep, so its walk ends (the row's when every pixel's
        // has). (On CPU drivers a per-pixel break, since a loop ends when no lane is left in
        // it; a vote would be another loop over the lanes.)
        bool stop = p.finished || p.dropped < floorKey;
        if (!BRANCHING && stop) {
            break;
        }
        walking = walking && !stop;
        if (BRANCHING && !subgroupAny(walking)) {
            break;
        }
        BinTriangle t = loadWalkedTriangle(entry);
        RasterSample s;
        bool take = coverSample(t, x, y, s);
        uint64_t key = fragmentKey(floatBitsToUint(s.viewDepth), t.order);
        take = take && (BRANCHING ? walking : !p.finished) && s.zNdc < opaqueDepth &&
               key > p.doneKey;
        found += take ? 1u : 0u;
        // A fragment not taken changes nothing (NO_KEY): GPUs skip the insertion where no
        // lane takes one; CPU drivers, where an `if` runs masked anyway, insert NO_KEY.
        if (BRANCHING) {
            if (take) {
                insertFragment(selection, p.dropped, key);
            }
        } else {
            insertFragment(selection, p.dropped, take ? key : NO_KEY);
        }
        e++;
    } while (e < walkTo);
    return found;
}

// The stretch after the one of `slab` ending at `to`: the next slab with entries, if the
// list goes on (then `next` and `nextTo` are that slab and where it ends).
bool nextStretch(uint bin, uint end, uint slab, uint to, inout Row r, out uint next,
                 out uint nextTo) {
    bool found = SLABS > 1u && to < end;
    next = slab;
    nextTo = to;
    if (found) do {
        next++;
        nextTo = slabEnd(bin, next);
        r.spent++;
    } while (nextTo == to);
    return found;
}

// Shades and composites the nearest selected fragment; whether the pixel is now opaque
// enough to finish.
bool compositeNearest(inout Pixel p, inout uint64_t selection[SELECT_SIZE], uint x, uint y,
                      FrameInfo frame) {
    BinTriangle t = loadShadingTriangle(uint(selection[0]));
    RasterSample s;
    sampleTriangle(t, x, y, s);
    vec3 l;
    vec3 tr;
    shadeFragment(t, x, y, s, frame, l, tr);
    p.radiance += p.transmittance * l;
    p.transmittance *= tr;
    p.doneKey = selection[0];
    bool opaqueEnough =
        u_push.threshold > 0.0 && all(lessThan(p.transmittance, vec3(u_push.threshold)));
    takeNearest(selection);
    return opaqueEnough;
}

// Shades and composites, nearest first, the selected fragments nearer than `final`, which
// nothing unwalked or dropped can come before; the row's budget takes what the row's
// longest such loop took, so that the whole row agrees on when to suspend.
void compositeFinal(inout Pixel p, inout uint64_t selection[SELECT_SIZE], uint64_t final,
                    uint x, uint y, FrameInfo frame, inout Row r) {
    uint composited = 0u;
    bool opaqueEnough = false;
    bool more = selection[0] < final && !p.finished;
    if (BRANCHING) {
        // Until the tile agrees, so that the subgroupMax below sees all of it.
        while (subgroupAny(more)) {
            if (more) {
                opaqueEnough = compositeNearest(p, selection, x, y, frame);
                composited++;
                more = selection[0] < final && !opaqueEnough;
            }
        }
    } else if (more) do {
        opaqueEnough = compositeNearest(p, selection, x, y, frame);
        composited++;
    } while (selection[0] < final && !opaqueEnough);
    p.fragments += composited;
    p.passed = max(p.passed, final);
    r.spent += shadingIterations(subgroupMax(composited));
    p.finished = p.finished || opaqueEnough;
}

// A sweep's end: pixels that left early (finished) did not see the rest, so the row's budget
// and whether it ran out are the row's; a pixel that dropped nothing in a sweep down to the
// list's end has composited everything. Unless the row is suspended inside the sweep, its
// selections start empty again.
void endSweep(inout Pixel p, inout uint64_t selection[SELECT_SIZE], inout Row r,
              bool endedEarly) {
    r.outOfBudget = subgroupAny(r.outOfBudget);
    r.spent = subgroupMax(r.spent);
    // Pixels that finished earlier in the sweep did not reach the suspension.
    if (PARTIAL_WALKS) {
        r.resumeCursor = subgroupMax(r.resumeCursor);
        r.resumeEntry = subgroupMax(r.resumeEntry);
    }
    p.finished = p.finished || (!r.outOfBudget && !endedEarly && p.dropped == NO_KEY);
    if (!PARTIAL_WALKS || !r.outOfBudget) {
        p.dropped = NO_KEY;
        clearSelection(selection);
    }
}

// Statistics: one atomic per subgroup, not per pixel, in the workgroup's slot.
void addStatistics(Pixel p) {
    uint subgroupFragments = subgroupAdd(p.fragments);
    uint subgroupSweeps = subgroupMax(p.sweeps);
    uint subgroupFound = subgroupAdd(p.firstFound);
    uint slot = (gl_WorkGroupID.x % STATISTICS_SLOTS) * 16u;
    if (subgroupElect()) {
        atomicAdd(g_counters.statistics[slot], subgroupFragments);
        atomicMax(g_counters.statistics[slot + 1u], subgroupSweeps);
        atomicAdd(g_counters.statistics[slot + 2u], subgroupFound);
    }
}

void main() {
    // Loads first, outside all control flow: CPU drivers load uniform values once for the
    // subgroup there, but once per lane after a branch (an early return counts).
    FrameInfo frame = u_frame;
    uint resumeCapacity = g_counters.resumeCapacity;
    uint itemCapacity = g_counters.resumeItemCapacity;
    uint block;
    uint row;
    uint stateSlot;
    if (!rowToRaster(itemCapacity, resumeCapacity, block, row, stateSlot)) {
        return;
    }
    // The tile's own bin: its slabs' parts of the list, near to far, each ending where the
    // next starts (slabEnd).
    uint tile = row >> TILE_SHIFT;
    uint bin = (block * TILES_PER_BLOCK + tile) * SLABS;
    uint first = binStart(block, tile, bin);
    uint end = g_binEnds[bin + SLABS - 1u];
    uint x = (block % u_push.binsX) * BIN_SIZE + laneColumn();
    uint y = (block / u_push.binsX) * BIN_SIZE + row;
    bool onFrame = x < u_push.width && y < u_push.height;
    if (!BRANCHING && !onFrame) {
        return;
    }
    float opaqueDepth = opaqueDepthAt(
        BRANCHING ? ivec2(min(x, u_push.width - 1u), min(y, u_push.height - 1u)) : ivec2(x, y));

    Pixel p = freshPixel();
    // Off the frame (GPUs): a pixel finished from the start, which writes nothing.
    p.finished = BRANCHING && !onFrame;
    uint64_t selection[SELECT_SIZE];
    clearSelection(selection);
    Row r = freshRow();
    // A resumed row without a saved state starts over (its pixels are untouched so far).
    if (CONTINUATION && stateSlot != NO_STATE) {
        resumePixel(stateSlot, resumeCapacity, row, p, selection, r);
    }

    // Sweeps of the list, each a loop over its stretches. What a sweep does at its start and
    // end is outside the stretch loop, where it runs once a sweep: inside, it ran masked in
    // every stretch (an `if` never branches on CPU drivers).
    do {
        uint slab;
        uint from;
        uint to;
        beginSweep(p, r, bin, first, end, slab, from, to);
        p.sweeps += p.finished || r.resumeSweep ? 0u : 1u;
        r.resumeSweep = false;
        // Where this sweep suspends the row, if it does, is the only resumption point from
        // here on: pixels that finish before it must not keep the one they were resumed at.
        r.resumeCursor = 0u;
        r.resumeEntry = 0u;
        bool nextFound = false;
        // The sweep ended before the list did, for a fragment some pixel of the row dropped.
        bool endedEarly = false;
        // A pixel leaves the stretch loop once it is finished, the row once all are or the
        // sweep is over. (On CPU drivers its own exit, a vote being a loop over the lanes;
        // on GPUs the tile's: see the top.)
        if (BRANCHING ? subgroupAny(!p.finished) : !p.finished) do {
            // Every entry of the stretch is of one slab, so its floor is the stretch's.
            uint64_t floorKey = slabFloorKey(min(slab, SLABS - 1u));
            // The entries of this stretch the budget has room for, after its shading and the
            // search for the next slab: all of them, but for rows whose lists are very long. A
            // row that cannot walk them all walks what it can and is suspended below, before
            // compositing anything.
            uint shadeCost = shadingIterations(uint(SELECT_SIZE));
            uint room = LOOP_BUDGET - min(r.spent + shadeCost + SLABS, LOOP_BUDGET);
            bool partial = to - from > room;
            if (partial && !PARTIAL_WALKS) {
                r.outOfBudget = true;
                break;
            }
            uint walkTo = partial ? from + room : to;
            r.spent += walkTo - from;
            uint found =
                walkStretch(p, selection, floorKey, from, walkTo, end, x, y, opaqueDepth);
            if (partial) {
                r.outOfBudget = true;
                r.resumeCursor = slab;
                r.resumeEntry = walkTo;
                break;
            }
            p.firstFound += p.sweeps == 1u && !CONTINUATION ? found : 0u;
            // Whatever a pixel keeps nearer than the next stretch's floor is final.
            uint next;
            uint nextTo;
            nextFound = nextStretch(bin, end, slab, to, r, next, nextTo);
            uint64_t limit = nextFound ? slabFloorKey(next) : NO_KEY;
            compositeFinal(p, selection, min(limit, p.dropped), x, y, frame, r);
            slab = next;
            from = to;
            to = nextTo;
            // Only for a fragment dropped before the next slab: a pixel that dropped only
            // fragments past it has composited all it can here, walks on, and ends the sweep
            // where it could composite no more. (Ending for any drop, a pixel whose kept
            // fragments all lay past the next slab composited nothing, and the next sweep
            // ended in the same place: tilted stacks never finished.)
            bool stillWorking = !BRANCHING || !p.finished;
            endedEarly = nextFound && subgroupAny(stillWorking && p.dropped < limit);
        } while (nextFound && !endedEarly &&
                 (BRANCHING ? subgroupAny(!p.finished) : !p.finished));
        endSweep(p, selection, r, endedEarly);
    } while (!r.outOfBudget && subgroupAny(!p.finished));
    // After the loop, so that the suspension's code, which runs masked whenever it is not
    // taken (an `if` never branches on CPU drivers), runs once a row, not once a stretch.
    if (!PARTIAL_WALKS && r.outOfBudget && r.spent == 0u && subgroupElect()) {
        // Not even one stretch fits a fresh budget: the row is suspended as it is, and the
        // continuations, which walk lists in parts, go through it. Later frames move to
        // slabs, where the first dispatch does too.
        atomicOr(g_counters.overflow, OVERFLOW_CROWDED_BIN);
        atomicAdd(g_counters.crowdedRows, 1u);
    }
    if (r.outOfBudget) {
        suspendRow(p, selection, r, block, row, itemCapacity, resumeCapacity);
    } else if (onFrame && (p.fragments > 0u || CONTINUATION)) {
        // A resumed pixel writes what earlier dispatches gathered too.
        writePixel(ivec2(x, y), p.radiance, p.transmittance);
    }
    addStatistics(p);
}
