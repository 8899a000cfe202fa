//! A scene's assets on the GPU (`resident`: uploaded once, shared by the renderers made over
//! them) and, per frame slot, the frame info and draws with the descriptor set every mesh
//! pipeline binds as set 0.

#![deny(unsafe_code)]

mod resident;
mod sampled;
#[cfg(test)]
mod sampling_tests;
pub mod texture_array;
pub mod texture_records;

pub use resident::ResidentAssets;
pub use sampled::SampledViews;

use crate::gpu::{
    vk, Buffer, DepthMode, DescriptorLayout, DescriptorSet, Gpu, GpuImage, GraphicsPipeline,
    GraphicsPipelineDesc, MemoryLocation, PipelineState, Resource, Upload,
};
use crate::interface::scene::SCENE_SET;
use crate::interface::specialization::Specialization;
use crate::scene::{Scene, Texture};
use crate::shader_types::{GpuDrawInfo, GpuFrameInfo, GpuVertex};
use crate::Result;
use std::collections::VecDeque;
use std::sync::atomic::{AtomicU64, Ordering};
use std::sync::Arc;

/// Vertex attributes of [`GpuVertex`]: (location, format, offset).
pub const VERTEX_ATTRIBUTES: [(u32, vk::Format, u32); 4] = [
    (0, vk::Format::R32G32B32_SFLOAT, 0),
    (1, vk::Format::R32G32B32_SFLOAT, 12),
    (2, vk::Format::R32G32_SFLOAT, 24),
    (3, vk::Format::R32G32B32A32_SFLOAT, 32),
];
/// The same without the normal, which `MeshStages::OrderUnlit` does not read.
const UNLIT_ATTRIBUTES: [(u32, vk::Format, u32); 3] = [
    VERTEX_ATTRIBUTES[0],
    VERTEX_ATTRIBUTES[2],
    VERTEX_ATTRIBUTES[3],
];
pub const VERTEX_STRIDE: u32 = std::mem::size_of::<GpuVertex>() as u32;

/// Usage of the scene's buffers: compute methods read them through texel views as well.
const SCENE_STORAGE: vk::BufferUsageFlags = vk::BufferUsageFlags::from_raw(
    vk::BufferUsageFlags::STORAGE_BUFFER.as_raw()
        | vk::BufferUsageFlags::UNIFORM_TEXEL_BUFFER.as_raw(),
);

/// Where one mesh's triangles start in the index buffer.
#[derive(Clone, Copy, Debug)]
pub struct MeshRange {
    pub first_index: u32,
    pub index_count: u32,
    pub vertex_offset: i32,
}

/// One draw as the mesh pipelines issue it.
#[derive(Clone, Copy, Debug)]
pub struct DrawCall {
    /// Index into the draw-info buffer (pushed as a constant).
    pub draw_index: u32,
    pub range: MeshRange,
    pub cull_back: bool,
    /// Index into `ResidentAssets::texture_sets` (the last one is a white texture).
    pub texture_set: usize,
}

/// One frame slot's share of the scene: the frame info and draws a frame in flight reads
/// while the next frames are written into other slots, and set 0 over them.
struct SceneSlot {
    frame: Buffer,
    draws: Buffer,
    set: DescriptorSet,
    /// Moved vertices on their way to the vertex buffer (made on the first move).
    staging: Option<Buffer>,
    /// The texture array of the assets the slot's frame draws from, kept until the slot is
    /// written again (its frame has completed), though the assets move on to a new version.
    texture_array: Option<Arc<texture_array::TextureArray>>,
}

