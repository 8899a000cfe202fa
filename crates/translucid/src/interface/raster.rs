//! The rasterization rules' constants (`interface_raster.glsl`): what `crate::raster`, the CPU
//! reference's rules, and `raster_rules.glsl`, the shaders' copy of them, must agree on.

use super::{Include, StructDecl};

shader_constants! {
    /// Sub-pixel precision of snapped vertex positions.
    pub const SUBPIXEL_BITS: u32 as int = 8;
    /// Half a pixel in sub-pixel units: pixel centres.
    pub const HALF_PIXEL: u32 as int = 1 << (SUBPIXEL_BITS - 1);
    /// Largest |x_fb| or |y_fb| (pixels) a vertex may have to use the fixed-point path. Keeps
    /// every edge-function product under 2^58.
    pub const GUARD_BAND: f32 = (1u32 << 20) as f32;
}

pub fn include() -> Include {
    const STRUCTS: &[&StructDecl] = &[];
    Include {
        file: "interface_raster.glsl",
        source: "raster.rs",
        constants: CONSTANTS,
        structs: STRUCTS,
        sets: vec![],
        more: None,
        needs: &[],
    }
}
