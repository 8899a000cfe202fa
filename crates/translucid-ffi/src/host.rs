//! Host-device mode: the requirements query, the engine's device description, and frames
//! recorded into the engine's command buffer. Exports `translucid_host_get_requirements`,
//! `translucid_frame_record` and `translucid_frame_complete`.
//!
//! The frame rule (kept by the core's `translucid::context::Context`): up to the context's
//! `frames_in_flight` frames are recorded and not yet completed, kept oldest first.
//! Completing a frame completes the older ones first, since one queue runs them in order;
//! abandoning one ends it and every newer one. Until a frame's flight ends, the renderer that
//! recorded it stays alive, even when the assets it drew were destroyed meanwhile.

use crate::cast::{
    check_header, check_type, translucid_base_in_structure, translucid_context, try_out,
    try_out_structure, try_ref, try_slice, OutStructure,
};
use crate::context::Objects;
use crate::frame::{translucid_frame, translucid_frame_info};
use crate::frame_input::frame_request;
use crate::method::translucid_method;
use crate::panic;
use crate::result::{translucid_result, Failure, FfiResult};
use crate::structure::translucid_structure_type;
use crate::views::{translucid_host_views_create_info, FrameViews};
use crate::vulkan::{
    PFN_vkGetInstanceProcAddr, VkBool32, VkCommandBuffer, VkDevice, VkFormat, VkImage,
    VkImageLayout, VkInstance, VkPhysicalDevice, VkPhysicalDeviceFeatures, VkQueueFlags,
    VkShaderStageFlags, VkSubgroupFeatureFlags,
};
use std::ffi::{c_char, c_void, CStr, CString};
use translucid::context::{Completion, Recording};
use translucid::gpu::{
    host_requirements, host_requirements_with, AllocationCallbacks, Gpu, HostDevice, HostImage,
    HostRequirements, Profile,
};

/// What the engine must give its instance and device before translucid can use them. The
/// caller sets `s_type` and `next`; translucid fills the rest, and the structures chained.
#[allow(non_camel_case_types)]
#[repr(C)]
pub struct translucid_host_requirements {
    /// `TRANSLUCID_STRUCTURE_TYPE_HOST_REQUIREMENTS`, set by the caller.
    pub s_type: u32,
    /// Set by the caller: NULL, or a `translucid_host_subgroup_requirements` for translucid
    /// to fill too.
    pub next: *mut c_void,
    /// The lowest `VkApplicationInfo::apiVersion` for the instance, and the lowest version of
    /// the physical device (`VK_API_VERSION_1_2`).
    pub api_version: u32,
    /// What the queue family the engine submits translucid's work on must support (graphics
    /// and compute, and timestamps: `timestampValidBits` > 0).
    pub queue_flags: VkQueueFlags,
    /// The device features to enable: each one translucid needs is `VK_TRUE` (OR them into
    /// the engine's own).
    pub features: VkPhysicalDeviceFeatures,
    /// Number of device extensions to enable (0 in this version).
    pub extension_count: u32,
    /// `extension_count` static extension names; NULL when there are none.
    pub extensions: *const *const c_char,
}

/// What `TRANSLUCID_METHOD_EXACT` and `TRANSLUCID_METHOD_WAVELET` need of the device's
/// subgroups (`VkPhysicalDeviceSubgroupProperties`): properties to choose a physical device
/// by, not features to enable. Chained by the caller to `translucid_host_requirements::next`,
/// with `s_type` and `next` set; translucid fills the rest. A frame of either method on a
/// device without them fails with `TRANSLUCID_RESULT_ERROR_NO_DEVICE`, naming them.
///
/// Recommended besides, on devices that have them: `subgroupSizeControl` and
/// `computeFullSubgroups` enabled (`VkPhysicalDeviceVulkan13Features`, or
/// `VkPhysicalDeviceSubgroupSizeControlFeaturesEXT` with `VK_EXT_subgroup_size_control`),
/// and a `translucid_host_subgroup_size_control` saying so. Both methods then rasterize a
/// tile of one subgroup's pixels at a time (8x4 at 32 lanes, 8x8 at 64) instead of a row of
/// 8 pixels, which leaves most lanes of a wide subgroup idle.
#[allow(non_camel_case_types)]
#[repr(C)]
pub struct translucid_host_subgroup_requirements {
    /// `TRANSLUCID_STRUCTURE_TYPE_HOST_SUBGROUP_REQUIREMENTS`, set by the caller.
    pub s_type: u32,
    /// NULL, set by the caller.
    pub next: *mut c_void,
    /// The stages that must be in `supportedStages` (`VK_SHADER_STAGE_COMPUTE_BIT`).
    pub stages: VkShaderStageFlags,
    /// The operations that must be in `supportedOperations` (basic, vote, arithmetic and
    /// ballot).
    pub operations: VkSubgroupFeatureFlags,
    /// The least `subgroupSize` (8).
    pub min_size: u32,
}

