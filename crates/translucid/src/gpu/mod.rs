//! Vulkan through `ash`: the only module that talks to the driver.
//!
//! - [`Gpu`] (`device.rs`) owns the instance, the device, one queue, the allocator and a
//!   command pool; it picks discrete > integrated > CPU devices unless `TRANSLUCID_DEVICE`
//!   names one, and with `TRANSLUCID_VALIDATION=1` turns on the Khronos validation layer and
//!   fails every submission that produced a validation error (`validation.rs`).
//! - `memory.rs`: buffers and images from `gpu-allocator`, with a running count of live bytes
//!   and its peak so a frame can report its GPU memory, and a list of the live allocations
//!   with their memory and role (per-frame data, staging); `append.rs`: device-local buffers
//!   that grow by appending, shared by the versions of a context's assets; `staging.rs`:
//!   uploads into device-local memory (staged copies), run at once on translucid's own
//!   device and carried by the next frame on the engine's.
//! - `commands.rs`: one-shot command buffers (record, submit, wait) and barrier helpers.
//! - `pipeline.rs`: shader modules from build.rs's SPIR-V, descriptor layouts, pipelines.
//! - `attachments.rs`: render passes over a method's own sets of attachments.
//! - `timestamps.rs`: GPU timestamps around every stage.
//! - `background.rs`: work on a worker thread (preparation) counted apart from the frames'.
//! - `host.rs`: host-device mode: the engine's device wrapped without being owned, and the
//!   copies between the engine's images and the frame targets.
//!
//! Synchronisation is deliberately simple: every frame is recorded into one command buffer,
//! submitted, and waited for with a fence. Readback copies into host-visible buffers. On the
//! engine's device the engine submits and waits instead, and tells translucid when the frame
//! completed.

mod append;
mod attachments;
mod background;
mod commands;
mod device;
mod engine_images;
mod engine_pass;
mod error;
mod host;
mod host_depth;
mod memory;
mod pipeline;
mod pipeline_cache;
mod profile;
mod retirement;
#[cfg(test)]
mod rounded_division_tests;
#[cfg(test)]
mod spirv_checks;
mod staging;
mod subgroup_probe;
mod timestamps;
mod validation;

pub use append::AppendBuffer;
pub use ash::vk;
pub use attachments::{fullscreen_pipeline, Attachment, AttachmentPass, DepthAttachment, Load};
pub use background::in_background;
pub use commands::{
    image_barrier, memory_barrier, mip_region, whole_image_region, Scope, ANY_ACCESS,
    COMPUTE_WRITE, HOST_READ, TRANSFER_WRITE,
};
pub use device::{
    list_devices, software_sampling_asked, DeviceInfo, Gpu, GpuOptions, HeldPipelines, Shared,
    CPU_DRIVER_LOOP_BUDGET, GPU_LOOP_BUDGET,
};
pub use engine_images::{EngineImages, ENGINE_COLOUR_FORMAT};
pub use engine_pass::{EngineDepthViews, EnginePass};
pub use host::{
    host_requirements, host_requirements_with, AllocationCallbacks, HostDevice, HostImage,
    HostRequirements, HostTargets, OptionalFeature, SubgroupRequirements, HOST_API_VERSION,
    HOST_DEPTH_FORMAT, HOST_DEPTH_FORMATS, SUBGROUP_REQUIREMENTS,
};
pub use host_depth::DepthImport;
pub use memory::MemoryLocation;
pub use memory::{
    AllocationInfo, AllocationUsage, Buffer, BufferView, GpuImage, MemoryRole, MemoryStats,
    ViewedBuffer,
};
pub use pipeline::{
    BindingKind, Blend, ComputePipeline, DepthMode, DescriptorLayout, DescriptorSet,
    GraphicsPipeline, GraphicsPipelineDesc, PipelineState, RenderTarget, RenderTargetDesc,
    Resource, Sampler,
};
pub use pipeline_cache::ComputePipelineCache;
pub use profile::{forced_by_env, Profile};
pub use retirement::Retirement;
pub use staging::{Upload, Uploads};
pub use timestamps::Timestamps;

/// SPIR-V bytes compiled by build.rs from `shaders/<folder>/<file>`.
#[macro_export]
macro_rules! spirv {
    ($path:literal) => {
        include_bytes!(concat!(env!("OUT_DIR"), "/shaders/", $path, ".spv"))
    };
}
