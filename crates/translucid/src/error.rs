//! One error type for the whole crate.

use std::path::PathBuf;

/// Everything that can go wrong in translucid, each variant naming the problem.
#[derive(Debug, thiserror::Error)]
pub enum Error {
    /// A scene file could not be read from disk.
    #[error("cannot read scene {path}: {source}")]
    SceneIo {
        path: PathBuf,
        #[source]
        source: std::io::Error,
    },
    /// A scene file is not valid glTF, or uses it in a way we cannot load.
    #[error("invalid glTF {path}: {reason}")]
    InvalidGltf { path: PathBuf, reason: String },
    /// A glTF file would take more than its import's limits allow (bytes, accessor elements,
    /// node instances, triangles, texels: `scene::gltf::ImportLimits`); refused before the
    /// memory is taken.
    #[error("glTF {path} refused: {reason}")]
    ImportLimit { path: PathBuf, reason: String },
    /// A glTF file requires an extension translucid does not implement.
    #[error("{path} requires unsupported glTF extension {extension}")]
    UnsupportedExtension { path: PathBuf, extension: String },
    /// Scene data that cannot be rendered (bad index, NaN position, missing texture...).
    #[error("invalid scene: {0}")]
    InvalidScene(String),
    /// A frame or scene past a limit of the device or of translucid: a storage binding's or a
    /// texel view's range, the largest image, 65535 pixels a side, 2^32 quads, the work bound.
    #[error("too large: {0}")]
    TooLarge(String),
    /// A value given to a call that it does not take: an opaque layer of the wrong size or
    /// with values out of range, a mesh index past the scene's, assets that do not extend the
    /// ones in use.
    #[error("invalid argument: {0}")]
    InvalidArgument(String),
    /// translucid used one of its own objects wrongly: a bug, to be reported.
    #[error("internal error: {0}")]
    Internal(String),
    /// A handle that names no object of its kind here: NULL, never issued, or another kind's
    /// (`context::handles`).
    #[error("{0}")]
    InvalidHandle(String),
    /// A handle whose object was destroyed.
    #[error("{0}")]
    StaleHandle(String),
    /// A handle another context issued.
    #[error("{0}")]
    ForeignHandle(String),
    /// A frame recorded while as many as the context was made for are in flight.
    #[error("{0}")]
    FrameInFlight(String),
    /// A name that is neither a generated scene nor a file path.
    #[error("unknown scene {0:?}: not a file and not one of the generated scenes ({1})")]
    UnknownScene(String, String),
    /// A viewport of zero size or over the device's limit.
    #[error("invalid viewport {width}x{height}: {reason}")]
    InvalidViewport {
        width: u32,
        height: u32,
        reason: String,
    },
    /// A method name translucid does not know.
    #[error("unknown method {0:?} (known: {1})")]
    UnknownMethod(String, String),
    /// A method setting out of its range (a wavelet rank over 3, a negative noise...).
    #[error("invalid method option: {0}")]
    InvalidOption(String),
    /// No Vulkan loader, no suitable device, or the requested device does not exist.
    #[error("no Vulkan device: {0}")]
    NoDevice(String),
    /// The device lacks a feature, property or limit a method needs; the message names the
    /// method and what is missing.
    #[error("{0}")]
    DeviceLacks(String),
    /// The engine's device (host-device mode) lacks a Vulkan version, feature, extension or
    /// queue capability translucid needs; the message names every one missing.
    #[error("the engine's Vulkan device does not meet translucid's requirements: {0}")]
    HostRequirements(String),
    /// Host-device mode: the engine's images, layouts or command buffer cannot be used as
    /// given (wrong format, an undefined layout, a NULL handle, a size mismatch...).
    #[error("host-device frame: {0}")]
    HostFrame(String),
    /// A Vulkan call failed; `object` names what it was making, when it made something.
    #[error("Vulkan call {call} failed{}: {result}", for_object(object))]
    Vulkan {
        call: &'static str,
        object: String,
        result: ash::vk::Result,
    },
    /// The Khronos validation layer reported errors (only with `TRANSLUCID_VALIDATION=1`).
    #[error("Vulkan validation errors:\n{0}")]
    Validation(String),
    /// An allocation would take the device's memory past the budget it was given
    /// (`GpuOptions::memory_budget`, `HostDevice::memory_budget`).
    #[error("{0}")]
    MemoryBudget(String),
    /// GPU memory allocation failed for `object`.
    #[error("GPU memory allocation for {object} failed: {source}")]
    Allocation {
        object: String,
        #[source]
        source: gpu_allocator::AllocationError,
    },
    /// An image could not be decoded or written.
    #[error("image error: {0}")]
    Image(#[from] ::image::ImageError),
    /// Other I/O failure.
    #[error("I/O error: {0}")]
    Io(#[from] std::io::Error),
}

/// " for NAME", or nothing when no object is named.
fn for_object(object: &str) -> String {
    if object.is_empty() {
        String::new()
    } else {
        format!(" for {object}")
    }
}

/// `Result` with translucid's [`Error`].
pub type Result<T, E = Error> = std::result::Result<T, E>;

impl Error {
    /// The same error, its message starting with `prefix` (where it has a message of its
    /// own): says which element of a list it is about.
    pub fn prefixed(self, prefix: &str) -> Self {
        let at = |m: String| format!("{prefix}: {m}");
        match self {
            Self::InvalidScene(m) => Self::InvalidScene(at(m)),
            Self::TooLarge(m) => Self::TooLarge(at(m)),
            Self::InvalidArgument(m) => Self::InvalidArgument(at(m)),
            Self::InvalidHandle(m) => Self::InvalidHandle(at(m)),
            Self::StaleHandle(m) => Self::StaleHandle(at(m)),
            Self::ForeignHandle(m) => Self::ForeignHandle(at(m)),
            other => other,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A failed creation names what it was making; a plain call failure names the call alone.
    #[test]
    fn vulkan_errors_name_their_object() {
        let named = Error::Vulkan {
            call: "vkCreateBuffer",
            object: "bin lists (134217744 bytes)".into(),
            result: ash::vk::Result::ERROR_OUT_OF_DEVICE_MEMORY,
        };
        let text = named.to_string();
        assert!(
            text.starts_with("Vulkan call vkCreateBuffer failed for bin lists (134217744 bytes)"),
            "{text}"
        );
        let plain = Error::Vulkan {
            call: "vkQueueSubmit",
            object: String::new(),
            result: ash::vk::Result::ERROR_DEVICE_LOST,
        };
        assert!(
            plain
                .to_string()
                .starts_with("Vulkan call vkQueueSubmit failed: "),
            "{plain}"
        );
    }
}
