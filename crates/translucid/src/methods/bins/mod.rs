//! The bins: the compute stages that sort a frame's transparent triangles into per-bin lists,
//! which the exact method's raster and the wavelet method's bin raster both read.
//!
//! Stages (one compute shader each, `shaders/bins/`):
//! 0. `depth_pyramid`: the farthest opaque depth per 8×8 block and over ever larger cells
//!    (one dispatch: its last workgroup builds the levels above the first).
//! 1. `setup`: per transparent quad, transform, set up its triangles (fixed-point or
//!    homogeneous), cull (back faces, off screen, wholly behind the opaque layer by the
//!    pyramid), append visible triangles. The occlusion cull, and the pyramid with it, is
//!    left out of the next `OCCLUSION_REST` frames when a frame's saved less than the
//!    pyramid cost (the raster depth-tests every fragment). Binning runs for as many
//!    triangles as setup kept (an indirect dispatch setup sizes).
//! 2. `bin_count`, the scan (`block_scan`, `band_plan`, `bin_offsets`) and `bin_fill`: per bin
//!    (one row of an 8×8-pixel block), count the triangles that may cover it, prefix-sum the
//!    counts and list the blocks with entries, then, per band, plan the band, write its bins'
//!    offsets and fill their triangle lists.
//!    Frames with many fragments per pixel order each list by depth slab (nearest vertex).
//!
//! A raster then runs over each band's blocks (one workgroup per row, from the indirect
//! command the band's plan wrote) before the next band is filled: [`Bins::record_band`] is
//! called once per band by the method that owns the raster.
//!
//! Memory is sized from the frame: two triangle records per quad at most, bin lists grown to
//! what the GPU counted, and sized again from the host's estimate when the transparent quads
//! grow by a quarter (content streamed in, which frames in flight have not counted yet). A
//! frame whose lists pass their capacity is right all the same: the scan lists the blocks in
//! order and the frame is filled and rasterized in bands of blocks
//! whose lists fit, one after another in the same command buffer (up to `BANDS`; bands
//! without blocks are near-empty dispatches). A frame after one that fitted with room to
//! spare records one band only. Counters come back every frame and grow the
//! buffers for later frames. What one recording cannot answer leaves pixels untouched, never
//! drawn from truncated work: blocks past the last band, counted as degraded rows (rendered
//! again when translucid submits; reported on an engine's device). Homogeneous records past
//! one buffer's worth lose triangles (rendered again, or reported).

#![deny(clippy::unwrap_used)]

mod composite;
pub mod features;
pub mod layout;
pub(crate) mod resources;

use super::{FrameDone, FrameSetup, RecordContext};
use crate::assets::GpuScene;
use crate::frame::FrameTargets;
use crate::gpu::{image_barrier, memory_barrier, vk, ComputePipeline, ComputePipelineCache, Gpu};
use crate::interface::specialization::Specialization;
use crate::interface::SetDecl;
use crate::scene::Scene;
use crate::{Error, Result};
use features::{DeclaredContent, FrameEstimate, MeshFacts, RasterFeatures};
use layout::{
    BinCounters, BinPush, BIN_SIZE, DISPATCH_BAND_FILL_OFFSET, DISPATCH_BINNING_OFFSET,
    DISPATCH_BIN_OFFSETS_OFFSET, DISPATCH_RASTER_BINS_OFFSET, DRAW_COMPOSITE_OFFSET, LAST_STAMP,
    OVERFLOW_BAND_LISTS, OVERFLOW_CROWDED_BIN, OVERFLOW_HOMOGENEOUS, SCAN_GROUP_SIZE,
};
use resources::{Capacities, Resources};
use std::sync::Arc;

/// Loop iterations one binning invocation takes at most on CPU drivers: a triangle taller
/// than that many bins' worth is binned by several invocations, in slices of rows
/// (bin_lists.glsl). Within lavapipe's loop limit (`CPU_DRIVER_LOOP_BUDGET`), which whole
/// rows of the frame at most sizes fit, so that a triangle is rarely binned twice.
pub const SLICE_ITERATIONS: u32 = 60_000;

/// The same in shallow frames on GPUs (the GPU profile), where a subgroup runs as long as
/// its longest invocation: a tall triangle is binned as work items of at most this many
/// iterations, (triangle, slice) pairs of its own invocations, so that one full-screen
/// triangle does not hold its subgroup for a whole frame's bins (16 tile rows a slice at
/// 1920 pixels across). Invocations of slices a triangle does not reach find no rows and do
/// nothing more.
pub const GPU_SLICE_ITERATIONS: u32 = 4096;

/// The smallest loop budget a test may force (`BinOptions::loop_budget`): room for a
/// stretch's shading and the searches over the most slabs, and some walking.
const LEAST_LOOP_BUDGET: u32 = 4096;

/// What the raster that reads the bins asks of them.
#[derive(Clone, Copy)]
pub struct RasterNeeds {
    /// Its method, in errors and logs.
    pub method: &'static str,
    /// Lists are ordered by 2^slab_bits depth slabs from the first frame on.
    pub slab_bits: u32,
    /// What it keeps of the rows it suspends onto the resume lists; none if it never does.
    pub suspended_rows: Option<SuspendedRows>,
}

/// A raster's state for each row it suspends with a state slot: one binding of its own,
/// which `set` adds to the bins' set, made and grown with the resume lists' slots (rows past
/// them start over when resumed).
#[derive(Clone, Copy)]
pub struct SuspendedRows {
    /// The bins' set extended by the binding.
    pub set: &'static SetDecl,
    /// The binding's name in `set`, and the bytes it keeps for one tile.
    pub binding: &'static str,
    pub bytes_per_tile: u64,
    /// State slots each of the two resume lists starts with (unless
    /// `BinOptions::initial_resume_rows` says otherwise).
    pub initial_slots: u32,
}

/// Settings of the bins, whichever raster reads them. Left at their defaults, the bins size
/// themselves from the frame; the rest are for tests that reach the bins' limits.
#[derive(Clone, Debug, Default)]
pub struct BinOptions {
    /// First capacity of the per-bin triangle lists, in entries. `None` sizes it from the
    /// frame. Small values force the bands (for tests).
    pub initial_bin_entries: Option<u32>,
    /// First capacity of the homogeneous (near-plane) triangle records.
    pub initial_homogeneous: Option<u32>,
    /// First state slots of the rows a raster suspends for a later dispatch (rows hundreds of
    /// fragments deep; the exact raster's: `SuspendedRows`).
    pub initial_resume_rows: Option<u32>,
    /// Tests: a loop budget under the device's (at least 4096), so that rows tens of
    /// layers deep suspend and resume.
    pub loop_budget: Option<u32>,
    /// Start with the stages built without the near-plane path, whatever the scene looks
    /// like, so that tests can exercise the rebuild-and-render-again fallback.
    #[doc(hidden)]
    pub assume_fixed_path: bool,
    /// Rasterize one tile per workgroup, as on devices whose subgroups are wider than a row
    /// (most GPUs), so that tests cover that path on lavapipe's subgroups of 8 too.
    #[doc(hidden)]
    pub assume_wide_subgroups: bool,
    /// Bin at most this many tile rows of a triangle per binning invocation (the shader loop
    /// budget otherwise decides, about 357 at 1280 pixels across), so that tests cover
    /// triangles split into several slices.
    #[doc(hidden)]
    pub bin_rows_per_slice: Option<u32>,
    /// Binning workgroups tally their entries in 2^bits shared slots (at most the GPU's; 0:
    /// no tally), on any device, so that tests can fill the table and spill from it.
    #[doc(hidden)]
    pub bin_tally_bits: Option<u32>,
    /// Sample textures in hardware (`Some(true)`, where the assets have a texture array)
    /// or in software (`Some(false)`) whatever the profile, so that tests cover the
    /// hardware path on lavapipe's CPU profile.
    #[doc(hidden)]
    pub hardware_sampling: Option<bool>,
    /// Bands of bins recorded per frame (`None`: [`BANDS`]), so that tests can reach the
    /// frames that need more than it records.
    #[doc(hidden)]
    pub bands: Option<u32>,
    /// Workgroups the dispatches over triangles (setup, binning), blocks (the rasters) and
    /// resumed rows (exact's continuations) take in x before they go on in z (`None`:
    /// [`MOST_GROUPS_X`]), so that tests cover the split with small frames.
    #[doc(hidden)]
    pub groups_x: Option<u32>,
    /// The most near-plane triangle records the bins may hold (`None`: one storage binding's
    /// worth), so that tests reach that limit with a small frame.
    #[doc(hidden)]
    pub most_homogeneous: Option<u32>,
    /// What the engine declared its frames may draw: every frame's shaders cover it
    /// ([`features::DeclaredContent`]).
    pub declared: features::DeclaredContent,
    /// The loop was prepared (`Context::prepare`): the superset variant is built up front
    /// too, and frames whose content is past `declared` draw with it rather than build
    /// their own ([`RasterFeatures::superset`]).
    pub prepared: bool,
}

