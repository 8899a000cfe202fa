// The bins a triangle's bounds touch.
#ifndef TRANSLUCID_BIN_LISTS_GLSL
#define TRANSLUCID_BIN_LISTS_GLSL

#include "bin_triangle.glsl"
#include "scene_bindings_compute.glsl"

#extension GL_EXT_shader_explicit_arithmetic_types_int64 : require

// Each bin's list holds SLABS slabs, near to far. A triangle's place in the frame's order is
// the key (depth bits of its nearest vertex, order key) (positive floats order like their
// bits), and its fragments' keys are never less. Slabs split that order at keys the slab plan
// (slab_plan.glsl) chooses each frame so that each slab takes about as many bin entries,
// from a histogram of the triangles' depths (slab_histogram.comp): where depth bunches, slabs
// are finer, and where many triangles share one depth (coincident surfaces, instances drawn
// in one place) they split it by order key. Walking the slabs in order, a pixel that already
// holds its nearest fragments can stop at the first slab whose floor is past them. Shallow
// frames keep one slab, since more cost a longer scan; the host sets SLAB_BITS (a
// specialization constant of the binning and raster stages) for pixels expected or found
// deep, about one slab for every few fragments of a pixel (methods/exact/depth.rs), so that
// a slab's part of a pixel's fragments fits its selection.
#include "interface_specialization.glsl"
const uint SLABS = 1u << SLAB_BITS;

// A bin is a tile of a block: BIN_SIZE pixels across and TILE_ROWS rows down, the pixels one
// subgroup rasterizes (a row at 8 lanes, 8x4 at 32, the whole block at 64), so that every
// lane of a GPU's subgroup has a pixel and the subgroup's votes and broadcasts see the
// whole tile. TILE_SHIFT is the device's (methods/bins/features.rs). Binning works in tile
// rows (a block has TILES_PER_BLOCK of them) and enters a triangle in a tile where it may
// cover a pixel centre on any of the tile's rows.
const uint TILE_ROWS = 1u << TILE_SHIFT;
const uint TILES_PER_BLOCK = uint(BIN_SIZE) >> TILE_SHIFT;
const int BLOCK_TILE_SHIFT = BIN_SHIFT - int(TILE_SHIFT);

// The bins a non-empty pixel rectangle touches: inclusive block columns (x, z) and tile
// rows (y, w).
ivec4 binRect(ivec4 bounds) {
    return ivec4(bounds.x >> BIN_SHIFT, bounds.y >> int(TILE_SHIFT), (bounds.z - 1) >> BIN_SHIFT,
                 (bounds.w - 1) >> int(TILE_SHIFT));
}

// The bin of block column bx in tile row ty.
uint binIndex(int bx, int ty) {
    uint block = uint(ty >> BLOCK_TILE_SHIFT) * u_push.binsX + uint(bx);
    return block * TILES_PER_BLOCK + uint(ty & int(TILES_PER_BLOCK - 1u));
}

// Where the lists of listed block `block` start within the current band's: its offset among
// all the frame's (block_scan.comp) less the band's first.
uint blockStart(uint block) {
    return texelFetch(u_blockTotalTexels, int(block)).r - g_counters.bandBase;
}

// Where the list of bin `bin` (its first slab's part) of tile `tile` of listed block `block`
// starts, once filled: where the bin before it in the block ends (g_binEnds), or, for the
// block's first tile, at the block's start.
uint binStart(uint block, uint tile, uint bin) {
    return tile == 0u ? blockStart(block) : g_binEnds[max(bin, 1u) - 1u];
}

// The tile rows of `r` this binning invocation covers. A triangle's bins are split into
// slices of u_push.binRowsPerSlice tile rows, one invocation each (gl_GlobalInvocationID.y), so
// that no invocation loops more than SLICE_ITERATIONS times (bins/mod.rs) however large the
// triangle and frame; setup sizes the dispatch to the triangle that needs the most
// (binningSlices). Shallow frames slice each triangle from its first row, so that a frame of
// triangles under a slice's height bins each once (slices of the frame's rows cost every
// triangle a second, empty invocation: the dragon's binning 6.7 ms instead of 9.3). Deep
// frames (SLABS > 1) slice the frame's rows: their triangles enter hundreds of bins each, and
// there the threads appending to the lists of different parts of the screen took 3.5 ms off
// particles' fill.
ivec2 sliceRows(ivec4 r) {
    int rows = int(u_push.binRowsPerSlice);
    int first = (SLABS > 1u ? 0 : r.y) + int(gl_GlobalInvocationID.y) * rows;
    return ivec2(max(r.y, first), min(r.w, first + rows - 1));
}

