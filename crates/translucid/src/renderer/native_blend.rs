//! The yardstick every speed figure is measured against: what an engine writes for its
//! transparent draws. One hardware pass, the methods' shading, the draws in submission order,
//! blended straight into the engine's colour image against its depth (dual-source, so that
//! coloured transmittance blends as `blend` does): no target of translucid's, no copy in or
//! out. It is not a method (it is not exact, and users do not pick it); the bench and the
//! example host record it beside each method on the same renderer, so that it draws the same
//! frame from the same slot data.

use super::host_device::HostFrameKind;
use super::Renderer;
use crate::assets::{GpuScene, MeshStages};
use crate::gpu::{
    vk, Blend, DepthMode, EnginePass, Gpu, GraphicsPipeline, HostImage, HostTargets, PipelineState,
};
use crate::interface::specialization::Specialization;
use crate::{Error, Result};
use std::sync::Arc;

/// (back faces kept, back faces culled)
type MeshPipelines = (Arc<GraphicsPipeline>, Arc<GraphicsPipeline>);

/// The yardstick's render passes, one per kind of engine image (formats and layouts) it was
/// given, each with its pipelines: kept while the renderer lives, since frames in flight
/// may draw through any of them.
#[derive(Default)]
pub(super) struct NativeBlend {
    passes: Vec<EngineBlendPass>,
}

struct EngineBlendPass {
    pass: EnginePass,
    /// Testing depth growing away from the eye (LESS), and reversed-Z depth (GREATER).
    pipelines: [MeshPipelines; 2],
}

/// Whether the yardstick's pass can blend into colour images of `format`: dual-source
/// blending on an attachment of that format.
pub(super) fn can_blend_into(gpu: &Gpu, format: vk::Format) -> bool {
    gpu.info().dual_source_blend
        && gpu
            .format_features(format)
            .contains(vk::FormatFeatureFlags::COLOR_ATTACHMENT_BLEND)
}

impl EngineBlendPass {
    fn new(
        gpu: &Gpu,
        gpu_scene: &GpuScene,
        (colour, depth): (&HostImage, &HostImage),
        slots: usize,
    ) -> Result<Self> {
        let format = colour.format;
        if !can_blend_into(gpu, format) {
            return Err(Error::HostRequirements(format!(
                "native_blend blends into the engine's colour image with dual-source blending: \
                 {} cannot for {format:?}",
                gpu.info().name
            )));
        }
        let pass = EnginePass::new(gpu, colour, Some(depth), slots)?;
        let pipelines = |depth| {
            gpu_scene.mesh_pipelines_with(
                gpu,
                pass.render_pass,
                MeshStages::Plain,
                crate::spirv!("blend/blend.frag"),
                &[],
                &PipelineState {
                    blends: &[Blend::PremultipliedTransmittance],
                    depth,
                    constants: &Specialization::NONE,
                    vertex_input: true,
                },
            )
        };
        let pipelines = [
            pipelines(DepthMode::Less(false))?,
            pipelines(DepthMode::Greater(false))?,
        ];
        Ok(Self { pass, pipelines })
    }
}

impl Renderer {
    /// Records the yardstick for this renderer's frame into the engine's command buffer:
    /// its transparent draws blended unsorted, in one pass, straight into `targets`' colour
    /// against its depth (see the module's comment). It takes a frame slot like
    /// [`Renderer::record_host`] and completes through [`Renderer::complete_host`], whose
    /// one stage, "native blend", is the pass's GPU time; the method learns nothing from it.
    ///
    /// # Safety
    /// As [`Renderer::record_host`]; besides, the colour image has COLOR_ATTACHMENT usage and
    /// the depth image DEPTH_STENCIL_ATTACHMENT usage.
    pub unsafe fn record_native_blend(&mut self, targets: &HostTargets) -> Result<()> {
        self.record_engine_blend(targets, "native blend", HostFrameKind::NativeBlend)
    }

    /// The index of the yardstick's pass (and pipelines) into images like `colour` and
    /// `depth` (their formats and layouts), built now if no earlier frame drew into such.
    pub(super) fn engine_blend_pass(
        &mut self,
        colour: &HostImage,
        depth: &HostImage,
    ) -> Result<usize> {
        let passes = &mut self.native_blend.passes;
        if let Some(i) = passes.iter().position(|p| p.pass.fits(colour, Some(depth))) {
            return Ok(i);
        }
        let slots = self.timestamps.len();
        let made = EngineBlendPass::new(&self.gpu, &self.gpu_scene, (colour, depth), slots)?;
        passes.push(made);
        Ok(passes.len() - 1)
    }

    /// One frame of the yardstick's pass into `targets`, its stage named `stage`: the
    /// yardstick's frame, or the `blend` method's on an engine's device.
    pub(super) fn record_engine_blend(
        &mut self,
        targets: &HostTargets,
        stage: &'static str,
        kind: HostFrameKind,
    ) -> Result<()> {
        let (gpu, slot) = self.begin_host_frame(targets)?;
        let cmd = targets.cmd;
        let index = self.engine_blend_pass(&targets.colour, &targets.depth)?;
        let native = &mut self.native_blend.passes[index];
        let images = (&targets.colour, Some(&targets.depth));
        let reversed = self.scene.camera.reversed_depth();
        let extent = self.targets.extent;
        native.pass.begin(cmd, images, slot, (extent, reversed))?;
        let pipelines = &native.pipelines[usize::from(reversed)];
        self.gpu_scene.draw(
            &gpu,
            cmd,
            &self.gpu_scene.transparent_calls,
            (&pipelines.0, &pipelines.1),
        );
        native.pass.end(cmd);
        self.timestamps[slot].mark(cmd, stage);
        self.end_host_frame(&gpu, cmd, slot, kind)
    }
}
