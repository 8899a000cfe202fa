//! Instance, physical-device choice, logical device, queue, allocator and command pool.

use super::error::vk_err;
use super::host::HostDevice;
use super::memory::MemoryStats;
use super::profile::Profile;
use super::validation::{self, ValidationLog};
use crate::{Error, Result};
use ash::vk;
use gpu_allocator::vulkan::{Allocator, AllocatorCreateDesc};
use std::mem::ManuallyDrop;
use std::sync::atomic::{AtomicU64, Ordering};
use std::sync::{Arc, Mutex};
use std::sync::{OnceLock, RwLock};

/// How to create a [`Gpu`].
#[derive(Clone, Debug, Default)]
pub struct GpuOptions {
    /// Device index (as listed by `translucid info`) or a case-insensitive substring of its
    /// name. `None` picks discrete > integrated > virtual > CPU.
    pub device: Option<String>,
    /// Turn on the Khronos validation layer; every validation error fails the call that
    /// submitted the offending work.
    pub validation: bool,
    /// Force the CPU-driver or the GPU variants (`Profile`); `None` follows
    /// `TRANSLUCID_PROFILE`, else the device.
    pub profile: Option<Profile>,
    /// Sample textures in the bin rasters' software sampler, bit for bit the CPU
    /// reference, where the device would sample them in hardware (GPUs: docs/gpu.md);
    /// `TRANSLUCID_SAMPLING=software` does the same.
    pub software_sampling: bool,
    /// The most GPU memory everything made on the device may hold, in bytes; `None`: no
    /// limit ([`Gpu::memory_budget`]). Within a budget the allocator reserves memory in
    /// blocks of 4 MB.
    pub memory_budget: Option<u64>,
}

impl GpuOptions {
    /// Options from `TRANSLUCID_DEVICE` and `TRANSLUCID_VALIDATION=1` (`TRANSLUCID_PROFILE`
    /// is read by [`Gpu::new`] whatever the options).
    pub fn from_env() -> Self {
        Self {
            device: std::env::var("TRANSLUCID_DEVICE")
                .ok()
                .filter(|s| !s.is_empty()),
            validation: std::env::var("TRANSLUCID_VALIDATION").is_ok_and(|v| v == "1"),
            profile: None,
            software_sampling: false,
            memory_budget: None,
        }
    }
}

/// What `translucid info` shows of a device, and the limits methods size themselves by.
#[derive(Clone, Debug)]
pub struct DeviceInfo {
    pub index: usize,
    pub name: String,
    pub kind: &'static str,
    pub api_version: String,
    pub driver: String,
    /// The driver's `VkDriverId` (`VK_DRIVER_ID_MESA_LLVMPIPE` for lavapipe).
    pub driver_id: vk::DriverId,
    pub subgroup_size: u32,
    /// Compute shaders have the subgroup votes, ballots and reductions the exact raster uses.
    pub compute_subgroup_operations: bool,
    /// The device has `subgroupSizeControl` and `computeFullSubgroups`, and compute shaders
    /// can require its subgroup size (enabled or not).
    pub subgroup_size_control: bool,
    /// Compute pipelines can be held to whole subgroups of `subgroup_size` invocations
    /// (`VK_EXT_subgroup_size_control`'s required size and full subgroups, enabled on the
    /// devices translucid makes): the bin rasters' tiles span a subgroup only where they are
    /// (`methods::bins::features::tile_shift`). On an engine's device, only where the engine
    /// says it enabled them (`HostDevice::subgroup_size_control`): translucid cannot see
    /// enabled features past the core ones.
    pub full_subgroups: bool,
    pub max_shared_memory: u32,
    pub max_storage_buffer_range: u32,
    pub max_texel_buffer_elements: u32,
    pub max_image_dimension_2d: u32,
    pub max_compute_workgroup_invocations: u32,
    /// Colour attachments one subpass may write (at least 4; 8 on desktop GPUs).
    pub max_color_attachments: u32,
    /// Nanoseconds per timestamp tick.
    pub timestamp_period_ns: f32,
    pub dual_source_blend: bool,
    /// 64-bit integers in shaders (the bin rasterizers' fixed-point edge functions need them).
    /// No shader uses 64-bit floats: translucid never enables `shaderFloat64`.
    pub shader_int64: bool,
    /// Stores and atomics in fragment shaders (the linked_list method appends its nodes so).
    pub fragment_stores_and_atomics: bool,
    /// The geometry-shader feature, which fragment shaders need to read `gl_PrimitiveID`
    /// (the linked_list method's tie-break).
    pub geometry_shader: bool,
    /// A blend state per colour attachment (the depth_peeling method keeps its depth range
    /// with MAX and its layers with sums and products in one pass).
    pub independent_blend: bool,
    /// Samplers one compute stage may bind: the least of the device's per-stage and
    /// per-set limits (the bin rasters' texture array: `assets::texture_array`).
    pub max_stage_samplers: u32,
    /// Sampled images (combined samplers and texel views included) one compute stage may
    /// bind: the least of the device's per-stage and per-set limits for them.
    pub max_stage_sampled_images: u32,
    /// Asked for the software sampler where the device could sample in hardware
    /// (`GpuOptions::software_sampling`, `TRANSLUCID_SAMPLING=software`).
    pub software_sampling: bool,
    /// Loop iterations a shader invocation may take in one dispatch (the rasters'
    /// LOOP_BUDGET): [`CPU_DRIVER_LOOP_BUDGET`] on CPU drivers, [`GPU_LOOP_BUDGET`] elsewhere.
    /// The driver's, whatever the profile: a forced GPU profile on lavapipe keeps its limit.
    pub loop_budget: u32,
    /// The variants the device gets: its own, or the one forced.
    pub profile: Profile,
}