impl SceneSlot {
    fn new(
        gpu: &Gpu,
        layout: &DescriptorLayout,
        materials: &Buffer,
        draw_bytes: u64,
    ) -> Result<Self> {
        // Per-frame data: written by the host into the slot before each frame recorded in it.
        let frame = gpu.create_per_frame_buffer(
            "frame info",
            std::mem::size_of::<GpuFrameInfo>() as u64,
            vk::BufferUsageFlags::UNIFORM_BUFFER,
        )?;
        let draws = gpu.create_per_frame_buffer("scene draws", draw_bytes, SCENE_STORAGE)?;
        let set = layout.create_named_set(&[
            ("FrameBlock", Resource::Buffer(&frame)),
            ("DrawBlock", Resource::Buffer(&draws)),
            ("MaterialBlock", Resource::Buffer(materials)),
        ])?;
        Ok(Self {
            frame,
            draws,
            set,
            staging: None,
            texture_array: None,
        })
    }
}

/// Draws a frame slot has room for at first, at least.
pub const FIRST_DRAWS: usize = 256;

/// The most draws (opaque and transparent) a frame may have on `gpu`: their records are one
/// storage binding the graphics passes read (160 bytes a draw; 838,860 draws in the 128 MB
/// every Vulkan device binds).
pub fn most_draws(gpu: &Gpu) -> usize {
    gpu.info().max_storage_buffer_range as usize / std::mem::size_of::<GpuDrawInfo>()
}

/// Bytes of draw records a frame slot makes room for, given `draws` now: twice as many, so
/// that a growing draw count reallocates rarely, within one storage binding; or an error
/// naming the limit when the draws themselves pass it.
fn draw_room(gpu: &Gpu, draws: usize) -> Result<u64> {
    let most = most_draws(gpu);
    if draws > most {
        return Err(crate::Error::TooLarge(format!(
            "the frame has {draws} draws; their records ({} bytes each) fit at most {most} in \
             the {} MB this device binds as the one storage binding the graphics passes read",
            std::mem::size_of::<GpuDrawInfo>(),
            gpu.info().max_storage_buffer_range >> 20
        )));
    }
    let room = (2 * draws).clamp(FIRST_DRAWS, most.max(FIRST_DRAWS));
    Ok(room as u64 * std::mem::size_of::<GpuDrawInfo>() as u64)
}

/// Tells apart the users of one [`ResidentAssets`], for its uploads on the engine's device.
static NEXT_SCENE_ID: AtomicU64 = AtomicU64::new(1);

/// The stages a method's mesh pipelines run before its fragment shader.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum MeshStages {
    /// `scene/mesh.vert` alone.
    Plain,
    /// `scene/ordered.vert` and `scene/ordered.geom`: the fragment shader (compiled with
    /// `ORDER_DEPTH`) finds each fragment's order depth as the CPU reference does, for the
    /// methods that sort fragments by it.
    OrderDepth,
    /// As `OrderDepth`, the stages handing on nothing but what the order depth needs
    /// (`scene/ordered_order_only.vert` and `.geom`), for fragment shaders that read it
    /// alone (depth_peeling's first pass, wavelet's bounds): no output goes unread.
    OrderOnly,
    /// As `OrderDepth`, without the eye vector and the normal (`scene/ordered_unlit.vert`
    /// and `.geom`), for fragment shaders that shade transmittance alone (wavelet's
    /// accumulate pass).
    OrderUnlit,
}

pub struct GpuScene {
    /// The assets, shared with the other renderers made over them.
    pub resident: Arc<ResidentAssets>,
    id: u64,
    /// Total quads of the transparent draws.
    pub transparent_quads: u32,
    /// Per frame slot, what a frame writes and reads while others are in flight.
    slots: Vec<SceneSlot>,
    /// The slot frames write and record now.
    slot: usize,
    /// Set 0: frame, draws, materials.
    pub layout: DescriptorLayout,
    pub opaque_calls: Vec<DrawCall>,
    pub transparent_calls: Vec<DrawCall>,
    /// The frame size the frame info is written for.
    extent: (u32, u32),
    /// Meshes whose vertices moved since the last frame was recorded.
    moved_meshes: Vec<usize>,
    /// On the engine's device, per frame in flight (oldest first): the meshes whose moves
    /// it carried, to carry again if it is abandoned.
    moved_in_flight: VecDeque<Vec<usize>>,
    /// Frames recorded whole and frames completed (on the engine's device), which say
    /// which frame carries the assets' pending uploads and when they ran.
    frames_recorded: u64,
    frames_completed: u64,
}

