//! `linked_list`: per-pixel linked lists (the A-buffer), the exact method engines ship today.
//!
//! The transparent draws are rasterized by the hardware; every fragment nearer than the opaque
//! layer is shaded and pushed onto its pixel's list: a node from a pool (radiance and
//! transmittance in halves, order depth, draw, primitive, next), its index swapped into the
//! pixel's head (`shaders/linked_list/append.frag`). A compute pass then composites each
//! pixel's nodes in the reference's order, front to back, over the frame (`resolve.comp`).
//!
//! The pool holds `capacity` nodes. A fragment past it is blended at once, unsorted, over the
//! opaque layer (a tail the sorted nodes are then composited over) and counted
//! ([`super::FrameCheck::tail_fragments`]). By default the pool is sized from each frame's
//! expected fragments before it is recorded (a sample of its quads' area on screen: content
//! streamed in, or the same draws seen nearer, which the frames in flight have not counted),
//! and grows for later frames when a frame finds it too small all the same (that frame is
//! rendered again, standalone, or completes degraded on an engine's device, its tail
//! counted); with
//! [`LinkedListOptions::node_budget`] it stays as given. Within its pool the result is exact.
//! The passes reach the pool through a storage binding while it fits one (128 MB: 4.8
//! million nodes on lavapipe), and through a storage texel view past it, whose stores cost
//! more there: the larger of the two bounds the pool (on lavapipe the view, 512 MB: 19
//! million nodes; on devices whose storage bindings reach further, the binding).

use super::bins::features::{ESTIMATE_QUADS, FRAME_ESTIMATE_QUADS};
use super::{FrameCheck, FrameDone, FrameSetup, Method, RecordContext};
use crate::assets::GpuScene;
use crate::frame::FrameTargets;
use crate::gpu::{
    image_barrier, memory_barrier, vk, Blend, Buffer, ComputePipeline, ComputePipelineCache,
    DepthMode, DescriptorLayout, DescriptorSet, Gpu, GraphicsPipeline, MemoryLocation,
    PipelineState, RenderTarget, Resource, Retirement, ViewedBuffer,
};
use crate::interface::methods::{LINKED_LIST_RESOLVE_SET, LINKED_LIST_SET};
use crate::interface::specialization::{Specialization, NODES_AS_TEXELS};
use crate::scene::Scene;
use crate::{Error, Result};
use std::sync::Arc;

/// Words of a node (`NODE_WORDS` of linked_list.glsl).
const NODE_WORDS: u64 = 7;
const NODE_BYTES: u64 = NODE_WORDS * 4;
/// The counters' words: fragments, capacity, width, height (`ListCounters`).
const COUNTER_BYTES: u64 = 16;

/// The linked_list method's settings.
#[derive(Clone, Debug, Default)]
pub struct LinkedListOptions {
    /// Nodes in the pool, fixed: fragments past it are blended unsorted (the tail). `None`
    /// sizes the pool from the frame and grows it as frames need.
    pub node_budget: Option<u64>,
    /// Reach the pool through its texel view whatever its size, as pools past one storage
    /// binding are, so that tests can check that path on small frames.
    #[doc(hidden)]
    pub nodes_as_texels: bool,
}

/// The pool and the heads, replaced together when the pool grows, with the passes' sets.
struct Lists {
    heads: Buffer,
    /// Named by the sets only.
    _nodes: ViewedBuffer,
    append_set: DescriptorSet,
    resolve_set: DescriptorSet,
    capacity: u32,
}

/// The append pass's set (heads, nodes, counters) and the resolve's (the same, and the
/// frame's colour).
struct Layouts {
    append: DescriptorLayout,
    resolve: DescriptorLayout,
}

/// The two passes' pipelines, for a pool reached through its storage binding or through its
/// texel view (`NODES_AS_TEXELS`).
struct Passes {
    nodes_as_texels: bool,
    /// (back faces kept, back faces culled)
    append: (Arc<GraphicsPipeline>, Arc<GraphicsPipeline>),
    resolve: Arc<ComputePipeline>,
}

impl Passes {
    fn new(
        gpu: &Gpu,
        gpu_scene: &GpuScene,
        render_pass: vk::RenderPass,
        layouts: &Layouts,
        nodes_as_texels: bool,
    ) -> Result<Self> {
        let constants = Specialization::new().with(NODES_AS_TEXELS, nodes_as_texels);
        let append = gpu_scene.mesh_pipelines_with(
            gpu,
            render_pass,
            crate::assets::MeshStages::OrderDepth,
            crate::spirv!("linked_list/append.frag"),
            &[&layouts.append],
            &PipelineState {
                blends: &[Blend::PremultipliedTransmittance],
                depth: DepthMode::Less(false),
                constants: &constants,
                vertex_input: true,
            },
        )?;
        let resolve = ComputePipelineCache::new(0).get(
            gpu,
            &[&layouts.resolve],
            crate::spirv!("linked_list/resolve.comp"),
            &constants,
        )?;
        Ok(Self {
            nodes_as_texels,
            append,
            resolve,
        })
    }
}