/// The loop budget on CPU drivers. Lavapipe (gallivm) ends every loop of a shader
/// invocation silently once their iterations add up to 65,535; the rasters stop at this and
/// leave the rest of a row to a continuation dispatch. (A raster may pass it by two searches
/// over the slabs before it stops.)
pub const CPU_DRIVER_LOOP_BUDGET: u32 = 60_000;
const _: () = assert!(CPU_DRIVER_LOOP_BUDGET + 2 * crate::interface::bins::MAX_SLABS < 65_535);
/// The loop budget on other devices, which end no loop: rows that deep take fewer
/// continuation dispatches, and one dispatch stays far from a driver's timeout. (Not yet
/// measured on a GPU.)
pub const GPU_LOOP_BUDGET: u32 = 1 << 18;

/// A Vulkan device: either a headless one translucid made, with one graphics+compute queue
/// ([`Gpu::new`]), or the engine's, wrapped without being owned ([`Gpu::from_host`]). Cheap
/// to clone: every resource holds a clone, so the device outlives everything created from it
/// and resources free themselves on drop.
#[derive(Clone)]
pub struct Gpu(Arc<Shared>);

impl std::ops::Deref for Gpu {
    type Target = Shared;
    fn deref(&self) -> &Shared {
        &self.0
    }
}

/// The device and what is shared by everything created from it.
pub struct Shared {
    _entry: ash::Entry,
    instance: ash::Instance,
    physical: vk::PhysicalDevice,
    messenger: Option<(ash::ext::debug_utils::Instance, vk::DebugUtilsMessengerEXT)>,
    /// Boxed so its address, handed to the messenger, never moves.
    validation: Box<ValidationLog>,
    pub(crate) device: ash::Device,
    /// The queue and command pool translucid submits with; `None` on the engine's device,
    /// where translucid only records into the engine's command buffers.
    pub(crate) submission: Option<Submission>,
    /// Whether translucid created the instance and device, and so destroys them.
    owns_device: bool,
    pub(crate) allocator: ManuallyDrop<Mutex<Allocator>>,
    pub(crate) memory: MemoryStats,
    /// The most bytes `memory` may hold: an allocation past it fails (MemoryBudget).
    pub(crate) memory_budget: Option<u64>,
    /// The engine's host allocator, on its device: every object translucid makes there is
    /// created and destroyed with it. (Device memory comes from gpu-allocator, which takes
    /// none: its blocks use the driver's own host allocations.)
    allocation_callbacks: Option<super::host::AllocationCallbacks>,
    /// Pipelines created on the device so far: each one costs a shader compilation, which
    /// a frame loop must not pay.
    pipelines_created: AtomicU64,
    /// Compute dispatches recorded on the device so far (direct and indirect).
    dispatches_recorded: AtomicU64,
    /// Every pipeline is made through this cache (made on first use), whose data an engine
    /// can save and hand back on its next run ([`Gpu::pipeline_cache_data`]).
    pipeline_cache: OnceLock<vk::PipelineCache>,
    /// Pipelines are made under the read side; a merge into the cache, which Vulkan wants
    /// externally synchronised, under the write side.
    pipeline_cache_lock: RwLock<()>,
    /// The compute pipelines the device's renderers use, shared between them (see
    /// `pipeline_cache.rs`).
    pub(crate) compute_pipelines: super::pipeline_cache::SharedComputePipelines,
    /// The same for graphics pipelines, and the render passes they may be made for, by the
    /// definition that makes passes compatible (attachment formats and samples).
    pub(crate) graphics_pipelines: super::pipeline::SharedGraphicsPipelines,
    pub(crate) render_passes: Mutex<std::collections::HashMap<vk::RenderPass, Vec<i64>>>,
    /// Held while a submission records, submits and waits: the queue, the command pool and
    /// the reused command buffer and fence are externally synchronised objects.
    pub(crate) submitting: Mutex<()>,
    info: DeviceInfo,
}

/// What a device translucid created submits with: one command buffer and one fence, made
/// with the device and reused by every submission (taken in turn under `Shared::submitting`),
/// so that a frame allocates no Vulkan object to submit.
#[derive(Clone, Copy)]
pub(crate) struct Submission {
    pub family: u32,
    pub queue: vk::Queue,
    pub command_pool: vk::CommandPool,
    pub command_buffer: vk::CommandBuffer,
    pub fence: vk::Fence,
}

fn load_entry() -> Result<ash::Entry> {
    // SAFETY: loading the system Vulkan loader runs its initialisers; this is the documented
    // way to use ash and nothing else in the process depends on the library's state.
    unsafe { ash::Entry::load() }.map_err(|e| {
        Error::NoDevice(format!(
            "cannot load the Vulkan loader ({e}); install libvulkan1 and a driver \
             (Debian: mesa-vulkan-drivers)"
        ))
    })
}

/// The `apiVersion` translucid's own instances are made with.
const INSTANCE_API_VERSION: u32 = vk::API_VERSION_1_2;

