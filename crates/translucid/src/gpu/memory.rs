//! Buffers and images with memory from `gpu-allocator`. Each resource holds a [`Gpu`] clone
//! and frees itself on drop, so error paths cannot leak.

use super::error::{vk_err, vk_err_for};
use super::Gpu;
use crate::Result;
use ash::vk;
use gpu_allocator::vulkan::{Allocation, AllocationCreateDesc, AllocationScheme};
pub use gpu_allocator::MemoryLocation;
use std::collections::BTreeMap;
use std::sync::atomic::{AtomicU64, Ordering};
use std::sync::Mutex;

/// What an allocation is for, which says where its memory should be (docs/gpu.md, "Memory"):
/// what the GPU reads every frame is device-local, unless the host writes it for each frame.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum MemoryRole {
    /// Kept while its owner lives: assets, working buffers, images (device-local), and
    /// readbacks the GPU writes for the host (host-visible, read by no shader).
    Resource,
    /// Written by the host for each frame and read by that frame's shaders (frame info,
    /// draws): host-visible, one per frame slot.
    PerFrame,
    /// Host-visible data on its way into device-local memory, read only by copies: an
    /// upload's staging (`gpu::staging`) is freed once its copies have run.
    Staging,
}

/// What a live allocation holds and where its memory is: what [`Gpu::allocations`] lists.
#[derive(Clone, Debug)]
pub struct AllocationInfo {
    pub name: String,
    pub bytes: u64,
    /// The memory asked for: `GpuOnly` (device-local), `CpuToGpu` or `GpuToCpu`
    /// (host-visible).
    pub location: MemoryLocation,
    /// The memory type's flags the allocation got. (A CPU driver such as lavapipe has only
    /// host-visible types: there, `location` says what a GPU would get.)
    pub properties: vk::MemoryPropertyFlags,
    pub usage: AllocationUsage,
    pub role: MemoryRole,
}

/// A buffer's or an image's usage.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum AllocationUsage {
    Buffer(vk::BufferUsageFlags),
    Image(vk::ImageUsageFlags),
}

impl AllocationInfo {
    /// Whether the allocation was asked in host-visible memory.
    pub fn host_visible(&self) -> bool {
        self.location != MemoryLocation::GpuOnly
    }

    /// Whether the GPU's pipelines may read it (as vertices, indices, indirect arguments,
    /// uniforms, storage, texels, sampled or attached images), not only copies.
    pub fn read_by_pipelines(&self) -> bool {
        match self.usage {
            AllocationUsage::Buffer(u) => u.intersects(
                vk::BufferUsageFlags::VERTEX_BUFFER
                    | vk::BufferUsageFlags::INDEX_BUFFER
                    | vk::BufferUsageFlags::INDIRECT_BUFFER
                    | vk::BufferUsageFlags::UNIFORM_BUFFER
                    | vk::BufferUsageFlags::STORAGE_BUFFER
                    | vk::BufferUsageFlags::UNIFORM_TEXEL_BUFFER
                    | vk::BufferUsageFlags::STORAGE_TEXEL_BUFFER,
            ),
            AllocationUsage::Image(u) => !(u & !(vk::ImageUsageFlags::TRANSFER_SRC
                | vk::ImageUsageFlags::TRANSFER_DST))
                .is_empty(),
        }
    }
}

/// Live bytes allocated through one device, their peak, every byte ever allocated, and
/// what each live allocation is.
#[derive(Default)]
pub struct MemoryStats {
    current: AtomicU64,
    peak: AtomicU64,
    total: AtomicU64,
    next_id: AtomicU64,
    live: Mutex<BTreeMap<u64, AllocationInfo>>,
}

impl MemoryStats {
    fn add(&self, bytes: u64) {
        // What background work allocates is not the frames' (the budget counts it still).
        if !super::background::is_background() {
            self.total.fetch_add(bytes, Ordering::Relaxed);
        }
        let now = self.current.fetch_add(bytes, Ordering::Relaxed) + bytes;
        self.peak.fetch_max(now, Ordering::Relaxed);
    }

    fn sub(&self, bytes: u64) {
        self.current.fetch_sub(bytes, Ordering::Relaxed);
    }

    pub(crate) fn current_and_peak(&self) -> (u64, u64) {
        (
            self.current.load(Ordering::Relaxed),
            self.peak.load(Ordering::Relaxed),
        )
    }

    pub(crate) fn total(&self) -> u64 {
        self.total.load(Ordering::Relaxed)
    }