/// Says that the engine enabled `subgroupSizeControl` and `computeFullSubgroups` on its
/// device (Vulkan 1.3's features, or `VK_EXT_subgroup_size_control`'s with the extension in
/// `translucid_host_device_create_info::enabled_extensions`), chained to
/// `translucid_host_device_create_info::next`. translucid cannot read enabled features past
/// `VkPhysicalDeviceFeatures`, so without it the exact and wavelet rasters work a row of 8
/// pixels at a time. `enabled` without Vulkan 1.3 or the extension is
/// `TRANSLUCID_RESULT_ERROR_DEVICE_REQUIREMENTS`; on a device whose compute shaders cannot
/// require its subgroup size, the rasters keep rows (and log a warning).
#[allow(non_camel_case_types)]
#[repr(C)]
pub struct translucid_host_subgroup_size_control {
    /// `TRANSLUCID_STRUCTURE_TYPE_HOST_SUBGROUP_SIZE_CONTROL`.
    pub s_type: u32,
    /// NULL, or a `translucid_host_views_create_info`.
    pub next: *const c_void,
    /// `VK_TRUE`: both features are enabled.
    pub enabled: VkBool32,
}

/// The engine's device, chained to `translucid_context_create_info::next` with `mode`
/// `TRANSLUCID_CONTEXT_MODE_HOST_DEVICE`. translucid never destroys these objects: destroy the
/// context before them. The enabled features and extensions are checked against
/// `translucid_host_get_requirements` (`TRANSLUCID_RESULT_ERROR_DEVICE_REQUIREMENTS` names
/// what is missing); a `VK_NULL_HANDLE` instance, physical device or device is
/// `TRANSLUCID_RESULT_ERROR_INVALID_ARGUMENT`.
#[allow(non_camel_case_types)]
#[repr(C)]
pub struct translucid_host_device_create_info {
    /// `TRANSLUCID_STRUCTURE_TYPE_HOST_DEVICE_CREATE_INFO`.
    pub s_type: u32,
    /// NULL, or a `translucid_host_subgroup_size_control` and a
    /// `translucid_host_views_create_info`, each at most once, in either order.
    pub next: *const c_void,
    /// The `apiVersion` the instance was created with.
    pub api_version: u32,
    pub instance: VkInstance,
    pub physical_device: VkPhysicalDevice,
    pub device: VkDevice,
    /// The family of the queue(s) the engine submits translucid's command buffers to.
    pub queue_family_index: u32,
    /// The loader's `vkGetInstanceProcAddr`; translucid loads every Vulkan function through it.
    pub get_instance_proc_addr: PFN_vkGetInstanceProcAddr,
    /// The features the device was created with (`pEnabledFeatures`, or
    /// `VkPhysicalDeviceFeatures2::features`).
    pub enabled_features: *const VkPhysicalDeviceFeatures,
    pub enabled_extension_count: u32,
    /// `enabled_extension_count` extension names the device was created with.
    pub enabled_extensions: *const *const c_char,
}

/// One of the engine's images: a single-sample 2D image at least the frame's size (width x
/// height) with one mip level (and array layers as a `translucid_host_image_layers` or a
/// `translucid_host_frame_views` says; layer 0 without them), owned by the queue family named at
/// context creation (or created with concurrent sharing). A larger image holds the frame in
/// its top-left corner (a dynamic resolution drawing into images made for the largest
/// size), or where a `translucid_host_image_region` says; translucid reads and writes only
/// the frame's pixels. translucid cannot query an image's
/// size, so it checks the `width` and `height` given against the frame's; an image smaller
/// than it says is undefined behaviour, as in Vulkan.
#[allow(non_camel_case_types)]
#[repr(C)]
#[derive(Clone, Copy, Debug)]
pub struct translucid_host_image {
    pub image: VkImage,
    pub format: VkFormat,
    /// The layout the image is in when the recorded commands run (not UNDEFINED: its contents
    /// are the opaque layer): GENERAL, an attachment, read-only, shader-read or transfer
    /// layout, or synchronization2's ATTACHMENT_OPTIMAL and READ_ONLY_OPTIMAL when the device
    /// has that feature enabled (PRESENT_SRC_KHR for colour too).
    pub layout: VkImageLayout,
    /// The layout the recorded commands leave the image in.
    pub final_layout: VkImageLayout,
    /// The image's width and height, at least the frame's (translucid cannot query an
    /// image's size, so it checks these).
    pub width: u32,
    pub height: u32,
}