impl GpuScene {
    /// Uploads `scene` (validated first) for frames of `width`×`height`, with `frame_slots`
    /// frames in flight at most, and writes the scene's own frame into slot 0.
    pub fn new(
        gpu: &Gpu,
        scene: &Scene,
        width: u32,
        height: u32,
        frame_slots: usize,
    ) -> Result<Self> {
        let resident = Arc::new(ResidentAssets::new(gpu, scene)?);
        Self::over(gpu, resident, scene, width, height, frame_slots)
    }

    /// Like [`Self::new`] over assets uploaded before, from a scene with the same assets.
    pub fn over(
        gpu: &Gpu,
        resident: Arc<ResidentAssets>,
        scene: &Scene,
        width: u32,
        height: u32,
        frame_slots: usize,
    ) -> Result<Self> {
        scene.validate()?;
        resident.check_scene(scene)?;
        let stages = vk::ShaderStageFlags::VERTEX
            | vk::ShaderStageFlags::FRAGMENT
            | vk::ShaderStageFlags::COMPUTE;
        let layout = DescriptorLayout::declared(gpu, &SCENE_SET, stages)?;
        // Room for twice the draws and at least FIRST_DRAWS: frames that draw more do not
        // grow every slot's buffer one after another.
        let draw_bytes = draw_room(gpu, scene.opaque.len() + scene.transparent.len())?;
        let slots = (0..frame_slots.max(1))
            .map(|_| SceneSlot::new(gpu, &layout, resident.materials(), draw_bytes))
            .collect::<Result<Vec<_>>>()?;
        let mut gpu_scene = Self {
            resident,
            id: NEXT_SCENE_ID.fetch_add(1, Ordering::Relaxed),
            transparent_quads: 0,
            slots,
            slot: 0,
            layout,
            opaque_calls: Vec::new(),
            transparent_calls: Vec::new(),
            extent: (width, height),
            moved_meshes: Vec::new(),
            moved_in_flight: VecDeque::new(),
            frames_recorded: 0,
            frames_completed: 0,
        };
        gpu_scene.set_frame(gpu, scene)?;
        Ok(gpu_scene)
    }

    /// Draws from `resident`, these assets extended (checked), for `scene`, which has them:
    /// the buffers and descriptor sets stay, since the assets added were appended to them.
    pub fn adopt(&mut self, resident: Arc<ResidentAssets>, scene: &Scene) -> Result<()> {
        if !resident.extends(&self.resident) {
            return Err(crate::Error::InvalidArgument(
                "the assets to draw from do not extend the ones drawn from".into(),
            ));
        }
        resident.check_scene(scene)?;
        // The versions share their buffers and the queue of uploads into them (staging
        // and all, until the frames that carried them complete): the old version may go now.
        self.resident = resident;
        Ok(())
    }

    /// Meshes whose vertices moved since the last frame was recorded (methods renew what they
    /// keep of them when they are given the next frame).
    pub fn moved_meshes(&self) -> &[usize] {
        &self.moved_meshes
    }

    /// Notes that mesh `index` moved: the next frame recorded copies its vertices in (see
    /// [`Self::record_moved_vertices`]).
    pub fn mesh_moved(&mut self, index: usize) {
        if !self.moved_meshes.contains(&index) {
            self.moved_meshes.push(index);
        }
    }

