//! What a frame is drawn into and by: the colour and depth targets every method receives and
//! returns. Used by the renderer and by the methods, so that neither imports the other.

#![deny(unsafe_code)]

use crate::gpu::{vk, Gpu, GpuImage, RenderTarget, RenderTargetDesc};
use crate::Result;
/// Colour is linear RGBA16F: blending into 8 bits would pile rounding up per layer.
pub const COLOUR_FORMAT: vk::Format = vk::Format::R16G16B16A16_SFLOAT;
pub const DEPTH_FORMAT: vk::Format = vk::Format::D32_SFLOAT;

/// Colour and depth of the frames, made for the largest. Between passes the colour image is
/// in COLOR_ATTACHMENT_OPTIMAL and depth in DEPTH_STENCIL_ATTACHMENT_OPTIMAL: every method
/// receives and returns them so. A frame smaller than the images draws into their top-left
/// corner; the pixels outside it are undefined.
pub struct FrameTargets {
    pub colour: GpuImage,
    pub depth: GpuImage,
    /// The size of the frame being drawn: what passes cover and dispatches span.
    pub extent: vk::Extent2D,
    /// The size of the images, the largest frame: what buffers per pixel are made for.
    pub capacity: vk::Extent2D,
}

impl FrameTargets {
    /// Targets for frames of up to `width` x `height`, the current frame that large.
    pub fn new(gpu: &Gpu, width: u32, height: u32) -> Result<Self> {
        let extent = vk::Extent2D { width, height };
        let colour = gpu.create_image(
            "frame colour",
            extent,
            COLOUR_FORMAT,
            vk::ImageUsageFlags::COLOR_ATTACHMENT
                | vk::ImageUsageFlags::TRANSFER_SRC
                | vk::ImageUsageFlags::TRANSFER_DST
                | vk::ImageUsageFlags::STORAGE
                | vk::ImageUsageFlags::SAMPLED,
            1,
        )?;
        let depth = gpu.create_image(
            "frame depth",
            extent,
            DEPTH_FORMAT,
            vk::ImageUsageFlags::DEPTH_STENCIL_ATTACHMENT
                | vk::ImageUsageFlags::TRANSFER_SRC
                | vk::ImageUsageFlags::TRANSFER_DST
                | vk::ImageUsageFlags::SAMPLED,
            1,
        )?;
        Ok(Self {
            colour,
            depth,
            extent,
            capacity: extent,
        })
    }

    /// Makes `extent` the size of the frames drawn from now on: at least 1x1, and within the
    /// images' size.
    pub fn set_extent(&mut self, extent: vk::Extent2D) -> Result<()> {
        let capacity = self.capacity;
        if extent.width == 0
            || extent.height == 0
            || extent.width > capacity.width
            || extent.height > capacity.height
        {
            return Err(crate::Error::InvalidViewport {
                width: extent.width,
                height: extent.height,
                reason: format!(
                    "the renderer was made for frames of 1x1 up to {}x{}",
                    capacity.width, capacity.height
                ),
            });
        }
        self.extent = extent;
        Ok(())
    }

    /// A render pass and framebuffer over these targets that leaves them in the between-pass
    /// layouts. With `clear` it starts from nothing (and stores depth: the opaque layer);
    /// otherwise it loads both and only reads depth (a transparent pass).
    pub fn render_target(&self, gpu: &Gpu, clear: bool) -> Result<RenderTarget> {
        let colour = vk::ImageLayout::COLOR_ATTACHMENT_OPTIMAL;
        let depth = vk::ImageLayout::DEPTH_STENCIL_ATTACHMENT_OPTIMAL;
        let before = |layout| {
            if clear {
                vk::ImageLayout::UNDEFINED
            } else {
                layout
            }
        };
        RenderTarget::new(
            gpu,
            &RenderTargetDesc {
                colour_format: COLOUR_FORMAT,
                depth_format: DEPTH_FORMAT,
                clear,
                store_depth: clear,
                colour_layouts: (before(colour), colour),
                depth_layouts: (before(depth), depth),
            },
            &self.colour,
            &self.depth,
        )
    }

    /// Pixels of the largest frame.
    pub fn capacity_pixels(&self) -> u64 {
        u64::from(self.capacity.width) * u64::from(self.capacity.height)
    }
}
