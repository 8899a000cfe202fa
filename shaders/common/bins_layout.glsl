// Buffers of the bins and of the rasters that read them (host mirror:
// crates/translucid/src/methods/bins/layout.rs).
#ifndef TRANSLUCID_BINS_LAYOUT_GLSL
#define TRANSLUCID_BINS_LAYOUT_GLSL

#extension GL_EXT_shader_explicit_arithmetic_types_int64 : require

// Blocks are BIN_SIZE x BIN_SIZE pixels; one workgroup rasterizes one block, one subgroup-
// sized row of invocations per row of pixels. Each row of a block is a bin of its own with
// its own triangle list (bin = block * BIN_SIZE + row), so a row walks only the triangles
// that touch it.
#define BIN_SHIFT 3
#define BIN_SIZE 8

// A bin's list may be ordered by depth slab (see bin_lists.glsl), into at most MAX_SLABS.
#define MAX_SLABS 1024

// Slots of BinCounters.statistics, and its words: a cache line (16 words) a slot.
#define STATISTICS_SLOTS 8u
#define STATISTICS_WORDS 128u

// Overflow bits in BinCounters.overflow: a buffer was too small for the frame (the host
// grows it for later frames). The bin lists' overflow is answered within the frame, by bands;
// a band whose lists did not fit after all (OVERFLOW_BAND_LISTS) lost entries.
#define OVERFLOW_HOMOGENEOUS 1u
#define OVERFLOW_BIN_ENTRIES 2u
#define OVERFLOW_BAND_LISTS 16u
// A bin so crowded that one pass over it cannot fit the shader loop budget (wavelet's bin
// raster reports it; the exact raster resumes such rows instead).
#define OVERFLOW_CROWDED_BIN 4u
#define OVERFLOW_RESUME 8u

// Lavapipe (gallivm) stops every loop of a shader invocation once their iterations add up to
// 65535, silently. The raster counts its iterations against this budget (with room for the
// few it does not count) and, before it would run out, saves the pixel and leaves the rest to
// a continuation dispatch. Subgroups resume from a list of (block row) items, each with the
// states of its BIN_SIZE pixels where a state slot was left (else the row starts over).
#define LOOP_BUDGET 60000u
// A resume item's state slot when the row saved no state (it starts over), and a saved
// state's sweep.x when the row resumes with a new sweep (saved between sweeps).
#define NO_STATE 0xFFFFFFFFu
#define NEW_SWEEP 0xFFFFFFFFu

// Indirect dispatch commands (see bins_bindings.glsl) and binning's workgroup size.
#define DISPATCH_RASTER_BINS 2u
#define DISPATCH_BINNING 3u
#define DISPATCH_BIN_OFFSETS 4u
#define DISPATCH_BAND_FILL 5u
#define DRAW_COMPOSITE 6u
#define BINNING_GROUP_SIZE 64u
// Workgroup size of the scan, and the multiple the blocks of the bin arrays are padded to.
#define SCAN_GROUP_SIZE 256u

// Most fragments a pixel keeps while it walks its row's list (the raster's SELECT_SIZE).
#define MAX_SELECT_SIZE 16

// One pixel's compositing state between raster dispatches (std430, 192 bytes). A row is
// suspended anywhere in a sweep, even inside one slab's part of its list, so the sweep's
// selection goes with it (unless sweep.x is NEW_SWEEP).
struct ExactPixelState {
    vec4 radiance;          // xyz: radiance so far
    vec4 transmittance;     // xyz: transmittance so far
    uvec4 done;             // x, y: depth bits and order key of the last composited fragment,
                            // z: 1 once the pixel has no fragment left (it waits for its row)
    uvec4 sweep;            // x: the slab the row resumes in, y: the list entry it resumes at,
                            // z, w: the nearest fragment the sweep dropped (low, high word)
    uvec2 selection[MAX_SELECT_SIZE]; // the sweep's kept keys (low, high word)
};

// One transparent draw as the bins see it (std430, 80 bytes).
struct BinDraw {
    mat4 mvp;               // view-projection x model, computed on the host like the reference
    uint drawIndex;         // into the scene's DrawInfo array
    uint firstItem;         // global index of the draw's first quad, in submission order
    uint quadCount;
    uint firstQuad;         // into the scene's quad buffer
};

// A visible triangle after setup, as the stages use it. Fixed-point edges
// E = a*px + b*py + c are positive inside; on the homogeneous path the lines live in
// BinHomogeneous. Stored packed as an BinTriangleRecord.
struct BinTriangle {
    i64vec4 edgeC;          // xyz: c of edges 0..2
    ivec4 edgeA;            // xyz: a of edges 0..2, w: tie bits (bit k: edge k owns ties)
    ivec4 edgeB;            // xyz: b of edges 0..2, w: index into the homogeneous array or -1
    ivec4 bounds;           // half-open pixel rectangle x0, y0, x1, y1
    vec4 zNdc;              // xyz: depth-buffer value of each vertex, w: 1 / |double area|
    vec4 invW;              // xyz: 1 / clip w of each vertex
    uint order;             // order key: global quad index * 2 + sub-triangle, which is
                            // also the index of the record (setup.comp), so that a
                            // fragment's rank names its triangle
    uint materialIndex;
    uint attributeFlags;    // TRIANGLE_FACE_NORMAL, TRIANGLE_HAS_UVS
};