/// A raster's shader in its two variants: sampling textures in software (bit for bit the
/// reference) and in hardware (`HARDWARE_SAMPLING`).
#[derive(Clone, Copy)]
pub struct RasterShader {
    pub software: &'static [u8],
    pub hardware_sampled: &'static [u8],
}

/// Whether a frame of `scene` over `gpu_scene` samples in hardware
/// (`features::hardware_sampling`): only where the texture array holds every texture its
/// transparent draws use.
fn sampling(
    info: &crate::gpu::DeviceInfo,
    forced: Option<bool>,
    gpu_scene: &GpuScene,
    scene: &Scene,
) -> bool {
    features::hardware_sampling(
        info.profile == crate::gpu::Profile::Gpu,
        info.software_sampling,
        forced,
        gpu_scene
            .texture_array()
            .is_some_and(|a| a.holds_textures_of(scene)),
    )
}

/// The workgroups in x every Vulkan device allows in one dispatch
/// (`maxComputeWorkGroupCount`): setup and binning dispatches over more triangles go on in
/// z (4.2 million triangles of 64 a workgroup fill one row).
pub const MOST_GROUPS_X: u32 = 65_535;

/// Bands recorded per frame ([`BinOptions::bands`] for tests). A frame whose bin lists pass
/// their capacity is rasterized in bands of blocks whose lists fit, one after another in the
/// same command buffer, and the lists grow for later frames; a frame needing more than BANDS
/// times the capacity leaves the blocks past the last band untouched (counted, and rendered
/// again when translucid submits). Bands without blocks cost a tiny dispatch and empty
/// indirect ones.
pub const BANDS: u32 = 4;
/// A dispatch of `groups` workgroups as (x, z) with at most `most_x` in x
/// (`splitGroups` of bins_bindings.glsl, which the shaders' `linearWorkGroup` undoes; the
/// last row in z may hold workgroups past `groups`, which find no item).
fn split_groups(groups: u32, most_x: u32) -> (u32, u32) {
    (groups.min(most_x), groups.div_ceil(most_x))
}

/// `PYRAMID_GROUP_SIZE` of depth_pyramid.comp.
const PYRAMID_GROUP_SIZE: u32 = 256;

/// What last wrote the frame targets before a frame's raster: the opaque pass.
pub const OPAQUE_PASS_WRITES: (vk::PipelineStageFlags, vk::AccessFlags) = (
    vk::PipelineStageFlags::ALL_GRAPHICS,
    vk::AccessFlags::from_raw(
        vk::AccessFlags::COLOR_ATTACHMENT_WRITE.as_raw()
            | vk::AccessFlags::DEPTH_STENCIL_ATTACHMENT_WRITE.as_raw(),
    ),
);
/// What last touched them before a finishing submission: the previous one, waited for.
pub const FINISHED_SUBMISSION_WRITES: (vk::PipelineStageFlags, vk::AccessFlags) = (
    vk::PipelineStageFlags::ALL_COMMANDS,
    vk::AccessFlags::from_raw(
        vk::AccessFlags::MEMORY_READ.as_raw() | vk::AccessFlags::MEMORY_WRITE.as_raw(),
    ),
);

/// The bin stages' pipelines for one set of features.
struct StagePipelines {
    depth_pyramid: Arc<ComputePipeline>,
    setup: Arc<ComputePipeline>,
    bin_count: Arc<ComputePipeline>,
    /// Deep frames' slab histogram, whose last workgroup plans the slabs (bin_lists.glsl),
    /// before the count; none for frames of one slab.
    slab_histogram: Option<Arc<ComputePipeline>>,
    /// The scan (bin_scan.glsl): the blocks' sums and offsets with the first band's plan,
    /// the band's bin offsets, and a later band's plan.
    block_scan: Arc<ComputePipeline>,
    bin_offsets: Arc<ComputePipeline>,
    band_plan: Arc<ComputePipeline>,
    bin_fill: Arc<ComputePipeline>,
    /// Setup without the occlusion cull, for frames recorded without the depth pyramid.
    setup_unculled: Arc<ComputePipeline>,
}

impl StagePipelines {
    /// The stages specialized for `features`, from `cache` (built there on first use).
    fn select(
        cache: &mut ComputePipelineCache,
        gpu: &Gpu,
        layouts: &[&crate::gpu::DescriptorLayout],
        features: &RasterFeatures,
    ) -> Result<Self> {
        let mut stage = |spirv: &'static [u8], constants: &Specialization| {
            cache.get(gpu, layouts, spirv, constants)
        };
        let setup = features.setup_constants(false);
        let setup_unculled = features.setup_constants(true);
        let binning = features.binning_constants();
        Ok(Self {
            depth_pyramid: stage(
                crate::spirv!("bins/depth_pyramid.comp"),
                &Specialization::NONE,
            )?,
            setup: stage(crate::spirv!("bins/setup.comp"), &setup)?,
            bin_count: stage(crate::spirv!("bins/bin_count.comp"), &binning)?,
            slab_histogram: match features.slab_bits {
                0 => None,
                _ => Some(stage(crate::spirv!("bins/slab_histogram.comp"), &binning)?),
            },
            block_scan: stage(crate::spirv!("bins/block_scan.comp"), &binning)?,
            bin_offsets: stage(crate::spirv!("bins/bin_offsets.comp"), &binning)?,
            band_plan: stage(crate::spirv!("bins/band_plan.comp"), &binning)?,
            bin_fill: stage(crate::spirv!("bins/bin_fill.comp"), &binning)?,
            setup_unculled: stage(crate::spirv!("bins/setup.comp"), &setup_unculled)?,
        })
    }
}

/// What the bins learned from a completed frame.
#[derive(Clone, Copy, Debug)]
pub struct BinsDone {
    pub counters: BinCounters,
    /// The features changed for later frames: the raster's pipelines must follow.
    pub features_changed: bool,
    /// Buffers grew for later frames (a finishing submission cannot reuse the frame's).
    pub grown: bool,
    /// The frame is not all right: triangles were lost, the stages missed a feature the
    /// frame needed, or blocks were left untouched. Render it again.
    pub rerender: bool,
    /// Pixel rows the frame left with the opaque colour (blocks past the last band, or rows
    /// a band left unfinished).
    pub degraded_rows: u64,
}

