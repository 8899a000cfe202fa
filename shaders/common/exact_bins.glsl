// The bins a triangle's bounds touch.
#ifndef TRANSLUCID_EXACT_BINS_GLSL
#define TRANSLUCID_EXACT_BINS_GLSL

#include "exact_layout.glsl"

#extension GL_EXT_shader_explicit_arithmetic_types_int64 : require

// Each bin's list holds SLABS depth slabs, near to far. Slabs split the frame's range of
// triangle view depths (ExactCounters.depthLo..depthHi) evenly in float-bit space, which is
// close to logarithmic in depth, and a triangle goes to the slab of its nearest vertex.
// Walking the slabs in order, a pixel that already holds its nearest fragments can stop at
// the first slab whose floor is past them. Shallow frames keep one slab: the host raises
// SLAB_BITS (a specialization constant of the binning and raster stages) when pixels turn
// out deep, since more slabs cost a longer scan.
layout(constant_id = 6) const uint SLAB_BITS = 0u;
const uint SLABS = 1u << SLAB_BITS;

// The bins a non-empty pixel rectangle touches: inclusive block columns (x, z) and pixel
// rows (y, w).
ivec4 binRect(ivec4 bounds) {
    return ivec4(bounds.x >> BIN_SHIFT, bounds.y, (bounds.z - 1) >> BIN_SHIFT, bounds.w - 1);
}

// The bin of block column bx in pixel row y.
uint binIndex(int bx, int y) {
    uint block = uint(y >> BIN_SHIFT) * u_push.binsX + uint(bx);
    return block * BIN_SIZE + uint(y & (BIN_SIZE - 1));
}

// The pixel rows of `r` this binning invocation covers. A triangle's bins are split into
// slices of u_push.binRowsPerSlice rows, one invocation each (gl_GlobalInvocationID.y), so
// that no invocation loops more than LOOP_BUDGET times however large the triangle and frame;
// setup sizes the dispatch to the triangle that needs the most (binningSlices). Shallow
// frames slice each triangle from its first row, so that a frame of triangles under a
// slice's height bins each once (slices of the frame's rows cost every triangle a second,
// empty invocation: the dragon's binning 6.7 ms instead of 9.3). Deep frames (SLABS > 1)
// slice the frame's rows: their triangles enter hundreds of bins each, and there the threads
// appending to the lists of different parts of the screen took 3.5 ms off particles' fill.
ivec2 sliceRows(ivec4 r) {
    int rows = int(u_push.binRowsPerSlice);
    int first = (SLABS > 1u ? 0 : r.y) + int(gl_GlobalInvocationID.y) * rows;
    return ivec2(max(r.y, first), min(r.w, first + rows - 1));
}

// The slices a triangle with pixel bounds `bounds` needs (sliceRows).
uint binningSlices(ivec4 bounds) {
    uint rows = uint(max(bounds.w - (SLABS > 1u ? 0 : bounds.y), 0));
    return max((rows + u_push.binRowsPerSlice - 1u) / u_push.binRowsPerSlice, 1u);
}

// Bits of a triangle's nearest and farthest vertex view depth, widened by a relative 2^-12
// so that every fragment's interpolated depth, rounded in float, lies between them.
// Homogeneous triangles (a vertex may be behind the eye) span everything.
uvec2 triangleDepthBits(ExactTriangle t) {
    if (t.edgeB.w >= 0) {
        return uvec2(0u, 0x7F800000u);
    }
    float nearest = 1.0 / max(max(t.invW.x, t.invW.y), t.invW.z);
    float farthest = 1.0 / min(min(t.invW.x, t.invW.y), t.invW.z);
    return uvec2(floatBitsToUint(nearest * (1.0 - 1.0 / 4096.0)),
                 floatBitsToUint(farthest * (1.0 + 1.0 / 4096.0)));
}

// Slabs are 2^shift depth-bit values wide, starting at the frame's nearest depth `lo`, so
// that SLABS of them cover up to `hi`.
uint slabShift(uint lo, uint hi) {
    return uint(max(findMSB(hi - lo) + 1 - int(SLAB_BITS), 0));
}

// The slab of depth bits `bits`: depths nearer than `lo` (homogeneous triangles) go to the
// first, farther than the last slab's floor to the last.
uint slabOf(uint bits, uint lo, uint shift) {
    return min((max(bits, lo) - lo) >> shift, SLABS - 1u);
}

// The least depth bits a triangle of slab `slab` may have.
uint slabFloor(uint slab, uint lo, uint shift) {
    return slab == 0u ? 0u : lo + (slab << shift);
}