    pub(crate) fn reset_peak(&self) {
        self.peak
            .store(self.current.load(Ordering::Relaxed), Ordering::Relaxed);
    }

    fn live(&self) -> std::sync::MutexGuard<'_, BTreeMap<u64, AllocationInfo>> {
        self.live.lock().unwrap_or_else(|e| e.into_inner())
    }

    /// Notes a live allocation; its id, for [`Self::forget`].
    fn note(&self, info: AllocationInfo) -> u64 {
        let id = self.next_id.fetch_add(1, Ordering::Relaxed);
        self.live().insert(id, info);
        id
    }

    fn forget(&self, id: u64) {
        self.live().remove(&id);
    }

    pub(crate) fn allocations(&self) -> Vec<AllocationInfo> {
        self.live().values().cloned().collect()
    }
}

/// An allocation and its entry among the device's live ones.
struct Memory {
    allocation: Allocation,
    id: u64,
    location: MemoryLocation,
}

impl Gpu {
    fn allocate(
        &self,
        name: &str,
        requirements: vk::MemoryRequirements,
        location: MemoryLocation,
        (usage, role): (AllocationUsage, MemoryRole),
    ) -> Result<Memory> {
        let linear = matches!(usage, AllocationUsage::Buffer(_));
        if let Some(budget) = self.memory_budget {
            let (held, _) = self.memory.current_and_peak();
            if held.saturating_add(requirements.size) > budget {
                return Err(crate::Error::MemoryBudget(format!(
                    "{name} needs {} bytes of GPU memory, and the context holds {held} of its \
                     {budget}-byte memory budget (translucid_context_trim gives back what no \
                     frame in flight uses)",
                    requirements.size
                )));
            }
        }
        let allocation = self
            .allocator
            .lock()
            .map_err(|_| {
                crate::Error::NoDevice("allocator lock poisoned by an earlier panic".into())
            })?
            .allocate(&AllocationCreateDesc {
                name,
                requirements,
                location,
                linear,
                allocation_scheme: AllocationScheme::GpuAllocatorManaged,
            })
            .map_err(|source| crate::Error::Allocation {
                object: format!("{name} ({} bytes)", requirements.size),
                source,
            })?;
        self.memory.add(allocation.size());
        // Which memory each object took (device-local, host-visible or both): what a GPU
        // reads from every frame should be device-local unless it is per-frame data
        // (docs/gpu.md, "Memory").
        log::debug!(
            "allocated {name}: {} bytes, {role:?}, {location:?} in {:?} memory, {usage:?}",
            allocation.size(),
            allocation.memory_properties()
        );
        let id = self.memory.note(AllocationInfo {
            name: name.to_string(),
            bytes: allocation.size(),
            location,
            properties: allocation.memory_properties(),
            usage,
            role,
        });
        Ok(Memory {
            allocation,
            id,
            location,
        })
    }

    /// Every allocation alive on this device now: what it is, its memory and its use.
    pub fn allocations(&self) -> Vec<AllocationInfo> {
        self.memory.allocations()
    }

    fn free(&self, memory: Memory) {
        let Memory { allocation, id, .. } = memory;
        self.memory.forget(id);
        self.memory.sub(allocation.size());
        if let Ok(mut a) = self.allocator.lock() {
            if let Err(e) = a.free(allocation) {
                log::warn!("freeing GPU memory failed: {e}");
            }
        }
    }

    /// A buffer of `size` bytes (made at least 16, so empty data still binds, as a buffer or
    /// as a view of one RGBA32 texel; reads still return `size` bytes). A host-visible one
    /// the pipelines read is staging ([`MemoryRole::Staging`]) when it is only copied from
    /// (TRANSFER_SRC alone); else per-frame data is made with
    /// [`Self::create_per_frame_buffer`].
    pub fn create_buffer(
        &self,
        name: &str,
        size: u64,
        usage: vk::BufferUsageFlags,
        location: MemoryLocation,
    ) -> Result<Buffer> {
        let role = if location == MemoryLocation::CpuToGpu
            && usage == vk::BufferUsageFlags::TRANSFER_SRC
        {
            MemoryRole::Staging
        } else {
            MemoryRole::Resource
        };
        self.create_buffer_for(name, size, usage, location, role)
    }

    /// A host-visible buffer of `size` bytes the host writes for each frame and that frame's
    /// pipelines read: one per frame slot, the only host-visible memory shaders read
    /// ([`MemoryRole::PerFrame`]).
    pub fn create_per_frame_buffer(
        &self,
        name: &str,
        size: u64,
        usage: vk::BufferUsageFlags,
    ) -> Result<Buffer> {
        self.create_buffer_for(
            name,
            size,
            usage,
            MemoryLocation::CpuToGpu,
            MemoryRole::PerFrame,
        )
    }

