//! Frames: render a list of draws with one method, then read the pixels, write a PNG or look
//! at the statistics. Exports `translucid_frame_*`.

use crate::cast::{
    check_type, translucid_context, try_out, try_out_slice, try_out_structure, try_ref, try_str,
    OutStructure,
};
use crate::context::Objects;
use crate::frame_input::{frame_request, opaque_layer_from};
use crate::material::translucid_material;
use crate::mesh::translucid_mesh;
use crate::method::translucid_method;
use crate::panic;
use crate::result::{translucid_result, Failure, FfiResult};
use crate::structure::translucid_structure_type;
use crate::views::TRANSLUCID_MAX_VIEWS;
use std::ffi::{c_char, c_void};
use translucid::context::frames::FrameRecord;
use translucid::Image;

/// Most draws in one frame: what every Vulkan device holds in the one storage binding of
/// draw records the graphics passes read (128 MB of 160-byte records is 838,860 draws).
pub const TRANSLUCID_MAX_DRAWS: u32 = 786_432;
/// Most stages `translucid_frame_statistics` reports.
pub const TRANSLUCID_MAX_STAGES: usize = 16;
/// Size of a stage name, NUL included.
pub const TRANSLUCID_STAGE_NAME_SIZE: usize = 32;

/// Where the frame is seen from, in Vulkan conventions: clip space with framebuffer Y down and
/// depth z/w in [0, 1]. Give the engine's own `projection` matrix (reversed-Z, an infinite far
/// plane and orthographic projections are taken as they are), or leave it all zero for a
/// symmetric perspective from `fov_y`, `z_near` and `z_far` whose aspect is the frame's
/// width / height.
///
/// Depth: with the engine's matrix, the engine's depth image must hold that matrix's depth;
/// whether depth grows or shrinks with distance (reversed-Z) is read from the matrix. With
/// `fov_y`, depth is 0 at `z_near` and 1 at `z_far`, as `glm::perspectiveRH_ZO` with its Y
/// axis flipped.
#[allow(non_camel_case_types)]
#[repr(C)]
#[derive(Clone, Copy, Debug)]
pub struct translucid_camera {
    /// World-to-view matrix, column-major (as GLM, glam and most engines store it), finite;
    /// right-handed view space looking down -Z.
    pub view: [f32; 16],
    /// Clip-from-view matrix, column-major, as the engine rasterizes with it (without the
    /// jitter): perspective (`w` proportional to view z, the far plane may be at infinity)
    /// or orthographic (`w` constant, looking down -Z). All zero: `fov_y`, `z_near`, `z_far`.
    pub projection: [f32; 16],
    /// Without `projection`: vertical field of view in radians, in (0, pi).
    pub fov_y: f32,
    /// Without `projection`: near plane distance, > 0 and finite.
    pub z_near: f32,
    /// Without `projection`: far plane distance, > `z_near`; `INFINITY` for an infinite far
    /// plane.
    pub z_far: f32,
    /// Sub-pixel offset of the whole image in pixels (x right, y down), applied after the
    /// projection as temporal anti-aliasing jitters it; 0, 0 for none. The engine's depth
    /// must have been rendered with the same jitter.
    pub jitter: [f32; 2],
}

/// Ambient light plus one directional light, for lit materials.
#[allow(non_camel_case_types)]
#[repr(C)]
#[derive(Clone, Copy, Debug)]
pub struct translucid_light {
    /// Points towards the light; finite and non-zero (normalised by translucid).
    pub direction: [f32; 3],
    /// Linear RGB, each channel in [0, 65504] (the largest half float, what colour targets
    /// hold).
    pub colour: [f32; 3],
    /// Linear RGB, each channel in [0, 65504].
    pub ambient: [f32; 3],
}

/// Which layer a draw belongs to.
#[allow(non_camel_case_types)]
#[repr(u32)]
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum translucid_layer {
    /// Blended by the frame's method, in submission order where order matters.
    Transparent = 0,
    /// Depth-tested and depth-writing, drawn first.
    Opaque = 1,
}

