//! `exact`: the compute bin rasterizer. Every pixel composites exactly the fragments the CPU
//! reference does, in the same order, under the same raster rules.
//!
//! Stages (one compute shader each, `shaders/exact/`):
//! 0. `depth_pyramid`: the farthest opaque depth per 8×8 block and over ever larger cells.
//! 1. `setup`: per transparent quad, transform, set up its triangles (fixed-point or
//!    homogeneous), cull (back faces, off screen, wholly behind the opaque layer by the
//!    pyramid), append visible triangles. Binning runs for as many triangles as setup kept
//!    (an indirect dispatch setup sizes).
//! 2. `bin_count`, `bin_scan`, `bin_fill`: per bin (one row of an 8×8-pixel block), count the
//!    triangles that may cover it, prefix-sum the counts, fill the per-bin triangle lists
//!    (per band, with the raster: see below).
//!    Frames with many fragments per pixel order each list by depth slab (nearest vertex).
//! 3. `raster`: one workgroup per block with triangles, one invocation per pixel; each pixel
//!    selects its nearest remaining fragments in registers, composites them front to back
//!    over the opaque colour, and repeats until none is left (or transmittance is under the
//!    threshold). On slab-ordered lists a row's walk ends once every pixel holds fragments
//!    nearer than the next slab, and starts past the slabs its pixels have composited. Rows
//!    of pixels that reach the driver's loop budget are saved where they stopped (even
//!    inside one slab's part of a list, with their selections) and finished by continuation
//!    dispatches of the same shader, sized on the GPU (indirect dispatch).
//!
//! Why this shape: on lavapipe (subgroups of 8, 32 KB shared memory) barrier-heavy
//! shared-memory phases cost more than blending itself, fixed-size register work is cheap, an
//! `if` runs both its sides, and data read in loops is cheapest through texel views
//! (`docs/performance-log.md`). Selection by key (view depth, draw, quad, triangle) is exact by
//! construction, so no pixel can come out of order and no fallback path is needed.
//!
//! Memory is sized from the frame: two triangle records per quad at most, bin lists grown to
//! what the GPU counted. A frame whose lists pass their capacity is right all the same: the
//! scan lists the blocks in order and the frame is filled and rasterized in bands of blocks
//! whose lists fit, one after another in the same command buffer (up to `BANDS`; bands
//! without blocks are near-empty dispatches, and their continuations keep resuming the last
//! band's rows). Suspended rows always find room on the resume lists; those that find no
//! slot for their pixels' state start over when resumed. Counters come back every frame and
//! grow the buffers for later frames. What one recording cannot answer leaves pixels
//! untouched, never drawn from truncated work: blocks past the last band (rendered again
//! when translucid submits; reported on an engine's device), and rows still unfinished after
//! the last continuation (finished by a further submission of continuations, or reported).
//! Homogeneous records past one buffer's worth lose triangles (rendered again, or reported).

#![deny(clippy::unwrap_used)]

pub mod features;
pub mod layout;
pub(crate) mod resources;

use super::{FrameCheck, FrameDone, FrameSetup, Method, MethodOptions, RecordContext};
use crate::assets::GpuScene;
use crate::frame::FrameTargets;
use crate::gpu::{image_barrier, memory_barrier, vk, ComputePipeline, ComputePipelineCache, Gpu};
use crate::scene::Scene;
use crate::{Error, Result};
use features::{MeshFacts, RasterFeatures};
use layout::{
    ExactPush, BIN_SIZE, DISPATCH_BAND_FILL_OFFSET, DISPATCH_BINNING_OFFSET,
    DISPATCH_BIN_OFFSETS_OFFSET, DISPATCH_RASTER_BINS_OFFSET, LOOP_BUDGET, OVERFLOW_BAND_LISTS,
    OVERFLOW_CROWDED_BIN, OVERFLOW_HOMOGENEOUS,
};
use resources::{Capacities, Resources};
use std::sync::Arc;

const STAGES: [(&str, &[u8]); 6] = [
    ("setup", crate::spirv!("exact/setup.comp")),
    ("bin_count", crate::spirv!("exact/bin_count.comp")),
    ("bin_scan", crate::spirv!("exact/bin_scan.comp")),
    ("bin_fill", crate::spirv!("exact/bin_fill.comp")),
    ("raster", crate::spirv!("exact/raster.comp")),
    ("depth_pyramid", crate::spirv!("exact/depth_pyramid.comp")),
];