    fn create_buffer_for(
        &self,
        name: &str,
        size: u64,
        usage: vk::BufferUsageFlags,
        location: MemoryLocation,
        role: MemoryRole,
    ) -> Result<Buffer> {
        let len = size;
        let size = size.max(16);
        let info = vk::BufferCreateInfo::default()
            .size(size)
            .usage(usage)
            .sharing_mode(vk::SharingMode::EXCLUSIVE);
        // SAFETY: valid device and create info.
        let raw = unsafe { self.device.create_buffer(&info, self.callbacks()) }.map_err(
            vk_err_for("vkCreateBuffer", format!("{name} ({size} bytes)")),
        )?;
        let mut buffer = Buffer {
            gpu: self.clone(),
            raw,
            size,
            len,
            name: name.to_string(),
            allocation: None,
        };
        // SAFETY: raw is a live buffer of this device.
        let requirements = unsafe { self.device.get_buffer_memory_requirements(raw) };
        let memory = self.allocate(
            name,
            requirements,
            location,
            (AllocationUsage::Buffer(usage), role),
        )?;
        // SAFETY: the allocation satisfies the buffer's requirements and is not bound elsewhere.
        unsafe {
            self.device.bind_buffer_memory(
                raw,
                memory.allocation.memory(),
                memory.allocation.offset(),
            )
        }
        .map_err(vk_err("vkBindBufferMemory"))?;
        buffer.allocation = Some(memory);
        Ok(buffer)
    }

    /// A host-visible buffer holding `data`, for data the host hands over once (a caller's
    /// opaque layer; the tests' inputs). What shaders read every frame goes into
    /// device-local memory through `gpu::staging` instead.
    pub fn create_buffer_with_data(
        &self,
        name: &str,
        usage: vk::BufferUsageFlags,
        data: &[u8],
    ) -> Result<Buffer> {
        let mut buffer =
            self.create_buffer(name, data.len() as u64, usage, MemoryLocation::CpuToGpu)?;
        buffer.write(0, data)?;
        Ok(buffer)
    }

    /// A 2D image with a view covering all its mips.
    pub fn create_image(
        &self,
        name: &str,
        extent: vk::Extent2D,
        format: vk::Format,
        usage: vk::ImageUsageFlags,
        mip_levels: u32,
    ) -> Result<GpuImage> {
        // The depth formats translucid reads from engines, its own D32 among them (tests make
        // engine images of each).
        let aspect = if super::HOST_DEPTH_FORMATS.contains(&format) {
            super::host::depth_format_aspects(format)
        } else {
            vk::ImageAspectFlags::COLOR
        };
        let info = vk::ImageCreateInfo::default()
            .image_type(vk::ImageType::TYPE_2D)
            .format(format)
            .extent(vk::Extent3D {
                width: extent.width,
                height: extent.height,
                depth: 1,
            })
            .mip_levels(mip_levels)
            .array_layers(1)
            .samples(vk::SampleCountFlags::TYPE_1)
            .tiling(vk::ImageTiling::OPTIMAL)
            .usage(usage)
            .initial_layout(vk::ImageLayout::UNDEFINED);
        // SAFETY: valid device and create info.
        let raw =
            unsafe { self.device.create_image(&info, self.callbacks()) }.map_err(vk_err_for(
                "vkCreateImage",
                format!("{name} ({}x{})", extent.width, extent.height),
            ))?;
        let mut image = GpuImage {
            gpu: self.clone(),
            raw,
            view: vk::ImageView::null(),
            allocation: None,
            extent,
            format,
            aspect,
            mip_levels,
        };
        // SAFETY: raw is a live image of this device.
        let requirements = unsafe { self.device.get_image_memory_requirements(raw) };
        let memory = self.allocate(
            name,
            requirements,
            MemoryLocation::GpuOnly,
            (AllocationUsage::Image(usage), MemoryRole::Resource),
        )?;
        // SAFETY: the allocation satisfies the image's requirements and is not bound elsewhere.
        unsafe {
            self.device.bind_image_memory(
                raw,
                memory.allocation.memory(),
                memory.allocation.offset(),
            )
        }
        .map_err(vk_err("vkBindImageMemory"))?;
        image.allocation = Some(memory);
        let view_info = vk::ImageViewCreateInfo::default()
            .image(raw)
            .view_type(vk::ImageViewType::TYPE_2D)
            .format(format)
            .subresource_range(vk::ImageSubresourceRange {
                // A view reads one aspect: the depth of a depth/stencil format.
                aspect_mask: image.read_aspect(),
                ..image.full_range()
            });
        // SAFETY: the image is bound to memory; the range is within it.
        image.view = unsafe { self.device.create_image_view(&view_info, self.callbacks()) }
            .map_err(vk_err("vkCreateImageView"))?;
        Ok(image)
    }
}

