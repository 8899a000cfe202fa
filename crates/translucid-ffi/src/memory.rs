//! The GPU memory a context holds, the budget it holds it within, and giving back what no
//! frame in flight uses. Exports `translucid_context_get_memory_statistics` and
//! `translucid_context_trim`.

use crate::cast::{
    check_header, translucid_base_in_structure, translucid_context, try_out_structure, try_ref,
    write_optional, OutStructure,
};
use crate::panic;
use crate::result::translucid_result;
use crate::result::{Failure, FfiResult};
use crate::structure::translucid_structure_type;
use crate::vulkan::VkAllocationCallbacks;
use std::ffi::c_void;
use translucid::gpu::AllocationCallbacks;

/// What the engine controls of a context's memory, chained first to
/// `translucid_context_create_info::next` (in host-device mode, its own `next` then holds the
/// `translucid_host_device_create_info`).
#[allow(non_camel_case_types)]
#[repr(C)]
pub struct translucid_memory_create_info {
    /// `TRANSLUCID_STRUCTURE_TYPE_MEMORY_CREATE_INFO`.
    pub s_type: u32,
    /// NULL in standalone mode; in host-device mode, the
    /// `translucid_host_device_create_info`.
    pub next: *const c_void,
    /// The most GPU memory the context may hold, in bytes, as
    /// `translucid_memory_statistics::total_bytes` counts it; 0: no limit. A call that would
    /// allocate past it (a first frame at a larger size, a grown buffer, an asset) fails with
    /// `TRANSLUCID_RESULT_ERROR_OUT_OF_MEMORY`, a message naming the budget, and nothing
    /// changed: the context goes on within it (`translucid_context_trim` gives back what no
    /// frame in flight uses). Within a budget the context reserves device memory in blocks
    /// of 4 MB, so what it reserves passes what it holds by at most one block per memory
    /// type; allocations larger than a block get memory of their own.
    pub budget_bytes: u64,
    /// Host-device mode, optional: the engine's host allocator, which every Vulkan object
    /// translucid makes on the engine's device (buffers, images, views, pipelines, passes,
    /// sets) is created and destroyed with, as the engine's own are. Copied; its functions
    /// and `pUserData` must stay valid until the context is destroyed, and be callable from
    /// any thread the context is used on and from the threads that prepare in the
    /// background (`translucid_context_prepare_in_background`). Device memory comes from
    /// translucid's allocator (gpu-allocator), whose `vkAllocateMemory` calls pass none.
    /// Must be NULL in standalone mode, where translucid makes the device.
    pub allocation_callbacks: *const VkAllocationCallbacks,
}

/// The `translucid_memory_create_info` at the front of `next`, if one is there.
pub(crate) fn memory_create_info<'a>(
    next: *const c_void,
) -> FfiResult<Option<&'a translucid_memory_create_info>> {
    if next.is_null() {
        return Ok(None);
    }
    let link = try_ref(next.cast::<translucid_base_in_structure>(), "next")?;
    if link.s_type != translucid_structure_type::MemoryCreateInfo as u32 {
        return Ok(None);
    }
    // A structure of the type its s_type names (C contract).
    try_ref(next.cast::<translucid_memory_create_info>(), "next").map(Some)
}

impl translucid_memory_create_info {
    /// The budget, `None` for no limit.
    pub(crate) fn budget(&self) -> Option<u64> {
        (self.budget_bytes > 0).then_some(self.budget_bytes)
    }

    /// A copy of the engine's allocation callbacks, if it gave them.
    pub(crate) fn callbacks(&self) -> FfiResult<Option<AllocationCallbacks>> {
        if self.allocation_callbacks.is_null() {
            return Ok(None);
        }
        let given = try_ref(
            self.allocation_callbacks,
            "translucid_memory_create_info.allocation_callbacks",
        )?;
        let (Some(_), Some(_), Some(_)) =
            (given.pfn_allocation, given.pfn_reallocation, given.pfn_free)
        else {
            return Err(Failure::null(
                "translucid_memory_create_info.allocation_callbacks: pfnAllocation, \
                 pfnReallocation or pfnFree (Vulkan requires all three)",
            ));
        };
        Ok(Some(AllocationCallbacks(*given)))
    }
}

