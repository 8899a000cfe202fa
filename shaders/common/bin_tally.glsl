// A binning workgroup's tally of its bin entries, so that the global count of a bin takes
// one atomic per workgroup that enters it rather than one per entry (the GPU profile, in
// frames of one slab: BIN_TALLY_BITS, methods/bins/features.rs). Neighbouring triangles of
// a mesh enter the same bins, and on a GPU thousands of invocations adding to one word wait
// on each other; on a CPU driver the table's probes cost more than the atomics they save
// (measured on lavapipe: docs/performance-log.md), so it is off there.
//
// The tally is a small open-addressing table in shared memory from bin to entries: a lane
// claims a bin's slot by compare-and-swap and adds to it; a bin whose few probes all meet
// other bins is not tallied and takes its global atomic at once. Slots are claimed and never
// freed within a workgroup, so a bin is either tallied in every lane that enters it or in
// none (its probes met the same claimed slots in each), and the count (flushTally) and the
// fill (reserveTally, nextPlace) agree on which.
#ifndef TRANSLUCID_BIN_TALLY_GLSL
#define TRANSLUCID_BIN_TALLY_GLSL

#include "bin_lists.glsl"

// Only frames of one slab tally: a workgroup holds 64 triangles, mostly small and
// neighbours. Deep frames' workgroups hold 8 large ones (ROW_LANES a triangle) whose
// hundreds of entries each would overflow the table and pay its probes for nothing.
const bool TALLIED = BIN_TALLY_BITS > 0u && SLABS == 1u;
// One slot when off, which nothing reads.
const uint TALLY_SLOTS = 1u << BIN_TALLY_BITS;
const uint NO_TALLY = 0xFFFFFFFFu;
// Probes before a bin gives up on the table: few, as a table that full gains little.
const uint TALLY_PROBES = 4u;

shared uint s_tallyBins[TALLY_SLOTS];
// Entries of each slot's bin; in the fill, once reserved, the next free place in its list.
shared uint s_tallyCounts[TALLY_SLOTS];

// Empties the table. Every invocation of the workgroup calls it, in uniform control flow.
void clearTally() {
    for (uint i = gl_LocalInvocationIndex; i < TALLY_SLOTS; i += BINNING_GROUP_SIZE) {
        s_tallyBins[i] = NO_TALLY;
        s_tallyCounts[i] = 0u;
    }
    barrier();
}

// The first slot bin `bin` probes: a multiplicative hash, since neighbouring blocks' bins
// have neighbouring indices. (The shift is masked only so that it stays defined when the
// tally is off and nothing calls this.)
uint tallyHome(uint bin) {
    return (bin * 2654435761u) >> ((32u - BIN_TALLY_BITS) & 31u);
}

// The slot that holds bin `bin`, or NO_TALLY. With `claim`, the probes take the first empty
// slot for it by compare-and-swap (which also reads the slots without racing the lanes that
// claim them); without, the table must be complete (after a barrier). Written out rather
// than looped, so that it does not count against the loop budget.
uint tallySlot(uint bin, bool claim) {
    uint slot = tallyHome(bin);
    uint found = NO_TALLY;
    [[unroll]] for (uint probe = 0u; probe < TALLY_PROBES; probe++) {
        if (found == NO_TALLY) {
            uint held = claim ? atomicCompSwap(s_tallyBins[slot], NO_TALLY, bin)
                              : s_tallyBins[slot];
            // The swap returns NO_TALLY where this lane claimed the slot.
            found = held == bin || (claim && held == NO_TALLY) ? slot : NO_TALLY;
        }
        slot = (slot + 1u) & (TALLY_SLOTS - 1u);
    }
    return found;
}

// Adds one entry of bin `bin` to the tally; false if the bin is not tallied.
bool tallyEntry(uint bin) {
    uint slot = tallySlot(bin, true);
    if (slot == NO_TALLY) {
        return false;
    }
    atomicAdd(s_tallyCounts[slot], 1u);
    return true;
}

// The count: adds the tallied bins' entries to their global counts, one atomic a bin.
// Every invocation calls it once its entries are in, in uniform control flow.
void flushTally() {
    barrier();
    for (uint i = gl_LocalInvocationIndex; i < TALLY_SLOTS; i += BINNING_GROUP_SIZE) {
        uint bin = s_tallyBins[i];
        if (bin != NO_TALLY) {
            atomicAdd(g_binEnds[bin], s_tallyCounts[i]);
        }
    }
}

// The fill: reserves each tallied bin's entries in its list, one atomic a bin, and keeps
// where they start as the slot's cursor. Called as flushTally is.
void reserveTally() {
    barrier();
    for (uint i = gl_LocalInvocationIndex; i < TALLY_SLOTS; i += BINNING_GROUP_SIZE) {
        uint bin = s_tallyBins[i];
        if (bin != NO_TALLY) {
            s_tallyCounts[i] = atomicAdd(g_binEnds[bin], s_tallyCounts[i]);
        }
    }
    barrier();
}

// The place in its list of the next entry of bin `bin`: from its tally's reservation, or a
// global atomic of its own where the bin is not tallied.
uint nextPlace(uint bin) {
    uint slot = TALLIED ? tallySlot(bin, false) : NO_TALLY;
    return slot != NO_TALLY ? atomicAdd(s_tallyCounts[slot], 1u) : atomicAdd(g_binEnds[bin], 1u);
}

#endif