/// Where a host-device frame is recorded. A `VK_NULL_HANDLE` command buffer or image, an
/// UNDEFINED or unsuitable layout, or an unsupported format is
/// `TRANSLUCID_RESULT_ERROR_INVALID_ARGUMENT`, reported before anything is recorded.
#[allow(non_camel_case_types)]
#[repr(C)]
pub struct translucid_host_frame_targets {
    /// `TRANSLUCID_STRUCTURE_TYPE_HOST_FRAME_TARGETS`.
    pub s_type: u32,
    /// NULL, or a `translucid_host_image_layers` for images of several array layers and
    /// a `translucid_host_image_region` for a frame in a part of the images, in either order.
    pub next: *const c_void,
    /// A primary command buffer of the engine's device, recording, outside any render pass,
    /// to be submitted on the queue family named at context creation.
    pub command_buffer: VkCommandBuffer,
    /// The opaque colour, onto which the transparent layer is composited. Needs
    /// COLOR_ATTACHMENT, TRANSFER_SRC and TRANSFER_DST usage and a format that can be blitted
    /// both ways (UNORM, SRGB or float; not integer). Where its format blends,
    /// `TRANSLUCID_METHOD_BLEND` and the yardstick (`translucid_frame_record_native_blend`)
    /// draw straight into it, and `TRANSLUCID_METHOD_EXACT` and `TRANSLUCID_METHOD_WAVELET`
    /// blend their result onto it where the transparent layer covers (no copy; its alpha is
    /// kept); the other methods, and every method over a format that does not blend, copy it
    /// in and the result back (alpha overwritten).
    pub colour: translucid_host_image,
    /// The opaque depth, read only (the stencil of a format that has one is ignored), as the
    /// frame's camera projects it (forward or reversed-Z), in `VK_FORMAT_D32_SFLOAT`,
    /// `VK_FORMAT_D16_UNORM`, `VK_FORMAT_X8_D24_UNORM_PACK32`, `VK_FORMAT_D24_UNORM_S8_UINT`
    /// or `VK_FORMAT_D32_SFLOAT_S8_UINT`. Needs SAMPLED usage: `TRANSLUCID_METHOD_EXACT` and
    /// `TRANSLUCID_METHOD_WAVELET` sample it where it is, and the other methods sample it
    /// into a depth of their own, but copy `VK_FORMAT_D32_SFLOAT` depth that grows away from
    /// the eye, which then needs TRANSFER_SRC usage. A format with stencil must be in a
    /// layout of both aspects (not DEPTH_ATTACHMENT_OPTIMAL or DEPTH_READ_ONLY_OPTIMAL).
    /// `TRANSLUCID_METHOD_BLEND` and the yardstick test against it as a depth attachment:
    /// DEPTH_STENCIL_ATTACHMENT usage too.
    pub depth: translucid_host_image,
}

/// The formats and layouts of the engine's images that a frame loop records into, chained to
/// `translucid_prepare_info::next` in host-device mode, as the loop's
/// `translucid_host_frame_targets` will give them (`translucid_host_image`'s `format`,
/// `layout` and `final_layout`; checked as those are): `translucid_context_prepare` then
/// also builds what the first frame into such images would build, so that it builds
/// nothing. For a loop that records with several such sets (an XR swapchain and a mirror
/// window), prepare once for each; the views of a frame of several take one (a view after
/// another in the same layer differs only in its layouts, which need nothing built). A
/// standalone context takes none (`TRANSLUCID_RESULT_ERROR_INVALID_ARGUMENT`).
#[allow(non_camel_case_types)]
#[repr(C)]
pub struct translucid_host_image_formats {
    /// `TRANSLUCID_STRUCTURE_TYPE_HOST_IMAGE_FORMATS`.
    pub s_type: u32,
    /// NULL.
    pub next: *const c_void,
    pub colour_format: VkFormat,
    pub colour_layout: VkImageLayout,
    pub colour_final_layout: VkImageLayout,
    pub depth_format: VkFormat,
    pub depth_layout: VkImageLayout,
    pub depth_final_layout: VkImageLayout,
}

