//! What a scene needs of the bin stages and of the rasters that read them, decided on the host
//! so that code it cannot reach is compiled away: specialization constants
//! (`crate::interface::specialization`) of the bin stages and the constants every raster over
//! the bins shares (each raster adds its own: `methods::exact::raster`, the wavelet bin
//! raster).

#![deny(unsafe_code)]

use super::layout::BIN_SIZE;
use crate::interface::specialization::{
    Specialization, BIN_TALLY_BITS, BRANCHING, DEEP_BINNING_LANES, FACE_NORMALS, FLAT_COLOURS,
    HOMOGENEOUS_PATH, LOOP_BUDGET, RASTER_GROUP_SIZE, RECORDS_AS_TEXELS, SKIP_OCCLUSION_CULL,
    SLAB_BITS, STORAGE_WALK, TEXTURES, TILE_SHIFT, TRANSMISSION, VERTEX_COLOURS, VERTEX_NORMALS,
};
use crate::raster::{clip_position, model_view_projection, viewport_transform, GUARD_BAND};
use crate::scene::Scene;
use glam::{Mat4, Vec3, Vec4};

/// What the stages are specialized for.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct RasterFeatures {
    /// Some triangle may need the homogeneous path (near plane, behind the eye, guard band).
    pub homogeneous: bool,
    pub textures: bool,
    /// Some lit draw has vertex normals, and some lit draw has none. Normals are only for
    /// lighting, so with neither the shader drops lighting altogether.
    pub vertex_normals: bool,
    pub face_normals: bool,
    /// Each bin's list holds 2^slab_bits depth slabs.
    pub slab_bits: u32,
    /// A bin is a tile of 2^tile_shift pixel rows of a block, one subgroup's pixels
    /// ([`tile_shift`]).
    pub tile_shift: u32,
    /// Rows of a block per workgroup of the first raster dispatch: a subgroup must see one
    /// tile, so the whole block where subgroups are exactly a row wide (eight of them a
    /// workgroup), else a tile (a workgroup a subgroup).
    pub rows: u32,
    /// Some draw's material transmits light (transmission above 0).
    pub transmission: bool,
    /// Some draw's mesh has vertex colours (the others' are white).
    pub vertex_colours: bool,
    /// Every quad's corners have one colour (particles, billboards), so that shading reads
    /// one colour per triangle instead of three.
    pub flat_colours: bool,
    /// Binning invocations per triangle once bins hold slabs (bin_lists.glsl): a row's width
    /// of them, unless the dispatch would pass the workgroups every device allows.
    pub deep_binning_lanes: u32,
    /// Loop iterations a raster's row may take in one dispatch (the device's, or less in
    /// tests).
    pub loop_budget: u32,
    /// The rasters branch where the subgroup agrees (the GPU profile).
    pub branching: bool,
    /// Setup writes the triangle records through texel views: they pass what one storage
    /// binding holds (`Resources::records_pass_a_binding`).
    pub records_as_texels: bool,
    /// The rasters' walks read list entries and triangle records as storage buffers, not
    /// texels ([`storage_walk`]).
    pub storage_walk: bool,
    /// Binning workgroups tally their entries in a shared table of 2^bin_tally_bits slots
    /// (0: off; [`bin_tally_bits`]).
    pub bin_tally_bits: u32,
    /// The rasters sample textures in hardware (their `HARDWARE_SAMPLING` variant), from
    /// the assets' texture array ([`hardware_sampling`]).
    pub hardware_sampling: bool,
}

/// What an engine declares its frames may draw ([`crate::context::Context::prepare`]), so
/// that the bins' shaders are built once for all of it: a frame then takes these features
/// whether or not it draws them ([`RasterFeatures::covering`]; textures apart, whose two
/// variants are both built), and content streamed in within the declaration needs no other
/// variant. Each variant covers the frames without its feature too, pixel for pixel (every
/// shader decides per draw or per triangle), only slower.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub struct DeclaredContent {
    /// Textured materials.
    pub textures: bool,
    /// Vertex colours or draw tints, one colour per quad (particles, billboards).
    pub vertex_colours: bool,
    /// Vertex colours that vary across a quad (implies `vertex_colours`).
    pub corner_colours: bool,
    /// Lit materials, on meshes with normals or without.
    pub lit: bool,
    /// Materials that transmit light.
    pub transmission: bool,
    /// Triangles crossing the near plane or the guard band (the homogeneous path).
    pub near_plane: bool,
    /// Deep pixels: exact's variants for them (more fragments per pass, depth slabs) are
    /// built up front too, and its frames move between those alone (at most
    /// `exact::depth::DEEP_SLAB_BITS` of slabs).
    pub deep: bool,
}

impl DeclaredContent {
    /// Everything a frame can draw.
    pub const ALL: Self = Self {
        textures: true,
        vertex_colours: true,
        corner_colours: true,
        lit: true,
        transmission: true,
        near_plane: true,
        deep: true,
    };

    /// What a frame with `features` (its own, before [`RasterFeatures::covering`]) draws.
    /// Deep pixels are not a shader variant of the bins: never set.
    pub fn of_features(features: &RasterFeatures) -> Self {
        Self {
            textures: features.textures,
            vertex_colours: features.vertex_colours,
            corner_colours: features.vertex_colours && !features.flat_colours,
            lit: features.vertex_normals || features.face_normals,
            transmission: features.transmission,
            near_plane: features.homogeneous,
            deep: false,
        }
    }

    /// What a frame of `scene` at `width` x `height` draws (deep pixels aside).
    pub fn drawn_by(scene: &Scene, width: u32, height: u32) -> Self {
        let meshes = MeshFacts::of_scene(scene);
        let near_plane = homogeneous_triangles(scene, &meshes, width, height);
        // The subgroups shape the raster, not the content.
        let subgroups = Subgroups {
            size: BIN_SIZE,
            full: false,
        };
        Self::of_features(&RasterFeatures::of_frame(
            scene, &meshes, near_plane, subgroups,
        ))
    }

