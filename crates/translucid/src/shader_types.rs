//! The scene's records as the shaders read them ([`crate::interface::scene`] declares them),
//! made from the scene's types; and the mesh pipelines' vertex.

#![deny(unsafe_code)]

use crate::scene::{Camera, Draw, Light, Material, Mesh};
use bytemuck::{Pod, Zeroable};
use glam::{Mat4, Vec4};

pub use crate::interface::scene::*;

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