fn create_instance(entry: &ash::Entry, validation: bool) -> Result<ash::Instance> {
    let app = vk::ApplicationInfo::default()
        .application_name(c"translucid")
        .engine_name(c"translucid")
        .api_version(INSTANCE_API_VERSION);
    let mut layers = Vec::new();
    let mut extensions = Vec::new();
    if validation {
        // SAFETY: plain enumeration call on a loaded entry.
        let available = unsafe { entry.enumerate_instance_layer_properties() }
            .map_err(vk_err("vkEnumerateInstanceLayerProperties"))?;
        let found = available
            .iter()
            .any(|l| l.layer_name_as_c_str().ok() == Some(validation::LAYER_NAME));
        if !found {
            return Err(Error::NoDevice(
                "TRANSLUCID_VALIDATION=1 but the Khronos validation layer is not installed \
                 (Debian: vulkan-validationlayers)"
                    .into(),
            ));
        }
        layers.push(validation::LAYER_NAME.as_ptr());
        extensions.push(ash::ext::debug_utils::NAME.as_ptr());
    }
    let info = vk::InstanceCreateInfo::default()
        .application_info(&app)
        .enabled_layer_names(&layers)
        .enabled_extension_names(&extensions);
    // SAFETY: the create info and everything it points to live until the call returns.
    unsafe { entry.create_instance(&info, None) }.map_err(vk_err("vkCreateInstance"))
}

fn device_kind(t: vk::PhysicalDeviceType) -> (&'static str, u32) {
    match t {
        vk::PhysicalDeviceType::DISCRETE_GPU => ("discrete", 0),
        vk::PhysicalDeviceType::INTEGRATED_GPU => ("integrated", 1),
        vk::PhysicalDeviceType::VIRTUAL_GPU => ("virtual", 2),
        vk::PhysicalDeviceType::CPU => ("cpu", 3),
        _ => ("other", 4),
    }
}

pub(super) fn describe(
    instance: &ash::Instance,
    index: usize,
    pd: vk::PhysicalDevice,
) -> DeviceInfo {
    // SAFETY: pd came from this instance.
    let extensions =
        unsafe { instance.enumerate_device_extension_properties(pd) }.unwrap_or_default();
    let listed = |name: &std::ffi::CStr| {
        extensions
            .iter()
            .any(|e| e.extension_name_as_c_str() == Ok(name))
    };
    // An extension's structures are only chained for a device that lists it (or, for size
    // control, has it in core: Vulkan 1.3, which an engine's device may be).
    // SAFETY: as above.
    let version = unsafe { instance.get_physical_device_properties(pd) }.api_version;
    let has_size_control = listed(ash::ext::subgroup_size_control::NAME);
    let size_control_known = has_size_control || version >= vk::API_VERSION_1_3;
    let mut subgroup = vk::PhysicalDeviceSubgroupProperties::default();
    let mut driver = vk::PhysicalDeviceDriverProperties::default();
    let mut size_control = vk::PhysicalDeviceSubgroupSizeControlProperties::default();
    let mut props2 = vk::PhysicalDeviceProperties2::default()
        .push_next(&mut subgroup)
        .push_next(&mut driver);
    if size_control_known {
        props2 = props2.push_next(&mut size_control);
    }
    // SAFETY: pd came from this instance; the chained structs outlive the call.
    let features = unsafe {
        instance.get_physical_device_properties2(pd, &mut props2);
        instance.get_physical_device_features(pd)
    };
    let p = props2.properties;
    let limits = p.limits;
    let mut size_features = vk::PhysicalDeviceSubgroupSizeControlFeatures::default();
    let mut features2 = vk::PhysicalDeviceFeatures2::default();
    if size_control_known {
        features2 = features2.push_next(&mut size_features);
    }
    // SAFETY: as above.
    unsafe { instance.get_physical_device_features2(pd, &mut features2) };
    let subgroup_size_control = size_features.subgroup_size_control == vk::TRUE
        && size_features.compute_full_subgroups == vk::TRUE
        && size_control
            .required_subgroup_size_stages
            .contains(vk::ShaderStageFlags::COMPUTE)
        && (size_control.min_subgroup_size..=size_control.max_subgroup_size)
            .contains(&subgroup.subgroup_size);
    // translucid's own devices are Vulkan 1.2 ones: they need the extension.
    let full_subgroups = subgroup_size_control && has_size_control;
    let v = p.api_version;
    DeviceInfo {
        index,
        name: p
            .device_name_as_c_str()
            .map(|s| s.to_string_lossy().into_owned())
            .unwrap_or_default(),
        kind: device_kind(p.device_type).0,
        api_version: format!(
            "{}.{}.{}",
            vk::api_version_major(v),
            vk::api_version_minor(v),
            vk::api_version_patch(v)
        ),
        driver: driver
            .driver_info_as_c_str()
            .map(|s| s.to_string_lossy().into_owned())
            .unwrap_or_default(),
        driver_id: driver.driver_id,
        subgroup_size: subgroup.subgroup_size,
        compute_subgroup_operations: subgroup
            .supported_stages
            .contains(super::host::SUBGROUP_REQUIREMENTS.stages)
            && subgroup
                .supported_operations
                .contains(super::host::SUBGROUP_REQUIREMENTS.operations),
        subgroup_size_control,
        full_subgroups,
        max_shared_memory: limits.max_compute_shared_memory_size,
        max_storage_buffer_range: limits.max_storage_buffer_range,
        max_texel_buffer_elements: limits.max_texel_buffer_elements,
        max_image_dimension_2d: limits.max_image_dimension2_d,
        max_compute_workgroup_invocations: limits.max_compute_work_group_invocations,
        max_color_attachments: limits.max_color_attachments,
        timestamp_period_ns: limits.timestamp_period,
        dual_source_blend: features.dual_src_blend == vk::TRUE,
        shader_int64: features.shader_int64 == vk::TRUE,
        fragment_stores_and_atomics: features.fragment_stores_and_atomics == vk::TRUE,
        geometry_shader: features.geometry_shader == vk::TRUE,
        independent_blend: features.independent_blend == vk::TRUE,
        max_stage_samplers: limits
            .max_per_stage_descriptor_samplers
            .min(limits.max_descriptor_set_samplers),
        max_stage_sampled_images: limits
            .max_per_stage_descriptor_sampled_images
            .min(limits.max_descriptor_set_sampled_images)
            .min(limits.max_per_stage_resources),
        software_sampling: false,
        loop_budget: match Profile::of_device(p.device_type, driver.driver_id) {
            Profile::CpuDriver => CPU_DRIVER_LOOP_BUDGET,
            Profile::Gpu => GPU_LOOP_BUDGET,
        },
        profile: Profile::of_device(p.device_type, driver.driver_id),
    }
}

