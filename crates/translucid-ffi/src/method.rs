//! Methods as the C API numbers them. The numbers are fixed now, before every method exists,
//! so that a host built today keeps working when a later library adds the method.

use crate::cast::{try_out, try_out_slice};
use crate::panic;
use crate::result::{translucid_result, Failure, FfiResult};
use std::ffi::c_char;
use translucid::methods::MethodKind;

/// Where the wavelet method keeps each pixel's coefficients.
#[allow(non_camel_case_types)]
#[repr(u32)]
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum translucid_wavelet_storage {
    /// In registers, on the bins the exact method's raster reads too (CPU drivers' default):
    /// smaller, and faster there; needs the device features the exact method needs.
    Bins = 0,
    /// In full-screen coefficient images, drawn by the graphics pipeline (GPUs' default).
    Images = 1,
}

impl translucid_wavelet_storage {
    pub fn from_raw(value: u32) -> FfiResult<Self> {
        [Self::Bins, Self::Images]
            .into_iter()
            .find(|s| *s as u32 == value)
            .ok_or_else(|| Failure::enumeration("wavelet storage", value))
    }

    pub fn core(self) -> translucid::methods::wavelet::Storage {
        match self {
            Self::Bins => translucid::methods::wavelet::Storage::Bins,
            Self::Images => translucid::methods::wavelet::Storage::Images,
        }
    }
}

/// A transparency method.
#[allow(non_camel_case_types)]
#[repr(u32)]
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum translucid_method {
    /// Unsorted alpha blending in submission order: the fast, wrong baseline.
    Blend = 0,
    /// Exact order-independent transparency (the compute bin rasterizer).
    Exact = 1,
    /// Wavelet OIT: approximate, bounded memory.
    Wavelet = 2,
    /// Weighted blended OIT: approximate, cheapest.
    Wboit = 3,
    /// Per-pixel linked lists, sorted per pixel: exact while the node pool holds the frame's
    /// fragments (`translucid_linked_list_settings::node_budget`). On an engine's device it
    /// needs the features `translucid_host_get_method_requirements` lists for it.
    LinkedList = 4,
    /// Dual depth peeling: N passes peel 2N layers, exact while every pixel has at most 2N
    /// (`translucid_depth_peeling_settings::passes`). On an engine's device it needs
    /// `geometryShader` and `independentBlend`, and `maxColorAttachments` of at least 7
    /// (desktop GPUs have 8).
    DepthPeeling = 5,
}

impl translucid_method {
    /// Every value, in order. (Not in the header: cbindgen would write it as a macro of Rust
    /// names.)
    pub(crate) const ALL: [Self; 6] = [
        Self::Blend,
        Self::Exact,
        Self::Wavelet,
        Self::Wboit,
        Self::LinkedList,
        Self::DepthPeeling,
    ];

    /// The core library's method.
    pub fn kind(self) -> MethodKind {
        match self {
            Self::Blend => MethodKind::Blend,
            Self::Exact => MethodKind::Exact,
            Self::Wavelet => MethodKind::Wavelet,
            Self::Wboit => MethodKind::Wboit,
            Self::LinkedList => MethodKind::LinkedList,
            Self::DepthPeeling => MethodKind::DepthPeeling,
        }
    }

    /// The value of the core's method `kind`.
    pub fn of_kind(kind: MethodKind) -> Self {
        match kind {
            MethodKind::Blend => Self::Blend,
            MethodKind::Exact => Self::Exact,
            MethodKind::Wavelet => Self::Wavelet,
            MethodKind::Wboit => Self::Wboit,
            MethodKind::LinkedList => Self::LinkedList,
            MethodKind::DepthPeeling => Self::DepthPeeling,
        }
    }

    /// The name the core library (and the CLI) uses.
    pub fn name(self) -> &'static str {
        self.kind().name()
    }

    fn c_name(self) -> *const c_char {
        match self {
            Self::Blend => c"blend",
            Self::Exact => c"exact",
            Self::Wavelet => c"wavelet",
            Self::Wboit => c"wboit",
            Self::LinkedList => c"linked_list",
            Self::DepthPeeling => c"depth_peeling",
        }
        .as_ptr()
    }

    /// Whether this build has the method.
    pub fn available(self) -> bool {
        translucid::methods::NAMES.contains(&self.name())
    }

    /// The method for a value from C: unknown values and methods this build lacks are errors.
    pub fn from_raw(value: u32) -> FfiResult<Self> {
        let method = Self::ALL
            .into_iter()
            .find(|m| *m as u32 == value)
            .ok_or_else(|| Failure::enumeration("method", value))?;
        if !method.available() {
            return Err(Failure::new(
                translucid_result::ErrorMethodUnavailable,
                format!(
                    "method {value} ({}) is not in this build (available: {})",
                    method.name(),
                    translucid::methods::NAMES.join(", ")
                ),
            ));
        }
        Ok(method)
    }

    /// The method's name ("blend", "exact", ...) as a static string, or NULL for a value no
    /// version defines. Works for methods this build lacks too.
    #[no_mangle]
    pub extern "C" fn translucid_method_name(method: u32) -> *const c_char {
        Self::ALL
            .into_iter()
            .find(|m| *m as u32 == method)
            .map_or(std::ptr::null(), Self::c_name)
    }

    /// Lists the methods this build has, in enum order. Writes up to `capacity` values to
    /// `methods` (which may be NULL when `capacity` is 0) and the number available to
    /// `*out_count`. Returns `TRANSLUCID_RESULT_INCOMPLETE` when `capacity` was too small.
    #[no_mangle]
    #[must_use]
    pub extern "C" fn translucid_method_get_available(
        methods: *mut u32,
        capacity: usize,
        out_count: *mut usize,
    ) -> translucid_result {
        panic::without_context(|| {
            let out_count = try_out(out_count, "out_count")?;
            let available: Vec<u32> = Self::ALL
                .into_iter()
                .filter(|m| m.available())
                .map(|m| m as u32)
                .collect();
            let written = available.len().min(capacity);
            if written > 0 {
                let out = try_out_slice(methods, written, "methods")?;
                for (slot, m) in out.iter_mut().zip(&available) {
                    slot.write(*m);
                }
            }
            out_count.write(available.len());
            Ok(if written < available.len() {
                translucid_result::Incomplete
            } else {
                translucid_result::Success
            })
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::ffi::CStr;

    #[test]
    fn every_core_method_has_a_value_named_as_the_core_names_it() {
        for kind in MethodKind::ALL {
            let method = translucid_method::ALL
                .into_iter()
                .find(|m| m.kind() == kind)
                .unwrap_or_else(|| panic!("{kind} has no C enum value"));
            // SAFETY: c_name returns a static NUL-terminated literal.
            let c_name = unsafe { CStr::from_ptr(method.c_name()) };
            assert_eq!(c_name.to_str(), Ok(kind.name()));
            assert!(method.available(), "{kind}");
        }
    }
}
