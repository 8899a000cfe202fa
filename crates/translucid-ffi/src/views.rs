//! Where a frame is in the engine's images: the structures chained to the frame targets
//! (`translucid_host_image_layers` and `translucid_host_image_region` for a frame of one
//! view, `translucid_host_frame_views` for a frame of several), turned into the core's
//! views, each checked against the images before anything is recorded; and how many views
//! a context's frames may have (`translucid_host_views_create_info`).

use crate::cast::{translucid_base_in_structure, try_ref, try_slice};
use crate::frame::translucid_camera;
use crate::frame_input::camera_from;
use crate::host::{
    host_device_chain, host_image, translucid_host_device_create_info,
    translucid_host_frame_targets,
};
use crate::result::{translucid_result, Failure, FfiResult};
use crate::structure::translucid_structure_type;
use std::ffi::c_void;
use translucid::context::HostView;
use translucid::gpu::{vk, HostTargets};
use translucid::scene::Camera;

/// The most views a frame has.
pub const TRANSLUCID_MAX_VIEWS: usize = 4;

/// The array layers a frame reads and writes, chained to `translucid_host_frame_targets::next`
/// where its images have several: a view of a layered image recorded as a frame of its own
/// (one eye of stereo into an XR swapchain's two layers), into its layer; the other layers
/// are left as they are. Without it, both images' layer 0. A frame of several views gives
/// each view's layer in its `translucid_host_frame_views` instead.
#[allow(non_camel_case_types)]
#[repr(C)]
pub struct translucid_host_image_layers {
    /// `TRANSLUCID_STRUCTURE_TYPE_HOST_IMAGE_LAYERS`.
    pub s_type: u32,
    /// NULL, or a `translucid_host_image_region`.
    pub next: *const c_void,
    /// The colour image's layer, and how many it has (its `arrayLayers`: translucid cannot
    /// query it, so it checks the layer against this; 0 means 1).
    pub colour_layer: u32,
    pub colour_layer_count: u32,
    /// The same of the depth image.
    pub depth_layer: u32,
    pub depth_layer_count: u32,
}

/// Where in the images a frame is, chained to `translucid_host_frame_targets::next` (before or
/// after a `translucid_host_image_layers`) for a view in a part of them: a split screen, or one
/// half of a side-by-side stereo image. The frame reads and writes its `width` x `height`
/// pixels from (`x`, `y`) in both images (one place for colour and depth), which must hold
/// them (the images' `width` at least `x` plus the frame's, their `height` at least `y`
/// plus the frame's); the other pixels are left as they are. Without it, (0, 0). The frame
/// is the view: its size and camera are the view's (the camera projects onto the region).
/// Views recorded as frames of their own that share an image are recorded one after
/// another, each taking the image in the layout the one before left it in (its `layout`
/// the previous view's `final_layout`); a frame of several views (`translucid_host_frame_views`)
/// does that itself.
#[allow(non_camel_case_types)]
#[repr(C)]
pub struct translucid_host_image_region {
    /// `TRANSLUCID_STRUCTURE_TYPE_HOST_IMAGE_REGION`.
    pub s_type: u32,
    /// NULL, or a `translucid_host_image_layers`.
    pub next: *const c_void,
    pub x: u32,
    pub y: u32,
}

/// One view of a frame of several (`translucid_host_frame_views`): its camera and its place
/// in the engine's images.
#[allow(non_camel_case_types)]
#[repr(C)]
#[derive(Clone, Copy, Debug)]
pub struct translucid_frame_view {
    /// The view's camera (`translucid_frame_info::camera` is not read), as the engine drew
    /// the view's depth: its own view, projection and jitter.
    pub camera: translucid_camera,
    /// The view's top-left corner, in both images: the view is the frame's `width` x
    /// `height` pixels from there (as a `translucid_host_image_region`), and the images
    /// must hold it.
    pub x: u32,
    pub y: u32,
    /// The view's array layer of the colour image and of the depth image, below the
    /// counts the `translucid_host_frame_views` gives.
    pub colour_layer: u32,
    pub depth_layer: u32,
}