/// A buffer and its memory.
pub struct Buffer {
    gpu: Gpu,
    pub raw: vk::Buffer,
    /// Bytes the buffer has (and binds).
    pub size: u64,
    /// Bytes it was asked for, which `read` returns: `size` can be larger.
    len: u64,
    /// What it holds, for messages.
    pub name: String,
    allocation: Option<Memory>,
}

impl Buffer {
    /// The device the buffer belongs to.
    pub fn gpu(&self) -> &Gpu {
        &self.gpu
    }

    /// Copies `data` into a host-visible buffer at `offset`. (A device-local buffer is
    /// filled by an upload, `gpu::staging`: writing it fails on every device, also where its
    /// memory is mapped.)
    pub fn write(&mut self, offset: u64, data: &[u8]) -> Result<()> {
        let end = offset + data.len() as u64;
        if end > self.size {
            return Err(crate::Error::Internal(format!(
                "write of {end} bytes past the {}-byte {}",
                self.size, self.name
            )));
        }
        let name = &self.name;
        let mapped = self
            .allocation
            .as_mut()
            .filter(|m| m.location != MemoryLocation::GpuOnly)
            .and_then(|m| m.allocation.mapped_slice_mut())
            .ok_or_else(|| {
                crate::Error::Internal(format!(
                    "write to {name}, a buffer that is not host-visible"
                ))
            })?;
        mapped[offset as usize..end as usize].copy_from_slice(data);
        Ok(())
    }

    /// The first word of a host-visible buffer the GPU may be writing right now (a frame the
    /// engine may not have waited for), read as one volatile load.
    pub fn read_word_volatile(&self) -> Result<u32> {
        let bytes = self.read()?;
        if bytes.len() < 4 {
            return Err(crate::Error::Internal(
                "word read of a buffer under 4 bytes".into(),
            ));
        }
        // SAFETY: the mapping holds at least 4 bytes and stays mapped while `self` lives; a
        // volatile, unaligned load of plain bytes makes no assumption about the GPU's writes.
        let word = unsafe { std::ptr::read_volatile(bytes.as_ptr().cast::<[u8; 4]>()) };
        Ok(u32::from_le_bytes(word))
    }

    /// The allocation of a buffer asked in host-visible memory: `None` for a device-local
    /// one, even where the device maps it (a CPU driver's memory is all host-visible), so
    /// that writing or reading it from the host fails on every device alike.
    fn host_visible(&self) -> Option<&Allocation> {
        self.allocation
            .as_ref()
            .filter(|m| m.location != MemoryLocation::GpuOnly)
            .map(|m| &m.allocation)
    }

    /// The contents of a host-visible buffer.
    pub fn read(&self) -> Result<&[u8]> {
        self.host_visible()
            .and_then(|a| a.mapped_slice())
            .map(|s| &s[..self.len as usize])
            .ok_or_else(|| {
                crate::Error::Internal("read of a buffer that is not host-visible".into())
            })
    }
}

impl Drop for Buffer {
    fn drop(&mut self) {
        // SAFETY: every submission is waited for before its resources can be dropped, so the
        // buffer is not in use.
        unsafe {
            self.gpu
                .device
                .destroy_buffer(self.raw, self.gpu.callbacks())
        };
        if let Some(a) = self.allocation.take() {
            self.gpu.free(a);
        }
    }
}

/// A typed view of a buffer, read in shaders as a texel buffer (`usamplerBuffer`).
///
/// CPU drivers such as lavapipe fetch texels with straight-line vector loads, while a
/// storage-buffer load inside divergent control flow becomes a per-lane loop with a branch
/// per component; hot read-only data goes through views for that reason.
pub struct BufferView {
    gpu: Gpu,
    pub raw: vk::BufferView,
}

/// A buffer and a texel view of it (see [`BufferView`] for why shaders read views).
pub struct ViewedBuffer {
    // Declared first so that it is destroyed before its buffer.
    pub view: BufferView,
    pub buffer: Buffer,
}

