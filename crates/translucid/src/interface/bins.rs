//! The bins and the rasters that read them: their buffers' records, counters and constants
//! (`interface_bins.glsl`).

use super::{Binding, Include, SetDecl, StructDecl};

shader_constants! {
    /// Textures the bin rasters' hardware sampling binds: the assets' first ones. A frame
    /// whose transparent draws use a later one samples in software. (Each slot is its own
    /// branch of the sampler: texture_sampler.glsl.)
    pub const TEXTURE_ARRAY_SLOTS: u32 = 16;
    /// Blocks are BIN_SIZE x BIN_SIZE pixels, in tiles of BIN_SIZE x TILE_ROWS, one subgroup's
    /// pixels (bin_lists.glsl). Each tile is a bin of its own with its own triangle list
    /// (bin = block * TILES_PER_BLOCK + tile), so a tile walks only the triangles that touch
    /// it.
    pub const BIN_SHIFT: u32 as int = 3;
    pub const BIN_SIZE: u32 as int = 1 << BIN_SHIFT;
    /// A bin's list may be ordered by depth slab (bin_lists.glsl), into at most MAX_SLABS; the
    /// counters keep a farthest depth for each.
    pub const MAX_SLABS: u32 as int = 1024;
    /// Slots of BinCounters.statistics, each a cache line (16 words).
    pub const STATISTICS_SLOTS: u32 = 8;
    pub const STATISTICS_WORDS: u32 = STATISTICS_SLOTS * 16;

    /// Overflow bits in BinCounters.overflow: a buffer was too small for the frame (the host
    /// grows it for later frames). The bin lists' overflow is answered within the frame, by
    /// bands; a band whose lists did not fit after all (OVERFLOW_BAND_LISTS) lost entries.
    pub const OVERFLOW_HOMOGENEOUS: u32 = 1;
    pub const OVERFLOW_BIN_ENTRIES: u32 = 2;
    /// A bin so crowded that one pass over it cannot fit the shader loop budget (wavelet's bin
    /// raster reports it; the exact raster resumes such rows instead).
    pub const OVERFLOW_CROWDED_BIN: u32 = 4;
    pub const OVERFLOW_RESUME: u32 = 8;
    pub const OVERFLOW_BAND_LISTS: u32 = 16;


    /// Indirect commands in g_dispatch, 16 bytes each (bins_bindings.glsl says what each
    /// counts): resume lists 0 and 1, then these.
    pub const DISPATCH_RASTER_BINS: u32 = 2;
    pub const DISPATCH_BINNING: u32 = 3;
    pub const DISPATCH_BIN_OFFSETS: u32 = 4;
    pub const DISPATCH_BAND_FILL: u32 = 5;
    /// The composite's VkDrawIndirectCommand.
    pub const DRAW_COMPOSITE: u32 = 6;
    /// Words of g_dispatch: every command above, 16 bytes each.
    pub const DISPATCH_WORDS: u32 = (DRAW_COMPOSITE + 1) * 4;
    /// Invocations per workgroup of the binning passes.
    pub const BINNING_GROUP_SIZE: u32 = 64;
    /// Workgroup size of the scan, and the multiple the blocks of the bin arrays are padded
    /// to.
    pub const SCAN_GROUP_SIZE: u32 = 256;
    /// Counters of BinCounters.groupsDone (last_group.glsl), zeroed with the counters each
    /// frame.
    pub const GROUPS_DONE_PYRAMID: u32 as int = 0;
    pub const GROUPS_DONE_SCAN: u32 as int = 1;
    pub const GROUPS_DONE_SLABS: u32 as int = 2;
    pub const GROUPS_DONE_COUNTERS: u32 as int = 3;
    /// Levels the opaque depth pyramid's lookup climbs at most: enough for the largest frame
    /// (65535 pixels a side).
    pub const PYRAMID_MAX_LEVELS: u32 as int = 14;

    /// The last stamp a submission takes before they start again from 1 (texels of the
    /// transparent layer keep 6 bits of it; the layer is cleared when they start again).
    pub const LAST_STAMP: u32 = 63;

    /// BinTriangleRecord.flags: the edges are those of the vertices in order, negated: the
    /// triangle winds the other way in fixed-point framebuffer coordinates, and edges are
    /// positive inside.
    pub const TRIANGLE_NEGATED: u32 = 1;
    /// The triangle's attributes hold its face normal, not vertex normals: its draw is lit and
    /// its mesh has no normals.
    pub const TRIANGLE_FACE_NORMAL: u32 = 2;
    /// The triangle's mesh has uvs; a textured fragment without them samples (0, 0).
    pub const TRIANGLE_HAS_UVS: u32 = 4;
    /// The triangle takes the homogeneous path (BinHomogeneous).
    pub const TRIANGLE_HOMOGENEOUS: u32 = 8;
    /// The material sits above this bit of the flags, in the same texel as the coverage
    /// data, so that shading reads no attribute texel it does not use.
    pub const TRIANGLE_MATERIAL_SHIFT: u32 as int = 8;

    /// What shading needs of a transparent quad besides its triangles' records, gathered by
    /// setup so that a fragment reads a few texels instead of following draw, quad and vertex
    /// indices. One record per quad, at its index in the frame (a triangle's order key >> 1),
    /// shared by its two triangles: triangle 0 has corners 0, 1, 2 and triangle 1 corners 0,
    /// 2, 3, as in the reference. A record holds only the sections the scene's constants let
    /// shading read (quad_attributes.glsl), each whole texels of 16 bytes, in this order:
    /// - colours (VERTEX_COLOURS): each corner's vertex colour times the draw's tint, a texel
    ///   each; one texel for the quad with FLAT_COLOURS.
    /// - normals (VERTEX_NORMALS): the corners' world-space normals (normal matrix applied),
    ///   x, y, z of corner 0, then of corner 1, and so on, packed in three texels. Quads of a
    ///   draw without normals (TRIANGLE_FACE_NORMAL) hold each triangle's face normal instead,
    ///   in the xyz of a texel of its own; with FACE_NORMALS alone the section is those two
    ///   texels.
    /// - uvs (TEXTURES): corners 0 and 1 in one texel, 2 and 3 in the next.
    pub const COLOUR_TEXELS: u32 as int = 4;
    pub const FLAT_COLOUR_TEXELS: u32 as int = 1;
    pub const NORMAL_TEXELS: u32 as int = 3;
    pub const FACE_NORMAL_TEXELS: u32 as int = 2;
    pub const UV_TEXELS: u32 as int = 2;

    /// BinTexture.samplerBits: each axis's wrap mode, the filters, the mipmap mode.
    pub const SAMPLER_WRAP_S_SHIFT: u32 as int = 0;
    pub const SAMPLER_WRAP_T_SHIFT: u32 as int = 2;
    pub const SAMPLER_WRAP_MASK: u32 = 3;
    pub const SAMPLER_WRAP_REPEAT: u32 = 0;
    pub const SAMPLER_WRAP_CLAMP_TO_EDGE: u32 = 1;
    pub const SAMPLER_WRAP_MIRRORED_REPEAT: u32 = 2;
    pub const SAMPLER_MAG_LINEAR: u32 = 16;
    pub const SAMPLER_MIN_LINEAR: u32 = 32;
    pub const SAMPLER_MIP_SHIFT: u32 as int = 6;
    pub const SAMPLER_MIP_MASK: u32 = 3;
    pub const SAMPLER_MIP_NONE: u32 = 0;
    pub const SAMPLER_MIP_NEAREST: u32 = 1;
    pub const SAMPLER_MIP_LINEAR: u32 = 2;
}