fn usable_devices(instance: &ash::Instance) -> Result<Vec<(vk::PhysicalDevice, DeviceInfo)>> {
    // SAFETY: plain enumeration on a live instance.
    let devices = unsafe { instance.enumerate_physical_devices() }
        .map_err(vk_err("vkEnumeratePhysicalDevices"))?;
    Ok(devices
        .into_iter()
        .enumerate()
        .map(|(i, pd)| (pd, describe(instance, i, pd)))
        .filter(|(_, info)| {
            let (major, minor) = {
                let mut it = info
                    .api_version
                    .split('.')
                    .map(|s| s.parse::<u32>().unwrap_or(0));
                (it.next().unwrap_or(0), it.next().unwrap_or(0))
            };
            (major, minor) >= (1, 2)
        })
        .collect())
}

/// Every Vulkan 1.2+ device on this machine.
pub fn list_devices() -> Result<Vec<DeviceInfo>> {
    let entry = load_entry()?;
    let instance = create_instance(&entry, false)?;
    let result = usable_devices(&instance).map(|d| d.into_iter().map(|(_, i)| i).collect());
    // SAFETY: nothing created from this instance is alive.
    unsafe { instance.destroy_instance(None) };
    result
}

fn choose(
    devices: Vec<(vk::PhysicalDevice, DeviceInfo)>,
    wanted: Option<&str>,
) -> Result<(vk::PhysicalDevice, DeviceInfo)> {
    let names = || {
        devices
            .iter()
            .map(|(_, d)| format!("{}: {} ({})", d.index, d.name, d.kind))
            .collect::<Vec<_>>()
            .join(", ")
    };
    if devices.is_empty() {
        return Err(Error::NoDevice(
            "no Vulkan 1.2 device found (install a driver; Debian: mesa-vulkan-drivers)".into(),
        ));
    }
    let found = match wanted {
        Some(w) => {
            let lower = w.to_lowercase();
            let by_index = w.parse::<usize>().ok();
            devices
                .iter()
                .position(|(_, d)| {
                    Some(d.index) == by_index || d.name.to_lowercase().contains(&lower)
                })
                .ok_or_else(|| {
                    Error::NoDevice(format!(
                        "no device matches {w:?} (by index or name); the devices are: {}",
                        names()
                    ))
                })?
        }
        None => devices
            .iter()
            .enumerate()
            .min_by_key(|(i, (_, d))| {
                let rank = ["discrete", "integrated", "virtual", "cpu"]
                    .iter()
                    .position(|k| *k == d.kind)
                    .unwrap_or(4);
                (rank, *i)
            })
            .map(|(i, _)| i)
            .unwrap_or(0),
    };
    Ok(devices
        .into_iter()
        .nth(found)
        .expect("index from the same list"))
}

impl Gpu {
    /// Creates the device described by `options`.
    pub fn new(options: &GpuOptions) -> Result<Self> {
        let entry = load_entry()?;
        let instance = create_instance(&entry, options.validation)?;
        let validation = Box::<ValidationLog>::default();
        // From here on, a failure must destroy what exists: build in a guard-free way by
        // finishing creation in a helper and cleaning up the instance on error.
        let messenger = if options.validation {
            match create_messenger(&entry, &instance, &validation) {
                Ok(m) => Some(m),
                Err(e) => {
                    // SAFETY: nothing else was created from the instance.
                    unsafe { instance.destroy_instance(None) };
                    return Err(e);
                }
            }
        } else {
            None
        };
        let chosen = usable_devices(&instance)
            .and_then(|d| choose(d, options.device.as_deref()))
            .and_then(|(physical, mut info)| {
                info.profile = options
                    .profile
                    .or(Profile::from_env()?)
                    .unwrap_or(info.profile);
                info.software_sampling = options.software_sampling || software_sampling_asked()?;
                Ok((physical, info))
            });
        let (physical, info) = match chosen {
            Ok(c) => c,
            Err(e) => {
                destroy_instance(&instance, &messenger);
                return Err(e);
            }
        };
        let gpu = match create_device(&instance, physical, &info, options.memory_budget) {
            Ok((device, allocator, submission)) => Self(Arc::new(Shared {
                _entry: entry,
                instance,
                physical,
                messenger,
                validation,
                device,
                submission: Some(submission),
                owns_device: true,
                allocator: ManuallyDrop::new(Mutex::new(allocator)),
                memory: MemoryStats::default(),
                memory_budget: options.memory_budget,
                allocation_callbacks: None,
                pipelines_created: AtomicU64::new(0),
                dispatches_recorded: AtomicU64::new(0),
                pipeline_cache: OnceLock::new(),
                pipeline_cache_lock: RwLock::new(()),
                compute_pipelines: Default::default(),
                graphics_pipelines: Default::default(),
                render_passes: Default::default(),
                submitting: Mutex::new(()),
                info,
            })),
            Err(e) => {
                destroy_instance(&instance, &messenger);
                return Err(e);
            }
        };
        gpu.with_checked_subgroups()
    }

