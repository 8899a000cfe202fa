//! Transparency methods, one module each, behind one small trait.
//!
//! A method is created for one uploaded scene and one frame size. Each frame it records its
//! passes into the frame's command buffer: it receives the opaque layer in the frame targets
//! (colour in COLOR_ATTACHMENT_OPTIMAL, depth in DEPTH_STENCIL_ATTACHMENT_OPTIMAL), depth-tests
//! against it, composites the transparent layer over the colour, and returns the targets in
//! the same layouts. It marks a timestamp after each of its stages.

mod blend;

use crate::gpu::{vk, Gpu, Timestamps};
use crate::renderer::{FrameTargets, GpuScene};
use crate::{Error, Result};

/// Every method's name, as the CLI and the C API spell it.
pub const NAMES: &[&str] = &["blend"];

/// What a method records into.
pub struct RecordContext<'a> {
    pub gpu: &'a Gpu,
    pub cmd: vk::CommandBuffer,
    pub scene: &'a GpuScene,
    pub targets: &'a FrameTargets,
    pub timestamps: &'a mut Timestamps,
}

pub trait Method {
    fn name(&self) -> &'static str;
    /// Records the transparent pass of one frame.
    fn record(&mut self, ctx: &mut RecordContext<'_>) -> Result<()>;
}

/// Creates the method called `name` for `scene` and `targets`.
pub fn create(
    name: &str,
    gpu: &Gpu,
    scene: &GpuScene,
    targets: &FrameTargets,
) -> Result<Box<dyn Method>> {
    match name {
        "blend" => Ok(Box::new(blend::Blend::new(gpu, scene, targets)?)),
        other => Err(Error::UnknownMethod(other.to_string(), NAMES.join(", "))),
    }
}