/// What the raster stage computes from each row's list.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum RasterProgram {
    /// This method: every pixel selects and composites its fragments in order.
    Exact,
    /// The wavelet method's bin raster (`shaders/wavelet/bins_rank<N>.comp`): its SPIR-V and
    /// the constants it takes after the raster's own (constant_id 8 on). Its rows are not
    /// resumed by continuations, and it keeps the shallow frames' settings.
    Wavelet {
        spirv: &'static [u8],
        constants: [u32; 6],
    },
}

impl RasterProgram {
    /// The method's name, in errors.
    fn method(&self) -> &'static str {
        match self {
            Self::Exact => "exact",
            Self::Wavelet { .. } => "wavelet",
        }
    }

    /// A limit `e` the stages' resources hit, said as the method's (wavelet's bins share
    /// them).
    fn in_errors(&self, e: Error) -> Error {
        match e {
            Error::InvalidScene(message) => {
                Error::InvalidScene(format!("{}: {message}", self.method()))
            }
            other => other,
        }
    }

    /// The timestamp after the raster.
    fn stage(&self) -> &'static str {
        match self {
            Self::Exact => "raster",
            Self::Wavelet { .. } => "wavelet raster",
        }
    }
}

pub struct Exact {
    gpu: Gpu,
    program: RasterProgram,
    resources: Resources,
    /// Every stage variant built so far, by specialization.
    cache: ComputePipelineCache,
    /// The variants this frame's features need.
    stages: StagePipelines,
    /// Continuation dispatches recorded after the raster; multiplied when some row was still
    /// unfinished after the last one.
    continuations: u32,
    /// The resume list holding the rows the last submission left unfinished.
    pending_list: u32,
    /// Bands of bins recorded per frame.
    bands: u32,
    /// What the features need of each mesh, its bounds kept up with moved vertices.
    meshes: Vec<MeshFacts>,
    push: ExactPush,
    /// The constants the stage pipelines are specialized with.
    features: RasterFeatures,
    /// Tests start without the near-plane path whatever the frame (MethodOptions).
    fixed_path_forced: bool,
    /// The GPU found a near-plane triangle the host's estimate missed: later frames keep the
    /// near-plane path rather than render again.
    homogeneous_missed: bool,
    /// Per frame slot, what its last frame was recorded with: with frames in flight, the
    /// settings may have moved on by the time that frame completes.
    recorded: Vec<Recorded>,
}

/// The settings a frame was recorded with.
#[derive(Clone, Copy, Debug)]
struct Recorded {
    features: RasterFeatures,
    continuations: u32,
    capacities: resources::Capacities,
}

const SETUP: usize = 0;
const BIN_COUNT: usize = 1;
const BIN_SCAN: usize = 2;
const BIN_FILL: usize = 3;
const RASTER: usize = 4;
/// Built twice: level 0 (constant 0 false), then the levels above (true).
const DEPTH_PYRAMID: usize = 5;
/// What last wrote the frame targets before a frame's raster: the opaque pass.
const OPAQUE_PASS_WRITES: (vk::PipelineStageFlags, vk::AccessFlags) = (
    vk::PipelineStageFlags::ALL_GRAPHICS,
    vk::AccessFlags::from_raw(
        vk::AccessFlags::COLOR_ATTACHMENT_WRITE.as_raw()
            | vk::AccessFlags::DEPTH_STENCIL_ATTACHMENT_WRITE.as_raw(),
    ),
);
/// What last touched them before a finishing submission: the previous one, waited for.
const FINISHED_SUBMISSION_WRITES: (vk::PipelineStageFlags, vk::AccessFlags) = (
    vk::PipelineStageFlags::ALL_COMMANDS,
    vk::AccessFlags::from_raw(
        vk::AccessFlags::MEMORY_READ.as_raw() | vk::AccessFlags::MEMORY_WRITE.as_raw(),
    ),
);
/// Bands recorded per frame (MethodOptions::bands for tests). A frame whose bin lists pass their capacity is rasterized in
/// bands of blocks whose lists fit, one after another in the same command buffer, and the
/// lists grow for later frames; a frame needing more than BANDS times the capacity leaves the
/// blocks past the last band untouched (counted, and rendered again when translucid submits).
/// Bands without blocks cost a tiny dispatch and empty indirect ones.
pub const BANDS: u32 = 4;
/// `PYRAMID_GROUP_SIZE` of depth_pyramid.comp.
const PYRAMID_GROUP_SIZE: u32 = 256;
/// With about 60,000 loop iterations each, this many continuations finish any pixel this
/// method can render in reasonable time (10,000 full-screen layers take a few hundred);
/// past it the frame fails with an error. Continuations with no rows cost an empty
/// indirect dispatch.
const MAX_CONTINUATIONS: u32 = 4096;
/// Continuations are multiplied by this when rows were left unfinished: a deep frame finds
/// its count in a few re-renders (1, 8, 64, 512, 4096).
const CONTINUATION_GROWTH: u32 = 8;