/// The (colour, depth) images, without handles, that the `translucid_host_image_formats`
/// chained at `next` (of the prepare info) describes; `None` when `next` is NULL.
pub(crate) fn image_formats(next: *const c_void) -> FfiResult<Option<(HostImage, HostImage)>> {
    if next.is_null() {
        return Ok(None);
    }
    let what = "translucid_prepare_info.next";
    let link = try_ref(next.cast::<translucid_base_in_structure>(), what)?;
    check_type(
        link.s_type,
        translucid_structure_type::HostImageFormats,
        what,
    )?;
    // A structure of the type its s_type names (C contract).
    let formats = try_ref(next.cast::<translucid_host_image_formats>(), what)?;
    check_header(
        formats.s_type,
        formats.next,
        translucid_structure_type::HostImageFormats,
        "translucid_host_image_formats",
    )?;
    // An image of the frame targets in all that is prepared for: no handle, no size.
    let image = |format, layout, final_layout| {
        let described = translucid_host_image {
            image: VkImage::null(),
            format,
            layout,
            final_layout,
            width: 0,
            height: 0,
        };
        host_image(&described, 0, translucid::gpu::vk::Offset2D::default())
    };
    Ok(Some((
        image(
            formats.colour_format,
            formats.colour_layout,
            formats.colour_final_layout,
        ),
        image(
            formats.depth_format,
            formats.depth_layout,
            formats.depth_final_layout,
        ),
    )))
}

/// The engine's device description as the core takes it.
pub(crate) fn host_device(info: &translucid_host_device_create_info) -> FfiResult<HostDevice> {
    let get_instance_proc_addr = info
        .get_instance_proc_addr
        .ok_or_else(|| Failure::null("host device get_instance_proc_addr"))?;
    let features = *try_ref(info.enabled_features, "host device enabled_features")?;
    let count = usize::try_from(info.enabled_extension_count)
        .map_err(|_| Failure::size("too many enabled extensions"))?;
    let names = try_slice(info.enabled_extensions, count, "enabled_extensions")?;
    let extensions = names
        .iter()
        .enumerate()
        .map(|(i, &name)| {
            if name.is_null() {
                return Err(Failure::null(&format!("enabled_extensions[{i}]")));
            }
            // SAFETY: non-NULL; a NUL-terminated string live for the call (C contract).
            Ok(CString::from(unsafe { CStr::from_ptr(name) }))
        })
        .collect::<FfiResult<Vec<_>>>()?;
    Ok(HostDevice {
        memory_budget: None,
        allocation_callbacks: None,
        subgroup_size_control: host_device_chain(info.next)?.subgroup_size_control,
        get_instance_proc_addr,
        instance: info.instance,
        physical_device: info.physical_device,
        device: info.device,
        queue_family: info.queue_family_index,
        api_version: info.api_version,
        features,
        extensions,
        profile: None,
        software_sampling: false,
    })
}

/// What the structures chained to `translucid_host_device_create_info::next` say.
#[derive(Default)]
pub(crate) struct HostDeviceChain {
    /// A `translucid_host_subgroup_size_control` says both features are enabled.
    pub subgroup_size_control: bool,
    /// `translucid_host_views_create_info::views_per_frame`, as given (0 without it).
    pub views_per_frame: u32,
}