    /// Whether a frame drawing `content` is within this declaration: the shaders built for
    /// it draw that frame.
    pub fn covers(&self, content: &Self) -> bool {
        let within = |drawn: bool, declared: bool| !drawn || declared;
        within(content.textures, self.textures)
            && within(
                content.vertex_colours,
                self.vertex_colours || self.corner_colours,
            )
            && within(content.corner_colours, self.corner_colours)
            && within(content.lit, self.lit)
            && within(content.transmission, self.transmission)
            && within(content.near_plane, self.near_plane)
            && within(content.deep, self.deep)
    }

    /// What either declares.
    pub fn union(self, other: Self) -> Self {
        Self {
            textures: self.textures || other.textures,
            vertex_colours: self.vertex_colours || other.vertex_colours,
            corner_colours: self.corner_colours || other.corner_colours,
            lit: self.lit || other.lit,
            transmission: self.transmission || other.transmission,
            near_plane: self.near_plane || other.near_plane,
            deep: self.deep || other.deep,
        }
    }
}

impl RasterFeatures {
    /// These features widened to cover `declared`: the shaders built for the result draw
    /// this frame and any frame within the declaration. Textures are the exception: the
    /// texturing code slows a frame that samples nothing (particles at 640x360, exact: 108
    /// ms a frame without it, 309 with it, on lavapipe), so a frame keeps its own, and a
    /// declared loop builds both variants up front (`Bins::prebuild_texture_variant`).
    pub fn covering(self, declared: &DeclaredContent) -> Self {
        let colours = declared.vertex_colours || declared.corner_colours;
        Self {
            homogeneous: self.homogeneous || declared.near_plane,
            vertex_normals: self.vertex_normals || declared.lit,
            face_normals: self.face_normals || declared.lit,
            transmission: self.transmission || declared.transmission,
            vertex_colours: self.vertex_colours || colours,
            flat_colours: self.flat_colours && !declared.corner_colours,
            ..self
        }
    }

    /// The superset variant of these features: covering every content a frame can draw,
    /// textures apart (a prepared loop builds both, as for a declaration of textures). A
    /// prepared loop builds it up front, and its frames whose content is past the
    /// declaration draw with it (right, only slower) instead of building their own variant
    /// in the frame.
    pub fn superset(self) -> Self {
        self.covering(&DeclaredContent::ALL)
    }

    /// These features with their content cut down to what `declared` names: where a
    /// prepared loop's renderer starts, its frames past the declaration drawn with the
    /// superset ([`Self::superset`]) from the first.
    pub fn within(self, declared: &DeclaredContent) -> Self {
        Self {
            homogeneous: self.homogeneous && declared.near_plane,
            textures: self.textures && declared.textures,
            vertex_normals: self.vertex_normals && declared.lit,
            face_normals: self.face_normals && declared.lit,
            transmission: self.transmission && declared.transmission,
            vertex_colours: self.vertex_colours
                && (declared.vertex_colours || declared.corner_colours),
            flat_colours: self.flat_colours || !declared.corner_colours,
            ..self
        }
    }

    /// The features of a frame of `scene`, whose meshes `meshes` describes
    /// ([`MeshFacts::of`] each).
    pub fn of(
        scene: &Scene,
        meshes: &[MeshFacts],
        width: u32,
        height: u32,
        subgroups: Subgroups,
    ) -> Self {
        let near_plane = homogeneous_triangles(scene, meshes, width, height);
        Self::of_frame(scene, meshes, near_plane, subgroups)
    }

    /// [`Self::of`] with [`homogeneous_triangles`] of the frame already counted
    /// (`near_plane`), which the caller needs too.
    pub fn of_frame(
        scene: &Scene,
        meshes: &[MeshFacts],
        near_plane: u64,
        subgroups: Subgroups,
    ) -> Self {
        let draws = || scene.transparent.iter();
        let lit = |d: &crate::scene::Draw| scene.materials[d.material].lit;
        Self {
            homogeneous: near_plane > 0,
            textures: draws().any(|d| scene.materials[d.material].texture.is_some()),
            vertex_normals: draws().any(|d| lit(d) && scene.meshes[d.mesh].normals.is_some()),
            face_normals: draws().any(|d| lit(d) && scene.meshes[d.mesh].normals.is_none()),
            slab_bits: 0,
            tile_shift: tile_shift(subgroups),
            rows: if subgroups.size == BIN_SIZE {
                BIN_SIZE
            } else {
                1 << tile_shift(subgroups)
            },
            transmission: draws().any(|d| scene.materials[d.material].transmission > 0.0),
            vertex_colours: draws()
                .any(|d| scene.meshes[d.mesh].colours.is_some() || d.tint != glam::Vec4::ONE),
            flat_colours: draws().all(|d| meshes[d.mesh].flat_colours),
            loop_budget: crate::gpu::CPU_DRIVER_LOOP_BUDGET,
            branching: false,
            records_as_texels: false,
            storage_walk: false,
            bin_tally_bits: 0,
            hardware_sampling: false,
            deep_binning_lanes: deep_binning_lanes(
                draws()
                    .map(|d| scene.meshes[d.mesh].quads.len() as u64)
                    .sum(),
            ),
        }
    }

    /// The features of another frame of the same scene: what depends on the frame's draws and
    /// camera from `fresh` ([`Self::of`] that frame), what the raster chose (slabs, rows per
    /// workgroup) from `self`.
    pub fn for_frame(self, fresh: Self) -> Self {
        Self {
            slab_bits: self.slab_bits,
            tile_shift: self.tile_shift,
            rows: self.rows,
            loop_budget: self.loop_budget,
            branching: self.branching,
            records_as_texels: self.records_as_texels,
            storage_walk: self.storage_walk,
            bin_tally_bits: self.bin_tally_bits,
            ..fresh
        }
    }