/// The pipelines a frame records, for its features.
struct StagePipelines {
    depth_pyramid: Arc<ComputePipeline>,
    /// The depth pyramid shader specialized to build the levels above level 0.
    pyramid_top: Arc<ComputePipeline>,
    setup: Arc<ComputePipeline>,
    bin_count: Arc<ComputePipeline>,
    /// The scan's steps 0 to 3 (constant 0): block sums, block offsets, a band's bin
    /// offsets, a band's plan.
    scan_steps: [Arc<ComputePipeline>; 4],
    bin_fill: Arc<ComputePipeline>,
    raster: Arc<ComputePipeline>,
    /// The raster shader again, specialized to resume suspended rows (exact only).
    continuation: Option<Arc<ComputePipeline>>,
}

impl StagePipelines {
    /// The stages specialized for `features`, from `cache` (built there on first use).
    fn select(
        cache: &mut ComputePipelineCache,
        gpu: &Gpu,
        layouts: &[&crate::gpu::DescriptorLayout],
        features: &RasterFeatures,
        program: &RasterProgram,
    ) -> Result<Self> {
        let mut stage =
            |stage: usize, constants: &[u32]| cache.get(gpu, layouts, STAGES[stage].1, constants);
        // Setup takes the raster's constants 0 to 3, 6 (SLAB_BITS, declared in
        // exact_bins.glsl, which setup includes), 9 and 10, with the same ids; the rest stay
        // at their defaults so that setup is shared by the features that differ only there.
        let mut setup = features.constants(false);
        setup[4..6].fill(0);
        setup[7..9].fill(0);
        let binning = features.binning_constants();
        let scan_step = |n: u32| {
            let mut constants = binning;
            constants[0] = n;
            constants
        };
        let depth_pyramid = stage(DEPTH_PYRAMID, &[0])?;
        let pyramid_top = stage(DEPTH_PYRAMID, &[1])?;
        let setup = stage(SETUP, &setup)?;
        let bin_count = stage(BIN_COUNT, &binning)?;
        let scan_steps = [
            stage(BIN_SCAN, &binning)?,
            stage(BIN_SCAN, &scan_step(1))?,
            stage(BIN_SCAN, &scan_step(2))?,
            stage(BIN_SCAN, &scan_step(3))?,
        ];
        let bin_fill = stage(BIN_FILL, &binning)?;
        let (raster, continuation) = match program {
            RasterProgram::Exact => (
                stage(RASTER, &features.constants(false))?,
                Some(stage(RASTER, &features.constants(true))?),
            ),
            RasterProgram::Wavelet { spirv, constants } => {
                let words: Vec<u32> = features
                    .constants(false)
                    .into_iter()
                    .chain(*constants)
                    .collect();
                (cache.get(gpu, layouts, spirv, &words)?, None)
            }
        };
        Ok(Self {
            depth_pyramid,
            pyramid_top,
            setup,
            bin_count,
            scan_steps,
            bin_fill,
            raster,
            continuation,
        })
    }
}

/// `ExactPush::order_by_z` for `scene`'s camera.
fn orders_by_z(scene: &Scene) -> u32 {
    u32::from(scene.camera.depth_order() == crate::raster::DepthOrder::DeviceZ)
}

/// Homogeneous records a frame with `near_plane` triangles that may take the near-plane path
/// needs, up to what one buffer binds (past that the frame reports the overflow).
fn homogeneous_bound(gpu: &Gpu, near_plane: u64) -> u32 {
    near_plane.min(u64::from(Capacities::most(gpu).homogeneous)) as u32
}

