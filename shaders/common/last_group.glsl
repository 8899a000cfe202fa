// One dispatch for a step whose last part needs what every workgroup wrote (the depth
// pyramid's upper levels, the scan of the block totals, the slab plan): each workgroup does
// its share, and the last to finish goes on with the rest alone: a dispatch and a barrier
// fewer, each a fixed cost of the frame.
#ifndef TRANSLUCID_LAST_GROUP_GLSL
#define TRANSLUCID_LAST_GROUP_GLSL

#include "bins_bindings.glsl"

shared bool s_lastGroup;

// Whether this workgroup is the dispatch's last to finish; every invocation of the workgroup
// gets the same answer. The workgroup's writes are made visible first, so that the last one
// sees every workgroup's (through buffers declared coherent).
bool lastGroupDone(uint counter) {
    memoryBarrierBuffer();
    barrier();
    if (gl_LocalInvocationIndex == 0u) {
        uint groups = gl_NumWorkGroups.x * gl_NumWorkGroups.y * gl_NumWorkGroups.z;
        s_lastGroup = atomicAdd(g_counters.groupsDone[counter], 1u) == groups - 1u;
    }
    barrier();
    bool last = s_lastGroup;
    // What the others wrote before they counted themselves.
    memoryBarrierBuffer();
    return last;
}

#endif
