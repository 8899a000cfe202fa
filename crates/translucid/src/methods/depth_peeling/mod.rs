//! `depth_peeling`: dual depth peeling (Bavoil and Myers), the exact method that needs no
//! per-pixel lists: each pass of the transparent draws peels the nearest and the farthest
//! layer a pixel has left, so N passes peel 2N layers.
//!
//! A first pass keeps each pixel's depth range, (-near, far) in one MAX-blended RG32F image
//! (`shaders/depth_peeling/first.frag`). Each peeling pass reads the range the pass before it
//! left (the two range images take turns) and writes the fragments at its near end into a
//! front layer, those at its far end into a back layer, and the depths of the rest into the
//! next range (`peel.frag`). A compute pass after each peeling pass puts the front layer
//! under the front layers so far and the back layer over the back ones, and notes whether
//! any pixel has fragments left (`composite.comp`); a last one composites front over back
//! over the frame (`resolve.comp`).
//!
//! Layers are depths: fragments at one depth in one pixel peel together, composited front to
//! back in the order the driver blends them, which is submission order, so surfaces that meet
//! at one depth cover one another as the reference orders them (the first drawn nearer). The
//! result is exact where the frame's pixels have at most 2N distinct depths. Past 2N, the middle layers
//! are left out and the pixels counted ([`super::FrameCheck::unpeeled_pixels`]). With
//! [`DepthPeelingOptions::passes`] N stays as given. By default N follows the frames: half
//! the most fragments a pixel of a completed frame had (the first pass counts them; a layer
//! holds at least one), up to [`MOST_PASSES`]; and a frame records [`PASSES_AHEAD`] passes
//! more, or as many as its own estimate calls for (half the most quads whose bounds on
//! screen meet over one part of it, `FrameEstimate::deepest`), each skipped on the GPU once
//! the pass before it left nothing to peel, so that a frame deeper than the ones before it,
//! recorded before they completed (frames in flight), is right all the same ([`gate`]). A frame past even those is counted, and rendered again
//! where translucid submits.

mod gate;

use super::bins::features::{estimate_sampled, FRAME_ESTIMATE_QUADS};
use super::{FrameCheck, FrameDone, FrameSetup, Method, MethodOptions, RecordContext};
use crate::assets::GpuScene;
use crate::frame::FrameTargets;
use crate::gpu::{
    image_barrier, memory_barrier, vk, Attachment, AttachmentPass, Blend, Buffer, ComputePipeline,
    ComputePipelineCache, DepthAttachment, DepthMode, DescriptorLayout, DescriptorSet, Gpu,
    GpuImage, GraphicsPipeline, Load, MemoryLocation, PipelineState, Resource, Sampler,
};
use crate::interface::methods::{DEPTH_PEELING_COMPOSITE_SET, DEPTH_PEELING_PEEL_SET};
use crate::interface::specialization::Specialization;
use crate::scene::Scene;
use crate::{Error, Result};
use std::sync::Arc;

/// The most peeling passes a frame may take (`2 * MOST_PASSES` layers).
pub const MOST_PASSES: u32 = 128;
/// Where the pass count starts when it is not fixed.
const FIRST_PASSES: u32 = 4;
/// Passes a frame records past what the frames before it needed, skipped on the GPU where
/// it needs none of them: a frame may peel 2 * PASSES_AHEAD layers more than they had.
/// A skipped pass costs its render pass, its barriers and an indirect command per draw; a
/// frame of many draws records fewer ahead, AHEAD_DRAWS of them in all (at least one pass).
pub const PASSES_AHEAD: u32 = 32;
const AHEAD_DRAWS: u32 = 4096;