    /// This new device, with `full_subgroups` off unless a workgroup held to whole subgroups
    /// really runs in one ([`subgroup_probe`](super::subgroup_probe)), or where
    /// `TRANSLUCID_BIN_TILES=row` asks for the bins' tiles of one row (docs/gpu.md, A/B).
    fn with_checked_subgroups(mut self) -> Result<Self> {
        if !self.info.full_subgroups {
            return Ok(self);
        }
        let keep = if row_tiles_forced()? {
            log::info!("TRANSLUCID_BIN_TILES=row: the bins' tiles are one row");
            false
        } else {
            let size = self.info.subgroup_size;
            // A probe that cannot run leaves the tiles a row, which every device runs right.
            let lanes = super::subgroup_probe::lanes_per_subgroup(&self).unwrap_or_else(|e| {
                log::warn!("{}: the subgroup probe failed ({e})", self.info.name);
                0
            });
            if lanes != size {
                log::warn!(
                    "{}: a workgroup held to whole subgroups of {size} lanes ran in subgroups \
                     of {lanes}; the bins' tiles are one row",
                    self.info.name
                );
            }
            lanes == size
        };
        // The probe's objects are gone, so this is the only reference.
        Arc::get_mut(&mut self.0)
            .expect("no clone of a device being made")
            .info
            .full_subgroups = keep;
        Ok(self)
    }
}

impl Gpu {
    /// This device as an engine hands its own to translucid ([`Gpu::from_host`]), for a
    /// harness that plays the engine on a device translucid made (the bench): its features
    /// and extensions as enabled, its queue family. `None` on an engine's device.
    ///
    /// A `Gpu` made from it must be dropped before this one.
    pub fn as_host_device(&self) -> Option<HostDevice> {
        let submission = self.submission?;
        let info = &self.info;
        let features = enabled_features(info);
        let mut extensions = Vec::new();
        // Enabled when the device was made; passed on where the probe found it sound.
        if info.full_subgroups {
            extensions.push(ash::ext::subgroup_size_control::NAME.to_owned());
        }
        Some(HostDevice {
            get_instance_proc_addr: self._entry.static_fn().get_instance_proc_addr,
            instance: self.instance.handle(),
            physical_device: self.physical,
            device: self.device.handle(),
            queue_family: submission.family,
            api_version: INSTANCE_API_VERSION,
            features,
            extensions,
            // The profile this device was made with (forced or its own).
            profile: Some(self.info.profile),
            subgroup_size_control: info.full_subgroups,
            software_sampling: self.info.software_sampling,
            memory_budget: self.memory_budget,
            allocation_callbacks: self.allocation_callbacks,
        })
    }

    /// Wraps the engine's instance and device (host-device mode, already checked against
    /// the requirements by the caller) with an allocator of translucid's own. Nothing of the
    /// engine's is destroyed when the last clone drops.
    pub(super) fn wrap_host(
        entry: ash::Entry,
        instance: ash::Instance,
        device: ash::Device,
        physical: vk::PhysicalDevice,
        info: DeviceInfo,
        memory_budget: Option<u64>,
        allocation_callbacks: Option<super::host::AllocationCallbacks>,
    ) -> Result<Self> {
        let allocator = create_allocator(&instance, &device, physical, memory_budget)?;
        Ok(Self(Arc::new(Shared {
            _entry: entry,
            instance,
            physical,
            messenger: None,
            validation: Box::default(),
            device,
            submission: None,
            owns_device: false,
            allocator: ManuallyDrop::new(Mutex::new(allocator)),
            memory: MemoryStats::default(),
            memory_budget,
            allocation_callbacks,
            pipelines_created: AtomicU64::new(0),
            dispatches_recorded: AtomicU64::new(0),
            pipeline_cache: OnceLock::new(),
            pipeline_cache_lock: RwLock::new(()),
            compute_pipelines: Default::default(),
            graphics_pipelines: Default::default(),
            render_passes: Default::default(),
            submitting: Mutex::new(()),
            info,
        })))
    }
}

