//! Render passes over any set of colour attachments (plus an optional depth attachment),
//! for methods that render into images of their own: several accumulation targets at once,
//! a depth buffer of their own, the frame's colour with a blend.

use super::error::vk_err;
use super::{Gpu, GpuImage};
use crate::Result;
use ash::vk;

/// What an attachment holds when the pass begins.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Load {
    /// Cleared to this value (depth uses the first component).
    Clear([f32; 4]),
    /// What the image held, in the attachment's `before` layout.
    Keep,
    /// Undefined: the pass writes every texel it needs.
    Discard,
}

/// One attachment of an [`AttachmentPass`].
pub struct Attachment<'a> {
    pub image: &'a GpuImage,
    pub load: Load,
    /// Layout before the pass (ignored unless `load` is `Keep`) and after it.
    pub layouts: (vk::ImageLayout, vk::ImageLayout),
}

impl<'a> Attachment<'a> {
    /// `image` loaded as it is, in `layout` before and after the pass.
    pub fn kept(image: &'a GpuImage, layout: vk::ImageLayout) -> Self {
        Self {
            image,
            load: Load::Keep,
            layouts: (layout, layout),
        }
    }

    fn description(&self) -> vk::AttachmentDescription {
        let (load, initial) = match self.load {
            Load::Clear(_) => (vk::AttachmentLoadOp::CLEAR, vk::ImageLayout::UNDEFINED),
            Load::Keep => (vk::AttachmentLoadOp::LOAD, self.layouts.0),
            Load::Discard => (vk::AttachmentLoadOp::DONT_CARE, vk::ImageLayout::UNDEFINED),
        };
        vk::AttachmentDescription::default()
            .format(self.image.format)
            .samples(vk::SampleCountFlags::TYPE_1)
            .load_op(load)
            .store_op(vk::AttachmentStoreOp::STORE)
            .stencil_load_op(vk::AttachmentLoadOp::DONT_CARE)
            .stencil_store_op(vk::AttachmentStoreOp::DONT_CARE)
            .initial_layout(initial)
            .final_layout(self.layouts.1)
    }

    fn clear_value(&self, depth: bool) -> vk::ClearValue {
        let value = match self.load {
            Load::Clear(v) => v,
            _ => [0.0; 4],
        };
        if depth {
            vk::ClearValue {
                depth_stencil: vk::ClearDepthStencilValue {
                    depth: value[0],
                    stencil: 0,
                },
            }
        } else {
            vk::ClearValue {
                color: vk::ClearColorValue { float32: value },
            }
        }
    }
}

/// How a pass uses its depth attachment.
pub struct DepthAttachment<'a> {
    pub attachment: Attachment<'a>,
    /// Whether the pass writes depth (else the subpass holds it read-only).
    pub write: bool,
}

/// A one-subpass render pass, its framebuffer and its clear values.
pub struct AttachmentPass {
    gpu: Gpu,
    pub render_pass: vk::RenderPass,
    pub framebuffer: vk::Framebuffer,
    pub extent: vk::Extent2D,
    clears: Vec<vk::ClearValue>,
}

