//! Host-device mode: the engine's instance and device, wrapped without being owned, and the
//! copies between the engine's images and the frame targets.
//!
//! The engine asks [`host_requirements`] what to enable before it creates its device, then
//! describes what it created in a [`HostDevice`]; [`Gpu::from_host`] checks the description
//! against the requirements and names everything missing. Function pointers are loaded
//! through the engine's `vkGetInstanceProcAddr`, so translucid uses the same loader (and
//! layers) as the engine. translucid then owns only its allocator and what it creates; it
//! never submits, never waits on the engine's queues and never destroys the engine's objects.

use super::device::describe;
use super::{Gpu, GpuImage};
use crate::{Error, Result};
use ash::vk;
use ash::vk::ImageLayout as L;
use std::ffi::{CStr, CString};

/// The lowest Vulkan version translucid runs on (instance and device).
pub const HOST_API_VERSION: u32 = vk::API_VERSION_1_2;

/// What the engine must enable for translucid.
#[derive(Clone, Copy, Debug)]
pub struct HostRequirements {
    /// The lowest `apiVersion` for the instance, and the physical device's version.
    pub api_version: u32,
    /// What the queue family the engine names must support.
    pub queue_flags: vk::QueueFlags,
    /// The features every method together needs (blend: dual-source blending; exact and
    /// wavelet: 64-bit shader integers), each `vk::TRUE`.
    pub features: vk::PhysicalDeviceFeatures,
    /// Device extensions; none today.
    pub extensions: &'static [&'static CStr],
    /// What exact and wavelet need of the device's subgroups, which are properties to pick a
    /// device by, not features to enable.
    pub subgroups: SubgroupRequirements,
}

/// The subgroups the bin rasters (exact, wavelet) need: a tile of pixels votes, broadcasts
/// and reduces as one subgroup, and the smallest tile is a row of `BIN_SIZE` pixels.
///
/// Recommended besides: `subgroupSizeControl` and `computeFullSubgroups` enabled (Vulkan
/// 1.3, or `VK_EXT_subgroup_size_control`) and said so in
/// [`HostDevice::subgroup_size_control`]; the rasters' tiles then fill a whole subgroup
/// (8x4 pixels at 32 lanes) instead of a row of 8.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct SubgroupRequirements {
    /// Stages that use subgroup operations (`VkPhysicalDeviceSubgroupProperties::supportedStages`).
    pub stages: vk::ShaderStageFlags,
    /// The operations they use (`supportedOperations`).
    pub operations: vk::SubgroupFeatureFlags,
    /// The least `subgroupSize`.
    pub min_size: u32,
}

/// What the bin rasters need of subgroups ([`SubgroupRequirements`]).
pub const SUBGROUP_REQUIREMENTS: SubgroupRequirements = SubgroupRequirements {
    stages: vk::ShaderStageFlags::COMPUTE,
    operations: vk::SubgroupFeatureFlags::from_raw(
        vk::SubgroupFeatureFlags::BASIC.as_raw()
            | vk::SubgroupFeatureFlags::VOTE.as_raw()
            | vk::SubgroupFeatureFlags::ARITHMETIC.as_raw()
            | vk::SubgroupFeatureFlags::BALLOT.as_raw(),
    ),
    min_size: crate::methods::bins::layout::BIN_SIZE,
};

/// What translucid needs of the engine's device.
pub fn host_requirements() -> HostRequirements {
    HostRequirements {
        api_version: HOST_API_VERSION,
        queue_flags: vk::QueueFlags::GRAPHICS | vk::QueueFlags::COMPUTE,
        features: vk::PhysicalDeviceFeatures::default()
            .dual_src_blend(true)
            .shader_int64(true),
        extensions: &[],
        subgroups: SUBGROUP_REQUIREMENTS,
    }
}

/// A device feature only some methods need, beyond [`host_requirements`]'s: a method that
/// needs one says so by name when the device lacks it (an engine enables it only for the
/// methods it uses).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum OptionalFeature {
    FragmentStoresAndAtomics,
    GeometryShader,
    IndependentBlend,
}

impl OptionalFeature {
    /// The feature's Vulkan name.
    pub fn name(self) -> &'static str {
        match self {
            Self::FragmentStoresAndAtomics => "fragmentStoresAndAtomics",
            Self::GeometryShader => "geometryShader",
            Self::IndependentBlend => "independentBlend",
        }
    }

    fn enable(self, features: vk::PhysicalDeviceFeatures) -> vk::PhysicalDeviceFeatures {
        match self {
            Self::FragmentStoresAndAtomics => features.fragment_stores_and_atomics(true),
            Self::GeometryShader => features.geometry_shader(true),
            Self::IndependentBlend => features.independent_blend(true),
        }
    }

    fn enabled(self, info: &super::DeviceInfo) -> bool {
        match self {
            Self::FragmentStoresAndAtomics => info.fragment_stores_and_atomics,
            Self::GeometryShader => info.geometry_shader,
            Self::IndependentBlend => info.independent_blend,
        }
    }
}

