//! Frames on the engine's device: recorded into the engine's command buffer over the engine's
//! images, submitted by the engine, completed when the engine says its submission finished.
//!
//! The frame copies the engine's colour and depth into the frame targets (the opaque layer,
//! timed as "opaque"), runs the method exactly as a standalone frame does, and copies the
//! result back into the engine's colour image ("output"). Overflow cannot re-render inside
//! the recording: [`Renderer::complete_host`] reports it after the fact, with the buffers
//! already grown, so recording the same frame again renders it correctly.

use super::{method_ms, Renderer};
use crate::gpu::{memory_barrier, vk, Buffer, Gpu, HostTargets, MemoryLocation};
use crate::{Error, Result};

/// What a host-device frame reports once the engine's submission completed.
#[derive(Clone, Debug)]
pub struct HostFrame {
    /// GPU time of each stage in milliseconds, in order ("opaque" is the copy of the engine's
    /// images, "output" the copy back).
    pub stages: Vec<(&'static str, f64)>,
    /// GPU time of the method's stages alone.
    pub method_ms: f64,
    /// Peak bytes of GPU memory allocated by translucid from recording to completion.
    pub peak_gpu_bytes: u64,
    /// Fragments composited, for methods that count them (0 otherwise).
    pub fragments: u64,
    /// A buffer overflowed: the image the frame wrote is wrong. The buffers have grown;
    /// recording the frame again renders it correctly.
    pub overflowed: bool,
}

/// A host-visible word that the host clears when it records a frame and the frame's last
/// command sets to the frame's number: it equals the number only once the commands ran.
pub(super) struct Completion {
    marker: Buffer,
    frame: u32,
    /// A frame is recorded and not completed: its resources must not be reused yet.
    pub(super) in_flight: bool,
}

impl Completion {
    fn new(gpu: &Gpu) -> Result<Self> {
        let marker = gpu.create_buffer(
            "host frame completion",
            4,
            vk::BufferUsageFlags::TRANSFER_DST,
            MemoryLocation::GpuToCpu,
        )?;
        Ok(Self {
            marker,
            frame: 0,
            in_flight: false,
        })
    }

    /// Clears the word and records the command that sets it, after everything else.
    fn record(&mut self, gpu: &Gpu, cmd: vk::CommandBuffer) -> Result<()> {
        self.frame = self.frame.wrapping_add(1).max(1);
        self.marker.write(0, &0u32.to_le_bytes())?;
        memory_barrier(
            gpu,
            cmd,
            (
                vk::PipelineStageFlags::ALL_COMMANDS,
                vk::AccessFlags::MEMORY_WRITE,
            ),
            (
                vk::PipelineStageFlags::TRANSFER,
                vk::AccessFlags::TRANSFER_WRITE,
            ),
        );
        gpu.cmd_update_buffer(cmd, &self.marker, 0, &self.frame.to_le_bytes());
        memory_barrier(
            gpu,
            cmd,
            (
                vk::PipelineStageFlags::TRANSFER,
                vk::AccessFlags::TRANSFER_WRITE,
            ),
            (vk::PipelineStageFlags::HOST, vk::AccessFlags::HOST_READ),
        );
        self.in_flight = true;
        Ok(())
    }

    fn ran(&self) -> Result<bool> {
        Ok(self.marker.read_word_volatile()? == self.frame)
    }
}

impl Renderer {
    /// Records one frame into the engine's command buffer. Nothing is submitted. Recording
    /// another frame fails until [`Renderer::complete_host`] has seen this one run.
    ///
    /// # Safety
    /// `targets` names live objects of the engine's device this renderer's [`Gpu`] wraps:
    /// a command buffer in the recording state outside any render pass, and colour and depth
    /// images of the renderer's size, in the layouts named, with the usages
    /// [`HostTargets`] lists. The renderer must not be dropped while the GPU may run the
    /// recorded commands: submit them at most once, and complete or discard them first.
    ///
    /// [`Gpu`]: crate::gpu::Gpu
    pub unsafe fn record_host(&mut self, targets: &HostTargets) -> Result<()> {
        let gpu = self.gpu.clone();
        if !gpu.is_host_device() {
            return Err(Error::HostFrame(
                "recording into an engine's command buffer needs a context on the engine's \
                 device (host-device mode)"
                    .into(),
            ));
        }
        gpu.check_host_targets(targets)?;
        if self.completion.as_ref().is_some_and(|c| c.in_flight) {
            return Err(Error::HostFrame(
                "the last frame recorded is not completed: one frame in flight".into(),
            ));
        }
        if self.completion.is_none() {
            self.completion = Some(Completion::new(&gpu)?);
        }
        gpu.reset_peak_memory();
        let cmd = targets.cmd;
        self.scene.record_pending_uploads(&gpu, cmd);
        self.timestamps.begin(cmd);
        gpu.record_host_input(targets, &self.targets.colour, &self.targets.depth);
        self.timestamps.mark(cmd, "opaque");
        self.record_method(&gpu, cmd)?;
        gpu.record_host_output(targets, &self.targets.colour);
        self.timestamps.mark(cmd, "output");
        match &mut self.completion {
            Some(c) => c.record(&gpu, cmd),
            None => Ok(()),
        }
    }

    /// Reads the completed frame's timestamps and counters, growing the method's buffers if
    /// they overflowed. `None`, changing nothing, while the frame's commands have not run
    /// (not submitted, or still running). After an error the renderer is not to be used again.
    pub fn complete_host(&mut self) -> Result<Option<HostFrame>> {
        match &self.completion {
            Some(c) if c.in_flight && c.ran()? => {}
            _ => return Ok(None),
        }
        let Some(stages) = self.timestamps.try_read()? else {
            return Ok(None);
        };
        if let Some(c) = &mut self.completion {
            c.in_flight = false;
        }
        let check = self.method.frame_done(&self.scene, &self.targets)?;
        self.scene.uploads_completed();
        Ok(Some(HostFrame {
            method_ms: method_ms(&stages),
            stages,
            peak_gpu_bytes: self.gpu.memory_in_use().1,
            fragments: check.fragments,
            overflowed: check.rerender || check.finish,
        }))
    }
}