impl Shared {
    /// What every Vulkan object made on the device is created and destroyed with: the
    /// engine's allocation callbacks on its device, if it gave them.
    pub(crate) fn callbacks(&self) -> Option<&vk::AllocationCallbacks<'static>> {
        self.allocation_callbacks.as_ref().map(|c| &c.0)
    }

    /// Runs `create` with the device's pipeline cache, as pipeline creation may: while no
    /// merge into it runs.
    pub(crate) fn with_pipeline_cache<T>(&self, create: impl FnOnce(vk::PipelineCache) -> T) -> T {
        let cache = self.pipeline_cache();
        let _shared = self
            .pipeline_cache_lock
            .read()
            .unwrap_or_else(std::sync::PoisonError::into_inner);
        create(cache)
    }

    /// The device's pipeline cache, made on first use (null, caching nothing, if the driver
    /// cannot make one).
    fn pipeline_cache(&self) -> vk::PipelineCache {
        *self.pipeline_cache.get_or_init(|| {
            // SAFETY: valid device and create info.
            unsafe {
                self.device.create_pipeline_cache(
                    &vk::PipelineCacheCreateInfo::default(),
                    self.callbacks(),
                )
            }
            .unwrap_or_else(|e| {
                log::warn!("vkCreatePipelineCache failed ({e}); pipelines are not cached");
                vk::PipelineCache::null()
            })
        })
    }

    /// The pipeline cache's contents, for the engine to save and give back to
    /// [`Self::merge_pipeline_cache`] on its next run, so that its first frames skip shader
    /// compilation the driver has cached.
    pub fn pipeline_cache_data(&self) -> Result<Vec<u8>> {
        let cache = self.pipeline_cache();
        if cache == vk::PipelineCache::null() {
            return Ok(Vec::new());
        }
        // SAFETY: a live cache of this device.
        unsafe { self.device.get_pipeline_cache_data(cache) }
            .map_err(super::error::vk_err("vkGetPipelineCacheData"))
    }

    /// Adds what `data` (from [`Self::pipeline_cache_data`], maybe of another run) holds to
    /// the device's pipeline cache. False, changing nothing, when the data was made by
    /// another driver or device (its header says which), or is too short to say.
    pub fn merge_pipeline_cache(&self, data: &[u8]) -> Result<bool> {
        if !self.cache_data_fits(data) {
            return Ok(false);
        }
        let cache = self.pipeline_cache();
        if cache == vk::PipelineCache::null() {
            return Ok(false);
        }
        let info = vk::PipelineCacheCreateInfo::default().initial_data(data);
        // SAFETY: valid device; the data's header names this device (checked above).
        let loaded = unsafe { self.device.create_pipeline_cache(&info, self.callbacks()) }
            .map_err(super::error::vk_err("vkCreatePipelineCache"))?;
        let _exclusive = self
            .pipeline_cache_lock
            .write()
            .unwrap_or_else(std::sync::PoisonError::into_inner);
        // SAFETY: both caches are live and of this device, the destination held exclusively
        // (the lock above); `loaded` is destroyed once merged.
        let merged = unsafe {
            let merged = self.device.merge_pipeline_caches(cache, &[loaded]);
            self.device.destroy_pipeline_cache(loaded, self.callbacks());
            merged
        };
        merged.map_err(super::error::vk_err("vkMergePipelineCaches"))?;
        Ok(true)
    }

    /// Whether pipeline cache `data` starts with a version-one header naming this device's
    /// vendor, device and pipeline cache UUID.
    fn cache_data_fits(&self, data: &[u8]) -> bool {
        // SAFETY: a live physical device of this instance.
        let properties = unsafe { self.instance.get_physical_device_properties(self.physical) };
        let word = |at: usize| {
            data.get(at..at + 4)
                .map(|b| u32::from_le_bytes([b[0], b[1], b[2], b[3]]))
        };
        word(0).is_some_and(|size| size >= 32)
            && word(4) == Some(vk::PipelineCacheHeaderVersion::ONE.as_raw() as u32)
            && word(8) == Some(properties.vendor_id)
            && word(12) == Some(properties.device_id)
            && data.get(16..32) == Some(&properties.pipeline_cache_uuid[..])
    }

    /// Whether this is the engine's device (host-device mode): translucid records into the
    /// engine's command buffers and never submits.
    pub fn is_host_device(&self) -> bool {
        self.submission.is_none()
    }

    pub(crate) fn instance(&self) -> &ash::Instance {
        &self.instance
    }

    pub(crate) fn physical_device(&self) -> vk::PhysicalDevice {
        self.physical
    }

    /// Limits and identity of the chosen device.
    pub fn info(&self) -> &DeviceInfo {
        &self.info
    }

    /// The profile this device was made with: its own, or the one forced
    /// ([`GpuOptions::profile`], `TRANSLUCID_PROFILE`).
    pub fn profile(&self) -> Profile {
        self.info.profile
    }

    /// Fails with every validation error reported since the last check.
    pub fn check_validation(&self) -> Result<()> {
        let errors = self.validation.take();
        if errors.is_empty() {
            Ok(())
        } else {
            Err(Error::Validation(errors.join("\n")))
        }
    }

    /// Bytes of GPU memory currently allocated through this device, and the peak since the
    /// last [`Gpu::reset_peak_memory`].
    pub fn memory_in_use(&self) -> (u64, u64) {
        self.memory.current_and_peak()
    }

    /// The most bytes of GPU memory allocations on this device may hold (`None`: no limit):
    /// an allocation past it fails with [`Error::MemoryBudget`].
    pub fn memory_budget(&self) -> Option<u64> {
        self.memory_budget
    }

    /// Bytes of GPU memory allocated on this device so far, freed or not: a frame loop's
    /// figure stops growing once its buffers have reached their size.
    pub fn bytes_allocated(&self) -> u64 {
        self.memory.total()
    }

    pub fn reset_peak_memory(&self) {
        self.memory.reset_peak();
    }

    /// Holds every pipeline alive on the device now, so that renderers made after the ones
    /// holding them are gone still find them (a context's trim keeps them so).
    pub fn hold_pipelines(&self) -> HeldPipelines {
        HeldPipelines {
            _compute: self.compute_pipelines.live(),
            _graphics: self.graphics_pipelines.live(),
        }
    }

    /// Pipelines created on this device so far (compute and graphics).
    pub fn pipelines_created(&self) -> u64 {
        self.pipelines_created.load(Ordering::Relaxed)
    }

    pub(crate) fn count_pipeline(&self) {
        if !super::background::count_background_pipeline() {
            self.pipelines_created.fetch_add(1, Ordering::Relaxed);
        }
    }

    /// Compute dispatches recorded on this device so far: what a frame records is the
    /// difference across its recording (other threads recording on the device add theirs).
    pub fn dispatches_recorded(&self) -> u64 {
        self.dispatches_recorded.load(Ordering::Relaxed)
    }

    pub(crate) fn count_dispatch(&self) {
        self.dispatches_recorded.fetch_add(1, Ordering::Relaxed);
    }
}