/// What the engine must enable for a method that needs `optional` features: [`host_requirements`]
/// with those features on too.
pub fn host_requirements_with(optional: &[OptionalFeature]) -> HostRequirements {
    let mut wanted = host_requirements();
    for feature in optional {
        wanted.features = feature.enable(wanted.features);
    }
    wanted
}

impl Gpu {
    /// Checks that the device has `optional` enabled, for the method named `method`: the
    /// error names each one missing (on an engine's device, as a requirement to enable).
    pub fn require_features(&self, method: &str, optional: &[OptionalFeature]) -> Result<()> {
        let info = self.info();
        let missing: Vec<&str> = optional
            .iter()
            .filter(|f| !f.enabled(info))
            .map(|f| f.name())
            .collect();
        if missing.is_empty() {
            return Ok(());
        }
        let missing = missing.join(", ");
        Err(if self.is_host_device() {
            Error::HostRequirements(format!(
                "the {method} method needs {missing} enabled on the engine's device; enable \
                 what translucid_host_get_method_requirements lists for it"
            ))
        } else {
            Error::NoDevice(format!(
                "{} lacks {missing}, which the {method} method needs",
                info.name
            ))
        })
    }
}

/// The features of `f` that are on, by their Vulkan names (only those translucid may need).
fn features_on(f: &vk::PhysicalDeviceFeatures) -> Vec<&'static str> {
    [
        ("dualSrcBlend", f.dual_src_blend),
        ("shaderInt64", f.shader_int64),
    ]
    .into_iter()
    .filter(|(_, on)| *on == vk::TRUE)
    .map(|(name, _)| name)
    .collect()
}

/// The engine's device, as it created it.
#[derive(Clone, Debug)]
pub struct HostDevice {
    pub get_instance_proc_addr: vk::PFN_vkGetInstanceProcAddr,
    pub instance: vk::Instance,
    pub physical_device: vk::PhysicalDevice,
    pub device: vk::Device,
    /// The family of the queues the engine will submit translucid's work on.
    pub queue_family: u32,
    /// The `apiVersion` the engine created its instance with.
    pub api_version: u32,
    /// The features the engine enabled on the device.
    pub features: vk::PhysicalDeviceFeatures,
    /// The device extensions the engine enabled.
    pub extensions: Vec<CString>,
    /// Force the CPU-driver or the GPU variants; `None` follows `TRANSLUCID_PROFILE`, else
    /// the device.
    pub profile: Option<super::Profile>,
    /// The engine enabled `subgroupSizeControl` and `computeFullSubgroups` (Vulkan 1.3's
    /// features, or `VK_EXT_subgroup_size_control`'s with the extension), so that the bin
    /// rasters may hold their workgroups to whole subgroups of the device's size and make a
    /// tile one subgroup's pixels. Checked against what the device supports; translucid
    /// cannot see enabled features beyond the core ones.
    pub subgroup_size_control: bool,
    /// Keep the bin rasters' software sampler where the profile would sample textures in
    /// hardware (`GpuOptions::software_sampling`; `TRANSLUCID_SAMPLING=software` does the
    /// same).
    pub software_sampling: bool,
    /// The most GPU memory translucid's objects on the device may hold, in bytes; `None`:
    /// no limit.
    pub memory_budget: Option<u64>,
    /// The engine's host allocator, which every Vulkan object translucid makes on the device
    /// is created and destroyed with.
    pub allocation_callbacks: Option<AllocationCallbacks>,
}