/// (-near, far): one MAX blend keeps both ends. 32-bit, so that the next pass finds each
/// fragment's depth exactly.
const RANGE_FORMAT: vk::Format = vk::Format::R32G32_SFLOAT;
/// One colour channel of one pass's layer: (radiance, 0, 0, transmittance) of its
/// fragments, composited front to back by [`Blend::Under`].
const LAYER_FORMAT: vk::Format = vk::Format::R16G16B16A16_SFLOAT;
/// The layers composited so far: 32-bit, as they gather up to 2N layers.
const SUM_FORMAT: vk::Format = vk::Format::R32G32B32A32_SFLOAT;
/// The range's clear value, an empty range (`NO_RANGE` in depth_peeling.glsl).
const NO_RANGE: [f32; 4] = [-f32::MAX; 4];
/// Each pixel's fragments, counted by the first pass (exact in floats to 2^24).
const COUNT_FORMAT: vk::Format = vk::Format::R32_SFLOAT;
/// Words of the peeling buffer (`Peeling` of composite.comp): pixels unpeeled, the most
/// fragments a pixel has, then a flag per pass.
const PEELING_WORDS: u64 = 2 + MOST_PASSES as u64 + 1;

/// The depth_peeling method's settings.
#[derive(Clone, Debug, Default)]
pub struct DepthPeelingOptions {
    /// Peeling passes, fixed (each peels two layers). `None` starts at a few and grows them
    /// to what a frame with more layers needs.
    pub passes: Option<u32>,
    /// Where a count that is not fixed starts (what an earlier renderer learned).
    pub initial_passes: Option<u32>,
}

/// The images the passes write, each the largest frame's size.
struct Images {
    /// The two ranges the passes take turns reading and writing.
    ranges: [GpuImage; 2],
    /// The first pass's count of each pixel's fragments.
    count: GpuImage,
    /// One pass's front layer (red, green, blue), then its back layer.
    layers: [GpuImage; 6],
    /// The same, composited over the passes so far.
    sums: [GpuImage; 4],
}

impl Images {
    fn new(gpu: &Gpu, targets: &FrameTargets) -> Result<Self> {
        let size = targets.capacity;
        let attached = vk::ImageUsageFlags::COLOR_ATTACHMENT | vk::ImageUsageFlags::SAMPLED;
        let range = |name| gpu.create_image(name, size, RANGE_FORMAT, attached, 1);
        let layer = |name| gpu.create_image(name, size, LAYER_FORMAT, attached, 1);
        let storage = vk::ImageUsageFlags::STORAGE;
        let sum = |name| gpu.create_image(name, size, SUM_FORMAT, storage, 1);
        Ok(Self {
            ranges: [
                range("depth peeling range 0")?,
                range("depth peeling range 1")?,
            ],
            count: gpu.create_image(
                "depth peeling fragment count",
                size,
                COUNT_FORMAT,
                attached,
                1,
            )?,
            layers: [
                layer("depth peeling front red")?,
                layer("depth peeling front green")?,
                layer("depth peeling front blue")?,
                layer("depth peeling back red")?,
                layer("depth peeling back green")?,
                layer("depth peeling back blue")?,
            ],
            sums: [
                sum("depth peeling front radiance so far")?,
                sum("depth peeling front transmittance so far")?,
                sum("depth peeling back radiance so far")?,
                sum("depth peeling back transmittance so far")?,
            ],
        })
    }
}

pub struct DepthPeeling {
    images: Images,
    first: AttachmentPass,
    first_pipelines: (Arc<GraphicsPipeline>, Arc<GraphicsPipeline>),
    /// Peeling into range 0 and into range 1 (each reading the other).
    peel: [AttachmentPass; 2],
    peel_pipelines: (Arc<GraphicsPipeline>, Arc<GraphicsPipeline>),
    /// The peeling pass's set reading range i.
    peel_sets: [DescriptorSet; 2],
    composite: Arc<ComputePipeline>,
    resolve: Arc<ComputePipeline>,
    /// The composite's set reading range i (the one the pass just wrote); the resolve's too.
    composite_sets: [DescriptorSet; 2],
    _layouts: [DescriptorLayout; 2],
    _sampler: Sampler,
    /// Pixels left unpeeled and per-pass flags (`Peeling` of composite.comp).
    peeling: Buffer,
    /// The peeling buffer of each frame slot, read once the frame completes.
    readbacks: Vec<Buffer>,
    /// Passes the frames so far needed (or the fixed count), and per slot the passes its
    /// frame was recorded with.
    passes: u32,
    recorded: Vec<u32>,
    fixed: bool,
    /// Passes the frame set last is expected to need, from its estimate (half the most
    /// quads over one part of the screen).
    expected: u32,
    /// Skips the passes a frame records past what it needs.
    gate: gate::Gate,
    /// The first draw of each peeling pass: its attachments as it starts (clear.frag).
    clear: Arc<GraphicsPipeline>,
}

