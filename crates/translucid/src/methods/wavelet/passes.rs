//! The wavelet method's images, render passes and pipelines, one recording function per pass.

use super::Settings;
use crate::assets::GpuScene;
use crate::frame::{FrameTargets, DEPTH_FORMAT};
use crate::gpu::{
    fullscreen_pipeline, image_barrier, vk, Attachment, AttachmentPass, Blend, DepthAttachment,
    DepthMode, DescriptorLayout, DescriptorSet, Gpu, GpuImage, GraphicsPipeline, Load,
    PipelineState, Resource, Sampler,
};
use crate::interface::methods::{
    WAVELET_BOUNDS_SET, WAVELET_MAX_TEXELS, WAVELET_READ_SET, WAVELET_RESOLVE_SET,
};
use crate::methods::RecordContext;
use crate::Result;
use std::sync::Arc;

/// Colour attachments one draw may write (the Vulkan minimum, and lavapipe's limit).
const MAX_ATTACHMENTS: usize = 8;
/// Coefficient texels at rank 3; the shaders' sampler array has this many slots.
const MAX_TEXELS: usize = WAVELET_MAX_TEXELS as usize;

const BOUNDS_FORMAT: vk::Format = vk::Format::R32G32_SFLOAT;

type Pair = (Arc<GraphicsPipeline>, Arc<GraphicsPipeline>);

/// SPIR-V of the rank's accumulate, resolve and shade shaders: the rank is compiled in, so
/// that every loop over coefficients unrolls to constant indices.
fn shaders(rank: u32) -> [&'static [u8]; 3] {
    match rank {
        0 => [
            crate::spirv!("wavelet/accumulate_rank0.frag"),
            crate::spirv!("wavelet/resolve_rank0.frag"),
            crate::spirv!("wavelet/shade_rank0.frag"),
        ],
        1 => [
            crate::spirv!("wavelet/accumulate_rank1.frag"),
            crate::spirv!("wavelet/resolve_rank1.frag"),
            crate::spirv!("wavelet/shade_rank1.frag"),
        ],
        2 => [
            crate::spirv!("wavelet/accumulate_rank2.frag"),
            crate::spirv!("wavelet/resolve_rank2.frag"),
            crate::spirv!("wavelet/shade_rank2.frag"),
        ],
        _ => [
            crate::spirv!("wavelet/accumulate_rank3.frag"),
            crate::spirv!("wavelet/resolve_rank3.frag"),
            crate::spirv!("wavelet/shade_rank3.frag"),
        ],
    }
}

/// One draw of the scene into a range of coefficient texels.
struct Accumulation {
    pass: AttachmentPass,
    pipelines: Pair,
}

