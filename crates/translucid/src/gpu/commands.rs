//! Submitting recorded work and waiting for it, and barrier helpers.

use super::error::vk_err;
use super::{Buffer, Gpu, GpuImage};
use crate::{Error, Result};
use ash::vk;

impl Gpu {
    /// Records `record` into the device's command buffer, submits it, waits for it, and then
    /// fails on any validation error the work produced.
    pub fn submit_and_wait<T>(
        &self,
        record: impl FnOnce(vk::CommandBuffer) -> Result<T>,
    ) -> Result<T> {
        let Some(submission) = self.submission else {
            return Err(Error::HostFrame(
                "translucid never submits on the engine's device; this work must be recorded \
                 into the engine's command buffer"
                    .into(),
            ));
        };
        // A poisoned lock only means an earlier submission panicked: the reset below puts the
        // command buffer back in its initial state whatever that one left.
        let _submitting = self
            .submitting
            .lock()
            .unwrap_or_else(std::sync::PoisonError::into_inner);
        // SAFETY: the last submission was waited for (or never made), so the buffer is not
        // pending; the pool allows resetting single buffers.
        unsafe {
            self.device.reset_command_buffer(
                submission.command_buffer,
                vk::CommandBufferResetFlags::empty(),
            )
        }
        .map_err(vk_err("vkResetCommandBuffer"))?;
        let value = self.record_and_submit(submission, record)?;
        self.check_validation()?;
        Ok(value)
    }

    fn record_and_submit<T>(
        &self,
        submission: super::device::Submission,
        record: impl FnOnce(vk::CommandBuffer) -> Result<T>,
    ) -> Result<T> {
        let cmd = submission.command_buffer;
        let fence = submission.fence;
        let begin = vk::CommandBufferBeginInfo::default()
            .flags(vk::CommandBufferUsageFlags::ONE_TIME_SUBMIT);
        // SAFETY: cmd is in the initial state: reset before every submission.
        unsafe { self.device.begin_command_buffer(cmd, &begin) }
            .map_err(vk_err("vkBeginCommandBuffer"))?;
        let value = record(cmd)?;
        // SAFETY: cmd is in the recording state.
        unsafe { self.device.end_command_buffer(cmd) }.map_err(vk_err("vkEndCommandBuffer"))?;
        let cmds = [cmd];
        let submit = [vk::SubmitInfo::default().command_buffers(&cmds)];
        // SAFETY: the command buffer is executable; the queue and the fence are only used under
        // the `submitting` lock, and the fence is unsignalled (reset below after each wait).
        let waited = unsafe {
            self.device
                .queue_submit(submission.queue, &submit, fence)
                .map_err(vk_err("vkQueueSubmit"))
                .and_then(|_| {
                    self.device
                        .wait_for_fences(&[fence], true, u64::MAX)
                        .map_err(vk_err("vkWaitForFences"))
                })
                .and_then(|_| {
                    self.device
                        .reset_fences(&[fence])
                        .map_err(vk_err("vkResetFences"))
                })
        };
        waited?;
        Ok(value)
    }

    /// Copies the top-left `extent` of a single-mip 2D image (in TRANSFER_SRC_OPTIMAL) into
    /// a buffer, tightly packed.
    pub fn cmd_copy_image_to_buffer(
        &self,
        cmd: vk::CommandBuffer,
        image: &GpuImage,
        buffer: &Buffer,
        extent: vk::Extent2D,
    ) {
        let region = corner_region(image, extent);
        // SAFETY: caller guarantees the image layout and that the buffer is large enough;
        // the region lies within the image (corner_region).
        unsafe {
            self.device.cmd_copy_image_to_buffer(
                cmd,
                image.raw,
                vk::ImageLayout::TRANSFER_SRC_OPTIMAL,
                buffer.raw,
                &[region],
            )
        };
    }
}