    /// Records the copy of the moved meshes' vertices (as `scene` holds them now) from the
    /// current slot's staging buffer into the vertex buffer, after every command before it on
    /// the queue (frames in flight included) and before the frame's draws and dispatches.
    /// The slot's last frame must have completed. Recorded again by every frame until
    /// [`Self::uploads_recorded`] says one recording went through.
    pub fn record_moved_vertices(
        &mut self,
        gpu: &Gpu,
        cmd: vk::CommandBuffer,
        scene: &Scene,
    ) -> Result<()> {
        if self.moved_meshes.is_empty() {
            return Ok(());
        }
        let mut bytes: Vec<u8> = Vec::new();
        let mut regions = Vec::with_capacity(self.moved_meshes.len());
        for &mesh in &self.moved_meshes {
            let vertices = resident::gpu_vertices(&scene.meshes[mesh]);
            let first = u64::try_from(self.resident.ranges[mesh].vertex_offset).unwrap_or(0);
            regions.push(vk::BufferCopy {
                src_offset: bytes.len() as u64,
                dst_offset: first * u64::from(VERTEX_STRIDE),
                size: (vertices.len() * VERTEX_STRIDE as usize) as u64,
            });
            bytes.extend_from_slice(bytemuck::cast_slice(&vertices));
        }
        let needed = bytes.len() as u64;
        let staging_of = || {
            gpu.create_buffer(
                "moved vertices",
                needed.next_power_of_two(),
                vk::BufferUsageFlags::TRANSFER_SRC,
                MemoryLocation::CpuToGpu,
            )
        };
        if self.slots[self.slot]
            .staging
            .as_ref()
            .is_none_or(|s| s.size < needed)
        {
            self.slots[self.slot].staging = Some(staging_of()?);
            // The other slots' first moves then allocate nothing either: a frame loop
            // allocates once, on its first move. (A slot in flight may be given a buffer,
            // never have its own replaced.)
            for slot in &mut self.slots {
                if slot.staging.is_none() {
                    slot.staging = Some(staging_of()?);
                }
            }
        }
        let slot = &mut self.slots[self.slot];
        let Some(staging) = slot.staging.as_mut() else {
            return Ok(());
        };
        staging.write(0, &bytes)?;
        use crate::gpu::{memory_barrier, ANY_ACCESS, TRANSFER_WRITE};
        memory_barrier(gpu, cmd, ANY_ACCESS, TRANSFER_WRITE);
        gpu.cmd_copy_buffer_regions(cmd, staging, self.resident.vertices(), &regions);
        memory_barrier(gpu, cmd, TRANSFER_WRITE, ANY_ACCESS);
        Ok(())
    }

    /// Makes `slot` the frame slot that [`Self::set_frame`] writes and recording reads.
    pub fn use_slot(&mut self, slot: usize) {
        self.slot = slot % self.slots.len();
    }

    /// The slot frames write and record now.
    pub fn slot(&self) -> usize {
        self.slot
    }

    /// Frame slots: frames that may be in flight at once.
    pub fn slot_count(&self) -> usize {
        self.slots.len()
    }

    /// Makes `width` x `height` the size of the frames written from now on (their
    /// viewport and the look-at cameras' aspect).
    pub fn set_extent(&mut self, width: u32, height: u32) {
        self.extent = (width, height);
    }

    /// The current slot's set 0 (frame, draws, materials).
    pub fn set(&self) -> &DescriptorSet {
        &self.slots[self.slot].set
    }

    /// The current slot's texture array (the bin rasters' hardware sampling), where the
    /// device and the assets have one.
    pub fn texture_array(&self) -> Option<&texture_array::TextureArray> {
        self.slots[self.slot].texture_array.as_deref()
    }

    /// The current slot's draw buffer.
    pub fn draws(&self) -> &Buffer {
        &self.slots[self.slot].draws
    }