pub struct Passes {
    _bounds: GpuImage,
    _coefficients: Vec<GpuImage>,
    _depth: GpuImage,
    _sampler: Sampler,
    _layouts: [DescriptorLayout; 3],
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

impl Passes {
    pub fn new(
        gpu: &Gpu,
        gpu_scene: &GpuScene,
        targets: &FrameTargets,
        settings: &Settings,
        constants: super::SpecConstants,
    ) -> Result<Self> {
        let [accumulate_spirv, resolve_spirv, shade_spirv] = shaders(settings.rank);
        // The images hold the largest frame; smaller ones use their top-left corner.
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
        let sampler = Sampler::nearest_clamp(gpu)?;
        let stages = vk::ShaderStageFlags::FRAGMENT;
        let bounds_layout = DescriptorLayout::declared(gpu, &WAVELET_BOUNDS_SET, stages)?;
        let read_layout = DescriptorLayout::declared(gpu, &WAVELET_READ_SET, stages)?;
        let resolve_layout = DescriptorLayout::declared(gpu, &WAVELET_RESOLVE_SET, stages)?;
        // Slots past the rank's texels repeat the first image; the shaders never read them.
        let coefficient_views: Vec<vk::ImageView> = (0..MAX_TEXELS)
            .map(|i| coefficients.get(i).unwrap_or(&coefficients[0]).view)
            .collect();
        let bounds_view = [bounds.view];
        let sampled = |views| Resource::Images(views, sampler.raw);
        let read = [
            ("u_waveletBounds", sampled(&bounds_view)),
            ("u_waveletCoefficients", sampled(&coefficient_views)),
        ];
        let bounds_set = bounds_layout.create_named_set(&read[..1])?;
        let read_set = read_layout.create_named_set(&read)?;
        let depth_view = [targets.depth.view];
        let mut resolve = read.to_vec();
        resolve.push(("u_opaqueDepth", sampled(&depth_view)));
        let resolve_set = resolve_layout.create_named_set(&resolve)?;

        let frame_depth = |load, layouts| DepthAttachment {
            attachment: Attachment {
                image: &targets.depth,
                load,
                layouts,
            },
            write: false,
        };
        let fragment_constants = constants.specialization();

        let bounds_pass = AttachmentPass::new(
            gpu,
            &[Attachment {
                image: &bounds,
                load: Load::Clear([-f32::MAX; 4]),
                layouts: (vk::ImageLayout::UNDEFINED, SAMPLED),
            }],
            Some(&frame_depth(Load::Keep, (DEPTH, DEPTH_READ))),
        )?;
        let bounds_pipelines = gpu_scene.mesh_pipelines_with(
            gpu,
            bounds_pass.render_pass,
            crate::assets::MeshStages::Plain,
            crate::spirv!("wavelet/bounds.frag"),
            &[],
            &PipelineState {
                blends: &[Blend::Max],
                depth: DepthMode::Less(false),
                fragment_constants: &fragment_constants,
                vertex_input: true,
            },
        )?;

        let mut accumulations = Vec::new();
        for (chunk, images) in coefficients.chunks(MAX_ATTACHMENTS).enumerate() {
            let colours: Vec<Attachment<'_>> = images
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
                Some(&frame_depth(Load::Keep, (DEPTH_READ, DEPTH_READ))),
            )?;
            let chunk_constants = super::SpecConstants {
                first_texel: (chunk * MAX_ATTACHMENTS) as i32,
                ..constants
            };
            let blends = vec![Blend::Add; images.len()];
            let pipelines = gpu_scene.mesh_pipelines_with(
                gpu,
                pass.render_pass,
                crate::assets::MeshStages::Plain,
                accumulate_spirv,
                &[&bounds_layout],
                &PipelineState {
                    blends: &blends,
                    depth: DepthMode::Less(false),
                    fragment_constants: &chunk_constants.specialization(),
                    vertex_input: true,
                },
            )?;
            accumulations.push(Accumulation { pass, pipelines });
        }

        let resolve_pass = AttachmentPass::new(
            gpu,
            &[Attachment::kept(&targets.colour, COLOUR)],
            Some(&DepthAttachment {
                attachment: Attachment {
                    image: &depth,
                    load: Load::Discard,
                    layouts: (vk::ImageLayout::UNDEFINED, DEPTH),
                },
                write: true,
            }),
        )?;
        let resolve_pipeline = fullscreen_pipeline(
            gpu,
            resolve_pass.render_pass,
            resolve_spirv,
            &[&gpu_scene.layout, &resolve_layout],
            &PipelineState {
                blends: &[Blend::Multiply],
                depth: DepthMode::WriteAlways,
                fragment_constants: &fragment_constants,
                vertex_input: false,
            },
        )?;

        let shade_pass = AttachmentPass::new(
            gpu,
            &[Attachment::kept(&targets.colour, COLOUR)],
            Some(&DepthAttachment {
                attachment: Attachment {
                    image: &depth,
                    load: Load::Keep,
                    layouts: (DEPTH, DEPTH),
                },
                write: false,
            }),
        )?;
        let shade_pipelines = gpu_scene.mesh_pipelines_with(
            gpu,
            shade_pass.render_pass,
            crate::assets::MeshStages::Plain,
            shade_spirv,
            &[&read_layout],
            &PipelineState {
                blends: &[Blend::Add],
                depth: DepthMode::Less(false),
                fragment_constants: &fragment_constants,
                vertex_input: true,
            },
        )?;

        Ok(Self {
            frame_depth: targets.depth.raw,
            _bounds: bounds,
            _coefficients: coefficients,
            _depth: depth,
            _sampler: sampler,
            _layouts: [bounds_layout, read_layout, resolve_layout],
            bounds_pass,
            bounds_pipelines,
            bounds_set,
            accumulations,
            resolve_pass,
            resolve_pipeline,
            resolve_set,
            shade_pass,
            shade_pipelines,
            read_set,
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
            &[ctx.gpu_scene.set().raw, self.resolve_set.raw],
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
