//! Device-local buffers that grow by appending, up to a capacity fixed at creation, filled by
//! uploads (`staging.rs`).

use super::staging::Upload;
use super::{vk, Buffer, BufferView, Gpu, MemoryLocation};
use crate::Result;
use std::sync::{Arc, Mutex};

/// A device-local buffer written by appending: what was written stays where it is, so the
/// descriptor sets and views naming the buffer stay valid, and the GPU work recorded
/// before an append, which reads only what was written before it, is never written under.
/// Several owners may share one (behind an `Arc`) and append to it. The data goes in by
/// the [`Upload`]s the calls return, which the caller runs (`gpu::Uploads`) before any
/// frame reads it.
pub struct AppendBuffer {
    // Declared first so that it is destroyed before its buffer.
    view: Option<BufferView>,
    buffer: Arc<Buffer>,
    /// Bytes reserved so far.
    used: Mutex<u64>,
}

impl AppendBuffer {
    /// A device-local buffer of `capacity` bytes (at least 16) with `usage` (and
    /// TRANSFER_DST), viewed as texels of `format` when given, and the upload of `data` to
    /// its start.
    pub fn new(
        gpu: &Gpu,
        name: &str,
        usage: vk::BufferUsageFlags,
        capacity: u64,
        format: Option<vk::Format>,
        data: &[u8],
    ) -> Result<(Self, Upload)> {
        let capacity = capacity.max(data.len() as u64).max(16);
        let buffer = Arc::new(gpu.create_buffer(
            name,
            capacity,
            usage | vk::BufferUsageFlags::TRANSFER_DST,
            MemoryLocation::GpuOnly,
        )?);
        let upload = Upload::to_buffer(gpu, &buffer, 0, data)?;
        let view = format
            .map(|f| gpu.create_buffer_view(&buffer, f))
            .transpose()?;
        let appended = Self {
            view,
            buffer,
            used: Mutex::new(data.len() as u64),
        };
        Ok((appended, upload))
    }

    pub fn buffer(&self) -> &Buffer {
        &self.buffer
    }

    /// The texel view (for buffers made with a format).
    pub fn view(&self) -> Option<&BufferView> {
        self.view.as_ref()
    }

    /// Bytes reserved so far.
    pub fn used(&self) -> u64 {
        *self.used.lock().unwrap_or_else(|e| e.into_inner())
    }

    /// Reserves room for `data` at a multiple of `align` bytes: its offset and the upload
    /// that puts it there, or `None` (reserving nothing) when the rest of the buffer is too
    /// small. The room is past every byte reserved before, which no GPU work recorded so
    /// far reads.
    pub fn append(&self, gpu: &Gpu, data: &[u8], align: u64) -> Result<Option<(u64, Upload)>> {
        let mut used = self.used.lock().unwrap_or_else(|e| e.into_inner());
        let offset = used.next_multiple_of(align.max(1));
        let Some(end) = offset.checked_add(data.len() as u64) else {
            return Ok(None);
        };
        if end > self.buffer.size {
            return Ok(None);
        }
        let upload = Upload::to_buffer(gpu, &self.buffer, offset, data)?;
        *used = end;
        Ok(Some((offset, upload)))
    }

    /// The upload of `data` at `offset`, a range reserved before: the caller knows that no
    /// GPU work recorded so far reads it (a record no frame has used yet).
    pub fn rewrite(&self, gpu: &Gpu, offset: u64, data: &[u8]) -> Result<Upload> {
        Upload::to_buffer(gpu, &self.buffer, offset, data)
    }
}