    /// Writes the frame `scene` describes (camera, light, draws; checked by the caller
    /// against the assets this was made with) into the current slot, for the next frame to
    /// draw. The slot's draw buffer grows when the frame has more draws than it holds: then
    /// its descriptor set is new. No frame that reads the slot may be in flight.
    pub fn set_frame(&mut self, gpu: &Gpu, scene: &Scene) -> Result<()> {
        let (width, height) = self.extent;
        let frame_info = GpuFrameInfo::new(&scene.camera, &scene.light, width, height);
        let slot = &mut self.slots[self.slot];
        slot.frame.write(0, bytemuck::bytes_of(&frame_info))?;
        slot.texture_array = self.resident.texture_array().cloned();
        let all_draws = scene.opaque.iter().chain(&scene.transparent);
        let draw_infos: Vec<GpuDrawInfo> = all_draws
            .clone()
            .map(|d| GpuDrawInfo::new(d, &scene.meshes[d.mesh], self.resident.first_quads[d.mesh]))
            .collect();
        let bytes: &[u8] = bytemuck::cast_slice(&draw_infos);
        if bytes.len() as u64 > slot.draws.size {
            let materials = self.resident.materials();
            let room = draw_room(gpu, draw_infos.len())?;
            *slot = SceneSlot::new(gpu, &self.layout, materials, room)?;
            slot.frame.write(0, bytemuck::bytes_of(&frame_info))?;
        }
        slot.draws.write(0, bytes)?;
        let calls = all_draws.enumerate().map(|(i, d)| DrawCall {
            draw_index: i as u32,
            range: self.resident.ranges[d.mesh],
            cull_back: !scene.materials[d.material].double_sided,
            texture_set: scene.materials[d.material]
                .texture
                .unwrap_or(scene.textures.len()),
        });
        self.opaque_calls.clear();
        self.opaque_calls.extend(calls);
        self.transparent_calls = self.opaque_calls.split_off(scene.opaque.len());
        self.transparent_quads = u32::try_from(scene.transparent_quads())
            .map_err(|_| crate::Error::TooLarge("more than 2^32 transparent quads".into()))?;
        Ok(())
    }

    /// The pair of pipelines every scene draw goes through (back faces kept, back faces
    /// culled), for the mesh vertex shader, `fragment`, and the given depth and blend state.
    pub fn mesh_pipelines(
        &self,
        gpu: &Gpu,
        render_pass: vk::RenderPass,
        fragment: &[u8],
        depth_write: bool,
        blend: crate::gpu::Blend,
    ) -> Result<(Arc<GraphicsPipeline>, Arc<GraphicsPipeline>)> {
        self.mesh_pipelines_with(
            gpu,
            render_pass,
            MeshStages::Plain,
            fragment,
            &[],
            &PipelineState {
                blends: &[blend],
                depth: DepthMode::Less(depth_write),
                constants: &Specialization::NONE,
                vertex_input: true,
            },
        )
    }

    /// Like [`Self::mesh_pipelines`], with the method's own descriptor sets after the scene's
    /// two (set 2 on) and the full pipeline state (several attachments, specialization).
    pub fn mesh_pipelines_with(
        &self,
        gpu: &Gpu,
        render_pass: vk::RenderPass,
        stages: MeshStages,
        fragment: &[u8],
        extra_sets: &[&DescriptorLayout],
        state: &PipelineState<'_>,
    ) -> Result<(Arc<GraphicsPipeline>, Arc<GraphicsPipeline>)> {
        let mut sets = vec![&self.layout, &self.resident.texture_layout];
        sets.extend_from_slice(extra_sets);
        let pipeline = |cull_back| {
            GraphicsPipeline::shared(
                gpu,
                &GraphicsPipelineDesc {
                    vertex: match stages {
                        MeshStages::Plain => crate::spirv!("scene/mesh.vert"),
                        MeshStages::OrderDepth => crate::spirv!("scene/ordered.vert"),
                        MeshStages::OrderOnly => crate::spirv!("scene/ordered_order_only.vert"),
                        MeshStages::OrderUnlit => crate::spirv!("scene/ordered_unlit.vert"),
                    },
                    geometry: match stages {
                        MeshStages::Plain => None,
                        MeshStages::OrderDepth => Some(crate::spirv!("scene/ordered.geom")),
                        MeshStages::OrderOnly => {
                            Some(crate::spirv!("scene/ordered_order_only.geom"))
                        }
                        MeshStages::OrderUnlit => Some(crate::spirv!("scene/ordered_unlit.geom")),
                    },
                    fragment,
                    vertex_stride: VERTEX_STRIDE,
                    // The order depth needs the position alone.
                    attributes: match stages {
                        MeshStages::OrderOnly => &VERTEX_ATTRIBUTES[..1],
                        MeshStages::OrderUnlit => &UNLIT_ATTRIBUTES,
                        _ => &VERTEX_ATTRIBUTES,
                    },
                    cull_back,
                    depth_write: false,
                    blend: crate::gpu::Blend::None,
                    render_pass,
                    sets: &sets,
                    push_bytes: 4,
                },
                state,
            )
        };
        Ok((pipeline(false)?, pipeline(true)?))
    }

