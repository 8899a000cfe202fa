//! The wavelet method's images, render passes and pipelines, one recording function per pass.

use super::Settings;
use crate::assets::{GpuScene, MeshStages};
use crate::frame::{FrameTargets, DEPTH_FORMAT};
use crate::gpu::{
    fullscreen_pipeline, image_barrier, vk, Attachment, AttachmentPass, Blend, DepthAttachment,
    DepthMode, DescriptorLayout, DescriptorSet, Gpu, GpuImage, GraphicsPipeline, Load,
    PipelineState, Resource, Sampler,
};
use crate::interface::methods::{
    WAVELET_BOUNDS_SET, WAVELET_MAX_TEXELS, WAVELET_READ_SET, WAVELET_RESOLVE_SET,
};
use crate::interface::specialization::Specialization;
use crate::methods::RecordContext;
use crate::Result;
use std::sync::Arc;

/// Colour attachments one draw may write (the Vulkan minimum, and lavapipe's limit).
const MAX_ATTACHMENTS: usize = 8;

/// Coefficient texels at rank 3; the shaders' sampler array has this many slots.
const MAX_TEXELS: usize = WAVELET_MAX_TEXELS as usize;

/// Texels each accumulate draw writes, of a rank's `texels`: equal parts of at most
/// MAX_ATTACHMENTS (`WAVELET_DRAW_TEXELS` of wavelet.glsl), so that every output a draw's
/// shader writes has its attachment.
fn draw_texels(texels: usize) -> usize {
    let draws = texels.div_ceil(MAX_ATTACHMENTS);
    debug_assert_eq!(texels % draws, 0, "{texels} texels in {draws} equal draws");
    texels / draws
}

const BOUNDS_FORMAT: vk::Format = vk::Format::R32G32_SFLOAT;

type Pair = (Arc<GraphicsPipeline>, Arc<GraphicsPipeline>);

/// SPIR-V of the rank's accumulate, resolve and shade shaders: the rank is compiled in, so
/// that every loop over coefficients unrolls to constant indices. `depth` picks the order depth
/// of the scene draws' fragments ([`FragmentDepth`]).
fn shaders(rank: u32, depth: FragmentDepth) -> [&'static [u8]; 3] {
    use FragmentDepth::{Driver, Reference};
    match (rank.min(3), depth) {
        (0, Reference) => [
            crate::spirv!("wavelet/accumulate_rank0.frag"),
            crate::spirv!("wavelet/resolve_rank0.frag"),
            crate::spirv!("wavelet/shade_rank0.frag"),
        ],
        (0, Driver) => [
            crate::spirv!("wavelet/accumulate_rank0_driver_depth.frag"),
            crate::spirv!("wavelet/resolve_rank0.frag"),
            crate::spirv!("wavelet/shade_rank0_driver_depth.frag"),
        ],
        (1, Reference) => [
            crate::spirv!("wavelet/accumulate_rank1.frag"),
            crate::spirv!("wavelet/resolve_rank1.frag"),
            crate::spirv!("wavelet/shade_rank1.frag"),
        ],
        (1, Driver) => [
            crate::spirv!("wavelet/accumulate_rank1_driver_depth.frag"),
            crate::spirv!("wavelet/resolve_rank1.frag"),
            crate::spirv!("wavelet/shade_rank1_driver_depth.frag"),
        ],
        (2, Reference) => [
            crate::spirv!("wavelet/accumulate_rank2.frag"),
            crate::spirv!("wavelet/resolve_rank2.frag"),
            crate::spirv!("wavelet/shade_rank2.frag"),
        ],
        (2, Driver) => [
            crate::spirv!("wavelet/accumulate_rank2_driver_depth.frag"),
            crate::spirv!("wavelet/resolve_rank2.frag"),
            crate::spirv!("wavelet/shade_rank2_driver_depth.frag"),
        ],
        (_, Reference) => [
            crate::spirv!("wavelet/accumulate_rank3.frag"),
            crate::spirv!("wavelet/resolve_rank3.frag"),
            crate::spirv!("wavelet/shade_rank3.frag"),
        ],
        (_, Driver) => [
            crate::spirv!("wavelet/accumulate_rank3_driver_depth.frag"),
            crate::spirv!("wavelet/resolve_rank3.frag"),
            crate::spirv!("wavelet/shade_rank3_driver_depth.frag"),
        ],
    }
}

