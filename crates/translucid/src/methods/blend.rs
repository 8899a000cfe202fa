//! `blend`: unsorted hardware alpha blending. Depth test on, depth write off, submission
//! order; polychrome transmittance through dual-source blending (`dst = L + T ⊙ dst`).
//! Correct only when the submission happens to be sorted back to front and nothing
//! interpenetrates. On an engine's device it is the yardstick's pass, straight into the
//! engine's images (`renderer/native_blend.rs`), so that it costs what the engine's own
//! blend does.

use super::{Method, RecordContext};
use crate::assets::GpuScene;
use crate::frame::FrameTargets;
use crate::gpu::{Gpu, GraphicsPipeline, RenderTarget};
use crate::{Error, Result};

pub struct Blend {
    target: RenderTarget,
    /// (back faces kept, back faces culled)
    pipelines: (
        std::sync::Arc<GraphicsPipeline>,
        std::sync::Arc<GraphicsPipeline>,
    ),
}

impl Blend {
    pub fn new(gpu: &Gpu, gpu_scene: &GpuScene, targets: &FrameTargets) -> Result<Self> {
        if !gpu.info().dual_source_blend {
            return Err(Error::DeviceLacks(format!(
                "{} lacks dual-source blending, which the blend method needs for coloured transmittance",
                gpu.info().name
            )));
        }
        let target = targets.render_target(gpu, false)?;
        let pipelines = gpu_scene.mesh_pipelines(
            gpu,
            target.render_pass,
            crate::spirv!("blend/blend.frag"),
            false,
            crate::gpu::Blend::PremultipliedTransmittance,
        )?;
        Ok(Self { target, pipelines })
    }
}

impl Method for Blend {
    fn name(&self) -> &'static str {
        "blend"
    }

    fn record(&mut self, ctx: &mut RecordContext<'_>) -> Result<()> {
        self.target.begin(ctx.cmd, ctx.targets.extent, [0.0; 4]);
        ctx.gpu_scene.draw(
            ctx.gpu,
            ctx.cmd,
            &ctx.gpu_scene.transparent_calls,
            (&self.pipelines.0, &self.pipelines.1),
        );
        self.target.end(ctx.cmd);
        ctx.timestamps.mark(ctx.cmd, "blend");
        Ok(())
    }

    fn blends_in_place(&self) -> bool {
        true
    }
}