impl DepthPeeling {
    pub fn new(
        gpu: &Gpu,
        scene: &Scene,
        gpu_scene: &GpuScene,
        targets: &FrameTargets,
        options: &DepthPeelingOptions,
    ) -> Result<Self> {
        require_device(gpu)?;
        let passes = first_pass_count(options)?;
        let images = Images::new(gpu, targets)?;
        let RenderPasses { first, peel } = RenderPasses::new(gpu, targets, &images)?;
        let sampler = Sampler::nearest_clamp(gpu)?;
        let peel_layout = DescriptorLayout::declared(
            gpu,
            &DEPTH_PEELING_PEEL_SET,
            vk::ShaderStageFlags::FRAGMENT,
        )?;
        let composite_layout = DescriptorLayout::declared(
            gpu,
            &DEPTH_PEELING_COMPOSITE_SET,
            vk::ShaderStageFlags::COMPUTE,
        )?;
        let first_pipelines = first_pipelines(gpu, gpu_scene, &first)?;
        let peel_pipelines = peel_pipelines(gpu, gpu_scene, &peel[0], &peel_layout)?;
        let (composite, resolve) = compute_pipelines(gpu, &composite_layout)?;
        let peeling = peeling_buffer(gpu)?;
        let peel_sets = peel_sets(&peel_layout, &images, &sampler)?;
        let composite_sets =
            composite_sets(&composite_layout, &images, &sampler, &peeling, targets)?;
        let readbacks = readback_buffers(gpu, gpu_scene.slot_count())?;
        let gate = gate::Gate::new(gpu, &peeling, readbacks.len())?;
        let clear = clear_pipeline(gpu, &peel[0])?;
        Ok(Self {
            images,
            first,
            first_pipelines,
            peel,
            peel_pipelines,
            peel_sets,
            composite,
            resolve,
            composite_sets,
            _layouts: [peel_layout, composite_layout],
            _sampler: sampler,
            peeling,
            recorded: vec![passes; readbacks.len()],
            readbacks,
            passes,
            fixed: options.passes.is_some(),
            // The renderer's first frame is the scene it was made with, set no other way.
            expected: expected_passes(scene, targets),
            gate,
            clear,
        })
    }

    /// Passes the frames so far needed: the next frame records these, and some more
    /// ([`recorded_passes`]).
    pub fn passes(&self) -> u32 {
        self.passes
    }
}

/// The passes a frame of `scene` into `targets` is expected to need, from its estimate: half
/// the most quads over one part of the screen (a layer holds at least one).
fn expected_passes(scene: &Scene, targets: &FrameTargets) -> u32 {
    let extent = targets.extent;
    let estimate = estimate_sampled(scene, extent.width, extent.height, FRAME_ESTIMATE_QUADS);
    estimate.deepest.div_ceil(2).min(u64::from(MOST_PASSES)) as u32
}

/// Passes a frame of `draws` transparent draws records, where the frames before it needed
/// `needed` (or were given that many, `fixed`) and its estimate `expected`: PASSES_AHEAD
/// past `needed`, or as far as `expected` where the draws allow it (AHEAD_DRAWS skippable
/// draws in all).
fn recorded_passes(needed: u32, expected: u32, fixed: bool, draws: usize) -> u32 {
    if fixed {
        return needed;
    }
    let allowed = (AHEAD_DRAWS / (draws.max(1) as u32).min(AHEAD_DRAWS)).max(1);
    let ahead = allowed.min(PASSES_AHEAD);
    (needed + ahead)
        .max(expected.min(needed + allowed))
        .min(MOST_PASSES)
}

