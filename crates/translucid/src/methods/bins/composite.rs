//! The composite pass of the bin rasters on an engine's device ([`super::super::InPlace`]):
//! blends the transparent layer they left (`transparent_layer.glsl`) onto the engine's colour
//! image where it is, one quad over each block with a non-empty bin (the scan counts them
//! into the draw's indirect command), with dual-source blending: `colour = radiance +
//! transmittance x colour`. Pixels the submission did not write are discarded, so that they
//! keep the engine's colour bit for bit. Nothing is copied in or out.

use crate::gpu::{
    vk, Blend, Buffer, DepthMode, DescriptorLayout, DescriptorSet, EnginePass, Gpu, GpuImage,
    GraphicsPipeline, GraphicsPipelineDesc, HostImage, PipelineState, Resource,
};
use crate::interface::bins::{CompositePush, COMPOSITE_SET};
use crate::interface::specialization::Specialization;
use crate::Result;
use std::sync::Arc;

/// What one composite records: onto which colour image, for which slot and frame size, the
/// submission's stamp and the frame's blocks across, and the draw's indirect command.
pub struct CompositeFrame<'a> {
    pub colour: &'a HostImage,
    pub slot: usize,
    pub extent: vk::Extent2D,
    pub stamp: u32,
    pub bins_x: u32,
    pub draw: (&'a Buffer, u64),
}

pub struct Composite {
    gpu: Gpu,
    layout: DescriptorLayout,
    set: DescriptorSet,
    slots: usize,
    /// One render pass (and pipeline) per kind of colour image composited onto (format and
    /// layouts), kept while the bins live: frames in flight may draw through any of them.
    passes: Vec<(EnginePass, Arc<GraphicsPipeline>)>,
}

impl Composite {
    /// The pass over the listed blocks of `raster_bins` and the transparent `layer`'s two
    /// images (in GENERAL layout), for `slots` frames in flight.
    pub fn new(
        gpu: &Gpu,
        raster_bins: &Buffer,
        layer: &[GpuImage; 2],
        slots: usize,
    ) -> Result<Self> {
        let layout = DescriptorLayout::declared(
            gpu,
            &COMPOSITE_SET,
            vk::ShaderStageFlags::VERTEX | vk::ShaderStageFlags::FRAGMENT,
        )?;
        let set = layout.create_named_set(&[
            ("RasterBinBlock", Resource::Buffer(raster_bins)),
            ("u_transparentLayer", Resource::StorageImage(layer[0].view)),
            (
                "u_transparentLayerStamps",
                Resource::StorageImage(layer[1].view),
            ),
        ])?;
        Ok(Self {
            gpu: gpu.clone(),
            layout,
            set,
            slots,
            passes: Vec::new(),
        })
    }

    /// Records the pass; the transparent layer and the draw's command are written and
    /// visible to the vertex, fragment and indirect stages.
    pub fn record(&mut self, cmd: vk::CommandBuffer, frame: &CompositeFrame<'_>) -> Result<()> {
        let index = self.pass_for(frame.colour)?;
        let (pass, pipeline) = &mut self.passes[index];
        pass.begin(cmd, (frame.colour, None), frame.slot, (frame.extent, false))?;
        let push = CompositePush {
            bins_x: frame.bins_x,
            stamp: frame.stamp,
            extent: [frame.extent.width as f32, frame.extent.height as f32],
            origin_x: frame.colour.origin.x as u32,
            origin_y: frame.colour.origin.y as u32,
        };
        self.gpu.cmd_draw_indirect(
            cmd,
            pipeline,
            (&[self.set.raw], bytemuck::bytes_of(&push)),
            frame.draw,
        );
        pass.end(cmd);
        Ok(())
    }

    /// The index of the pass (and pipeline) onto colour images like `colour` (its format and
    /// layouts), built now if no earlier frame composited onto one.
    pub fn pass_for(&mut self, colour: &HostImage) -> Result<usize> {
        if let Some(i) = self.passes.iter().position(|(p, _)| p.fits(colour, None)) {
            return Ok(i);
        }
        let pass = EnginePass::new(&self.gpu, colour, None, self.slots)?;
        let pipeline = self.pipeline(pass.render_pass)?;
        self.passes.push((pass, pipeline));
        Ok(self.passes.len() - 1)
    }

    fn pipeline(&self, render_pass: vk::RenderPass) -> Result<Arc<GraphicsPipeline>> {
        GraphicsPipeline::shared(
            &self.gpu,
            &GraphicsPipelineDesc {
                vertex: crate::spirv!("bins/composite.vert"),
                geometry: None,
                fragment: crate::spirv!("bins/composite.frag"),
                vertex_stride: 0,
                attributes: &[],
                cull_back: false,
                depth_write: false,
                blend: Blend::None,
                render_pass,
                sets: &[&self.layout],
                push_bytes: std::mem::size_of::<CompositePush>() as u32,
            },
            &PipelineState {
                blends: &[Blend::PremultipliedTransmittance],
                depth: DepthMode::Off,
                constants: &Specialization::NONE,
                vertex_input: false,
            },
        )
    }
}
