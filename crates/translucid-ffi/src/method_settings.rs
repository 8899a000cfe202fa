//! Method settings, chained to `translucid_frame_info.next`: one structure per method, so that a
//! new method or setting adds a structure and changes none. Settings of a method other than
//! the frame's are allowed and ignored, so one chain may serve every method an engine uses.

use crate::cast::{translucid_base_in_structure, try_ref};
use crate::method::{translucid_method, translucid_wavelet_storage};
use crate::result::{translucid_result, Failure, FfiResult};
use crate::structure::translucid_structure_type;
use std::ffi::c_void;
use translucid::methods::MethodOptions;

/// Settings of `TRANSLUCID_METHOD_EXACT`.
#[allow(non_camel_case_types)]
#[repr(C)]
#[derive(Clone, Copy, Debug)]
pub struct translucid_exact_settings {
    /// `TRANSLUCID_STRUCTURE_TYPE_EXACT_SETTINGS`.
    pub s_type: u32,
    /// The next method settings structure, or NULL.
    pub next: *const c_void,
    /// Stop compositing a pixel once every channel of its transmittance is below this, in
    /// [0, 1]; 0 (the default) composites every fragment: the exact result.
    pub threshold: f32,
}

/// Settings of `TRANSLUCID_METHOD_WAVELET`.
#[allow(non_camel_case_types)]
#[repr(C)]
#[derive(Clone, Copy, Debug)]
pub struct translucid_wavelet_settings {
    /// `TRANSLUCID_STRUCTURE_TYPE_WAVELET_SETTINGS`.
    pub s_type: u32,
    /// The next method settings structure, or NULL.
    pub next: *const c_void,
    /// Haar coefficients kept per colour channel, 2, 4, 8 or 16 (ranks 0 to 3: more is closer
    /// to exact, and costs memory and time); 0 is the default, 16.
    pub coefficients: u32,
    /// Depth noise strength in coefficient cells, finite and >= 0; 0 (the default) is off.
    /// The noise is a fixed per-pixel pattern, so frames repeat.
    pub noise: f32,
    /// A `translucid_wavelet_storage`, where the coefficients live; 0 is
    /// `TRANSLUCID_WAVELET_STORAGE_BINS`, which falls back to the images on a device without
    /// what the exact method needs and for frames too crowded for its loop budget. A frame
    /// whose settings chain holds no `translucid_wavelet_settings` gets the device's storage:
    /// the bins on CPU drivers, the images on GPUs (the context's profile).
    pub storage: u32,
}

/// Settings of `TRANSLUCID_METHOD_LINKED_LIST`.
#[allow(non_camel_case_types)]
#[repr(C)]
#[derive(Clone, Copy, Debug)]
pub struct translucid_linked_list_settings {
    /// `TRANSLUCID_STRUCTURE_TYPE_LINKED_LIST_SETTINGS`.
    pub s_type: u32,
    /// The next method settings structure, or NULL.
    pub next: *const c_void,
    /// The node pool, in fragments (28 bytes each). 0 (the default) sizes the pool from each
    /// frame's expected fragments before the frame is recorded (its transparent quads' area on
    /// screen, from a sample of at most 4096 of them; a quarter to spare, grown with half to
    /// spare), so that a frame is right on its first recording, frames in flight included,
    /// when assets stream in or the same draws are seen deeper (a camera moving into a
    /// cloud). A frame with more fragments than that all the same (a sample that missed what
    /// is dense), or whose growth a memory budget refuses, is rendered again (standalone) or
    /// completes with `TRANSLUCID_RESULT_FRAME_DEGRADED` (host device), its tail counted, and
    /// the pool grows for later frames. A budget stays as given: the fragments past it are
    /// blended unsorted and counted
    /// (`translucid_frame_statistics::tail_fragments`). At most one storage buffer's worth of
    /// nodes; past it, `TRANSLUCID_RESULT_ERROR_INVALID_ARGUMENT`.
    pub node_budget: u32,
}