    /// Texels of a quad's attribute record: the sections shading can read with these
    /// features, as quad_attributes.glsl adds them up.
    pub fn attribute_texels(&self) -> u32 {
        use super::layout::*;
        let colours = match (self.vertex_colours, self.flat_colours) {
            (false, _) => 0,
            (true, true) => FLAT_COLOUR_TEXELS,
            (true, false) => COLOUR_TEXELS,
        };
        let normals = match (self.vertex_normals, self.face_normals) {
            (true, _) => NORMAL_TEXELS,
            (false, true) => FACE_NORMAL_TEXELS,
            (false, false) => 0,
        };
        let uvs = if self.textures { UV_TEXELS } else { 0 };
        colours + normals + uvs
    }

    /// Depth slabs per bin.
    pub fn slabs(&self) -> u32 {
        1 << self.slab_bits
    }

    /// The constants of the binning stages: the slabs, the tiles, the lanes per triangle and
    /// the tally.
    pub fn binning_constants(&self) -> Specialization {
        Specialization::new()
            .with(SLAB_BITS, self.slab_bits)
            .with(TILE_SHIFT, self.tile_shift)
            .with(DEEP_BINNING_LANES, self.deep_binning_lanes)
            .with(BIN_TALLY_BITS, self.bin_tally_bits)
    }

    /// What the triangles and their attribute records hold: the constants of every stage that
    /// writes or reads them (setup and the rasters).
    fn record_constants(&self) -> Specialization {
        self.binning_constants()
            .with(HOMOGENEOUS_PATH, self.homogeneous)
            .with(TEXTURES, self.textures)
            .with(VERTEX_NORMALS, self.vertex_normals)
            .with(FACE_NORMALS, self.face_normals)
            .with(VERTEX_COLOURS, self.vertex_colours)
            .with(FLAT_COLOURS, self.flat_colours)
    }

    /// Setup's constants: it may write its records through texel views, and skip its
    /// occlusion cull (`skip_cull`).
    pub fn setup_constants(&self, skip_cull: bool) -> Specialization {
        self.record_constants()
            .with(RECORDS_AS_TEXELS, self.records_as_texels)
            .with(SKIP_OCCLUSION_CULL, skip_cull)
    }

    /// These features with the records where `records_as_texels` says, and the walks' loads
    /// chosen for them ([`storage_walk`]).
    pub fn with_records(self, records_as_texels: bool, texel_walk_forced: bool) -> Self {
        Self {
            records_as_texels,
            storage_walk: storage_walk(self.branching, records_as_texels, texel_walk_forced),
            ..self
        }
    }

    /// What every raster over the bins is specialized with: the records' constants, the
    /// materials' transmission, a first dispatch's rows per workgroup, the loop budget,
    /// whether they branch and how their walks load.
    pub fn raster_constants(&self) -> Specialization {
        self.record_constants()
            .with(TRANSMISSION, self.transmission)
            .with(RASTER_GROUP_SIZE, BIN_SIZE * self.rows)
            .with(LOOP_BUDGET, self.loop_budget)
            .with(BRANCHING, self.branching)
            .with(STORAGE_WALK, self.storage_walk)
    }
}

/// A device's compute subgroups, as the rasters' tiles need them.
#[derive(Clone, Copy, Debug)]
pub struct Subgroups {
    /// Invocations in a subgroup.
    pub size: u32,
    /// Pipelines can be held to whole subgroups of that size (`DeviceInfo::full_subgroups`).
    pub full: bool,
}

impl From<&crate::gpu::DeviceInfo> for Subgroups {
    fn from(info: &crate::gpu::DeviceInfo) -> Self {
        Self {
            size: info.subgroup_size,
            full: info.full_subgroups,
        }
    }
}

/// Pixel rows of a tile, as a power of two: a tile is one subgroup's pixels, so that none of
/// its lanes idles (8x1 at 8 lanes, 8x2 at 16, 8x4 at 32, a whole 8x8 block at 64 or more).
/// A device that cannot be held to whole subgroups may split a workgroup of several rows
/// into partial subgroups, which would split a tile: there a tile is one row, in a workgroup
/// of its own, as no subgroup is smaller than a row (`Bins::new` refuses such devices).
pub fn tile_shift(subgroups: Subgroups) -> u32 {
    if subgroups.full {
        (subgroups.size / BIN_SIZE).clamp(1, BIN_SIZE).ilog2()
    } else {
        0
    }
}

/// Whether the rasters' walks read list entries and triangle records as storage buffers:
/// on GPUs (`branching`), where the entry a tile walks is the same in every lane and a
/// storage load at one address is one load for the subgroup (a scalar load on AMD), while a
/// texel fetch goes through the texture units lane by lane; not on CPU drivers, where a
/// storage load in divergent control flow is a loop over the lanes. Only while the records
/// fit one storage binding (else setup writes them as texels and the walks read texels),
/// and not where `TRANSLUCID_WALK_LOADS=texels` forces texels (the A/B of docs/gpu.md).
pub fn storage_walk(branching: bool, records_as_texels: bool, texel_walk_forced: bool) -> bool {
    branching && !records_as_texels && !texel_walk_forced
}

/// Whether `TRANSLUCID_WALK_LOADS` asks for texel loads in the walks (`texels`) rather than
/// the device's choice (`device`, or unset).
pub fn texel_walk_forced() -> crate::Result<bool> {
    crate::gpu::forced_by_env("TRANSLUCID_WALK_LOADS", "texels", "device")
}

/// Slots of a binning workgroup's tally on GPUs, as a power of two: 512, twice the entries
/// its 64 triangles make when each enters a block or two on a few rows, in 4 KB of shared
/// memory (more would cut the workgroups a GPU core holds).
pub const GPU_TALLY_BITS: u32 = 9;

/// The tally binning takes ([`RasterFeatures::bin_tally_bits`]): on GPUs (`branching`),
/// where many invocations adding to one bin's count wait on each other, unless
/// `TRANSLUCID_BIN_COUNTS=global` forces an atomic an entry (the A/B of docs/gpu.md); none on
/// CPU drivers, where a lane's atomics do not contend and the table's probes cost more.
pub fn bin_tally_bits(branching: bool, global_counts_forced: bool) -> u32 {
    if branching && !global_counts_forced {
        GPU_TALLY_BITS
    } else {
        0
    }
}