/// Where the scene draws' fragments take their order depth from.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum FragmentDepth {
    /// The CPU reference's, computed at the pixel centre from the triangle's fixed-point setup,
    /// which a geometry stage hands each fragment (`scene/ordered.geom`): every fragment then
    /// is the CPU model's, coverage, depth and texture level of detail.
    Reference,
    /// The driver's interpolated depth, on a device without geometry shaders: it differs from
    /// the reference's in the last bits, which moves a pixel whose fragments meet at one depth.
    Driver,
}

impl FragmentDepth {
    /// The reference's where the device has a geometry stage.
    pub fn of(gpu: &Gpu) -> Self {
        if gpu.info().geometry_shader {
            Self::Reference
        } else {
            Self::Driver
        }
    }

    fn stages(self) -> MeshStages {
        match self {
            Self::Reference => MeshStages::OrderDepth,
            Self::Driver => MeshStages::Plain,
        }
    }

    /// The accumulate pass shades transmittance alone: no eye vector or normal.
    fn accumulate_stages(self) -> MeshStages {
        match self {
            Self::Reference => MeshStages::OrderUnlit,
            Self::Driver => MeshStages::Plain,
        }
    }

    /// The bounds pass reads the order depth alone.
    fn bounds_stages(self) -> MeshStages {
        match self {
            Self::Reference => MeshStages::OrderOnly,
            Self::Driver => MeshStages::Plain,
        }
    }

    fn bounds_spirv(self) -> &'static [u8] {
        match self {
            Self::Reference => crate::spirv!("wavelet/bounds.frag"),
            Self::Driver => crate::spirv!("wavelet/bounds_driver_depth.frag"),
        }
    }
}

/// One draw of the scene into a range of coefficient texels.
struct Accumulation {
    pass: AttachmentPass,
    pipelines: Pair,
}

pub struct Passes {
    _images: Images,
    _sampler: Sampler,
    _layouts: Layouts,
    bounds_pass: AttachmentPass,
    bounds_pipelines: Pair,
    bounds_set: DescriptorSet,
    accumulations: Vec<Accumulation>,
    resolve_pass: AttachmentPass,
    resolve_pipeline: Arc<GraphicsPipeline>,
    resolve_set: DescriptorSet,
    shade_pass: AttachmentPass,
    shade_pipelines: Pair,
    read_set: DescriptorSet,
    frame_depth: vk::Image,
}

const COLOUR: vk::ImageLayout = vk::ImageLayout::COLOR_ATTACHMENT_OPTIMAL;
const DEPTH: vk::ImageLayout = vk::ImageLayout::DEPTH_STENCIL_ATTACHMENT_OPTIMAL;
const DEPTH_READ: vk::ImageLayout = vk::ImageLayout::DEPTH_STENCIL_READ_ONLY_OPTIMAL;
const SAMPLED: vk::ImageLayout = vk::ImageLayout::SHADER_READ_ONLY_OPTIMAL;

/// The method's images. They hold the largest frame; smaller ones use their top-left corner.
struct Images {
    /// Each pixel's nearest and farthest transparent view depth.
    bounds: GpuImage,
    /// The coefficient texels, one image each ([`Settings::texels`]).
    coefficients: Vec<GpuImage>,
    /// The resolve's depth: the opaque depth, or nearer, where every channel is absorbed.
    depth: GpuImage,
}

impl Images {
    fn new(gpu: &Gpu, targets: &FrameTargets, settings: &Settings) -> Result<Self> {
        let extent = targets.capacity;
        let usage = vk::ImageUsageFlags::COLOR_ATTACHMENT | vk::ImageUsageFlags::SAMPLED;
        let bounds = gpu.create_image("wavelet bounds", extent, BOUNDS_FORMAT, usage, 1)?;
        let format = match settings.precision {
            super::Precision::Half => vk::Format::R16G16B16A16_SFLOAT,
            super::Precision::Single => vk::Format::R32G32B32A32_SFLOAT,
        };
        let coefficients = (0..settings.texels())
            .map(|i| {
                gpu.create_image(
                    &format!("wavelet coefficients {i}"),
                    extent,
                    format,
                    usage,
                    1,
                )
            })
            .collect::<Result<Vec<_>>>()?;
        let depth = gpu.create_image(
            "wavelet depth",
            extent,
            DEPTH_FORMAT,
            vk::ImageUsageFlags::DEPTH_STENCIL_ATTACHMENT,
            1,
        )?;
        Ok(Self {
            bounds,
            coefficients,
            depth,
        })
    }
}

/// The descriptor layouts of the method's sets, all read by fragment shaders.
struct Layouts {
    /// The bounds, read by the accumulation draws.
    bounds: DescriptorLayout,
    /// The bounds and the coefficients, read by the shade draw.
    read: DescriptorLayout,
    /// The read set's bindings and the opaque depth, read by the resolve.
    resolve: DescriptorLayout,
}