impl AttachmentPass {
    pub fn new(
        gpu: &Gpu,
        colours: &[Attachment<'_>],
        depth: Option<&DepthAttachment<'_>>,
    ) -> Result<Self> {
        let extent = colours
            .first()
            .map(|a| a.image.extent)
            .or(depth.map(|d| d.attachment.image.extent))
            .expect("a pass has at least one attachment");
        let mut descriptions: Vec<_> = colours.iter().map(Attachment::description).collect();
        let mut clears: Vec<_> = colours.iter().map(|a| a.clear_value(false)).collect();
        let colour_refs: Vec<_> = (0..colours.len() as u32)
            .map(|attachment| vk::AttachmentReference {
                attachment,
                layout: vk::ImageLayout::COLOR_ATTACHMENT_OPTIMAL,
            })
            .collect();
        let depth_ref = depth.map(|d| {
            descriptions.push(d.attachment.description());
            clears.push(d.attachment.clear_value(true));
            vk::AttachmentReference {
                attachment: colours.len() as u32,
                layout: if d.write {
                    vk::ImageLayout::DEPTH_STENCIL_ATTACHMENT_OPTIMAL
                } else {
                    vk::ImageLayout::DEPTH_STENCIL_READ_ONLY_OPTIMAL
                },
            }
        });
        let render_pass =
            one_subpass_render_pass(gpu, &descriptions, &colour_refs, depth_ref.as_ref())?;
        let views: Vec<_> = colours
            .iter()
            .chain(depth.map(|d| &d.attachment))
            .map(|a| a.image.view)
            .collect();
        let fb_info = vk::FramebufferCreateInfo::default()
            .render_pass(render_pass)
            .attachments(&views)
            .width(extent.width)
            .height(extent.height)
            .layers(1);
        // SAFETY: the views are live, single-level and match the pass's formats.
        let framebuffer = match unsafe { gpu.device.create_framebuffer(&fb_info, gpu.callbacks()) }
        {
            Ok(f) => f,
            Err(e) => {
                gpu.forget_render_pass(render_pass);
                // SAFETY: unused render pass.
                unsafe { gpu.device.destroy_render_pass(render_pass, gpu.callbacks()) };
                return Err(vk_err("vkCreateFramebuffer")(e));
            }
        };
        Ok(Self {
            gpu: gpu.clone(),
            render_pass,
            framebuffer,
            extent,
            clears,
        })
    }

    /// Begins the pass over the top-left `area` of its attachments, with its clears, and
    /// sets the matching viewport and scissor.
    pub fn begin(&self, cmd: vk::CommandBuffer, area: vk::Extent2D) {
        super::pipeline::begin_render_pass(
            &self.gpu,
            cmd,
            (self.render_pass, self.framebuffer),
            (area, self.extent),
            &self.clears,
        );
    }

    pub fn end(&self, cmd: vk::CommandBuffer) {
        // SAFETY: cmd is inside this render pass.
        unsafe { self.gpu.device.cmd_end_render_pass(cmd) };
    }

    /// Draws one triangle covering the target (the `fullscreen.vert` shader) with
    /// `pipeline` and its descriptor sets, inside this pass.
    pub fn draw_fullscreen(
        &self,
        cmd: vk::CommandBuffer,
        pipeline: &super::GraphicsPipeline,
        (sets, push): (&[vk::DescriptorSet], &[u8]),
    ) {
        self.gpu.cmd_bind_graphics(cmd, pipeline, (sets, push));
        // SAFETY: cmd is inside this render pass, the pipeline was made for it and takes no
        // vertex input; it is bound with its sets.
        unsafe { self.gpu.device.cmd_draw(cmd, 3, 1, 0, 0) };
    }
}

impl Drop for AttachmentPass {
    fn drop(&mut self) {
        // SAFETY: no pending work uses them.
        unsafe {
            self.gpu
                .device
                .destroy_framebuffer(self.framebuffer, self.gpu.callbacks());
            self.gpu.forget_render_pass(self.render_pass);
            self.gpu
                .device
                .destroy_render_pass(self.render_pass, self.gpu.callbacks());
        }
    }
}

/// A render pass of one subpass over `descriptions`, writing the colour attachments
/// `colours` and testing against `depth`, ordered like the frame's own passes (see
/// RenderTarget), its definition noted on the device so that pipelines made for it are
/// shared with the passes it is compatible with.
pub(super) fn one_subpass_render_pass(
    gpu: &Gpu,
    descriptions: &[vk::AttachmentDescription],
    colours: &[vk::AttachmentReference],
    depth: Option<&vk::AttachmentReference>,
) -> Result<vk::RenderPass> {
    let mut subpass = vk::SubpassDescription::default()
        .pipeline_bind_point(vk::PipelineBindPoint::GRAPHICS)
        .color_attachments(colours);
    if let Some(d) = depth {
        subpass = subpass.depth_stencil_attachment(d);
    }
    let subpasses = [subpass];
    let dependencies = super::pipeline::external_dependencies();
    let info = vk::RenderPassCreateInfo::default()
        .attachments(descriptions)
        .subpasses(&subpasses)
        .dependencies(&dependencies);
    // SAFETY: valid device; every pointee lives for the call.
    let render_pass = unsafe { gpu.device.create_render_pass(&info, gpu.callbacks()) }
        .map_err(vk_err("vkCreateRenderPass"))?;
    gpu.note_render_pass(
        render_pass,
        super::pipeline::render_pass_definition(descriptions, colours.len(), depth.is_some()),
    );
    Ok(render_pass)
}

/// A pipeline for a full-screen pass (the `fullscreen.vert` triangle, no vertex input) with
/// descriptor sets `sets` (from set 0) and the given state.
pub fn fullscreen_pipeline(
    gpu: &Gpu,
    render_pass: vk::RenderPass,
    fragment: &[u8],
    (sets, push_bytes): (&[&super::DescriptorLayout], u32),
    state: &super::PipelineState<'_>,
) -> Result<std::sync::Arc<super::GraphicsPipeline>> {
    super::GraphicsPipeline::shared(
        gpu,
        &super::GraphicsPipelineDesc {
            vertex: crate::spirv!("scene/fullscreen.vert"),
            geometry: None,
            fragment,
            vertex_stride: 0,
            attributes: &[],
            cull_back: false,
            depth_write: false,
            blend: super::Blend::None,
            render_pass,
            sets,
            push_bytes,
        },
        &super::PipelineState {
            vertex_input: false,
            ..*state
        },
    )
}

impl Gpu {
    /// Binds graphics `pipeline` with its descriptor sets (from set 0, if any) and push
    /// constants (if any), inside a render pass it was made for.
    fn cmd_bind_graphics(
        &self,
        cmd: vk::CommandBuffer,
        pipeline: &super::GraphicsPipeline,
        (sets, push): (&[vk::DescriptorSet], &[u8]),
    ) {
        // SAFETY: cmd is inside a render pass compatible with the pipeline's; the sets and
        // push constants match its layout (vertex and fragment stages, as every graphics
        // pipeline's here).
        unsafe {
            let d = &self.device;
            d.cmd_bind_pipeline(cmd, vk::PipelineBindPoint::GRAPHICS, pipeline.raw);
            if !sets.is_empty() {
                d.cmd_bind_descriptor_sets(
                    cmd,
                    vk::PipelineBindPoint::GRAPHICS,
                    pipeline.layout,
                    0,
                    sets,
                    &[],
                );
            }
            if !push.is_empty() {
                d.cmd_push_constants(
                    cmd,
                    pipeline.layout,
                    vk::ShaderStageFlags::VERTEX | vk::ShaderStageFlags::FRAGMENT,
                    0,
                    push,
                );
            }
        }
    }

