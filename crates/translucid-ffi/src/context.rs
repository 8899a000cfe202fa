//! The context: one device and every object created on it. Exports `translucid_context_*`.

use crate::cast::{
    self, check_header, check_type, translucid_base_in_structure, translucid_context, try_out,
    try_ref, try_str,
};
use crate::host::{host_gpu, translucid_host_device_create_info};
use crate::panic::{self, CallState};
use crate::result::{translucid_result, Failure, FfiResult};
use crate::structure::translucid_structure_type;
use crate::version;
use std::cell::UnsafeCell;
use std::ffi::{c_char, c_void, CStr, CString};
use std::ops::{Deref, DerefMut};
use std::sync::atomic::{AtomicBool, Ordering};
use translucid::gpu::{Gpu, GpuOptions, Profile};

/// How the context gets its device.
#[allow(non_camel_case_types)]
#[repr(u32)]
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum translucid_context_mode {
    /// translucid creates its own headless device, renders offscreen and reads pixels back.
    Standalone = 0,
    /// The engine's device, described by a `translucid_host_device_create_info` chained to
    /// `next`: translucid records into the engine's command buffers and never submits.
    HostDevice = 1,
}

/// Turn on the Khronos validation layer; every validation error then fails the call that
/// caused it with `TRANSLUCID_RESULT_ERROR_VALIDATION`. (`TRANSLUCID_VALIDATION=1` in the
/// environment does the same.) Both are ignored in host-device mode: enable the layer on the
/// engine's instance.
pub const TRANSLUCID_CONTEXT_CREATE_VALIDATION: u32 = 1;
/// Give the device the variants made for CPU drivers (masked, branch-free shaders), whatever
/// it is; `TRANSLUCID_PROFILE=cpu` in the environment does the same. Without either profile
/// flag, a device gets its own: CPU drivers theirs, GPUs the GPU variants. For testing and
/// measuring; at most one of the two.
pub const TRANSLUCID_CONTEXT_CREATE_PROFILE_CPU: u32 = 2;
/// Give the device the GPU variants (branching shaders), whatever it is, as
/// `TRANSLUCID_PROFILE=gpu` does: so that they can be checked on a CPU driver.
pub const TRANSLUCID_CONTEXT_CREATE_PROFILE_GPU: u32 = 4;
/// Sample textures in `exact` and `wavelet`'s bins with translucid's software sampler, bit
/// for bit the CPU reference, where the GPU profile would sample them in hardware (faster,
/// and within the driver's filtering precision of the reference: docs/textures.md), in
/// standalone and host-device mode; `TRANSLUCID_SAMPLING=software` in the environment does
/// the same.
pub const TRANSLUCID_CONTEXT_CREATE_SOFTWARE_SAMPLING: u32 = 8;
const CONTEXT_CREATE_FLAGS: u32 = TRANSLUCID_CONTEXT_CREATE_VALIDATION
    | TRANSLUCID_CONTEXT_CREATE_PROFILE_CPU
    | TRANSLUCID_CONTEXT_CREATE_PROFILE_GPU
    | TRANSLUCID_CONTEXT_CREATE_SOFTWARE_SAMPLING;

/// How to create a context. Zero-initialise it, then set `s_type`, `header_version` and what
/// you need; zero everywhere else means the default.
#[allow(non_camel_case_types)]
#[repr(C)]
pub struct translucid_context_create_info {
    /// `TRANSLUCID_STRUCTURE_TYPE_CONTEXT_CREATE_INFO`.
    pub s_type: u32,
    /// NULL in standalone mode; in host-device mode, a `translucid_host_device_create_info`.
    /// Either may come after a `translucid_memory_create_info` (a budget), chained first.
    pub next: *const c_void,
    /// `TRANSLUCID_HEADER_VERSION`: lets the library refuse a header it is not compatible with.
    pub header_version: u32,
    /// A `translucid_context_mode`; 0 is standalone.
    pub mode: u32,
    /// `TRANSLUCID_CONTEXT_CREATE_*` bits; other bits must be 0.
    pub flags: u32,
    /// Optional, standalone mode: the device's index or a case-insensitive substring of its
    /// name. NULL uses `TRANSLUCID_DEVICE` from the environment, else the best device
    /// (discrete, integrated, then CPU). Must be NULL in host-device mode.
    pub device: *const c_char,
    /// Host-device mode: the most frames recorded and not yet completed at any time, 1 to
    /// `TRANSLUCID_MAX_FRAMES_IN_FLIGHT`, and times
    /// `translucid_host_views_create_info::views_per_frame` at most that (8 frames of
    /// stereo). A frame of several views counts once; views recorded as frames of their own
    /// count each (the yardstick's frames too). 0 means 1. Standalone frames complete within
    /// their call: 0 or 1.
    pub frames_in_flight: u32,
    /// Optional: `pipeline_cache_size` bytes that `translucid_context_get_pipeline_cache_data`
    /// gave on an earlier run, merged into the context's pipeline cache so that its first
    /// frames skip the shader compilation the driver cached (copied; NULL and 0 for none).
    /// Data from another driver or device is ignored.
    pub pipeline_cache_data: *const c_void,
    pub pipeline_cache_size: usize,
}

