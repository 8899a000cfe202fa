//! Building up front what a frame loop needs, so that no frame compiles a shader: the content
//! the engine declares its frames may draw, and a frame like those it will make, now or on a
//! thread beside the frame loop. Exports `translucid_context_prepare`,
//! `translucid_context_prepare_in_background` and `translucid_context_get_prepare_status`.

use crate::cast::{check_type, translucid_context, try_ref, write_optional};
use crate::context::Objects;
use crate::frame::translucid_frame_info;
use crate::frame_input::frame_request;
use crate::host::image_formats;
use crate::panic;
use crate::result::{translucid_result, Failure, FfiResult};
use crate::structure::translucid_structure_type;
use std::ffi::c_void;
use translucid::context::background::PrepareStatus;
use translucid::context::renderers::FrameRequest;
use translucid::gpu::HostImage;
use translucid::methods::bins::features::DeclaredContent;

/// Textured materials. (Both variants are built: frames without a textured transparent draw
/// run without the texturing code, which costs them most of all the declared content.)
pub const TRANSLUCID_CONTENT_TEXTURES: u32 = 1;
/// Vertex colours or draw tints, one colour per quad (particles, billboards).
pub const TRANSLUCID_CONTENT_VERTEX_COLOURS: u32 = 2;
/// Vertex colours that vary across a quad (covers `TRANSLUCID_CONTENT_VERTEX_COLOURS`).
pub const TRANSLUCID_CONTENT_CORNER_COLOURS: u32 = 4;
/// Lit materials (`TRANSLUCID_MATERIAL_LIT`), on meshes with normals or without.
pub const TRANSLUCID_CONTENT_LIT: u32 = 8;
/// Materials that transmit light (`transmission` above 0).
pub const TRANSLUCID_CONTENT_TRANSMISSION: u32 = 16;
/// Triangles that cross the near plane, pass behind the eye or reach far outside the frame.
pub const TRANSLUCID_CONTENT_NEAR_PLANE: u32 = 32;
/// Pixels many layers deep (more than 8 fragments a pixel on average, or pixels needing more
/// than two passes): `exact`'s variants for them are built up front too, and its frames keep
/// to those (at most 16 depth slabs); so are the pipelines of `wavelet`'s coefficient
/// images, which its frames move to from the bins where a row is too crowded for them.
pub const TRANSLUCID_CONTENT_DEEP: u32 = 64;
/// All of the above.
pub const TRANSLUCID_CONTENT_ALL: u32 = 127;

/// What `translucid_context_prepare` builds for. Zero-initialise it, then set `s_type`.
#[allow(non_camel_case_types)]
#[repr(C)]
pub struct translucid_prepare_info {
    /// `TRANSLUCID_STRUCTURE_TYPE_PREPARE_INFO`.
    pub s_type: u32,
    /// NULL, or in host-device mode a `translucid_host_image_formats`: the engine's images
    /// the loop records into, so that its first frame builds nothing for them either.
    pub next: *const c_void,
    /// A frame like those of the loop: its method, the settings chained to it, its width
    /// and height, the largest the loop records, and a camera like the loop's (its depth
    /// direction, forward or reversed-Z, is read; give one also for a loop of frames of
    /// several views, whose frame infos' cameras are not read). Its draws are only checked
    /// (`draw_count` 0 is fine).
    pub frame: *const translucid_frame_info,
    /// `TRANSLUCID_CONTENT_*` bits: what the loop's frames may draw, streamed-in assets
    /// included. Added to what earlier calls declared.
    pub content: u32,
}

fn declared(content: u32) -> FfiResult<DeclaredContent> {
    if content & !TRANSLUCID_CONTENT_ALL != 0 {
        return Err(Failure::argument(format!(
            "translucid_prepare_info.content has unknown bits {:#x}",
            content & !TRANSLUCID_CONTENT_ALL
        )));
    }
    let has = |bit: u32| content & bit != 0;
    Ok(DeclaredContent {
        textures: has(TRANSLUCID_CONTENT_TEXTURES),
        vertex_colours: has(TRANSLUCID_CONTENT_VERTEX_COLOURS),
        corner_colours: has(TRANSLUCID_CONTENT_CORNER_COLOURS),
        lit: has(TRANSLUCID_CONTENT_LIT),
        transmission: has(TRANSLUCID_CONTENT_TRANSMISSION),
        near_plane: has(TRANSLUCID_CONTENT_NEAR_PLANE),
        deep: has(TRANSLUCID_CONTENT_DEEP),
    })
}