pub struct LinkedList {
    gpu: Gpu,
    append: RenderTarget,
    passes: Passes,
    layouts: Layouts,
    lists: Lists,
    counters: Buffer,
    /// Per frame slot, the host's copy of the counters.
    readbacks: Vec<Buffer>,
    /// Per frame slot, the pool its frame was recorded with.
    recorded: Vec<u32>,
    fixed: bool,
    /// A pool the memory budget refused: no frame asks for one as large again.
    refused: u32,
    /// `LinkedListOptions::nodes_as_texels`.
    texels_forced: bool,
    retirement: Retirement,
}

/// The most nodes one storage binding holds.
fn binding_nodes(gpu: &Gpu) -> u64 {
    u64::from(gpu.info().max_storage_buffer_range) / NODE_BYTES
}

/// The most nodes the pool holds: what one storage binding or one texel view of its words
/// reaches, whichever is more.
fn most_nodes(gpu: &Gpu) -> u64 {
    let view_nodes = u64::from(gpu.info().max_texel_buffer_elements) / NODE_WORDS;
    binding_nodes(gpu).max(view_nodes).min(u64::from(u32::MAX))
}

/// Whether a pool of `capacity` nodes passes what one storage binding holds, so that the
/// passes must reach it through its texel view (which then holds it: `most_nodes`).
fn nodes_pass_a_binding(gpu: &Gpu, capacity: u32) -> bool {
    u64::from(capacity) > binding_nodes(gpu)
}

impl LinkedList {
    pub fn new(
        gpu: &Gpu,
        scene: &Scene,
        gpu_scene: &GpuScene,
        targets: &FrameTargets,
        options: &LinkedListOptions,
    ) -> Result<Self> {
        let info = gpu.info();
        if !info.dual_source_blend {
            return Err(Error::DeviceLacks(format!(
                "{} lacks dualSrcBlend, which the linked_list method's tail needs",
                info.name
            )));
        }
        gpu.require_features(
            "linked_list",
            super::MethodKind::LinkedList.optional_features(),
        )?;
        let most = most_nodes(gpu);
        let capacity = match options.node_budget {
            Some(0) => {
                return Err(Error::InvalidOption(
                    "linked_list: a node budget of 0; give at least 1".into(),
                ))
            }
            Some(budget) if budget > most => {
                return Err(Error::InvalidOption(format!(
                    "linked_list: a budget of {budget} nodes; the pool {} binds holds at most \
                     {most}",
                    info.name
                )))
            }
            Some(budget) => budget,
            None => {
                let expected = expected_fragments(scene, targets, ESTIMATE_QUADS);
                pool_for(expected, 0.25, targets, most)
            }
        } as u32;
        let layouts = Layouts {
            append: DescriptorLayout::declared(
                gpu,
                &LINKED_LIST_SET,
                vk::ShaderStageFlags::FRAGMENT,
            )?,
            resolve: DescriptorLayout::declared(
                gpu,
                &LINKED_LIST_RESOLVE_SET,
                vk::ShaderStageFlags::COMPUTE,
            )?,
        };
        let counters = gpu.create_buffer(
            "linked list counters",
            COUNTER_BYTES,
            vk::BufferUsageFlags::STORAGE_BUFFER
                | vk::BufferUsageFlags::TRANSFER_DST
                | vk::BufferUsageFlags::TRANSFER_SRC,
            MemoryLocation::GpuOnly,
        )?;
        let lists = Self::lists(gpu, &layouts, &counters, targets, capacity)?;
        let append = targets.render_target(gpu, false)?;
        let passes = Passes::new(
            gpu,
            gpu_scene,
            append.render_pass,
            &layouts,
            options.nodes_as_texels || nodes_pass_a_binding(gpu, capacity),
        )?;
        let readbacks = (0..gpu_scene.slot_count())
            .map(|_| {
                gpu.create_buffer(
                    "linked list counters readback",
                    COUNTER_BYTES,
                    vk::BufferUsageFlags::TRANSFER_DST,
                    MemoryLocation::GpuToCpu,
                )
            })
            .collect::<Result<Vec<_>>>()?;
        Ok(Self {
            gpu: gpu.clone(),
            append,
            passes,
            layouts,
            recorded: vec![capacity; readbacks.len()],
            readbacks,
            lists,
            counters,
            fixed: options.node_budget.is_some(),
            refused: u32::MAX,
            texels_forced: options.nodes_as_texels,
            retirement: Retirement::default(),
        })
    }