impl BinPush {
    /// Sizes the stages for a frame of `width` x `height`.
    fn set_size(&mut self, width: u32, height: u32) {
        self.width = width;
        self.height = height;
        self.bins_x = width.div_ceil(BIN_SIZE);
        self.bins_y = height.div_ceil(BIN_SIZE);
    }

    /// Slices binning's rows for stages specialized with `features`, at most `rows_limit`
    /// rows a slice: shallow frames on GPUs, or with a tally (whose fill walks each slice
    /// twice), in work items of GPU_SLICE_ITERATIONS; others in SLICE_ITERATIONS (deep
    /// frames already spread a triangle's rows over a row of lanes: bin_lists.glsl).
    fn set_slices(&mut self, features: &RasterFeatures, rows_limit: u32) {
        let short = features.branching || features.bin_tally_bits > 0;
        let iterations = if short && features.slab_bits == 0 {
            GPU_SLICE_ITERATIONS
        } else {
            SLICE_ITERATIONS
        };
        // A tile row of bins costs at most bins_x + BIN_SIZE iterations: its blocks, and a
        // row span for each of its pixel rows (at most a block's).
        self.bin_rows_per_slice = (iterations / (self.bins_x + BIN_SIZE))
            .min(rows_limit)
            .max(1);
    }
}

/// The settings a frame was recorded with.
#[derive(Clone, Copy, Debug)]
struct Recorded {
    features: RasterFeatures,
    capacities: Capacities,
    /// With setup's occlusion cull (and the depth pyramid it reads).
    culled: bool,
    /// The frame's width and height.
    size: (u32, u32),
    /// It cleared the transparent layer before its raster.
    clears_layer: bool,
    /// The bands it recorded, and its place among the recordings.
    bands: u32,
    recording: u64,
    /// Bin rows a binning invocation covered at most.
    rows_per_slice: u32,
}

/// Frames recorded without the occlusion cull once a frame's cull saved less than its depth
/// pyramid cost, before one is recorded with it again to see whether it has become worth it.
/// The pyramid's cost grows with the frame's blocks, the cull's saving with the blocks the
/// dropped triangles would have been binned into: the cull pays when those are at least
/// 1/OCCLUSION_BLOCKS_PER_CELL of the frame's. Measured on lavapipe, where the pyramid takes
/// about 55 ns a block (0.8 ms at 1280x720) and a dropped triangle about 270 ns a block of
/// binning and raster (StainedGlassLamp: 1,300 small triangles dropped, 0.3-0.5 ms a frame
/// faster without the cull). On a GPU both are microseconds, and the rule seldom matters.
const OCCLUSION_REST: u32 = 30;
const OCCLUSION_BLOCKS_PER_CELL: u32 = 5;

pub struct Bins {
    gpu: Gpu,
    /// The method whose raster reads the bins, in errors and logs.
    method: &'static str,
    resources: Resources,
    /// Every pipeline built so far, by specialization: the bin stages' and the raster's.
    cache: ComputePipelineCache,
    /// The variants this frame's features need.
    stages: StagePipelines,
    /// Bands recorded per frame, unless `single_band`.
    bands: u32,
    /// The bands were set by the options: every frame records them all.
    bands_fixed: bool,
    /// Standalone frames only: the last completed frame filled at most half the lists'
    /// capacity (which grows to keep that room), in one band: the next frames record that one
    /// band only, and no empty ones. A frame past it keeps the opaque colour in the blocks
    /// past the band, is rendered again, and the buffers grow. On an engine's device, which
    /// cannot record a frame again, every frame records all its bands, so that content that
    /// grows suddenly (streamed in, a camera cut) is right on its first recording (2026-12-07,
    /// lavapipe, `examples-c/frame_loop` exact at 480x270: 3.65-3.75 ms a frame with every band,
    /// 3.64-3.69 ms with one).
    single_band: bool,
    /// Recordings so far, and the first one after the last moved mesh: a mesh whose vertices
    /// moved may now fill the screen, so frames record every band until one recorded after
    /// the move has completed and fitted.
    recordings: u64,
    first_after_move: u64,
    /// What the features need of each mesh, its bounds kept up with moved vertices.
    meshes: Vec<MeshFacts>,
    /// Transparent quads when the lists were last sized from the host's estimate.
    estimated_quads: u32,
    push: BinPush,
    /// The most rows a slice of binning may take (BinOptions; normally no limit).
    slice_rows_limit: u32,
    /// BinOptions::hardware_sampling.
    hardware_sampling_forced: Option<bool>,
    /// The constants the stage pipelines (and the raster's) are specialized with.
    features: RasterFeatures,
    /// `TRANSLUCID_WALK_LOADS=texels`: the walks read texels on any device.
    texel_walk_forced: bool,
    /// Tests start without the near-plane path whatever the frame (BinOptions).
    fixed_path_forced: bool,
    /// What every frame's features cover (BinOptions::declared).
    declared: features::DeclaredContent,
    /// BinOptions::prepared.
    prepared: bool,
    /// A frame past the declaration was drawn with the superset variant (said once).
    superset_drawn: bool,
    /// Frames still to record without the occlusion cull.
    unculled_frames: u32,
    /// The largest buffers may grow to.
    most: Capacities,
    /// The GPU found a near-plane triangle the host's estimate missed: later frames keep the
    /// near-plane path rather than render again.
    homogeneous_missed: bool,
    /// Per frame slot, what its last frame was recorded with: with frames in flight, the
    /// settings may have moved on by the time that frame completes.
    recorded: Vec<Recorded>,
    /// The composite onto the engine's colour, made with the transparent layer by the first
    /// frame on its device.
    composite: Option<composite::Composite>,
    /// The last submission's stamp (transparent_layer.glsl) on an engine's device; 0 before
    /// the first.
    stamp: u32,
    /// A frame that cleared the transparent layer has completed.
    layer_cleared: bool,
}

/// Homogeneous records a frame with `near_plane` triangles that may take the near-plane path
/// needs, up to the most the bins hold (past that the frame is refused).
fn homogeneous_bound(most: &Capacities, near_plane: u64) -> u32 {
    near_plane.min(u64::from(most.homogeneous)) as u32
}

/// The largest buffers the bins may grow to on `gpu`, within the test limits of `options`,
/// for a raster keeping `state_bytes` for each row it suspends.
fn most_capacities(gpu: &Gpu, options: &BinOptions, state_bytes: u64) -> Capacities {
    let mut most = Capacities::most(gpu, state_bytes);
    if let Some(limit) = options.most_homogeneous {
        most.homogeneous = most.homogeneous.min(limit.max(1));
    }
    most
}