    /// Binds vertex and index buffers and issues `calls` with `pipelines.0` (back faces
    /// kept) or `pipelines.1` (back faces culled).
    pub fn draw(
        &self,
        gpu: &Gpu,
        cmd: vk::CommandBuffer,
        calls: &[DrawCall],
        pipelines: (&crate::gpu::GraphicsPipeline, &crate::gpu::GraphicsPipeline),
    ) {
        self.draw_each(gpu, cmd, calls, pipelines, |_, call| {
            gpu.cmd_draw_indexed(
                cmd,
                call.range.index_count,
                call.range.first_index,
                call.range.vertex_offset,
            );
        });
    }

    /// As [`Self::draw`], each call i from the VkDrawIndexedIndirectCommand at `offset` + 20 i
    /// of `args` ([`indirect_commands`] writes them; the GPU may zero their instance counts).
    pub fn draw_indirect(
        &self,
        gpu: &Gpu,
        cmd: vk::CommandBuffer,
        calls: &[DrawCall],
        pipelines: (&crate::gpu::GraphicsPipeline, &crate::gpu::GraphicsPipeline),
        (args, offset): (&crate::gpu::Buffer, u64),
    ) {
        let stride = std::mem::size_of::<vk::DrawIndexedIndirectCommand>() as u64;
        self.draw_each(gpu, cmd, calls, pipelines, |i, _| {
            gpu.cmd_draw_indexed_indirect(cmd, args, offset + stride * i as u64);
        });
    }

    /// Binds what `calls` need and has `issue` record each one (with its index) that draws
    /// anything.
    fn draw_each(
        &self,
        gpu: &Gpu,
        cmd: vk::CommandBuffer,
        calls: &[DrawCall],
        pipelines: (&crate::gpu::GraphicsPipeline, &crate::gpu::GraphicsPipeline),
        mut issue: impl FnMut(usize, &DrawCall),
    ) {
        // The render pass is compatible with both pipelines, whose layouts take this scene's
        // sets 0 and 1 and a 4-byte push constant.
        gpu.cmd_bind_mesh_buffers(cmd, self.resident.vertices(), self.resident.indices());
        let mut bound: Option<bool> = None;
        let mut bound_texture: Option<usize> = None;
        for (i, call) in calls.iter().enumerate() {
            let pipeline = if call.cull_back {
                pipelines.1
            } else {
                pipelines.0
            };
            if bound != Some(call.cull_back) {
                gpu.cmd_bind_graphics_pipeline(cmd, pipeline);
                gpu.cmd_bind_graphics_set(cmd, pipeline.layout, 0, self.set().raw);
                bound = Some(call.cull_back);
                bound_texture = None;
            }
            if bound_texture != Some(call.texture_set) {
                let set = self.resident.texture_set(call.texture_set);
                gpu.cmd_bind_graphics_set(cmd, pipeline.layout, 1, set);
                bound_texture = Some(call.texture_set);
            }
            gpu.cmd_push_draw_constants(cmd, pipeline, &call.draw_index.to_ne_bytes());
            if call.range.index_count > 0 {
                issue(i, call);
            }
        }
    }
}

/// The VkDrawIndexedIndirectCommand of each of `calls`, one instance each, as
/// [`GpuScene::draw_indirect`] reads them.
pub fn indirect_commands(calls: &[DrawCall]) -> Vec<vk::DrawIndexedIndirectCommand> {
    calls
        .iter()
        .map(|call| vk::DrawIndexedIndirectCommand {
            index_count: call.range.index_count,
            instance_count: 1,
            first_index: call.range.first_index,
            vertex_offset: call.range.vertex_offset,
            first_instance: 0,
        })
        .collect()
}