/// What the method needs of the device: its optional features, blending in the range's and
/// the count's formats (the first pass blends them, by MAX and by ADD), and as many colour
/// attachments in a pass as a peeling pass writes.
fn require_device(gpu: &Gpu) -> Result<()> {
    gpu.require_features(
        "depth_peeling",
        super::MethodKind::DepthPeeling.optional_features(),
    )?;
    for (format, what) in [
        (RANGE_FORMAT, "depth range"),
        (COUNT_FORMAT, "fragment count"),
    ] {
        if !gpu
            .format_features(format)
            .contains(vk::FormatFeatureFlags::COLOR_ATTACHMENT_BLEND)
        {
            return Err(Error::DeviceLacks(format!(
                "{} cannot blend {format:?} attachments, which the depth_peeling method's \
                 {what} needs",
                gpu.info().name
            )));
        }
    }
    // A peeling pass writes the range and six layer channels.
    let attachments = 1 + 6;
    let most = gpu.info().max_color_attachments;
    if most < attachments {
        let message = format!(
            "{} writes at most {most} colour attachments in a pass; the depth_peeling \
             method needs {attachments}",
            gpu.info().name
        );
        return Err(if gpu.is_host_device() {
            Error::HostRequirements(message)
        } else {
            Error::DeviceLacks(message)
        });
    }
    Ok(())
}

/// The passes the first frame is recorded with: the fixed count, checked, else where a
/// growing count starts.
fn first_pass_count(options: &DepthPeelingOptions) -> Result<u32> {
    match options.passes {
        Some(n) if n == 0 || n > MOST_PASSES => Err(Error::InvalidOption(format!(
            "depth_peeling: {n} passes; give 1 to {MOST_PASSES}"
        ))),
        Some(n) => Ok(n),
        None => Ok(options
            .initial_passes
            .unwrap_or(FIRST_PASSES)
            .clamp(1, MOST_PASSES)),
    }
}

/// The render passes of the transparent draws, all testing against the frame's opaque
/// depth without writing it.
struct RenderPasses {
    /// Into range 0 and the fragment count.
    first: AttachmentPass,
    /// Peeling into range 0 and into range 1 (each reading the other).
    peel: [AttachmentPass; 2],
}

impl RenderPasses {
    fn new(gpu: &Gpu, targets: &FrameTargets, images: &Images) -> Result<Self> {
        let read = vk::ImageLayout::SHADER_READ_ONLY_OPTIMAL;
        let depth = DepthAttachment {
            attachment: Attachment::kept(
                &targets.depth,
                vk::ImageLayout::DEPTH_STENCIL_ATTACHMENT_OPTIMAL,
            ),
            write: false,
        };
        // Every image a pass writes is cleared and left for the next pass to sample.
        let cleared = |image, value| Attachment {
            image,
            load: Load::Clear(value),
            layouts: (vk::ImageLayout::UNDEFINED, read),
        };
        let first = AttachmentPass::new(
            gpu,
            &[
                cleared(&images.ranges[0], NO_RANGE),
                cleared(&images.count, [0.0; 4]),
            ],
            Some(&depth),
        )?;
        // A peeling pass clears its attachments by its first draw (clear.frag), which the
        // gate skips with the rest of a pass that has nothing to peel.
        let discarded = |image| Attachment {
            image,
            load: Load::Discard,
            layouts: (vk::ImageLayout::UNDEFINED, read),
        };
        let peel_into = |range| {
            let mut attachments = vec![discarded(range)];
            attachments.extend(images.layers.iter().map(discarded));
            AttachmentPass::new(gpu, &attachments, Some(&depth))
        };
        let peel = [peel_into(&images.ranges[0])?, peel_into(&images.ranges[1])?];
        Ok(Self { first, peel })
    }
}

/// The first pass's pair of scene pipelines ([`GpuScene::mesh_pipelines`]), blending the
/// range by MAX and the fragment count by ADD.
fn first_pipelines(
    gpu: &Gpu,
    gpu_scene: &GpuScene,
    first: &AttachmentPass,
) -> Result<(Arc<GraphicsPipeline>, Arc<GraphicsPipeline>)> {
    gpu_scene.mesh_pipelines_with(
        gpu,
        first.render_pass,
        crate::assets::MeshStages::OrderOnly,
        crate::spirv!("depth_peeling/first.frag"),
        &[],
        &PipelineState {
            blends: &[Blend::Max, Blend::Add],
            depth: DepthMode::Less(false),
            constants: &Specialization::NONE,
            vertex_input: true,
        },
    )
}