/// One instance of a mesh.
#[allow(non_camel_case_types)]
#[repr(C)]
#[derive(Clone, Copy, Debug)]
pub struct translucid_draw {
    pub mesh: translucid_mesh,
    pub material: translucid_material,
    /// Model-to-world matrix, column-major, finite and affine (its last row 0, 0, 0, 1).
    pub transform: [f32; 16],
    /// A `translucid_layer`; 0 is transparent.
    pub layer: u32,
    /// Linear RGBA multiplied into this instance's colour, as a vertex colour is (alpha into
    /// its coverage), each channel in [0, 65504]; all zero (the default) is no tint.
    pub tint: [f32; 4],
}

/// Pixel layouts for reading frames and passing opaque layers. Rows top first, tightly
/// packed.
#[allow(non_camel_case_types)]
#[repr(u32)]
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum translucid_pixel_format {
    /// 4 bytes per pixel, sRGB-encoded RGB, alpha 255.
    Rgba8Srgb = 0,
    /// 16 bytes per pixel, four native-endian floats of linear RGB, alpha 1.
    Rgba32fLinear = 1,
}

impl translucid_pixel_format {
    pub fn from_raw(value: u32) -> FfiResult<Self> {
        [Self::Rgba8Srgb, Self::Rgba32fLinear]
            .into_iter()
            .find(|f| *f as u32 == value)
            .ok_or_else(|| Failure::enumeration("pixel format", value))
    }

    pub fn bytes_per_pixel(self) -> usize {
        match self {
            Self::Rgba8Srgb => 4,
            Self::Rgba32fLinear => 16,
        }
    }
}

/// The engine's own opaque layer, which the transparent draws are depth-tested against and
/// composited over (instead of a background colour and opaque draws).
#[allow(non_camel_case_types)]
#[repr(C)]
pub struct translucid_opaque_layer {
    /// `TRANSLUCID_STRUCTURE_TYPE_OPAQUE_LAYER`.
    pub s_type: u32,
    /// NULL.
    pub next: *const c_void,
    /// A `translucid_pixel_format` for `colour`.
    pub colour_format: u32,
    /// Required: width x height pixels in `colour_format` (alpha ignored); each channel of
    /// the linear colour in [0, 65504].
    pub colour: *const c_void,
    /// Required: width x height floats, each in [0, 1]: the depth buffer of the frame's
    /// camera, in the convention where depth grows away from the eye (0 near, 1 far). With a
    /// reversed-Z projection, hand over 1 - d.
    pub depth: *const f32,
}

/// Everything one frame needs. Zero-initialise, then set `s_type`, `width`, `height`, the
/// camera and the draws.
#[allow(non_camel_case_types)]
#[repr(C)]
pub struct translucid_frame_info {
    /// `TRANSLUCID_STRUCTURE_TYPE_FRAME_INFO`.
    pub s_type: u32,
    /// NULL, or a chain of method settings (`translucid_exact_settings`,
    /// `translucid_wavelet_settings`, `translucid_linked_list_settings`,
    /// `translucid_depth_peeling_settings`), each at most once; a method without its
    /// structure in the chain takes its defaults. Settings of other methods than `method`
    /// are checked and otherwise ignored, so one chain may serve every method.
    pub next: *const c_void,
    /// A `translucid_method`; see `translucid_method_get_available`.
    pub method: u32,
    /// 1 to the device's largest image side (`VkPhysicalDeviceLimits::maxImageDimension2D`,
    /// at least 4096); past it, `TRANSLUCID_RESULT_ERROR_INVALID_SIZE`. Frames of any size
    /// may follow one another, as a dynamic resolution moves it: a frame no larger in either
    /// side than the largest one drawn with the method and settings builds and allocates
    /// nothing for its size; a larger one allocates that size's buffers once.
    pub width: u32,
    /// As `width`.
    pub height: u32,
    pub camera: translucid_camera,
    /// Optional: NULL uses a default light.
    pub light: *const translucid_light,
    /// `draw_count` draws (NULL allowed when 0), at most `TRANSLUCID_MAX_DRAWS`.
    pub draws: *const translucid_draw,
    pub draw_count: u32,
    /// Linear RGB behind everything when there is no `opaque_layer`.
    pub background: [f32; 3],
    /// Optional: the engine's opaque colour and depth, replacing `background`; then no draw
    /// may be in the opaque layer.
    pub opaque_layer: *const translucid_opaque_layer,
    /// Optional: the engine's frame number, which the frame's statistics report back. It may
    /// not go backwards on a context (views of one engine frame share it); 0 is none.
    pub frame_index: u64,
}

