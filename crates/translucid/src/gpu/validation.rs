//! The Khronos validation layer's messages, collected so that every submission can fail on
//! the first validation error instead of printing it and carrying on.

use ash::vk;
use std::ffi::{c_void, CStr};
use std::sync::Mutex;

pub(crate) const LAYER_NAME: &CStr = c"VK_LAYER_KHRONOS_validation";

/// Validation errors seen since the last [`ValidationLog::take`].
#[derive(Default)]
pub(crate) struct ValidationLog {
    errors: Mutex<Vec<String>>,
}

impl ValidationLog {
    pub(crate) fn take(&self) -> Vec<String> {
        match self.errors.lock() {
            Ok(mut e) => std::mem::take(&mut *e),
            Err(poisoned) => std::mem::take(&mut *poisoned.into_inner()),
        }
    }

    fn push(&self, message: String) {
        match self.errors.lock() {
            Ok(mut e) => e.push(message),
            Err(poisoned) => poisoned.into_inner().push(message),
        }
    }
}

/// Debug-utils callback. `user_data` points at the `ValidationLog` owned by the `Gpu`, which
/// outlives the messenger (the messenger is destroyed first in `Gpu::drop`).
pub(crate) unsafe extern "system" fn callback(
    severity: vk::DebugUtilsMessageSeverityFlagsEXT,
    _types: vk::DebugUtilsMessageTypeFlagsEXT,
    data: *const vk::DebugUtilsMessengerCallbackDataEXT<'_>,
    user_data: *mut c_void,
) -> vk::Bool32 {
    // SAFETY: the layer passes a valid callback-data pointer for the duration of the call, and
    // its message is a NUL-terminated string when non-null.
    let message = unsafe {
        data.as_ref()
            .filter(|d| !d.p_message.is_null())
            .map(|d| CStr::from_ptr(d.p_message).to_string_lossy().into_owned())
            .unwrap_or_default()
    };
    if severity.contains(vk::DebugUtilsMessageSeverityFlagsEXT::ERROR) {
        // SAFETY: user_data is the address of the Gpu's boxed ValidationLog (see above).
        if let Some(log) = unsafe { (user_data as *const ValidationLog).as_ref() } {
            log.push(message);
        }
    } else if severity.contains(vk::DebugUtilsMessageSeverityFlagsEXT::WARNING) {
        log::warn!("vulkan: {message}");
    }
    vk::FALSE
}
