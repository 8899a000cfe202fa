//! Turning a frame's C description into what the core's context takes (`FrameRequest`) and
//! the core's `OpaqueLayer`: check every value, convert the camera, light and draws. The
//! draws' handles are resolved by the renderer that draws them
//! (`translucid::context::renderers`).

use crate::cast::{check_header, check_type, try_ref, try_slice};
use crate::context::Objects;
use crate::frame::{
    translucid_camera, translucid_draw, translucid_frame_info, translucid_layer, translucid_light,
    translucid_opaque_layer, translucid_pixel_format, TRANSLUCID_MAX_DRAWS,
};
use crate::method::translucid_method;
use crate::method_settings::MethodSettings;
use crate::result::{Failure, FfiResult};
use crate::structure::translucid_structure_type;
use glam::{Mat4, Vec2, Vec3};
use translucid::context::renderers::{DrawRequest, FrameRequest, Layer};
use translucid::image::srgb_to_linear;
use translucid::scene::{Camera, Light, Projection};
use translucid::OpaqueLayer;

fn rgb(v: [f32; 3], what: &str) -> FfiResult<Vec3> {
    let v = Vec3::from_array(v);
    if !translucid::shading::is_colour(v.extend(0.0)) {
        return Err(Failure::argument(format!(
            "{what} {{{}, {}, {}}} must be non-negative and at most {}",
            v.x,
            v.y,
            v.z,
            translucid::shading::MAX_COLOUR
        )));
    }
    Ok(v)
}

/// The core's camera from the C one: the engine's projection matrix when it gave one, else
/// the field-of-view helper.
pub(crate) fn camera_from(c: &translucid_camera) -> FfiResult<Camera> {
    let projection = if c.projection.iter().all(|&v| v == 0.0) {
        Projection::Perspective {
            fov_y: c.fov_y,
            near: c.z_near,
            far: c.z_far,
        }
    } else {
        Projection::Matrix(Mat4::from_cols_array(&c.projection))
    };
    let camera = Camera {
        view: Mat4::from_cols_array(&c.view),
        projection,
        jitter: Vec2::from_array(c.jitter),
    };
    camera
        .validate()
        .map_err(|e| Failure::argument(format!("translucid_camera: {e}")))?;
    Ok(camera)
}

fn light_from(light: Option<&translucid_light>) -> FfiResult<Light> {
    let Some(l) = light else {
        return Ok(Light::default());
    };
    let direction = Vec3::from_array(l.direction);
    if !direction.is_finite() || direction.length_squared() == 0.0 {
        return Err(Failure::argument(
            "translucid_light.direction must be finite and non-zero",
        ));
    }
    Ok(Light {
        direction: direction.normalize(),
        colour: rgb(l.colour, "translucid_light.colour")?,
        ambient: rgb(l.ambient, "translucid_light.ambient")?,
    })
}

/// Checks `info` and turns it into a renderer's request (with the host's opaque layer, when
/// it has one, in the second value).
/// A draw as the core takes it: its transform finite, its tint a colour (zero: none), its
/// layer known.
fn draw_from(i: usize, d: &translucid_draw) -> FfiResult<DrawRequest> {
    let in_draw = |f: Failure| Failure::new(f.code, format!("draws[{i}]: {}", f.message));
    let transform = Mat4::from_cols_array(&d.transform);
    if !transform.is_finite() {
        return Err(in_draw(Failure::argument("transform is not finite")));
    }
    let tint = match glam::Vec4::from_array(d.tint) {
        t if t == glam::Vec4::ZERO => glam::Vec4::ONE,
        t if translucid::shading::is_colour(t) => t,
        t => {
            return Err(in_draw(Failure::argument(format!(
                "tint {:?} must be non-negative and at most {}",
                t.to_array(),
                translucid::shading::MAX_COLOUR
            ))))
        }
    };
    let layer = match d.layer {
        l if l == translucid_layer::Transparent as u32 => Layer::Transparent,
        l if l == translucid_layer::Opaque as u32 => Layer::Opaque,
        l => return Err(in_draw(Failure::enumeration("translucid_layer", l))),
    };
    Ok(DrawRequest {
        mesh: d.mesh.id,
        material: d.material.id,
        transform,
        tint,
        layer,
    })
}