/// Settings of `TRANSLUCID_METHOD_DEPTH_PEELING`.
#[allow(non_camel_case_types)]
#[repr(C)]
#[derive(Clone, Copy, Debug)]
pub struct translucid_depth_peeling_settings {
    /// `TRANSLUCID_STRUCTURE_TYPE_DEPTH_PEELING_SETTINGS`.
    pub s_type: u32,
    /// The next method settings structure, or NULL.
    pub next: *const c_void,
    /// Peeling passes, each peeling a pixel's nearest and farthest layer left, 1 to 128. 0
    /// (the default) follows the frames: the passes the frames before needed (half their
    /// deepest pixel's fragments) and up to 32 more, or as many as the frame's own estimate
    /// calls for (half the most transparent quads whose bounds on screen meet over one cell of
    /// 8 x 8 pixels, larger past 512 pixels a side; from a sample of at most 4096 quads),
    /// skipped on the GPU where the
    /// frame needs none of them, so that a frame deeper than those before it (a camera moving
    /// into a cloud) is right on its first recording, frames in flight included (a frame of
    /// many draws records fewer ahead: 4096 skippable draws in all). Past them it is rendered
    /// again, or completes with
    /// `TRANSLUCID_RESULT_FRAME_DEGRADED` on an engine's device. A count stays as given:
    /// pixels with more than twice as many layers lose their middle ones and are counted
    /// (`translucid_frame_statistics::unpeeled_pixels`).
    pub passes: u32,
}

/// The settings a frame's chain gives, each method's defaults where it gives none.
#[derive(Clone, Copy, Debug, Default)]
pub struct MethodSettings {
    exact: Option<translucid_exact_settings>,
    wavelet: Option<translucid_wavelet_settings>,
    linked_list: Option<translucid_linked_list_settings>,
    depth_peeling: Option<translucid_depth_peeling_settings>,
}

/// Chains longer than this are refused (a loop in the caller's chain would never end).
const MOST_LINKS: usize = 16;

impl MethodSettings {
    /// The settings chained from `translucid_frame_info.next`: each structure type at most
    /// once, none of another kind.
    pub fn from_chain(mut next: *const c_void) -> FfiResult<Self> {
        let mut settings = Self::default();
        let mut links = 0;
        while !next.is_null() {
            links += 1;
            if links > MOST_LINKS {
                return Err(chain_error(format!(
                    "translucid_frame_info.next: a chain of more than {MOST_LINKS} structures \
                     (four method settings at most; a loop?)"
                )));
            }
            let base = try_ref(next.cast::<translucid_base_in_structure>(), "next")?;
            use translucid_structure_type as T;
            next = match translucid_structure_type::from_raw(base.s_type) {
                Some(T::ExactSettings) => set(&mut settings.exact, next)?,
                Some(T::WaveletSettings) => set(&mut settings.wavelet, next)?,
                Some(T::LinkedListSettings) => set(&mut settings.linked_list, next)?,
                Some(T::DepthPeelingSettings) => set(&mut settings.depth_peeling, next)?,
                _ => {
                    return Err(chain_error(format!(
                        "translucid_frame_info.next holds structure type {}; it takes method \
                         settings only (translucid_exact_settings, translucid_wavelet_settings, \
                         translucid_linked_list_settings, translucid_depth_peeling_settings)",
                        base.s_type
                    )))
                }
            };
        }
        Ok(settings)
    }

    /// The words that tell `method`'s renderers apart: the method and its own settings (a
    /// structure left out reads as its zeros, the defaults, so that it keys the same renderer).
    pub fn key(&self, method: translucid_method) -> Vec<u64> {
        let words: Vec<u32> = match method {
            translucid_method::Exact => vec![self.exact.map_or(0, |s| s.threshold.to_bits())],
            translucid_method::Wavelet => self.wavelet.map_or(vec![0; 3], |s| {
                vec![s.coefficients, s.noise.to_bits(), s.storage]
            }),
            translucid_method::LinkedList => vec![self.linked_list.map_or(0, |s| s.node_budget)],
            translucid_method::DepthPeeling => vec![self.depth_peeling.map_or(0, |s| s.passes)],
            _ => Vec::new(),
        };
        std::iter::once(method as u64)
            .chain(words.into_iter().map(u64::from))
            .collect()
    }

