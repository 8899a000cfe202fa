//! A render pass straight over the engine's own colour image, and depth image if it tests
//! depth: colour loaded and stored, depth (and stencil) loaded and kept, read-only. Each
//! frame makes views of the engine's images and a framebuffer over them (the engine may hand
//! different images every frame), kept until the frame slot is recorded again, when that
//! frame has completed. (The composite over translucid's own colour target uses it too,
//! described as an engine image.)

use super::error::vk_err;
use super::host::depth_format_aspects;
use super::{Gpu, HostImage};
use crate::Result;
use ash::vk;

/// The views and framebuffer one frame drew through, destroyed with it.
struct FrameViews {
    gpu: Gpu,
    views: Vec<vk::ImageView>,
    framebuffer: vk::Framebuffer,
}

impl Drop for FrameViews {
    fn drop(&mut self) {
        // SAFETY: kept until the frame that drew through them completed (see `EnginePass`).
        unsafe {
            self.gpu
                .device
                .destroy_framebuffer(self.framebuffer, self.gpu.callbacks());
            for &view in &self.views {
                self.gpu
                    .device
                    .destroy_image_view(view, self.gpu.callbacks());
            }
        }
    }
}

/// What makes two engine passes the same render pass: formats and layouts.
#[derive(Clone, Copy, PartialEq, Eq)]
struct PassKey {
    colour: (vk::Format, vk::ImageLayout, vk::ImageLayout),
    depth: Option<(vk::Format, vk::ImageLayout, vk::ImageLayout)>,
}

impl PassKey {
    fn of(colour: &HostImage, depth: Option<&HostImage>) -> Self {
        let key = |i: &HostImage| (i.format, i.layout, i.final_layout);
        Self {
            colour: key(colour),
            depth: depth.map(key),
        }
    }
}

/// A view of one of the engine's images: `aspect` of its one level and the frame's layer.
fn engine_view(
    gpu: &Gpu,
    image: &HostImage,
    aspect: vk::ImageAspectFlags,
) -> Result<vk::ImageView> {
    let info = vk::ImageViewCreateInfo::default()
        .image(image.image)
        .view_type(vk::ImageViewType::TYPE_2D)
        .format(image.format)
        .subresource_range(vk::ImageSubresourceRange {
            aspect_mask: aspect,
            base_mip_level: 0,
            level_count: 1,
            base_array_layer: image.layer,
            layer_count: 1,
        });
    // SAFETY: the engine's live image of this device, of the format named (the record_host
    // contract), with one level and at least `layer + 1` layers.
    unsafe { gpu.device.create_image_view(&info, gpu.callbacks()) }
        .map_err(vk_err("vkCreateImageView"))
}

/// Per frame slot, a view of the engine's depth image (its depth aspect, for sampling) made
/// for the frame recorded in it, kept until the slot is recorded again.
pub struct EngineDepthViews {
    gpu: Gpu,
    slots: Vec<Option<FrameViews>>,
}

impl EngineDepthViews {
    pub fn new(gpu: &Gpu, slots: usize) -> Self {
        Self {
            gpu: gpu.clone(),
            slots: (0..slots).map(|_| None).collect(),
        }
    }

    /// A view of `depth` for the frame recorded in `slot`, whose last frame has completed.
    pub fn view(&mut self, slot: usize, depth: &HostImage) -> Result<vk::ImageView> {
        // Frees the slot's last view first: that frame has completed.
        self.slots[slot] = None;
        let view = engine_view(&self.gpu, depth, vk::ImageAspectFlags::DEPTH)?;
        self.slots[slot] = Some(FrameViews {
            gpu: self.gpu.clone(),
            views: vec![view],
            framebuffer: vk::Framebuffer::null(),
        });
        Ok(view)
    }
}

pub struct EnginePass {
    gpu: Gpu,
    key: PassKey,
    pub render_pass: vk::RenderPass,
    /// Per frame slot, what its last frame drew through.
    slots: Vec<Option<FrameViews>>,
}