/// The chain at `next` of the engine's device description, checked: at most one
/// `translucid_host_subgroup_size_control` and one `translucid_host_views_create_info`, in
/// either order.
pub(crate) fn host_device_chain(next: *const c_void) -> FfiResult<HostDeviceChain> {
    let mut chain = HostDeviceChain::default();
    let (mut control_seen, mut views_seen) = (false, false);
    let mut link = next;
    while !link.is_null() {
        let what = "a structure chained to translucid_host_device_create_info";
        let base = try_ref(link.cast::<translucid_base_in_structure>(), what)?;
        let kind = translucid_structure_type::from_raw(base.s_type);
        match kind {
            Some(translucid_structure_type::HostSubgroupSizeControl) if !control_seen => {
                control_seen = true;
                // A structure of the type its s_type names (C contract).
                let control = try_ref(link.cast::<translucid_host_subgroup_size_control>(), what)?;
                chain.subgroup_size_control = control.enabled != 0;
                link = control.next;
            }
            Some(translucid_structure_type::HostViewsCreateInfo) if !views_seen => {
                views_seen = true;
                // A structure of the type its s_type names (C contract).
                let views = try_ref(link.cast::<translucid_host_views_create_info>(), what)?;
                chain.views_per_frame = views.views_per_frame;
                link = views.next;
            }
            _ => {
                let name = kind.map_or_else(|| base.s_type.to_string(), |k| k.c_name());
                return Err(Failure::new(
                    translucid_result::ErrorInvalidStructureType,
                    format!(
                        "translucid_host_device_create_info.next: structure type {name} is not \
                         taken there, or is chained twice; chain at most one \
                         translucid_host_subgroup_size_control and one \
                         translucid_host_views_create_info"
                    ),
                ));
            }
        }
    }
    Ok(chain)
}

/// Wraps the engine's device described by `info`, with the variants of `profile` (`None`:
/// `TRANSLUCID_PROFILE`, else the device's), keeping the software sampler if
/// `software_sampling`.
pub(crate) fn host_gpu(
    info: &translucid_host_device_create_info,
    profile: Option<Profile>,
    software_sampling: bool,
    (memory_budget, allocation_callbacks): (Option<u64>, Option<AllocationCallbacks>),
) -> FfiResult<Gpu> {
    check_type(
        info.s_type,
        translucid_structure_type::HostDeviceCreateInfo,
        "translucid_host_device_create_info",
    )?;
    let host = HostDevice {
        profile,
        software_sampling,
        memory_budget,
        allocation_callbacks,
        ..host_device(info)?
    };
    // SAFETY: the header documents that the handles are live objects of one instance made
    // through this vkGetInstanceProcAddr, outliving the context (destroyed before them).
    Ok(unsafe { Gpu::from_host(&host) }?)
}

pub(crate) fn host_image(
    image: &translucid_host_image,
    layer: u32,
    origin: translucid::gpu::vk::Offset2D,
) -> HostImage {
    HostImage {
        image: image.image,
        format: image.format,
        layout: image.layout,
        final_layout: image.final_layout,
        layer,
        origin,
    }
}

fn not_host(call: &str) -> Failure {
    Failure::new(
        translucid_result::ErrorNotSupported,
        format!(
            "{call} needs a host-device context (TRANSLUCID_CONTEXT_MODE_HOST_DEVICE); a \
             standalone context renders with translucid_frame_render"
        ),
    )
}

/// Records the frame `info` describes into the engine's command buffer of `targets`; the
/// frame's handle.
fn record(
    objects: &mut Objects,
    info: &translucid_frame_info,
    targets: &translucid_host_frame_targets,
    recording: Recording,
) -> FfiResult<u64> {
    check_type(
        targets.s_type,
        translucid_structure_type::HostFrameTargets,
        "translucid_host_frame_targets",
    )?;
    let views = FrameViews::from_chain(targets.next)?;
    if !objects.gpu().is_host_device() {
        return Err(not_host("translucid_frame_record"));
    }
    objects.core.flight_room()?;
    objects.core.check_view_count(views.count())?;
    let (mut request, _) = frame_request(objects, info, views.camera())?;
    let size = (info.width, info.height);
    let views = views.host_views(targets, size, request.camera)?;
    if !info.opaque_layer.is_null() {
        return Err(Failure::argument(
            "translucid_frame_info.opaque_layer must be NULL in host-device mode: the opaque \
             layer is the colour and depth images of the translucid_host_frame_targets",
        ));
    }
    // SAFETY: the header documents the engine's side: a recording command buffer outside a
    // render pass and images of at least the frame's size with the usages listed (for the
    // yardstick, attachment usages too), all of the device this context wraps. Handles,
    // formats, layouts and each view's place are checked first.
    Ok(unsafe { objects.core.record(&mut request, &views, recording) }?)
}