/// GPU time of one stage.
#[allow(non_camel_case_types)]
#[repr(C)]
#[derive(Clone, Copy, Debug)]
pub struct translucid_stage_time {
    /// NUL-terminated stage name ("opaque", then the method's stages...).
    pub name: [c_char; TRANSLUCID_STAGE_NAME_SIZE],
    pub milliseconds: f64,
}

/// What a frame cost. The caller sets `s_type` and `next`; translucid fills the rest.
#[allow(non_camel_case_types)]
#[repr(C)]
pub struct translucid_frame_statistics {
    /// `TRANSLUCID_STRUCTURE_TYPE_FRAME_STATISTICS`, set by the caller.
    pub s_type: u32,
    /// NULL, or a `translucid_frame_view_statistics` to fill too, set by the caller.
    pub next: *mut c_void,
    /// The `translucid_method` that rendered the frame.
    pub method: u32,
    pub width: u32,
    pub height: u32,
    /// Number of valid entries in `stages`.
    pub stage_count: u32,
    /// GPU time per stage, in order; the first `stage_count` are valid.
    pub stages: [translucid_stage_time; TRANSLUCID_MAX_STAGES],
    /// GPU time of all stages.
    pub gpu_milliseconds: f64,
    /// GPU time of the method's stages alone (not the opaque layer).
    pub method_milliseconds: f64,
    /// Peak GPU memory allocated while the frame was rendered.
    pub peak_gpu_bytes: u64,
    /// Transparent fragments composited, for methods that count them (exact); 0 otherwise.
    pub fragments: u64,
    /// Times the frame was rendered again because a method's buffer overflowed (and was
    /// grown); 0 for methods without such buffers, and always 0 in host-device mode, which
    /// cannot render again inside a recording (see `overflowed`).
    pub overflow_rerenders: u32,
    /// 1 when the frame went past a limit of one recording (pixel rows left with the opaque
    /// colour, or near-plane triangles past one storage buffer's worth), so that its image is
    /// not all right; else 0. Only host-device frames can end so (`translucid_frame_complete`
    /// returns `TRANSLUCID_RESULT_FRAME_DEGRADED`); standalone frames render again instead.
    pub overflowed: u32,
    /// The frame's `translucid_frame_info::frame_index`.
    pub frame_index: u64,
    /// Pipelines the calls that made the frame created, each a shader compilation: the
    /// `translucid_frame_render` or `translucid_frame_record` call, and for a recorded frame
    /// its `translucid_frame_complete` (where `exact` moves to the variants of deeper frames).
    /// A new method or new settings may need some, as may content a loop did not draw
    /// before; a prepared loop (`translucid_context_prepare`) needs none up to the prepared
    /// size, its first frame included where the engine's image formats were prepared for
    /// too, also when assets are created or destroyed (a renderer made for new assets takes
    /// the pipelines of the one it replaces) and when they bring content past the
    /// declaration (drawn with the superset variant).
    pub pipelines_created: u64,
    /// GPU memory those calls allocated, in bytes: the first frames of a renderer, a frame
    /// larger than any before with its method and settings, frames that need larger buffers, the first frame after assets were created (their images, and
    /// the staging their texels are copied from, freed once copied; meshes and materials go
    /// into device-local room left for them, copied from staging only past 64 KiB of data)
    /// or after so many were destroyed that the live ones are uploaded anew; 0 in a warm
    /// frame loop.
    pub bytes_allocated: u64,
    /// Fragments blended unsorted because they found no room (`TRANSLUCID_METHOD_LINKED_LIST`
    /// past its `translucid_linked_list_settings::node_budget`): the image is not exact where
    /// they fell. 0 for an exact frame and for other methods.
    pub tail_fragments: u64,
    /// Pixels with more layers than `TRANSLUCID_METHOD_DEPTH_PEELING`'s passes peel (twice
    /// `translucid_depth_peeling_settings::passes`): their middle layers are missing. 0 for an
    /// exact frame and for other methods.
    pub unpeeled_pixels: u64,
    /// Compute dispatches the frame recorded (its last rendering, for a standalone frame
    /// rendered again): the fixed chain a method's frame costs besides its work. 0 for
    /// methods that only draw.
    pub dispatches: u64,
}