impl EnginePass {
    /// A pass over images like `colour` and `depth` (their formats and layouts), for `slots`
    /// frames in flight.
    pub fn new(
        gpu: &Gpu,
        colour: &HostImage,
        depth: Option<&HostImage>,
        slots: usize,
    ) -> Result<Self> {
        let key = PassKey::of(colour, depth);
        let attachment = |image: &HostImage| {
            vk::AttachmentDescription::default()
                .format(image.format)
                .samples(vk::SampleCountFlags::TYPE_1)
                .load_op(vk::AttachmentLoadOp::LOAD)
                .store_op(vk::AttachmentStoreOp::STORE)
                // The engine's stencil is its own: kept as it is.
                .stencil_load_op(vk::AttachmentLoadOp::LOAD)
                .stencil_store_op(vk::AttachmentStoreOp::STORE)
                .initial_layout(image.layout)
                .final_layout(image.final_layout)
        };
        let mut descriptions = vec![attachment(colour)];
        descriptions.extend(depth.map(attachment));
        let colour = [vk::AttachmentReference {
            attachment: 0,
            layout: vk::ImageLayout::COLOR_ATTACHMENT_OPTIMAL,
        }];
        let depth = depth.map(|_| vk::AttachmentReference {
            attachment: 1,
            layout: vk::ImageLayout::DEPTH_STENCIL_READ_ONLY_OPTIMAL,
        });
        let render_pass = super::attachments::one_subpass_render_pass(
            gpu,
            &descriptions,
            &colour,
            depth.as_ref(),
        )?;
        Ok(Self {
            gpu: gpu.clone(),
            key,
            render_pass,
            slots: (0..slots).map(|_| None).collect(),
        })
    }

    /// Whether this pass draws over images like `colour` and `depth`.
    pub fn fits(&self, colour: &HostImage, depth: Option<&HostImage>) -> bool {
        self.key == PassKey::of(colour, depth)
    }

    /// Begins the pass in `cmd` over `extent` pixels of `colour` and `depth` from their
    /// origin (images like the pass's, checked to hold them) for the frame recorded in `slot`,
    /// whose last frame has completed. The viewport maps depth as the engine's image holds
    /// it: turned around when `reversed` (the pipelines then test GREATER).
    pub fn begin(
        &mut self,
        cmd: vk::CommandBuffer,
        (colour, depth): (&HostImage, Option<&HostImage>),
        slot: usize,
        (extent, reversed): (vk::Extent2D, bool),
    ) -> Result<()> {
        let view = |image: &HostImage, aspect| engine_view(&self.gpu, image, aspect);
        // Frees the slot's last views first: that frame has completed.
        self.slots[slot] = None;
        // Dropped with its views if a later one fails.
        let mut frame = FrameViews {
            gpu: self.gpu.clone(),
            views: Vec::with_capacity(2),
            framebuffer: vk::Framebuffer::null(),
        };
        frame.views.push(view(colour, vk::ImageAspectFlags::COLOR)?);
        if let Some(depth) = depth {
            let aspects = depth_format_aspects(depth.format);
            frame.views.push(view(depth, aspects)?);
        }
        // The frame's pixels from its origin (the same in both images).
        let origin = colour.origin;
        let info = vk::FramebufferCreateInfo::default()
            .render_pass(self.render_pass)
            .attachments(&frame.views)
            .width(origin.x as u32 + extent.width)
            .height(origin.y as u32 + extent.height)
            .layers(1);
        // SAFETY: the views are live, single-level and match the pass's formats.
        frame.framebuffer = unsafe {
            self.gpu
                .device
                .create_framebuffer(&info, self.gpu.callbacks())
        }
        .map_err(vk_err("vkCreateFramebuffer"))?;
        let framebuffer = frame.framebuffer;
        self.slots[slot] = Some(frame);

        let area = vk::Rect2D {
            offset: origin,
            extent,
        };
        let begin = vk::RenderPassBeginInfo::default()
            .render_pass(self.render_pass)
            .framebuffer(framebuffer)
            .render_area(area);
        let (min_depth, max_depth) = if reversed { (1.0, 0.0) } else { (0.0, 1.0) };
        let viewport = vk::Viewport {
            x: origin.x as f32,
            y: origin.y as f32,
            width: extent.width as f32,
            height: extent.height as f32,
            min_depth,
            max_depth,
        };
        // SAFETY: cmd is recording outside any render pass (the record_host contract); the
        // framebuffer belongs to this pass.
        unsafe {
            let d = &self.gpu.device;
            d.cmd_begin_render_pass(cmd, &begin, vk::SubpassContents::INLINE);
            d.cmd_set_viewport(cmd, 0, &[viewport]);
            d.cmd_set_scissor(cmd, 0, &[area]);
        }
        Ok(())
    }

    pub fn end(&self, cmd: vk::CommandBuffer) {
        // SAFETY: cmd is inside this render pass.
        unsafe { self.gpu.device.cmd_end_render_pass(cmd) };
    }
}

impl Drop for EnginePass {
    fn drop(&mut self) {
        self.slots.clear();
        // SAFETY: no pending work uses it (the renderer outlives its frames in flight).
        unsafe {
            self.gpu.forget_render_pass(self.render_pass);
            self.gpu
                .device
                .destroy_render_pass(self.render_pass, self.gpu.callbacks());
        }
    }
}