impl Exact {
    pub fn new(
        gpu: &Gpu,
        scene: &Scene,
        uploaded: &GpuScene,
        targets: &FrameTargets,
        options: &MethodOptions,
    ) -> Result<Self> {
        Self::with_program(gpu, scene, uploaded, targets, options, RasterProgram::Exact)
    }

    /// The exact method's stages with `program` as the raster.
    pub fn with_program(
        gpu: &Gpu,
        scene: &Scene,
        uploaded: &GpuScene,
        targets: &FrameTargets,
        options: &MethodOptions,
        program: RasterProgram,
    ) -> Result<Self> {
        let method = program.method();
        let info = gpu.info();
        if !(info.shader_int64 && info.shader_float64) {
            return Err(crate::Error::NoDevice(format!(
                "{} lacks 64-bit shader integers or floats, which the {method} method's edge functions need",
                info.name
            )));
        }
        // The raster runs a workgroup per row of BIN_SIZE pixels and votes, broadcasts and
        // reduces over it: a subgroup must hold a whole row.
        if !info.compute_subgroup_operations || info.subgroup_size < BIN_SIZE {
            return Err(crate::Error::NoDevice(format!(
                "{} has compute subgroups of {} invocations{}; the {method} method needs at least \
                 {BIN_SIZE} with vote, ballot and arithmetic operations",
                info.name,
                info.subgroup_size,
                if info.compute_subgroup_operations {
                    ""
                } else {
                    " without all of vote, ballot and arithmetic"
                }
            )));
        }
        let width = targets.extent.width;
        let height = targets.extent.height;
        if width > 0xFFFF || height > 0xFFFF {
            // Triangle records keep their pixel bounds in 16 bits.
            return Err(crate::Error::InvalidScene(format!(
                "{method}: {width}x{height} is over the 65535 pixels a side it supports"
            )));
        }
        let meshes = MeshFacts::of_scene(scene);
        let near_plane = features::homogeneous_triangles(scene, &meshes, width, height);
        let bins_x = width.div_ceil(BIN_SIZE);
        let bins_y = height.div_ceil(BIN_SIZE);
        let expected = features::estimated_fragments(scene, width, height);
        let capacities = Capacities::initial(
            uploaded.transparent_quads,
            bins_x * bins_y,
            expected,
            homogeneous_bound(gpu, near_plane),
            options,
        );
        let mut features = RasterFeatures::of_frame(scene, &meshes, near_plane, info.subgroup_size);
        features.homogeneous &= !options.assume_fixed_path;
        if program == RasterProgram::Exact {
            features = features.expecting(expected, width, height);
            if options.assume_deep_pixels {
                features = features.deep();
            }
        }
        if options.assume_wide_subgroups {
            features.rows = 1;
        }
        let resources = Resources::new(gpu, scene, uploaded, targets, capacities, features.slabs())
            .map_err(|e| program.in_errors(e))?;
        let layouts = [&uploaded.layout, &resources.layout];
        let mut cache = ComputePipelineCache::new(std::mem::size_of::<ExactPush>() as u32);
        let stages = StagePipelines::select(&mut cache, gpu, &layouts, &features, &program)?;
        let continuations = u32::from(stages.continuation.is_some());
        let push = ExactPush {
            item_count: uploaded.transparent_quads,
            draw_count: scene.transparent.len() as u32,
            width,
            height,
            bins_x,
            bins_y,
            threshold: options.threshold,
            resume_list: 0,
            // A row of bins costs at most bins_x + 1 iterations.
            bin_rows_per_slice: (LOOP_BUDGET / (bins_x + 1))
                .min(options.bin_rows_per_slice.unwrap_or(u32::MAX))
                .max(1),
            order_by_z: orders_by_z(scene),
            pad: [0; 2],
        };
        Ok(Self {
            gpu: gpu.clone(),
            program,
            resources,
            cache,
            stages,
            fixed_path_forced: options.assume_fixed_path,
            homogeneous_missed: false,
            recorded: vec![
                Recorded {
                    features,
                    continuations,
                    capacities,
                };
                uploaded.slot_count()
            ],
            continuations,
            pending_list: 0,
            bands: options.bands.unwrap_or(BANDS).max(1),
            meshes,
            push,
            features,
        })
    }