/// Most frames in flight a host-device context takes, times its views per frame
/// (`translucid_host_views_create_info::views_per_frame`): 4 frames of 4 views, 8 of stereo.
pub const TRANSLUCID_MAX_FRAMES_IN_FLIGHT: u32 = 16;
const _: () =
    assert!(TRANSLUCID_MAX_FRAMES_IN_FLIGHT == translucid::renderer::MAX_FRAMES_IN_FLIGHT);

/// Most live objects of one kind (meshes, textures, materials or frames) in one context.
pub const TRANSLUCID_MAX_OBJECTS: u32 = 1 << 24;
const _: () = assert!(TRANSLUCID_MAX_OBJECTS == translucid::context::handles::MAX_OBJECTS);

/// What the boundary guards: everything a call can touch. The object model (assets,
/// renderers, frames and their flight) is the core's `translucid::context::Context`; the C
/// API converts to and from it.
pub struct Objects {
    pub core: translucid::context::Context,
}

impl Objects {
    pub fn gpu(&self) -> &Gpu {
        self.core.gpu()
    }
}

/// The object behind `translucid_context *`.
pub struct Context {
    /// Set while a call runs on the context (`Context::enter`): calls on one context must
    /// not overlap, and one that would is refused instead of let in.
    in_call: AtomicBool,
    /// Fixed at creation: the `const` queries read it whatever call runs meanwhile.
    device_name: CString,
    calls: UnsafeCell<Calls>,
}

/// What a call on the context works on, one call at a time.
pub struct Calls {
    pub state: CallState,
    pub objects: Objects,
}

/// A call's hold on its context, from [`Context::enter`]; dropping it lets the next call in.
pub struct Entered<'a> {
    context: &'a Context,
}

impl Deref for Entered<'_> {
    type Target = Calls;
    fn deref(&self) -> &Calls {
        // SAFETY: `in_call` was swapped from false to true by this `Entered` and stays true
        // until it drops, so no other reference to `calls` exists meanwhile.
        unsafe { &*self.context.calls.get() }
    }
}

impl DerefMut for Entered<'_> {
    fn deref_mut(&mut self) -> &mut Calls {
        // SAFETY: as in `deref`; `&mut self` makes this the only use of the hold.
        unsafe { &mut *self.context.calls.get() }
    }
}

impl Drop for Entered<'_> {
    fn drop(&mut self) {
        self.context.in_call.store(false, Ordering::Release);
    }
}

impl Context {
    /// Starts a call on the context; `None` while another thread is in one.
    pub fn enter(&self) -> Option<Entered<'_>> {
        self.in_call
            .compare_exchange(false, true, Ordering::Acquire, Ordering::Relaxed)
            .ok()
            .map(|_| Entered { context: self })
    }

    pub fn device_name(&self) -> &CStr {
        &self.device_name
    }
}

