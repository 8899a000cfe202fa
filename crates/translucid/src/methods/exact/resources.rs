//! The exact method's buffers: sized from the frame, grown when the GPU reports an overflow.

use super::layout::{
    ExactCounters, ExactDraw, ExactTexture, HOMOGENEOUS_BYTES, OVERFLOW_BIN_ENTRIES,
    OVERFLOW_HOMOGENEOUS, TRIANGLE_BYTES,
};
use crate::gpu::{
    memory_barrier, vk, BindingKind, Buffer, DescriptorLayout, DescriptorSet, Gpu, MemoryLocation,
    Resource, Sampler,
};
use crate::methods::MethodOptions;
use crate::renderer::{FrameTargets, GpuScene};
use crate::scene::{srgb_lut, Scene};
use crate::{Error, Result};

/// Entries the growable buffers hold.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Capacities {
    /// Two per quad: setup can never write more.
    pub triangles: u32,
    pub homogeneous: u32,
    pub bin_entries: u32,
}

impl Capacities {
    /// A first guess from the frame: every quad's two triangles, each touching a few bins.
    /// Overflow corrects it after one frame.
    pub fn initial(quads: u32, bins: u32, options: &MethodOptions) -> Self {
        let triangles = quads.saturating_mul(2).max(1);
        Self {
            triangles,
            homogeneous: options
                .initial_homogeneous
                .unwrap_or((triangles / 64).max(64))
                .max(1),
            bin_entries: options
                .initial_bin_entries
                .unwrap_or(triangles.saturating_mul(4).max(bins))
                .max(1),
        }
    }

    /// Larger capacities when the frame overflowed, from what the GPU counted.
    pub fn grown_for(&self, c: &ExactCounters) -> Option<Self> {
        if c.overflow & (OVERFLOW_HOMOGENEOUS | OVERFLOW_BIN_ENTRIES) == 0 {
            return None;
        }
        let with_headroom =
            |needed: u32, now: u32| needed.saturating_add(needed / 4).max(now.saturating_mul(2));
        let mut next = *self;
        if c.overflow & OVERFLOW_HOMOGENEOUS != 0 {
            next.homogeneous = with_headroom(c.homogeneous_count, self.homogeneous);
        }
        if c.overflow & OVERFLOW_BIN_ENTRIES != 0 {
            next.bin_entries = with_headroom(c.bin_entry_count, self.bin_entries);
        }
        Some(next)
    }
}

/// Buffers that grow.
struct Growable {
    triangles: Buffer,
    homogeneous: Buffer,
    bin_entries: Buffer,
}

pub struct Resources {
    pub capacities: Capacities,
    pub layout: DescriptorLayout,
    draws: Buffer,
    counters: Buffer,
    bin_counts: Buffer,
    bin_offsets: Buffer,
    bin_cursors: Buffer,
    textures: Buffer,
    texels: Buffer,
    srgb: Buffer,
    depth_sampler: Sampler,
    growable: Growable,
}

const STORAGE: vk::BufferUsageFlags = vk::BufferUsageFlags::STORAGE_BUFFER;

fn storage_buffer(gpu: &Gpu, name: &str, bytes: u64) -> Result<Buffer> {
    let limit = u64::from(gpu.info().max_storage_buffer_range);
    if bytes > limit {
        return Err(Error::InvalidScene(format!(
            "exact: the {name} need {} MB, over this device's {} MB storage-buffer limit",
            bytes >> 20,
            limit >> 20
        )));
    }
    gpu.create_buffer(
        name,
        bytes,
        STORAGE | vk::BufferUsageFlags::TRANSFER_DST,
        MemoryLocation::GpuOnly,
    )
}

