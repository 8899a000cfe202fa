//! The exact raster's own interface (`interface_exact.glsl`): what a row it suspends keeps,
//! in a binding that extends the bins' set.

use super::bins::BINS_SET;
use super::{Binding, Include, SetDecl, StructDecl};

shader_constants! {
    /// Most fragments a pixel keeps while it walks its row's list (the raster's SELECT_SIZE).
    pub const MAX_SELECT_SIZE: u32 as int = 16;
    /// A resume item's state slot when the row saved no state (it starts over).
    pub const NO_STATE: u32 = u32::MAX;
    /// A saved state's sweep.x when the row resumes with a new sweep (saved between sweeps).
    pub const NEW_SWEEP: u32 = u32::MAX;
}

shader_struct! {
    /// One pixel's compositing state between raster dispatches (std430, 192 bytes). A row is
    /// suspended anywhere in a sweep, even inside one slab's part of its list, so the sweep's
    /// selection goes with it (unless sweep.x is NEW_SWEEP).
    pub struct ExactPixelState as ExactPixelState {
        /// xyz: radiance so far.
        pub radiance: vec4,
        /// xyz: transmittance so far.
        pub transmittance: vec4,
        /// x, y: depth bits and order key of the last composited fragment, z: 1 once the pixel
        /// has no fragment left (it waits for its row).
        pub done: uvec4,
        /// x: the slab the row resumes in, y: the list entry it resumes at, z, w: the nearest
        /// fragment the sweep dropped (low, high word).
        pub sweep: uvec4,
        /// The sweep's kept keys (low, high word).
        pub selection: uvec2[MAX_SELECT_SIZE],
    }
}

/// The bins' set with the states of the tiles the raster suspends: slot s of resume list k
/// keeps its pixels' states at (k * resumeCapacity + s) * TILE_PIXELS (raster_tile.glsl;
/// interface_bins_set.glsl says how tiles take slots).
pub const EXACT_RASTER_SET: SetDecl = SetDecl {
    set: "1",
    extends: Some(&BINS_SET),
    bindings: &[Binding::buffer(
        "PixelStateBlock",
        "",
        &["ExactPixelState g_pixelStates[]"],
    )],
};

pub fn include() -> Include {
    const STRUCTS: &[&StructDecl] = &[&ExactPixelState::GLSL];
    Include {
        file: "interface_exact.glsl",
        source: "exact.rs",
        constants: CONSTANTS,
        structs: STRUCTS,
        sets: vec![&EXACT_RASTER_SET],
        more: None,
        needs: &["interface_bins_set.glsl"],
    }
}
