//! Host mirrors of `shaders/common/layout.glsl`. Field order, sizes and offsets must match
//! the GLSL structs; `tests::layouts_match_glsl` parses the GLSL and checks every offset.

#![deny(unsafe_code)]

use crate::scene::{Camera, Draw, Light, Material, Mesh};
use bytemuck::{Pod, Zeroable};
use glam::{Mat4, Vec4};

pub const MATERIAL_LIT: u32 = 1;
pub const MATERIAL_DOUBLE_SIDED: u32 = 2;
pub const DRAW_HAS_NORMALS: u32 = 1;
pub const DRAW_HAS_UVS: u32 = 2;

#[repr(C)]
#[derive(Clone, Copy, Debug, Pod, Zeroable)]
pub struct GpuMaterial {
    pub base_colour: [f32; 4],
    pub tint_transmission: [f32; 4],
    pub reflectance: f32,
    pub alpha_cutoff: f32,
    pub texture_index: i32,
    pub flags: u32,
}

#[repr(C)]
#[derive(Clone, Copy, Debug, Pod, Zeroable)]
pub struct GpuDrawInfo {
    pub model: [f32; 16],
    pub normal_matrix: [f32; 16],
    pub material_index: u32,
    pub flags: u32,
    pub first_quad: u32,
    pub quad_count: u32,
    /// The draw's tint, multiplied into its vertex colours.
    pub tint: [f32; 4],
}

#[repr(C)]
#[derive(Clone, Copy, Debug, Pod, Zeroable)]
pub struct GpuFrameInfo {
    pub view_proj: [f32; 16],
    pub light_direction: [f32; 4],
    pub light_colour: [f32; 4],
    pub ambient: [f32; 4],
    pub viewport: [f32; 4],
    /// Device depth = x − y / d + z · d at order depth d ([`Camera::depth_mapping`]); w is 1
    /// when the order depth is device depth + 1 (orthographic), 0 when it is clip w.
    pub depth_mapping: [f32; 4],
    /// xyz: the camera's position in the world, which face normals of the graphics passes
    /// are taken relative to.
    pub eye: [f32; 4],
}

/// One vertex of the mesh pipelines (48 bytes; attribute locations 0–3).
#[repr(C)]
#[derive(Clone, Copy, Debug, Pod, Zeroable)]
pub struct GpuVertex {
    pub position: [f32; 3],
    pub normal: [f32; 3],
    pub uv: [f32; 2],
    pub colour: [f32; 4],
}

impl GpuMaterial {
    pub fn new(m: &Material) -> Self {
        let mut flags = 0;
        if m.lit {
            flags |= MATERIAL_LIT;
        }
        if m.double_sided {
            flags |= MATERIAL_DOUBLE_SIDED;
        }
        Self {
            base_colour: m.base_colour.to_array(),
            tint_transmission: m.transmission_tint.extend(m.transmission).to_array(),
            reflectance: m.reflectance,
            alpha_cutoff: m.alpha_cutoff.unwrap_or(-1.0),
            texture_index: m.texture.map_or(-1, |t| t as i32),
            flags,
        }
    }
}

impl GpuDrawInfo {
    pub fn new(draw: &Draw, mesh: &Mesh, first_quad: u32) -> Self {
        let normal_matrix = Mat4::from_mat3(crate::shading::normal_matrix(&draw.transform));
        Self {
            model: draw.transform.to_cols_array(),
            normal_matrix: normal_matrix.to_cols_array(),
            material_index: draw.material as u32,
            flags: flag(mesh.normals.is_some(), DRAW_HAS_NORMALS)
                | flag(mesh.uvs.is_some(), DRAW_HAS_UVS),
            first_quad,
            quad_count: mesh.quads.len() as u32,
            tint: draw.tint.to_array(),
        }
    }
}

fn flag(set: bool, bit: u32) -> u32 {
    if set {
        bit
    } else {
        0
    }
}