impl ViewedBuffer {
    pub fn new(gpu: &Gpu, buffer: Buffer, format: vk::Format) -> Result<Self> {
        Ok(Self {
            view: gpu.create_buffer_view(&buffer, format)?,
            buffer,
        })
    }
}

impl Gpu {
    /// A view of all of `buffer` as texels of `format` (a 32-bit-per-channel format with one
    /// or four channels). The buffer must have been made with UNIFORM_TEXEL_BUFFER usage.
    pub fn create_buffer_view(&self, buffer: &Buffer, format: vk::Format) -> Result<BufferView> {
        let texel_bytes = match format {
            vk::Format::R32_UINT | vk::Format::R32_SINT | vk::Format::R32_SFLOAT => 4,
            vk::Format::R32G32B32A32_UINT
            | vk::Format::R32G32B32A32_SINT
            | vk::Format::R32G32B32A32_SFLOAT => 16,
            other => unreachable!("create_buffer_view: unsupported format {other:?}"),
        };
        let texels = buffer.size / texel_bytes;
        let limit = u64::from(self.info().max_texel_buffer_elements);
        if texels > limit {
            return Err(crate::Error::TooLarge(format!(
                "{} ({texels} texels) is over this device's limit of {limit} texels a view",
                buffer.name
            )));
        }
        self.texel_view(buffer, format, texels * texel_bytes)
    }

    /// A view of as much of `buffer` as one texel view holds, from its start, as texels of
    /// `format` (R32_UINT, R32_SINT or R32_SFLOAT): for a buffer the shaders reach past that
    /// only another way (through a storage binding).
    pub fn create_buffer_view_prefix(
        &self,
        buffer: &Buffer,
        format: vk::Format,
    ) -> Result<BufferView> {
        assert!(
            matches!(
                format,
                vk::Format::R32_UINT | vk::Format::R32_SINT | vk::Format::R32_SFLOAT
            ),
            "create_buffer_view_prefix: unsupported format {format:?}"
        );
        let texels = (buffer.size / 4).min(u64::from(self.info().max_texel_buffer_elements));
        self.texel_view(buffer, format, texels * 4)
    }

    fn texel_view(&self, buffer: &Buffer, format: vk::Format, bytes: u64) -> Result<BufferView> {
        let info = vk::BufferViewCreateInfo::default()
            .buffer(buffer.raw)
            .format(format)
            .offset(0)
            .range(bytes);
        // SAFETY: valid device, a live buffer, and a range within it of whole texels.
        let raw = unsafe { self.device.create_buffer_view(&info, self.callbacks()) }
            .map_err(vk_err("vkCreateBufferView"))?;
        Ok(BufferView {
            gpu: self.clone(),
            raw,
        })
    }
}

impl Drop for BufferView {
    fn drop(&mut self) {
        // SAFETY: as for Buffer: no submission using the view is pending. The owner keeps the
        // view next to (and dropped before or with) its buffer.
        unsafe {
            self.gpu
                .device
                .destroy_buffer_view(self.raw, self.gpu.callbacks())
        };
    }
}

/// A 2D image, its memory and a view of all its mips.
pub struct GpuImage {
    gpu: Gpu,
    pub raw: vk::Image,
    pub view: vk::ImageView,
    pub extent: vk::Extent2D,
    pub format: vk::Format,
    pub aspect: vk::ImageAspectFlags,
    pub mip_levels: u32,
    allocation: Option<Memory>,
}

impl GpuImage {
    /// The aspect views and copies read: the image's, or the depth of a depth/stencil one.
    pub fn read_aspect(&self) -> vk::ImageAspectFlags {
        if self.aspect.contains(vk::ImageAspectFlags::DEPTH) {
            vk::ImageAspectFlags::DEPTH
        } else {
            self.aspect
        }
    }

    pub fn full_range(&self) -> vk::ImageSubresourceRange {
        vk::ImageSubresourceRange {
            aspect_mask: self.aspect,
            base_mip_level: 0,
            level_count: self.mip_levels,
            base_array_layer: 0,
            layer_count: 1,
        }
    }
}

impl Drop for GpuImage {
    fn drop(&mut self) {
        // SAFETY: as for Buffer: no submission using the image is pending.
        unsafe {
            if self.view != vk::ImageView::null() {
                self.gpu
                    .device
                    .destroy_image_view(self.view, self.gpu.callbacks());
            }
            self.gpu
                .device
                .destroy_image(self.raw, self.gpu.callbacks());
        }
        if let Some(a) = self.allocation.take() {
            self.gpu.free(a);
        }
    }
}