// Invocations that bin one triangle, taking its rows in turn (binningLane). Deep frames'
// triangles are large: with one invocation each, the lanes of a subgroup held different
// triangles, and the row loop ran over the rows of all of them with most lanes idle; a
// subgroup's lanes on one triangle's consecutive rows also append to neighbouring bins
// (particles' fill 36 to 24 ms, its count 17 to 15). Small triangles would leave most of
// the lanes idle instead, so shallow frames keep one. The host sets DEEP_BINNING_LANES to
// BIN_SIZE, or 1 for frames so large that BIN_SIZE lanes a triangle would pass 65535
// workgroups in x (deep_binning_lanes in features.rs).
const uint ROW_LANES = SLABS > 1u ? DEEP_BINNING_LANES : 1u;

// The triangle record a binning invocation bins, and the first of its rows (of every
// ROW_LANES) within its slice.
uint binningTriangle() {
    return linearInvocation() / ROW_LANES;
}

int binningLane() {
    return int(linearInvocation() % ROW_LANES);
}

// The slices a triangle with pixel bounds `bounds` needs (sliceRows).
uint binningSlices(ivec4 bounds) {
    ivec4 r = binRect(bounds);
    uint rows = uint(max(r.w + 1 - (SLABS > 1u ? 0 : r.y), 0));
    return max((rows + u_push.binRowsPerSlice - 1u) / u_push.binRowsPerSlice, 1u);
}

// The tile rows of `rows` in the current band's blocks (g_counters.bandFirstBlock to
// bandLastBlock, in block order), and, on tile row ty, the block columns of `run` in them:
// fill enters only the band's bins, whose lists the band's offsets place.
ivec2 bandRows(ivec2 rows) {
    int top = int(g_counters.bandFirstBlock / u_push.binsX) << BLOCK_TILE_SHIFT;
    int bottom = ((int(g_counters.bandLastBlock / u_push.binsX) + 1) << BLOCK_TILE_SHIFT) - 1;
    return ivec2(max(rows.x, top), min(rows.y, bottom));
}

ivec2 bandColumns(int ty, ivec2 run) {
    uint first = g_counters.bandFirstBlock;
    uint last = g_counters.bandLastBlock;
    uint blockRow = uint(ty >> BLOCK_TILE_SHIFT);
    int lo = blockRow == first / u_push.binsX ? int(first % u_push.binsX) : run.x;
    int hi = blockRow == last / u_push.binsX ? int(last % u_push.binsX) : run.y;
    return ivec2(max(run.x, lo), min(run.y, hi));
}

// Whether fragments are ordered by z_ndc (an orthographic camera) rather than clip w: the
// frame's FrameInfo.depthMapping.w.
bool ordersByZ() {
    return u_frame.depthMapping.w != 0.0;
}

// Bits of a triangle's nearest and farthest vertex order depth (orderDepth in
// bin_fragment.glsl: clip w, or z_ndc + 1 within the depth clip): every fragment's depth lies
// between them, since interpolation clamps it to the vertices' range (raster_rules.glsl),
// computed as here. Homogeneous triangles (a vertex may be behind the eye) span everything.
uvec2 triangleDepthBits(BinTriangle t) {
    if (t.edgeB.w >= 0) {
        return uvec2(0u, 0x7F800000u);
    }
    float nearest = 1.0 / max(max(t.invW.x, t.invW.y), t.invW.z);
    float farthest = 1.0 / min(min(t.invW.x, t.invW.y), t.invW.z);
    if (ordersByZ()) {
        nearest = max(min(min(t.zNdc.x, t.zNdc.y), t.zNdc.z), 0.0) + 1.0;
        farthest = min(max(max(t.zNdc.x, t.zNdc.y), t.zNdc.z), 1.0) + 1.0;
    }
    return uvec2(floatBitsToUint(nearest), floatBitsToUint(farthest));
}

// The histogram's buckets split the depth bits from the frame's nearest, `lo`, to its
// farthest, `hi`, into MAX_SLABS equal parts (to within one): the depth-bit values a bucket
// spans.
uint slabRange(uint lo, uint hi) {
    return hi >= lo ? hi - lo + 1u : 1u;
}

// The histogram bucket of depth bits `bits`: depths nearer than `lo` (homogeneous
// triangles) go to the first, farther than `hi` to the last.
uint bucketOf(uint bits, uint lo, uint range) {
    uint64_t offset = uint64_t(max(bits, lo) - lo);
    return uint(min(offset * uint64_t(MAX_SLABS) / uint64_t(range), uint64_t(MAX_SLABS - 1u)));
}