impl Bins {
    /// The bins of `scene` for `raster`, given the frame's `expected` depth
    /// ([`features::estimate`]).
    pub fn new(
        gpu: &Gpu,
        scene: &Scene,
        gpu_scene: &GpuScene,
        targets: &FrameTargets,
        options: &BinOptions,
        expected: &FrameEstimate,
        raster: RasterNeeds,
    ) -> Result<Self> {
        let method = raster.method;
        let info = gpu.info();
        if !info.shader_int64 {
            return Err(Error::DeviceLacks(format!(
                "{} lacks 64-bit shader integers, which the {method} method's edge functions need",
                info.name
            )));
        }
        // The rasters' tiles, at least a row of BIN_SIZE pixels, vote, broadcast and reduce
        // as one subgroup.
        let wanted = crate::gpu::SUBGROUP_REQUIREMENTS;
        if !info.compute_subgroup_operations || info.subgroup_size < wanted.min_size {
            return Err(Error::DeviceLacks(format!(
                "{} has compute subgroups of {} invocations{}; the {method} method needs at least \
                 {} with basic, vote, ballot and arithmetic operations",
                info.name,
                info.subgroup_size,
                if info.compute_subgroup_operations {
                    ""
                } else {
                    " without all of basic, vote, ballot and arithmetic"
                },
                wanted.min_size
            )));
        }
        let capacity = targets.capacity;
        if capacity.width > 0xFFFF || capacity.height > 0xFFFF {
            // Triangle records keep their pixel bounds in 16 bits.
            return Err(Error::TooLarge(format!(
                "{method}: {}x{} is over the 65535 pixels a side it supports",
                capacity.width, capacity.height
            )));
        }
        let (width, height) = (targets.extent.width, targets.extent.height);
        let meshes = MeshFacts::of_scene(scene);
        let state_bytes = raster.suspended_rows.map_or(0, |rows| rows.bytes_per_tile);
        let most = most_capacities(gpu, options, state_bytes);
        let near_plane = features::homogeneous_triangles(scene, &meshes, width, height);
        let mut features = RasterFeatures::of_frame(scene, &meshes, near_plane, info.into());
        features.homogeneous &= !options.assume_fixed_path;
        if options.prepared {
            // The declared variants, whatever this frame draws: the renderer's frames (this
            // one included, `Renderer::sharing`) are set one by one, those past the
            // declaration drawn with the superset.
            features = features.within(&options.declared);
        }
        let mut features = features.covering(&options.declared);
        features.slab_bits = raster.slab_bits;
        if options.assume_wide_subgroups {
            features.rows = 1 << features.tile_shift;
        }
        features.loop_budget = options.loop_budget.map_or(info.loop_budget, |b| {
            b.clamp(LEAST_LOOP_BUDGET, info.loop_budget)
        });
        features.branching = info.profile == crate::gpu::Profile::Gpu;
        let hardware_sampling_forced = options.hardware_sampling;
        features.hardware_sampling = sampling(info, hardware_sampling_forced, gpu_scene, scene);
        features.bin_tally_bits = match options.bin_tally_bits {
            Some(bits) => bits.min(features::GPU_TALLY_BITS),
            None => features::bin_tally_bits(features.branching, features::global_counts_forced()?),
        };
        // Buffers per block and row are made for the largest frame; attribute records for
        // the textured frames of a loop that declared them.
        let declared_texels = RasterFeatures {
            textures: features.textures || options.declared.textures,
            ..features
        }
        .attribute_texels();
        let capacities = Capacities::initial(
            gpu_scene.transparent_quads,
            declared_texels,
            capacity.width.div_ceil(BIN_SIZE) * capacity.height.div_ceil(BIN_SIZE),
            expected,
            homogeneous_bound(&most, near_plane),
            raster.suspended_rows.map_or(0, |rows| rows.initial_slots),
            options,
        )
        .within(&most);
        let resources = Resources::new(
            gpu,
            scene,
            gpu_scene,
            targets,
            capacities,
            features.slabs(),
            raster.suspended_rows,
        )
        .map_err(|e| in_errors(method, e))?;
        let layouts = [&gpu_scene.layout, &resources.layout];
        let mut cache = ComputePipelineCache::new(std::mem::size_of::<BinPush>() as u32);
        let texel_walk_forced = features::texel_walk_forced()?;
        let features =
            features.with_records(resources.records_pass_a_binding(gpu), texel_walk_forced);
        let stages = StagePipelines::select(&mut cache, gpu, &layouts, &features)?;
        let slice_rows_limit = options.bin_rows_per_slice.unwrap_or(u32::MAX);
        let mut push = BinPush {
            item_count: gpu_scene.transparent_quads,
            draw_count: scene.transparent.len() as u32,
            threshold: 0.0,
            resume_list: 0,
            groups_x: options
                .groups_x
                .unwrap_or(MOST_GROUPS_X)
                .clamp(1, MOST_GROUPS_X),
            ..bytemuck::Zeroable::zeroed()
        };
        push.set_size(width, height);
        push.set_slices(&features, slice_rows_limit);
        Ok(Self {
            gpu: gpu.clone(),
            method,
            resources,
            cache,
            stages,
            bands: options.bands.unwrap_or(BANDS).max(1),
            bands_fixed: options.bands.is_some(),
            single_band: false,
            recordings: 0,
            first_after_move: 0,
            meshes,
            estimated_quads: gpu_scene.transparent_quads,
            push,
            slice_rows_limit,
            hardware_sampling_forced,
            features,
            texel_walk_forced,
            fixed_path_forced: options.assume_fixed_path,
            declared: options.declared,
            prepared: options.prepared,
            superset_drawn: false,
            unculled_frames: 0,
            most,
            homogeneous_missed: false,
            recorded: vec![
                Recorded {
                    features,
                    capacities,
                    culled: true,
                    size: (width, height),
                    clears_layer: false,
                    bands: 0,
                    recording: 0,
                    rows_per_slice: push.bin_rows_per_slice,
                };
                gpu_scene.slot_count()
            ],
            composite: None,
            stamp: 0,
            layer_cleared: false,
        })
    }

    /// The raster's transmittance threshold (exact's; 0 composites every fragment).
    pub fn set_threshold(&mut self, threshold: f32) {
        self.push.threshold = threshold;
    }

    /// The features the frames are recorded with.
    pub fn features(&self) -> RasterFeatures {
        self.features
    }

    /// What the engine declared its frames may draw.
    pub fn declared(&self) -> features::DeclaredContent {
        self.declared
    }

    /// Whether the loop was prepared (BinOptions::prepared).
    pub fn prepared(&self) -> bool {
        self.prepared
    }

    /// Where the engine declared textures, builds now the variant of frames with the other
    /// texture state than this one's (textured draws or none): its stages, and what `raster`
    /// builds of the method's raster for the bins' features as they are then; so that the
    /// loop moves between the two and builds nothing.
    pub fn prebuild_texture_variant(
        &mut self,
        gpu_scene: &GpuScene,
        raster: impl FnOnce(&mut Self) -> Result<()>,
    ) -> Result<()> {
        if !self.declared.textures {
            return Ok(());
        }
        let other = RasterFeatures {
            textures: !self.features.textures,
            ..self.features
        };
        self.prebuild_variant(gpu_scene, other, raster)
    }

    /// In a prepared loop, builds now the superset variant ([`RasterFeatures::superset`])
    /// in both texture states, as [`Self::prebuild_texture_variant`] builds its variant; so
    /// that frames past the declaration build nothing. Its buffers are sized by the first
    /// frame that draws with it.
    pub fn prebuild_superset(
        &mut self,
        gpu_scene: &GpuScene,
        mut raster: impl FnMut(&mut Self) -> Result<()>,
    ) -> Result<()> {
        if !self.prepared {
            return Ok(());
        }
        let superset = self.features.superset();
        for textures in [false, true] {
            let features = RasterFeatures {
                textures,
                ..superset
            };
            self.prebuild_variant(gpu_scene, features, &mut raster)?;
        }
        Ok(())
    }

    /// Builds now the stages of `features`, and what `raster` builds of the method's raster
    /// with them as the bins' features; the bins' own features, stages and buffers stay.
    fn prebuild_variant(
        &mut self,
        gpu_scene: &GpuScene,
        features: RasterFeatures,
        raster: impl FnOnce(&mut Self) -> Result<()>,
    ) -> Result<()> {
        self.build_stages(gpu_scene, &features)?;
        let current = std::mem::replace(&mut self.features, features);
        let built = raster(self);
        self.features = current;
        built
    }