impl GpuScene {
    /// On the engine's device: records into this frame's command buffer the assets'
    /// uploads (buffers, textures, the software sampler's copies) that no frame (of any
    /// renderer over the same assets) carries, before anything reads them.
    pub fn record_pending_uploads(&self, gpu: &Gpu, cmd: vk::CommandBuffer) {
        self.resident
            .record_pending_uploads(gpu, cmd, self.id, self.frames_recorded + 1);
    }

    /// The frame that recorded the pending uploads (assets, moved vertices) was recorded
    /// whole (and submitted, or handed to the engine): later frames need not record them.
    /// A recording that failed leaves them to the next.
    pub fn uploads_recorded(&mut self) {
        self.frames_recorded += 1;
        self.moved_meshes.clear();
    }

    /// On the engine's device, as [`Self::uploads_recorded`]: the frame recorded is in
    /// flight, to complete or be abandoned.
    pub fn frame_recorded_in_flight(&mut self) {
        self.frames_recorded += 1;
        self.moved_in_flight
            .push_back(std::mem::take(&mut self.moved_meshes));
    }

    /// The oldest frame recorded with this scene and not completed yet completed: the
    /// uploads it (or a frame before it) carried ran, and their staging goes.
    pub fn uploads_completed(&mut self) {
        self.moved_in_flight.pop_front();
        self.frames_completed += 1;
        self.resident
            .uploads_completed(self.id, self.frames_completed);
    }

    /// The newest `frames` recorded in flight will never run (abandoned): the uploads and
    /// moved vertices they carried go with the next frame recorded.
    pub fn frames_abandoned(&mut self, frames: u64) {
        for _ in 0..frames {
            for mesh in self.moved_in_flight.pop_back().unwrap_or_default() {
                self.mesh_moved(mesh);
            }
        }
        self.frames_recorded = self
            .frames_recorded
            .saturating_sub(frames)
            .max(self.frames_completed);
        self.resident
            .uploads_abandoned(self.id, self.frames_recorded);
    }
}

impl Drop for GpuScene {
    fn drop(&mut self) {
        // Uploads recorded into a frame that never completed here (abandoned) are recorded
        // again by the next frame over the same assets.
        self.resident.uploads_lost(self.id);
    }
}

/// Creates the textures' images (all mips) and the uploads of their texels.
pub(crate) fn create_textures<'a>(
    gpu: &Gpu,
    textures: impl Iterator<Item = &'a Texture>,
) -> Result<(Vec<Arc<GpuImage>>, Vec<Upload>)> {
    let mut images = Vec::new();
    let mut uploads = Vec::new();
    let max = gpu.info().max_image_dimension_2d;
    for t in textures {
        // Checked before anything is created: a driver may crash on an image it cannot make.
        if t.width() > max || t.height() > max {
            return Err(crate::Error::TooLarge(format!(
                "texture {} is {}x{}; this device's largest image is {max}x{max}",
                t.name,
                t.width(),
                t.height()
            )));
        }
        let format = if t.srgb {
            vk::Format::R8G8B8A8_SRGB
        } else {
            vk::Format::R8G8B8A8_UNORM
        };
        let image = Arc::new(gpu.create_image(
            &t.name,
            vk::Extent2D {
                width: t.width(),
                height: t.height(),
            },
            format,
            vk::ImageUsageFlags::SAMPLED | vk::ImageUsageFlags::TRANSFER_DST,
            t.levels.len() as u32,
        )?);
        let bytes: Vec<u8> = t
            .levels
            .iter()
            .flat_map(|l| l.texels.iter().flatten().copied())
            .collect();
        uploads.push(Upload::to_image(gpu, &image, &t.name, &bytes)?);
        images.push(image);
    }
    Ok((images, uploads))
}
