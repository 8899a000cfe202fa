#version 450
// Binning, pass 1: every triangle adds one to the count of each bin it may cover.

#include "exact_bindings.glsl"
#include "exact_bins.glsl"

layout(local_size_x = 64) in;

void main() {
    uint ti = gl_GlobalInvocationID.x;
    if (ti >= g_counters.triangleCount) {
        return;
    }
    ExactTriangle t = loadTriangle(ti);
    ivec4 r = binRect(t.bounds);
    ivec2 rows = sliceRows(r);
    uint touched = 0u;
    for (int by = rows.x; by <= rows.y; by++) {
        ivec2 cols = rowColumns(t, by, r.xz);
        for (int bx = cols.x; bx <= cols.y; bx++) {
            int x0 = bx << BIN_SHIFT;
            if (!mayCoverRect(t, x0, by, x0 + BIN_SIZE, by + 1)) {
                continue;
            }
            atomicAdd(g_binCounts[binIndex(bx, by)], 1u);
            touched++;
        }
    }
    atomicAdd(g_counters.binEntryCount, touched);
}