fn growable(gpu: &Gpu, c: Capacities) -> Result<Growable> {
    Ok(Growable {
        triangles: storage_buffer(
            gpu,
            "triangle records",
            u64::from(c.triangles) * TRIANGLE_BYTES,
        )?,
        homogeneous: storage_buffer(
            gpu,
            "homogeneous records",
            u64::from(c.homogeneous) * HOMOGENEOUS_BYTES,
        )?,
        bin_entries: storage_buffer(gpu, "bin lists", u64::from(c.bin_entries) * 4)?,
    })
}

/// The transparent draws in the order the reference ranks them, with their model-view-
/// projection computed on the host exactly as the reference does.
fn exact_draws(scene: &Scene, width: u32, height: u32) -> Vec<ExactDraw> {
    let view_projection = scene.camera.view_projection(width as f32 / height as f32);
    let mut first_quad_of_mesh = Vec::with_capacity(scene.meshes.len());
    let mut total = 0u32;
    for mesh in &scene.meshes {
        first_quad_of_mesh.push(total);
        total += mesh.quads.len() as u32;
    }
    let mut first_item = 0u32;
    scene
        .transparent
        .iter()
        .enumerate()
        .map(|(i, d)| {
            let quad_count = scene.meshes[d.mesh].quads.len() as u32;
            let draw = ExactDraw {
                mvp: (view_projection * d.transform).to_cols_array(),
                draw_index: (scene.opaque.len() + i) as u32,
                first_item,
                quad_count,
                first_quad: first_quad_of_mesh[d.mesh],
            };
            first_item += quad_count;
            draw
        })
        .collect()
}

/// Texture descriptors and every level's texels, packed RGBA8, for the software sampler.
fn texture_data(scene: &Scene) -> (Vec<ExactTexture>, Vec<u32>) {
    let mut infos = Vec::with_capacity(scene.textures.len());
    let mut texels = Vec::new();
    for t in &scene.textures {
        infos.push(ExactTexture {
            first_texel: texels.len() as u32,
            width: t.width(),
            height: t.height(),
            levels: t.levels.len() as u32,
            srgb: u32::from(t.srgb),
            pad: [0; 3],
        });
        for level in &t.levels {
            texels.extend(level.texels.iter().map(|&t| u32::from_le_bytes(t)));
        }
    }
    (infos, texels)
}

impl Resources {
    pub fn new(
        gpu: &Gpu,
        scene: &Scene,
        width: u32,
        height: u32,
        capacities: Capacities,
    ) -> Result<Self> {
        let bins = u64::from(width.div_ceil(super::BIN_SIZE))
            * u64::from(height.div_ceil(super::BIN_SIZE));
        let draws = exact_draws(scene, width, height);
        let (texture_infos, texels) = texture_data(scene);
        let texel_bytes = texels.len() as u64 * 4;
        if texel_bytes > u64::from(gpu.info().max_storage_buffer_range) {
            return Err(Error::InvalidScene(format!(
                "exact: the scene's textures take {} MB, over this device's {} MB storage-buffer limit",
                texel_bytes >> 20,
                gpu.info().max_storage_buffer_range >> 20
            )));
        }
        let counters = gpu.create_buffer(
            "exact counters",
            std::mem::size_of::<ExactCounters>() as u64,
            STORAGE | vk::BufferUsageFlags::TRANSFER_DST,
            MemoryLocation::GpuToCpu,
        )?;
        let layout = DescriptorLayout::new(
            gpu,
            &[
                BindingKind::StorageBuffer,    // 0 vertices
                BindingKind::StorageBuffer,    // 1 quads
                BindingKind::StorageBuffer,    // 2 exact draws
                BindingKind::StorageBuffer,    // 3 triangles
                BindingKind::StorageBuffer,    // 4 homogeneous
                BindingKind::StorageBuffer,    // 5 counters
                BindingKind::StorageBuffer,    // 6 bin counts
                BindingKind::StorageBuffer,    // 7 bin offsets
                BindingKind::StorageBuffer,    // 8 bin cursors
                BindingKind::StorageBuffer,    // 9 bin entries
                BindingKind::StorageBuffer,    // 10 textures
                BindingKind::StorageBuffer,    // 11 texels
                BindingKind::StorageBuffer,    // 12 sRGB table
                BindingKind::SampledImages(1), // 13 opaque depth
                BindingKind::StorageImage,     // 14 colour
            ],
            vk::ShaderStageFlags::COMPUTE,
        )?;
        Ok(Self {
            capacities,
            layout,
            draws: gpu.create_buffer_with_data(
                "exact draws",
                STORAGE,
                bytemuck::cast_slice(&draws),
            )?,
            counters,
            bin_counts: storage_buffer(gpu, "bin counts", bins * 4)?,
            bin_offsets: storage_buffer(gpu, "bin offsets", bins * 4)?,
            bin_cursors: storage_buffer(gpu, "bin cursors", bins * 4)?,
            textures: gpu.create_buffer_with_data(
                "exact textures",
                STORAGE,
                bytemuck::cast_slice(&texture_infos),
            )?,
            texels: gpu.create_buffer_with_data(
                "exact texels",
                STORAGE,
                bytemuck::cast_slice(&texels),
            )?,
            srgb: gpu.create_buffer_with_data(
                "sRGB table",
                STORAGE,
                bytemuck::cast_slice(srgb_lut()),
            )?,
            depth_sampler: Sampler::nearest_clamp(gpu)?,
            growable: growable(gpu, capacities)?,
        })
    }