    /// Makes `program` the raster from the next frame on (the wavelet bins' constants follow
    /// the camera's depth mapping), its pipelines built unless made before.
    pub fn set_program(&mut self, uploaded: &GpuScene, program: RasterProgram) -> Result<()> {
        if program != self.program {
            let layouts = [&uploaded.layout, &self.resources.layout];
            self.stages = StagePipelines::select(
                &mut self.cache,
                &self.gpu,
                &layouts,
                &self.features,
                &program,
            )?;
            self.program = program;
        }
        Ok(())
    }

    /// Whether the completed frame had a row whose list was too long for one pass of the
    /// raster's loop budget (the exact raster then moves to slabs and walks such lists in
    /// parts; a program that cannot may fall back to another method).
    pub fn crowded(&self, slot: usize) -> Result<bool> {
        Ok(self.resources.counters(slot)?.overflow & OVERFLOW_CROWDED_BIN != 0)
    }

    fn dispatch(&self, ctx: &RecordContext<'_>, p: &ComputePipeline, groups: [u32; 3]) {
        p.dispatch(
            ctx.cmd,
            &[ctx.scene.set().raw, self.resources.set()],
            bytemuck::bytes_of(&self.push),
            groups,
        );
    }

    /// `p` with the workgroups of the indirect command at `offset`.
    fn dispatch_indirect(&self, ctx: &RecordContext<'_>, p: &ComputePipeline, offset: u64) {
        p.dispatch_indirect(
            ctx.cmd,
            &[ctx.scene.set().raw, self.resources.set()],
            bytemuck::bytes_of(&self.push),
            self.resources.dispatches(),
            offset,
        );
    }

    /// One band: its plan (bin_scan.comp, step 3), its bins' offsets, its fill, its raster and
    /// continuations. The first band's binning stages are timed on their own.
    fn record_band(&mut self, ctx: &mut RecordContext<'_>, first: bool) {
        let cmd = ctx.cmd;
        let [_, _, write_offsets, plan] = self.stages.scan_steps.clone();
        let bin_fill = self.stages.bin_fill.clone();
        let push = ExactPush {
            resume_list: self.pending_list,
            ..self.push
        };
        plan.dispatch(
            cmd,
            &[ctx.scene.set().raw, self.resources.set()],
            bytemuck::bytes_of(&push),
            [1, 1, 1],
        );
        self.compute_to_compute(cmd);
        self.dispatch_indirect(ctx, &write_offsets, DISPATCH_BIN_OFFSETS_OFFSET);
        self.compute_to_compute(cmd);
        if first {
            ctx.timestamps.mark(cmd, "bin scan");
        }
        self.dispatch_indirect(ctx, &bin_fill, DISPATCH_BAND_FILL_OFFSET);
        self.compute_to_compute(cmd);
        if first {
            ctx.timestamps.mark(cmd, "bin fill");
        }
        // Later bands take one continuation each: they have blocks only in frames past the
        // lists' capacity, and when empty they go on resuming the last band's rows.
        let continuations = if first { self.continuations } else { 1 };
        self.record_raster(ctx, continuations);
        self.compute_to_compute(cmd);
    }

    /// The raster over the band's blocks, then `continuations` continuations. The raster
    /// suspends rows onto the pending list: the band's plan emptied it if the band has
    /// blocks; if not, it holds the rows the last band left, which these continuations go on
    /// resuming.
    fn record_raster(&mut self, ctx: &RecordContext<'_>, continuations: u32) {
        let push = ExactPush {
            resume_list: self.pending_list ^ 1,
            ..self.push
        };
        self.stages.raster.dispatch_indirect(
            ctx.cmd,
            &[ctx.scene.set().raw, self.resources.set()],
            bytemuck::bytes_of(&push),
            self.resources.dispatches(),
            DISPATCH_RASTER_BINS_OFFSET,
        );
        self.record_continuations(ctx, continuations);
    }

    /// `count` continuation dispatches from the pending list: each resumes the rows on one
    /// list (one workgroup each, counted on the GPU) and suspends rows onto the other, which
    /// the next reads.
    fn record_continuations(&mut self, ctx: &RecordContext<'_>, count: u32) {
        let cmd = ctx.cmd;
        let sets = [ctx.scene.set().raw, self.resources.set()];
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
        let Some(continuation) = self.stages.continuation.clone() else {
            return;
        };
        for _ in 0..count {
            let list = self.pending_list;
            self.compute_to_compute(cmd);
            let push = ExactPush {
                resume_list: list,
                ..self.push
            };
            continuation.dispatch_indirect(
                cmd,
                &sets,
                bytemuck::bytes_of(&push),
                self.resources.dispatches(),
                u64::from(list) * 16,
            );
            memory_barrier(&self.gpu, cmd, (compute, rw), transfer);
            self.resources.record_resume_list_reset(cmd, list);
            memory_barrier(&self.gpu, cmd, transfer, to_next);
            self.pending_list = list ^ 1;
        }
    }

