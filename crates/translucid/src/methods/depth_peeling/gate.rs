//! The gate of depth_peeling's passes. A frame records passes past what the frames before it
//! needed; once a pass leaves no pixel anything to peel, a compute pass after its composite
//! zeroes the indirect commands of the passes after it (their clears, draws, composites and
//! gates), so that each costs its render pass and barriers alone. Indirect commands rather
//! than conditional rendering: every Vulkan device has them, an engine's included.

use crate::assets::{indirect_commands, DrawCall};
use crate::gpu::{
    vk, Buffer, ComputePipeline, ComputePipelineCache, DescriptorLayout, DescriptorSet, Gpu,
    Resource,
};
use crate::interface::methods::{DEPTH_PEELING_GATE_SET, GATE_DRAW_WORDS};
use crate::interface::specialization::Specialization;
use crate::Result;
use std::sync::Arc;

/// Byte offsets in a frame's commands (`PeelingGate` of gate.comp): the composite's
/// dispatch, the clear's draw, the gate's own dispatch, then the transparent draws.
pub const COMPOSITE: u64 = 0;
pub const CLEAR: u64 = 16;
const GATE: u64 = 32;
pub const DRAWS: u64 = 48;
/// gate.comp's workgroup size.
const GATE_GROUP_SIZE: u32 = 64;

pub struct Gate {
    layout: DescriptorLayout,
    pipeline: Arc<ComputePipeline>,
    /// Per frame slot: its frame's commands, which the host writes as the frame is recorded
    /// and the gates zero, and the set over them.
    slots: Vec<GateSlot>,
}

struct GateSlot {
    commands: Buffer,
    set: DescriptorSet,
    /// Draws the commands hold.
    draws: usize,
}

impl Gate {
    /// The gate of `slots` frame slots, reading the composites' flags in `peeling`.
    pub fn new(gpu: &Gpu, peeling: &Buffer, slots: usize) -> Result<Self> {
        let layout = DescriptorLayout::declared(
            gpu,
            &DEPTH_PEELING_GATE_SET,
            vk::ShaderStageFlags::COMPUTE,
        )?;
        let pipeline = ComputePipelineCache::new(8).get(
            gpu,
            &[&layout],
            crate::spirv!("depth_peeling/gate.comp"),
            &Specialization::NONE,
        )?;
        let slots = (0..slots)
            .map(|_| GateSlot::new(gpu, &layout, peeling, 1))
            .collect::<Result<_>>()?;
        Ok(Self {
            layout,
            pipeline,
            slots,
        })
    }

    /// Writes the commands of the frame recorded into `slot`: `calls`, and composites over
    /// `extent`, all enabled. (The slot's last frame has completed, or was abandoned: its
    /// commands are free, and replaced when the calls outgrow them.)
    pub fn write(
        &mut self,
        gpu: &Gpu,
        slot: usize,
        peeling: &Buffer,
        calls: &[DrawCall],
        extent: vk::Extent2D,
    ) -> Result<()> {
        if calls.len() > self.slots[slot].draws {
            let draws = calls.len().max(2 * self.slots[slot].draws);
            self.slots[slot] = GateSlot::new(gpu, &self.layout, peeling, draws)?;
        }
        let gate_groups = (calls.len() as u32).div_ceil(GATE_GROUP_SIZE).max(1);
        let mut words = vec![
            extent.width.div_ceil(8),
            extent.height.div_ceil(8),
            1,
            0,
            3,
            1,
            0,
            0,
            gate_groups,
            1,
            1,
            0,
        ];
        for draw in indirect_commands(calls) {
            words.extend([
                draw.index_count,
                draw.instance_count,
                draw.first_index,
                draw.vertex_offset as u32,
                draw.first_instance,
            ]);
        }
        self.slots[slot]
            .commands
            .write(0, bytemuck::cast_slice(&words))
    }

    /// The commands of the frame recorded into `slot`.
    pub fn commands(&self, slot: usize) -> &Buffer {
        &self.slots[slot].commands
    }

    /// Records the gate after the composite of `pass`, over `draws` draws, into the frame of
    /// `slot`.
    pub fn record(&self, cmd: vk::CommandBuffer, slot: usize, pass: u32, draws: usize) {
        let slot = &self.slots[slot];
        let push: [u32; 2] = [pass, draws as u32];
        self.pipeline.dispatch_indirect(
            cmd,
            &[slot.set.raw],
            bytemuck::cast_slice(&push),
            &slot.commands,
            GATE,
        );
    }
}

impl GateSlot {
    fn new(gpu: &Gpu, layout: &DescriptorLayout, peeling: &Buffer, draws: usize) -> Result<Self> {
        let bytes = DRAWS + 4 * u64::from(GATE_DRAW_WORDS) * draws as u64;
        let commands = gpu.create_per_frame_buffer(
            "depth peeling gate",
            bytes,
            vk::BufferUsageFlags::INDIRECT_BUFFER | vk::BufferUsageFlags::STORAGE_BUFFER,
        )?;
        let set = layout.create_named_set(&[
            ("PeelingFlags", Resource::Buffer(peeling)),
            ("PeelingGate", Resource::Buffer(&commands)),
        ])?;
        Ok(Self {
            commands,
            set,
            draws,
        })
    }
}

// The shader's draw commands are Vulkan's.
const _: () =
    assert!(GATE_DRAW_WORDS as usize * 4 == std::mem::size_of::<vk::DrawIndexedIndirectCommand>());
