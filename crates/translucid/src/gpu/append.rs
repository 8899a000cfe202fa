//! Host-visible buffers that grow by appending, up to a capacity fixed at creation.

use super::{vk, Buffer, BufferView, Gpu, MemoryLocation};
use crate::Result;
use std::sync::Mutex;

/// A host-visible buffer written by appending: what was written stays where it is, so the
/// descriptor sets and views naming the buffer stay valid, and the GPU work recorded
/// before an append, which reads only what was written before it, is never written under.
/// Several owners may share one (behind an `Arc`) and append to it.
pub struct AppendBuffer {
    // Declared first so that it is destroyed before its buffer.
    view: Option<BufferView>,
    buffer: Buffer,
    /// Bytes written so far.
    used: Mutex<u64>,
}

impl AppendBuffer {
    /// A buffer of `capacity` bytes (at least 16) with `usage`, viewed as texels of
    /// `format` when given, holding `data` at its start.
    pub fn new(
        gpu: &Gpu,
        name: &str,
        usage: vk::BufferUsageFlags,
        capacity: u64,
        format: Option<vk::Format>,
        data: &[u8],
    ) -> Result<Self> {
        let capacity = capacity.max(data.len() as u64).max(16);
        let mut buffer = gpu.create_buffer(name, capacity, usage, MemoryLocation::CpuToGpu)?;
        buffer.write(0, data)?;
        let view = format
            .map(|f| gpu.create_buffer_view(&buffer, f))
            .transpose()?;
        Ok(Self {
            view,
            buffer,
            used: Mutex::new(data.len() as u64),
        })
    }

    pub fn buffer(&self) -> &Buffer {
        &self.buffer
    }

    /// The texel view (for buffers made with a format).
    pub fn view(&self) -> Option<&BufferView> {
        self.view.as_ref()
    }

    /// Bytes written so far.
    pub fn used(&self) -> u64 {
        *self.used.lock().unwrap_or_else(|e| e.into_inner())
    }

    /// Appends `data` at a multiple of `align` bytes; its offset, or `None` (writing
    /// nothing) when the rest of the buffer is too small.
    pub fn append(&self, data: &[u8], align: u64) -> Option<u64> {
        let mut used = self.used.lock().unwrap_or_else(|e| e.into_inner());
        let offset = used.next_multiple_of(align.max(1));
        let end = offset.checked_add(data.len() as u64)?;
        if end > self.buffer.size {
            return None;
        }
        // SAFETY: the range [offset, end) lies in the buffer's mapping, past every byte
        // written before (the lock is held and `used` only grows), so no other write and no
        // GPU work recorded so far touches it, and no Rust reference to the mapping is alive.
        unsafe { self.buffer.write_unaliased(offset, data) }.ok()?;
        *used = end;
        Some(offset)
    }
}