    /// Draws with `pipeline` (no vertex input), its descriptor sets (from set 0) and push
    /// constants, inside a render pass it was made for, as many vertices and instances as
    /// the `VkDrawIndirectCommand` at `offset` of `args` holds when the draw runs.
    pub fn cmd_draw_indirect(
        &self,
        cmd: vk::CommandBuffer,
        pipeline: &super::GraphicsPipeline,
        sets_and_push: (&[vk::DescriptorSet], &[u8]),
        (args, offset): (&super::Buffer, u64),
    ) {
        self.cmd_bind_graphics(cmd, pipeline, sets_and_push);
        // SAFETY: the pipeline is bound inside a render pass made for it; the command lies
        // within `args`, which has INDIRECT_BUFFER usage.
        unsafe { self.device.cmd_draw_indirect(cmd, args.raw, offset, 1, 16) };
    }

    /// Binds `set` as descriptor set `index` of graphics pipelines with `layout`. Sets bound
    /// later at lower indices with compatible layouts (the scene's sets 0 and 1) leave it bound.
    pub fn cmd_bind_graphics_set(
        &self,
        cmd: vk::CommandBuffer,
        layout: vk::PipelineLayout,
        index: u32,
        set: vk::DescriptorSet,
    ) {
        // SAFETY: cmd is recording; the caller passes a layout that has a set `index` matching
        // `set`'s layout.
        unsafe {
            self.device.cmd_bind_descriptor_sets(
                cmd,
                vk::PipelineBindPoint::GRAPHICS,
                layout,
                index,
                &[set],
                &[],
            )
        };
    }
}