/// `camera`, when given, replaces `info.camera`, which is then not read (a frame of several
/// views, whose views give theirs).
pub(crate) fn frame_request<'a>(
    objects: &Objects,
    info: &'a translucid_frame_info,
    camera: Option<Camera>,
) -> FfiResult<(FrameRequest, Option<&'a translucid_opaque_layer>)> {
    check_type(
        info.s_type,
        translucid_structure_type::FrameInfo,
        "translucid_frame_info",
    )?;
    let settings = MethodSettings::from_chain(info.next)?;
    let method = translucid_method::from_raw(info.method)?;
    check_frame_size(objects.gpu(), info.width, info.height)?;
    let last_frame_index = objects.core.last_frame_index();
    if info.frame_index != 0 && info.frame_index < last_frame_index {
        return Err(Failure::argument(format!(
            "translucid_frame_info.frame_index {} after {last_frame_index}: frame indices may \
             not go backwards on a context (views of one frame share theirs; 0 is none)",
            info.frame_index
        )));
    }
    if info.draw_count > TRANSLUCID_MAX_DRAWS {
        return Err(Failure::size(format!(
            "draw_count {} is over TRANSLUCID_MAX_DRAWS ({TRANSLUCID_MAX_DRAWS})",
            info.draw_count
        )));
    }
    let count = usize::try_from(info.draw_count).map_err(|_| Failure::size("too many draws"))?;
    let draws = try_slice(info.draws, count, "draws")?;
    let light = if info.light.is_null() {
        None
    } else {
        Some(try_ref(info.light, "light")?)
    };
    let layer = if info.opaque_layer.is_null() {
        None
    } else {
        Some(try_ref(info.opaque_layer, "opaque_layer")?)
    };
    if let Some(i) = draws
        .iter()
        .position(|d| d.layer == translucid_layer::Opaque as u32)
    {
        if objects.gpu().is_host_device() {
            return Err(Failure::argument(format!(
                "draws[{i}] is in TRANSLUCID_LAYER_OPAQUE, but in host-device mode the opaque \
                 layer is your colour and depth images: draw opaque geometry into them"
            )));
        }
        if layer.is_some() {
            return Err(Failure::argument(format!(
                "draws[{i}] is in TRANSLUCID_LAYER_OPAQUE, but the frame has the host's opaque \
                 layer: draw opaque geometry into that layer, or leave opaque_layer NULL"
            )));
        }
    }
    let request = FrameRequest {
        key: settings.key(method),
        method: method.kind(),
        width: info.width,
        height: info.height,
        options: settings.options()?,
        camera: match camera {
            Some(camera) => camera,
            None => camera_from(&info.camera)?,
        },
        light: light_from(light)?,
        background: rgb(info.background, "background")?,
        draws: draws
            .iter()
            .enumerate()
            .map(|(i, d)| draw_from(i, d))
            .collect::<FfiResult<_>>()?,
        frame_index: info.frame_index,
    };
    Ok((request, layer))
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

/// A frame's size, in the header's terms: 1 to the device's largest image on each side.
fn check_frame_size(gpu: &translucid::gpu::Gpu, width: u32, height: u32) -> FfiResult {
    let most = gpu.info().max_image_dimension_2d;
    for (field, value) in [("width", width), ("height", height)] {
        if value == 0 {
            return Err(Failure::size(format!(
                "translucid_frame_info.{field} is 0: a frame is at least 1x1"
            )));
        }
        if value > most {
            return Err(Failure::size(format!(
                "translucid_frame_info.{field} {value} is over {most}, the largest frame this \
                 device renders (VkPhysicalDeviceLimits::maxImageDimension2D)"
            )));
        }
    }
    Ok(())
}
