//! `wboit`: McGuire and Bavoil's weighted blended OIT, the classic approximate comparator,
//! made polychrome: opacity and revealage are kept per colour channel.
//!
//! One draw of the scene sums `w·L`, `w·α` (α = 1 − T per channel) and the absorbance `−ln T`
//! (so the revealage `ΠT = exp(−Σ −ln T)` is a sum too, and every attachment blends the same
//! way without the independentBlend feature); a full-screen pass composites the weighted
//! average colour over the frame: `result = Σw·L / Σw·α ⊙ (1 − ΠT) + ΠT ⊙ opaque`. The weight
//! is the paper's equation (10), `w = max_c α_c · max(1e-2, 3e3·(1 − z)³)` on device depth `z`
//! (`shaders/common/wboit.glsl`). The sums are RGBA32F: weights reach 3e3 per layer, past half
//! floats' range within a few dozen layers.

pub mod model;

use super::{Method, RecordContext};
use crate::assets::GpuScene;
use crate::frame::FrameTargets;
use crate::gpu::{
    fullscreen_pipeline, vk, Attachment, AttachmentPass, Blend, DepthAttachment, DepthMode,
    DescriptorLayout, DescriptorSet, Gpu, GpuImage, GraphicsPipeline, Load, PipelineState,
    Resource, Sampler,
};
use crate::interface::methods::WBOIT_COMPOSITE_SET;
use crate::interface::specialization::Specialization;
use crate::Result;
use std::sync::Arc;

const SUM_FORMAT: vk::Format = vk::Format::R32G32B32A32_SFLOAT;

pub struct Wboit {
    /// Weighted radiance, weighted opacity, absorbance.
    _images: [GpuImage; 3],
    accumulate: AttachmentPass,
    accumulate_pipelines: (Arc<GraphicsPipeline>, Arc<GraphicsPipeline>),
    composite: AttachmentPass,
    composite_pipeline: Arc<GraphicsPipeline>,
    _sampler: Sampler,
    _layout: DescriptorLayout,
    set: DescriptorSet,
}

impl Wboit {
    pub fn new(gpu: &Gpu, gpu_scene: &GpuScene, targets: &FrameTargets) -> Result<Self> {
        let usage = vk::ImageUsageFlags::COLOR_ATTACHMENT | vk::ImageUsageFlags::SAMPLED;
        let image = |name, format| gpu.create_image(name, targets.capacity, format, usage, 1);
        let images = [
            image("wboit weighted radiance", SUM_FORMAT)?,
            image("wboit weighted opacity", SUM_FORMAT)?,
            image("wboit absorbance", SUM_FORMAT)?,
        ];
        let read = vk::ImageLayout::SHADER_READ_ONLY_OPTIMAL;
        let colour = vk::ImageLayout::COLOR_ATTACHMENT_OPTIMAL;
        let depth = vk::ImageLayout::DEPTH_STENCIL_ATTACHMENT_OPTIMAL;
        let cleared = |image, value| Attachment {
            image,
            load: Load::Clear(value),
            layouts: (vk::ImageLayout::UNDEFINED, read),
        };
        let accumulate = AttachmentPass::new(
            gpu,
            &[
                cleared(&images[0], [0.0; 4]),
                cleared(&images[1], [0.0; 4]),
                cleared(&images[2], [0.0; 4]),
            ],
            Some(&DepthAttachment {
                attachment: Attachment {
                    image: &targets.depth,
                    load: Load::Keep,
                    layouts: (depth, depth),
                },
                write: false,
            }),
        )?;
        let accumulate_pipelines = gpu_scene.mesh_pipelines_with(
            gpu,
            accumulate.render_pass,
            crate::assets::MeshStages::Plain,
            crate::spirv!("wboit/accumulate.frag"),
            &[],
            &PipelineState {
                blends: &[Blend::Add; 3],
                depth: DepthMode::Less(false),
                constants: &Specialization::NONE,
                vertex_input: true,
            },
        )?;
        let composite =
            AttachmentPass::new(gpu, &[Attachment::kept(&targets.colour, colour)], None)?;
        let sampler = Sampler::nearest_clamp(gpu)?;
        let layout =
            DescriptorLayout::declared(gpu, &WBOIT_COMPOSITE_SET, vk::ShaderStageFlags::FRAGMENT)?;
        let image = |i: usize| Resource::Images(std::slice::from_ref(&images[i].view), sampler.raw);
        let set = layout.create_named_set(&[
            ("u_radiance", image(0)),
            ("u_opacity", image(1)),
            ("u_absorbance", image(2)),
        ])?;
        let composite_pipeline = fullscreen_pipeline(
            gpu,
            composite.render_pass,
            crate::spirv!("wboit/composite.frag"),
            (&[&layout], 0),
            &PipelineState {
                blends: &[Blend::PremultipliedTransmittance],
                depth: DepthMode::Off,
                constants: &Specialization::NONE,
                vertex_input: false,
            },
        )?;
        Ok(Self {
            _images: images,
            accumulate,
            accumulate_pipelines,
            composite,
            composite_pipeline,
            _sampler: sampler,
            _layout: layout,
            set,
        })
    }
}

impl Method for Wboit {
    fn name(&self) -> &'static str {
        "wboit"
    }

    fn record(&mut self, ctx: &mut RecordContext<'_>) -> Result<()> {
        self.accumulate.begin(ctx.cmd, ctx.targets.extent);
        ctx.gpu_scene.draw(
            ctx.gpu,
            ctx.cmd,
            &ctx.gpu_scene.transparent_calls,
            (&self.accumulate_pipelines.0, &self.accumulate_pipelines.1),
        );
        self.accumulate.end(ctx.cmd);
        ctx.timestamps.mark(ctx.cmd, "wboit accumulate");
        self.composite.begin(ctx.cmd, ctx.targets.extent);
        self.composite
            .draw_fullscreen(ctx.cmd, &self.composite_pipeline, (&[self.set.raw], &[]));
        self.composite.end(ctx.cmd);
        ctx.timestamps.mark(ctx.cmd, "wboit composite");
        Ok(())
    }
}