/// One view's share of a frame: the frame's figures of the same names are the sums of its
/// views'.
#[allow(non_camel_case_types)]
#[repr(C)]
#[derive(Clone, Copy, Default)]
pub struct translucid_view_statistics {
    /// GPU time of the view's stages.
    pub gpu_milliseconds: f64,
    /// GPU time of the method's stages alone.
    pub method_milliseconds: f64,
    pub fragments: u64,
    pub tail_fragments: u64,
    pub unpeeled_pixels: u64,
    pub dispatches: u64,
    /// 1 when this view went past a limit of one recording (its part of the image is not
    /// all right); else 0.
    pub overflowed: u32,
}

/// Each view's share of a frame (`translucid_host_frame_views`), chained to
/// `translucid_frame_statistics::next`: what each eye or each player's view cost. The caller
/// sets `s_type` (and `next` to NULL); translucid fills the rest. A frame of one view, and a
/// standalone frame, has one, equal to the frame's figures.
#[allow(non_camel_case_types)]
#[repr(C)]
pub struct translucid_frame_view_statistics {
    /// `TRANSLUCID_STRUCTURE_TYPE_FRAME_VIEW_STATISTICS`, set by the caller.
    pub s_type: u32,
    /// NULL, set by the caller.
    pub next: *mut c_void,
    /// Number of valid entries in `views`: the frame's views.
    pub view_count: u32,
    /// Each view's share, in the order of `translucid_host_frame_views::views`.
    pub views: [translucid_view_statistics; TRANSLUCID_MAX_VIEWS],
}

impl OutStructure for translucid_frame_view_statistics {
    const TYPE: translucid_structure_type = translucid_structure_type::FrameViewStatistics;
    const NAME: &'static str = "translucid_frame_view_statistics";
    unsafe fn header(ptr: *const Self) -> (u32, *mut c_void) {
        // SAFETY: the trait's contract; only the two fields are read.
        unsafe {
            (
                std::ptr::addr_of!((*ptr).s_type).read(),
                std::ptr::addr_of!((*ptr).next).read(),
            )
        }
    }
}

impl OutStructure for translucid_frame_statistics {
    const TYPE: translucid_structure_type = translucid_structure_type::FrameStatistics;
    const NAME: &'static str = "translucid_frame_statistics";
    unsafe fn header(ptr: *const Self) -> (u32, *mut c_void) {
        // SAFETY: the trait's contract; only the two fields are read.
        unsafe {
            (
                std::ptr::addr_of!((*ptr).s_type).read(),
                std::ptr::addr_of!((*ptr).next).read(),
            )
        }
    }
}

/// A rendered frame's handle. `{0}` is the NULL handle.
#[allow(non_camel_case_types)]
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct translucid_frame {
    pub id: u64,
}