/// The peeling passes' pair of scene pipelines, blending the next range by MAX and the six
/// layer channels front to back (UNDER). Made with one peeling pass, they draw in the other
/// too: the two passes' attachments have the same formats, so their render passes are
/// compatible.
fn peel_pipelines(
    gpu: &Gpu,
    gpu_scene: &GpuScene,
    peel: &AttachmentPass,
    peel_layout: &DescriptorLayout,
) -> Result<(Arc<GraphicsPipeline>, Arc<GraphicsPipeline>)> {
    gpu_scene.mesh_pipelines_with(
        gpu,
        peel.render_pass,
        crate::assets::MeshStages::OrderDepth,
        crate::spirv!("depth_peeling/peel.frag"),
        &[peel_layout],
        &PipelineState {
            blends: &[
                Blend::Max,
                Blend::Under,
                Blend::Under,
                Blend::Under,
                Blend::Under,
                Blend::Under,
                Blend::Under,
            ],
            depth: DepthMode::Less(false),
            constants: &Specialization::NONE,
            vertex_input: true,
        },
    )
}

/// The composite after each peeling pass and the resolve after the last, which share the
/// composite's set and push constants ([`push`], 16 bytes).
fn compute_pipelines(
    gpu: &Gpu,
    composite_layout: &DescriptorLayout,
) -> Result<(Arc<ComputePipeline>, Arc<ComputePipeline>)> {
    let mut computes = ComputePipelineCache::new(16);
    let composite = computes.get(
        gpu,
        &[composite_layout],
        crate::spirv!("depth_peeling/composite.comp"),
        &Specialization::NONE,
    )?;
    let resolve = computes.get(
        gpu,
        &[composite_layout],
        crate::spirv!("depth_peeling/resolve.comp"),
        &Specialization::NONE,
    )?;
    Ok((composite, resolve))
}

/// The clear draw of the peeling passes: no blending, no depth test (every pixel starts
/// empty, also behind the opaque layer).
fn clear_pipeline(gpu: &Gpu, peel: &AttachmentPass) -> Result<Arc<GraphicsPipeline>> {
    crate::gpu::fullscreen_pipeline(
        gpu,
        peel.render_pass,
        crate::spirv!("depth_peeling/clear.frag"),
        (&[], 0),
        &PipelineState {
            blends: &[Blend::None; 7],
            depth: DepthMode::Off,
            constants: &Specialization::NONE,
            vertex_input: false,
        },
    )
}

/// The peeling buffer ([`PEELING_WORDS`]): cleared each frame, read by the gates and copied
/// to the slot's readback.
fn peeling_buffer(gpu: &Gpu) -> Result<Buffer> {
    let usage = vk::BufferUsageFlags::STORAGE_BUFFER
        | vk::BufferUsageFlags::TRANSFER_DST
        | vk::BufferUsageFlags::TRANSFER_SRC;
    gpu.create_buffer(
        "depth peeling flags",
        PEELING_WORDS * 4,
        usage,
        MemoryLocation::GpuOnly,
    )
}

/// The peeling pass's set reading range 0, and the one reading range 1.
fn peel_sets(
    peel_layout: &DescriptorLayout,
    images: &Images,
    sampler: &Sampler,
) -> Result<[DescriptorSet; 2]> {
    let peel_set = |range: &GpuImage| {
        peel_layout
            .create_named_set(&[("u_previous", Resource::Images(&[range.view], sampler.raw))])
    };
    Ok([peel_set(&images.ranges[0])?, peel_set(&images.ranges[1])?])
}