impl translucid_prepare_info {
    /// Declares what the frame loop's frames may draw (`content`, and what `frame` draws)
    /// and builds, now, every pipeline frames like `frame` need: same method and settings,
    /// at most its size, over any assets, streamed-in ones included. Those frames then
    /// report `pipelines_created` 0. Frames draw with the declared shaders whether they need
    /// all of them or not (textures apart: a frame without a textured draw takes the
    /// untextured variant, built too): declare what the loop draws, not more. Frames whose
    /// content is past the declaration draw with a superset variant built now too (every
    /// content kind, both texture variants; right, only slower: exact on untextured
    /// particles 1.6x their own variant's time on lavapipe), and exact's frames deeper than
    /// declared stay at the variants built; each says so once in the log.
    ///
    /// On an engine's device, chain the formats and layouts of the images the loop records
    /// into (`translucid_host_image_formats`, once for each set of formats, layouts and final
    /// layouts the loop hands over; a call that declares nothing more only builds what is
    /// missing): without them, the first frame into each set builds the few pipelines of the
    /// passes made for those images (`blend`'s pass into them, the composite of `exact` and
    /// `wavelet` onto a colour format that blends, the import of depth the other methods
    /// cannot copy).
    ///
    /// Call it at load time, once per method and settings the loop uses, after creating the
    /// assets or before; a later call that declares more makes the next frames build their
    /// renderers anew (declare in the background for the loop to go on meanwhile). Still
    /// built when first needed (documented in the README, "No compile in the frame loop"): a
    /// frame larger than the prepared one, other methods or settings, and on GPUs two
    /// variants the superset does not cover: texture sampling in software once a frame's
    /// textures pass the texture array, and triangle records read as texels once they pass
    /// a storage binding.
    /// `out_pipelines_created` (may be NULL) receives the pipelines this call built.
    #[no_mangle]
    #[must_use]
    pub extern "C" fn translucid_context_prepare(
        context: *mut translucid_context,
        info: *const translucid_prepare_info,
        out_pipelines_created: *mut u64,
    ) -> translucid_result {
        panic::with_context(context, |objects| {
            let (request, content, engine_images) = prepared(objects, info)?;
            let (pipelines, _bytes) = objects.core.prepare(&request, content, engine_images)?;
            write_optional(out_pipelines_created, "out_pipelines_created", pipelines)?;
            Ok(translucid_result::Success)
        })
    }

    /// `translucid_context_prepare` on a thread of translucid's own, for a loop that goes on
    /// meanwhile (streaming in a level while the current one plays): returns once `info` is
    /// checked (and copied) and the work has started. Frames recorded meanwhile draw with what
    /// was declared before (content past that with the superset variant, where the loop was
    /// prepared before; else built when first drawn, as without preparing). The work takes
    /// effect only in the `translucid_context_get_prepare_status` call that finds it finished,
    /// never in another call, so that the engine picks the frame (between engine frames, not
    /// between the views of one): its content is declared, and the next frame of each method makes its renderer anew from the
    /// pipelines built (no shader compiled; its buffers are allocated again, while frames
    /// in flight keep the old ones until they complete). Several may run at once, and
    /// beside `translucid_context_prepare`; none can be cancelled. The work makes a renderer
    /// of its own for the while (a frame's buffers, counted against the context's memory
    /// budget, but not in the statistics of the frames recorded meanwhile); its pipelines
    /// stay with the context and go into `translucid_context_get_pipeline_cache_data`.
    /// `translucid_context_destroy` waits for work still running.
    #[no_mangle]
    #[must_use]
    pub extern "C" fn translucid_context_prepare_in_background(
        context: *mut translucid_context,
        info: *const translucid_prepare_info,
    ) -> translucid_result {
        panic::with_context(context, |objects| {
            let (request, content, engine_images) = prepared(objects, info)?;
            objects
                .core
                .prepare_in_background(&request, content, engine_images)?;
            Ok(translucid_result::Success)
        })
    }
}

/// Whether the work `translucid_context_prepare_in_background` started has finished, and
/// where it has, puts it in effect (this call only: call it between engine frames). Returns:
/// - `TRANSLUCID_RESULT_SUCCESS`: none is running, and all of it is in effect (also when
///   none was started): `out_pipelines_created` (may be NULL) receives the pipelines built
///   by the work put in effect since the last call.
/// - `TRANSLUCID_RESULT_NOT_READY`: some is still running (what has finished is in effect);
///   nothing is written.
/// - An error that some work ended with, reported once (its content is not declared, and
///   frames build what it would have when they first need it); other work goes on.
#[no_mangle]
#[must_use]
pub extern "C" fn translucid_context_get_prepare_status(
    context: *mut translucid_context,
    out_pipelines_created: *mut u64,
) -> translucid_result {
    panic::with_context(context, |objects| match objects.core.prepare_status()? {
        PrepareStatus::Building => Ok(translucid_result::NotReady),
        PrepareStatus::Ready { pipelines } => {
            write_optional(out_pipelines_created, "out_pipelines_created", pipelines)?;
            Ok(translucid_result::Success)
        }
    })
}

/// What a prepare info asks for: frames like its frame request, drawing its content, into
/// engine images like its (colour, depth).
type Prepared = (
    FrameRequest,
    DeclaredContent,
    Option<(HostImage, HostImage)>,
);

/// The frame request, content and engine images `info` describes, checked.
fn prepared(objects: &mut Objects, info: *const translucid_prepare_info) -> FfiResult<Prepared> {
    let info = try_ref(info, "info")?;
    check_type(
        info.s_type,
        translucid_structure_type::PrepareInfo,
        "translucid_prepare_info",
    )?;
    let engine_images = image_formats(info.next)?;
    let content = declared(info.content)?;
    let frame = try_ref(info.frame, "translucid_prepare_info.frame")?;
    let (request, _layer) = frame_request(objects, frame, None)?;
    Ok((request, content, engine_images))
}
