//! The C API of translucid. In standalone mode the library makes its own headless Vulkan
//! device, renders offscreen and hands pixels back; in host-device mode ([`host`]) it wraps the
//! engine's device and records into the engine's command buffers, never submitting. The
//! header is `include/translucid.h`,
//! generated from this crate by cbindgen (see `cbindgen.toml`) and checked fresh by
//! `tests/header.rs`.
//!
//! Conventions, the same for every export:
//! - An opaque `translucid_context` owns a device and every object made on it. One context
//!   must be used by one thread at a time (externally synchronised); different contexts may
//!   be used from different threads at once. A call that finds another thread in a call on
//!   its context is refused (`TRANSLUCID_RESULT_ERROR_CONTEXT_BUSY`) and does nothing.
//! - Create-info structs are zero-initialised by the caller and start with `s_type` and
//!   `next`; zero fields mean the default. Enums cross as `uint32_t`: an unknown value is an
//!   error, never undefined behaviour.
//! - Every fallible call returns a `translucid_result` (0 success, > 0 a status, < 0 an
//!   error), keeps a message for `translucid_context_get_last_error`, and writes its
//!   out-parameters only on success.
//! - Objects are named by generational handles: a destroyed or another context's handle is
//!   an error, not a crash.
//! - No panic crosses into C: it becomes `TRANSLUCID_RESULT_ERROR_PANIC`, and the context
//!   refuses further work.
//! - Functions are named `translucid_<object>_<verb>[_<what>]`, but for the few that only name
//!   a constant (`translucid_result_string`); a structure type is its struct's name
//!   upper-cased. `tests/header.rs` holds the generated header to both.
//!
//! The object model (handles, assets, renderers, frames in flight) is the core's
//! `translucid::context`; this crate converts, checks structures and turns errors into
//! results.
//!
//! Module map: [`cast`] (the only place raw pointers become references), [`panic`] (the
//! boundary), [`result`], [`structure`], [`version`], then one module per object
//! with its exports: [`context`], [`method`], [`mesh`], [`texture`], [`material`], [`frame`]
//! (with [`frame_input`] building the core scene), [`host`] (host-device mode, with the
//! Vulkan types of [`vulkan`], and [`views`]: where a frame's views are in the engine's
//! images).

pub mod cast;
pub mod context;
pub mod frame;
pub mod frame_input;
pub mod host;
pub mod material;
pub mod memory;
pub mod mesh;
pub mod method;
pub mod method_settings;
pub mod panic;
pub mod prepare;
pub mod result;
pub mod structure;
pub mod texture;
pub mod version;
pub mod views;
pub mod vulkan;

pub use result::translucid_result;