    /// Builds now the stages of frames whose lists hold 2^`slab_bits` slabs, with these
    /// features otherwise, so that a later move there builds nothing.
    pub fn prebuild_stages(&mut self, gpu_scene: &GpuScene, slab_bits: u32) -> Result<()> {
        let features = RasterFeatures {
            slab_bits,
            ..self.features
        };
        self.build_stages(gpu_scene, &features)
    }

    /// The stages' pipelines for `features`, built unless built before (kept by the cache).
    fn build_stages(&mut self, gpu_scene: &GpuScene, features: &RasterFeatures) -> Result<()> {
        let layouts = [&gpu_scene.layout, &self.resources.layout];
        StagePipelines::select(&mut self.cache, &self.gpu, &layouts, features).map(drop)
    }

    /// Bands recorded per frame.
    pub fn bands(&self) -> u32 {
        if self.single_band {
            1
        } else {
            self.bands
        }
    }

    /// Render width and height in pixels.
    pub fn size(&self) -> (u32, u32) {
        (self.push.width, self.push.height)
    }

    /// A raster pipeline over the bins' descriptor sets and push constants, built unless it
    /// was before: `shader`'s variant that samples textures as the features say, with the
    /// assets' texture array as set 2 where it samples in hardware.
    pub fn pipeline(
        &mut self,
        gpu_scene: &GpuScene,
        shader: RasterShader,
        constants: &Specialization,
    ) -> Result<Arc<ComputePipeline>> {
        let mut layouts = vec![&gpu_scene.layout, &self.resources.layout];
        let spirv = if self.features.hardware_sampling {
            let array = gpu_scene.texture_array().ok_or_else(|| {
                Error::Internal("hardware sampling without a texture array".into())
            })?;
            layouts.push(&array.layout);
            shader.hardware_sampled
        } else {
            shader.software
        };
        self.cache.get(&self.gpu, &layouts, spirv, constants)
    }

    /// Takes the frame `f` describes; whether the features changed (the raster's pipelines
    /// must follow).
    pub fn set_frame(&mut self, f: &FrameSetup<'_>) -> Result<bool> {
        let (width, height) = (f.targets.extent.width, f.targets.extent.height);
        self.push.set_size(width, height);
        self.push.set_slices(&self.features, self.slice_rows_limit);
        self.resources.use_slot(f.slot);
        self.resources
            .set_frame(f.gpu, f.scene, f.gpu_scene, f.targets)?;
        self.push.item_count = f.gpu_scene.transparent_quads;
        self.push.draw_count = f.scene.transparent.len() as u32;
        // Setup writes at most two triangles per quad, and homogeneous records for at most
        // the triangles of draws that leave the fixed-point path.
        let triangles = f.gpu_scene.transparent_quads.saturating_mul(2);
        // Meshes added since (the renderer adopted extended assets).
        let known = self.meshes.len();
        self.meshes
            .extend(f.scene.meshes[known..].iter().map(MeshFacts::of));
        if !f.gpu_scene.moved_meshes().is_empty() {
            self.single_band = false;
            self.first_after_move = self.recordings;
        }
        for &moved in f.gpu_scene.moved_meshes() {
            self.meshes[moved].bounds = features::bounds(&f.scene.meshes[moved].positions);
        }
        // Triangles that may take the near-plane path: the records' bound and the feature.
        let near_plane = features::homogeneous_triangles(f.scene, &self.meshes, width, height);
        let homogeneous = homogeneous_bound(&self.most, near_plane);
        let subgroups = self.gpu.info().into();
        let mut fresh = RasterFeatures::of_frame(f.scene, &self.meshes, near_plane, subgroups);
        fresh.homogeneous =
            (fresh.homogeneous && !self.fixed_path_forced) || self.homogeneous_missed;
        let mut features = self.features.for_frame(fresh.covering(&self.declared));
        if self.prepared && !self.declared.covers(&DeclaredContent::of_features(&fresh)) {
            if !self.superset_drawn {
                log::warn!(
                    "{}: a frame draws content past what the loop declared; it and such \
                     frames after it draw with the superset variant, slower (declare the \
                     content to draw them with their own)",
                    self.method
                );
                self.superset_drawn = true;
            }
            features = features.superset();
        }
        features.hardware_sampling = sampling(
            self.gpu.info(),
            self.hardware_sampling_forced,
            f.gpu_scene,
            f.scene,
        );
        // Draws that joined may need more of each quad's attributes (a first textured draw).
        let attribute_texels = features.attribute_texels();
        let capacities = self.resources.capacities;
        // Transparent content a quarter past what the lists were last sized for (streamed
        // in, draws joining): sized now from the host's estimate, as the first frame was, so
        // that the frame is right on its first recording also when the frames in flight
        // before it cannot have counted it.
        let quads = f.gpu_scene.transparent_quads;
        let mut bin_entries = capacities.bin_entries;
        if quads
            > self
                .estimated_quads
                .saturating_add(self.estimated_quads / 4)
        {
            let expected = features::estimate(f.scene, width, height);
            self.estimated_quads = quads;
            bin_entries = Capacities::expected_bin_entries(quads, &expected)
                .min(self.most.bin_entries)
                .max(bin_entries);
        }
        if triangles > capacities.triangles
            || homogeneous > capacities.homogeneous
            || attribute_texels > capacities.attribute_texels
            || bin_entries > capacities.bin_entries
        {
            // A quarter to spare: draws and meshes added one after another regrow rarely.
            let with_room = |needed: u32, now: u32| {
                if needed > now {
                    needed.saturating_add(needed / 4)
                } else {
                    now
                }
            };
            let grown = Capacities {
                triangles: with_room(triangles, capacities.triangles),
                homogeneous: with_room(homogeneous, capacities.homogeneous),
                attribute_texels: attribute_texels.max(capacities.attribute_texels),
                bin_entries,
                ..capacities
            };
            self.resources
                .grow(f.gpu, grown)
                .map_err(|e| in_errors(self.method, e))?;
        }
        let features = features.with_records(
            self.resources.records_pass_a_binding(f.gpu),
            self.texel_walk_forced,
        );
        let changed = features != self.features;
        if changed {
            self.select(f.gpu_scene, features)?;
        }
        Ok(changed)
    }

    /// Makes `features` the frames' from now on, the stages' pipelines built unless made
    /// before.
    fn select(&mut self, gpu_scene: &GpuScene, features: RasterFeatures) -> Result<()> {
        // set_frame grows the records for what the frame's shading reads; nothing after it
        // changes that.
        debug_assert!(features.attribute_texels() <= self.resources.capacities.attribute_texels);
        let layouts = [&gpu_scene.layout, &self.resources.layout];
        self.stages = StagePipelines::select(&mut self.cache, &self.gpu, &layouts, &features)?;
        self.features = features;
        self.push.set_slices(&features, self.slice_rows_limit);
        Ok(())
    }

