//! Turning `vk::Result` into [`crate::Error`] at each call site, naming the call.

use crate::Error;
use ash::vk;

/// `.map_err(vk_err("vkCreateBuffer"))?`: wraps a failed call with its name.
pub(crate) fn vk_err(call: &'static str) -> impl Fn(vk::Result) -> Error {
    move |result| Error::Vulkan { call, result }
}