fn create_messenger(
    entry: &ash::Entry,
    instance: &ash::Instance,
    log: &ValidationLog,
) -> Result<(ash::ext::debug_utils::Instance, vk::DebugUtilsMessengerEXT)> {
    let loader = ash::ext::debug_utils::Instance::new(entry, instance);
    let info = vk::DebugUtilsMessengerCreateInfoEXT::default()
        .message_severity(
            vk::DebugUtilsMessageSeverityFlagsEXT::ERROR
                | vk::DebugUtilsMessageSeverityFlagsEXT::WARNING,
        )
        .message_type(
            vk::DebugUtilsMessageTypeFlagsEXT::VALIDATION
                | vk::DebugUtilsMessageTypeFlagsEXT::GENERAL
                | vk::DebugUtilsMessageTypeFlagsEXT::PERFORMANCE,
        )
        .pfn_user_callback(Some(validation::callback))
        .user_data(log as *const ValidationLog as *mut _);
    // SAFETY: the log outlives the messenger (Gpu drops the messenger before the box).
    let messenger = unsafe { loader.create_debug_utils_messenger(&info, None) }
        .map_err(vk_err("vkCreateDebugUtilsMessengerEXT"))?;
    Ok((loader, messenger))
}

fn destroy_instance(
    instance: &ash::Instance,
    messenger: &Option<(ash::ext::debug_utils::Instance, vk::DebugUtilsMessengerEXT)>,
) {
    // SAFETY: called only on creation failure, when no device exists.
    unsafe {
        if let Some((loader, m)) = messenger {
            loader.destroy_debug_utils_messenger(*m, None);
        }
        instance.destroy_instance(None);
    }
}

/// The allocator of a device whose allocations hold at most `memory_budget` bytes: within a
/// budget it reserves device memory in the smallest blocks (4 MB) it makes, so that what it
/// reserves passes what is allocated by at most a block per memory type.
fn create_allocator(
    instance: &ash::Instance,
    device: &ash::Device,
    physical: vk::PhysicalDevice,
    memory_budget: Option<u64>,
) -> Result<Allocator> {
    const SMALLEST_BLOCK: u64 = 4 << 20;
    let allocation_sizes = match memory_budget {
        Some(_) => gpu_allocator::AllocationSizes::new(SMALLEST_BLOCK, SMALLEST_BLOCK),
        None => Default::default(),
    };
    Allocator::new(&AllocatorCreateDesc {
        instance: instance.clone(),
        device: device.clone(),
        physical_device: physical,
        debug_settings: Default::default(),
        buffer_device_address: false,
        allocation_sizes,
    })
    .map_err(|source| crate::Error::Allocation {
        object: "the memory allocator".into(),
        source,
    })
}

type DeviceParts = (ash::Device, Allocator, Submission);

/// Whether `TRANSLUCID_BIN_TILES` asks for tiles of one row (`row`) rather than the device's
/// (`subgroup`, or unset).
pub(super) fn row_tiles_forced() -> Result<bool> {
    super::profile::forced_by_env("TRANSLUCID_BIN_TILES", "row", "subgroup")
}

/// Whether `TRANSLUCID_SAMPLING` asks for the software sampler (`software`) rather than the
/// device's choice (`device`, or unset).
pub fn software_sampling_asked() -> Result<bool> {
    super::profile::forced_by_env("TRANSLUCID_SAMPLING", "software", "device")
}

/// The features translucid enables on a device it makes: the optional ones where present
/// (methods that need one check DeviceInfo).
fn enabled_features(info: &DeviceInfo) -> vk::PhysicalDeviceFeatures {
    vk::PhysicalDeviceFeatures::default()
        .dual_src_blend(info.dual_source_blend)
        .shader_int64(info.shader_int64)
        .fragment_stores_and_atomics(info.fragment_stores_and_atomics)
        .geometry_shader(info.geometry_shader)
        .independent_blend(info.independent_blend)
}