    /// Records the frame up to its bands: counters reset, the targets moved to the raster's
    /// layouts, the depth pyramid, setup, the bin count and scan, and the list of blocks.
    pub fn record_binning(&mut self, ctx: &mut RecordContext<'_>) -> Result<()> {
        let cmd = ctx.cmd;
        self.resources.use_slot(ctx.slot);
        // Buffers grown after the last frame, or another opaque depth: the slot's set names
        // the new ones.
        let depth = match &ctx.in_place {
            Some(engine) => engine.depth,
            None => ctx.targets.depth.view,
        };
        self.push.opaque_depth_reversed = ctx.in_place.is_some_and(|e| e.reversed).into();
        // The frame's corner in the engine's images (both hold it at the same place).
        let origin = ctx
            .in_place
            .map_or(vk::Offset2D::default(), |e| e.colour.origin);
        (self.push.opaque_depth_x, self.push.opaque_depth_y) = (origin.x as u32, origin.y as u32);
        if ctx.in_place.is_some() {
            self.make_layer()?;
        }
        self.resources.refresh_set(depth, ctx.in_place.is_some())?;
        self.resources.retirement.recorded();
        let culled = self.unculled_frames == 0;
        self.unculled_frames = self.unculled_frames.saturating_sub(1);
        self.recorded[ctx.slot] = Recorded {
            features: self.features,
            capacities: self.resources.capacities,
            culled,
            size: self.size(),
            clears_layer: false,
            bands: self.bands(),
            recording: self.recordings,
            rows_per_slice: self.push.bin_rows_per_slice,
        };
        self.recordings += 1;
        self.begin_submission(cmd, ctx.slot, ctx.in_place.is_some());
        self.resources.record_reset(cmd, self.features.rows);
        // Setup's occlusion cull reads the opaque depth (through the pyramid), as does the
        // raster's depth test.
        self.targets_to_raster(ctx, OPAQUE_PASS_WRITES);
        let cells = self.push.bins_x * self.push.bins_y;
        let s = &self.stages;
        if culled {
            self.dispatch(
                ctx,
                &s.depth_pyramid,
                [cells.div_ceil(PYRAMID_GROUP_SIZE), 1, 1],
            );
            self.compute_to_compute(cmd);
        }
        ctx.timestamps.mark(cmd, "depth pyramid");

        let items = self.push.item_count;
        if items > 0 {
            let setup = if culled { &s.setup } else { &s.setup_unculled };
            let groups = items.div_ceil(layout::BINNING_GROUP_SIZE);
            let (x, z) = split_groups(groups, self.push.groups_x);
            self.dispatch(ctx, setup, [x, 1, z]);
        }
        self.compute_to_compute(cmd);
        ctx.timestamps.mark(cmd, "setup");

        if let Some(histogram) = &s.slab_histogram {
            self.dispatch_indirect(ctx, histogram, DISPATCH_BINNING_OFFSET, &self.push);
            self.compute_to_compute(cmd);
            ctx.timestamps.mark(cmd, "slab plan");
        }
        self.dispatch_indirect(ctx, &s.bin_count, DISPATCH_BINNING_OFFSET, &self.push);
        self.compute_to_compute(cmd);
        ctx.timestamps.mark(cmd, "bin count");
        // The frame's blocks, in whole workgroups (the arrays are padded for the largest). It
        // lists them and plans the first band too (the resume lists are empty).
        let scan_groups = cells.div_ceil(SCAN_GROUP_SIZE);
        let first_band = BinPush {
            resume_list: 0,
            ..self.push
        };
        self.dispatch_with(ctx, &s.block_scan, &first_band, [scan_groups, 1, 1]);
        self.compute_to_compute(cmd);
        Ok(())
    }

    /// One band's bins: its plan (band_plan.comp; the block scan planned the first), its
    /// bins' offsets and its fill, ready for the raster. `pending_list` is the resume list the raster suspends rows
    /// onto: the plan empties it when the band has blocks (the last band's unfinished rows
    /// are abandoned, counted as degraded). The first band's stages are timed on their own.
    pub fn record_band(&self, ctx: &mut RecordContext<'_>, first: bool, pending_list: u32) {
        let cmd = ctx.cmd;
        let stages = &self.stages;
        let push = BinPush {
            resume_list: pending_list,
            ..self.push
        };
        // The scan planned the first band.
        if !first {
            self.dispatch_with(ctx, &stages.band_plan, &push, [1, 1, 1]);
            self.compute_to_compute(cmd);
        }
        self.dispatch_indirect(
            ctx,
            &stages.bin_offsets,
            DISPATCH_BIN_OFFSETS_OFFSET,
            &self.push,
        );
        self.compute_to_compute(cmd);
        if first {
            ctx.timestamps.mark(cmd, "bin scan");
        }
        self.dispatch_indirect(
            ctx,
            &self.stages.bin_fill,
            DISPATCH_BAND_FILL_OFFSET,
            &self.push,
        );
        self.compute_to_compute(cmd);
        if first {
            ctx.timestamps.mark(cmd, "bin fill");
        }
    }

    /// The sets a raster binds: the scene's, the bins', and the texture array where it
    /// samples in hardware (the frame slot's, which set_frame found there and which the slot
    /// keeps alive: `GpuScene::texture_array`).
    fn raster_sets(&self, ctx: &RecordContext<'_>) -> Vec<vk::DescriptorSet> {
        let mut sets = vec![ctx.gpu_scene.set().raw, self.resources.set()];
        if self.features.hardware_sampling {
            let array = ctx.gpu_scene.texture_array();
            debug_assert!(array.is_some(), "hardware sampling without a texture array");
            sets.extend(array.map(|a| a.set.raw));
        }
        sets
    }

    /// `raster` over the band's blocks (the indirect command its plan wrote), suspending rows
    /// onto resume list `suspend_to`.
    pub fn record_raster(
        &self,
        ctx: &RecordContext<'_>,
        raster: &ComputePipeline,
        suspend_to: u32,
    ) {
        // A raster appends to the list after the one it is pushed (the one it would resume).
        let push = BinPush {
            resume_list: suspend_to ^ 1,
            ..self.push
        };
        raster.dispatch_indirect(
            ctx.cmd,
            &self.raster_sets(ctx),
            bytemuck::bytes_of(&push),
            self.resources.dispatches(),
            DISPATCH_RASTER_BINS_OFFSET,
        );
    }

    /// `raster` over the rows on resume list `list`, one workgroup each (counted on the GPU),
    /// after the compute work before.
    pub fn record_resumed(&self, ctx: &RecordContext<'_>, raster: &ComputePipeline, list: u32) {
        self.compute_to_compute(ctx.cmd);
        let push = BinPush {
            resume_list: list,
            ..self.push
        };
        raster.dispatch_indirect(
            ctx.cmd,
            &self.raster_sets(ctx),
            bytemuck::bytes_of(&push),
            self.resources.dispatches(),
            u64::from(list) * 16,
        );
    }

    /// Empties resume list `list` after the compute work before, for the dispatches after.
    pub fn record_resume_list_empty(&self, cmd: vk::CommandBuffer, list: u32) {
        let compute = vk::PipelineStageFlags::COMPUTE_SHADER;
        let rw = vk::AccessFlags::SHADER_READ | vk::AccessFlags::SHADER_WRITE;
        let transfer = (
            vk::PipelineStageFlags::TRANSFER,
            vk::AccessFlags::TRANSFER_WRITE,
        );
        let to_next = (
            compute | vk::PipelineStageFlags::DRAW_INDIRECT,
            rw | vk::AccessFlags::INDIRECT_COMMAND_READ,
        );
        memory_barrier(&self.gpu, cmd, (compute, rw), transfer);
        self.resources.record_resume_list_reset(cmd, list);
        memory_barrier(&self.gpu, cmd, transfer, to_next);
    }