    /// Moves the frame targets to the layouts the raster uses (colour written as a storage
    /// image, depth sampled); `since` is the access that last wrote them.
    fn targets_to_raster(
        &self,
        ctx: &RecordContext<'_>,
        since: (vk::PipelineStageFlags, vk::AccessFlags),
    ) {
        let shader = (
            vk::PipelineStageFlags::COMPUTE_SHADER,
            vk::AccessFlags::SHADER_READ | vk::AccessFlags::SHADER_WRITE,
        );
        image_barrier(
            &self.gpu,
            ctx.cmd,
            &ctx.targets.colour,
            vk::ImageLayout::COLOR_ATTACHMENT_OPTIMAL,
            vk::ImageLayout::GENERAL,
            since,
            shader,
        );
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

    /// Returns the frame targets to their attachment layouts after the raster, and makes the
    /// counters visible to the host.
    fn targets_from_raster(&self, ctx: &RecordContext<'_>) {
        let cmd = ctx.cmd;
        let shader = (
            vk::PipelineStageFlags::COMPUTE_SHADER,
            vk::AccessFlags::SHADER_READ | vk::AccessFlags::SHADER_WRITE,
        );
        let after = (
            vk::PipelineStageFlags::ALL_COMMANDS,
            vk::AccessFlags::MEMORY_READ | vk::AccessFlags::MEMORY_WRITE,
        );
        image_barrier(
            &self.gpu,
            cmd,
            &ctx.targets.colour,
            vk::ImageLayout::GENERAL,
            vk::ImageLayout::COLOR_ATTACHMENT_OPTIMAL,
            shader,
            after,
        );
        image_barrier(
            &self.gpu,
            cmd,
            &ctx.targets.depth,
            vk::ImageLayout::SHADER_READ_ONLY_OPTIMAL,
            vk::ImageLayout::DEPTH_STENCIL_ATTACHMENT_OPTIMAL,
            shader,
            after,
        );
        self.resources.record_readback(cmd);
    }

    /// Makes one stage's writes visible to the next, including the indirect dispatch
    /// commands the scan and the raster write.
    fn compute_to_compute(&self, cmd: vk::CommandBuffer) {
        let stage = vk::PipelineStageFlags::COMPUTE_SHADER;
        let rw = vk::AccessFlags::SHADER_READ | vk::AccessFlags::SHADER_WRITE;
        let next = (
            stage | vk::PipelineStageFlags::DRAW_INDIRECT,
            rw | vk::AccessFlags::INDIRECT_COMMAND_READ,
        );
        memory_barrier(&self.gpu, cmd, (stage, rw), next);
    }
}

impl Method for Exact {
    fn name(&self) -> &'static str {
        "exact"
    }

    fn set_frame(&mut self, f: &FrameSetup<'_>) -> Result<()> {
        let (width, height) = (self.push.width, self.push.height);
        self.resources.use_slot(f.slot);
        self.resources
            .set_frame(f.gpu, f.scene, f.uploaded, f.targets)?;
        self.push.item_count = f.uploaded.transparent_quads;
        self.push.draw_count = f.scene.transparent.len() as u32;
        self.push.order_by_z = orders_by_z(f.scene);
        // Setup writes at most two triangles per quad, and homogeneous records for at most
        // the triangles of draws that leave the fixed-point path.
        let triangles = f.uploaded.transparent_quads.saturating_mul(2);
        for &moved in f.moved_meshes {
            self.meshes[moved].bounds = features::bounds(&f.scene.meshes[moved].positions);
        }
        // Triangles that may take the near-plane path: the records' bound and the feature.
        let near_plane = features::homogeneous_triangles(f.scene, &self.meshes, width, height);
        let homogeneous = homogeneous_bound(f.gpu, near_plane);
        let capacities = self.resources.capacities;
        if triangles > capacities.triangles || homogeneous > capacities.homogeneous {
            let grown = resources::Capacities {
                triangles: triangles.max(capacities.triangles),
                homogeneous: homogeneous.max(capacities.homogeneous),
                ..capacities
            };
            self.resources
                .grow(f.gpu, grown)
                .map_err(|e| self.program.in_errors(e))?;
            self.resources.refresh_set(f.targets)?;
        }
        let subgroup_size = self.gpu.info().subgroup_size;
        let mut fresh = RasterFeatures::of_frame(f.scene, &self.meshes, near_plane, subgroup_size);
        fresh.homogeneous =
            (fresh.homogeneous && !self.fixed_path_forced) || self.homogeneous_missed;
        let features = self.features.for_frame(fresh);
        if features != self.features {
            let layouts = [&f.uploaded.layout, &self.resources.layout];
            self.stages =
                StagePipelines::select(&mut self.cache, f.gpu, &layouts, &features, &self.program)?;
            self.features = features;
        }
        Ok(())
    }