impl Context {
    fn create(info: &translucid_context_create_info) -> FfiResult<Self> {
        let host_mode = info.mode == translucid_context_mode::HostDevice as u32;
        let what = "translucid_context_create_info";
        check_type(
            info.s_type,
            translucid_structure_type::ContextCreateInfo,
            what,
        )?;
        // A memory create-info first, then in host-device mode the engine's device, checked
        // below; nothing else in standalone mode.
        let memory = crate::memory::memory_create_info(info.next)?;
        let next = memory.map_or(info.next, |m| m.next);
        match (host_mode, memory) {
            (true, _) => {}
            (false, Some(_)) => crate::memory::check_standalone_chain(next)?,
            (false, None) => check_header(
                info.s_type,
                info.next,
                translucid_structure_type::ContextCreateInfo,
                what,
            )?,
        }
        let memory_budget = memory.and_then(|m| m.budget());
        let allocation_callbacks = memory.map(|m| m.callbacks()).transpose()?.flatten();
        if allocation_callbacks.is_some() && !host_mode {
            return Err(Failure::argument(
                "translucid_memory_create_info.allocation_callbacks must be NULL in standalone \
                 mode: they are for the objects translucid makes on an engine's device",
            ));
        }
        version::check_header_version(info.header_version)?;
        if !host_mode && info.mode != translucid_context_mode::Standalone as u32 {
            return Err(Failure::enumeration("translucid_context_mode", info.mode));
        }
        if info.flags & !CONTEXT_CREATE_FLAGS != 0 {
            return Err(Failure::argument(format!(
                "unknown context flags {:#x}",
                info.flags & !CONTEXT_CREATE_FLAGS
            )));
        }
        let profile = match (
            info.flags & TRANSLUCID_CONTEXT_CREATE_PROFILE_CPU != 0,
            info.flags & TRANSLUCID_CONTEXT_CREATE_PROFILE_GPU != 0,
        ) {
            (false, false) => None,
            (true, false) => Some(Profile::CpuDriver),
            (false, true) => Some(Profile::Gpu),
            (true, true) => {
                return Err(Failure::argument(
                    "TRANSLUCID_CONTEXT_CREATE_PROFILE_CPU and _GPU together: give at most one",
                ))
            }
        };
        let device = try_str(info.device, "device")?;
        let frames_in_flight = match info.frames_in_flight {
            0 => 1,
            n if n <= TRANSLUCID_MAX_FRAMES_IN_FLIGHT && (host_mode || n == 1) => n,
            n => {
                return Err(Failure::argument(format!(
                    "translucid_context_create_info.frames_in_flight is {n}; it must be 0 or 1 \
                     in standalone mode, 0 to {TRANSLUCID_MAX_FRAMES_IN_FLIGHT} in host-device \
                     mode"
                )))
            }
        };
        // Checked before a device is made.
        let cache_data = (info.pipeline_cache_size > 0)
            .then(|| {
                cast::try_slice(
                    info.pipeline_cache_data.cast::<u8>(),
                    info.pipeline_cache_size,
                    "translucid_context_create_info.pipeline_cache_data",
                )
            })
            .transpose()?;
        let mut views_per_frame = 1;
        let gpu = if host_mode {
            if device.is_some() {
                return Err(Failure::argument(
                    "device must be NULL in host-device mode: the engine's device is used",
                ));
            }
            if next.is_null() {
                return Err(Failure::null(
                    "next (host-device mode needs a translucid_host_device_create_info)",
                ));
            }
            // Read the chained structure's type before the structure: a smaller one must not
            // be read as a host-device create info.
            let link = try_ref(next.cast::<translucid_base_in_structure>(), "next")?;
            if link.s_type != translucid_structure_type::HostDeviceCreateInfo as u32 {
                return Err(Failure::new(
                    translucid_result::ErrorInvalidStructureType,
                    format!(
                        "next holds structure type {} where host-device mode needs \
                         TRANSLUCID_STRUCTURE_TYPE_HOST_DEVICE_CREATE_INFO",
                        link.s_type
                    ),
                ));
            }
            let host = try_ref(next.cast::<translucid_host_device_create_info>(), "next")?;
            views_per_frame = crate::views::views_per_frame(host, frames_in_flight)?;
            host_gpu(
                host,
                profile,
                info.flags & TRANSLUCID_CONTEXT_CREATE_SOFTWARE_SAMPLING != 0,
                (memory_budget, allocation_callbacks),
            )?
        } else {
            let from_env = GpuOptions::from_env();
            // Say where the device name that matched nothing came from.
            let source = if device.is_some() {
                "translucid_context_create_info.device"
            } else {
                "TRANSLUCID_DEVICE (environment)"
            };
            Gpu::new(&GpuOptions {
                device: device.map(str::to_string).or(from_env.device),
                validation: info.flags & TRANSLUCID_CONTEXT_CREATE_VALIDATION != 0
                    || from_env.validation,
                profile,
                software_sampling: info.flags & TRANSLUCID_CONTEXT_CREATE_SOFTWARE_SAMPLING != 0,
                memory_budget,
            })
            .map_err(|e| match e {
                translucid::Error::NoDevice(m) if m.starts_with("no device matches") => {
                    translucid::Error::NoDevice(format!("{source}: {m}"))
                }
                other => other,
            })?
        };
        if let Some(data) = cache_data {
            // False for another driver's or device's data, which is documented as ignored.
            let _merged = gpu.merge_pipeline_cache(data)?;
        }
        let device_name = CString::new(gpu.info().name.replace('\0', "")).unwrap_or_default();
        Ok(Self {
            in_call: AtomicBool::new(false),
            device_name,
            calls: UnsafeCell::new(Calls {
                state: CallState::default(),
                objects: Objects {
                    core: translucid::context::Context::new(gpu, frames_in_flight, views_per_frame),
                },
            }),
        })
    }
}