    /// A pool of `capacity` nodes from the next frame on (the old one kept while frames in
    /// flight use it), and the passes that reach it.
    fn grow(&mut self, gpu_scene: &GpuScene, targets: &FrameTargets, capacity: u32) -> Result<()> {
        let lists = Self::lists(&self.gpu, &self.layouts, &self.counters, targets, capacity)?;
        let old = std::mem::replace(&mut self.lists, lists);
        self.retirement.retire(old);
        let as_texels = self.texels_forced || nodes_pass_a_binding(&self.gpu, capacity);
        if as_texels != self.passes.nodes_as_texels {
            let passes = Passes::new(
                &self.gpu,
                gpu_scene,
                self.append.render_pass,
                &self.layouts,
                as_texels,
            )?;
            let old = std::mem::replace(&mut self.passes, passes);
            self.retirement.retire(old);
        }
        Ok(())
    }

    /// Heads for the largest frame and a pool of `capacity` nodes, with their set.
    fn lists(
        gpu: &Gpu,
        layouts: &Layouts,
        counters: &Buffer,
        targets: &FrameTargets,
        capacity: u32,
    ) -> Result<Lists> {
        let storage = vk::BufferUsageFlags::STORAGE_BUFFER | vk::BufferUsageFlags::TRANSFER_DST;
        let heads = gpu.create_buffer(
            "linked list heads",
            targets.capacity_pixels() * 4,
            storage,
            MemoryLocation::GpuOnly,
        )?;
        let buffer = gpu.create_buffer(
            "linked list nodes",
            u64::from(capacity) * NODE_BYTES,
            storage | vk::BufferUsageFlags::STORAGE_TEXEL_BUFFER,
            MemoryLocation::GpuOnly,
        )?;
        // Each binding reaches as far as it can; the passes read through the one that
        // reaches the whole pool.
        let nodes = ViewedBuffer {
            view: gpu.create_buffer_view_prefix(&buffer, vk::Format::R32_UINT)?,
            buffer,
        };
        let lists = [
            ("HeadBlock", Resource::Buffer(&heads)),
            ("NodeBlock", Resource::BufferPrefix(&nodes.buffer)),
            ("ListCounters", Resource::Buffer(counters)),
            ("u_nodeTexels", Resource::TexelBuffer(nodes.view.raw)),
        ];
        let append_set = layouts.append.create_named_set(&lists)?;
        let mut resolve = lists.to_vec();
        resolve.push(("u_colour", Resource::StorageImage(targets.colour.view)));
        let resolve_set = layouts.resolve.create_named_set(&resolve)?;
        Ok(Lists {
            heads,
            _nodes: nodes,
            append_set,
            resolve_set,
            capacity,
        })
    }
}

/// The fragments a frame of `scene` into `targets` is expected to have, from at most
/// `most_quads` of its quads.
fn expected_fragments(scene: &Scene, targets: &FrameTargets, most_quads: u64) -> u64 {
    let (width, height) = (targets.extent.width, targets.extent.height);
    super::bins::features::estimated_fragments(scene, width, height, most_quads)
}

/// A pool for `fragments` expected fragments and `spare` (a fraction) more, at least a node
/// a pixel, at most `most`.
fn pool_for(fragments: u64, spare: f64, targets: &FrameTargets, most: u64) -> u64 {
    (fragments + (fragments as f64 * spare) as u64)
        .max(targets.capacity_pixels())
        .min(most)
}