// An BinTriangle as stored (std430, 64 bytes: four texels). The walks read a record for
// every triangle they visit, one texel fetch each, so it keeps the snapped vertices instead
// of the edges (loaders rebuild a, b and c exactly, as setup computes them). Its order key
// is its index, and a homogeneous-path triangle, which has no fixed-point vertices, keeps its
// index into the homogeneous array in their place. Shading skips the depths texel
// (loadShadingTriangle in bin_fragment.glsl). Fixed-point vertices fit 32 bits (guard band
// 2^20 pixels, 8 sub-pixel bits), pixel bounds 16 bits (viewports are at most 65535).
struct BinTriangleRecord {
    ivec4 vertices01;       // fixed-point x, y of vertices 0 and 1; on the homogeneous path
                            // (TRIANGLE_HOMOGENEOUS) x: the homogeneous index, the rest 0
    ivec2 vertex2;
    uint flags;             // TRIANGLE_*, material index << TRIANGLE_MATERIAL_SHIFT
    uint boundsMin;         // x0 | y0 << 16
    vec3 zNdc;              // depth-buffer value of each vertex
    uint boundsEnd;         // x1 | y1 << 16 (0 for a hole, which binning skips)
    vec3 invW;              // 1 / clip w of each vertex
    float invArea;          // 1 / |double area|, with invW: what shading's sample needs
};

// Set when the edges are those of the vertices in order, negated: the triangle winds the
// other way in fixed-point framebuffer coordinates, and edges are positive inside.
#define TRIANGLE_NEGATED 1u
// The material and the attribute flags sit in the same texel as the coverage data, so that
// shading reads no attribute texel it does not use.
#define TRIANGLE_MATERIAL_SHIFT 8

// Set when the triangle's attributes (below) hold its face normal, not vertex normals: its
// draw is lit and its mesh has no normals.
#define TRIANGLE_FACE_NORMAL 2u
// Set when the triangle's mesh has uvs; a textured fragment without them samples (0, 0).
#define TRIANGLE_HAS_UVS 4u
// Set when the triangle takes the homogeneous path (BinHomogeneous).
#define TRIANGLE_HOMOGENEOUS 8u

// What shading needs of a transparent quad besides its triangles' records, gathered by setup
// so that a fragment reads a few texels instead of following draw, quad and vertex indices.
// One record per quad, at its index in the frame (a triangle's order key >> 1), shared by its
// two triangles: triangle 0 has corners 0, 1, 2 and triangle 1 corners 0, 2, 3, as in the
// reference. A record holds only the sections the scene's constants let shading read
// (quad_attributes.glsl), each whole texels of 16 bytes, in this order:
// - colours (VERTEX_COLOURS): each corner's vertex colour times the draw's tint, a texel
//   each; one texel for the quad with FLAT_COLOURS.
// - normals (VERTEX_NORMALS): the corners' world-space normals (normal matrix applied),
//   x, y, z of corner 0, then of corner 1, and so on, packed in three texels. Quads of a draw
//   without normals (TRIANGLE_FACE_NORMAL) hold each triangle's face normal instead, in the
//   xyz of a texel of its own; with FACE_NORMALS alone the section is those two texels.
// - uvs (TEXTURES): corners 0 and 1 in one texel, 2 and 3 in the next.
#define COLOUR_TEXELS 4
#define FLAT_COLOUR_TEXELS 1
#define NORMAL_TEXELS 3
#define FACE_NORMAL_TEXELS 2
#define UV_TEXELS 2

// Extra data of a triangle on the homogeneous path (std430, 192 bytes: 176 padded to 32).
struct BinHomogeneous {
    dvec4 line0;            // a, b, c of edge 0 (positive inside)
    dvec4 line1;
    dvec4 line2;
    dvec4 zInvDet;          // xyz: clip z of each vertex, w: 1 / |det|
    i64vec4 fixedC;         // fixed-point replacement edges where both ends allow it
    ivec4 fixedA;           // xyz: a, w: bit k set when edge k uses the fixed replacement
    ivec4 fixedB;           // xyz: b, w: tie bits of the replacement edges
};

