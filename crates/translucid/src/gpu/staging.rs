//! Device-local memory filled by copies (docs/gpu.md, "Memory"): what the shaders read every
//! frame but the host writes once (a scene's assets) lives in device-local memory, which the
//! host cannot write on a discrete GPU. An [`Upload`] carries data there: from a host-visible
//! staging buffer by `vkCmdCopyBuffer` (or, for a texture, `vkCmdCopyBufferToImage`), or,
//! for a buffer range of at most 64 KiB, inside the command buffer itself
//! (`vkCmdUpdateBuffer`), which needs no staging memory at all; each between barriers that
//! order it after every command before it on the queue and before every command after it.
//!
//! [`Uploads`] runs them: on translucid's own device at once (one submission, waited for,
//! the staging freed); on an engine's device, which translucid never submits to, the next
//! frame recorded into the engine's command buffer carries them, and they are kept (staging
//! and all) until that frame is known to have completed. A frame that was recorded but
//! never ran (abandoned: its recorder is dropped without completing it, or its recording
//! failed) leaves them pending for the next frame.

use super::{image_barrier, memory_barrier, mip_region, vk, Buffer, Gpu, GpuImage, MemoryLocation};
use super::{Scope, ANY_ACCESS, TRANSFER_WRITE};
use crate::Result;
use std::sync::{Arc, Mutex};

/// The most bytes a buffer upload carries inside the command buffer (`vkCmdUpdateBuffer`'s
/// limit); larger ones go through a staging buffer.
pub const INLINE_BYTES: usize = 65536;

/// Data on its way into a device-local buffer range or a texture's mips. It keeps its
/// destination alive, so that it can be recorded (again) while it is kept.
pub struct Upload {
    source: Source,
    target: Target,
}

enum Source {
    /// Carried by the command buffer.
    Inline(Vec<u8>),
    /// A host-visible staging buffer holding the data (this many bytes of it: a buffer has
    /// at least 16).
    Staged(Buffer, u64),
}

enum Target {
    Buffer {
        buffer: Arc<Buffer>,
        offset: u64,
    },
    /// Every mip of the image, level 0 first, tightly packed RGBA8.
    Image(Arc<GpuImage>),
}

impl Upload {
    /// `data` into `buffer` (made with TRANSFER_DST usage) at `offset`.
    pub fn to_buffer(gpu: &Gpu, buffer: &Arc<Buffer>, offset: u64, data: &[u8]) -> Result<Self> {
        let end = offset + data.len() as u64;
        if end > buffer.size {
            return Err(crate::Error::Internal(format!(
                "an upload of {} bytes at {offset} into the {}-byte {}",
                data.len(),
                buffer.size,
                buffer.name
            )));
        }
        let inline = data.len() <= INLINE_BYTES && data.len() % 4 == 0 && offset % 4 == 0;
        let source = if inline {
            Source::Inline(data.to_vec())
        } else {
            Source::Staged(staging(gpu, &buffer.name, data)?, data.len() as u64)
        };
        Ok(Self {
            source,
            target: Target::Buffer {
                buffer: buffer.clone(),
                offset,
            },
        })
    }

    /// `texels` (every mip, level 0 first, tightly packed) into `image` (made with
    /// TRANSFER_DST usage), which the copy leaves in SHADER_READ_ONLY_OPTIMAL.
    pub fn to_image(gpu: &Gpu, image: &Arc<GpuImage>, name: &str, texels: &[u8]) -> Result<Self> {
        Ok(Self {
            source: Source::Staged(staging(gpu, name, texels)?, texels.len() as u64),
            target: Target::Image(image.clone()),
        })
    }

    /// Bytes of staging memory the upload holds.
    pub fn staging_bytes(&self) -> u64 {
        match &self.source {
            Source::Inline(_) => 0,
            Source::Staged(buffer, _) => buffer.size,
        }
    }

    /// Records the copy, after every command before it on the queue (frames in flight
    /// included: an upload recorded again may land in a buffer they read elsewhere, or an
    /// image they sample) and before every command after it.
    pub fn record(&self, gpu: &Gpu, cmd: vk::CommandBuffer) {
        let (any, transfer) = (ANY_ACCESS, TRANSFER_WRITE);
        match (&self.target, &self.source) {
            (Target::Buffer { .. }, Source::Inline(data)) if data.is_empty() => {}
            (Target::Buffer { buffer, offset }, source) => {
                memory_barrier(gpu, cmd, any, transfer);
                match source {
                    Source::Inline(data) => gpu.cmd_update_buffer(cmd, buffer, *offset, data),
                    Source::Staged(staging, bytes) => {
                        gpu.cmd_copy_buffer(cmd, staging, buffer, *offset, *bytes);
                    }
                }
                memory_barrier(gpu, cmd, transfer, any);
            }
            (Target::Image(image), Source::Staged(staging, _)) => {
                record_image(gpu, cmd, image, staging, any, transfer);
            }
            (Target::Image(_), Source::Inline(_)) => {
                unreachable!("image uploads are staged (Upload::to_image)")
            }
        }
    }
}