shader_struct! {
    /// One transparent draw as the bins see it (std430, 80 bytes).
    pub struct BinDraw as BinDraw {
        /// View-projection x model, computed on the host like the reference.
        pub mvp: mat4,
        /// Into the scene's DrawInfo array.
        pub draw_index: uint,
        /// Global index of the draw's first quad, in submission order.
        pub first_item: uint,
        pub quad_count: uint,
        /// Into the scene's quad buffer.
        pub first_quad: uint,
    }
}

shader_struct! {
    /// A visible triangle after setup, as stored (std430, 64 bytes: four texels; BinTriangle
    /// in bins_bindings.glsl is what the stages unpack it to). The walks read a record for
    /// every triangle they visit, one texel fetch each, so it keeps the snapped vertices
    /// instead of the edges (loaders rebuild the edges exactly, as setup computes them). Its
    /// order key is its index, and a homogeneous-path triangle, which has no fixed-point
    /// vertices, keeps its index into the homogeneous array in their place. Shading skips the
    /// depths texel (loadShadingTriangle in bin_fragment.glsl). Fixed-point vertices fit 32
    /// bits (guard band 2^20 pixels, 8 sub-pixel bits), pixel bounds 16 bits (viewports are
    /// at most 65535).
    pub struct BinTriangleRecord as BinTriangleRecord {
        /// Fixed-point x, y of vertices 0 and 1; on the homogeneous path
        /// (TRIANGLE_HOMOGENEOUS) x: the homogeneous index, the rest 0.
        pub vertices01: ivec4,
        pub vertex2: ivec2,
        /// TRIANGLE_* bits, material index << TRIANGLE_MATERIAL_SHIFT.
        pub flags: uint,
        /// x0 | y0 << 16.
        pub bounds_min: uint,
        /// Depth-buffer value of each vertex.
        pub z_ndc: vec3,
        /// x1 | y1 << 16 (0 for a hole, which binning skips).
        pub bounds_end: uint,
        /// 1 / clip w of each vertex.
        pub inv_w: vec3,
        /// 1 / |double area|, with invW: what shading's sample needs.
        pub inv_area: float,
    }
}

