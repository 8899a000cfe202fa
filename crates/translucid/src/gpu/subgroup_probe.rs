//! Whether a device's compute subgroups really hold `subgroup_size` lanes when a pipeline is
//! held to whole subgroups of that size. Lavapipe reports 32 and 64 lanes at
//! `LP_NATIVE_VECTOR_WIDTH` 1024 and 2048 (its vector width over 32 bits) but runs compute
//! shaders 16 lanes at a time, full-subgroup flag or not: a tile sized for the reported
//! subgroup would be split between two, which then disagree on what they vote. Checked
//! once, on the devices translucid makes, by one workgroup of `subgroup_size` invocations.

use super::{vk, BindingKind, ComputePipeline, DescriptorLayout, Gpu, MemoryLocation, Resource};
use crate::interface::specialization::{Specialization, RASTER_GROUP_SIZE};
use crate::Result;

/// The fewest lanes a subgroup held in one workgroup of the device's subgroup size, run as
/// the rasters' pipelines are (`gpu::pipeline` holds it to whole subgroups).
pub(super) fn lanes_per_subgroup(gpu: &Gpu) -> Result<u32> {
    let size = gpu.info().subgroup_size;
    let storage = vk::BufferUsageFlags::STORAGE_BUFFER;
    let mut probe = gpu.create_buffer("subgroup probe", 4, storage, MemoryLocation::GpuToCpu)?;
    probe.write(0, &u32::MAX.to_ne_bytes())?;
    let layout = DescriptorLayout::new(
        gpu,
        &[BindingKind::StorageBuffer],
        vk::ShaderStageFlags::COMPUTE,
    )?;
    let set = layout.create_set(&[Resource::Buffer(&probe)])?;
    let pipeline = ComputePipeline::specialized(
        gpu,
        crate::spirv!("gpu/subgroup_probe.comp"),
        &[&layout],
        0,
        &Specialization::new().with(RASTER_GROUP_SIZE, size),
    )?;
    pipeline.dispatch_and_wait(&[set.raw], &[], [1, 1, 1])?;
    let bytes = probe.read()?;
    let lanes = u32::from_ne_bytes(bytes[..4].try_into().expect("four bytes"));
    Ok(lanes)
}