impl Gpu {
    /// Copies `buffer` into the mip levels of `image` that `regions` name (one region a level,
    /// as [`mip_region`] makes them, texels tightly packed); the image must be in
    /// TRANSFER_DST_OPTIMAL.
    pub fn cmd_copy_buffer_to_image_levels(
        &self,
        cmd: vk::CommandBuffer,
        buffer: &Buffer,
        image: &GpuImage,
        regions: &[vk::BufferImageCopy],
    ) {
        let texel_bytes = match image.format {
            vk::Format::R16G16B16A16_SFLOAT => 8,
            vk::Format::D16_UNORM => 2,
            _ => 4,
        };
        let end = |r: &vk::BufferImageCopy| {
            r.buffer_offset
                + u64::from(r.image_extent.width) * u64::from(r.image_extent.height) * texel_bytes
        };
        assert!(
            regions.iter().all(|r| end(r) <= buffer.size),
            "a level's region runs past the {}-byte buffer",
            buffer.size
        );
        // SAFETY: cmd is recording outside a render pass, every region lies within the buffer
        // (checked above) and the caller put the image in TRANSFER_DST_OPTIMAL.
        unsafe {
            self.device.cmd_copy_buffer_to_image(
                cmd,
                buffer.raw,
                image.raw,
                vk::ImageLayout::TRANSFER_DST_OPTIMAL,
                regions,
            )
        };
    }

    /// Copies `buffer` (texels tightly packed) into the top-left `extent` of `image`'s first
    /// level, which must be in TRANSFER_DST_OPTIMAL.
    pub fn cmd_copy_buffer_to_image(
        &self,
        cmd: vk::CommandBuffer,
        buffer: &Buffer,
        image: &GpuImage,
        extent: vk::Extent2D,
    ) {
        self.cmd_copy_buffer_to_image_levels(cmd, buffer, image, &[corner_region(image, extent)]);
    }

    /// Overwrites the top-left `extent` of `image`'s first level with `buffer` (texels tightly
    /// packed), after whatever came before, and leaves the image in `layout` for what
    /// follows: an opaque layer's upload.
    pub fn cmd_upload_image(
        &self,
        cmd: vk::CommandBuffer,
        (image, extent): (&GpuImage, vk::Extent2D),
        buffer: &Buffer,
        layout: vk::ImageLayout,
    ) {
        let any = (
            vk::PipelineStageFlags::ALL_COMMANDS,
            vk::AccessFlags::MEMORY_READ | vk::AccessFlags::MEMORY_WRITE,
        );
        let transfer_write = (
            vk::PipelineStageFlags::TRANSFER,
            vk::AccessFlags::TRANSFER_WRITE,
        );
        let (undefined, dst) = (
            vk::ImageLayout::UNDEFINED,
            vk::ImageLayout::TRANSFER_DST_OPTIMAL,
        );
        image_barrier(self, cmd, image, undefined, dst, any, transfer_write);
        self.cmd_copy_buffer_to_image(cmd, buffer, image, extent);
        image_barrier(self, cmd, image, dst, layout, transfer_write, any);
    }

    /// Copies `bytes` bytes from the start of `src` to `dst` at `dst_offset` (TRANSFER_SRC and
    /// TRANSFER_DST usage).
    pub fn cmd_copy_buffer(
        &self,
        cmd: vk::CommandBuffer,
        src: &Buffer,
        dst: &Buffer,
        dst_offset: u64,
        bytes: u64,
    ) {
        let region = vk::BufferCopy {
            src_offset: 0,
            dst_offset,
            size: bytes,
        };
        self.cmd_copy_buffer_regions(cmd, src, dst, &[region]);
    }

    /// Copies `regions` of `src` into `dst` (TRANSFER_SRC and TRANSFER_DST usage).
    pub fn cmd_copy_buffer_regions(
        &self,
        cmd: vk::CommandBuffer,
        src: &Buffer,
        dst: &Buffer,
        regions: &[vk::BufferCopy],
    ) {
        for r in regions {
            assert!(
                r.src_offset + r.size <= src.size && r.dst_offset + r.size <= dst.size,
                "a {}-byte copy from offset {} of the {}-byte {} to offset {} of the {}-byte {}",
                r.size,
                r.src_offset,
                src.size,
                src.name,
                r.dst_offset,
                dst.size,
                dst.name
            );
        }
        // SAFETY: cmd is recording outside a render pass; every region lies within both
        // buffers (checked above).
        unsafe { self.device.cmd_copy_buffer(cmd, src.raw, dst.raw, regions) };
    }