/// Whether `TRANSLUCID_BIN_COUNTS` asks for a global atomic an entry (`global`) rather than
/// the device's choice (`device`, or unset).
pub fn global_counts_forced() -> crate::Result<bool> {
    crate::gpu::forced_by_env("TRANSLUCID_BIN_COUNTS", "global", "device")
}

/// Whether the rasters sample textures in hardware: on GPUs (`gpu_profile`), unless the
/// device was asked for the software sampler (`DeviceInfo::software_sampling`: bit for bit
/// the reference's), or `forced` says otherwise (tests); and only where the textures the
/// frame uses are in the assets' texture array (`has_array`: `assets::texture_array`).
pub fn hardware_sampling(
    gpu_profile: bool,
    software_asked: bool,
    forced: Option<bool>,
    has_array: bool,
) -> bool {
    forced.unwrap_or(gpu_profile && !software_asked) && has_array
}

/// Quads the estimate of [`estimate`] looks at, at most: every k-th of larger scenes, scaled.
pub const ESTIMATE_QUADS: u64 = 1 << 16;

/// Quads an estimate made for every frame looks at, at most: some tens of microseconds.
pub const FRAME_ESTIMATE_QUADS: u64 = 1 << 12;

/// What a frame of a scene is expected to put in the bins, before any frame has counted it.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FrameEstimate {
    /// Fragments of the transparent draws.
    pub fragments: u64,
    /// Bin entries: a triangle takes one for each block its span on each pixel row touches.
    pub bin_entries: u64,
    /// The most quads whose bounds on screen meet in one cell of a coarse grid (at most
    /// 64 x 64 cells): about the most fragments a pixel has, from above where every quad is
    /// looked at (a quad covers a pixel once, and its bounds cover at least what it does).
    pub deepest: u64,
}

/// About how many fragments the scene's transparent draws put over a `width` x `height`
/// frame ([`estimate`]), from at most `most_quads` of their quads (every k-th, scaled).
pub fn estimated_fragments(scene: &Scene, width: u32, height: u32, most_quads: u64) -> u64 {
    estimate_sampled(scene, width, height, most_quads).fragments
}

/// What the scene's transparent draws put over a `width` x `height` frame, about: their
/// quads' areas on screen (beyond the near plane), each at most its bounding box's part of
/// the screen, and the pixel rows each of their triangles spans. A triangle's span on a row
/// of w pixels touches about (w + BIN_SIZE - 1) / BIN_SIZE blocks, so its bin entries are
/// about its area / BIN_SIZE and a block per row. It ignores what the opaque layer hides
/// and what faces away.
pub fn estimate(scene: &Scene, width: u32, height: u32) -> FrameEstimate {
    estimate_sampled(scene, width, height, ESTIMATE_QUADS)
}

/// [`estimate`] from at most `most_quads` of the quads (every k-th of larger scenes, scaled):
/// rougher, and cheaper where it is made every frame.
pub fn estimate_sampled(scene: &Scene, width: u32, height: u32, most_quads: u64) -> FrameEstimate {
    let view_projection = scene.camera.view_projection(width, height);
    let quads: u64 = scene
        .transparent
        .iter()
        .map(|d| scene.meshes[d.mesh].quads.len() as u64)
        .sum();
    let stride = quads.div_ceil(most_quads.max(1)).max(1);
    let mut area = 0.0f64;
    let mut triangle_rows = 0.0f64;
    let mut depth = DepthGrid::new(width, height);
    // Quads seen so far; every `stride`-th of them is looked at (the stride-th, the
    // 2 stride-th, ...), without walking the others.
    let mut seen = 0u64;
    for draw in &scene.transparent {
        let mesh = &scene.meshes[draw.mesh];
        let first = (stride - 1 - seen % stride) as usize;
        seen += mesh.quads.len() as u64;
        if first >= mesh.quads.len() {
            continue;
        }
        let mvp = model_view_projection(&view_projection, &draw.transform);
        for quad in mesh.quads.iter().skip(first).step_by(stride as usize) {
            let clip = quad.map(|v| clip_position(&mvp, mesh.positions[v as usize]));
            let lone = quad[3] == quad[2] || quad[3] == quad[0];
            let footprint = if clip.iter().all(|c| c.w > 0.0) {
                // The quad's area (each triangle's bounding box would count a quad wider
                // than the screen twice), its triangles' rows: triangle 0 has corners 0, 1, 2
                // and triangle 1 corners 0, 2, 3.
                let [a, b, c, d] = clip.map(|c| viewport_transform(c, width, height));
                let quad = screen_footprint(&[a, b, c, d], width, height);
                let first = screen_footprint(&[a, b, c], width, height).rows;
                let second = if lone {
                    0.0
                } else {
                    screen_footprint(&[a, c, d], width, height).rows
                };
                Footprint {
                    rows: first + second,
                    ..quad
                }
            } else {
                // Through the camera plane: its part beyond the near plane, as setup bins it.
                let beyond = beyond_near_plane(clip);
                let on_screen: Vec<Vec3> = beyond
                    .iter()
                    .map(|&c| viewport_transform(c, width, height))
                    .collect();
                let quad = screen_footprint(&on_screen, width, height);
                Footprint {
                    rows: quad.rows * if lone { 1.0 } else { 2.0 },
                    ..quad
                }
            };
            area += footprint.area;
            triangle_rows += footprint.rows;
            depth.add(footprint.bounds);
        }
    }
    let scaled = |v: f64| (v * stride as f64) as u64;
    FrameEstimate {
        fragments: scaled(area),
        bin_entries: scaled(area / f64::from(BIN_SIZE) + triangle_rows),
        deepest: depth.deepest() * stride,
    }
}

/// Counts, per cell of a coarse grid over the screen, the quads whose bounds meet it: each
/// quad adds at four corners of a difference table, summed once at the end.
struct DepthGrid {
    columns: usize,
    rows: usize,
    /// Pixels a cell spans (x, y).
    cell: (f64, f64),
    /// (rows + 1) x (columns + 1) differences.
    table: Vec<i64>,
}