fn complete(objects: &mut Objects, frame: translucid_frame) -> FfiResult<translucid_result> {
    if !objects.gpu().is_host_device() {
        return Err(not_host("translucid_frame_complete"));
    }
    Ok(match objects.core.complete(frame.id)? {
        Completion::NotReady => translucid_result::NotReady,
        Completion::Complete => translucid_result::Success,
        Completion::Degraded => translucid_result::FrameDegraded,
    })
}

impl OutStructure for translucid_host_requirements {
    const TYPE: translucid_structure_type = translucid_structure_type::HostRequirements;
    const NAME: &'static str = "translucid_host_requirements";
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

impl translucid_host_requirements {
    /// Fills `*out_requirements` (whose `s_type` the caller set to
    /// `TRANSLUCID_STRUCTURE_TYPE_HOST_REQUIREMENTS`), and a
    /// `translucid_host_subgroup_requirements` chained to it, with what the engine's instance
    /// and device must have: call it before creating them. Needs no context.
    #[no_mangle]
    #[must_use]
    pub extern "C" fn translucid_host_get_requirements(
        out_requirements: *mut translucid_host_requirements,
    ) -> translucid_result {
        panic::without_context(|| write_requirements(out_requirements, host_requirements()))
    }

    /// Like `translucid_host_get_requirements`, for an engine that will use `method` (a
    /// `translucid_method`): the features every method needs and those `method` needs
    /// besides (`TRANSLUCID_METHOD_LINKED_LIST`: `fragmentStoresAndAtomics` and
    /// `geometryShader`; `TRANSLUCID_METHOD_DEPTH_PEELING`: `geometryShader` and
    /// `independentBlend`, on a device with `maxColorAttachments` of at least 7). OR
    /// together the features of the methods the engine uses. A frame with a method whose
    /// features the engine's device lacks fails with
    /// `TRANSLUCID_RESULT_ERROR_DEVICE_REQUIREMENTS`, naming them. Needs no context.
    #[no_mangle]
    #[must_use]
    pub extern "C" fn translucid_host_get_method_requirements(
        method: u32,
        out_requirements: *mut translucid_host_requirements,
    ) -> translucid_result {
        panic::without_context(|| {
            let method = translucid_method::from_raw(method)?;
            write_requirements(
                out_requirements,
                host_requirements_with(method.kind().optional_features()),
            )
        })
    }
}

fn write_requirements(
    out_requirements: *mut translucid_host_requirements,
    wanted: HostRequirements,
) -> FfiResult<translucid_result> {
    let requirements = try_ref(out_requirements.cast_const(), "out_requirements")?;
    check_type(
        requirements.s_type,
        translucid_structure_type::HostRequirements,
        "translucid_host_requirements",
    )?;
    let header = (requirements.s_type, requirements.next);
    let subgroups = subgroup_requirements_out(header.1)?;
    let out = try_out(out_requirements, "out_requirements")?;
    debug_assert!(wanted.extensions.is_empty(), "list them in a static array");
    if let Some((sub_header, sub_out)) = subgroups {
        sub_out.write(translucid_host_subgroup_requirements {
            s_type: sub_header.0,
            next: sub_header.1,
            stages: wanted.subgroups.stages,
            operations: wanted.subgroups.operations,
            min_size: wanted.subgroups.min_size,
        });
    }
    out.write(translucid_host_requirements {
        s_type: header.0,
        next: header.1,
        api_version: wanted.api_version,
        queue_flags: wanted.queue_flags,
        features: wanted.features,
        extension_count: 0,
        extensions: std::ptr::null(),
    });
    Ok(translucid_result::Success)
}

impl OutStructure for translucid_host_subgroup_requirements {
    const TYPE: translucid_structure_type = translucid_structure_type::HostSubgroupRequirements;
    const NAME: &'static str = "translucid_host_subgroup_requirements";
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

/// The `translucid_host_subgroup_requirements` chained at `next` (the requirements' only
/// chained structure), checked, to be written once the whole call succeeds.
#[allow(clippy::type_complexity)]
fn subgroup_requirements_out<'a>(
    next: *mut c_void,
) -> FfiResult<
    Option<(
        (u32, *mut c_void),
        &'a mut std::mem::MaybeUninit<translucid_host_subgroup_requirements>,
    )>,
> {
    if next.is_null() {
        return Ok(None);
    }
    let what = "translucid_host_requirements.next";
    let link = try_ref(
        next.cast_const().cast::<translucid_base_in_structure>(),
        what,
    )?;
    check_type(
        link.s_type,
        translucid_structure_type::HostSubgroupRequirements,
        what,
    )?;
    try_out_structure(next.cast::<translucid_host_subgroup_requirements>(), what).map(Some)
}

/// `translucid_frame_record` and `translucid_frame_record_native_blend`: the arguments
/// checked, the frame recorded, tracked and its handle written.
fn record_frame(
    objects: &mut Objects,
    (info, targets, out_frame): (
        *const translucid_frame_info,
        *const translucid_host_frame_targets,
        *mut translucid_frame,
    ),
    recording: Recording,
) -> FfiResult<translucid_result> {
    let info = try_ref(info, "info")?;
    let targets = try_ref(targets, "targets")?;
    let out = try_out(out_frame, "out_frame")?;
    let id = record(objects, info, targets, recording)?;
    out.write(translucid_frame { id });
    Ok(translucid_result::Success)
}

impl translucid_frame {
    /// Host-device mode: records a frame into the engine's command buffer and writes its
    /// handle to `*out_frame`. Nothing is submitted: the engine submits the command buffer,
    /// waits for it, then calls `translucid_frame_complete`. The commands copy the opaque
    /// colour and depth from the engine's images, composite the transparent draws over the
    /// colour, copy the result into the colour image and leave both images in their
    /// `final_layout` (`TRANSLUCID_METHOD_BLEND` draws straight into the images instead,
    /// where the colour format blends: one stage, "blend"). `info->opaque_layer` must be
    /// NULL and no draw opaque; `info->width` and `height` are the frame's size (each
    /// view's), which covers the top-left corner of the images (all of them when they are
    /// that size) unless a structure chained to `targets` places it.
    ///
    /// The engine's obligations:
    /// - The command buffer is recording, outside any render pass, and its pool is not used
    ///   by another thread during the call. translucid binds its own pipelines, descriptor
    ///   sets and push constants: bind yours again before recording more of your own work.
    /// - Submit the recorded commands once (no simultaneous use, no resubmission), and not
    ///   after the frame or context is destroyed.
    /// - "Finished" means the host waited for the submission (`vkWaitForFences`, a timeline
    ///   `vkWaitSemaphores`, or `vkDeviceWaitIdle`); a semaphore another queue waits on is
    ///   not enough.
    /// - Colour in a UNORM format is taken as linear, in an SRGB format as sRGB; its alpha is
    ///   kept or overwritten as `targets.colour` says. Depth is the frame camera's (`translucid_camera`): the engine's
    ///   projection matrix, or the field-of-view perspective, with the same jitter.
    ///
    /// Views: a frame of several views (stereo, a split screen) chains a
    /// `translucid_host_frame_views` to `targets`; the views share the frame's uploads, and
    /// the frame is one frame in flight. Views may also be recorded as frames of their own,
    /// each counting as a frame in flight.
    ///
    /// Frames in flight: up to the context's `frames_in_flight` frames may be recorded and
    /// not completed, in one command buffer or several; past that, recording returns
    /// `TRANSLUCID_RESULT_ERROR_FRAME_IN_FLIGHT`.
    /// Submit them to one queue in the order they were recorded. Each frame's own data
    /// (draws, constants, counters, timestamps) has a slot of its own; the working buffers
    /// are shared, so the frames run one after another on the GPU. A frame uses the
    /// context's assets as they were when it was recorded: updating or destroying them
    /// afterwards does not change it.
    ///
    /// What a frame builds: nothing, once a frame with the same method, size and settings
    /// has been drawn over the same assets (its pipelines, uploads and buffers are reused
    /// whatever the camera, light, draws and transforms; buffers grow when a frame needs
    /// more); after assets were created or destroyed, the uploads
    /// (`translucid_frame_statistics` counts both). Arguments are checked before anything is recorded; an error from the method
    /// itself may leave commands recorded, so reset the command buffer after any error.
    ///
    /// Barriers: the recorded commands wait for the engine's earlier writes of both images
    /// (any stage) and make their own writes available to whatever the engine records
    /// after them, so the engine needs no barrier of its own around the call.
    #[no_mangle]
    #[must_use]
    pub extern "C" fn translucid_frame_record(
        context: *mut translucid_context,
        info: *const translucid_frame_info,
        targets: *const translucid_host_frame_targets,
        out_frame: *mut translucid_frame,
    ) -> translucid_result {
        panic::with_context(context, |objects| {
            record_frame(objects, (info, targets, out_frame), Recording::Method)
        })
    }