impl Layouts {
    fn new(gpu: &Gpu) -> Result<Self> {
        let stages = vk::ShaderStageFlags::FRAGMENT;
        Ok(Self {
            bounds: DescriptorLayout::declared(gpu, &WAVELET_BOUNDS_SET, stages)?,
            read: DescriptorLayout::declared(gpu, &WAVELET_READ_SET, stages)?,
            resolve: DescriptorLayout::declared(gpu, &WAVELET_RESOLVE_SET, stages)?,
        })
    }
}

/// One set of each of [`Layouts`].
struct Sets {
    bounds: DescriptorSet,
    read: DescriptorSet,
    resolve: DescriptorSet,
}

impl Sets {
    fn new(
        layouts: &Layouts,
        images: &Images,
        sampler: &Sampler,
        targets: &FrameTargets,
    ) -> Result<Self> {
        let coefficients = &images.coefficients;
        // Slots past the rank's texels repeat the first image; the shaders never read them.
        let coefficient_views: Vec<vk::ImageView> = (0..MAX_TEXELS)
            .map(|i| coefficients.get(i).unwrap_or(&coefficients[0]).view)
            .collect();
        let bounds_view = [images.bounds.view];
        let sampled = |views| Resource::Images(views, sampler.raw);
        let read = [
            ("u_waveletBounds", sampled(&bounds_view)),
            ("u_waveletCoefficients", sampled(&coefficient_views)),
        ];
        let bounds = layouts.bounds.create_named_set(&read[..1])?;
        let read_set = layouts.read.create_named_set(&read)?;
        let depth_view = [targets.depth.view];
        let mut resolve = read.to_vec();
        resolve.push(("u_opaqueDepth", sampled(&depth_view)));
        let resolve = layouts.resolve.create_named_set(&resolve)?;
        Ok(Self {
            bounds,
            read: read_set,
            resolve,
        })
    }
}

impl Passes {
    pub fn new(
        gpu: &Gpu,
        gpu_scene: &GpuScene,
        targets: &FrameTargets,
        settings: &Settings,
        constants: super::SpecConstants,
    ) -> Result<Self> {
        let depth = FragmentDepth::of(gpu);
        let [accumulate_spirv, resolve_spirv, shade_spirv] = shaders(settings.rank, depth);
        let images = Images::new(gpu, targets, settings)?;
        let sampler = Sampler::nearest_clamp(gpu)?;
        let layouts = Layouts::new(gpu)?;
        let sets = Sets::new(&layouts, &images, &sampler, targets)?;
        let specialization = constants.specialization();
        let (bounds_pass, bounds_pipelines) = new_bounds_pass(
            gpu,
            gpu_scene,
            targets,
            &images.bounds,
            depth,
            &specialization,
        )?;
        // Draws of equal parts, each told the first texel it writes.
        let per_draw = draw_texels(images.coefficients.len());
        let accumulations = images
            .coefficients
            .chunks(per_draw)
            .enumerate()
            .map(|(chunk, texels)| {
                let chunk_constants = super::SpecConstants {
                    first_texel: (chunk * per_draw) as i32,
                    ..constants
                };
                Accumulation::new(
                    gpu,
                    gpu_scene,
                    targets,
                    texels,
                    (accumulate_spirv, depth),
                    &layouts.bounds,
                    &chunk_constants.specialization(),
                )
            })
            .collect::<Result<Vec<_>>>()?;
        let (resolve_pass, resolve_pipeline) = new_resolve_pass(
            gpu,
            gpu_scene,
            targets,
            &images.depth,
            resolve_spirv,
            &layouts.resolve,
            &specialization,
        )?;
        let (shade_pass, shade_pipelines) = new_shade_pass(
            gpu,
            gpu_scene,
            targets,
            &images.depth,
            (shade_spirv, depth),
            &layouts.read,
            &specialization,
        )?;
        Ok(Self {
            frame_depth: targets.depth.raw,
            _images: images,
            _sampler: sampler,
            _layouts: layouts,
            bounds_pass,
            bounds_pipelines,
            bounds_set: sets.bounds,
            accumulations,
            resolve_pass,
            resolve_pipeline,
            resolve_set: sets.resolve,
            shade_pass,
            shade_pipelines,
            read_set: sets.read,
        })
    }