/// The composite's set reading range 0, and the one reading range 1: the range a peeling
/// pass just wrote, its layers, the sums so far, the flags, and the frame's colour (which
/// the resolve writes).
fn composite_sets(
    composite_layout: &DescriptorLayout,
    images: &Images,
    sampler: &Sampler,
    peeling: &Buffer,
    targets: &FrameTargets,
) -> Result<[DescriptorSet; 2]> {
    let count_view = [images.count.view];
    let composite_set = |range: &GpuImage| {
        let range = [range.view];
        let [front, back] =
            [0, 3].map(|first| [0, 1, 2].map(|channel| images.layers[first + channel].view));
        let sampled = |views| Resource::Images(views, sampler.raw);
        let [front_sum, front_t, back_sum, back_t] =
            [0, 1, 2, 3].map(|i| Resource::StorageImage(images.sums[i].view));
        composite_layout.create_named_set(&[
            ("u_range", sampled(&range[..])),
            ("u_frontLayer", sampled(&front)),
            ("u_backLayer", sampled(&back)),
            ("u_front", front_sum),
            ("u_frontT", front_t),
            ("u_back", back_sum),
            ("u_backT", back_t),
            ("Peeling", Resource::Buffer(peeling)),
            ("u_colour", Resource::StorageImage(targets.colour.view)),
            ("u_fragments", sampled(&count_view)),
        ])
    };
    Ok([
        composite_set(&images.ranges[0])?,
        composite_set(&images.ranges[1])?,
    ])
}

/// A readback of the peeling buffer for each frame slot, so that a frame's flags are read
/// once it completes while later frames write theirs.
fn readback_buffers(gpu: &Gpu, slots: usize) -> Result<Vec<Buffer>> {
    (0..slots)
        .map(|_| {
            gpu.create_buffer(
                "depth peeling flags readback",
                PEELING_WORDS * 4,
                vk::BufferUsageFlags::TRANSFER_DST,
                MemoryLocation::GpuToCpu,
            )
        })
        .collect()
}

/// `Push` of composite.comp and resolve.comp.
fn push(pass: u32, last: bool, extent: vk::Extent2D) -> [u8; 16] {
    let words = [pass, u32::from(last), extent.width, extent.height];
    bytemuck::cast(words)
}

