//! Result codes: 0 is success, positive values are statuses that are not errors, negative
//! values are errors, grouped in ranges (-1...-99 the caller's mistake, -100...-199 the device or
//! the environment, -200... translucid's own fault). Values are stable: a retired code stays
//! reserved as a comment.

use std::ffi::{c_char, CStr};
use translucid::gpu::vk;

/// What every fallible call returns. Errors are negative; test with `result < 0`.
#[allow(non_camel_case_types)]
#[repr(i32)]
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum translucid_result {
    /// The call did everything it was asked.
    Success = 0,
    /// The call succeeded but a list was cut short, as Vulkan's `VK_INCOMPLETE`: the caller's
    /// array or buffer holds less than there is (`translucid_method_get_available`,
    /// `translucid_context_get_pipeline_cache_data`); what was written is valid.
    Incomplete = 1,
    /// From `translucid_frame_complete`: the frame's commands have not run (not submitted,
    /// or still running). Nothing changed; the frame stays in flight: complete it after the
    /// submission finished, or abandon it. From `translucid_context_get_prepare_status`:
    /// work preparing in the background is still running.
    NotReady = 2,
    /// From `translucid_frame_complete`: the frame ran but went past a limit of one
    /// recording, so pixel rows it could not finish kept the opaque colour
    /// (`translucid_frame_statistics::overflowed`); the buffers have grown, and recording the
    /// same frame again over a restored opaque colour renders it right.
    FrameDegraded = 3,

    /// A required pointer argument was NULL.
    ErrorNullPointer = -1,
    /// A struct's `s_type` is not the one the call expects (zeroed or garbage struct, or
    /// a struct of another kind), or its `next` chain holds a structure this library does not
    /// know.
    ErrorInvalidStructureType = -2,
    /// A value is out of its documented range: a non-finite vertex, an index past the vertex
    /// count, a reserved flag bit, a material parameter outside [0, 1]...
    ErrorInvalidArgument = -3,
    /// An enum argument (method, primitive, layer, pixel format, mode) has a value no version of
    /// the API defines.
    ErrorInvalidEnum = -4,
    /// A size is zero, over its documented limit (viewport, texture, vertex or index count,
    /// caller buffer too small for the output), or not the size it must be (a host image's
    /// width and height against the frame's).
    ErrorInvalidSize = -5,
    /// A handle that is NULL, of the wrong object type, or never issued.
    ErrorInvalidHandle = -6,
    /// A handle to an object that was destroyed.
    ErrorStaleHandle = -7,
    /// A handle issued by a different context.
    ErrorForeignHandle = -8,
    /// The header the caller compiled against (`TRANSLUCID_HEADER_VERSION`) is not compatible
    /// with this library.
    ErrorHeaderVersionMismatch = -9,
    /// A method the API defines but this build does not have yet.
    ErrorMethodUnavailable = -10,
    /// A call that the context's mode does not offer (`translucid_frame_render` on a
    /// host-device context, `translucid_frame_record` on a standalone one, reading the pixels
    /// of a host-device frame), or a feature the API defines but this build lacks.
    ErrorNotSupported = -11,
    /// Host-device mode: as many frames as the context was made for
    /// (`translucid_context_create_info::frames_in_flight`) are recorded and not completed:
    /// complete the oldest after its submission finished before recording another. Also
    /// returned for the statistics of a frame in flight, and for destroying one (complete
    /// it, or abandon it with `translucid_frame_abandon`).
    ErrorFrameInFlight = -12,
    /// Another thread is in a call on the same context: calls on one context must not
    /// overlap. Nothing was done; the message (`translucid_context_get_last_error` on the
    /// refused thread) names the rule.
    ErrorContextBusy = -13,

    /// No Vulkan loader, no usable device, or the requested device does not exist; or the
    /// device lacks what the frame's method needs (the message says what).
    ErrorNoDevice = -100,
    /// A Vulkan call failed; the message names it.
    ErrorVulkan = -101,
    /// The device or host ran out of memory, or the call would have taken the context past
    /// its memory budget (`translucid_memory_create_info::budget_bytes`).
    ErrorOutOfMemory = -102,
    /// The device was lost; the context cannot be used any more.
    ErrorDeviceLost = -103,
    /// The Khronos validation layer (`TRANSLUCID_CONTEXT_CREATE_VALIDATION` or
    /// `TRANSLUCID_VALIDATION=1`) reported errors for work this call submitted.
    ErrorValidation = -104,
    /// A file could not be written.
    ErrorIo = -105,
    /// Host-device mode: the engine's device lacks a Vulkan version, feature, extension or
    /// queue capability that `translucid_host_get_requirements` lists; the message names each.
    ErrorDeviceRequirements = -106,

    /// translucid panicked inside this call (a bug: please report it with the message). The
    /// context refuses all further work; destroy it.
    ErrorPanic = -200,
    /// An earlier call on this context panicked; only `translucid_context_destroy` and
    /// `translucid_context_get_last_error` still work.
    ErrorContextPoisoned = -201,
}

