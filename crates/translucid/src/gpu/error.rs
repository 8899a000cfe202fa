//! Turning `vk::Result` into [`crate::Error`] at each call site, naming the call.

use crate::Error;
use ash::vk;

/// `.map_err(vk_err("vkCreateSampler"))?`: wraps a failed call with its name.
pub(crate) fn vk_err(call: &'static str) -> impl Fn(vk::Result) -> Error {
    move |result| Error::Vulkan {
        call,
        object: String::new(),
        result,
    }
}

/// `.map_err(vk_err_for("vkCreateBuffer", "bin lists (128 bytes)"))?`: the call and what it
/// was making.
pub(crate) fn vk_err_for(call: &'static str, object: String) -> impl FnOnce(vk::Result) -> Error {
    move |result| Error::Vulkan {
        call,
        object,
        result,
    }
}