/// The frame's pixels, or why there are none here.
fn image_of(record: &FrameRecord) -> FfiResult<&Image> {
    record.image.as_ref().ok_or_else(|| {
        Failure::new(
            translucid_result::ErrorNotSupported,
            "a host-device frame's pixels are in the engine's colour image; translucid \
             keeps no copy to read or write",
        )
    })
}

fn render(objects: &mut Objects, info: &translucid_frame_info) -> FfiResult<u64> {
    if objects.gpu().is_host_device() {
        return Err(Failure::new(
            translucid_result::ErrorNotSupported,
            "translucid_frame_render renders on translucid's own device; a host-device context \
             records with translucid_frame_record",
        ));
    }
    let (request, layer) = frame_request(objects, info, None)?;
    let layer = layer
        .map(|l| opaque_layer_from(l, info.width, info.height))
        .transpose()?;
    Ok(objects.core.render(&request, layer.as_ref())?)
}

fn statistics_of(record: &FrameRecord, header: (u32, *mut c_void)) -> translucid_frame_statistics {
    let empty = translucid_stage_time {
        name: [0; TRANSLUCID_STAGE_NAME_SIZE],
        milliseconds: 0.0,
    };
    let mut stages = [empty; TRANSLUCID_MAX_STAGES];
    for (slot, (name, ms)) in stages.iter_mut().zip(&record.stages) {
        // Names are short ASCII; cut to fit and keep the final NUL.
        for (c, b) in slot
            .name
            .iter_mut()
            .zip(name.bytes().take(TRANSLUCID_STAGE_NAME_SIZE - 1))
        {
            *c = c_char::from_ne_bytes([b]);
        }
        slot.milliseconds = *ms;
    }
    let stage_count = record.stages.len().min(TRANSLUCID_MAX_STAGES);
    translucid_frame_statistics {
        s_type: header.0,
        next: header.1,
        method: translucid_method::of_kind(record.method) as u32,
        width: record.width,
        height: record.height,
        stage_count: u32::try_from(stage_count).unwrap_or(0),
        stages,
        gpu_milliseconds: record.stages.iter().map(|(_, ms)| ms).sum(),
        method_milliseconds: record.method_ms,
        peak_gpu_bytes: record.peak_gpu_bytes,
        fragments: record.fragments,
        overflow_rerenders: record.rerenders,
        overflowed: u32::from(record.overflowed),
        frame_index: record.frame_index,
        pipelines_created: record.built.0,
        bytes_allocated: record.built.1,
        tail_fragments: record.tail_fragments,
        unpeeled_pixels: record.unpeeled_pixels,
        dispatches: record.dispatches,
    }
}

/// An out-structure of view statistics: its caller-set header, and the struct to write.
type OutViews<'a> = (
    (u32, *mut c_void),
    &'a mut std::mem::MaybeUninit<translucid_frame_view_statistics>,
);

/// The view statistics chained to a frame statistics (`next`), if any: the only structure
/// taken there.
fn view_statistics_in<'a>(next: *mut c_void) -> FfiResult<Option<OutViews<'a>>> {
    if next.is_null() {
        return Ok(None);
    }
    let base = try_ref(
        next.cast_const()
            .cast::<crate::cast::translucid_base_in_structure>(),
        "out_statistics.next",
    )?;
    let expected = translucid_structure_type::FrameViewStatistics;
    if base.s_type != expected as u32 {
        let found = translucid_structure_type::from_raw(base.s_type)
            .map_or_else(|| base.s_type.to_string(), |t| t.c_name());
        return Err(Failure::new(
            translucid_result::ErrorInvalidStructureType,
            format!(
                "out_statistics.next holds structure type {found}, which \
                 translucid_frame_statistics does not take; chain a \
                 translucid_frame_view_statistics ({}) or set next to NULL",
                expected.c_name()
            ),
        ));
    }
    try_out_structure(
        next.cast::<translucid_frame_view_statistics>(),
        "out_statistics.next",
    )
    .map(Some)
}