    /// The core's options, every structure given checked (whatever the frame's method).
    pub fn options(&self) -> FfiResult<MethodOptions> {
        let mut options = MethodOptions::default();
        if let Some(s) = self.exact {
            if !(0.0..=1.0).contains(&s.threshold) {
                return Err(Failure::argument(format!(
                    "translucid_exact_settings.threshold {} is not in [0, 1]",
                    s.threshold
                )));
            }
            options.exact.threshold = s.threshold;
        }
        if let Some(s) = self.wavelet {
            options.wavelet.rank = match s.coefficients {
                0 => None,
                2 => Some(0),
                4 => Some(1),
                8 => Some(2),
                16 => Some(3),
                other => {
                    return Err(Failure::argument(format!(
                        "translucid_wavelet_settings.coefficients {other} is not 0 (the \
                         default), 2, 4, 8 or 16"
                    )))
                }
            };
            options.wavelet.noise = s.noise;
            options.wavelet.storage = Some(translucid_wavelet_storage::from_raw(s.storage)?.core());
        }
        if let Some(s) = self.linked_list {
            options.linked_list.node_budget =
                (s.node_budget != 0).then_some(u64::from(s.node_budget));
        }
        if let Some(s) = self.depth_peeling {
            options.depth_peeling.passes = (s.passes != 0).then_some(s.passes);
        }
        Ok(options)
    }
}

/// A method settings structure and the type its `s_type` names.
trait Settings: Copy {
    const NAME: &'static str;
    fn next(&self) -> *const c_void;
}

macro_rules! settings {
    ($($ty:ident),*) => {$(
        impl Settings for $ty {
            const NAME: &'static str = stringify!($ty);
            fn next(&self) -> *const c_void {
                self.next
            }
        }
    )*};
}
settings!(
    translucid_exact_settings,
    translucid_wavelet_settings,
    translucid_linked_list_settings,
    translucid_depth_peeling_settings
);

/// Reads the structure at `at` into `slot` (a second of its type is refused); the next link.
fn set<S: Settings>(slot: &mut Option<S>, at: *const c_void) -> FfiResult<*const c_void> {
    let settings = *try_ref(at.cast::<S>(), "next")?;
    if slot.replace(settings).is_some() {
        return Err(chain_error(format!(
            "translucid_frame_info.next chains two {}; give each method's settings once",
            S::NAME
        )));
    }
    Ok(settings.next())
}

fn chain_error(message: String) -> Failure {
    Failure::new(translucid_result::ErrorInvalidStructureType, message)
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::ptr::null;

    fn wavelet(coefficients: u32, next: *const c_void) -> translucid_wavelet_settings {
        translucid_wavelet_settings {
            s_type: translucid_structure_type::WaveletSettings as u32,
            next,
            coefficients,
            noise: 0.0,
            storage: 0,
        }
    }

    #[test]
    fn a_left_out_structure_keys_the_same_renderer_as_its_zeros() {
        let zeros = wavelet(0, null());
        let given =
            MethodSettings::from_chain((&zeros as *const translucid_wavelet_settings).cast())
                .expect("a chain");
        let none = MethodSettings::from_chain(null()).expect("no chain");
        let method = translucid_method::Wavelet;
        assert_eq!(given.key(method), none.key(method));
        let eight = wavelet(8, null());
        let other =
            MethodSettings::from_chain((&eight as *const translucid_wavelet_settings).cast())
                .expect("a chain");
        assert_ne!(other.key(method), none.key(method));
        // Another method's settings do not tell the frame's renderers apart.
        assert_eq!(
            other.key(translucid_method::Exact),
            none.key(translucid_method::Exact)
        );
    }

    #[test]
    fn a_chain_takes_each_structure_once() {
        let second = wavelet(0, null());
        let first = wavelet(0, (&second as *const translucid_wavelet_settings).cast());
        let err = MethodSettings::from_chain((&first as *const translucid_wavelet_settings).cast())
            .expect_err("two wavelet settings");
        assert_eq!(err.code, translucid_result::ErrorInvalidStructureType);
    }
}