    /// Draws the transparent scene with `pipelines`, whose set 2 (if any) is `extra`.
    fn draw_scene(ctx: &mut RecordContext<'_>, pipelines: &Pair, extra: Option<&DescriptorSet>) {
        if let Some(set) = extra {
            ctx.gpu
                .cmd_bind_graphics_set(ctx.cmd, pipelines.0.layout, 2, set.raw);
        }
        ctx.gpu_scene.draw(
            ctx.gpu,
            ctx.cmd,
            &ctx.gpu_scene.transparent_calls,
            (&pipelines.0, &pipelines.1),
        );
    }

    pub fn bounds(&self, ctx: &mut RecordContext<'_>) {
        self.bounds_pass.begin(ctx.cmd, ctx.targets.extent);
        Self::draw_scene(ctx, &self.bounds_pipelines, None);
        self.bounds_pass.end(ctx.cmd);
    }

    pub fn transmittance(&self, ctx: &mut RecordContext<'_>) {
        for a in &self.accumulations {
            a.pass.begin(ctx.cmd, ctx.targets.extent);
            Self::draw_scene(ctx, &a.pipelines, Some(&self.bounds_set));
            a.pass.end(ctx.cmd);
        }
    }

    pub fn resolve(&self, ctx: &mut RecordContext<'_>) {
        // The resolve pass samples the opaque depth, then the frame gets it back as it was.
        let attachment_read = (
            vk::PipelineStageFlags::LATE_FRAGMENT_TESTS,
            vk::AccessFlags::DEPTH_STENCIL_ATTACHMENT_READ,
        );
        let shader_read = (
            vk::PipelineStageFlags::FRAGMENT_SHADER,
            vk::AccessFlags::SHADER_READ,
        );
        let depth = &ctx.targets.depth;
        debug_assert_eq!(depth.raw, self.frame_depth);
        image_barrier(
            ctx.gpu,
            ctx.cmd,
            depth,
            DEPTH_READ,
            SAMPLED,
            attachment_read,
            shader_read,
        );
        self.resolve_pass.begin(ctx.cmd, ctx.targets.extent);
        self.resolve_pass.draw_fullscreen(
            ctx.cmd,
            &self.resolve_pipeline,
            (&[ctx.gpu_scene.set().raw, self.resolve_set.raw], &[]),
        );
        self.resolve_pass.end(ctx.cmd);
        let attachment = (
            vk::PipelineStageFlags::EARLY_FRAGMENT_TESTS
                | vk::PipelineStageFlags::LATE_FRAGMENT_TESTS,
            vk::AccessFlags::DEPTH_STENCIL_ATTACHMENT_READ
                | vk::AccessFlags::DEPTH_STENCIL_ATTACHMENT_WRITE,
        );
        image_barrier(
            ctx.gpu,
            ctx.cmd,
            depth,
            SAMPLED,
            DEPTH,
            shader_read,
            attachment,
        );
    }

    pub fn shade(&self, ctx: &mut RecordContext<'_>) {
        self.shade_pass.begin(ctx.cmd, ctx.targets.extent);
        Self::draw_scene(ctx, &self.shade_pipelines, Some(&self.read_set));
        self.shade_pass.end(ctx.cmd);
    }
}

/// The frame's opaque depth as a scene draw tests against it, without writing it.
fn frame_depth(
    targets: &FrameTargets,
    layouts: (vk::ImageLayout, vk::ImageLayout),
) -> DepthAttachment<'_> {
    DepthAttachment {
        attachment: Attachment {
            image: &targets.depth,
            load: Load::Keep,
            layouts,
        },
        write: false,
    }
}

/// The bounds pass and its pipelines: each fragment MAX-blends its view depth into the bounds.
/// The pass leaves the opaque depth read-only for the accumulations and the resolve.
fn new_bounds_pass(
    gpu: &Gpu,
    gpu_scene: &GpuScene,
    targets: &FrameTargets,
    bounds: &GpuImage,
    depth: FragmentDepth,
    constants: &Specialization,
) -> Result<(AttachmentPass, Pair)> {
    let pass = AttachmentPass::new(
        gpu,
        &[Attachment {
            image: bounds,
            load: Load::Clear([-f32::MAX; 4]),
            layouts: (vk::ImageLayout::UNDEFINED, SAMPLED),
        }],
        Some(&frame_depth(targets, (DEPTH, DEPTH_READ))),
    )?;
    let pipelines = gpu_scene.mesh_pipelines_with(
        gpu,
        pass.render_pass,
        depth.bounds_stages(),
        depth.bounds_spirv(),
        &[],
        &PipelineState {
            blends: &[Blend::Max],
            depth: DepthMode::Less(false),
            constants,
            vertex_input: true,
        },
    )?;
    Ok((pass, pipelines))
}