/// A frame of several views (stereo, a split screen), chained to
/// `translucid_host_frame_targets::next` instead of a `translucid_host_image_layers` or
/// `translucid_host_image_region`: `translucid_frame_record` records the frame once for
/// each view, with the view's camera, into the view's layer and region of the targets'
/// images. The views share the frame's method, size, settings, light and draws, and its
/// uploads (assets, textures and moved vertices go up once); each view has a slot of
/// per-frame data of its own, and they run one after another. The frame is one frame in
/// flight and completes once, with its views' times and counts added up in its
/// statistics. Views in one layer of an image may not overlap; a later view takes an
/// image layer an earlier one wrote in its `final_layout`, so images start in their
/// `layout` and end in their `final_layout` as with one view.
#[allow(non_camel_case_types)]
#[repr(C)]
pub struct translucid_host_frame_views {
    /// `TRANSLUCID_STRUCTURE_TYPE_HOST_FRAME_VIEWS`.
    pub s_type: u32,
    /// NULL.
    pub next: *const c_void,
    /// The colour image's and the depth image's array layers (their `arrayLayers`: the
    /// views' layers are checked against them; 0 means 1).
    pub colour_layer_count: u32,
    pub depth_layer_count: u32,
    /// 1 to the context's `translucid_host_views_create_info::views_per_frame`.
    pub view_count: u32,
    /// `view_count` views.
    pub views: *const translucid_frame_view,
}

/// How many views the frames of a host-device context have at most, chained to
/// `translucid_host_device_create_info::next` (with or without a
/// `translucid_host_subgroup_size_control`, in either order). Without it, frames have one
/// view. Views count apart from frames in flight: each view of a frame in flight takes a
/// slot of per-frame data, and `translucid_context_create_info::frames_in_flight` times
/// `views_per_frame` may be at most `TRANSLUCID_MAX_FRAMES_IN_FLIGHT` (3 frames of stereo:
/// 3 and 2).
#[allow(non_camel_case_types)]
#[repr(C)]
pub struct translucid_host_views_create_info {
    /// `TRANSLUCID_STRUCTURE_TYPE_HOST_VIEWS_CREATE_INFO`.
    pub s_type: u32,
    /// NULL, or a `translucid_host_subgroup_size_control`.
    pub next: *const c_void,
    /// The most views a frame has (`translucid_host_frame_views`), 1 to
    /// `TRANSLUCID_MAX_VIEWS`; 0 means 1.
    pub views_per_frame: u32,
}

/// The most views a frame of a context made with `host` has, checked with the context's
/// `frames_in_flight`: each view of a frame in flight takes a slot of per-frame data.
pub(crate) fn views_per_frame(
    host: &translucid_host_device_create_info,
    frames_in_flight: u32,
) -> FfiResult<u32> {
    let given = host_device_chain(host.next)?.views_per_frame;
    let views = given.max(1);
    let slots = crate::context::TRANSLUCID_MAX_FRAMES_IN_FLIGHT;
    if views as usize > TRANSLUCID_MAX_VIEWS || views * frames_in_flight > slots {
        return Err(Failure::argument(format!(
            "translucid_host_views_create_info.views_per_frame is {given}; it must be 0 to \
             TRANSLUCID_MAX_VIEWS ({TRANSLUCID_MAX_VIEWS}), and times frames_in_flight \
             ({frames_in_flight}) at most TRANSLUCID_MAX_FRAMES_IN_FLIGHT ({slots})"
        )));
    }
    Ok(views)
}

/// A view's camera and place, before it is checked against the images.
struct ViewPlace {
    camera: Option<Camera>,
    /// (colour, depth) layers.
    layers: (u32, u32),
    corner: (u32, u32),
}

/// What the chain of the frame targets says: one view's place, or several views.
pub(crate) struct FrameViews(Vec<ViewPlace>);

