//! The scene as every pipeline reads it: materials, draws and the frame's constants
//! (`interface_scene.glsl`).

use super::{Binding, Include, SetDecl, StructDecl};

shader_constants! {
    /// `Material.flags`: the material is lit by the frame's light.
    pub const MATERIAL_LIT: u32 = 1;
    /// `Material.flags`: both faces are drawn.
    pub const MATERIAL_DOUBLE_SIDED: u32 = 2;
    /// `DrawInfo.flags`: the draw's mesh has vertex normals.
    pub const DRAW_HAS_NORMALS: u32 = 1;
    /// `DrawInfo.flags`: the draw's mesh has uvs.
    pub const DRAW_HAS_UVS: u32 = 2;
}

shader_struct! {
    /// One material (std430, 48 bytes).
    pub struct GpuMaterial as Material {
        /// Linear RGB, alpha = coverage.
        pub base_colour: vec4,
        /// xyz: transmission tint, w: transmission.
        pub tint_transmission: vec4,
        pub reflectance: float,
        /// Below 0: no cutoff.
        pub alpha_cutoff: float,
        /// Below 0: no texture.
        pub texture_index: int,
        /// MATERIAL_* bits.
        pub flags: uint,
    }
}

shader_struct! {
    /// One draw (std430, 144 bytes).
    pub struct GpuDrawInfo as DrawInfo {
        pub model: mat4,
        /// shading::normal_matrix of model, in a mat4.
        pub normal_matrix: mat4,
        pub material_index: uint,
        /// DRAW_* bits.
        pub flags: uint,
        /// Index of the draw's first quad in the scene's quad buffer.
        pub first_quad: uint,
        pub quad_count: uint,
        /// Multiplied into the draw's vertex colours.
        pub tint: vec4,
    }
}

shader_struct! {
    /// Per-frame constants (a uniform block: std140, the same as std430 for these fields).
    pub struct GpuFrameInfo as FrameInfo {
        pub view_proj: mat4,
        /// xyz: towards the light, normalised.
        pub light_direction: vec4,
        pub light_colour: vec4,
        pub ambient: vec4,
        /// Width, height, 1/width, 1/height.
        pub viewport: vec4,
        /// Device depth = x - y / d + z d at order depth d; w is 1 when the order depth is
        /// device depth + 1 (orthographic projections), 0 when it is clip w.
        pub depth_mapping: vec4,
        /// xyz: the camera's position in the world, which face normals of the graphics passes
        /// are taken relative to.
        pub eye: vec4,
    }
}

pub fn include() -> Include {
    const STRUCTS: &[&StructDecl] = &[&GpuMaterial::GLSL, &GpuDrawInfo::GLSL, &GpuFrameInfo::GLSL];
    Include {
        file: "interface_scene.glsl",
        source: "scene.rs",
        constants: CONSTANTS,
        structs: STRUCTS,
        sets: vec![],
        more: None,
        needs: &[],
    }
}

/// Set 0 of every pipeline that reads the scene: the frame's constants, its draws and the
/// materials (`interface_scene_set.glsl`).
pub const SCENE_SET: SetDecl = SetDecl::new(
    "0",
    &[
        Binding::uniform("FrameBlock", &["FrameInfo u_frame"]),
        Binding::buffer("DrawBlock", "readonly", &["DrawInfo g_draws[]"]),
        Binding::buffer("MaterialBlock", "readonly", &["Material g_materials[]"]),
    ],
);

pub fn set_include() -> Include {
    Include {
        file: "interface_scene_set.glsl",
        source: "scene.rs",
        constants: &[],
        structs: &[],
        sets: vec![&SCENE_SET],
        more: None,
        needs: &["interface_scene.glsl"],
    }
}