impl translucid_result {
    /// Every code, for the to-string function and tests. (Not in the header: cbindgen would
    /// write it as a macro of Rust names.)
    pub(crate) const ALL: [translucid_result; 26] = [
        Self::Success,
        Self::Incomplete,
        Self::NotReady,
        Self::FrameDegraded,
        Self::ErrorNullPointer,
        Self::ErrorInvalidStructureType,
        Self::ErrorInvalidArgument,
        Self::ErrorInvalidEnum,
        Self::ErrorInvalidSize,
        Self::ErrorInvalidHandle,
        Self::ErrorStaleHandle,
        Self::ErrorForeignHandle,
        Self::ErrorHeaderVersionMismatch,
        Self::ErrorMethodUnavailable,
        Self::ErrorNotSupported,
        Self::ErrorFrameInFlight,
        Self::ErrorContextBusy,
        Self::ErrorNoDevice,
        Self::ErrorVulkan,
        Self::ErrorOutOfMemory,
        Self::ErrorDeviceLost,
        Self::ErrorValidation,
        Self::ErrorIo,
        Self::ErrorDeviceRequirements,
        Self::ErrorPanic,
        Self::ErrorContextPoisoned,
    ];

    /// The code for a raw value from C; `None` for values no version defines.
    pub fn from_raw(code: i32) -> Option<Self> {
        Self::ALL.into_iter().find(|r| *r as i32 == code)
    }

    /// A short, fixed description (the context's last-error message has the details).
    pub fn describe(self) -> &'static CStr {
        match self {
            Self::Success => c"success",
            Self::Incomplete => c"incomplete: the list was cut short by the caller's capacity",
            Self::NotReady => {
                c"not ready: the frame's commands (or the preparation) have not finished yet"
            }
            Self::FrameDegraded => c"frame degraded: past a limit, rows kept the opaque colour",
            Self::ErrorNullPointer => c"a required pointer was NULL",
            Self::ErrorInvalidStructureType => c"wrong or unknown structure type (s_type)",
            Self::ErrorInvalidArgument => c"invalid argument",
            Self::ErrorInvalidEnum => c"unknown enum value",
            Self::ErrorInvalidSize => c"size zero, over its limit, or not the size required",
            Self::ErrorInvalidHandle => c"invalid handle",
            Self::ErrorStaleHandle => c"handle to a destroyed object",
            Self::ErrorForeignHandle => c"handle from another context",
            Self::ErrorHeaderVersionMismatch => c"header version not compatible with the library",
            Self::ErrorMethodUnavailable => c"method not available in this build",
            Self::ErrorNotSupported => c"not supported in this mode or by this build",
            Self::ErrorFrameInFlight => c"a host-device frame is recorded and not completed",
            Self::ErrorContextBusy => c"another thread is in a call on this context",
            Self::ErrorNoDevice => c"no usable Vulkan device",
            Self::ErrorVulkan => c"Vulkan call failed",
            Self::ErrorOutOfMemory => c"out of memory",
            Self::ErrorDeviceLost => c"device lost",
            Self::ErrorValidation => c"Vulkan validation error",
            Self::ErrorIo => c"I/O error",
            Self::ErrorDeviceRequirements => c"the engine's device lacks what translucid requires",
            Self::ErrorPanic => c"internal error (panic); the context is unusable",
            Self::ErrorContextPoisoned => c"context unusable after an earlier internal error",
        }
    }

    /// Returns a static, NUL-terminated description of `code`; never NULL. Unknown values
    /// give "unknown result code".
    #[no_mangle]
    pub extern "C" fn translucid_result_string(code: i32) -> *const c_char {
        Self::from_raw(code)
            .map_or(c"unknown result code", Self::describe)
            .as_ptr()
    }
}