    /// Fills the whole buffer with a repeated 32-bit value (it needs TRANSFER_DST usage).
    pub fn cmd_fill_buffer(&self, cmd: vk::CommandBuffer, buffer: &Buffer, value: u32) {
        // SAFETY: cmd is recording outside a render pass; WHOLE_SIZE stays inside the buffer.
        unsafe {
            self.device
                .cmd_fill_buffer(cmd, buffer.raw, 0, vk::WHOLE_SIZE, value)
        };
    }

    /// Clears every texel of a colour `image` in `layout` (GENERAL or TRANSFER_DST_OPTIMAL;
    /// it needs TRANSFER_DST usage) to zero.
    pub fn cmd_clear_to_zero(
        &self,
        cmd: vk::CommandBuffer,
        image: &GpuImage,
        layout: vk::ImageLayout,
    ) {
        let zero = vk::ClearColorValue { uint32: [0; 4] };
        // SAFETY: cmd is recording outside a render pass; the range is the image's own.
        unsafe {
            self.device
                .cmd_clear_color_image(cmd, image.raw, layout, &zero, &[image.full_range()])
        };
    }

    /// Writes `data` (a multiple of 4 bytes, at most 64 KiB) at `offset` from the command
    /// buffer itself (the buffer needs TRANSFER_DST usage).
    pub fn cmd_update_buffer(
        &self,
        cmd: vk::CommandBuffer,
        buffer: &Buffer,
        offset: u64,
        data: &[u8],
    ) {
        let end = offset + data.len() as u64;
        assert!(
            offset % 4 == 0 && data.len() % 4 == 0 && data.len() <= 65536 && end <= buffer.size,
            "update of {} bytes at {offset} into a {}-byte buffer",
            data.len(),
            buffer.size
        );
        // SAFETY: cmd is recording outside a render pass; the range was checked above.
        unsafe { self.device.cmd_update_buffer(cmd, buffer.raw, offset, data) };
    }
}

/// A copy region covering mip 0 of `image`, tightly packed in the buffer.
pub fn whole_image_region(image: &GpuImage) -> vk::BufferImageCopy {
    mip_region(image, 0, 0)
}

/// A copy region covering the top-left `extent` of `image`'s first level, tightly packed.
fn corner_region(image: &GpuImage, extent: vk::Extent2D) -> vk::BufferImageCopy {
    assert!(
        extent.width <= image.extent.width && extent.height <= image.extent.height,
        "a {}x{} copy of a {}x{} image",
        extent.width,
        extent.height,
        image.extent.width,
        image.extent.height
    );
    whole_image_region(image).image_extent(vk::Extent3D {
        width: extent.width,
        height: extent.height,
        depth: 1,
    })
}

/// A copy region covering mip `level` of `image`, tightly packed at `buffer_offset`.
pub fn mip_region(image: &GpuImage, level: u32, buffer_offset: u64) -> vk::BufferImageCopy {
    vk::BufferImageCopy::default()
        .buffer_offset(buffer_offset)
        .image_subresource(vk::ImageSubresourceLayers {
            aspect_mask: image.read_aspect(),
            mip_level: level,
            base_array_layer: 0,
            layer_count: 1,
        })
        .image_extent(vk::Extent3D {
            width: (image.extent.width >> level).max(1),
            height: (image.extent.height >> level).max(1),
            depth: 1,
        })
}