impl Method for DepthPeeling {
    fn name(&self) -> &'static str {
        "depth_peeling"
    }

    fn set_frame(&mut self, f: &FrameSetup<'_>) -> Result<()> {
        // The frame's own estimate, so that a frame deeper than those before it (a camera
        // moving into a cloud, the first frame of a deep scene) records the passes it needs
        // though they have not completed.
        if !self.fixed {
            self.expected = expected_passes(f.scene, f.targets);
        }
        Ok(())
    }

    fn record(&mut self, ctx: &mut RecordContext<'_>) -> Result<()> {
        let (gpu, cmd) = (ctx.gpu, ctx.cmd);
        let extent = ctx.targets.extent;
        let draws = &ctx.gpu_scene.transparent_calls;
        let passes = recorded_passes(self.passes, self.expected, self.fixed, draws.len());
        self.recorded[ctx.slot] = passes;
        self.gate
            .write(gpu, ctx.slot, &self.peeling, draws, extent)?;
        let commands = self.gate.commands(ctx.slot);
        let transfer = (
            vk::PipelineStageFlags::TRANSFER,
            vk::AccessFlags::TRANSFER_WRITE,
        );
        let compute = (
            vk::PipelineStageFlags::COMPUTE_SHADER,
            vk::AccessFlags::SHADER_READ | vk::AccessFlags::SHADER_WRITE,
        );
        // The frames before this one are done with the flags and the sums.
        memory_barrier(gpu, cmd, compute, transfer);
        gpu.cmd_fill_buffer(cmd, &self.peeling, 0);
        memory_barrier(gpu, cmd, transfer, compute);
        for sum in &self.images.sums {
            // The first composite writes every pixel of the frame before any is read.
            let undefined = vk::ImageLayout::UNDEFINED;
            image_barrier(
                gpu,
                cmd,
                sum,
                undefined,
                vk::ImageLayout::GENERAL,
                compute,
                compute,
            );
        }

        self.first.begin(cmd, extent);
        ctx.gpu_scene.draw(
            gpu,
            cmd,
            draws,
            (&self.first_pipelines.0, &self.first_pipelines.1),
        );
        self.first.end(cmd);
        ctx.timestamps.mark(cmd, "depth peeling range");

        // Read by the passes' draws and composites, each zeroed by the gate before them.
        let indirect = (
            vk::PipelineStageFlags::DRAW_INDIRECT,
            vk::AccessFlags::INDIRECT_COMMAND_READ,
        );
        let next_pass = (compute.0 | indirect.0, compute.1 | indirect.1);
        for pass in 1..=passes {
            // Range `pass % 2` is written, the other one read.
            let (into, from) = ((pass % 2) as usize, ((pass + 1) % 2) as usize);
            let pipelines = &self.peel_pipelines;
            let peel = &self.peel[into];
            peel.begin(cmd, extent);
            gpu.cmd_draw_indirect(cmd, &self.clear, (&[], &[]), (commands, gate::CLEAR));
            gpu.cmd_bind_graphics_set(cmd, pipelines.0.layout, 2, self.peel_sets[from].raw);
            ctx.gpu_scene.draw_indirect(
                gpu,
                cmd,
                draws,
                (&pipelines.0, &pipelines.1),
                (commands, gate::DRAWS),
            );
            peel.end(cmd);
            self.composite.dispatch_indirect(
                cmd,
                &[self.composite_sets[into].raw],
                &push(pass, pass == passes, extent),
                commands,
                gate::COMPOSITE,
            );
            if pass < passes {
                memory_barrier(gpu, cmd, compute, compute);
                self.gate.record(cmd, ctx.slot, pass, draws.len());
            }
            memory_barrier(gpu, cmd, compute, next_pass);
        }
        ctx.timestamps.mark(cmd, "depth peeling passes");

        let colour = &ctx.targets.colour;
        let (attached, general) = (
            vk::ImageLayout::COLOR_ATTACHMENT_OPTIMAL,
            vk::ImageLayout::GENERAL,
        );
        let attachment = (
            vk::PipelineStageFlags::ALL_COMMANDS,
            vk::AccessFlags::MEMORY_READ | vk::AccessFlags::MEMORY_WRITE,
        );
        let groups = [extent.width.div_ceil(8), extent.height.div_ceil(8), 1];
        image_barrier(gpu, cmd, colour, attached, general, attachment, compute);
        self.resolve.dispatch(
            cmd,
            &[self.composite_sets[0].raw],
            &push(0, true, extent),
            groups,
        );
        image_barrier(gpu, cmd, colour, general, attached, compute, attachment);

        let transfer_read = (
            vk::PipelineStageFlags::TRANSFER,
            vk::AccessFlags::TRANSFER_READ,
        );
        memory_barrier(gpu, cmd, compute, transfer_read);
        let readback = &self.readbacks[ctx.slot];
        gpu.cmd_copy_buffer(cmd, &self.peeling, readback, 0, PEELING_WORDS * 4);
        memory_barrier(
            gpu,
            cmd,
            transfer,
            (vk::PipelineStageFlags::HOST, vk::AccessFlags::HOST_READ),
        );
        ctx.timestamps.mark(cmd, "depth peeling resolve");
        Ok(())
    }

    fn frame_done(&mut self, done: &FrameDone<'_>) -> Result<FrameCheck> {
        let slot = done.slot % self.readbacks.len();
        let words: &[u8] = self.readbacks[slot].read()?;
        let word = |i: usize| u32::from_le_bytes([0, 1, 2, 3].map(|b| words[4 * i + b]));
        let (unpeeled, most_fragments) = (word(0), word(1));
        let recorded = self.recorded[slot];
        let mut check = FrameCheck {
            unpeeled_pixels: u64::from(unpeeled),
            ..FrameCheck::default()
        };
        if self.fixed {
            return Ok(check);
        }
        // A layer holds at least one fragment: half the deepest pixel's fragments peel it.
        let needed = most_fragments.div_ceil(2).min(MOST_PASSES);
        if needed > self.passes {
            log::info!(
                "depth_peeling: up to {most_fragments} fragments a pixel; {needed} passes from \
                 now on (and {PASSES_AHEAD} ahead where the device can skip them)"
            );
            self.passes = needed;
        }
        if unpeeled > 0 && recorded < MOST_PASSES {
            log::info!(
                "depth_peeling: {unpeeled} pixels had more than the {} layers the frame's \
                 passes peel",
                2 * recorded
            );
            check.rerender = true;
        }
        Ok(check)
    }

    fn learned(&self, options: &mut MethodOptions) {
        options.depth_peeling.initial_passes = Some(self.passes);
    }
}
