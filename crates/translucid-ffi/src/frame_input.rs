//! Turning a frame's C description into the core's `Scene` and `OpaqueLayer`: resolve every
//! handle, check every value, copy only the objects the frame draws.

use crate::cast::{check_header, try_slice};
use crate::context::Objects;
use crate::frame::{
    translucid_draw, translucid_frame_info, translucid_layer, translucid_light,
    translucid_opaque_layer, translucid_pixel_format,
};
use crate::result::{Failure, FfiResult};
use crate::structure::translucid_structure_type;
use glam::{Mat4, Vec3};
use std::collections::HashMap;
use translucid::image::srgb_to_linear;
use translucid::scene::{Camera, Draw, Light, Projection, Scene};
use translucid::OpaqueLayer;

/// Maps handles to indices in the scene being built, copying each object once.
struct Interner<T> {
    index: HashMap<u64, usize>,
    items: Vec<T>,
}

impl<T> Interner<T> {
    fn new() -> Self {
        Self {
            index: HashMap::new(),
            items: Vec::new(),
        }
    }

    fn intern(&mut self, id: u64, make: impl FnOnce() -> FfiResult<T>) -> FfiResult<usize> {
        if let Some(&i) = self.index.get(&id) {
            return Ok(i);
        }
        let i = self.items.len();
        self.items.push(make()?);
        self.index.insert(id, i);
        Ok(i)
    }
}

fn rgb(v: [f32; 3], what: &str) -> FfiResult<Vec3> {
    let v = Vec3::from_array(v);
    if !v.is_finite() || v.min_element() < 0.0 {
        return Err(Failure::argument(format!(
            "{what} {v:?} must be finite and non-negative"
        )));
    }
    Ok(v)
}

pub fn build_scene(
    objects: &Objects,
    info: &translucid_frame_info,
    light: Option<&translucid_light>,
    draws: &[translucid_draw],
) -> FfiResult<Scene> {
    let c = &info.camera;
    if !c.z_far.is_finite() {
        return Err(Failure::argument(format!(
            "camera: far {} must be finite",
            c.z_far
        )));
    }
    let camera = Camera {
        view: Mat4::from_cols_array(&c.view),
        projection: Projection::Perspective {
            fov_y: c.fov_y,
            near: c.z_near,
            far: c.z_far,
        },
        jitter: glam::Vec2::ZERO,
    };
    camera
        .validate()
        .map_err(|e| Failure::argument(format!("camera: {e}")))?;
    let light = match light {
        None => Light::default(),
        Some(l) => {
            let direction = Vec3::from_array(l.direction);
            if !direction.is_finite() || direction.length_squared() == 0.0 {
                return Err(Failure::argument(
                    "light direction must be finite and non-zero",
                ));
            }
            Light {
                direction: direction.normalize(),
                colour: rgb(l.colour, "light colour")?,
                ambient: rgb(l.ambient, "light ambient")?,
            }
        }
    };
    let mut meshes = Interner::new();
    let mut materials = Interner::new();
    let mut textures = Interner::new();
    let mut scene = Scene {
        name: "C API frame".into(),
        camera,
        light,
        background: rgb(info.background, "background")?,
        ..Scene::default()
    };
    for (i, d) in draws.iter().enumerate() {
        let context = |f: Failure| Failure::new(f.code, format!("draw {i}: {}", f.message));
        let mesh = meshes
            .intern(d.mesh.id, || Ok(objects.meshes.get(d.mesh.id)?.clone()))
            .map_err(context)?;
        let material = materials
            .intern(d.material.id, || {
                let record = objects.materials.get(d.material.id)?;
                let mut material = record.material.clone();
                if let Some(t) = record.texture {
                    let texture = textures.intern(t, || Ok(objects.textures.get(t)?.clone()));
                    material.texture = Some(texture.map_err(|f| {
                        Failure::new(f.code, format!("its material's texture: {}", f.message))
                    })?);
                }
                Ok(material)
            })
            .map_err(context)?;
        let transform = Mat4::from_cols_array(&d.transform);
        if !transform.is_finite() {
            return Err(Failure::argument(format!(
                "draw {i}: transform is not finite"
            )));
        }
        let draw = Draw {
            mesh,
            material,
            transform,
        };
        match d.layer {
            l if l == translucid_layer::Transparent as u32 => scene.transparent.push(draw),
            l if l == translucid_layer::Opaque as u32 => scene.opaque.push(draw),
            l => return Err(context(Failure::enumeration("layer", l))),
        }
    }
    scene.meshes = meshes.items;
    scene.materials = materials.items;
    scene.textures = textures.items;
    scene.validate()?;
    Ok(scene)
}

/// The host's opaque layer, converted to linear colour.
pub fn opaque_layer_from(
    layer: &translucid_opaque_layer,
    width: u32,
    height: u32,
) -> FfiResult<OpaqueLayer> {
    check_header(
        layer.s_type,
        layer.next,
        translucid_structure_type::OpaqueLayer,
        "translucid_opaque_layer",
    )?;
    let format = translucid_pixel_format::from_raw(layer.colour_format)?;
    let n = usize::try_from(u64::from(width) * u64::from(height))
        .map_err(|_| Failure::size("opaque layer too large for this machine"))?;
    let colour: Vec<Vec3> = match format {
        translucid_pixel_format::Rgba8Srgb => {
            try_slice(layer.colour.cast::<u8>(), n * 4, "opaque_layer.colour")?
                .chunks_exact(4)
                .map(|p| Vec3::new(p[0].into(), p[1].into(), p[2].into()) / 255.0)
                .map(|v| Vec3::from_array(v.to_array().map(srgb_to_linear)))
                .collect()
        }
        translucid_pixel_format::Rgba32fLinear => {
            try_slice(layer.colour.cast::<f32>(), n * 4, "opaque_layer.colour")?
                .chunks_exact(4)
                .map(Vec3::from_slice)
                .collect()
        }
    };
    let depth = try_slice(layer.depth, n, "opaque_layer.depth")?.to_vec();
    let layer = OpaqueLayer {
        width,
        height,
        colour,
        depth,
    };
    layer.validate(width, height)?;
    Ok(layer)
}
