//! An engine's colour and depth images as translucid's bench and tests play an engine on its
//! device: made with the usages the header lists, filled each frame by the engine's "opaque
//! pass" (a copy of an opaque layer's texels), handed to a frame as [`HostTargets`], and
//! read back after the frame where a test wants the pixels. The C tests and examples play the
//! same engine in C (`examples-c/engine.c`).

use super::{memory_barrier, vk, Buffer, Gpu, GpuImage, HostImage, HostTargets, MemoryLocation};
use crate::{Image, OpaqueLayer, Result};

/// The engine's colour format.
pub const ENGINE_COLOUR_FORMAT: vk::Format = vk::Format::R16G16B16A16_SFLOAT;
/// Where the engine's opaque pass leaves its images, as a render pass would.
const COLOUR_ATTACHMENT: vk::ImageLayout = vk::ImageLayout::COLOR_ATTACHMENT_OPTIMAL;
const DEPTH_ATTACHMENT: vk::ImageLayout = vk::ImageLayout::DEPTH_STENCIL_ATTACHMENT_OPTIMAL;

pub struct EngineImages {
    pub colour: GpuImage,
    pub depth: GpuImage,
    pub depth_format: vk::Format,
    /// The opaque layer's texels, which the opaque pass copies into the images.
    pub colour_in: Buffer,
    pub depth_in: Buffer,
    /// One readback of the colour per frame in flight (none: the frame leaves the colour as
    /// an attachment, as the engine's next pass wants it).
    pub outs: Vec<Buffer>,
    pub extent: vk::Extent2D,
    /// The layouts the opaque pass leaves colour and depth in, and frames leave depth in.
    layouts: (vk::ImageLayout, vk::ImageLayout),
}

impl EngineImages {
    /// Images of `extent` on `gpu`, depth in `depth_format`, with `readbacks` colour
    /// readbacks; the opaque pass copies what [`Self::set_opaque`] wrote last (zeros before).
    pub fn new(
        gpu: &Gpu,
        extent: vk::Extent2D,
        depth_format: vk::Format,
        readbacks: usize,
    ) -> Result<Self> {
        let pixels = u64::from(extent.width) * u64::from(extent.height);
        let transfer = vk::ImageUsageFlags::TRANSFER_SRC | vk::ImageUsageFlags::TRANSFER_DST;
        let upload = |name, bytes| {
            gpu.create_buffer(
                name,
                bytes,
                vk::BufferUsageFlags::TRANSFER_SRC,
                MemoryLocation::CpuToGpu,
            )
        };
        let depth_bytes = pixels * u64::from(texel_bytes(depth_format));
        Ok(Self {
            colour: gpu.create_image(
                "engine colour",
                extent,
                ENGINE_COLOUR_FORMAT,
                transfer | vk::ImageUsageFlags::COLOR_ATTACHMENT,
                1,
            )?,
            depth: gpu.create_image(
                "engine depth",
                extent,
                depth_format,
                transfer
                    | vk::ImageUsageFlags::DEPTH_STENCIL_ATTACHMENT
                    | vk::ImageUsageFlags::SAMPLED,
                1,
            )?,
            depth_format,
            colour_in: upload("engine opaque colour", 8 * pixels)?,
            depth_in: upload("engine opaque depth", depth_bytes)?,
            outs: (0..readbacks)
                .map(|_| {
                    gpu.create_buffer(
                        "engine readback",
                        8 * pixels,
                        vk::BufferUsageFlags::TRANSFER_DST,
                        MemoryLocation::GpuToCpu,
                    )
                })
                .collect::<Result<_>>()?,
            extent,
            layouts: (COLOUR_ATTACHMENT, DEPTH_ATTACHMENT),
        })
    }

    /// Images of `layer`'s size holding it (D32_SFLOAT depth), with `readbacks` readbacks.
    pub fn of_layer(gpu: &Gpu, layer: &OpaqueLayer, readbacks: usize) -> Result<Self> {
        let mut images = Self::new(gpu, extent_of(layer), vk::Format::D32_SFLOAT, readbacks)?;
        images.set_opaque(layer)?;
        Ok(images)
    }