/// An engine's `VkAllocationCallbacks`, kept for the device's lifetime.
#[derive(Clone, Copy, Debug)]
pub struct AllocationCallbacks(pub vk::AllocationCallbacks<'static>);

// SAFETY: Vulkan calls an object's allocation callbacks from whichever thread uses the object,
// so the engine that hands them over makes them (and their user data) callable from any
// thread, as the header says; translucid only passes them to Vulkan.
unsafe impl Send for AllocationCallbacks {}
// SAFETY: as for Send; translucid never calls or changes them itself.
unsafe impl Sync for AllocationCallbacks {}

fn version_string(v: u32) -> String {
    format!("{}.{}", vk::api_version_major(v), vk::api_version_minor(v))
}

impl Gpu {
    /// Wraps the engine's device after checking it against [`host_requirements`]; the error
    /// names every version, feature, extension or queue capability that is missing.
    ///
    /// # Safety
    /// The handles are live objects of one instance (the device made from the physical device
    /// with the given features and extensions), `get_instance_proc_addr` is the loader's for
    /// that instance, and they outlive the returned `Gpu` and everything created from it.
    pub unsafe fn from_host(host: &HostDevice) -> Result<Self> {
        if host.instance == vk::Instance::null()
            || host.physical_device == vk::PhysicalDevice::null()
            || host.device == vk::Device::null()
        {
            return Err(Error::HostFrame(
                "the instance, physical device and device must not be VK_NULL_HANDLE".into(),
            ));
        }
        let wanted = host_requirements();
        let mut missing = Vec::new();
        if host.api_version < wanted.api_version {
            missing.push(format!(
                "instance apiVersion {} (the engine says {})",
                version_string(wanted.api_version),
                version_string(host.api_version)
            ));
        }
        let have = features_on(&host.features);
        missing.extend(
            features_on(&wanted.features)
                .into_iter()
                .filter(|f| !have.contains(f))
                .map(|f| format!("feature {f}")),
        );
        missing.extend(
            wanted
                .extensions
                .iter()
                .filter(|e| !host.extensions.iter().any(|h| h.as_c_str() == **e))
                .map(|e| format!("extension {}", e.to_string_lossy())),
        );
        let static_fn = ash::StaticFn {
            get_instance_proc_addr: host.get_instance_proc_addr,
        };
        // SAFETY: the pointer is the loader's vkGetInstanceProcAddr (caller's guarantee).
        let entry = unsafe { ash::Entry::from_static_fn(static_fn) };
        // SAFETY: the caller guarantees a live instance made through this loader.
        let instance = unsafe { ash::Instance::load(entry.static_fn(), host.instance) };
        // Vulkan 1.0 queries only until the versions are known to be good: describe() uses
        // 1.1 properties, which an older instance or device may not have.
        // SAFETY: physical device of this instance (caller's guarantee).
        let (properties, families) = unsafe {
            (
                instance.get_physical_device_properties(host.physical_device),
                instance.get_physical_device_queue_family_properties(host.physical_device),
            )
        };
        if properties.api_version < wanted.api_version {
            missing.push(format!(
                "a Vulkan {} device ({} is {})",
                version_string(wanted.api_version),
                properties
                    .device_name_as_c_str()
                    .map(|s| s.to_string_lossy().into_owned())
                    .unwrap_or_default(),
                version_string(properties.api_version)
            ));
        }
        match families.get(host.queue_family as usize) {
            None => missing.push(format!(
                "queue family {} (the device has {})",
                host.queue_family,
                families.len()
            )),
            Some(f) => {
                if !f.queue_flags.contains(wanted.queue_flags) {
                    missing.push(format!(
                        "graphics and compute on queue family {}",
                        host.queue_family
                    ));
                }
                if f.timestamp_valid_bits == 0 {
                    missing.push(format!(
                        "timestamps on queue family {} (for per-stage GPU times)",
                        host.queue_family
                    ));
                }
            }
        }
        if !missing.is_empty() {
            return Err(Error::HostRequirements(format!(
                "missing {}; enable what translucid_host_get_requirements lists",
                missing.join(", ")
            )));
        }
        let mut info = describe(&instance, 0, host.physical_device);
        // Methods look at what is enabled, not merely supported.
        info.dual_source_blend = true;
        info.shader_int64 = true;
        // Optional (`OptionalFeature`): the methods that need them say so when they are off.
        info.fragment_stores_and_atomics = host.features.fragment_stores_and_atomics == vk::TRUE;
        info.geometry_shader = host.features.geometry_shader == vk::TRUE;
        info.independent_blend = host.features.independent_blend == vk::TRUE;
        info.software_sampling =
            host.software_sampling || super::device::software_sampling_asked()?;
        info.full_subgroups = host.subgroup_size_control
            && held_subgroups_usable(host, properties.api_version, &info)?;
        info.profile = host
            .profile
            .or(super::Profile::from_env()?)
            .unwrap_or(info.profile);
        // SAFETY: a live device of this instance (caller's guarantee).
        let device = unsafe { ash::Device::load(instance.fp_v1_0(), host.device) };
        Self::wrap_host(
            entry,
            instance,
            device,
            host.physical_device,
            info,
            host.memory_budget,
            host.allocation_callbacks,
        )
    }
}

/// Whether the bin rasters may hold workgroups to whole subgroups on the engine's device,
/// which the engine says has `subgroupSizeControl` and `computeFullSubgroups` enabled: an
/// error if it was given neither Vulkan 1.3 nor the extension (so the features cannot be
/// on), `false` (tiles of a row, with a warning) on a device whose compute shaders cannot
/// require its subgroup size, on a driver measured to split such workgroups, or where
/// `TRANSLUCID_BIN_TILES=row` asks for rows.
fn held_subgroups_usable(
    host: &HostDevice,
    device_version: u32,
    info: &super::DeviceInfo,
) -> Result<bool> {
    let core = host.api_version >= vk::API_VERSION_1_3 && device_version >= vk::API_VERSION_1_3;
    let extension = host
        .extensions
        .iter()
        .any(|e| e.as_c_str() == ash::ext::subgroup_size_control::NAME);
    if !(core || extension) {
        return Err(Error::HostRequirements(format!(
            "subgroup_size_control is set, but {} was given neither Vulkan 1.3 nor the \
             extension VK_EXT_subgroup_size_control; leave it unset, or enable \
             subgroupSizeControl and computeFullSubgroups with one of them",
            info.name
        )));
    }
    if super::device::row_tiles_forced()? {
        log::info!("TRANSLUCID_BIN_TILES=row: the bins' tiles are one row");
        return Ok(false);
    }
    if !info.subgroup_size_control {
        log::warn!(
            "{}: its compute shaders cannot require subgroups of {} with full subgroups; the \
             bins' tiles are one row",
            info.name,
            info.subgroup_size
        );
        return Ok(false);
    }
    // translucid never submits on an engine's device, so it cannot probe it as it does its
    // own (`subgroup_probe`). Lavapipe above 16 lanes reports subgroups of 32 or 64 but runs
    // compute shaders 16 lanes at a time, held or not (docs/gpu.md).
    if info.driver_id == vk::DriverId::MESA_LLVMPIPE && info.subgroup_size > 16 {
        log::warn!(
            "{}: runs compute shaders in subgroups of 16, not the {} it reports; the bins' \
             tiles are one row",
            info.name,
            info.subgroup_size
        );
        return Ok(false);
    }
    Ok(true)
}

/// One of the engine's images: the layout it is in when the recorded commands run, and the
/// one it must be left in.
#[derive(Clone, Copy, Debug)]
pub struct HostImage {
    pub image: vk::Image,
    pub format: vk::Format,
    pub layout: vk::ImageLayout,
    pub final_layout: vk::ImageLayout,
    /// The array layer the frame reads and writes (0 for an image of one layer): each view
    /// of a layered image, as XR swapchains hand them, is a frame of its own.
    pub layer: u32,
    /// The frame's top-left corner in the image ((0, 0) but for a view in a part of it: a
    /// split screen, or one half of a side-by-side stereo image).
    pub origin: vk::Offset2D,
}

/// What a host-device frame records into: the engine's command buffer (recording, outside a
/// render pass) and its colour and depth images, both single-sample 2D images of the frame's
/// size with one mip level, of which the frame reads and writes one array layer each.
#[derive(Clone, Copy, Debug)]
pub struct HostTargets {
    pub cmd: vk::CommandBuffer,
    /// The opaque colour the result is composited onto: COLOR_ATTACHMENT, TRANSFER_SRC and
    /// TRANSFER_DST usage, a format that supports blits both ways (not an integer format).
    /// Where the format blends, `blend` and the yardstick draw into it, and the methods that
    /// composite in place blend onto it; the others copy it in and out.
    pub colour: HostImage,
    /// Read only: one of [`HOST_DEPTH_FORMATS`] (stencil ignored), with SAMPLED usage: the
    /// methods that composite in place sample it where it is, the others sample it into
    /// their depth target, but copy `D32_SFLOAT` depth growing away from the eye (which then
    /// needs TRANSFER_SRC usage). `blend` and the yardstick test against it:
    /// DEPTH_STENCIL_ATTACHMENT usage too.
    pub depth: HostImage,
}

// ATTACHMENT_OPTIMAL and READ_ONLY_OPTIMAL are synchronization2's (Vulkan 1.3): an engine
// whose images are in them has the feature enabled, which translucid's barriers then use.
const COLOUR_LAYOUTS: [vk::ImageLayout; 8] = [
    vk::ImageLayout::GENERAL,
    vk::ImageLayout::ATTACHMENT_OPTIMAL,
    vk::ImageLayout::READ_ONLY_OPTIMAL,
    vk::ImageLayout::COLOR_ATTACHMENT_OPTIMAL,
    vk::ImageLayout::SHADER_READ_ONLY_OPTIMAL,
    vk::ImageLayout::TRANSFER_SRC_OPTIMAL,
    vk::ImageLayout::TRANSFER_DST_OPTIMAL,
    vk::ImageLayout::PRESENT_SRC_KHR,
];

const DEPTH_LAYOUTS: [vk::ImageLayout; 10] = [
    vk::ImageLayout::GENERAL,
    vk::ImageLayout::ATTACHMENT_OPTIMAL,
    vk::ImageLayout::READ_ONLY_OPTIMAL,
    vk::ImageLayout::DEPTH_STENCIL_ATTACHMENT_OPTIMAL,
    vk::ImageLayout::DEPTH_STENCIL_READ_ONLY_OPTIMAL,
    vk::ImageLayout::DEPTH_ATTACHMENT_OPTIMAL,
    vk::ImageLayout::DEPTH_READ_ONLY_OPTIMAL,
    vk::ImageLayout::SHADER_READ_ONLY_OPTIMAL,
    vk::ImageLayout::TRANSFER_SRC_OPTIMAL,
    vk::ImageLayout::TRANSFER_DST_OPTIMAL,
];

/// The depth format translucid copies as it is into its own depth target (when depth grows
/// away from the eye).
pub const HOST_DEPTH_FORMAT: vk::Format = vk::Format::D32_SFLOAT;

/// The depth formats translucid reads: [`HOST_DEPTH_FORMAT`], and those it samples (the
/// stencil of the last two is ignored).
pub const HOST_DEPTH_FORMATS: [vk::Format; 5] = [
    vk::Format::D32_SFLOAT,
    vk::Format::D16_UNORM,
    vk::Format::X8_D24_UNORM_PACK32,
    vk::Format::D24_UNORM_S8_UINT,
    vk::Format::D32_SFLOAT_S8_UINT,
];

/// The aspects a layout transition of an image of depth `format` names: depth, and stencil
/// when the format has one (both aspects change layout together without
/// `separateDepthStencilLayouts`, which translucid does not ask for).
pub fn depth_format_aspects(format: vk::Format) -> vk::ImageAspectFlags {
    match format {
        vk::Format::D24_UNORM_S8_UINT
        | vk::Format::D32_SFLOAT_S8_UINT
        | vk::Format::D16_UNORM_S8_UINT => {
            vk::ImageAspectFlags::DEPTH | vk::ImageAspectFlags::STENCIL
        }
        _ => vk::ImageAspectFlags::DEPTH,
    }
}

/// Layouts that name the depth aspect alone (synchronization2 and separate depth/stencil
/// layouts): a depth image with stencil in one of them has its stencil in a layout
/// translucid is not told.
const DEPTH_ONLY_LAYOUTS: [vk::ImageLayout; 2] = [
    vk::ImageLayout::DEPTH_ATTACHMENT_OPTIMAL,
    vk::ImageLayout::DEPTH_READ_ONLY_OPTIMAL,
];

fn check_layouts(what: &str, image: &HostImage, allowed: &[vk::ImageLayout]) -> Result<()> {
    for (field, layout) in [
        ("layout", image.layout),
        ("final_layout", image.final_layout),
    ] {
        if !allowed.contains(&layout) {
            return Err(Error::HostFrame(format!(
                "{what} {field} is {layout:?}; it must be one of {allowed:?} (the opaque layer \
                 must be defined when the commands run, and is kept afterwards)"
            )));
        }
    }
    Ok(())
}

impl Gpu {
    /// Checks the engine's command buffer, images, formats and layouts before anything is
    /// recorded.
    pub fn check_host_targets(&self, t: &HostTargets) -> Result<()> {
        if t.cmd == vk::CommandBuffer::null()
            || t.colour.image == vk::Image::null()
            || t.depth.image == vk::Image::null()
        {
            return Err(Error::HostFrame(
                "the command buffer, colour image and depth image must not be VK_NULL_HANDLE"
                    .into(),
            ));
        }
        if t.colour.image == t.depth.image {
            return Err(Error::HostFrame(
                "the colour and depth images are the same image".into(),
            ));
        }
        self.check_host_formats(&t.colour, &t.depth)
    }

    /// Checks the formats and layouts of an engine's colour and depth images (their handles
    /// aside) against what host-device frames take.
    pub fn check_host_formats(&self, colour: &HostImage, depth: &HostImage) -> Result<()> {
        check_layouts("colour", colour, &COLOUR_LAYOUTS)?;
        check_layouts("depth", depth, &DEPTH_LAYOUTS)?;
        if depth_format_aspects(depth.format).contains(vk::ImageAspectFlags::STENCIL) {
            for layout in [depth.layout, depth.final_layout] {
                if DEPTH_ONLY_LAYOUTS.contains(&layout) {
                    return Err(Error::HostFrame(format!(
                        "depth layout {layout:?} names the depth aspect alone, but \
                         VK_FORMAT_{:?} has stencil too: use a layout of both aspects \
                         (DEPTH_STENCIL_ATTACHMENT_OPTIMAL, DEPTH_STENCIL_READ_ONLY_OPTIMAL, \
                         GENERAL...)",
                        depth.format
                    )));
                }
            }
        }
        let sampled = vk::FormatFeatureFlags::SAMPLED_IMAGE;
        if !HOST_DEPTH_FORMATS.contains(&depth.format)
            || !self.format_features(depth.format).contains(sampled)
        {
            let names: Vec<String> = HOST_DEPTH_FORMATS
                .iter()
                .map(|f| format!("VK_FORMAT_{f:?}"))
                .collect();
            return Err(Error::HostFrame(format!(
                "depth format is VK_FORMAT_{:?}; translucid reads depth images of {} that \
                 this device can sample",
                depth.format,
                names.join(", ")
            )));
        }
        let blit = vk::FormatFeatureFlags::BLIT_SRC | vk::FormatFeatureFlags::BLIT_DST;
        let props = self.format_features(colour.format);
        if colour.format == vk::Format::UNDEFINED
            || !props.contains(blit)
            || is_integer_or_depth(colour.format)
        {
            return Err(Error::HostFrame(format!(
                "colour format {:?} cannot be blitted to and from on this device (use a \
                 UNORM, SRGB or float colour format)",
                colour.format
            )));
        }
        Ok(())
    }
}

impl Gpu {
    /// What images of `format` with optimal tiling support on this device.
    pub(crate) fn format_features(&self, format: vk::Format) -> vk::FormatFeatureFlags {
        // SAFETY: a physical-device query on a live instance.
        unsafe {
            self.instance()
                .get_physical_device_format_properties(self.physical_device(), format)
        }
        .optimal_tiling_features
    }
}

fn is_integer_or_depth(f: vk::Format) -> bool {
    let name = format!("{f:?}");
    name.contains("INT") || name.starts_with('D') || name.starts_with("S8")
}

/// The colour (or depth) subresource of an image's one level and `layer`.
fn range(aspect: vk::ImageAspectFlags, layer: u32) -> vk::ImageSubresourceRange {
    vk::ImageSubresourceRange {
        aspect_mask: aspect,
        base_mip_level: 0,
        level_count: 1,
        base_array_layer: layer,
        layer_count: 1,
    }
}

fn layers(aspect: vk::ImageAspectFlags, layer: u32) -> vk::ImageSubresourceLayers {
    vk::ImageSubresourceLayers {
        aspect_mask: aspect,
        mip_level: 0,
        base_array_layer: layer,
        layer_count: 1,
    }
}

/// An image and the array layer of it a command reads or writes.
pub(super) type Layer = (vk::Image, u32);

impl HostImage {
    /// The image and its frame's layer.
    pub(super) fn layer(&self) -> Layer {
        (self.image, self.layer)
    }
}

/// Anything any earlier command did, in any stage: the engine's work before ours (or ours
/// before the engine's, in the other direction) is not known more precisely.
pub(super) const ANY: (vk::PipelineStageFlags, vk::AccessFlags) = (
    vk::PipelineStageFlags::ALL_COMMANDS,
    vk::AccessFlags::from_raw(
        vk::AccessFlags::MEMORY_READ.as_raw() | vk::AccessFlags::MEMORY_WRITE.as_raw(),
    ),
);
const TRANSFER_READ: (vk::PipelineStageFlags, vk::AccessFlags) = (
    vk::PipelineStageFlags::TRANSFER,
    vk::AccessFlags::TRANSFER_READ,
);
const COMPUTE_READ: (vk::PipelineStageFlags, vk::AccessFlags) = (
    vk::PipelineStageFlags::COMPUTE_SHADER,
    vk::AccessFlags::SHADER_READ,
);
const TRANSFER_WRITE: (vk::PipelineStageFlags, vk::AccessFlags) = (
    vk::PipelineStageFlags::TRANSFER,
    vk::AccessFlags::TRANSFER_WRITE,
);

/// Pipeline stages and the accesses in them.
type Access = (vk::PipelineStageFlags, vk::AccessFlags);

/// One layout transition of a raw image's layer: the image and layer, its aspect, (old, new)
/// layouts, and the source and destination stages and accesses.
pub(super) struct Transition(
    pub Layer,
    pub vk::ImageAspectFlags,
    pub (L, L),
    pub (vk::PipelineStageFlags, vk::AccessFlags),
    pub (vk::PipelineStageFlags, vk::AccessFlags),
);

impl Gpu {
    pub(super) fn transitions(&self, cmd: vk::CommandBuffer, list: &[Transition]) {
        let barriers: Vec<vk::ImageMemoryBarrier> = list
            .iter()
            .map(|Transition(image, aspect, layouts, src, dst)| {
                vk::ImageMemoryBarrier::default()
                    .old_layout(layouts.0)
                    .new_layout(layouts.1)
                    .src_access_mask(src.1)
                    .dst_access_mask(dst.1)
                    .src_queue_family_index(vk::QUEUE_FAMILY_IGNORED)
                    .dst_queue_family_index(vk::QUEUE_FAMILY_IGNORED)
                    .image(image.0)
                    .subresource_range(range(*aspect, image.1))
            })
            .collect();
        let src = list
            .iter()
            .fold(vk::PipelineStageFlags::empty(), |s, t| s | t.3 .0);
        let dst = list
            .iter()
            .fold(vk::PipelineStageFlags::empty(), |s, t| s | t.4 .0);
        // SAFETY: cmd is recording outside a render pass (checked contract); every barrier
        // names a live image with its whole single subresource.
        unsafe {
            self.device.cmd_pipeline_barrier(
                cmd,
                src,
                dst,
                vk::DependencyFlags::empty(),
                &[],
                &[],
                &barriers,
            )
        };
    }

    /// Blits `extent` pixels from `from` at its origin to `to` at its origin.
    fn blit(
        &self,
        cmd: vk::CommandBuffer,
        from: (Layer, vk::Offset2D),
        to: (Layer, vk::Offset2D),
        extent: vk::Extent2D,
    ) {
        let corners = |origin: vk::Offset2D| {
            [
                vk::Offset3D {
                    x: origin.x,
                    y: origin.y,
                    z: 0,
                },
                vk::Offset3D {
                    x: origin.x + extent.width as i32,
                    y: origin.y + extent.height as i32,
                    z: 1,
                },
            ]
        };
        let ((from, from_origin), (to, to_origin)) = (from, to);
        let region = vk::ImageBlit::default()
            .src_subresource(layers(vk::ImageAspectFlags::COLOR, from.1))
            .src_offsets(corners(from_origin))
            .dst_subresource(layers(vk::ImageAspectFlags::COLOR, to.1))
            .dst_offsets(corners(to_origin));
        // SAFETY: both images are in the transfer layouts named here (set by the barriers
        // before), have blittable formats (checked) and hold `extent` from their origins.
        unsafe {
            self.device.cmd_blit_image(
                cmd,
                from.0,
                vk::ImageLayout::TRANSFER_SRC_OPTIMAL,
                to.0,
                vk::ImageLayout::TRANSFER_DST_OPTIMAL,
                &[region],
                vk::Filter::NEAREST,
            )
        };
    }

    /// Records the copy of the engine's colour (`extent` large from its origin, the frame's
    /// size) into the top-left `extent` of `colour` (a frame target, left in
    /// COLOR_ATTACHMENT_OPTIMAL), and
    /// of its depth into `depth` when given (left in DEPTH_STENCIL_ATTACHMENT_OPTIMAL; `None`
    /// when [`super::DepthImport`] samples it instead). The engine's colour is left in
    /// TRANSFER_SRC_OPTIMAL for [`Gpu::record_host_output`], its depth in its final layout.
    pub(crate) fn record_host_input(
        &self,
        t: &HostTargets,
        extent: vk::Extent2D,
        colour: &GpuImage,
        depth: Option<&GpuImage>,
    ) {
        let (c, d) = (vk::ImageAspectFlags::COLOR, vk::ImageAspectFlags::DEPTH);
        let (src, dst) = (L::TRANSFER_SRC_OPTIMAL, L::TRANSFER_DST_OPTIMAL);
        let mut before = vec![
            Transition(
                t.colour.layer(),
                c,
                (t.colour.layout, src),
                ANY,
                TRANSFER_READ,
            ),
            Transition((colour.raw, 0), c, (L::UNDEFINED, dst), ANY, TRANSFER_WRITE),
        ];
        if let Some(depth) = depth {
            before.push(Transition(
                t.depth.layer(),
                d,
                (t.depth.layout, src),
                ANY,
                TRANSFER_READ,
            ));
            before.push(Transition(
                (depth.raw, 0),
                d,
                (L::UNDEFINED, dst),
                ANY,
                TRANSFER_WRITE,
            ));
        }
        self.transitions(t.cmd, &before);
        let target = ((colour.raw, 0), vk::Offset2D::default());
        self.blit(t.cmd, (t.colour.layer(), t.colour.origin), target, extent);
        let mut after = vec![Transition(
            (colour.raw, 0),
            c,
            (dst, L::COLOR_ATTACHMENT_OPTIMAL),
            TRANSFER_WRITE,
            ANY,
        )];
        if let Some(depth) = depth {
            let copy = vk::ImageCopy::default()
                .src_subresource(layers(d, t.depth.layer))
                .src_offset(vk::Offset3D {
                    x: t.depth.origin.x,
                    y: t.depth.origin.y,
                    z: 0,
                })
                .dst_subresource(layers(d, 0))
                .extent(vk::Extent3D {
                    width: extent.width,
                    height: extent.height,
                    depth: 1,
                });
            // SAFETY: both depth images are D32_SFLOAT (checked by the caller), in the
            // layouts named, and at least `extent` large (the frame's size: the engine's
            // contract, and within the target's, which the renderer checks).
            unsafe {
                self.device
                    .cmd_copy_image(t.cmd, t.depth.image, src, depth.raw, dst, &[copy])
            };
            after.push(Transition(
                t.depth.layer(),
                d,
                (src, t.depth.final_layout),
                TRANSFER_READ,
                ANY,
            ));
            after.push(Transition(
                (depth.raw, 0),
                d,
                (dst, L::DEPTH_STENCIL_ATTACHMENT_OPTIMAL),
                TRANSFER_WRITE,
                ANY,
            ));
        }
        self.transitions(t.cmd, &after);
    }

    /// Moves the engine's depth image to SHADER_READ_ONLY_OPTIMAL, for the compute stages
    /// that sample it where it is, after whatever came before.
    pub(crate) fn record_engine_depth_to_sampled(&self, t: &HostTargets) {
        let layouts = (t.depth.layout, L::SHADER_READ_ONLY_OPTIMAL);
        self.transition_engine_depth(t, layouts, (ANY, COMPUTE_READ));
    }

    /// Returns the engine's depth image from SHADER_READ_ONLY_OPTIMAL to its final layout,
    /// after the compute stages that sampled it.
    pub(crate) fn record_engine_depth_to_final(&self, t: &HostTargets) {
        let layouts = (L::SHADER_READ_ONLY_OPTIMAL, t.depth.final_layout);
        self.transition_engine_depth(t, layouts, (COMPUTE_READ, ANY));
    }

    /// Moves the engine's depth image between `layouts`, after the first access and before
    /// the second.
    fn transition_engine_depth(
        &self,
        t: &HostTargets,
        layouts: (L, L),
        (after, before): (Access, Access),
    ) {
        let aspects = depth_format_aspects(t.depth.format);
        let transition = Transition(t.depth.layer(), aspects, layouts, after, before);
        self.transitions(t.cmd, &[transition]);
    }

    /// Records the copy of the top-left `extent` of the composited `colour` (a frame target
    /// in COLOR_ATTACHMENT_OPTIMAL, left in TRANSFER_SRC_OPTIMAL) back into the engine's
    /// colour image at its origin, which ends in its final layout.
    pub(crate) fn record_host_output(
        &self,
        t: &HostTargets,
        extent: vk::Extent2D,
        colour: &GpuImage,
    ) {
        let c = vk::ImageAspectFlags::COLOR;
        let (src, dst) = (L::TRANSFER_SRC_OPTIMAL, L::TRANSFER_DST_OPTIMAL);
        let attachment = L::COLOR_ATTACHMENT_OPTIMAL;
        self.transitions(
            t.cmd,
            &[
                Transition((colour.raw, 0), c, (attachment, src), ANY, TRANSFER_READ),
                Transition(
                    t.colour.layer(),
                    c,
                    (src, dst),
                    TRANSFER_READ,
                    TRANSFER_WRITE,
                ),
            ],
        );
        let target = ((colour.raw, 0), vk::Offset2D::default());
        self.blit(t.cmd, target, (t.colour.layer(), t.colour.origin), extent);
        let last = Transition(
            t.colour.layer(),
            c,
            (dst, t.colour.final_layout),
            TRANSFER_WRITE,
            ANY,
        );
        self.transitions(t.cmd, &[last]);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn requirements_name_the_features_methods_check() {
        let on = features_on(&host_requirements().features);
        assert_eq!(on, ["dualSrcBlend", "shaderInt64"]);
    }

    #[test]
    fn integer_and_depth_colour_formats_are_refused() {
        assert!(is_integer_or_depth(vk::Format::R8G8B8A8_UINT));
        assert!(is_integer_or_depth(vk::Format::D32_SFLOAT));
        assert!(!is_integer_or_depth(vk::Format::R8G8B8A8_SRGB));
        assert!(!is_integer_or_depth(vk::Format::R16G16B16A16_SFLOAT));
    }
}