    /// Ends a frame's recording: on an engine's device, the composite of what its rasters
    /// left onto the engine's colour, timed as "composite"; notes which resume list holds the
    /// rows left unfinished, returns the frame targets to their attachment layouts and
    /// copies the counters for the host.
    pub fn record_end(&mut self, ctx: &mut RecordContext<'_>, pending_list: u32) -> Result<()> {
        self.resources.set_pending_list(pending_list);
        let cmd = ctx.cmd;
        let shader = (
            vk::PipelineStageFlags::COMPUTE_SHADER,
            vk::AccessFlags::SHADER_READ | vk::AccessFlags::SHADER_WRITE,
        );
        let after = (
            vk::PipelineStageFlags::ALL_COMMANDS,
            vk::AccessFlags::MEMORY_READ | vk::AccessFlags::MEMORY_WRITE,
        );
        let colour = &ctx.targets.colour;
        let (general, attachment) = (
            vk::ImageLayout::GENERAL,
            vk::ImageLayout::COLOR_ATTACHMENT_OPTIMAL,
        );
        image_barrier(&self.gpu, cmd, colour, general, attachment, shader, after);
        if let Some(engine) = &ctx.in_place {
            self.record_composite(ctx.cmd, &engine.colour, ctx.slot, ctx.targets.extent)?;
            ctx.timestamps.mark(cmd, "composite");
        } else {
            let depth = &ctx.targets.depth;
            let (sampled, attachment) = (
                vk::ImageLayout::SHADER_READ_ONLY_OPTIMAL,
                vk::ImageLayout::DEPTH_STENCIL_ATTACHMENT_OPTIMAL,
            );
            image_barrier(&self.gpu, cmd, depth, sampled, attachment, shader, after);
        }
        self.resources.record_readback(cmd);
        Ok(())
    }

    /// The composite (`composite.rs`) of this submission's transparent layer onto `colour`.
    fn record_composite(
        &mut self,
        cmd: vk::CommandBuffer,
        colour: &crate::gpu::HostImage,
        slot: usize,
        extent: vk::Extent2D,
    ) -> Result<()> {
        // The transparent layer the rasters wrote, and the draw command the scan did.
        memory_barrier(
            &self.gpu,
            cmd,
            (
                vk::PipelineStageFlags::COMPUTE_SHADER,
                vk::AccessFlags::SHADER_WRITE,
            ),
            (
                vk::PipelineStageFlags::VERTEX_SHADER
                    | vk::PipelineStageFlags::FRAGMENT_SHADER
                    | vk::PipelineStageFlags::DRAW_INDIRECT,
                vk::AccessFlags::SHADER_READ | vk::AccessFlags::INDIRECT_COMMAND_READ,
            ),
        );
        let slots = self.recorded.len();
        let composite = made_composite(&mut self.composite, &self.gpu, &self.resources, slots)?;
        let frame = composite::CompositeFrame {
            colour,
            slot,
            extent,
            stamp: self.stamp,
            bins_x: self.push.bins_x,
            draw: (self.resources.dispatches(), DRAW_COMPOSITE_OFFSET),
        };
        composite.record(cmd, &frame)
    }

    /// Builds now the composite onto colour images like `colour` (format and layouts), which
    /// the first frame onto one would build.
    pub fn prepare_composite(&mut self, colour: &crate::gpu::HostImage) -> Result<()> {
        // The composite's set names the transparent layer, which is made first.
        self.make_layer()?;
        let slots = self.recorded.len();
        let composite = made_composite(&mut self.composite, &self.gpu, &self.resources, slots)?;
        composite.pass_for(colour).map(|_| ())
    }

    /// Makes the transparent layer that frames on an engine's device leave for the
    /// composite, once; a new one is cleared before it is used.
    fn make_layer(&mut self) -> Result<()> {
        if self.resources.make_layer(&self.gpu)? {
            self.layer_cleared = false;
        }
        Ok(())
    }

    /// Starts a submission of the frame in `slot`: on an engine's device (`in_place`), its
    /// stamp, which the rasters write with what they leave and the composite blends; else
    /// stamp 0, compositing onto the frame target. Until a frame that cleared the transparent
    /// layer has completed (one recorded may be abandoned), every submission clears it first
    /// (its stamps to none, and both images into the layout the sets name), so that nothing
    /// the images held before passes for a pixel; and again each time the stamps start again
    /// from 1 (every LAST_STAMP submissions).
    fn begin_submission(&mut self, cmd: vk::CommandBuffer, slot: usize, in_place: bool) {
        if in_place {
            self.stamp = if self.stamp >= LAST_STAMP {
                1
            } else {
                self.stamp + 1
            };
            if self.stamp == 1 {
                self.layer_cleared = false;
            }
        }
        let clears = !self.layer_cleared;
        if clears {
            self.resources.record_layer_clear(cmd);
        }
        let slots = self.recorded.len();
        self.recorded[slot % slots].clears_layer = clears;
        self.push.stamp = if in_place { self.stamp } else { 0 };
    }

    /// Moves the frame targets to the layouts the stages use (colour written as a storage
    /// image, depth sampled); `since` is the access that last wrote them. (The engine's
    /// images, used in place, are the renderer's to move.)
    pub fn targets_to_raster(
        &self,
        ctx: &RecordContext<'_>,
        since: (vk::PipelineStageFlags, vk::AccessFlags),
    ) {
        let shader = (
            vk::PipelineStageFlags::COMPUTE_SHADER,
            vk::AccessFlags::SHADER_READ | vk::AccessFlags::SHADER_WRITE,
        );
        // In place, the frame target's colour is bound but neither read nor written: what
        // it held goes.
        let colour_layout = if ctx.in_place.is_some() {
            vk::ImageLayout::UNDEFINED
        } else {
            vk::ImageLayout::COLOR_ATTACHMENT_OPTIMAL
        };
        image_barrier(
            &self.gpu,
            ctx.cmd,
            &ctx.targets.colour,
            colour_layout,
            vk::ImageLayout::GENERAL,
            since,
            shader,
        );
        if ctx.in_place.is_some() {
            return;
        }
        image_barrier(
            &self.gpu,
            ctx.cmd,
            &ctx.targets.depth,
            vk::ImageLayout::DEPTH_STENCIL_ATTACHMENT_OPTIMAL,
            vk::ImageLayout::SHADER_READ_ONLY_OPTIMAL,
            since,
            shader,
        );
    }

    /// Makes one stage's writes visible to the next, including the indirect dispatch
    /// commands the scan and the raster write.
    pub fn compute_to_compute(&self, cmd: vk::CommandBuffer) {
        let stage = vk::PipelineStageFlags::COMPUTE_SHADER;
        let rw = vk::AccessFlags::SHADER_READ | vk::AccessFlags::SHADER_WRITE;
        let next = (
            stage | vk::PipelineStageFlags::DRAW_INDIRECT,
            rw | vk::AccessFlags::INDIRECT_COMMAND_READ,
        );
        memory_barrier(&self.gpu, cmd, (stage, rw), next);
    }

    fn dispatch(&self, ctx: &RecordContext<'_>, p: &ComputePipeline, groups: [u32; 3]) {
        self.dispatch_with(ctx, p, &self.push, groups);
    }

    fn dispatch_with(
        &self,
        ctx: &RecordContext<'_>,
        p: &ComputePipeline,
        push: &BinPush,
        groups: [u32; 3],
    ) {
        p.dispatch(
            ctx.cmd,
            &[ctx.gpu_scene.set().raw, self.resources.set()],
            bytemuck::bytes_of(push),
            groups,
        );
    }

    /// `p` with the workgroups of the indirect command at `offset`.
    fn dispatch_indirect(
        &self,
        ctx: &RecordContext<'_>,
        p: &ComputePipeline,
        offset: u64,
        push: &BinPush,
    ) {
        p.dispatch_indirect(
            ctx.cmd,
            &[ctx.gpu_scene.set().raw, self.resources.set()],
            bytemuck::bytes_of(push),
            self.resources.dispatches(),
            offset,
        );
    }