shader_struct! {
    /// Extra data of a triangle on the homogeneous path (std430, 128 bytes), from its vertices
    /// scaled by `2^-e` (crate::raster).
    pub struct BinHomogeneous as BinHomogeneous {
        /// xyz: a, b, c of edge 0 (positive inside); w: the exponent e.
        pub line0: vec4,
        pub line1: vec4,
        pub line2: vec4,
        /// xyz: scaled clip z of each vertex, w: 1 / |det|.
        pub z_inv_det: vec4,
        /// Fixed-point replacement edges where both ends allow it.
        pub fixed_c: i64vec4,
        /// xyz: a, w: bit k set when edge k uses the fixed replacement.
        pub fixed_a: ivec4,
        /// xyz: b, w: tie bits of the replacement edges.
        pub fixed_b: ivec4,
    }
}

shader_struct! {
    /// Counters the host reads back after every frame and checks.
    #[derive(PartialEq, Eq)]
    pub struct BinCounters as BinCounters {
        /// Triangles setup kept (a statistic: records sit at their order keys, and binning
        /// runs over every record).
        pub triangle_count: uint,
        pub homogeneous_count: uint,
        /// Entries the bins need (counted even when they do not fit).
        pub bin_entry_count: uint,
        /// OVERFLOW_* bits.
        pub overflow: uint,
        pub triangle_capacity: uint,
        pub homogeneous_capacity: uint,
        pub bin_entry_capacity: uint,
        /// Pixel-state slots of each resume list (rows it saves).
        pub resume_capacity: uint,
        /// State slots a resume list needed (counted even past the capacity).
        pub resume_needed: uint,
        /// Bits of the nearest and farthest vertex order depth of the fixed-point triangles
        /// (positive floats order like their bits).
        pub depth_lo: uint,
        pub depth_hi: uint,
        /// Bands (bin_scan.glsl): the listed blocks are rasterized in runs whose lists fit the
        /// capacity together, one band after another within the frame. Blocks with a
        /// non-empty bin: g_rasterBins[0, listedBlocks), in order.
        pub listed_blocks: uint,
        /// The current band: listed blocks [bandFirst, bandFirst + bandCount).
        pub band_first: uint,
        pub band_count: uint,
        /// The list offset of its first block (its lists start at 0).
        pub band_base: uint,
        /// Block indices of its first and last block.
        pub band_first_block: uint,
        pub band_last_block: uint,
        /// The listed block the next band starts at.
        pub band_next: uint,
        /// Bands rasterized.
        pub bands: uint,
        /// Blocks whose lists alone pass the capacity: left untouched.
        pub skipped_blocks: uint,
        /// Rows a band left unfinished: left untouched.
        pub abandoned_rows: uint,
        /// Rows of shallow frames whose list no budget could walk in one pass
        /// (OVERFLOW_CROWDED_BIN): continuations walk it in parts.
        pub crowded_rows: uint,
        /// Rows suspended with no state slot left (OVERFLOW_RESUME): they start over when
        /// resumed.
        pub restarted_rows: uint,
        /// Items each resume list holds: every row of the frame.
        pub resume_item_capacity: uint,
        /// Blocks under the bounds of the triangles setup's occlusion cull dropped (behind the
        /// opaque layer): what the cull saved binning.
        pub occluded_blocks: uint,
        /// Workgroups of a one-dispatch step that have finished, at GROUPS_DONE_*
        /// (last_group.glsl).
        pub groups_done: uint[GROUPS_DONE_COUNTERS],
        /// Rows the rasters suspended onto a resume list (each time a row was).
        pub suspended_rows: uint,
        pub pad: uint[3],
        /// Statistics of the raster: slot k holds the fragments composited at [16 k], the most
        /// sweeps of its list any pixel needed at [16 k + 1], and the fragments in front of the
        /// opaque layer found in the first sweep (all of them, fewer where a pixel had to drop
        /// some) at [16 k + 2]. A row adds to the slot of its workgroup, a cache line from the
        /// others, so that the CPU threads of drivers such as lavapipe do not fight over one
        /// line (two such atomics a row were 7 % of the spheres raster, and a sixth of a row's
        /// fixed cost).
        pub statistics: uint[STATISTICS_WORDS],
        /// Per depth slab: bits of its triangles' farthest vertex.
        pub slab_farthest: uint[MAX_SLABS],
        /// And their largest order key.
        pub slab_last_order: uint[MAX_SLABS],
        /// Where deep frames' slabs start (bin_lists.glsl): per slab, the least (depth bits,
        /// order key) of a triangle it may hold, written by the slab plan (slab_plan.glsl).
        pub slab_floor_bits: uint[MAX_SLABS],
        pub slab_floor_order: uint[MAX_SLABS],
        /// What the plan reads, gathered by slab_histogram.comp: MAX_SLABS buckets evenly over
        /// depthLo..depthHi, each with the bins its triangles enter (a 64-bit sum in two words)
        /// and the range of their nearest depth bits and of their order keys. Minima are kept
        /// complemented, so that a zeroed bucket is empty and atomicMax takes the least.
        pub bucket_weight_lo: uint[MAX_SLABS],
        pub bucket_weight_hi: uint[MAX_SLABS],
        /// Complemented.
        pub bucket_nearest_least: uint[MAX_SLABS],
        pub bucket_nearest_most: uint[MAX_SLABS],
        /// Complemented.
        pub bucket_order_least: uint[MAX_SLABS],
        pub bucket_order_most: uint[MAX_SLABS],
    }
}

