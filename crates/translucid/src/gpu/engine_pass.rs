//! A render pass straight over the engine's own colour and depth images: colour loaded and
//! stored, depth (and stencil) loaded and kept, read-only. Each frame makes views of the
//! engine's images and a framebuffer over them (the engine may hand different images every
//! frame), kept until the frame slot is recorded again, when that frame has completed.

use super::error::vk_err;
use super::host::depth_format_aspects;
use super::{Gpu, HostImage, HostTargets};
use crate::Result;
use ash::vk;

/// The views and framebuffer one frame drew through, destroyed with it.
struct FrameViews {
    gpu: Gpu,
    views: [vk::ImageView; 2],
    framebuffer: vk::Framebuffer,
}

impl Drop for FrameViews {
    fn drop(&mut self) {
        // SAFETY: kept until the frame that drew through them completed (see `EnginePass`).
        unsafe {
            self.gpu.device.destroy_framebuffer(self.framebuffer, None);
            for view in self.views {
                self.gpu.device.destroy_image_view(view, None);
            }
        }
    }
}

/// What makes two engine passes the same render pass: formats and layouts.
#[derive(Clone, Copy, PartialEq, Eq)]
struct PassKey {
    colour: (vk::Format, vk::ImageLayout, vk::ImageLayout),
    depth: (vk::Format, vk::ImageLayout, vk::ImageLayout),
}

impl PassKey {
    fn of(targets: &HostTargets) -> Self {
        let key = |i: &HostImage| (i.format, i.layout, i.final_layout);
        Self {
            colour: key(&targets.colour),
            depth: key(&targets.depth),
        }
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
    /// A pass over images like `targets`' (their formats and layouts), for `slots` frames
    /// in flight.
    pub fn new(gpu: &Gpu, targets: &HostTargets, slots: usize) -> Result<Self> {
        let key = PassKey::of(targets);
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
        let descriptions = [attachment(&targets.colour), attachment(&targets.depth)];
        let colour = [vk::AttachmentReference {
            attachment: 0,
            layout: vk::ImageLayout::COLOR_ATTACHMENT_OPTIMAL,
        }];
        let depth = vk::AttachmentReference {
            attachment: 1,
            layout: vk::ImageLayout::DEPTH_STENCIL_READ_ONLY_OPTIMAL,
        };
        let render_pass =
            super::attachments::one_subpass_render_pass(gpu, &descriptions, &colour, Some(&depth))?;
        Ok(Self {
            gpu: gpu.clone(),
            key,
            render_pass,
            slots: (0..slots).map(|_| None).collect(),
        })
    }

    /// Whether this pass draws over images like `targets'`.
    pub fn fits(&self, targets: &HostTargets) -> bool {
        self.key == PassKey::of(targets)
    }

    /// Begins the pass over the top-left `extent` of `targets`' images (checked, at least
    /// that large) for the frame recorded in `slot`, whose last frame has completed. The
    /// viewport maps depth as the engine's image holds it: turned around when `reversed`
    /// (the pipelines then test GREATER).
    pub fn begin(
        &mut self,
        targets: &HostTargets,
        slot: usize,
        extent: vk::Extent2D,
        reversed: bool,
    ) -> Result<()> {
        let view = |image: &HostImage, aspect| {
            let info = vk::ImageViewCreateInfo::default()
                .image(image.image)
                .view_type(vk::ImageViewType::TYPE_2D)
                .format(image.format)
                .subresource_range(vk::ImageSubresourceRange {
                    aspect_mask: aspect,
                    base_mip_level: 0,
                    level_count: 1,
                    base_array_layer: 0,
                    layer_count: 1,
                });
            // SAFETY: the engine's live image of this device, of the format named (the
            // record_host contract), with one level and one layer.
            unsafe { self.gpu.device.create_image_view(&info, None) }
                .map_err(vk_err("vkCreateImageView"))
        };
        // Frees the slot's last views first: that frame has completed.
        self.slots[slot] = None;
        let colour = view(&targets.colour, vk::ImageAspectFlags::COLOR)?;
        let depth = match view(&targets.depth, depth_format_aspects(targets.depth.format)) {
            Ok(v) => v,
            Err(e) => {
                // SAFETY: made above, used by nothing yet.
                unsafe { self.gpu.device.destroy_image_view(colour, None) };
                return Err(e);
            }
        };
        let mut frame = FrameViews {
            gpu: self.gpu.clone(),
            views: [colour, depth],
            framebuffer: vk::Framebuffer::null(),
        };
        let info = vk::FramebufferCreateInfo::default()
            .render_pass(self.render_pass)
            .attachments(&frame.views)
            .width(extent.width)
            .height(extent.height)
            .layers(1);
        // SAFETY: the views are live, single-level and match the pass's formats.
        frame.framebuffer = unsafe { self.gpu.device.create_framebuffer(&info, None) }
            .map_err(vk_err("vkCreateFramebuffer"))?;
        let framebuffer = frame.framebuffer;
        self.slots[slot] = Some(frame);

        let area = vk::Rect2D {
            offset: vk::Offset2D::default(),
            extent,
        };
        let begin = vk::RenderPassBeginInfo::default()
            .render_pass(self.render_pass)
            .framebuffer(framebuffer)
            .render_area(area);
        let (min_depth, max_depth) = if reversed { (1.0, 0.0) } else { (0.0, 1.0) };
        let viewport = vk::Viewport {
            x: 0.0,
            y: 0.0,
            width: extent.width as f32,
            height: extent.height as f32,
            min_depth,
            max_depth,
        };
        // SAFETY: cmd is recording outside any render pass (the record_host contract); the
        // framebuffer belongs to this pass.
        unsafe {
            let d = &self.gpu.device;
            d.cmd_begin_render_pass(targets.cmd, &begin, vk::SubpassContents::INLINE);
            d.cmd_set_viewport(targets.cmd, 0, &[viewport]);
            d.cmd_set_scissor(targets.cmd, 0, &[area]);
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
            self.gpu.device.destroy_render_pass(self.render_pass, None);
        }
    }
}