impl FrameViews {
    /// Reads the chain at `next` of the frame targets: at most one
    /// `translucid_host_image_layers` and one `translucid_host_image_region`, in either
    /// order, or one `translucid_host_frame_views` alone.
    pub(crate) fn from_chain(next: *const c_void) -> FfiResult<Self> {
        let mut place = ViewPlace {
            camera: None,
            layers: (0, 0),
            corner: (0, 0),
        };
        let (mut layers_seen, mut region_seen) = (false, false);
        let mut link = next;
        while !link.is_null() {
            let what = "a structure chained to translucid_host_frame_targets";
            let base = try_ref(link.cast::<translucid_base_in_structure>(), what)?;
            let kind = translucid_structure_type::from_raw(base.s_type);
            match kind {
                Some(translucid_structure_type::HostImageLayers) if !layers_seen => {
                    layers_seen = true;
                    // A structure of the type its s_type names (C contract).
                    let layers = try_ref(link.cast::<translucid_host_image_layers>(), what)?;
                    place.layers = image_layers(layers)?;
                    link = layers.next;
                }
                Some(translucid_structure_type::HostImageRegion) if !region_seen => {
                    region_seen = true;
                    // A structure of the type its s_type names (C contract).
                    let region = try_ref(link.cast::<translucid_host_image_region>(), what)?;
                    place.corner = (region.x, region.y);
                    link = region.next;
                }
                Some(translucid_structure_type::HostFrameViews)
                    if link == next && !layers_seen && !region_seen =>
                {
                    // A structure of the type its s_type names (C contract).
                    let views = try_ref(link.cast::<translucid_host_frame_views>(), what)?;
                    return Self::several(views);
                }
                _ => {
                    let name = kind.map_or_else(|| base.s_type.to_string(), |k| k.c_name());
                    return Err(Failure::new(
                        translucid_result::ErrorInvalidStructureType,
                        format!(
                            "translucid_host_frame_targets.next: structure type {name} is not \
                             taken there, or is chained twice or with another; chain at most \
                             one translucid_host_image_layers and one \
                             translucid_host_image_region, or one translucid_host_frame_views \
                             alone"
                        ),
                    ));
                }
            }
        }
        Ok(Self(vec![place]))
    }

    fn several(views: &translucid_host_frame_views) -> FfiResult<Self> {
        if !views.next.is_null() {
            return Err(Failure::new(
                translucid_result::ErrorInvalidStructureType,
                "translucid_host_frame_views.next must be NULL",
            ));
        }
        if views.view_count == 0 || views.view_count as usize > TRANSLUCID_MAX_VIEWS {
            return Err(Failure::argument(format!(
                "translucid_host_frame_views.view_count is {}; a frame has 1 to \
                 TRANSLUCID_MAX_VIEWS ({TRANSLUCID_MAX_VIEWS}) views",
                views.view_count
            )));
        }
        let count = views.view_count as usize;
        let list = try_slice(views.views, count, "translucid_host_frame_views.views")?;
        let places = list
            .iter()
            .enumerate()
            .map(|(i, view)| {
                let in_view = |f: Failure| {
                    Failure::new(
                        f.code,
                        format!("translucid_host_frame_views.views[{i}]: {}", f.message),
                    )
                };
                let layers = [
                    ("colour", view.colour_layer, views.colour_layer_count),
                    ("depth", view.depth_layer, views.depth_layer_count),
                ];
                for (what, layer, count) in layers {
                    if layer >= count.max(1) {
                        return Err(in_view(Failure::argument(format!(
                            "{what}_layer is {layer}; it must be below \
                             translucid_host_frame_views.{what}_layer_count, the {what} \
                             image's array layers ({count}{})",
                            if count == 0 { ", taken as 1" } else { "" }
                        ))));
                    }
                }
                Ok(ViewPlace {
                    camera: Some(camera_from(&view.camera).map_err(in_view)?),
                    layers: (view.colour_layer, view.depth_layer),
                    corner: (view.x, view.y),
                })
            })
            .collect::<FfiResult<Vec<_>>>()?;
        Ok(Self(places))
    }

    /// How many views.
    pub(crate) fn count(&self) -> usize {
        self.0.len()
    }

    /// The camera of the first view, where the views give theirs (the frame info's is then
    /// not read).
    pub(crate) fn camera(&self) -> Option<Camera> {
        self.0[0].camera
    }