    /// Host-device mode, for measuring: records `native_blend`, the yardstick translucid's
    /// speed is measured against, into the engine's command buffer, like
    /// `translucid_frame_record` (the same arguments, obligations, frames in flight and
    /// completion). It is what an engine writes for its transparent draws, not a
    /// transparency method: `info`'s draws blended unsorted, in submission order, in one
    /// hardware pass straight into the colour image against the depth image (tested, not
    /// written; stencil kept), with translucid's shading, and no copy in or out. The frame's
    /// `translucid_frame_statistics::gpu_milliseconds` is that pass's GPU time; a method's
    /// frame's over it is the method's cost next to the engine's own blend
    /// (`examples-c/frame_loop.c` prints it).
    ///
    /// Besides `translucid_frame_record`'s usages, the colour image needs
    /// `VK_IMAGE_USAGE_COLOR_ATTACHMENT_BIT` in a format the device blends with dual-source
    /// blending, and the depth image `VK_IMAGE_USAGE_DEPTH_STENCIL_ATTACHMENT_BIT`. The
    /// images end in their `final_layout`. It uses a frame slot of `info->method`'s
    /// renderer, which is made as for `translucid_frame_record`.
    #[no_mangle]
    #[must_use]
    pub extern "C" fn translucid_frame_record_native_blend(
        context: *mut translucid_context,
        info: *const translucid_frame_info,
        targets: *const translucid_host_frame_targets,
        out_frame: *mut translucid_frame,
    ) -> translucid_result {
        panic::with_context(context, |objects| {
            record_frame(objects, (info, targets, out_frame), Recording::NativeBlend)
        })
    }