fn create_device(
    instance: &ash::Instance,
    physical: vk::PhysicalDevice,
    info: &DeviceInfo,
    memory_budget: Option<u64>,
) -> Result<DeviceParts> {
    // SAFETY: physical came from this instance.
    let families = unsafe { instance.get_physical_device_queue_family_properties(physical) };
    let wanted = vk::QueueFlags::GRAPHICS | vk::QueueFlags::COMPUTE;
    let family = families
        .iter()
        .position(|f| f.queue_flags.contains(wanted) && f.timestamp_valid_bits > 0)
        .or_else(|| families.iter().position(|f| f.queue_flags.contains(wanted)))
        .ok_or_else(|| Error::NoDevice(format!("{} has no graphics+compute queue", info.name)))?
        as u32;
    let priorities = [1.0f32];
    let queues = [vk::DeviceQueueCreateInfo::default()
        .queue_family_index(family)
        .queue_priorities(&priorities)];
    let features = enabled_features(info);
    let mut size_control = vk::PhysicalDeviceSubgroupSizeControlFeatures::default()
        .subgroup_size_control(true)
        .compute_full_subgroups(true);
    let mut extension_names = Vec::new();
    let mut create = vk::DeviceCreateInfo::default()
        .queue_create_infos(&queues)
        .enabled_features(&features);
    if info.full_subgroups {
        extension_names.push(ash::ext::subgroup_size_control::NAME.as_ptr());
        create = create.push_next(&mut size_control);
    }
    let create = create.enabled_extension_names(&extension_names);
    // SAFETY: create info and its pointees live until the call returns.
    let device = unsafe { instance.create_device(physical, &create, None) }
        .map_err(vk_err("vkCreateDevice"))?;
    // SAFETY: family/index 0 were requested above.
    let queue = unsafe { device.get_device_queue(family, 0) };
    let allocator = match create_allocator(instance, &device, physical, memory_budget) {
        Ok(a) => a,
        Err(e) => {
            // SAFETY: nothing was created from the device yet.
            unsafe { device.destroy_device(None) };
            return Err(e);
        }
    };
    let pool_info = vk::CommandPoolCreateInfo::default()
        .queue_family_index(family)
        .flags(vk::CommandPoolCreateFlags::RESET_COMMAND_BUFFER);
    // SAFETY: valid device and create info.
    let pool = match unsafe { device.create_command_pool(&pool_info, None) } {
        Ok(p) => p,
        Err(e) => {
            drop(allocator);
            // SAFETY: the allocator holding device memory is gone; nothing else exists.
            unsafe { device.destroy_device(None) };
            return Err(vk_err("vkCreateCommandPool")(e));
        }
    };
    let parts = create_submission_objects(&device, pool);
    match parts {
        Ok((command_buffer, fence)) => Ok((
            device,
            allocator,
            Submission {
                family,
                queue,
                command_pool: pool,
                command_buffer,
                fence,
            },
        )),
        Err(e) => {
            drop(allocator);
            // SAFETY: the pool (and any buffer from it) is unused; nothing else exists.
            unsafe {
                device.destroy_command_pool(pool, None);
                device.destroy_device(None);
            }
            Err(e)
        }
    }
}

/// The command buffer and the fence every submission reuses.
fn create_submission_objects(
    device: &ash::Device,
    pool: vk::CommandPool,
) -> Result<(vk::CommandBuffer, vk::Fence)> {
    let alloc = vk::CommandBufferAllocateInfo::default()
        .command_pool(pool)
        .level(vk::CommandBufferLevel::PRIMARY)
        .command_buffer_count(1);
    // SAFETY: the pool belongs to this device and nothing else uses it yet.
    let command_buffer = unsafe { device.allocate_command_buffers(&alloc) }
        .map_err(vk_err("vkAllocateCommandBuffers"))?[0];
    // SAFETY: valid device; the fence is destroyed with the device (Drop for Shared).
    let fence = unsafe { device.create_fence(&vk::FenceCreateInfo::default(), None) }
        .map_err(vk_err("vkCreateFence"))?;
    Ok((command_buffer, fence))
}

impl Drop for Shared {
    fn drop(&mut self) {
        if let Some(&cache) = self.pipeline_cache.get() {
            // SAFETY: every pipeline made through the cache has been created (creation is
            // synchronous); the cache is ours on either kind of device.
            unsafe { self.device.destroy_pipeline_cache(cache, self.callbacks()) };
        }
        let (live, _) = self.memory.current_and_peak();
        if live != 0 {
            log::warn!("device destroyed with {live} bytes of GPU memory still allocated");
        }
        let Some(submission) = self.submission.filter(|_| self.owns_device) else {
            // The engine's device: the engine guarantees (host-device contract) that the GPU
            // no longer uses anything of ours; only our memory is ours to free.
            // SAFETY: the allocator is dropped exactly once, here.
            unsafe { ManuallyDrop::drop(&mut self.allocator) };
            return;
        };
        // SAFETY: we own every object below; waiting for idle first means none is in use, and
        // they are destroyed in reverse creation order. The allocator is dropped exactly once.
        unsafe {
            let _ = self.device.device_wait_idle();
            self.device.destroy_fence(submission.fence, None);
            self.device
                .destroy_command_pool(submission.command_pool, None);
            ManuallyDrop::drop(&mut self.allocator);
            self.device.destroy_device(None);
            if let Some((loader, m)) = self.messenger.take() {
                loader.destroy_debug_utils_messenger(m, None);
            }
            self.instance.destroy_instance(None);
        }
    }
}

/// Pipelines kept alive by [`Gpu::hold_pipelines`].
pub struct HeldPipelines {
    _compute: Vec<Arc<super::ComputePipeline>>,
    _graphics: Vec<Arc<super::GraphicsPipeline>>,
}