impl GpuFrameInfo {
    /// The frame constants of `camera` (jitter and depth direction as
    /// [`Camera::view_projection`] makes them) and `light` at `width` x `height`.
    pub fn new(camera: &Camera, light: &Light, width: u32, height: u32) -> Self {
        let (w, h) = (width as f32, height as f32);
        let (a, b, c) = camera.depth_mapping(width, height);
        let by_z = camera.depth_order() == crate::raster::DepthOrder::DeviceZ;
        Self {
            view_proj: camera.view_projection(width, height).to_cols_array(),
            depth_mapping: [a, b, c, f32::from(u8::from(by_z))],
            light_direction: light.direction.normalize_or_zero().extend(0.0).to_array(),
            light_colour: light.colour.extend(0.0).to_array(),
            ambient: light.ambient.extend(0.0).to_array(),
            viewport: Vec4::new(w, h, 1.0 / w, 1.0 / h).to_array(),
            eye: camera.eye().extend(1.0).to_array(),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::mem::{offset_of, size_of};

    fn check(name: &str, host: &[(&str, usize)], host_size: usize) {
        let src = include_str!("../../../shaders/common/layout.glsl");
        let (glsl, _) = crate::glsl_layout::std430_offsets(src, name);
        let host: Vec<_> = host
            .iter()
            .map(|(n, o)| (n.replace('_', "").to_lowercase(), *o))
            .collect();
        let glsl_norm: Vec<_> = glsl.iter().map(|(n, o)| (n.to_lowercase(), *o)).collect();
        assert_eq!(
            glsl_norm, host,
            "{name}: shader_types.rs and layout.glsl disagree; update both"
        );
        let end = glsl.last().map(|(_, o)| *o).unwrap_or(0);
        assert!(
            host_size > end && host_size % 16 == 0,
            "{name}: size {host_size} not a multiple of 16"
        );
    }

    #[test]
    fn layouts_match_glsl() {
        check(
            "Material",
            &[
                ("base_colour", offset_of!(GpuMaterial, base_colour)),
                (
                    "tint_transmission",
                    offset_of!(GpuMaterial, tint_transmission),
                ),
                ("reflectance", offset_of!(GpuMaterial, reflectance)),
                ("alpha_cutoff", offset_of!(GpuMaterial, alpha_cutoff)),
                ("texture_index", offset_of!(GpuMaterial, texture_index)),
                ("flags", offset_of!(GpuMaterial, flags)),
            ],
            size_of::<GpuMaterial>(),
        );
        check(
            "DrawInfo",
            &[
                ("model", offset_of!(GpuDrawInfo, model)),
                ("normal_matrix", offset_of!(GpuDrawInfo, normal_matrix)),
                ("material_index", offset_of!(GpuDrawInfo, material_index)),
                ("flags", offset_of!(GpuDrawInfo, flags)),
                ("first_quad", offset_of!(GpuDrawInfo, first_quad)),
                ("quad_count", offset_of!(GpuDrawInfo, quad_count)),
                ("tint", offset_of!(GpuDrawInfo, tint)),
            ],
            size_of::<GpuDrawInfo>(),
        );
        check(
            "FrameInfo",
            &[
                ("view_proj", offset_of!(GpuFrameInfo, view_proj)),
                ("light_direction", offset_of!(GpuFrameInfo, light_direction)),
                ("light_colour", offset_of!(GpuFrameInfo, light_colour)),
                ("ambient", offset_of!(GpuFrameInfo, ambient)),
                ("viewport", offset_of!(GpuFrameInfo, viewport)),
                ("depth_mapping", offset_of!(GpuFrameInfo, depth_mapping)),
                ("eye", offset_of!(GpuFrameInfo, eye)),
            ],
            size_of::<GpuFrameInfo>(),
        );
    }

    #[test]
    fn flags_match_glsl() {
        let src = include_str!("../../../shaders/common/layout.glsl");
        assert!(src.contains(&format!("#define MATERIAL_LIT {MATERIAL_LIT}u")));
        assert!(src.contains(&format!(
            "#define MATERIAL_DOUBLE_SIDED {MATERIAL_DOUBLE_SIDED}u"
        )));
        assert!(src.contains(&format!("#define DRAW_HAS_NORMALS {DRAW_HAS_NORMALS}u")));
        assert!(src.contains(&format!("#define DRAW_HAS_UVS {DRAW_HAS_UVS}u")));
    }
}