/// Each view's share of `record`.
fn view_statistics_of(
    record: &FrameRecord,
    header: (u32, *mut c_void),
) -> translucid_frame_view_statistics {
    let mut views = [translucid_view_statistics::default(); TRANSLUCID_MAX_VIEWS];
    for (out, share) in views.iter_mut().zip(&record.shares) {
        *out = translucid_view_statistics {
            gpu_milliseconds: share.gpu_ms,
            method_milliseconds: share.method_ms,
            fragments: share.fragments,
            tail_fragments: share.tail_fragments,
            unpeeled_pixels: share.unpeeled_pixels,
            dispatches: share.dispatches,
            overflowed: u32::from(share.overflowed),
        };
    }
    translucid_frame_view_statistics {
        s_type: header.0,
        next: header.1,
        view_count: record.shares.len().min(TRANSLUCID_MAX_VIEWS) as u32,
        views,
    }
}

fn write_pixels(
    image: &Image,
    format: translucid_pixel_format,
    out: &mut [std::mem::MaybeUninit<u8>],
) {
    let bytes: Vec<u8> = match format {
        translucid_pixel_format::Rgba8Srgb => image.to_srgb8(),
        translucid_pixel_format::Rgba32fLinear => image
            .pixels
            .iter()
            .flat_map(|p| p.to_array())
            .flat_map(f32::to_ne_bytes)
            .collect(),
    };
    for (slot, b) in out.iter_mut().zip(bytes) {
        slot.write(b);
    }
}

impl translucid_frame {
    /// Renders a frame and waits for it; writes its handle to `*out_frame`. The frame keeps
    /// its pixels and statistics until `translucid_frame_destroy` (or the context's).
    #[no_mangle]
    #[must_use]
    pub extern "C" fn translucid_frame_render(
        context: *mut translucid_context,
        info: *const translucid_frame_info,
        out_frame: *mut translucid_frame,
    ) -> translucid_result {
        panic::with_context(context, |objects| {
            let info = try_ref(info, "info")?;
            let out = try_out(out_frame, "out_frame")?;
            let id = render(objects, info)?;
            out.write(translucid_frame { id });
            Ok(translucid_result::Success)
        })
    }

    /// Copies the frame's pixels into `pixels`, which holds `size` bytes: at least width x
    /// height x 4 for `TRANSLUCID_PIXEL_FORMAT_RGBA8_SRGB`, x 16 for
    /// `TRANSLUCID_PIXEL_FORMAT_RGBA32F_LINEAR`.
    #[no_mangle]
    #[must_use]
    pub extern "C" fn translucid_frame_read(
        context: *mut translucid_context,
        frame: translucid_frame,
        format: u32,
        pixels: *mut c_void,
        size: usize,
    ) -> translucid_result {
        panic::with_context(context, |objects| {
            let image = image_of(objects.core.frame(frame.id)?)?;
            let format = translucid_pixel_format::from_raw(format)?;
            let needed = image.pixels.len() * format.bytes_per_pixel();
            if size < needed {
                return Err(Failure::size(format!(
                    "the {}x{} frame needs {needed} bytes in {}, the buffer has {size}",
                    image.width,
                    image.height,
                    crate::cast::c_enum_name("TRANSLUCID_PIXEL_FORMAT", &format!("{format:?}"))
                )));
            }
            let out = try_out_slice(pixels.cast::<u8>(), needed, "pixels")?;
            write_pixels(image, format, out);
            Ok(translucid_result::Success)
        })
    }

    /// Writes the frame as an 8-bit sRGB PNG at `path` (UTF-8), creating missing directories.
    #[no_mangle]
    #[must_use]
    pub extern "C" fn translucid_frame_write_png(
        context: *mut translucid_context,
        frame: translucid_frame,
        path: *const c_char,
    ) -> translucid_result {
        panic::with_context(context, |objects| {
            let image = image_of(objects.core.frame(frame.id)?)?;
            let path = try_str(path, "path")?.ok_or_else(|| Failure::null("path"))?;
            if path.is_empty() {
                return Err(Failure::argument("path is empty"));
            }
            image.save_png(path.as_ref())?;
            Ok(translucid_result::Success)
        })
    }