/// An error on its way to C: the code, and the message the context keeps as its last error.
#[derive(Debug)]
pub struct Failure {
    pub code: translucid_result,
    pub message: String,
}

impl Failure {
    pub fn new(code: translucid_result, message: impl Into<String>) -> Self {
        debug_assert!((code as i32) < 0, "{code:?} is not an error");
        Self {
            code,
            message: message.into(),
        }
    }

    pub fn null(what: &str) -> Self {
        Self::new(
            translucid_result::ErrorNullPointer,
            format!("{what} is NULL"),
        )
    }

    pub fn argument(message: impl Into<String>) -> Self {
        Self::new(translucid_result::ErrorInvalidArgument, message)
    }

    pub fn size(message: impl Into<String>) -> Self {
        Self::new(translucid_result::ErrorInvalidSize, message)
    }

    pub fn enumeration(what: &str, value: u32) -> Self {
        Self::new(
            translucid_result::ErrorInvalidEnum,
            format!("{what} {value} is not a value any version of the API defines"),
        )
    }
}

/// `Result` of the code behind an export.
pub type FfiResult<T = ()> = Result<T, Failure>;

impl From<translucid::Error> for Failure {
    fn from(error: translucid::Error) -> Self {
        use translucid::Error as E;
        use translucid_result as R;
        let code = match &error {
            E::InvalidScene(_)
            | E::InvalidGltf { .. }
            | E::ImportLimit { .. }
            | E::UnsupportedExtension { .. }
            | E::UnknownScene(..)
            | E::InvalidOption(_)
            | E::InvalidArgument(_)
            | E::HostFrame(_)
            // A bug of the library's: no code of its own, and nothing the caller can fix.
            | E::Internal(_) => R::ErrorInvalidArgument,
            E::TooLarge(_) => R::ErrorInvalidSize,
            E::InvalidHandle(_) => R::ErrorInvalidHandle,
            E::StaleHandle(_) => R::ErrorStaleHandle,
            E::ForeignHandle(_) => R::ErrorForeignHandle,
            E::FrameInFlight(_) => R::ErrorFrameInFlight,
            E::HostRequirements(_) => R::ErrorDeviceRequirements,
            E::InvalidViewport { .. } => R::ErrorInvalidSize,
            E::UnknownMethod(..) => R::ErrorMethodUnavailable,
            E::NoDevice(_) | E::DeviceLacks(_) => R::ErrorNoDevice,
            E::Vulkan { result, .. } => match *result {
                vk::Result::ERROR_OUT_OF_HOST_MEMORY | vk::Result::ERROR_OUT_OF_DEVICE_MEMORY => {
                    R::ErrorOutOfMemory
                }
                vk::Result::ERROR_DEVICE_LOST => R::ErrorDeviceLost,
                _ => R::ErrorVulkan,
            },
            E::Validation(_) => R::ErrorValidation,
            E::Allocation { .. } | E::MemoryBudget(_) => R::ErrorOutOfMemory,
            E::Image(_) | E::Io(_) | E::SceneIo { .. } => R::ErrorIo,
        };
        Self::new(code, error.to_string())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_code_round_trips_and_has_a_message_of_its_own() {
        let mut messages = std::collections::BTreeSet::new();
        for code in translucid_result::ALL {
            assert_eq!(translucid_result::from_raw(code as i32), Some(code));
            assert!(!code.describe().is_empty());
            // One meaning per code: no two codes share a message.
            assert!(messages.insert(code.describe()), "{code:?}");
        }
        assert_eq!(translucid_result::from_raw(-12345), None);
        assert_eq!(translucid_result::from_raw(4), None);
    }
}