// The least key a fragment of slab `slab` may have (0 for the first).
uint64_t slabFloorKey(uint slab) {
    return SLABS > 1u ? (uint64_t(g_counters.slabFloorBits[slab]) << 32) |
                            uint64_t(g_counters.slabFloorOrder[slab])
                      : 0ul;
}

// The slab of a triangle whose nearest vertex has depth bits `bits` and whose order key is
// `order`: the last whose floor is not past that key. Floors never decrease from one slab to
// the next, so a slab whose floor equals the next one's is empty.
uint slabOf(uint bits, uint order) {
    uint64_t key = (uint64_t(bits) << 32) | uint64_t(order);
    uint slab = 0u;
    [[unroll]] for (uint step = SLABS >> 1u; step > 0u; step >>= 1u) {
        slab += slabFloorKey(slab + step) <= key ? step : 0u;
    }
    return slab;
}

// Narrows the open interval (lo, hi) of fixed-point x at which edge (a, b, c) with tie bias
// may cover row py: a*px + k > 0, with k = b*py + c + bias, exact in 64 bits. The crossing
// -k/a is estimated in 32-bit floats: two conversions and one division (2.5 ulp in Vulkan)
// put it within 2^-21 of its size, so widened by 2^-19 of its size and one sub-pixel the
// interval holds every covered centre. On screen that is a few sub-pixels; far outside, the
// columns are clamped anyway.
void narrowRow(int a, int b, int64_t c, int bias, int py, inout float lo, inout float hi) {
    int64_t k = int64_t(b) * int64_t(py) + c + int64_t(bias);
    if (a == 0) {
        hi = k > 0 ? hi : lo;
        return;
    }
    float crossing = -float(k) / float(a);
    float slack = abs(crossing) * (1.0 / 524288.0) + 1.0;
    if (a > 0) {
        lo = max(lo, crossing - slack);
    } else {
        hi = min(hi, crossing + slack);
    }
}

// The pixel columns of pixel row y that may hold a centre triangle t covers: on one row
// each edge bounds the centres from one side (narrowRow, which covers rounding), so they
// are consecutive. Empty where first > last.
vec2 rowSpan(BinTriangle t, int y) {
    int py = (y << 8) + 128;
    float lo = -1.0e30;
    float hi = 1.0e30;
    int ties = t.edgeA.w;
    narrowRow(t.edgeA.x, t.edgeB.x, t.edgeC.x, ties & 1, py, lo, hi);
    narrowRow(t.edgeA.y, t.edgeB.y, t.edgeC.y, (ties >> 1) & 1, py, lo, hi);
    narrowRow(t.edgeA.z, t.edgeB.z, t.edgeC.z, (ties >> 2) & 1, py, lo, hi);
    // Pixel x has its centre at 256 x + 128: the first and the last pixel whose centre is in
    // (lo, hi). Scaling by 1/256 is exact.
    return vec2(floor((lo - 128.0) * (1.0 / 256.0)) + 1.0, ceil((hi - 128.0) * (1.0 / 256.0)) - 1.0);
}

// The block columns of tile row ty, within `cols`, that binning enters triangle t in: those
// that may hold one of its pixel centres on one of the tile's rows. The blocks from the
// first such column to the last, on any of the rows, none tested on its own. Counting and
// filling both take the tile row's blocks from here, so the counts and the lists agree.
// Homogeneous triangles keep `cols`. Measured on lavapipe (rows of one pixel): testing
// every block against the edges as well cost particles' binning 8 ms and hairball's 4; a
// whole pixel of margin each side instead of narrowRow's slack put 65 % more entries in the
// dragon's lists, and its raster took a third longer. Thin diagonal triangles (hair) would
// visit every block of their bounding box without the rows' bounds.
ivec2 tileColumns(BinTriangle t, int ty, ivec2 cols) {
    if (t.edgeB.w >= 0) {
        return cols;
    }
    vec2 span = vec2(1.0e30, -1.0e30);
    int y = ty << int(TILE_SHIFT);
    do {
        vec2 row = rowSpan(t, y);
        span = row.x <= row.y ? vec2(min(span.x, row.x), max(span.y, row.y)) : span;
    } while (++y < (ty + 1) << int(TILE_SHIFT));
    if (!(span.x <= span.y)) {
        return ivec2(1, 0);
    }
    // Clamped before converting to int.
    float first = clamp(span.x, -1.0, 1.0e9);
    float last = clamp(span.y, -1.0, 1.0e9);
    return ivec2(max(cols.x, int(first) >> BIN_SHIFT), min(cols.y, int(last) >> BIN_SHIFT));
}

#endif
