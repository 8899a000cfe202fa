//! The opaque-layer pass that fills the frame targets, and readback.

use crate::assets::GpuScene;
use crate::frame::FrameTargets;
use crate::gpu::{
    image_barrier, vk, Blend, Buffer, Gpu, GraphicsPipeline, MemoryLocation, RenderTarget,
};
use crate::image::{Image, OpaqueLayer};
use crate::Result;
use glam::{Vec3, Vec4};

/// Renders the opaque draws into cleared colour and depth.
pub struct OpaquePass {
    target: RenderTarget,
    pipelines: (
        std::sync::Arc<GraphicsPipeline>,
        std::sync::Arc<GraphicsPipeline>,
    ),
}

impl OpaquePass {
    pub fn new(gpu: &Gpu, targets: &FrameTargets, gpu_scene: &GpuScene) -> Result<Self> {
        let target = targets.render_target(gpu, true)?;
        let pipelines = gpu_scene.mesh_pipelines(
            gpu,
            target.render_pass,
            crate::spirv!("scene/opaque.frag"),
            true,
            Blend::None,
        )?;
        Ok(Self { target, pipelines })
    }

    pub fn record(
        &self,
        gpu: &Gpu,
        cmd: vk::CommandBuffer,
        (gpu_scene, targets): (&GpuScene, &FrameTargets),
        background: Vec3,
    ) {
        self.target
            .begin(cmd, targets.extent, background.extend(1.0).to_array());
        gpu_scene.draw(
            gpu,
            cmd,
            &gpu_scene.opaque_calls,
            (&self.pipelines.0, &self.pipelines.1),
        );
        self.target.end(cmd);
    }
}

/// Host-visible copies of the frame's colour (and optionally depth), with room for the
/// largest frame.
pub struct Readback {
    colour: Buffer,
    depth: Buffer,
    /// The size of the frame last recorded into the copies.
    extent: std::cell::Cell<vk::Extent2D>,
}

impl Readback {
    pub fn new(gpu: &Gpu, targets: &FrameTargets) -> Result<Self> {
        let pixels = targets.capacity_pixels();
        let dst = vk::BufferUsageFlags::TRANSFER_DST;
        Ok(Self {
            colour: gpu.create_buffer(
                "readback colour",
                pixels * 8,
                dst,
                MemoryLocation::GpuToCpu,
            )?,
            depth: gpu.create_buffer(
                "readback depth",
                pixels * 4,
                dst,
                MemoryLocation::GpuToCpu,
            )?,
            extent: std::cell::Cell::new(targets.extent),
        })
    }

    /// Records copies of the frame's colour (and depth when `with_depth`) into the readback
    /// buffers, returning the targets to their between-pass layouts.
    pub fn record(
        &self,
        gpu: &Gpu,
        cmd: vk::CommandBuffer,
        targets: &FrameTargets,
        with_depth: bool,
    ) {
        let attachment_write = (
            vk::PipelineStageFlags::ALL_COMMANDS,
            vk::AccessFlags::MEMORY_WRITE | vk::AccessFlags::MEMORY_READ,
        );
        let transfer_read = (
            vk::PipelineStageFlags::TRANSFER,
            vk::AccessFlags::TRANSFER_READ,
        );
        let mut images = vec![(
            &targets.colour,
            &self.colour,
            vk::ImageLayout::COLOR_ATTACHMENT_OPTIMAL,
        )];
        if with_depth {
            images.push((
                &targets.depth,
                &self.depth,
                vk::ImageLayout::DEPTH_STENCIL_ATTACHMENT_OPTIMAL,
            ));
        }
        self.extent.set(targets.extent);
        for (image, buffer, layout) in images {
            image_barrier(
                gpu,
                cmd,
                image,
                layout,
                vk::ImageLayout::TRANSFER_SRC_OPTIMAL,
                attachment_write,
                transfer_read,
            );
            gpu.cmd_copy_image_to_buffer(cmd, image, buffer, targets.extent);
            image_barrier(
                gpu,
                cmd,
                image,
                vk::ImageLayout::TRANSFER_SRC_OPTIMAL,
                layout,
                transfer_read,
                attachment_write,
            );
        }
        crate::gpu::memory_barrier(
            gpu,
            cmd,
            (
                vk::PipelineStageFlags::TRANSFER,
                vk::AccessFlags::TRANSFER_WRITE,
            ),
            (vk::PipelineStageFlags::HOST, vk::AccessFlags::HOST_READ),
        );
    }

    /// The colour copy as a linear image (alpha forced to 1).
    pub fn colour(&self) -> Result<Image> {
        let extent = self.extent.get();
        let pixels = extent.width as usize * extent.height as usize;
        let bytes = &self.colour.read()?[..pixels * 8];
        let pixels = bytes
            .chunks_exact(8)
            .map(|p| {
                let c = |i: usize| half::f16::from_le_bytes([p[2 * i], p[2 * i + 1]]).to_f32();
                Vec4::new(c(0), c(1), c(2), 1.0)
            })
            .collect();
        Ok(Image {
            width: extent.width,
            height: extent.height,
            pixels,
        })
    }

    /// The colour and depth copies as an opaque layer.
    pub fn opaque_layer(&self) -> Result<OpaqueLayer> {
        let colour = self.colour()?;
        let pixels = colour.pixels.len();
        let depth = self.depth.read()?[..pixels * 4]
            .chunks_exact(4)
            .map(|d| f32::from_le_bytes([d[0], d[1], d[2], d[3]]))
            .collect();
        Ok(OpaqueLayer {
            width: colour.width,
            height: colour.height,
            colour: colour.pixels.iter().map(|p| p.truncate()).collect(),
            depth,
        })
    }
}
