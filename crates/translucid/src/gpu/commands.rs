//! One-shot command buffers and barrier helpers.

use super::error::vk_err;
use super::{Buffer, Gpu, GpuImage};
use crate::{Error, Result};
use ash::vk;

impl Gpu {
    /// Records `record` into a fresh command buffer, submits it, waits for it, and then fails
    /// on any validation error the work produced.
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
        let alloc = vk::CommandBufferAllocateInfo::default()
            .command_pool(submission.command_pool)
            .level(vk::CommandBufferLevel::PRIMARY)
            .command_buffer_count(1);
        // SAFETY: the pool belongs to this device and is only used from &Gpu calls that wait
        // for their work before returning (one submission at a time per call).
        let cmd = unsafe { self.device.allocate_command_buffers(&alloc) }
            .map_err(vk_err("vkAllocateCommandBuffers"))?[0];
        let result = self.record_and_submit(submission.queue, cmd, record);
        // SAFETY: the submission (if any) was waited for; the buffer is idle.
        unsafe {
            self.device
                .free_command_buffers(submission.command_pool, &[cmd])
        };
        let value = result?;
        self.check_validation()?;
        Ok(value)
    }

    fn record_and_submit<T>(
        &self,
        queue: vk::Queue,
        cmd: vk::CommandBuffer,
        record: impl FnOnce(vk::CommandBuffer) -> Result<T>,
    ) -> Result<T> {
        let begin = vk::CommandBufferBeginInfo::default()
            .flags(vk::CommandBufferUsageFlags::ONE_TIME_SUBMIT);
        // SAFETY: cmd is a freshly allocated primary command buffer.
        unsafe { self.device.begin_command_buffer(cmd, &begin) }
            .map_err(vk_err("vkBeginCommandBuffer"))?;
        let value = record(cmd)?;
        // SAFETY: cmd is in the recording state.
        unsafe { self.device.end_command_buffer(cmd) }.map_err(vk_err("vkEndCommandBuffer"))?;
        // SAFETY: valid device; the fence is destroyed below after the wait.
        let fence = unsafe {
            self.device
                .create_fence(&vk::FenceCreateInfo::default(), None)
        }
        .map_err(vk_err("vkCreateFence"))?;
        let cmds = [cmd];
        let submit = [vk::SubmitInfo::default().command_buffers(&cmds)];
        // SAFETY: the command buffer is executable, the queue is ours and externally
        // synchronised by &self usage being one submission per call.
        let waited = unsafe {
            self.device
                .queue_submit(queue, &submit, fence)
                .map_err(vk_err("vkQueueSubmit"))
                .and_then(|_| {
                    self.device
                        .wait_for_fences(&[fence], true, u64::MAX)
                        .map_err(vk_err("vkWaitForFences"))
                })
        };
        // SAFETY: the fence is signalled or the submit failed; either way it is unused now.
        unsafe { self.device.destroy_fence(fence, None) };
        waited?;
        Ok(value)
    }

    /// Copies a whole single-mip 2D image (in TRANSFER_SRC_OPTIMAL) into a buffer.
    pub fn cmd_copy_image_to_buffer(
        &self,
        cmd: vk::CommandBuffer,
        image: &GpuImage,
        buffer: &Buffer,
    ) {
        let region = whole_image_region(image);
        // SAFETY: caller guarantees the image layout and that the buffer is large enough.
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
    /// Copies `buffer` (exactly mip 0's texels, tightly packed) into `image`, which must be in
    /// TRANSFER_DST_OPTIMAL.
    pub fn cmd_copy_buffer_to_image(
        &self,
        cmd: vk::CommandBuffer,
        buffer: &Buffer,
        image: &GpuImage,
    ) {
        let texel_bytes = match image.format {
            vk::Format::R16G16B16A16_SFLOAT => 8,
            _ => 4,
        };
        let needed = u64::from(image.extent.width) * u64::from(image.extent.height) * texel_bytes;
        assert!(
            buffer.size >= needed,
            "buffer of {} bytes for a {needed}-byte image",
            buffer.size
        );
        // SAFETY: cmd is recording outside a render pass, the buffer holds the whole level
        // (checked above) and the caller put the image in TRANSFER_DST_OPTIMAL.
        unsafe {
            self.device.cmd_copy_buffer_to_image(
                cmd,
                buffer.raw,
                image.raw,
                vk::ImageLayout::TRANSFER_DST_OPTIMAL,
                &[whole_image_region(image)],
            )
        };
    }

    /// Fills the whole buffer with a repeated 32-bit value (it needs TRANSFER_DST usage).
    pub fn cmd_fill_buffer(&self, cmd: vk::CommandBuffer, buffer: &Buffer, value: u32) {
        // SAFETY: cmd is recording outside a render pass; WHOLE_SIZE stays inside the buffer.
        unsafe {
            self.device
                .cmd_fill_buffer(cmd, buffer.raw, 0, vk::WHOLE_SIZE, value)
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

/// A copy region covering mip `level` of `image`, tightly packed at `buffer_offset`.
pub fn mip_region(image: &GpuImage, level: u32, buffer_offset: u64) -> vk::BufferImageCopy {
    vk::BufferImageCopy::default()
        .buffer_offset(buffer_offset)
        .image_subresource(vk::ImageSubresourceLayers {
            aspect_mask: image.aspect,
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