shader_struct! {
    /// A texture for the software sampler (std430, 32 bytes).
    pub struct BinTexture as BinTexture {
        /// Index of level 0's first texel in the texel buffer.
        pub first_texel: uint,
        pub width: uint,
        pub height: uint,
        pub levels: uint,
        pub srgb: uint,
        /// SAMPLER_* bits.
        pub sampler_bits: uint,
        pub pad: uint[2],
    }
}

shader_struct! {
    /// The push constants of every bin stage and of the rasters that read the bins
    /// (`u_push`).
    pub struct BinPush as BinPush {
        /// Transparent quads in all draws.
        pub item_count: uint,
        /// Transparent draws.
        pub draw_count: uint,
        pub width: uint,
        pub height: uint,
        /// Blocks across (BIN_SIZE pixels each).
        pub bins_x: uint,
        /// Blocks down.
        pub bins_y: uint,
        /// Stop once every channel's transmittance is below this; 0: exact.
        pub threshold: float,
        /// Raster: the list a continuation reads; it appends to the other.
        pub resume_list: uint,
        /// Binning: bin rows one invocation covers (bin_lists.glsl).
        pub bin_rows_per_slice: uint,
        /// Setup and binning: workgroups in x, the rest in z (splitGroups).
        pub groups_x: uint,
        /// In place: the submission's stamp (transparent_layer.glsl); else 0.
        pub stamp: uint,
        /// 1: u_opaqueDepth holds reversed-Z depth, 1 at the eye.
        pub opaque_depth_reversed: uint,
        /// The frame's top-left corner in u_opaqueDepth (an engine's image holding the
        /// frame in a part of it); else 0.
        pub opaque_depth_x: uint,
        pub opaque_depth_y: uint,
    }
}