/// A host-visible buffer holding `data`, read only by copies into `name`.
fn staging(gpu: &Gpu, name: &str, data: &[u8]) -> Result<Buffer> {
    let mut buffer = gpu.create_buffer(
        &format!("staging for {name}"),
        data.len() as u64,
        vk::BufferUsageFlags::TRANSFER_SRC,
        MemoryLocation::CpuToGpu,
    )?;
    buffer.write(0, data)?;
    Ok(buffer)
}

fn record_image(
    gpu: &Gpu,
    cmd: vk::CommandBuffer,
    image: &GpuImage,
    staging: &Buffer,
    any: Scope,
    transfer: Scope,
) {
    // The old contents are dropped (UNDEFINED): an upload recorded again rewrites them all.
    image_barrier(
        gpu,
        cmd,
        image,
        vk::ImageLayout::UNDEFINED,
        vk::ImageLayout::TRANSFER_DST_OPTIMAL,
        any,
        transfer,
    );
    let mut offset = 0u64;
    let mut regions = Vec::new();
    for level in 0..image.mip_levels {
        let region = mip_region(image, level, offset);
        offset += u64::from(region.image_extent.width * region.image_extent.height * 4);
        regions.push(region);
    }
    gpu.cmd_copy_buffer_to_image_levels(cmd, staging, image, &regions);
    let read = (
        vk::PipelineStageFlags::FRAGMENT_SHADER | vk::PipelineStageFlags::COMPUTE_SHADER,
        vk::AccessFlags::SHADER_READ,
    );
    image_barrier(
        gpu,
        cmd,
        image,
        vk::ImageLayout::TRANSFER_DST_OPTIMAL,
        vk::ImageLayout::SHADER_READ_ONLY_OPTIMAL,
        transfer,
        read,
    );
}

/// Uploads into one set of device-local objects, shared by everything that records frames
/// reading them (on the engine's device: the renderers over one set of assets).
#[derive(Default)]
pub struct Uploads {
    queued: Mutex<Vec<Queued>>,
}

struct Queued {
    upload: Upload,
    state: State,
}

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum State {
    /// No frame carries it (yet, or any more).
    Pending,
    /// Recorded into frame `frame` of recorder `by` (frames counted from 1 as each recorder
    /// records them, completing in that order).
    Recorded { by: u64, frame: u64 },
}

impl Uploads {
    fn queued(&self) -> std::sync::MutexGuard<'_, Vec<Queued>> {
        self.queued.lock().unwrap_or_else(|e| e.into_inner())
    }

    /// Runs `uploads`: on translucid's own device now, in one submission waited for (the
    /// staging freed on return); on an engine's device, with the next frame recorded
    /// ([`Self::record_pending`]).
    pub fn submit(&self, gpu: &Gpu, uploads: Vec<Upload>) -> Result<()> {
        if uploads.is_empty() {
            return Ok(());
        }
        if gpu.is_host_device() {
            self.queued()
                .extend(uploads.into_iter().map(|upload| Queued {
                    upload,
                    state: State::Pending,
                }));
            return Ok(());
        }
        gpu.submit_and_wait(|cmd| {
            for upload in &uploads {
                upload.record(gpu, cmd);
            }
            Ok(())
        })
    }

    /// Records into frame `frame` of recorder `by` (the frame after the last one `by`
    /// recorded whole) every upload no frame carries: those pending, and those an earlier
    /// recording of this frame took before it failed.
    pub fn record_pending(&self, gpu: &Gpu, cmd: vk::CommandBuffer, by: u64, frame: u64) {
        for queued in self.queued().iter_mut() {
            let carried = match queued.state {
                State::Pending => false,
                State::Recorded { by: b, frame: f } => b != by || f < frame,
            };
            if !carried {
                queued.upload.record(gpu, cmd);
                queued.state = State::Recorded { by, frame };
            }
        }
    }

    /// Recorder `by`'s frames up to `frame` completed: the uploads they carried ran, and
    /// their staging goes.
    pub fn completed(&self, by: u64, frame: u64) {
        self.queued().retain(|q| match q.state {
            State::Recorded { by: b, frame: f } => b != by || f > frame,
            State::Pending => true,
        });
    }

    /// Recorder `by` is gone without completing the frames that carried some uploads
    /// (they were abandoned): the next frame recorded carries them again.
    pub fn lost(&self, by: u64) {
        for queued in self.queued().iter_mut() {
            if matches!(queued.state, State::Recorded { by: b, .. } if b == by) {
                queued.state = State::Pending;
            }
        }
    }

    /// Recorder `by`'s frames after `frame` will never run (abandoned): the uploads they
    /// carried go with the next frame recorded, by any recorder.
    pub fn abandoned(&self, by: u64, frame: u64) {
        for queued in self.queued().iter_mut() {
            if matches!(queued.state, State::Recorded { by: b, frame: f } if b == by && f > frame) {
                queued.state = State::Pending;
            }
        }
    }

    /// Uploads not known to have run, and the staging bytes they hold.
    pub fn waiting(&self) -> (usize, u64) {
        let queued = self.queued();
        let bytes = queued.iter().map(|q| q.upload.staging_bytes()).sum();
        (queued.len(), bytes)
    }
}