// Counters the host reads back after every frame and checks (std430; its size is checked
// against layout.rs).
struct BinCounters {
    uint triangleCount;     // triangles setup kept (a statistic: records sit at their order
                            // keys, and binning runs over every record)
    uint homogeneousCount;
    uint binEntryCount;     // entries the bins need (counted even when they do not fit)
    uint overflow;          // OVERFLOW_* bits
    uint triangleCapacity;
    uint homogeneousCapacity;
    uint binEntryCapacity;
    uint resumeCapacity;    // pixel-state slots of each resume list (rows it saves)
    uint resumeNeeded;      // state slots a resume list needed (counted even past the capacity)
    uint depthLo;           // bits of the nearest and farthest vertex order depth of the
    uint depthHi;           // fixed-point triangles (positive floats order like their bits)
    // Bands (bin_scan.comp, step 3): the listed blocks are rasterized in runs whose lists fit
    // the capacity together, one band after another within the frame.
    uint listedBlocks;      // blocks with a non-empty bin: g_rasterBins[0, listedBlocks), in order
    uint bandFirst;         // the current band: listed blocks [bandFirst, bandFirst + bandCount)
    uint bandCount;
    uint bandBase;          // the list offset of its first block (its lists start at 0)
    uint bandFirstBlock;    // block indices of its first and last block
    uint bandLastBlock;
    uint bandNext;          // the listed block the next band starts at
    uint bands;             // bands rasterized
    uint skippedBlocks;     // blocks whose lists alone pass the capacity: left untouched
    uint abandonedRows;     // rows a band left unfinished: left untouched
    uint crowdedRows;       // rows of shallow frames whose list no budget could walk in one
                            // pass (OVERFLOW_CROWDED_BIN): continuations walk it in parts
    uint restartedRows;     // rows suspended with no state slot left (OVERFLOW_RESUME): they
                            // start over when resumed
    uint resumeItemCapacity; // items each resume list holds: every row of the frame
    uint occludedBlocks;    // blocks under the bounds of the triangles setup's occlusion cull
                            // dropped (behind the opaque layer): what the cull saved binning
    uint groupsDone[3];     // workgroups of a one-dispatch step that have finished, at
                            // GROUPS_DONE_* (last_group.glsl)
    uint pad[4];
    // Statistics of the raster: slot k holds the fragments composited at [16 k], the most
    // sweeps of its list any pixel needed at [16 k + 1], and the fragments in front of the
    // opaque layer found in the first sweep (all of them, fewer where a pixel had to drop
    // some) at [16 k + 2]. A row adds to the slot of its workgroup, a cache line from the
    // others, so that the CPU threads of drivers such as lavapipe do not fight over one line
    // (two such atomics a row were 7 % of the spheres raster, and a sixth of a row's fixed
    // cost).
    uint statistics[STATISTICS_WORDS];
    uint slabFarthest[MAX_SLABS]; // per depth slab: bits of its triangles' farthest vertex
    uint slabLastOrder[MAX_SLABS]; // and their largest order key
    // Where deep frames' slabs start (bin_lists.glsl): per slab, the least (depth bits, order
    // key) of a triangle it may hold, written by the slab plan (slab_plan.glsl).
    uint slabFloorBits[MAX_SLABS];
    uint slabFloorOrder[MAX_SLABS];
    // What the plan reads, gathered by slab_histogram.comp: MAX_SLABS buckets evenly over
    // depthLo..depthHi, each with the bins its triangles enter (a 64-bit sum in two words) and
    // the range of their nearest depth bits and of their order keys. Minima are kept
    // complemented, so that a zeroed bucket is empty and atomicMax takes the least.
    uint bucketWeightLo[MAX_SLABS];
    uint bucketWeightHi[MAX_SLABS];
    uint bucketNearestLeast[MAX_SLABS];  // ~least
    uint bucketNearestMost[MAX_SLABS];
    uint bucketOrderLeast[MAX_SLABS];    // ~least
    uint bucketOrderMost[MAX_SLABS];
};

// A texture for the software sampler (std430, 32 bytes).
struct BinTexture {
    uint firstTexel;        // index of level 0's first texel in the texel buffer
    uint width;
    uint height;
    uint levels;
    uint srgb;
    uint samplerBits;       // SAMPLER_* bits below
    uint pad0;
    uint pad1;
};

// BinTexture.sampler: each axis's wrap mode, the filters, the mipmap mode
// (methods/bins/layout.rs writes them).
#define SAMPLER_WRAP_S_SHIFT 0
#define SAMPLER_WRAP_T_SHIFT 2
#define SAMPLER_WRAP_MASK 3u
#define SAMPLER_WRAP_REPEAT 0u
#define SAMPLER_WRAP_CLAMP_TO_EDGE 1u
#define SAMPLER_WRAP_MIRRORED_REPEAT 2u
#define SAMPLER_MAG_LINEAR 16u
#define SAMPLER_MIN_LINEAR 32u
#define SAMPLER_MIP_SHIFT 6
#define SAMPLER_MIP_MASK 3u
#define SAMPLER_MIP_NONE 0u
#define SAMPLER_MIP_NEAREST 1u
#define SAMPLER_MIP_LINEAR 2u

#endif
