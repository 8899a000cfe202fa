//! Materials from C. Exports `translucid_material_*`.

use crate::cast::{check_header, translucid_context, try_out, try_ref, try_str};
use crate::panic;
use crate::result::{translucid_result, Failure, FfiResult};
use crate::structure::translucid_structure_type;
use crate::texture::translucid_texture;
use glam::{Vec3, Vec4};
use std::ffi::{c_char, c_void};
use translucid::scene::Material;

/// Lit by the frame's light (ambient plus two-sided Lambert); otherwise shown at its colour.
pub const TRANSLUCID_MATERIAL_LIT: u32 = 1;
/// Back faces (clockwise on screen) are culled; otherwise both sides are drawn.
pub const TRANSLUCID_MATERIAL_CULL_BACK_FACES: u32 = 2;
const MATERIAL_FLAGS: u32 = TRANSLUCID_MATERIAL_LIT | TRANSLUCID_MATERIAL_CULL_BACK_FACES;

/// A material. Zero-initialise, then set `s_type` and at least `base_colour` (zero is a fully
/// transparent black).
#[allow(non_camel_case_types)]
#[repr(C)]
pub struct translucid_material_create_info {
    /// `TRANSLUCID_STRUCTURE_TYPE_MATERIAL_CREATE_INFO`.
    pub s_type: u32,
    /// NULL.
    pub next: *const c_void,
    /// Linear RGB (each channel in [0, 65504], the largest half float) and alpha (coverage, 0
    /// to 1). Multiplied by vertex colours and the texture; the radiance a fragment gives and
    /// every output pixel are clamped to 65504.
    pub base_colour: [f32; 4],
    /// Base-colour texture, or `{0}` for none. The material keeps the handle: destroying the
    /// texture makes frames that draw this material fail.
    pub texture: translucid_texture,
    /// 0 to 1: fraction of the covered light passed through (tinted) instead of scattered.
    pub transmission: f32,
    /// 0 to 1 per channel: filter on transmitted light; ignored when `transmission` is 0.
    pub transmission_tint: [f32; 3],
    /// 0 to 1: specular reflectance at normal incidence of transmissive surfaces.
    pub reflectance: f32,
    /// Opaque draws only: fragments with alpha below this are discarded; 0 keeps all.
    pub alpha_cutoff: f32,
    /// `TRANSLUCID_MATERIAL_*` bits; other bits must be 0.
    pub flags: u32,
    /// Optional name for messages (copied).
    pub name: *const c_char,
}

/// A material handle. `{0}` is the NULL handle.
#[allow(non_camel_case_types)]
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct translucid_material {
    pub id: u64,
}

fn material_from_info(info: &translucid_material_create_info) -> FfiResult<Material> {
    check_header(
        info.s_type,
        info.next,
        translucid_structure_type::MaterialCreateInfo,
        "translucid_material_create_info",
    )?;
    if info.flags & !MATERIAL_FLAGS != 0 {
        return Err(Failure::argument(format!(
            "unknown material flags {:#x}",
            info.flags & !MATERIAL_FLAGS
        )));
    }
    let cutoff = info.alpha_cutoff;
    if !(0.0..=1.0).contains(&cutoff) {
        return Err(Failure::argument(format!(
            "alpha_cutoff {cutoff} is not in [0, 1]"
        )));
    }
    let material = Material {
        name: try_str(info.name, "name")?.unwrap_or("").to_string(),
        base_colour: Vec4::from_array(info.base_colour),
        texture: None,
        transmission: info.transmission,
        transmission_tint: Vec3::from_array(info.transmission_tint),
        reflectance: info.reflectance,
        lit: info.flags & TRANSLUCID_MATERIAL_LIT != 0,
        double_sided: info.flags & TRANSLUCID_MATERIAL_CULL_BACK_FACES == 0,
        alpha_cutoff: (cutoff > 0.0).then_some(cutoff),
    };
    material
        .validate()
        .map_err(|e| Failure::argument(format!("material \"{}\": {e}", material.name)))?;
    Ok(material)
}

impl translucid_material {
    /// Creates a material and writes its handle to `*out_material`.
    #[no_mangle]
    #[must_use]
    pub extern "C" fn translucid_material_create(
        context: *mut translucid_context,
        info: *const translucid_material_create_info,
        out_material: *mut translucid_material,
    ) -> translucid_result {
        panic::with_context(context, |objects| {
            let info = try_ref(info, "info")?;
            let out = try_out(out_material, "out_material")?;
            let material = material_from_info(info)?;
            let texture = (info.texture.id != 0).then_some(info.texture.id);
            let id = objects.core.create_material(material, texture)?;
            out.write(translucid_material { id });
            Ok(translucid_result::Success)
        })
    }

    /// Destroys a material; its handle becomes stale.
    #[no_mangle]
    pub extern "C" fn translucid_material_destroy(
        context: *mut translucid_context,
        material: translucid_material,
    ) -> translucid_result {
        panic::with_context(context, |objects| {
            objects.core.destroy_material(material.id)?;
            Ok(translucid_result::Success)
        })
    }
}