    /// Fills `*out_statistics`, whose `s_type` the caller set to
    /// `TRANSLUCID_STRUCTURE_TYPE_FRAME_STATISTICS`, and the
    /// `translucid_frame_view_statistics` its `next` may point to (else NULL). Nothing is
    /// written when it fails.
    #[no_mangle]
    #[must_use]
    pub extern "C" fn translucid_frame_get_statistics(
        context: *mut translucid_context,
        frame: translucid_frame,
        out_statistics: *mut translucid_frame_statistics,
    ) -> translucid_result {
        panic::with_context(context, |objects| {
            let record = objects.core.frame(frame.id)?;
            if record.abandoned {
                return Err(Failure::argument(
                    "the frame was abandoned (translucid_frame_abandon of it or of an earlier \
                     frame): it has no statistics",
                ));
            }
            if record.in_flight {
                return Err(Failure::new(
                    translucid_result::ErrorFrameInFlight,
                    "the frame is recorded but not completed: call translucid_frame_complete \
                     once the engine's submission finished",
                ));
            }
            let out = try_out(out_statistics, "out_statistics")?;
            // SAFETY: `try_out` checked the pointer; the caller set the header (C contract).
            let header = unsafe { translucid_frame_statistics::header(out.as_ptr()) };
            check_type(
                header.0,
                translucid_frame_statistics::TYPE,
                "out_statistics",
            )?;
            let views = view_statistics_in(header.1)?;
            out.write(statistics_of(record, header));
            if let Some((header, out)) = views {
                out.write(view_statistics_of(record, header));
            }
            Ok(translucid_result::Success)
        })
    }

    /// Frees a frame's pixels; its handle becomes stale. A host-device frame in flight
    /// (recorded, not completed) is not destroyed: that returns
    /// `TRANSLUCID_RESULT_ERROR_FRAME_IN_FLIGHT` and frees nothing, since the GPU may still
    /// be running its commands; complete it or abandon it (`translucid_frame_abandon`).
    #[no_mangle]
    pub extern "C" fn translucid_frame_destroy(
        context: *mut translucid_context,
        frame: translucid_frame,
    ) -> translucid_result {
        panic::with_context(context, |objects| {
            objects.core.destroy_frame(frame.id)?;
            Ok(translucid_result::Success)
        })
    }

    /// Host-device mode: ends a frame in flight without completing it, and destroys it; the
    /// frames recorded after it end too (their handles stay, without statistics: destroy
    /// them). You state that the GPU is not running the commands of any of them and never
    /// will: they were never submitted, or their submissions finished and you do not want
    /// their results. translucid keeps what their recordings built (pipelines, grown
    /// buffers), and the next frame recorded carries the uploads and moved vertices they
    /// carried: it builds and allocates nothing for them. Reset their command buffers
    /// (`vkResetCommandBuffer` or the pool) instead of ending or submitting them: the
    /// objects they name may be destroyed.
    #[no_mangle]
    pub extern "C" fn translucid_frame_abandon(
        context: *mut translucid_context,
        frame: translucid_frame,
    ) -> translucid_result {
        panic::with_context(context, |objects| {
            objects.core.abandon(frame.id)?;
            Ok(translucid_result::Success)
        })
    }
}

#[cfg(test)]
mod tests {
    /// The promise holds on every Vulkan device: its draws' records fit the 128 MB
    /// (2^27 bytes) of one storage binding that Vulkan requires every device to allow. The
    /// header once promised 2^20 draws, which no device under 160 MB of binding holds.
    #[test]
    fn the_most_draws_fit_the_smallest_storage_binding_vulkan_allows() {
        let record = std::mem::size_of::<translucid::shader_types::GpuDrawInfo>() as u64;
        assert!(u64::from(super::TRANSLUCID_MAX_DRAWS) * record <= 1 << 27);
    }
}