impl DepthGrid {
    /// Cells of 8 x 8 pixels, or larger ones past 64 a side.
    fn new(width: u32, height: u32) -> Self {
        let columns = width.div_ceil(8).clamp(1, 64) as usize;
        let rows = height.div_ceil(8).clamp(1, 64) as usize;
        Self {
            columns,
            rows,
            cell: (
                f64::from(width) / columns as f64,
                f64::from(height) / rows as f64,
            ),
            table: vec![0; (rows + 1) * (columns + 1)],
        }
    }

    /// A quad whose on-screen bounds are `bounds`, if it has any.
    fn add(&mut self, bounds: Option<[f64; 4]>) {
        let Some([x0, y0, x1, y1]) = bounds else {
            return;
        };
        let span = |lo: f64, hi: f64, size: f64, count: usize| {
            let first = ((lo / size).floor().max(0.0) as usize).min(count - 1);
            let last = ((hi / size).ceil() as usize).clamp(first + 1, count);
            (first, last)
        };
        let (c0, c1) = span(x0, x1, self.cell.0, self.columns);
        let (r0, r1) = span(y0, y1, self.cell.1, self.rows);
        let stride = self.columns + 1;
        self.table[r0 * stride + c0] += 1;
        self.table[r0 * stride + c1] -= 1;
        self.table[r1 * stride + c0] -= 1;
        self.table[r1 * stride + c1] += 1;
    }

    /// The most quads any cell counts.
    fn deepest(&self) -> u64 {
        let stride = self.columns + 1;
        let mut sums = vec![0i64; self.table.len()];
        let mut most = 0;
        for r in 0..self.rows {
            for c in 0..self.columns {
                let i = r * stride + c;
                let above = if r > 0 { sums[i - stride] } else { 0 };
                let left = if c > 0 { sums[i - 1] } else { 0 };
                let corner = if r > 0 && c > 0 {
                    sums[i - stride - 1]
                } else {
                    0
                };
                sums[i] = self.table[i] + above + left - corner;
                most = most.max(sums[i]);
            }
        }
        most.max(0) as u64
    }
}

/// The part of the convex polygon `clip` (clip-space corners, in order) beyond the near plane
/// (z >= 0), where every point has w > 0.
fn beyond_near_plane(clip: [Vec4; 4]) -> Vec<Vec4> {
    let corners = clip.map(|c| c.as_dvec4().to_array());
    crate::raster::clip_polygon(&corners, |v| v[2])
        .into_iter()
        .map(|v| glam::DVec4::from_array(v).as_vec4())
        .filter(|p| p.w > 0.0)
        .collect()
}

/// What a convex polygon covers of the screen.
struct Footprint {
    /// Pixels, at most its bounding box's overlap with the screen.
    area: f64,
    /// Pixel rows its bounding box spans on the screen.
    rows: f64,
    /// Its bounding box within the screen (x0, y0, x1, y1, in pixels), where they meet.
    bounds: Option<[f64; 4]>,
}

/// What the convex polygon `points` (framebuffer coordinates, in order) covers of a
/// `width` x `height` screen.
fn screen_footprint(points: &[Vec3], width: u32, height: u32) -> Footprint {
    let Some(first) = points.first() else {
        return Footprint {
            area: 0.0,
            rows: 0.0,
            bounds: None,
        };
    };
    let xy = |p: &Vec3| (f64::from(p.x), f64::from(p.y));
    let twice_area: f64 = points
        .iter()
        .zip(points.iter().cycle().skip(1))
        .map(|(p, q)| {
            let ((px, py), (qx, qy)) = (xy(p), xy(q));
            px * qy - qx * py
        })
        .sum();
    let area = twice_area.abs() / 2.0;
    let (mut lo, mut hi) = (xy(first), xy(first));
    for p in points {
        let (x, y) = xy(p);
        lo = (lo.0.min(x), lo.1.min(y));
        hi = (hi.0.max(x), hi.1.max(y));
    }
    let overlap = |lo: f64, hi: f64, size: u32| (hi.min(f64::from(size)) - lo.max(0.0)).max(0.0);
    let rows = overlap(lo.1, hi.1, height);
    let bounded = overlap(lo.0, hi.0, width) * rows;
    if area.is_finite() {
        let (w, h) = (f64::from(width), f64::from(height));
        Footprint {
            area: area.min(bounded),
            rows,
            bounds: (bounded > 0.0)
                .then(|| [lo.0.max(0.0), lo.1.max(0.0), hi.0.min(w), hi.1.min(h)]),
        }
    } else {
        Footprint {
            area: 0.0,
            rows: 0.0,
            bounds: None,
        }
    }
}

/// Binning lanes per triangle for a frame of `quads` transparent quads: BIN_SIZE, unless two
/// triangles a quad would then need more than the 65 535 binning workgroups (of 64) every
/// Vulkan device allows in x. Such dispatches now go on in z (`split_groups`), so this only
/// keeps the binning of very large frames as it was measured; whether BIN_SIZE lanes would
/// serve them better is not measured.
fn deep_binning_lanes(quads: u64) -> u32 {
    const MAX_GROUPS: u64 = 65_535;
    if quads * 2 * u64::from(BIN_SIZE) <= MAX_GROUPS * u64::from(super::layout::BINNING_GROUP_SIZE)
    {
        BIN_SIZE
    } else {
        1
    }
}

/// What the features need of a mesh, kept between frames: scanning a large mesh's vertices
/// every frame cost hairball (120,000 vertices) 0.7 ms of recording on lavapipe's host.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct MeshFacts {
    /// The bounding box of its positions (`None` without any).
    pub bounds: Option<(Vec3, Vec3)>,
    /// Each quad has one colour at all its corners (true without colours).
    pub flat_colours: bool,
}

impl MeshFacts {
    pub fn of(mesh: &crate::scene::Mesh) -> Self {
        Self {
            bounds: bounds(&mesh.positions),
            flat_colours: flat_colours(mesh),
        }
    }