impl Default for BinCounters {
    fn default() -> Self {
        bytemuck::Zeroable::zeroed()
    }
}

pub fn include() -> Include {
    const STRUCTS: &[&StructDecl] = &[
        &BinDraw::GLSL,
        &BinTriangleRecord::GLSL,
        &BinHomogeneous::GLSL,
        &BinCounters::GLSL,
        &BinTexture::GLSL,
        &BinPush::GLSL,
    ];
    Include {
        file: "interface_bins.glsl",
        source: "bins.rs",
        constants: CONSTANTS,
        structs: STRUCTS,
        sets: vec![],
        more: None,
        needs: &[],
    }
}

/// Set 1 of the bin stages and of the rasters that read them (set 0 is the scene's)
/// (`interface_bins_set.glsl`). What the hot loops read comes through texel buffers on CPU
/// drivers: lavapipe fetches texels with straight-line vector loads, where a storage buffer
/// load inside divergent control flow is a per-lane loop with a branch per component. On
/// GPUs the walks read the entry and record a whole tile visits from the storage buffers
/// (STORAGE_WALK).
/// Records are read texel by texel in field order (`methods::bins::layout`'s tests check the
/// loaders' offsets).
pub const BINS_SET: SetDecl = SetDecl::new(
    "1",
    &[
        // The scene as the stages read it.
        Binding::texels("u_vertexTexels", "usamplerBuffer").doc(&[
            "The scene's vertices (GpuVertex, 3 texels each: position and normal.x, normal.yz",
            "and uv, colour).",
        ]),
        Binding::texels("u_quadTexels", "usamplerBuffer"),
        Binding::texels("u_drawTexels", "usamplerBuffer").doc(&["DrawInfo, 10 texels each."]),
        Binding::texels("u_binDrawTexels", "usamplerBuffer").doc(&["BinDraw, 5 texels each."]),
        Binding::texels("u_materialTexels", "usamplerBuffer").doc(&["Material, 3 texels each."]),
        Binding::texels("u_textureInfoTexels", "usamplerBuffer")
            .doc(&["BinTexture, 2 texels each."]),
        Binding::texels("u_texels", "usamplerBuffer").doc(&["Every texture's texels, RGBA8."]),
        Binding::texels("u_srgbToLinear", "samplerBuffer").doc(&["256 entries."]),
        // The opaque layer.
        Binding::sampled("u_opaqueDepth", "sampler2D", 1).doc(&[
            "The opaque depth: the frame target's, or the engine's own depth image where it is",
            "(any depth format, reversed-Z turned around by opaqueDepthAt).",
        ]),
        Binding::buffer("DepthPyramidBlock", "coherent", &["float g_depthPyramid[]"]).doc(&[
            "The opaque depth pyramid (depth_pyramid.glsl). Coherent: the last workgroup of its",
            "build reads what the others wrote.",
        ]),
        Binding::texels("u_depthPyramidTexels", "samplerBuffer").doc(&["g_depthPyramid."]),
        // What setup makes of the triangles.
        Binding::buffer("TriangleBlock", "", &["BinTriangleRecord g_triangles[]"]).doc(&[
            "Triangle records and quad attribute records (interface_bins.glsl), read through",
            "u_triangleTexels and u_attributeTexels (the walks' records from g_triangles",
            "itself under STORAGE_WALK). Setup writes them as storage buffers, as",
            "far as one binding reaches, while they fit (faster on lavapipe than texel stores),",
            "else through u_triangleRecords and u_attributeRecords (RECORDS_AS_TEXELS).",
        ]),
        Binding::buffer("AttributeBlock", "", &["uvec4 g_attributes[]"]),
        Binding::storage_texels(
            "u_triangleRecords",
            ["rgba32ui", "writeonly", "uimageBuffer"],
        ),
        Binding::storage_texels(
            "u_attributeRecords",
            ["rgba32ui", "writeonly", "uimageBuffer"],
        ),
        Binding::texels("u_triangleTexels", "usamplerBuffer").doc(&["4 texels each."]),
        Binding::texels("u_attributeTexels", "usamplerBuffer"),
        Binding::buffer("HomogeneousBlock", "", &["BinHomogeneous g_homogeneous[]"]),
        Binding::texels("u_homogeneousTexels", "usamplerBuffer")
            .doc(&["g_homogeneous, 8 texels each."]),
        // The counters, the bins and their lists.
        Binding::buffer("CounterBlock", "coherent", &["BinCounters g_counters"]).doc(&[
            "Coherent: the last workgroup of a one-dispatch step (last_group.glsl) reads what",
            "the others' atomics added.",
        ]),
        Binding::buffer("BinEndBlock", "", &["uint g_binEnds[]"]).doc(&[
            "Per (bin, slab), at bin * SLABS + slab: bin_count counts the triangles of that part",
            "of the bin's list here; the scan turns a band's counts into where each part starts,",
            "in place (bin_scan.glsl); bin_fill advances them as it appends, so that after",
            "binning each is where its part ends and the next starts (binStart says where a",
            "bin's list starts).",
        ]),
        Binding::texels("u_binCountTexels", "usamplerBuffer").doc(&["g_binEnds, as counts."]),
        Binding::buffer("BlockTotalBlock", "coherent", &["uint g_blockTotals[]"]).doc(&[
            "Per block: the sum of its bins' counts, then its list offset (bin_scan.glsl).",
            "Coherent: the last workgroup of the sums scans what the others wrote.",
        ]),
        Binding::texels("u_blockTotalTexels", "usamplerBuffer"),
        Binding::buffer("BinEntryBlock", "", &["uint g_binEntries[]"]),
        Binding::texels("u_binEntryTexels", "usamplerBuffer").doc(&["g_binEntries."]),
        Binding::buffer("RasterBinBlock", "coherent", &["uint g_rasterBins[]"]).doc(&[
            "The listed blocks (those with a non-empty bin), in order. Coherent: the scan's",
            "first band plan reads what the scan's other invocations listed.",
        ]),
        Binding::buffer(
            "DispatchBlock",
            "",
            &["uint g_dispatch[DISPATCH_WORDS]", "uint g_resumeItems[]"],
        )
        .doc(&[
            "Indirect dispatches written on the GPU, each a VkDispatchIndirectCommand padded to",
            "16 bytes (x = count): k = 0, 1 dispatch the items of resume list k, the tiles a",
            "raster dispatch left unfinished, one workgroup each, u_push.groupsX to a row in x",
            "and the rest in z (the fourth word counts them); DISPATCH_RASTER_BINS counts the",
            "current band's blocks with a non-empty bin (listed in g_rasterBins from the band's",
            "first) for its raster dispatch (y = BIN_SIZE / rows per workgroup);",
            "DISPATCH_BINNING counts the binning passes' workgroups of BINNING_GROUP_SIZE",
            "triangles, so that they run for the triangles setup kept, not for every quad;",
            "DISPATCH_BIN_OFFSETS counts the scan's offset step's workgroups of SCAN_GROUP_SIZE",
            "listed blocks, so that it writes offsets only where some bin has an entry;",
            "DISPATCH_BAND_FILL is DISPATCH_BINNING while a band has blocks, else empty. The",
            "band plan (bin_scan.glsl) writes DISPATCH_RASTER_BINS, DISPATCH_BIN_OFFSETS and",
            "DISPATCH_BAND_FILL for each band. DRAW_COMPOSITE is a VkDrawIndirectCommand: the",
            "composite's quad (6 vertices) for each listed block, counted by the scan.",
            "Items of resume list k start at k * g_counters.resumeItemCapacity (room for every",
            "tile of the frame): block * TILES_PER_BLOCK + tile. Item i takes state slot i while",
            "there is one (below resumeCapacity; the tiles past them start over); what a slot keeps",
            "is the suspending raster's own binding (exact's: interface_exact.glsl).",
        ]),
        // Where the rasters write.
        Binding::image("u_colour", ["rgba16f", "", "image2D"]).doc(&[
            "The frame target's colour, which the rasters composite onto (standalone frames);",
            "or, on an engine's device, what they leave for the composite pass to blend onto",
            "the engine's colour where it is (transparent_layer.glsl), in two images (1x1 until",
            "the first such frame).",
        ]),
        Binding::image("u_transparentLayer", ["rg32ui", "writeonly", "uimage2D"]),
        Binding::image(
            "u_transparentLayerStamps",
            ["r32ui", "writeonly", "uimage2D"],
        ),
    ],
);