impl translucid_context {
    /// Creates a context. On success writes it to `*out_context`; on failure leaves
    /// `*out_context` untouched and `translucid_context_get_last_error(NULL)` says why.
    #[no_mangle]
    #[must_use]
    pub extern "C" fn translucid_context_create(
        info: *const translucid_context_create_info,
        out_context: *mut *mut translucid_context,
    ) -> translucid_result {
        panic::without_context(|| {
            let info = try_ref(info, "info")?;
            let out = try_out(out_context, "out_context")?;
            let context = Context::create(info)?;
            out.write(cast::context_into_raw(Box::new(context)));
            Ok(translucid_result::Success)
        })
    }

    /// Destroys a context and everything created with it (meshes, textures, materials,
    /// frames): their handles become invalid. Standalone mode waits for its device to be idle.
    /// Preparation still running in the background is waited for (not cancelled). In
    /// host-device mode the GPU must be done with every frame recorded (the frame in flight
    /// completed, or the engine's device idle); destroy the context before the engine's
    /// device. NULL is allowed and does nothing. A context another thread is in a call on
    /// is not destroyed (that would free what the call uses): the context stays, and
    /// `translucid_context_get_last_error(NULL)` says so.
    #[no_mangle]
    pub extern "C" fn translucid_context_destroy(context: *mut translucid_context) {
        // A panic while dropping leaks the rest of the context rather than unwinding into C.
        panic::or_fallback((), || {
            let Some(shared) = cast::context_ref(context) else {
                return;
            };
            match shared.enter() {
                Some(entered) => {
                    // Held to the end: a call racing the destruction is refused, not let in.
                    std::mem::forget(entered);
                    drop(cast::context_from_raw(context));
                }
                None => {
                    let _busy = panic::refuse_busy(context, "the context was not destroyed: ");
                }
            }
        });
    }

    /// The message of the last failed call on `context`, or of the last failed call without a
    /// context on this thread (`translucid_context_create`, calls given a NULL context) when
    /// `context` is NULL. Never NULL; "" when nothing has failed yet (a successful call does
    /// not clear it). Valid until the next call on the same context (or, for NULL, the next
    /// failing context-less call on this thread). After `TRANSLUCID_RESULT_ERROR_CONTEXT_BUSY`
    /// it is that refusal's message on the thread refused, until that thread's next call on
    /// the context.
    #[no_mangle]
    pub extern "C" fn translucid_context_get_last_error(
        context: *const translucid_context,
    ) -> *const c_char {
        panic::or_fallback(c"".as_ptr(), || match cast::context_ref(context) {
            Some(shared) => panic::last_error_of(context, shared),
            None => panic::thread_last_error(),
        })
    }

    /// The context's pipeline cache, for the engine to save and pass back in
    /// `translucid_context_create_info::pipeline_cache_data` on its next run (with the same
    /// driver and device). `*size` is in and out: with `data` NULL, the call writes the size
    /// the data needs; otherwise it copies up to `*size` bytes, writes how many it copied, and
    /// returns `TRANSLUCID_RESULT_INCOMPLETE` when that is not all of it. Call it after the
    /// frames whose pipelines should be kept (a context builds them on first use).
    #[no_mangle]
    #[must_use]
    pub extern "C" fn translucid_context_get_pipeline_cache_data(
        context: *mut translucid_context,
        data: *mut c_void,
        size: *mut usize,
    ) -> translucid_result {
        panic::with_context(context, |objects| {
            let capacity = *try_ref(size.cast_const(), "size")?;
            let out_size = try_out(size, "size")?;
            let bytes = objects.gpu().pipeline_cache_data()?;
            if data.is_null() {
                out_size.write(bytes.len());
                return Ok(translucid_result::Success);
            }
            let n = bytes.len().min(capacity);
            let out = cast::try_out_slice(data.cast::<u8>(), n, "data")?;
            for (slot, &b) in out.iter_mut().zip(&bytes) {
                slot.write(b);
            }
            out_size.write(n);
            Ok(if n < bytes.len() {
                translucid_result::Incomplete
            } else {
                translucid_result::Success
            })
        })
    }

    /// The name of the context's Vulkan device; "" for a NULL context. Valid as long as the
    /// context.
    #[no_mangle]
    pub extern "C" fn translucid_context_get_device_name(
        context: *const translucid_context,
    ) -> *const c_char {
        panic::or_fallback(c"".as_ptr(), || match cast::context_ref(context) {
            Some(context) => context.device_name().as_ptr(),
            None => c"".as_ptr(),
        })
    }
}