    /// The facts of every mesh of `scene`.
    pub fn of_scene(scene: &Scene) -> Vec<Self> {
        scene.meshes.iter().map(Self::of).collect()
    }
}

/// The bounding box of `positions`.
pub fn bounds(positions: &[Vec3]) -> Option<(Vec3, Vec3)> {
    let first = *positions.first()?;
    Some(
        positions
            .iter()
            .fold((first, first), |(lo, hi), p| (lo.min(*p), hi.max(*p))),
    )
}

/// Whether each quad of `mesh` has one colour at all its corners (true without colours).
fn flat_colours(mesh: &crate::scene::Mesh) -> bool {
    let Some(colours) = &mesh.colours else {
        return true;
    };
    mesh.quads.iter().all(|q| {
        let first = colours[q[0] as usize];
        q.iter().all(|&v| colours[v as usize] == first)
    })
}

/// Triangles of the frame that may take the homogeneous path: both of every quad of each
/// draw whose bounds leave the fixed-point path. Setup can write no more homogeneous records.
pub fn homogeneous_triangles(scene: &Scene, meshes: &[MeshFacts], width: u32, height: u32) -> u64 {
    let view_projection = scene.camera.view_projection(width, height);
    scene
        .transparent
        .iter()
        .filter(|d| leaves_fixed_path(d, &meshes[d.mesh], &view_projection, width, height))
        .map(|d| 2 * scene.meshes[d.mesh].quads.len() as u64)
        .sum()
}

/// Whether some triangle of draw `d` (of a mesh with `facts`) may need the homogeneous path.
fn leaves_fixed_path(
    d: &crate::scene::Draw,
    facts: &MeshFacts,
    view_projection: &Mat4,
    width: u32,
    height: u32,
) -> bool {
    let mvp = model_view_projection(view_projection, &d.transform);
    facts
        .bounds
        .is_some_and(|b| !bounds_on_fixed_path(&mvp, b, width, height))
}