impl Method for LinkedList {
    fn name(&self) -> &'static str {
        "linked_list"
    }

    fn set_frame(&mut self, f: &FrameSetup<'_>) -> Result<()> {
        // Sized from the frame's own estimate before it is recorded, so that it is right on
        // its first recording also where the frames in flight before it saw less: content
        // streamed in, or the same draws seen nearer (a camera moving into a cloud). Grown
        // with half to spare, so that a camera coming closer frame by frame regrows rarely.
        if self.fixed {
            return Ok(());
        }
        let expected = expected_fragments(f.scene, f.targets, FRAME_ESTIMATE_QUADS);
        let most = most_nodes(&self.gpu);
        if pool_for(expected, 0.25, f.targets, most) <= u64::from(self.lists.capacity) {
            return Ok(());
        }
        let capacity = pool_for(expected, 0.5, f.targets, most) as u32;
        if capacity >= self.refused {
            return Ok(());
        }
        log::info!("linked_list: {expected} fragments expected; the pool grows to {capacity}");
        match self.grow(f.gpu_scene, f.targets, capacity) {
            // Past the context's budget the frame keeps the pool it has: the fragments past
            // it are blended unsorted and counted, as for any frame the pool is too small for.
            Err(Error::MemoryBudget(e)) => {
                log::warn!(
                    "linked_list: the pool stays at {}: {e}",
                    self.lists.capacity
                );
                self.refused = capacity;
                Ok(())
            }
            grown => grown,
        }
    }

    fn record(&mut self, ctx: &mut RecordContext<'_>) -> Result<()> {
        let (gpu, cmd) = (ctx.gpu, ctx.cmd);
        self.retirement.recorded();
        self.recorded[ctx.slot] = self.lists.capacity;
        let transfer = (
            vk::PipelineStageFlags::TRANSFER,
            vk::AccessFlags::TRANSFER_WRITE,
        );
        let fragment = (
            vk::PipelineStageFlags::FRAGMENT_SHADER,
            vk::AccessFlags::SHADER_READ | vk::AccessFlags::SHADER_WRITE,
        );
        // The frames before this one finished reading the lists.
        memory_barrier(gpu, cmd, fragment, transfer);
        gpu.cmd_fill_buffer(cmd, &self.lists.heads, u32::MAX);
        let extent = ctx.targets.extent;
        let counters = [0, self.lists.capacity, extent.width, extent.height];
        gpu.cmd_update_buffer(cmd, &self.counters, 0, bytemuck::cast_slice(&counters));
        memory_barrier(gpu, cmd, transfer, fragment);

        self.append.begin(cmd, extent, [0.0; 4]);
        let set = self.lists.append_set.raw;
        let (keep_back, cull_back) = &self.passes.append;
        gpu.cmd_bind_graphics_set(cmd, keep_back.layout, 2, set);
        ctx.gpu_scene.draw(
            gpu,
            cmd,
            &ctx.gpu_scene.transparent_calls,
            (keep_back, cull_back),
        );
        self.append.end(cmd);
        ctx.timestamps.mark(cmd, "linked list append");

        // The resolve reads what every fragment wrote, and composites into the colour.
        let compute = (
            vk::PipelineStageFlags::COMPUTE_SHADER,
            vk::AccessFlags::SHADER_READ | vk::AccessFlags::SHADER_WRITE,
        );
        let attachment = (
            vk::PipelineStageFlags::ALL_COMMANDS,
            vk::AccessFlags::MEMORY_READ | vk::AccessFlags::MEMORY_WRITE,
        );
        memory_barrier(gpu, cmd, fragment, compute);
        let colour = &ctx.targets.colour;
        let (attached, general) = (
            vk::ImageLayout::COLOR_ATTACHMENT_OPTIMAL,
            vk::ImageLayout::GENERAL,
        );
        image_barrier(gpu, cmd, colour, attached, general, attachment, compute);
        self.passes.resolve.dispatch(
            cmd,
            &[self.lists.resolve_set.raw],
            &[],
            [extent.width.div_ceil(8), extent.height.div_ceil(8), 1],
        );
        image_barrier(gpu, cmd, colour, general, attached, compute, attachment);

        let readback = &self.readbacks[ctx.slot];
        let transfer_read = (
            vk::PipelineStageFlags::TRANSFER,
            vk::AccessFlags::TRANSFER_READ,
        );
        memory_barrier(gpu, cmd, compute, transfer_read);
        gpu.cmd_copy_buffer(cmd, &self.counters, readback, 0, COUNTER_BYTES);
        memory_barrier(
            gpu,
            cmd,
            transfer,
            (vk::PipelineStageFlags::HOST, vk::AccessFlags::HOST_READ),
        );
        ctx.timestamps.mark(cmd, "linked list resolve");
        Ok(())
    }

    fn frames_abandoned(&mut self, frames: u64) {
        self.retirement.abandoned(frames);
    }

    fn frame_done(&mut self, done: &FrameDone<'_>) -> Result<FrameCheck> {
        self.retirement.completed();
        let slot = done.slot % self.readbacks.len();
        let fragments = self.readbacks[slot].read_word_volatile()?;
        let recorded = self.recorded[slot];
        let tail = fragments.saturating_sub(recorded);
        let mut check = FrameCheck {
            fragments: u64::from(fragments),
            tail_fragments: u64::from(tail),
            ..FrameCheck::default()
        };
        if tail > 0 && !self.fixed {
            let most = most_nodes(&self.gpu) as u32;
            // Grown once for the frames recorded with the pool that was too small.
            if recorded == self.lists.capacity && recorded < most {
                let capacity = fragments.saturating_add(fragments / 4).min(most);
                self.grow(done.gpu_scene, done.targets, capacity)?;
                log::info!("linked_list: {fragments} fragments; the pool grows to {capacity}");
            }
            // Rendered again with the grown pool; past its most the tail stays.
            check.rerender = recorded < most;
        }
        Ok(check)
    }
}