/// A layout transition (and execution/memory dependency) on every mip of `image`.
#[allow(clippy::too_many_arguments)]
pub fn image_barrier(
    gpu: &Gpu,
    cmd: vk::CommandBuffer,
    image: &GpuImage,
    old: vk::ImageLayout,
    new: vk::ImageLayout,
    src: (vk::PipelineStageFlags, vk::AccessFlags),
    dst: (vk::PipelineStageFlags, vk::AccessFlags),
) {
    let barrier = vk::ImageMemoryBarrier::default()
        .old_layout(old)
        .new_layout(new)
        .src_access_mask(src.1)
        .dst_access_mask(dst.1)
        .src_queue_family_index(vk::QUEUE_FAMILY_IGNORED)
        .dst_queue_family_index(vk::QUEUE_FAMILY_IGNORED)
        .image(image.raw)
        .subresource_range(image.full_range());
    // SAFETY: cmd is recording; the barrier names a live image of this device.
    unsafe {
        gpu.device.cmd_pipeline_barrier(
            cmd,
            src.0,
            dst.0,
            vk::DependencyFlags::empty(),
            &[],
            &[],
            &[barrier],
        )
    };
}

/// A side of a [`memory_barrier`]: the stages and the accesses it orders.
pub type Scope = (vk::PipelineStageFlags, vk::AccessFlags);

/// Every command's reads and writes: what an upload recorded anywhere in a queue's stream
/// must come after and before.
pub const ANY_ACCESS: Scope = (
    vk::PipelineStageFlags::ALL_COMMANDS,
    vk::AccessFlags::from_raw(
        vk::AccessFlags::MEMORY_READ.as_raw() | vk::AccessFlags::MEMORY_WRITE.as_raw(),
    ),
);
/// Copies' and updates' writes.
pub const TRANSFER_WRITE: Scope = (
    vk::PipelineStageFlags::TRANSFER,
    vk::AccessFlags::TRANSFER_WRITE,
);
/// Compute shaders' writes.
pub const COMPUTE_WRITE: Scope = (
    vk::PipelineStageFlags::COMPUTE_SHADER,
    vk::AccessFlags::SHADER_WRITE,
);
/// The host's reads of mapped memory, once the submission has completed.
pub const HOST_READ: Scope = (vk::PipelineStageFlags::HOST, vk::AccessFlags::HOST_READ);

/// A global memory dependency between two pipeline stages.
pub fn memory_barrier(
    gpu: &Gpu,
    cmd: vk::CommandBuffer,
    src: (vk::PipelineStageFlags, vk::AccessFlags),
    dst: (vk::PipelineStageFlags, vk::AccessFlags),
) {
    let barrier = vk::MemoryBarrier::default()
        .src_access_mask(src.1)
        .dst_access_mask(dst.1);
    // SAFETY: cmd is recording.
    unsafe {
        gpu.device.cmd_pipeline_barrier(
            cmd,
            src.0,
            dst.0,
            vk::DependencyFlags::empty(),
            &[barrier],
            &[],
            &[],
        )
    };
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::gpu::GpuOptions;

    /// Every submission reuses the device's one command buffer and fence: after a recording
    /// that failed half-way, and after a completed one, the next still records, submits and
    /// completes, without a validation error (the layer checks buffer and fence states).
    #[test]
    fn submissions_reuse_one_command_buffer_through_failures() {
        let gpu = Gpu::new(&GpuOptions {
            device: std::env::var("TRANSLUCID_DEVICE").ok(),
            validation: true,
            profile: None,
            software_sampling: false,
            ..Default::default()
        })
        .expect("a Vulkan device with the validation layer");
        let buffer = gpu
            .create_buffer(
                "submission test",
                16,
                vk::BufferUsageFlags::TRANSFER_DST,
                crate::gpu::MemoryLocation::GpuToCpu,
            )
            .expect("buffer");
        let mut seen = Vec::new();
        for value in [1u32, 2, 3] {
            let failed = gpu.submit_and_wait(|cmd| -> Result<()> {
                gpu.cmd_fill_buffer(cmd, &buffer, 0);
                Err(Error::Internal("a recording that fails".into()))
            });
            assert!(failed.is_err());
            let used = gpu.submit_and_wait(|cmd| {
                gpu.cmd_fill_buffer(cmd, &buffer, value);
                Ok(cmd)
            });
            seen.push(used.expect("submission after a failed recording"));
            let bytes = buffer.read().expect("read back");
            assert_eq!(bytes[..4], value.to_ne_bytes());
        }
        assert!(seen.iter().all(|&cmd| cmd == seen[0]), "{seen:?}");
    }
}