impl Accumulation {
    /// The draw that ADD-blends every fragment's coefficients into `texels`;
    /// `constants` tell the shader which texel the first of them is.
    fn new(
        gpu: &Gpu,
        gpu_scene: &GpuScene,
        targets: &FrameTargets,
        texels: &[GpuImage],
        (accumulate_spirv, depth): (&[u8], FragmentDepth),
        bounds_layout: &DescriptorLayout,
        constants: &Specialization,
    ) -> Result<Self> {
        let colours: Vec<Attachment<'_>> = texels
            .iter()
            .map(|image| Attachment {
                image,
                load: Load::Clear([0.0; 4]),
                layouts: (vk::ImageLayout::UNDEFINED, SAMPLED),
            })
            .collect();
        let pass = AttachmentPass::new(
            gpu,
            &colours,
            Some(&frame_depth(targets, (DEPTH_READ, DEPTH_READ))),
        )?;
        let blends = vec![Blend::Add; texels.len()];
        let pipelines = gpu_scene.mesh_pipelines_with(
            gpu,
            pass.render_pass,
            depth.accumulate_stages(),
            accumulate_spirv,
            &[bounds_layout],
            &PipelineState {
                blends: &blends,
                depth: DepthMode::Less(false),
                constants,
                vertex_input: true,
            },
        )?;
        Ok(Self { pass, pipelines })
    }
}

/// The resolve pass and its full-screen pipeline: dims the frame's colour by the
/// transmittance (MULTIPLY) and writes the method's own depth, every pixel, for the shade
/// pass to test against.
fn new_resolve_pass(
    gpu: &Gpu,
    gpu_scene: &GpuScene,
    targets: &FrameTargets,
    depth: &GpuImage,
    resolve_spirv: &[u8],
    resolve_layout: &DescriptorLayout,
    constants: &Specialization,
) -> Result<(AttachmentPass, Arc<GraphicsPipeline>)> {
    let pass = AttachmentPass::new(
        gpu,
        &[Attachment::kept(&targets.colour, COLOUR)],
        Some(&DepthAttachment {
            attachment: Attachment {
                image: depth,
                load: Load::Discard,
                layouts: (vk::ImageLayout::UNDEFINED, DEPTH),
            },
            write: true,
        }),
    )?;
    let pipeline = fullscreen_pipeline(
        gpu,
        pass.render_pass,
        resolve_spirv,
        (&[&gpu_scene.layout, resolve_layout], 0),
        &PipelineState {
            blends: &[Blend::Multiply],
            depth: DepthMode::WriteAlways,
            constants,
            vertex_input: false,
        },
    )?;
    Ok((pass, pipeline))
}

/// The shade pass and its pipelines: every fragment in front of the resolve's depth ADDs
/// its share to the frame's colour.
fn new_shade_pass(
    gpu: &Gpu,
    gpu_scene: &GpuScene,
    targets: &FrameTargets,
    depth_image: &GpuImage,
    (shade_spirv, depth): (&[u8], FragmentDepth),
    read_layout: &DescriptorLayout,
    constants: &Specialization,
) -> Result<(AttachmentPass, Pair)> {
    let pass = AttachmentPass::new(
        gpu,
        &[Attachment::kept(&targets.colour, COLOUR)],
        Some(&DepthAttachment {
            attachment: Attachment {
                image: depth_image,
                load: Load::Keep,
                layouts: (DEPTH, DEPTH),
            },
            write: false,
        }),
    )?;
    let pipelines = gpu_scene.mesh_pipelines_with(
        gpu,
        pass.render_pass,
        depth.stages(),
        shade_spirv,
        &[read_layout],
        &PipelineState {
            blends: &[Blend::Add],
            depth: DepthMode::Less(false),
            constants,
            vertex_input: true,
        },
    )?;
    Ok((pass, pipelines))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Every rank's texels split into equal draws within the attachments, as the shaders
    /// size their outputs: 2, 3 and 6 in one draw, rank 3's 12 in two of 6.
    #[test]
    fn accumulate_draws_write_equal_parts_within_the_attachments() {
        let ranks: Vec<usize> = (0..4)
            .map(|rank| (3 * super::super::math::coefficient_count(rank)).div_ceil(4))
            .collect();
        assert_eq!(ranks, [2, 3, 6, 12]);
        let draws: Vec<usize> = ranks.iter().map(|&t| draw_texels(t)).collect();
        assert_eq!(draws, [2, 3, 6, 6]);
    }
}