    /// Host-device mode: call once the host waited for the engine's submission of the frame's
    /// command buffer. Reads the frame's GPU timings and counters (see
    /// `translucid_frame_get_statistics`) and ends the frame's flight. Frames in flight
    /// recorded before it are completed first, in order (on one queue they ran before it), so
    /// completing only the newest after waiting for it is enough; each keeps its own
    /// statistics, and completing one of them afterwards is the error for a frame not in
    /// flight. Returns:
    /// - `TRANSLUCID_RESULT_SUCCESS`: the colour image holds the frame.
    /// - `TRANSLUCID_RESULT_FRAME_DEGRADED`: the frame went past one of the limits a single
    ///   recording handles (README, "When a frame is not right"): pixel rows it could not
    ///   finish kept the opaque colour (`translucid_frame_statistics.overflowed`). translucid
    ///   has grown its buffers, so later frames are right; to repair this one, restore the
    ///   opaque colour (draw it again) and record the frame again, before presenting. Bin
    ///   lists too small for the frame do not end so: they are rasterized in bands within
    ///   the frame.
    /// - `TRANSLUCID_RESULT_NOT_READY`: the commands have not run (not submitted, or still
    ///   running). Nothing changed and the frame stays in flight.
    /// - `TRANSLUCID_RESULT_ERROR_INVALID_ARGUMENT` for a frame not in flight (completed,
    ///   also by the completion of a newer frame, or abandoned already): nothing changes, and
    ///   its statistics are there if it completed. Or another error from the method (such as
    ///   a bin too crowded for this device): the frame's flight is over, and the next
    ///   recording with its method builds that method's resources anew.
    #[no_mangle]
    #[must_use]
    pub extern "C" fn translucid_frame_complete(
        context: *mut translucid_context,
        frame: translucid_frame,
    ) -> translucid_result {
        panic::with_context(context, |objects| complete(objects, frame))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn vulkan_types_have_the_sizes_of_vulkan_h() {
        assert_eq!(std::mem::size_of::<VkImage>(), 8);
        assert_eq!(std::mem::size_of::<VkFormat>(), 4);
        assert_eq!(std::mem::size_of::<VkImageLayout>(), 4);
        assert_eq!(
            std::mem::size_of::<VkPhysicalDeviceFeatures>(),
            55 * 4,
            "VkPhysicalDeviceFeatures has 55 VkBool32 members"
        );
        assert_eq!(
            std::mem::size_of::<PFN_vkGetInstanceProcAddr>(),
            std::mem::size_of::<usize>()
        );
    }
}