    /// How the frame in `slot` was binned and its raster specialized (but for the raster's
    /// own selection, which it adds).
    pub fn shape(&self, slot: usize) -> super::BinShape {
        let recorded = &self.recorded[slot % self.recorded.len()];
        super::BinShape {
            select_size: 0,
            slabs: recorded.features.slabs(),
            tile_rows: 1 << recorded.features.tile_shift,
            rows_per_workgroup: recorded.features.rows,
            rows_per_slice: recorded.rows_per_slice,
            loop_budget: recorded.features.loop_budget,
            branching: recorded.features.branching,
            storage_walk: recorded.features.storage_walk,
            hardware_sampling: recorded.features.hardware_sampling,
            // Frames of several slabs do not tally (bin_tally.glsl).
            tally_slots: match recorded.features.bin_tally_bits {
                0 => 0,
                _ if recorded.features.slab_bits > 0 => 0,
                bits => 1 << bits,
            },
        }
    }

    /// The counters of the completed frame in `slot`.
    pub fn counters(&self, slot: usize) -> Result<BinCounters> {
        self.resources.counters(slot)
    }

    /// Whether the completed frame had a row whose list was too long for one pass of the
    /// raster's loop budget.
    pub fn crowded(&self, slot: usize) -> Result<bool> {
        Ok(self.counters(slot)?.overflow & OVERFLOW_CROWDED_BIN != 0)
    }

    /// Rows the completed frame in `slot` left on its pending resume list.
    pub fn unfinished_rows(&self, slot: usize) -> Result<u32> {
        self.resources.unfinished_rows(slot)
    }

    /// The starting capacities a renderer for the next, similar frame should take.
    pub fn learned(&self, options: &mut BinOptions) {
        let c = self.resources.capacities;
        options.initial_bin_entries = Some(c.bin_entries);
        options.initial_homogeneous = Some(c.homogeneous);
        options.initial_resume_rows = Some(c.resume);
    }

    /// The newest `frames` recorded will never run: see [`Method::frames_abandoned`].
    pub fn frames_abandoned(&mut self, frames: u64) {
        self.resources.retirement.abandoned(frames);
    }

    /// Reads the completed frame's counters: grows the buffers for later frames and moves the
    /// features to what later frames need (`slab_bits` says how many depth slabs the raster
    /// wants lists ordered by, from the counters and the size the frame was recorded at).
    pub fn frame_done(
        &mut self,
        done: &FrameDone<'_>,
        slab_bits: impl FnOnce(&BinCounters, (u32, u32)) -> u32,
    ) -> Result<BinsDone> {
        self.resources.retirement.completed();
        let counters = self.counters(done.slot)?;
        // Judged by what the frame was recorded with; fixes go to the current settings.
        let recorded = self.recorded[done.slot % self.recorded.len()];
        self.layer_cleared |= recorded.clears_layer;
        let method = self.method;
        // (With frames in flight, later frames may have another size.)
        let mut features = RasterFeatures {
            slab_bits: slab_bits(&counters, recorded.size),
            ..self.features
        };
        // The host's estimate missed a near-plane triangle: the frame needs the full shaders.
        let rebuild = counters.homogeneous_count > 0 && !recorded.features.homogeneous;
        features.homogeneous |= rebuild;
        self.homogeneous_missed |= rebuild;
        if rebuild && self.prepared && !self.declared.near_plane {
            // Past the declaration: the superset, built up front, rather than a variant of
            // its own; its records grown now, as set_frame grows them, for a frame rendered
            // again without another set_frame.
            features = features.superset();
            let texels = features.attribute_texels();
            let capacities = self.resources.capacities;
            if texels > capacities.attribute_texels {
                let grown = Capacities {
                    attribute_texels: texels,
                    ..capacities
                };
                self.resources
                    .grow(&self.gpu, grown)
                    .map_err(|e| in_errors(method, e))?;
            }
            features = features.with_records(
                self.resources.records_pass_a_binding(&self.gpu),
                self.texel_walk_forced,
            );
        }
        let features_changed = features != self.features;
        if features_changed {
            self.select(done.gpu_scene, features)?;
        }
        let cells = self.push.bins_x * self.push.bins_y;
        if recorded.culled
            && counters
                .occluded_blocks
                .saturating_mul(OCCLUSION_BLOCKS_PER_CELL)
                < cells
        {
            self.unculled_frames = OCCLUSION_REST;
        }
        // Lists past their capacity were rasterized in bands, and rows with no state slot
        // started over: right, unless some blocks were left untouched (degraded). Missing
        // homogeneous records (past one buffer's worth) lose triangles, and so would a band
        // whose lists did not fit (the frame's entry count past 2^32).
        let overflowed = counters.overflow & (OVERFLOW_HOMOGENEOUS | OVERFLOW_BAND_LISTS) != 0;
        if counters.overflow & OVERFLOW_HOMOGENEOUS != 0
            && recorded.capacities.homogeneous >= self.most.homogeneous
        {
            // No larger buffer can be made: rendering again would lose the same triangles.
            return Err(Error::TooLarge(format!(
                "{method}: the frame has {} transparent triangles crossing the near plane; \
                 their records fit at most {} ({} bytes each in one storage binding). Move the \
                 near plane, or draw fewer of them",
                counters.homogeneous_count,
                self.most.homogeneous,
                layout::HOMOGENEOUS_BYTES
            )));
        }
        let degraded_rows = counters.degraded_rows();
        let grown =
            self.resources
                .capacities
                .grown_for(&counters, &recorded.capacities, &self.most);
        if let Some(grown) = grown {
            log::info!(
                "{method}: buffers too small (overflow bits {:#x}: {} homogeneous triangles, \
                 {} bin entries, {} resume state slots needed); growing to {grown:?}",
                counters.overflow,
                counters.homogeneous_count,
                counters.bin_entry_count,
                counters.resume_needed
            );
            self.resources
                .grow(&self.gpu, grown)
                .map_err(|e| in_errors(method, e))?;
        }
        self.resources.set_slabs(&self.gpu, self.features.slabs())?;
        // Half the capacity to spare: the next frames may bin more.
        self.single_band = !self.bands_fixed
            && !self.gpu.is_host_device()
            && recorded.recording >= self.first_after_move
            && counters.bands <= 1
            && degraded_rows == 0
            && resources::fits_with_room(
                counters.bin_entry_count,
                self.resources.capacities.bin_entries,
            );
        if degraded_rows > 0 {
            log::warn!(
                "{method}: {degraded_rows} pixel rows left with the opaque colour: blocks past \
                 {} bands of {} bin entries ({} needed), or rows a band left unfinished ({})",
                recorded.bands,
                recorded.capacities.bin_entries,
                counters.bin_entry_count,
                counters.abandoned_rows
            );
        }
        Ok(BinsDone {
            counters,
            features_changed,
            grown: grown.is_some(),
            rerender: rebuild || overflowed || degraded_rows > 0,
            degraded_rows,
        })
    }
}

/// A limit `e` the bins' resources hit, said as `method`'s.
fn in_errors(method: &str, e: Error) -> Error {
    match e {
        Error::TooLarge(message) => Error::TooLarge(format!("{method}: {message}")),
        other => other,
    }
}

/// The bins' composite, made on first use (only frames on an engine's device composite).
fn made_composite<'a>(
    composite: &'a mut Option<composite::Composite>,
    gpu: &Gpu,
    resources: &Resources,
    slots: usize,
) -> Result<&'a mut composite::Composite> {
    let composite_pass = match composite.take() {
        Some(c) => c,
        None => composite::Composite::new(
            gpu,
            &resources.raster_bins,
            &resources.transparent_layer,
            slots,
        )?,
    };
    Ok(composite.insert(composite_pass))
}