/// Set 2 of the bin rasters that sample in hardware (`HARDWARE_SAMPLING`): the assets' first
/// TEXTURE_ARRAY_SLOTS textures, each with its own sampler, by texture index; the slots past
/// them hold a white texture (`assets::texture_array`).
pub const TEXTURE_ARRAY_SET: SetDecl = SetDecl::new(
    "2",
    &[
        Binding::sampled("u_textureArray", "sampler2D", TEXTURE_ARRAY_SLOTS).doc(&[
            "Indexed by constants only, which every Vulkan device can (a per-lane index needs",
            "an optional feature that lavapipe and some GPUs lack).",
        ]),
    ],
);

pub fn texture_array_include() -> Include {
    Include {
        file: "interface_texture_array.glsl",
        source: "bins.rs",
        constants: &[],
        structs: &[],
        sets: vec![&TEXTURE_ARRAY_SET],
        more: None,
        needs: &[],
    }
}

pub fn set_include() -> Include {
    Include {
        file: "interface_bins_set.glsl",
        source: "bins.rs",
        constants: &[],
        structs: &[],
        sets: vec![&BINS_SET],
        more: None,
        needs: &["interface_scene.glsl", "interface_bins.glsl"],
    }
}

shader_struct! {
    /// The push constants of the composite (bins/composite.vert and .frag).
    pub struct CompositePush as CompositePush {
        /// Blocks across.
        pub bins_x: uint,
        /// The submission whose pixels are blended.
        pub stamp: uint,
        /// The frame's size in pixels.
        pub extent: vec2,
        /// The frame's top-left corner in the colour image.
        pub origin_x: uint,
        pub origin_y: uint,
    }
}

/// The composite's set: the listed blocks and the transparent layer the rasters left
/// (`interface_composite.glsl`).
pub const COMPOSITE_SET: SetDecl = SetDecl::new(
    "0",
    &[
        Binding::buffer("RasterBinBlock", "readonly", &["uint g_rasterBins[]"]).doc(&[
            "The blocks with a non-empty bin, in block order (block_scan.comp): the",
            "composite's instances.",
        ]),
        Binding::image("u_transparentLayer", ["rg32ui", "readonly", "uimage2D"]),
        Binding::image(
            "u_transparentLayerStamps",
            ["r32ui", "readonly", "uimage2D"],
        ),
    ],
);

pub fn composite_include() -> Include {
    const STRUCTS: &[&StructDecl] = &[&CompositePush::GLSL];
    Include {
        file: "interface_composite.glsl",
        source: "bins.rs",
        constants: &[],
        structs: STRUCTS,
        sets: vec![&COMPOSITE_SET],
        more: None,
        needs: &["interface_bins.glsl"],
    }
}
