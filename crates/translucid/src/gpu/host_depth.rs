//! The engine's depth image into translucid's depth target, when it cannot be copied as it
//! is: a reversed-Z depth (turned around, `1 − d`), or a format other than D32_SFLOAT. A
//! full-screen pass samples the engine's image (which then needs SAMPLED usage) and writes
//! every texel of the target with `gl_FragDepth`. Each frame makes a view of the engine's
//! image (the engine may hand a different one every frame) and writes it into its slot's
//! descriptor set.

use super::error::vk_err;
use super::host::{Transition, ANY};
use super::{
    fullscreen_pipeline, Attachment, AttachmentPass, DepthAttachment, DepthMode, DescriptorLayout,
    DescriptorSet, Gpu, GpuImage, GraphicsPipeline, HostImage, Load, PipelineState, Resource,
    Sampler,
};
use crate::interface::methods::{DepthImportPush, DEPTH_IMPORT_SET};
use crate::interface::specialization::{Specialization, IMPORTED_DEPTH_REVERSED};
use crate::Result;
use ash::vk;
use ash::vk::ImageLayout as L;

/// A view of one of the engine's depth images, destroyed with it.
struct EngineDepthView {
    gpu: Gpu,
    raw: vk::ImageView,
}

impl Drop for EngineDepthView {
    fn drop(&mut self) {
        // SAFETY: kept until the frame that sampled it completed (see `DepthImport::slots`).
        unsafe {
            self.gpu
                .device
                .destroy_image_view(self.raw, self.gpu.callbacks())
        };
    }
}

/// What one frame slot's import samples through: its set, and the view of the engine's
/// image its last frame sampled, kept until the slot is recorded again, when that frame has
/// completed.
struct SlotInput {
    set: DescriptorSet,
    /// Kept alive for the frame that samples it.
    _view: EngineDepthView,
}

pub struct DepthImport {
    gpu: Gpu,
    slots: Vec<Option<SlotInput>>,
    /// Writing depth as sampled, and as sampled turned around (reversed-Z).
    pipelines: [std::sync::Arc<GraphicsPipeline>; 2],
    pass: AttachmentPass,
    sampler: Sampler,
    layout: DescriptorLayout,
}

const SAMPLED: (vk::PipelineStageFlags, vk::AccessFlags) = (
    vk::PipelineStageFlags::FRAGMENT_SHADER,
    vk::AccessFlags::SHADER_READ,
);

impl DepthImport {
    /// The pass into `target` (translucid's depth target), for `slots` frames in flight.
    pub fn new(gpu: &Gpu, target: &GpuImage, slots: usize) -> Result<Self> {
        let layout =
            DescriptorLayout::declared(gpu, &DEPTH_IMPORT_SET, vk::ShaderStageFlags::FRAGMENT)?;
        let pass = AttachmentPass::new(
            gpu,
            &[],
            Some(&DepthAttachment {
                attachment: Attachment {
                    image: target,
                    load: Load::Discard,
                    layouts: (L::UNDEFINED, L::DEPTH_STENCIL_ATTACHMENT_OPTIMAL),
                },
                write: true,
            }),
        )?;
        let pipeline = |reversed: bool| {
            fullscreen_pipeline(
                gpu,
                pass.render_pass,
                crate::spirv!("host/depth_import.frag"),
                (&[&layout], std::mem::size_of::<DepthImportPush>() as u32),
                &PipelineState {
                    blends: &[],
                    depth: DepthMode::WriteAlways,
                    constants: &Specialization::new().with(IMPORTED_DEPTH_REVERSED, reversed),
                    vertex_input: false,
                },
            )
        };
        let pipelines = [pipeline(false)?, pipeline(true)?];
        Ok(Self {
            gpu: gpu.clone(),
            slots: (0..slots).map(|_| None).collect(),
            pipelines,
            pass,
            sampler: Sampler::nearest_clamp(gpu)?,
            layout,
        })
    }

    /// Records the import of `depth` (the engine's, checked, holding `extent` from its
    /// origin: the frame's size) into the target's top-left `extent`, for the frame recorded
    /// in `slot` (whose
    /// last frame has completed), turned around when `reversed`. The engine's image ends in
    /// its final layout, the target in DEPTH_STENCIL_ATTACHMENT_OPTIMAL.
    pub fn record(
        &mut self,
        cmd: vk::CommandBuffer,
        slot: usize,
        depth: &HostImage,
        (extent, reversed): (vk::Extent2D, bool),
    ) -> Result<()> {
        // The view reads depth; transitions name every aspect of the format.
        let aspects = super::host::depth_format_aspects(depth.format);
        let info = vk::ImageViewCreateInfo::default()
            .image(depth.image)
            .view_type(vk::ImageViewType::TYPE_2D)
            .format(depth.format)
            .subresource_range(vk::ImageSubresourceRange {
                aspect_mask: vk::ImageAspectFlags::DEPTH,
                base_mip_level: 0,
                level_count: 1,
                base_array_layer: depth.layer,
                layer_count: 1,
            });
        // SAFETY: the engine's live depth image of this device, of the format named (the
        // record_host contract), with one level and at least `layer + 1` layers.
        let raw = unsafe {
            self.gpu
                .device
                .create_image_view(&info, self.gpu.callbacks())
        }
        .map_err(vk_err("vkCreateImageView"))?;
        let view = EngineDepthView {
            gpu: self.gpu.clone(),
            raw,
        };
        let resources = [(
            "u_engineDepth",
            Resource::Images(&[view.raw], self.sampler.raw),
        )];
        // The slot's last frame completed: its set can be written, and the view it named can
        // go.
        let input = match self.slots[slot].take() {
            Some(input) => {
                self.layout.write_named_set(&input.set, &resources)?;
                SlotInput {
                    _view: view,
                    ..input
                }
            }
            None => SlotInput {
                set: self.layout.create_named_set(&resources)?,
                _view: view,
            },
        };
        let set = input.set.raw;
        let read = L::SHADER_READ_ONLY_OPTIMAL;
        self.gpu.transitions(
            cmd,
            &[Transition(
                depth.layer(),
                aspects,
                (depth.layout, read),
                ANY,
                SAMPLED,
            )],
        );
        self.pass.begin(cmd, extent);
        // The frame's pixels start at its origin in the engine's image.
        let push = DepthImportPush {
            origin_x: depth.origin.x as u32,
            origin_y: depth.origin.y as u32,
        };
        let pipeline = &self.pipelines[usize::from(reversed)];
        self.pass
            .draw_fullscreen(cmd, pipeline, (&[set], bytemuck::bytes_of(&push)));
        self.pass.end(cmd);
        self.gpu.transitions(
            cmd,
            &[Transition(
                depth.layer(),
                aspects,
                (read, depth.final_layout),
                SAMPLED,
                ANY,
            )],
        );
        self.slots[slot] = Some(input);
        Ok(())
    }
}