/// Checks that nothing follows a memory create-info in standalone mode.
pub(crate) fn check_standalone_chain(rest: *const c_void) -> FfiResult {
    check_header(
        translucid_structure_type::MemoryCreateInfo as u32,
        rest,
        translucid_structure_type::MemoryCreateInfo,
        "translucid_memory_create_info",
    )
}

/// The GPU memory a context holds now, in bytes, by what it is for. Zero-initialise it, set
/// `s_type`, and pass it to `translucid_context_get_memory_statistics`.
#[allow(non_camel_case_types)]
#[repr(C)]
pub struct translucid_memory_statistics {
    /// `TRANSLUCID_STRUCTURE_TYPE_MEMORY_STATISTICS`.
    pub s_type: u32,
    /// NULL.
    pub next: *mut c_void,
    /// Device-local: the assets (vertices, textures, materials), the frame targets and the
    /// methods' working buffers, each sized for the largest frame its renderer drew.
    pub device_local_bytes: u64,
    /// Host-visible, written for each frame (one copy per frame in flight).
    pub per_frame_bytes: u64,
    /// Host-visible staging of uploads whose frames have not completed yet.
    pub staging_bytes: u64,
    /// Host-visible memory the GPU writes for the host: counters, timestamps, readbacks.
    pub readback_bytes: u64,
    /// All of it.
    pub total_bytes: u64,
}

impl OutStructure for translucid_memory_statistics {
    const TYPE: translucid_structure_type = translucid_structure_type::MemoryStatistics;
    const NAME: &'static str = "translucid_memory_statistics";
    unsafe fn header(ptr: *const Self) -> (u32, *mut c_void) {
        // SAFETY: the trait's contract; only the two fields are read.
        unsafe {
            (
                std::ptr::addr_of!((*ptr).s_type).read(),
                std::ptr::addr_of!((*ptr).next).read(),
            )
        }
    }
}

impl translucid_memory_statistics {
    /// Writes the GPU memory the context holds now, by what it is for.
    #[no_mangle]
    #[must_use]
    pub extern "C" fn translucid_context_get_memory_statistics(
        context: *mut translucid_context,
        out_statistics: *mut translucid_memory_statistics,
    ) -> translucid_result {
        panic::with_context(context, |objects| {
            let ((s_type, next), out) = try_out_structure(out_statistics, "out_statistics")?;
            let used = objects.core.memory();
            out.write(translucid_memory_statistics {
                s_type,
                next,
                device_local_bytes: used.device_local,
                per_frame_bytes: used.per_frame,
                staging_bytes: used.staging,
                readback_bytes: used.readback,
                total_bytes: used.total(),
            });
            Ok(translucid_result::Success)
        })
    }

    /// Gives back the GPU memory no frame in flight uses: the frame targets and working
    /// buffers of the methods' renderers, which a renderer sizes for the largest frame it
    /// drew and never shrinks. Their pipelines are kept, and the assets stay uploaded: the
    /// next frame builds no pipeline, and allocates its buffers anew for its own size (after
    /// a resolution drop, less; buffers that grew for deep frames start where they had
    /// grown). Call it between frames, after a resolution or quality change, or on a level
    /// change. `out_bytes_freed` (may be NULL) receives the bytes given back.
    #[no_mangle]
    #[must_use]
    pub extern "C" fn translucid_context_trim(
        context: *mut translucid_context,
        out_bytes_freed: *mut u64,
    ) -> translucid_result {
        panic::with_context(context, |objects| {
            let freed = objects.core.trim();
            write_optional(out_bytes_freed, "out_bytes_freed", freed)?;
            Ok(translucid_result::Success)
        })
    }
}