    fn record(&mut self, ctx: &mut RecordContext<'_>) -> Result<()> {
        let cmd = ctx.cmd;
        self.resources.use_slot(ctx.slot);
        // Buffers grown after the last frame: the slot's set names the new ones.
        self.resources.refresh_set(ctx.targets)?;
        self.resources.retirement.recorded();
        self.recorded[ctx.slot] = Recorded {
            features: self.features,
            continuations: self.continuations,
            capacities: self.resources.capacities,
        };
        self.resources.record_reset(cmd, self.features.rows);
        // Setup's occlusion cull reads the opaque depth (through the pyramid), as does the
        // raster's depth test.
        self.targets_to_raster(ctx, OPAQUE_PASS_WRITES);
        let cells = self.push.bins_x * self.push.bins_y;
        let s = &self.stages;
        self.dispatch(
            ctx,
            &s.depth_pyramid,
            [cells.div_ceil(PYRAMID_GROUP_SIZE), 1, 1],
        );
        self.compute_to_compute(cmd);
        self.dispatch(ctx, &s.pyramid_top, [1, 1, 1]);
        self.compute_to_compute(cmd);
        ctx.timestamps.mark(cmd, "depth pyramid");

        let items = self.push.item_count;
        if items > 0 {
            self.dispatch(ctx, &s.setup, [items.div_ceil(64), 1, 1]);
        }
        self.compute_to_compute(cmd);
        ctx.timestamps.mark(cmd, "setup");

        self.dispatch_indirect(ctx, &s.bin_count, DISPATCH_BINNING_OFFSET);
        self.compute_to_compute(cmd);
        ctx.timestamps.mark(cmd, "bin count");
        let [block_sums, list_blocks, ..] = &s.scan_steps;
        self.dispatch(ctx, block_sums, [self.resources.scan_groups(), 1, 1]);
        self.compute_to_compute(cmd);
        self.dispatch(ctx, list_blocks, [1, 1, 1]);
        self.compute_to_compute(cmd);
        // Both resume lists start empty.
        self.pending_list = 0;
        for band in 0..self.bands {
            self.record_band(ctx, band == 0);
        }
        self.resources.set_pending_list(self.pending_list);
        self.targets_from_raster(ctx);
        ctx.timestamps.mark(cmd, self.program.stage());
        Ok(())
    }

    fn record_finish(&mut self, ctx: &mut RecordContext<'_>) -> Result<()> {
        self.recorded[ctx.slot].continuations = self.continuations;
        self.targets_to_raster(ctx, FINISHED_SUBMISSION_WRITES);
        self.record_continuations(ctx, self.continuations);
        self.resources.set_pending_list(self.pending_list);
        self.targets_from_raster(ctx);
        ctx.timestamps.mark(ctx.cmd, "raster finished");
        Ok(())
    }

    fn learned(&self, options: &mut MethodOptions) {
        let c = self.resources.capacities;
        options.initial_bin_entries = Some(c.bin_entries);
        options.initial_homogeneous = Some(c.homogeneous);
        options.initial_resume_rows = Some(c.resume);
    }