    pub fn descriptor_set(
        &self,
        uploaded: &GpuScene,
        targets: &FrameTargets,
    ) -> Result<DescriptorSet> {
        let g = &self.growable;
        self.layout.create_set(&[
            Resource::Buffer(&uploaded.vertices),
            Resource::Buffer(&uploaded.quads),
            Resource::Buffer(&self.draws),
            Resource::Buffer(&g.triangles),
            Resource::Buffer(&g.homogeneous),
            Resource::Buffer(&self.counters),
            Resource::Buffer(&self.bin_counts),
            Resource::Buffer(&self.bin_offsets),
            Resource::Buffer(&self.bin_cursors),
            Resource::Buffer(&g.bin_entries),
            Resource::Buffer(&self.textures),
            Resource::Buffer(&self.texels),
            Resource::Buffer(&self.srgb),
            Resource::Images(&[targets.depth.view], self.depth_sampler.raw),
            Resource::StorageImage(targets.colour.view),
        ])
    }

    /// Zeroes the counters and bin counts and writes the capacities, before setup.
    pub fn record_reset(&self, cmd: vk::CommandBuffer) {
        let gpu = self.counters.gpu();
        let capacities = [
            self.capacities.triangles,
            self.capacities.homogeneous,
            self.capacities.bin_entries,
        ];
        gpu.cmd_fill_buffer(cmd, &self.counters, 0);
        gpu.cmd_update_buffer(cmd, &self.counters, 16, bytemuck::cast_slice(&capacities));
        gpu.cmd_fill_buffer(cmd, &self.bin_counts, 0);
        gpu.cmd_fill_buffer(cmd, &self.bin_cursors, 0);
        memory_barrier(
            gpu,
            cmd,
            (
                vk::PipelineStageFlags::TRANSFER,
                vk::AccessFlags::TRANSFER_WRITE,
            ),
            (
                vk::PipelineStageFlags::COMPUTE_SHADER,
                vk::AccessFlags::SHADER_READ | vk::AccessFlags::SHADER_WRITE,
            ),
        );
    }

    /// The counters of the last completed frame.
    pub fn counters(&self) -> Result<ExactCounters> {
        Ok(bytemuck::pod_read_unaligned(
            &self.counters.read()?[..std::mem::size_of::<ExactCounters>()],
        ))
    }

    pub fn grow(&mut self, gpu: &Gpu, capacities: Capacities) -> Result<()> {
        self.growable = growable(gpu, capacities)?;
        self.capacities = capacities;
        Ok(())
    }
}