    /// The views of a frame of `size` (width, height) seen by `camera` (the frame info's,
    /// for a view that does not give its own) into `targets`, each checked: within both
    /// images, and not overlapping another in the same layer. A view into a layer an earlier
    /// one wrote takes it in that one's final layout.
    pub(crate) fn host_views(
        &self,
        targets: &translucid_host_frame_targets,
        size: (u32, u32),
        camera: Camera,
    ) -> FfiResult<Vec<HostView>> {
        let mut views: Vec<HostView> = Vec::with_capacity(self.0.len());
        for (i, place) in self.0.iter().enumerate() {
            let origin = region_origin(targets, size, place.corner)?;
            let mut colour = host_image(&targets.colour, place.layers.0, origin);
            let mut depth = host_image(&targets.depth, place.layers.1, origin);
            for (j, earlier) in views.iter().enumerate() {
                let e = &earlier.targets;
                if e.colour.layer == colour.layer && overlap(e.colour.origin, origin, size) {
                    return Err(Failure::argument(format!(
                        "translucid_host_frame_views.views[{i}] overlaps views[{j}] in the \
                         colour image's layer {}: each view has pixels of its own",
                        colour.layer
                    )));
                }
                if e.colour.layer == colour.layer {
                    colour.layout = colour.final_layout;
                }
                if e.depth.layer == depth.layer {
                    depth.layout = depth.final_layout;
                }
            }
            views.push(HostView {
                camera: place.camera.unwrap_or(camera),
                targets: HostTargets {
                    cmd: targets.command_buffer,
                    colour,
                    depth,
                },
            });
        }
        Ok(views)
    }
}

/// Whether frames of `size` at corners `a` and `b` share a pixel.
fn overlap(a: vk::Offset2D, b: vk::Offset2D, size: (u32, u32)) -> bool {
    let (w, h) = (i64::from(size.0), i64::from(size.1));
    let (ax, ay, bx, by) = (
        i64::from(a.x),
        i64::from(a.y),
        i64::from(b.x),
        i64::from(b.y),
    );
    ax < bx + w && bx < ax + w && ay < by + h && by < ay + h
}

/// The corner of a frame of `size` at `corner` in the targets' images, which must hold it.
fn region_origin(
    targets: &translucid_host_frame_targets,
    size: (u32, u32),
    (x, y): (u32, u32),
) -> FfiResult<vk::Offset2D> {
    let (right, bottom) = (
        u64::from(x) + u64::from(size.0),
        u64::from(y) + u64::from(size.1),
    );
    for (what, image) in [("colour", &targets.colour), ("depth", &targets.depth)] {
        if u64::from(image.width) < right || u64::from(image.height) < bottom {
            return Err(Failure::size(format!(
                "translucid_host_frame_targets.{what} is {}x{} (width, height), but the frame \
                 is {}x{} from ({x}, {y}): the images must hold it",
                image.width, image.height, size.0, size.1
            )));
        }
    }
    // Within an image, which no device makes past i32::MAX pixels across.
    Ok(vk::Offset2D {
        x: i32::try_from(x).map_err(|_| Failure::size("the frame's corner x"))?,
        y: i32::try_from(y).map_err(|_| Failure::size("the frame's corner y"))?,
    })
}

/// The (colour, depth) layers `layers` names, checked against the counts it gives.
fn image_layers(layers: &translucid_host_image_layers) -> FfiResult<(u32, u32)> {
    for (what, layer, count) in [
        ("colour", layers.colour_layer, layers.colour_layer_count),
        ("depth", layers.depth_layer, layers.depth_layer_count),
    ] {
        if layer >= count.max(1) {
            return Err(Failure::argument(format!(
                "translucid_host_image_layers: the {what} image's layer {layer}, but it has \
                 {} (its {what}_layer_count)",
                count.max(1)
            )));
        }
    }
    Ok((layers.colour_layer, layers.depth_layer))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn at(x: i32, y: i32) -> vk::Offset2D {
        vk::Offset2D { x, y }
    }

    #[test]
    fn views_side_by_side_do_not_overlap_and_a_shared_pixel_does() {
        let size = (48, 36);
        assert!(!overlap(at(0, 0), at(48, 0), size));
        assert!(!overlap(at(0, 0), at(0, 36), size));
        assert!(overlap(at(0, 0), at(47, 35), size));
        assert!(overlap(at(10, 5), at(0, 0), size));
    }
}
