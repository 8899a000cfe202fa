//! Frames over an opaque layer the engine gives in CPU memory: instead of drawing
//! `Scene::opaque`, the frame starts from colour and depth the engine already rendered,
//! uploaded into the frame targets. This is the C API's standalone mode with an engine's
//! opaque layer; on an engine's device (`host_device.rs`) the methods read its images where
//! they are.

use super::{Frame, FrameTargets, Renderer, COLOUR_FORMAT};
use crate::gpu::{vk, Buffer, Gpu};
use crate::image::OpaqueLayer;
use crate::{Error, Result};

impl OpaqueLayer {
    /// Checks sizes and values: colour in [0, 65504] (`shading::MAX_COLOUR`), depth in [0, 1] (a Vulkan
    /// depth buffer without unrestricted depth range holds nothing else).
    pub fn validate(&self, width: u32, height: u32) -> Result<()> {
        let bad = |msg: String| Err(Error::InvalidArgument(format!("opaque layer: {msg}")));
        if (self.width, self.height) != (width, height) {
            return bad(format!(
                "is {}x{}, the frame is {width}x{height}",
                self.width, self.height
            ));
        }
        let n = width as usize * height as usize;
        if self.colour.len() != n || self.depth.len() != n {
            return bad(format!(
                "has {} colours and {} depths for {n} pixels",
                self.colour.len(),
                self.depth.len()
            ));
        }
        if let Some(i) = self
            .colour
            .iter()
            .position(|c| !crate::shading::is_colour(c.extend(0.0)))
        {
            return bad(format!(
                "colour of pixel {i} is {:?}: each channel must be in [0, {}]",
                self.colour[i],
                crate::shading::MAX_COLOUR
            ));
        }
        if let Some(i) = self.depth.iter().position(|d| !(0.0..=1.0).contains(d)) {
            return bad(format!(
                "depth of pixel {i} is {}: must be in [0, 1]",
                self.depth[i]
            ));
        }
        Ok(())
    }

    /// The layer as images hold it: colour as R16G16B16A16_SFLOAT texels (alpha 1), depth as
    /// D32_SFLOAT texels, row by row.
    pub fn texels(&self) -> (Vec<u8>, Vec<u8>) {
        let colour = self
            .colour
            .iter()
            .flat_map(|c| [c.x, c.y, c.z, 1.0])
            .flat_map(|v| half::f16::from_f32(v).to_le_bytes())
            .collect();
        let depth = self.depth.iter().flat_map(|d| d.to_le_bytes()).collect();
        (colour, depth)
    }
}

impl Renderer {
    /// Renders one frame over `layer` instead of the scene's opaque draws (which are not
    /// drawn), re-rendering like [`Renderer::render`] when the method asks. The upload is timed
    /// as the "opaque" stage, so [`Frame::method_ms`] still measures the method alone.
    pub fn render_over(&mut self, layer: &OpaqueLayer) -> Result<Frame> {
        let extent = self.targets.extent;
        layer.validate(extent.width, extent.height)?;
        self.gpu.reset_peak_memory();
        let gpu = self.gpu.clone();
        debug_assert_eq!(COLOUR_FORMAT, vk::Format::R16G16B16A16_SFLOAT);
        let (colour, depth) = layer.texels();
        let src = vk::BufferUsageFlags::TRANSFER_SRC;
        let colour = gpu.create_buffer_with_data("host opaque colour", src, &colour)?;
        let depth = gpu.create_buffer_with_data("host opaque depth", src, &depth)?;
        self.run(super::OpaqueSource::Host {
            colour: &colour,
            depth: &depth,
        })
    }
}

/// Records the copies of the host's colour and depth into the frame targets, leaving them in
/// the layouts every method expects.
pub(super) fn record_upload(
    gpu: &Gpu,
    cmd: vk::CommandBuffer,
    targets: &FrameTargets,
    colour: &Buffer,
    depth: &Buffer,
) {
    let extent = targets.extent;
    let colour_layout = vk::ImageLayout::COLOR_ATTACHMENT_OPTIMAL;
    gpu.cmd_upload_image(cmd, (&targets.colour, extent), colour, colour_layout);
    let depth_layout = vk::ImageLayout::DEPTH_STENCIL_ATTACHMENT_OPTIMAL;
    gpu.cmd_upload_image(cmd, (&targets.depth, extent), depth, depth_layout);
}