    /// Images of `layer`'s size holding its colour and depth `depth_texels` in
    /// `depth_format` (the layer's own depth left out).
    pub fn of_layer_with_depth(
        gpu: &Gpu,
        layer: &OpaqueLayer,
        readbacks: usize,
        depth_format: vk::Format,
        depth_texels: &[u8],
    ) -> Result<Self> {
        let mut images = Self::new(gpu, extent_of(layer), depth_format, readbacks)?;
        images.colour_in.write(0, &layer.texels().0)?;
        images.depth_in.write(0, depth_texels)?;
        Ok(images)
    }

    /// The same images, the opaque pass leaving colour and depth in `colour` and `depth`
    /// layouts.
    pub fn in_layouts(self, colour: vk::ImageLayout, depth: vk::ImageLayout) -> Self {
        Self {
            layouts: (colour, depth),
            ..self
        }
    }

    /// What the next opaque passes copy into the images: `layer`, of the images' size.
    pub fn set_opaque(&mut self, layer: &OpaqueLayer) -> Result<()> {
        let (colour, depth) = layer.texels();
        self.colour_in.write(0, &colour)?;
        self.depth_in.write(0, &depth)
    }

    /// The frame targets over these images, recorded into `cmd`. With readbacks the frame
    /// leaves the colour ready to copy; without, as an attachment.
    pub fn targets(&self, cmd: vk::CommandBuffer) -> HostTargets {
        let colour_final = if self.outs.is_empty() {
            self.layouts.0
        } else {
            vk::ImageLayout::TRANSFER_SRC_OPTIMAL
        };
        HostTargets {
            cmd,
            colour: HostImage {
                image: self.colour.raw,
                format: ENGINE_COLOUR_FORMAT,
                layout: self.layouts.0,
                final_layout: colour_final,
                layer: 0,
                origin: vk::Offset2D::default(),
            },
            depth: HostImage {
                image: self.depth.raw,
                format: self.depth_format,
                layout: self.layouts.1,
                final_layout: self.layouts.1,
                layer: 0,
                origin: vk::Offset2D::default(),
            },
        }
    }

    /// The engine's opaque pass: the opaque texels into its images, left in its layouts.
    pub fn record_opaque(&self, gpu: &Gpu, cmd: vk::CommandBuffer) {
        let (colour, depth) = ((&self.colour, self.extent), (&self.depth, self.extent));
        gpu.cmd_upload_image(cmd, colour, &self.colour_in, self.layouts.0);
        gpu.cmd_upload_image(cmd, depth, &self.depth_in, self.layouts.1);
    }

    /// Copies the colour image (left ready to copy by the frame) into readback `k` for the
    /// host.
    pub fn record_readback(&self, gpu: &Gpu, cmd: vk::CommandBuffer, k: usize) {
        gpu.cmd_copy_image_to_buffer(cmd, &self.colour, &self.outs[k], self.extent);
        memory_barrier(
            gpu,
            cmd,
            (
                vk::PipelineStageFlags::TRANSFER,
                vk::AccessFlags::TRANSFER_WRITE,
            ),
            (vk::PipelineStageFlags::HOST, vk::AccessFlags::HOST_READ),
        );
    }

    /// Readback `k` as sRGB bytes, after the frame that wrote it completed.
    pub fn srgb(&self, k: usize) -> Result<Vec<u8>> {
        let bytes = self.outs[k].read()?;
        let pixels = bytes
            .chunks_exact(8)
            .map(|p| {
                let c = |i: usize| half::f16::from_le_bytes([p[2 * i], p[2 * i + 1]]).to_f32();
                glam::Vec4::new(c(0), c(1), c(2), 1.0)
            })
            .collect();
        Ok(Image {
            width: self.extent.width,
            height: self.extent.height,
            pixels,
        }
        .to_srgb8())
    }
}

fn extent_of(layer: &OpaqueLayer) -> vk::Extent2D {
    vk::Extent2D {
        width: layer.width,
        height: layer.height,
    }
}

/// Bytes of a depth texel as the opaque pass copies it (stencil left out).
fn texel_bytes(format: vk::Format) -> u32 {
    match format {
        vk::Format::D16_UNORM => 2,
        _ => 4,
    }
}
