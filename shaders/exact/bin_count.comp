#version 450
// Binning, pass 1: every triangle adds one to the count of each bin its bounds touch.

#include "exact_bindings.glsl"
#include "exact_bins.glsl"

layout(local_size_x = 64) in;

void main() {
    uint ti = gl_GlobalInvocationID.x;
    if (ti >= g_counters.triangleCount) {
        return;
    }
    ivec4 r = binRect(g_triangles[ti].bounds);
    for (int by = r.y; by <= r.w; by++) {
        for (int bx = r.x; bx <= r.z; bx++) {
            atomicAdd(g_binCounts[uint(by) * u_push.binsX + uint(bx)], 1u);
        }
    }
    atomicAdd(g_counters.binEntryCount, uint((r.z - r.x + 1) * (r.w - r.y + 1)));
}