    fn frame_done(&mut self, done: &FrameDone<'_>) -> Result<FrameCheck> {
        self.resources.retirement.completed();
        let uploaded = done.uploaded;
        let counters = self.resources.counters(done.slot)?;
        // Judged by what the frame was recorded with; fixes go to the current settings.
        let recorded = self.recorded[done.slot % self.recorded.len()];
        let method = self.program.method();
        // A row of a shallow frame whose list is too long for one pass of the loop budget:
        // the exact raster's continuations walk it in parts (this frame is right), and later
        // frames bin in depth slabs, where the first dispatch does too. Other programs
        // cannot.
        let crowded = counters.overflow & OVERFLOW_CROWDED_BIN != 0;
        if crowded && self.program != RasterProgram::Exact {
            return Err(crate::Error::InvalidScene(format!(
                "{method}: one 8x8-pixel bin of this frame holds so many triangles that a \
                 single pass over them exceeds {}'s shader loop limit; render at a larger size \
                 or with fewer overlapping triangles",
                self.gpu.info().name
            )));
        }
        // What later frames need.
        let mut features = self.features;
        if crowded {
            features = features.deep();
        }
        // The host's estimate missed a near-plane triangle: the frame needs the full shaders.
        let rebuild = counters.homogeneous_count > 0 && !recorded.features.homogeneous;
        features.homogeneous |= rebuild;
        self.homogeneous_missed |= rebuild;
        // Deep pixels: select more fragments per pass, or order the bins by depth slab, from
        // the next frame on (this one is right either way).
        // (Other programs have no selection, and would only pay for slabs.)
        if self.program == RasterProgram::Exact {
            features = features.after_frame(
                counters.sweeps(),
                counters.fragments_in_front(),
                self.push.width,
                self.push.height,
            );
        }
        if features != self.features {
            let layouts = [&uploaded.layout, &self.resources.layout];
            self.stages = StagePipelines::select(
                &mut self.cache,
                &self.gpu,
                &layouts,
                &features,
                &self.program,
            )?;
        }
        // Lists past their capacity were rasterized in bands, and rows with no state slot
        // started over: right, unless some blocks were left untouched (degraded). Missing
        // homogeneous records (past one buffer's worth) lose triangles, and so would a band
        // whose lists did not fit (the frame's entry count past 2^32).
        let overflowed = counters.overflow & (OVERFLOW_HOMOGENEOUS | OVERFLOW_BAND_LISTS) != 0;
        let degraded_rows = counters.degraded_rows();
        let grown = self.resources.capacities.grown_for(
            &counters,
            &recorded.capacities,
            &Capacities::most(&self.gpu),
        );
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
                .map_err(|e| self.program.in_errors(e))?;
        }
        self.resources.set_slabs(&self.gpu, features.slabs())?;
        let features_changed = features != self.features;
        self.features = features;
        // Rows the last dispatch left on the pending list are unfinished.
        let unfinished = self.resources.unfinished_rows(done.slot)?;
        // (Continuations already multiplied since the frame was recorded are left alone.)
        if unfinished > 0 && recorded.continuations == self.continuations {
            if self.continuations >= MAX_CONTINUATIONS {
                return Err(crate::Error::InvalidScene(format!(
                    "exact: {unfinished} pixel rows still unfinished after {MAX_CONTINUATIONS} \
                     continuation dispatches; the frame is too deep for this driver"
                )));
            }
            self.continuations = (self.continuations * CONTINUATION_GROWTH).min(MAX_CONTINUATIONS);
            log::info!(
                "exact: {unfinished} rows unfinished; {} continuations next",
                self.continuations
            );
        }
        // Unfinished rows are finished by another submission of continuations, unless the
        // frame must be rendered again anyway, or its pipelines changed under the saved rows.
        let again = rebuild || overflowed || degraded_rows > 0;
        // (A finishing submission reads the buffers the frame used: not after they grew.)
        let finish = unfinished > 0 && !again && !features_changed && grown.is_none();
        let rerender = again || (unfinished > 0 && !finish);
        let kept = |count: u64| if rerender || finish { 0 } else { count };
        if degraded_rows > 0 {
            log::warn!(
                "{method}: {degraded_rows} pixel rows left with the opaque colour: blocks past \
                 {} bands of {} bin entries ({} needed), or rows a band left unfinished ({})",
                self.bands,
                recorded.capacities.bin_entries,
                counters.bin_entry_count,
                counters.abandoned_rows
            );
        }
        Ok(FrameCheck {
            rerender,
            finish,
            degraded_rows,
            unfinished_rows: u64::from(unfinished),
            bands: counters.bands,
            fragments: kept(counters.fragments()),
            triangles: kept(u64::from(counters.triangle_count)),
        })
    }
}