// Whether edge (a, b, c) with tie bias excludes every pixel centre of [x0, x1) x [y0, y1):
// a linear function is largest at a corner, so testing the best corner decides. (Edges are
// passed one by one: indexing an i64vec4 with a loop variable miscompiled on lavapipe 22.3.)
bool edgeExcludesRect(int a, int b, int64_t c, int bias, int x0, int y0, int x1, int y1) {
    int64_t px = (int64_t(a > 0 ? x1 - 1 : x0) << 8) + 128;
    int64_t py = (int64_t(b > 0 ? y1 - 1 : y0) << 8) + 128;
    return int64_t(a) * px + int64_t(b) * py + c + int64_t(bias) <= 0;
}

// Narrows the open interval (lo, hi) of fixed-point x at which edge (a, b, c) with tie bias
// covers row py: a*px + b*py + c + bias > 0.
void narrowRow(int a, int b, int64_t c, int bias, double py, inout double lo, inout double hi) {
    double k = double(b) * py + double(c + int64_t(bias));
    if (a > 0) {
        lo = max(lo, -k / double(a));
    } else if (a < 0) {
        hi = min(hi, -k / double(a));
    } else if (k <= 0.0) {
        hi = lo;
    }
}

// The block columns of pixel row y, within `cols`, that may hold a pixel centre of triangle t:
// on one row each edge bounds the centres from one side. Rounding is covered by a pixel of
// margin (rowRun then tests the end blocks), and homogeneous triangles keep `cols`.
// Thin diagonal triangles (hair) would otherwise visit every block of their bounding box.
ivec2 rowColumns(ExactTriangle t, int y, ivec2 cols) {
    if (t.edgeB.w >= 0) {
        return cols;
    }
    double py = double((y << 8) + 128);
    double lo = -1.0e30;
    double hi = 1.0e30;
    int ties = t.edgeA.w;
    narrowRow(t.edgeA.x, t.edgeB.x, t.edgeC.x, ties & 1, py, lo, hi);
    narrowRow(t.edgeA.y, t.edgeB.y, t.edgeC.y, (ties >> 1) & 1, py, lo, hi);
    narrowRow(t.edgeA.z, t.edgeB.z, t.edgeC.z, (ties >> 2) & 1, py, lo, hi);
    if (!(lo < hi)) {
        return ivec2(1, 0);
    }
    // Pixel x of centre px is (px - 128) / 256; clamp before converting to int.
    double first = clamp(floor((lo - 128.0) / 256.0) - 1.0, -1.0, 1.0e9);
    double last = clamp(ceil((hi - 128.0) / 256.0) + 1.0, -1.0, 1.0e9);
    return ivec2(max(cols.x, int(first) >> BIN_SHIFT), min(cols.y, int(last) >> BIN_SHIFT));
}

// Whether a triangle may cover a pixel centre of the pixel rectangle [x0, x1) x [y0, y1):
// false only when one fixed-point edge excludes every centre (its best corner is outside).
// Homogeneous triangles are not refined.
bool mayCoverRect(ExactTriangle t, int x0, int y0, int x1, int y1) {
    if (t.edgeB.w >= 0) {
        return true;
    }
    int ties = t.edgeA.w;
    return !edgeExcludesRect(t.edgeA.x, t.edgeB.x, t.edgeC.x, ties & 1, x0, y0, x1, y1) &&
           !edgeExcludesRect(t.edgeA.y, t.edgeB.y, t.edgeC.y, (ties >> 1) & 1, x0, y0, x1, y1) &&
           !edgeExcludesRect(t.edgeA.z, t.edgeB.z, t.edgeC.z, (ties >> 2) & 1, x0, y0, x1, y1);
}

// The run of block columns of pixel row y that binning enters triangle t in: rowColumns'
// range, less an end block that mayCoverRect rules out. On one row the blocks holding a
// covered pixel centre are consecutive, and rowColumns' margin of a pixel leaves at most one
// block at either end without one, so the blocks inside the run need no test of their own
// (testing every block cost particles' binning 8 ms, hairball's 4). Counting and filling
// both take their runs from here, so the counts and the lists agree.
ivec2 rowRun(ExactTriangle t, int y, ivec2 cols) {
    ivec2 run = rowColumns(t, y, cols);
    int first = run.x << BIN_SHIFT;
    int last = run.y << BIN_SHIFT;
    run.x += mayCoverRect(t, first, y, first + BIN_SIZE, y + 1) ? 0 : 1;
    run.y -= mayCoverRect(t, last, y, last + BIN_SIZE, y + 1) ? 0 : 1;
    return run;
}

#endif