/// Whether every vertex inside the positions' bounding box lands on the fixed-point path:
/// in front of the near plane and well inside the guard band. The conditions are linear in
/// clip space, so checking the box's corners (with a margin for rounding) covers its inside.
fn bounds_on_fixed_path(mvp: &Mat4, (lo, hi): (Vec3, Vec3), width: u32, height: u32) -> bool {
    (0..8).all(|corner| {
        let pick = |bit: u32, a: f32, b: f32| if corner & bit == 0 { a } else { b };
        let p = Vec3::new(
            pick(1, lo.x, hi.x),
            pick(2, lo.y, hi.y),
            pick(4, lo.z, hi.z),
        );
        let clip = clip_position(mvp, p);
        let fb = viewport_transform(clip, width, height);
        clip.w > 0.0
            && clip.z > 1e-6 * clip.w
            && fb.x.abs() < GUARD_BAND * 0.5
            && fb.y.abs() < GUARD_BAND * 0.5
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Features of a frame that draws none of the optional content.
    fn none() -> RasterFeatures {
        RasterFeatures {
            homogeneous: false,
            textures: false,
            vertex_normals: false,
            face_normals: false,
            slab_bits: 0,
            tile_shift: 0,
            rows: 1,
            transmission: false,
            vertex_colours: false,
            flat_colours: false,
            deep_binning_lanes: 1,
            loop_budget: crate::gpu::CPU_DRIVER_LOOP_BUDGET,
            branching: false,
            records_as_texels: false,
            storage_walk: false,
            bin_tally_bits: 0,
            hardware_sampling: false,
        }
    }

    /// A declared loop's frame takes every declared feature but textures, which it keeps as
    /// its own draws have them (untextured frames run without the texturing code).
    #[test]
    fn a_declared_loop_covers_all_but_the_frames_textures() {
        let plain = RasterFeatures {
            flat_colours: true,
            ..none()
        };
        let covered = plain.covering(&DeclaredContent::ALL);
        assert_eq!(
            covered,
            RasterFeatures {
                homogeneous: true,
                vertex_normals: true,
                face_normals: true,
                transmission: true,
                vertex_colours: true,
                flat_colours: false,
                ..plain
            }
        );
        let textured = RasterFeatures {
            textures: true,
            ..plain
        };
        assert!(textured.covering(&DeclaredContent::ALL).textures);
    }

    /// A frame is within a declaration when each thing it draws is declared; corner colours
    /// take their own declaration, and one colour a quad is within either.
    #[test]
    fn a_declaration_covers_what_it_names_and_no_more() {
        let plain = DeclaredContent::default();
        let flat = RasterFeatures {
            vertex_colours: true,
            flat_colours: true,
            ..none()
        };
        let corners = RasterFeatures {
            flat_colours: false,
            ..flat
        };
        let drawn = DeclaredContent::of_features;
        assert!(plain.covers(&drawn(&none())));
        assert!(!plain.covers(&drawn(&flat)));
        let colours = DeclaredContent {
            vertex_colours: true,
            ..plain
        };
        assert!(colours.covers(&drawn(&flat)));
        assert!(!colours.covers(&drawn(&corners)));
        let corner_colours = DeclaredContent {
            corner_colours: true,
            ..plain
        };
        assert!(corner_colours.covers(&drawn(&flat)));
        assert!(corner_colours.covers(&drawn(&corners)));
        for past in [
            RasterFeatures {
                textures: true,
                ..none()
            },
            RasterFeatures {
                face_normals: true,
                ..none()
            },
            RasterFeatures {
                transmission: true,
                ..none()
            },
            RasterFeatures {
                homogeneous: true,
                ..none()
            },
        ] {
            assert!(!plain.covers(&drawn(&past)), "{past:?}");
            assert!(DeclaredContent::ALL.covers(&drawn(&past)), "{past:?}");
        }
    }

    /// The superset variant draws any frame of its texture state: every other content
    /// feature on, the raster's own choices (slabs, rows, sampling) kept.
    #[test]
    fn the_superset_covers_every_content_and_keeps_the_rasters_choices() {
        let frame = RasterFeatures {
            slab_bits: 4,
            rows: 8,
            hardware_sampling: true,
            flat_colours: true,
            textures: true,
            ..none()
        };
        let untextured = RasterFeatures {
            textures: false,
            ..frame
        };
        assert!(!untextured.superset().textures);
        let superset = frame.superset();
        assert!(
            DeclaredContent::of_features(&superset).covers(&DeclaredContent {
                deep: false,
                ..DeclaredContent::ALL
            })
        );
        assert_eq!(
            (
                superset.slab_bits,
                superset.rows,
                superset.hardware_sampling
            ),
            (4, 8, true)
        );
        assert_eq!(superset.superset(), superset);
    }

    /// A frame's features cut down to a declaration are within it, and a frame within it
    /// keeps its own.
    #[test]
    fn features_within_a_declaration_are_covered_by_it() {
        let everything = RasterFeatures {
            textures: true,
            vertex_normals: true,
            face_normals: true,
            transmission: true,
            vertex_colours: true,
            homogeneous: true,
            ..none()
        };
        let colours = DeclaredContent {
            vertex_colours: true,
            lit: true,
            ..DeclaredContent::default()
        };
        for declared in [DeclaredContent::default(), colours, DeclaredContent::ALL] {
            let within = everything.within(&declared);
            assert!(declared.covers(&DeclaredContent::of_features(&within)));
            assert_eq!(within.within(&declared), within);
        }
        assert_eq!(everything.within(&DeclaredContent::ALL), everything);
    }

    /// A quad's attribute record holds the sections its frame's shading reads, and no more:
    /// the dragon (lit, vertex normals) only normals, particles (flat colours, textured)
    /// one colour and uvs.
    #[test]
    fn attribute_records_hold_what_shading_reads() {
        let none = none();
        assert_eq!(none.attribute_texels(), 0);
        let lit = RasterFeatures {
            vertex_normals: true,
            ..none
        };
        assert_eq!(lit.attribute_texels(), 3);
        let faces = RasterFeatures {
            face_normals: true,
            ..none
        };
        assert_eq!(faces.attribute_texels(), 2);
        let particles = RasterFeatures {
            textures: true,
            vertex_colours: true,
            flat_colours: true,
            ..none
        };
        assert_eq!(particles.attribute_texels(), 3);
        let everything = RasterFeatures {
            textures: true,
            vertex_normals: true,
            face_normals: true,
            vertex_colours: true,
            ..none
        };
        assert_eq!(
            everything.attribute_texels(),
            super::super::layout::MOST_ATTRIBUTE_TEXELS
        );
    }

    /// A mesh that a file without a camera is framed by (`Camera::framing`) stays on the
    /// fixed path all around the bench's orbit, its draw moving too. (The framing's near
    /// plane was tangent to the bounding sphere: 26 frames into the orbit the Stanford
    /// dragon's box reached it, and the whole mesh counted as crossing the near plane.)
    #[test]
    fn a_framed_mesh_stays_on_the_fixed_path_around_the_orbit() {
        use crate::scene::{motion::Orbit, Camera, Draw, Material, Mesh};
        // The dragon's bounds.
        let (lo, hi) = (Vec3::new(-1.0, -0.45, -0.66), Vec3::new(1.0, 0.45, 0.66));
        let corners: Vec<Vec3> = (0..8)
            .map(|c| Vec3::select(glam::BVec3::new(c & 1 != 0, c & 2 != 0, c & 4 != 0), hi, lo))
            .collect();
        let mut scene = Scene {
            camera: Camera::framing(lo, hi, 0.8),
            meshes: vec![Mesh::from_quads(
                "box",
                corners,
                vec![[0, 1, 3, 2], [4, 5, 7, 6]],
            )],
            materials: vec![Material::alpha(Vec3::ONE, 0.5)],
            ..Scene::default()
        };
        scene.transparent.push(Draw {
            mesh: 0,
            material: 0,
            transform: Mat4::IDENTITY,
            tint: glam::Vec4::ONE,
        });
        let facts = MeshFacts::of_scene(&scene);
        let orbit = Orbit::new(&scene);
        let mut frame = scene.clone();
        for i in 0..160 {
            frame.camera = orbit.camera(&scene, i);
            orbit.transparent(&scene, i, &mut frame.transparent);
            assert_eq!(
                homogeneous_triangles(&frame, &facts, 1280, 720),
                0,
                "frame {i}"
            );
        }
    }

    #[test]
    fn generated_scenes_need_only_the_fixed_path_and_no_textures() {
        for name in ["layers", "spheres", "planes"] {
            let scene = crate::scene::generated::generate(name).expect("scene");
            let f = RasterFeatures::of(&scene, &MeshFacts::of_scene(&scene), 640, 360, EIGHT);
            assert!(!f.homogeneous && !f.textures, "{name}: {f:?}");
        }
    }

    #[test]
    fn the_depth_estimate_counts_screen_area_within_the_screen() {
        let quad = |z: f32, half: f32| {
            let mut positions = Vec::new();
            let mut quads = Vec::new();
            for i in 0..10 {
                let z = z - i as f32 * 0.01;
                let first = positions.len() as u32;
                positions.extend([
                    Vec3::new(-half, -half, z),
                    Vec3::new(half, -half, z),
                    Vec3::new(half, half, z),
                    Vec3::new(-half, half, z),
                ]);
                quads.push([first, first + 1, first + 2, first + 3]);
            }
            let mut scene = crate::scene::generated::generate("spheres").expect("scene");
            scene.meshes = vec![crate::scene::Mesh::from_quads("q", positions, quads)];
            scene.transparent.truncate(1);
            scene.transparent[0].mesh = 0;
            scene.transparent[0].transform = glam::Mat4::IDENTITY;
            scene.camera = crate::scene::Camera::look_at(Vec3::Z * 3.0, Vec3::ZERO, 0.8, 0.1, 20.0);
            scene
        };
        // Ten layers far wider than the screen: ten fragments a pixel, not their whole area.
        let full = estimated_fragments(&quad(-1.0, 50.0), 64, 48, ESTIMATE_QUADS);
        assert_eq!(full, 10 * 64 * 48);
        // Their bin entries: a block for every 8 pixels of a row, and one more for each row
        // of each of a quad's two triangles.
        let entries = estimate(&quad(-1.0, 50.0), 64, 48).bin_entries;
        assert_eq!(entries, 10 * (64 * 48 / 8 + 2 * 48));
        // Ten layers deep wherever they are, wide or small; none behind the eye.
        assert_eq!(estimate(&quad(-1.0, 50.0), 64, 48).deepest, 10);
        assert_eq!(estimate(&quad(-1.0, 0.1), 64, 48).deepest, 10);
        assert_eq!(estimate(&quad(5.0, 50.0), 64, 48).deepest, 0);
        // Ten small layers: about their area.
        let small = estimated_fragments(&quad(-1.0, 0.1), 64, 48, ESTIMATE_QUADS) as f64;
        let side = 0.2 / (2.0 * 4.0 * (0.4f64).tan()) * 48.0;
        assert!((small / (10.0 * side * side) - 1.0).abs() < 0.05, "{small}");
        // Behind the eye: nothing.
        assert_eq!(
            estimated_fragments(&quad(5.0, 50.0), 64, 48, ESTIMATE_QUADS),
            0
        );
        // Through the camera plane: what lies beyond the near plane. (Such quads counted
        // nothing, and a frame of 200 of them started with bin lists 50 bands short.)
        let mut floor = quad(-1.0, 50.0);
        floor.camera = crate::scene::Camera::look_at(Vec3::Z * 3.0, Vec3::NEG_Y, 0.8, 0.1, 20.0);
        let through = estimated_fragments(&floor, 64, 48, ESTIMATE_QUADS);
        assert!(
            through > 5 * 64 * 48 && through <= 10 * 64 * 48,
            "{through}"
        );
    }

    /// A sample of the quads, scaled, estimates what all of them do where they are alike:
    /// every k-th quad across the draws (a draw with none of them sampled included).
    #[test]
    fn a_sampled_estimate_scales_every_kth_quad() {
        let mut scene = crate::scene::generated::generate("spheres").expect("scene");
        scene.transparent.truncate(1);
        let mesh = scene.transparent[0].mesh;
        let quads = scene.meshes[mesh].quads.len() as u64;
        let one = estimated_fragments(&scene, 64, 48, ESTIMATE_QUADS);
        // The same draw 12 times: every third quad of 12 x quads, scaled by 3.
        let draw = scene.transparent[0].clone();
        scene.transparent = vec![draw; 12];
        let all = estimated_fragments(&scene, 64, 48, 12 * quads);
        let sampled = estimated_fragments(&scene, 64, 48, 4 * quads);
        assert!(all.abs_diff(12 * one) <= 12, "{all} against 12 x {one}");
        let ratio = sampled as f64 / all as f64;
        assert!((ratio - 1.0).abs() < 0.02, "{sampled} of {all}");
        // The same draw 12 times is 12 times as deep, sampled or not.
        let deepest = estimate_sampled(&scene, 64, 48, 12 * quads).deepest;
        assert_eq!(deepest % 12, 0, "{deepest}");
        let sampled_deepest = estimate_sampled(&scene, 64, 48, 4 * quads).deepest;
        assert!(
            sampled_deepest.abs_diff(deepest) * 50 <= deepest,
            "{sampled_deepest} against {deepest}"
        );
        // Fewer quads looked at than draws: some draws have none, and the rest stand for them.
        let sparse = estimated_fragments(&scene, 64, 48, 5);
        assert!(sparse > 0, "{sparse}");
    }

    const EIGHT: Subgroups = Subgroups {
        size: 8,
        full: true,
    };

    #[test]
    fn a_tile_is_one_subgroups_pixels_up_to_a_block() {
        let rows = |size| 1 << tile_shift(Subgroups { size, full: true });
        assert_eq!([8, 16, 32, 64, 128].map(rows), [1, 2, 4, 8, 8]);
        let partial = |size| 1 << tile_shift(Subgroups { size, full: false });
        assert_eq!([8, 16, 32, 64, 128].map(partial), [1; 5]);
    }

    #[test]
    fn deep_binning_takes_a_row_of_lanes_per_triangle_while_the_dispatch_allows() {
        assert_eq!(deep_binning_lanes(4096), BIN_SIZE);
        assert_eq!(deep_binning_lanes(262_140), BIN_SIZE);
        assert_eq!(deep_binning_lanes(262_141), 1);
    }

    #[test]
    fn colours_are_flat_only_when_every_quad_has_one() {
        let particles = crate::scene::generated::generate("particles").expect("scene");
        assert!(
            RasterFeatures::of(
                &particles,
                &MeshFacts::of_scene(&particles),
                640,
                360,
                EIGHT
            )
            .flat_colours
        );
        let mut mesh = crate::scene::Mesh::from_quads("q", vec![Vec3::ZERO; 4], vec![[0, 1, 2, 3]]);
        assert!(flat_colours(&mesh), "no colours");
        mesh.colours = Some(vec![glam::Vec4::ONE; 4]);
        assert!(flat_colours(&mesh));
        mesh.colours.as_mut().expect("colours")[3].x = 0.5;
        assert!(
            !flat_colours(&mesh),
            "the second triangle's last corner differs"
        );
    }

    #[test]
    fn a_mesh_around_the_camera_needs_the_homogeneous_path() {
        let mvp = crate::scene::Camera::default().view_projection(64, 64);
        let around = (Vec3::new(-1.0, -1.0, 4.0), Vec3::new(1.0, 1.0, 6.0));
        assert!(!bounds_on_fixed_path(&mvp, around, 64, 64));
        let ahead = (Vec3::new(-1.0, -1.0, -1.0), Vec3::new(1.0, 1.0, 1.0));
        assert!(bounds_on_fixed_path(&mvp, ahead, 64, 64));
    }
}
