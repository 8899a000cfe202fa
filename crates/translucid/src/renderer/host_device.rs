//! Frames on the engine's device: recorded into the engine's command buffer over the engine's
//! images, submitted by the engine, completed when the engine says its submission finished.
//!
//! Where the engine's colour format blends, nothing is copied: `blend` draws straight into
//! the engine's images (`native_blend.rs`, one stage, "blend"), and the methods that
//! composite in place (exact, wavelet on the bins) sample the engine's depth where it is and
//! blend their transparent layer onto its colour, only where the layer has fragments. The
//! other methods, and every method over a colour format that does not blend, copy the
//! engine's colour and depth into the frame targets (the opaque layer, timed as "opaque"),
//! run as a standalone frame does, and copy the result back into the engine's colour image
//! ("output"). A frame is meant to be right on its one recording: bin lists past their
//! capacity are rasterized in bands within it. What the recording could not answer (more
//! bands than it records, rows still unfinished after its continuations, other buffers too
//! small) leaves the affected pixels with the engine's colour, and
//! [`Renderer::complete_host`] reports it once the frame completed, with the buffers already
//! grown, so that later frames are right.

use super::{method_ms, Renderer};
use crate::gpu::{
    memory_barrier, vk, Buffer, DepthImport, EngineDepthViews, Gpu, HostImage, HostTargets,
    MemoryLocation, HOST_DEPTH_FORMAT,
};
use crate::methods::{FrameCheck, FrameDone, InPlace};
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
    /// Transparent triangles left to rasterize after culling (the bin methods; 0 otherwise).
    pub triangles: u64,
    /// Compute dispatches the frame recorded (0 for the yardstick, which draws).
    pub dispatches: u64,
    /// Fragments blended unsorted for want of room (linked_list past a fixed node budget).
    pub tail_fragments: u64,
    /// Pixels with more layers than depth_peeling's fixed passes peel.
    pub unpeeled_pixels: u64,
    /// Bands the bin methods rasterized the frame in: more than one when their bin lists
    /// passed the capacity within the frame (the lists have grown for later frames).
    pub bands: u32,
    /// Pixel rows left with the engine's colour, past a documented limit of the method
    /// (exact: see the README's "When a frame is not right").
    pub degraded_rows: u64,
    /// The image the frame wrote is not all right: rows were left with the engine's colour
    /// (`degraded_rows`), or some buffer overflowed. The buffers have grown; recording the
    /// frame again renders it correctly.
    pub overflowed: bool,
}

/// What a frame on the engine's device recorded: the renderer's method, or the yardstick
/// ([`Renderer::record_native_blend`]), which its method has nothing to learn from.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(super) enum HostFrameKind {
    Method,
    NativeBlend,
}

/// A host-visible word that the host clears when it records a frame and the frame's last
/// command sets to the frame's number: it equals the number only once the commands ran.
pub(super) struct Completion {
    marker: Buffer,
    frame: u32,
}

impl Completion {
    fn new(gpu: &Gpu) -> Result<Self> {
        let marker = gpu.create_buffer(
            "host frame completion",
            4,
            vk::BufferUsageFlags::TRANSFER_DST,
            MemoryLocation::GpuToCpu,
        )?;
        Ok(Self { marker, frame: 0 })
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
        Ok(())
    }

    fn ran(&self) -> Result<bool> {
        Ok(self.marker.read_word_volatile()? == self.frame)
    }
}

impl Renderer {
    /// Records one frame into the engine's command buffer. Nothing is submitted. Up to the
    /// renderer's frames in flight may be recorded and not completed; past that, recording
    /// fails until [`Renderer::complete_host`] has seen the oldest one run. The frames must
    /// be submitted to one queue in the order they were recorded. When recording fails, the
    /// command buffer may hold part of a frame: reset it rather than submit it; uploads it
    /// would have carried (textures, moved vertices) go with the next frame recorded.
    ///
    /// # Safety
    /// `targets` names live objects of the engine's device this renderer's [`Gpu`] wraps:
    /// a command buffer in the recording state outside any render pass, and colour and depth
    /// images of at least the frame's size ([`Renderer::size`]), in the layouts named, with
    /// the usages [`HostTargets`] lists (for `blend`, attachment usages too). The renderer
    /// must not be dropped while the GPU may run the recorded commands: submit them at most
    /// once, and complete or discard them first.
    ///
    /// [`Gpu`]: crate::gpu::Gpu
    pub unsafe fn record_host(&mut self, targets: &HostTargets) -> Result<()> {
        // blend draws straight into the engine's images, and the methods that composite in
        // place blend onto its colour, where its format blends; else they go through the
        // frame targets as the other methods do.
        let blends = super::native_blend::can_blend_into(&self.gpu, targets.colour.format);
        if blends && self.method.blends_in_place() {
            return self.record_engine_blend(targets, "blend", HostFrameKind::Method);
        }
        if blends && self.method.composites_in_place() {
            return self.record_in_place(targets);
        }
        let (gpu, slot) = self.begin_host_frame(targets)?;
        let cmd = targets.cmd;
        // translucid tests depth growing away from the eye, in D32_SFLOAT: other depth is
        // sampled and converted.
        let reversed = self.scene.camera.reversed_depth();
        let extent = self.targets.extent;
        if reversed || targets.depth.format != HOST_DEPTH_FORMAT {
            gpu.record_host_input(targets, extent, &self.targets.colour, None);
            let import = self.depth_import()?;
            import.record(cmd, slot, &targets.depth, (extent, reversed))?;
        } else {
            let depth = Some(&self.targets.depth);
            gpu.record_host_input(targets, extent, &self.targets.colour, depth);
        }
        self.timestamps[slot].mark(cmd, "opaque");
        self.record_method(&gpu, cmd, None)?;
        gpu.record_host_output(targets, extent, &self.targets.colour);
        self.timestamps[slot].mark(cmd, "output");
        self.end_host_frame(&gpu, cmd, slot, HostFrameKind::Method)
    }

    /// Builds now what the first frame into engine images like `colour` and `depth` (their
    /// formats and layouts; the handles are not used) would build: `blend`'s pass into
    /// them, the composite of a method that composites in place, or the import of depth
    /// the other methods cannot copy. Frames into such images then build no pipeline for
    /// them. The frame camera's depth direction is the one this renderer was set to.
    pub fn prepare_host(&mut self, colour: &HostImage, depth: &HostImage) -> Result<()> {
        let gpu = self.gpu.clone();
        gpu.check_host_formats(colour, depth)?;
        let blends = super::native_blend::can_blend_into(&gpu, colour.format);
        if blends && self.method.blends_in_place() {
            return self.engine_blend_pass(colour, depth).map(|_| ());
        }
        if blends && self.method.composites_in_place() {
            return self.method.prepare_composite(colour);
        }
        if self.scene.camera.reversed_depth() || depth.format != HOST_DEPTH_FORMAT {
            self.depth_import()?;
        }
        Ok(())
    }

    /// The pass that imports depth the method cannot copy, made on first use.
    fn depth_import(&mut self) -> Result<&mut DepthImport> {
        let import = match self.depth_import.take() {
            Some(import) => import,
            None => DepthImport::new(&self.gpu, &self.targets.depth, self.timestamps.len())?,
        };
        Ok(self.depth_import.insert(import))
    }

    /// A frame of a method that composites in place: the engine's depth sampled where it is,
    /// the method's composite blended onto its colour; no copy, no frame target.
    fn record_in_place(&mut self, targets: &HostTargets) -> Result<()> {
        let (gpu, slot) = self.begin_host_frame(targets)?;
        let cmd = targets.cmd;
        let views = self
            .engine_depth_views
            .get_or_insert_with(|| EngineDepthViews::new(&gpu, self.timestamps.len()));
        let depth = views.view(slot, &targets.depth)?;
        gpu.record_engine_depth_to_sampled(targets);
        let in_place = InPlace {
            colour: targets.colour,
            depth,
            reversed: self.scene.camera.reversed_depth(),
        };
        self.record_method(&gpu, cmd, Some(in_place))?;
        gpu.record_engine_depth_to_final(targets);
        self.end_host_frame(&gpu, cmd, slot, HostFrameKind::Method)
    }

    /// What every frame on the engine's device records first, after checking `targets` and
    /// that a slot is free: the slot's frame data, pending uploads, the first timestamp, a
    /// barrier after the frames before it, moved vertices. Returns the device and the slot.
    pub(super) fn begin_host_frame(&mut self, targets: &HostTargets) -> Result<(Gpu, usize)> {
        let gpu = self.gpu.clone();
        if !gpu.is_host_device() {
            return Err(Error::HostFrame(
                "recording into an engine's command buffer needs a context on the engine's \
                 device (host-device mode)"
                    .into(),
            ));
        }
        gpu.check_host_targets(targets)?;
        let slots = self.timestamps.len();
        if self.in_flight.len() >= slots {
            return Err(Error::HostFrame(format!(
                "{slots} recorded frame(s) not completed: the renderer was made for {slots} in \
                 flight; complete the oldest first"
            )));
        }
        while self.completions.len() < slots {
            self.completions.push(Completion::new(&gpu)?);
        }
        let slot = self.slot;
        self.prepare_slot(slot)?;
        gpu.reset_peak_memory();
        let cmd = targets.cmd;
        self.slot_dispatches[slot] = gpu.dispatches_recorded();
        self.gpu_scene.record_pending_uploads(&gpu, cmd);
        self.timestamps[slot].begin(cmd);
        // Frame targets and the methods' working buffers are shared by the slots: the frames
        // recorded before (in flight, earlier on the queue) finish with them first. Frames
        // therefore run one after another on the GPU; only per-frame data is per slot.
        let any = (
            vk::PipelineStageFlags::ALL_COMMANDS,
            vk::AccessFlags::MEMORY_READ | vk::AccessFlags::MEMORY_WRITE,
        );
        memory_barrier(&gpu, cmd, any, any);
        self.gpu_scene
            .record_moved_vertices(&gpu, cmd, &self.scene)?;
        Ok((gpu, slot))
    }

    /// What every frame on the engine's device records last: its completion marker; then the
    /// frame is in flight.
    pub(super) fn end_host_frame(
        &mut self,
        gpu: &Gpu,
        cmd: vk::CommandBuffer,
        slot: usize,
        kind: HostFrameKind,
    ) -> Result<()> {
        self.slot_dispatches[slot] = gpu.dispatches_recorded() - self.slot_dispatches[slot];
        self.completions[slot].record(gpu, cmd)?;
        self.gpu_scene.frame_recorded_in_flight();
        self.in_flight.push_back((slot, kind));
        self.slot = (slot + 1) % self.timestamps.len();
        Ok(())
    }

    /// Reads the oldest recorded frame's timestamps and counters once it has completed,
    /// growing the method's buffers if they overflowed. `None`, changing nothing, while that
    /// frame's commands have not run (not submitted, or still running), or when no frame is
    /// in flight. After an error the renderer is not to be used again.
    pub fn complete_host(&mut self) -> Result<Option<HostFrame>> {
        let Some(&(slot, kind)) = self.in_flight.front() else {
            return Ok(None);
        };
        if !self.completions[slot].ran()? {
            return Ok(None);
        }
        let Some(stages) = self.timestamps[slot].try_read()? else {
            return Ok(None);
        };
        self.in_flight.pop_front();
        let check = match kind {
            HostFrameKind::Method => self.method.frame_done(&FrameDone {
                gpu_scene: &self.gpu_scene,
                targets: &self.targets,
                slot,
            })?,
            HostFrameKind::NativeBlend => FrameCheck::default(),
        };
        self.gpu_scene.uploads_completed();
        Ok(Some(HostFrame {
            method_ms: method_ms(&stages),
            stages,
            peak_gpu_bytes: self.gpu.memory_in_use().1,
            fragments: check.fragments,
            triangles: check.triangles,
            dispatches: self.slot_dispatches[slot],
            tail_fragments: check.tail_fragments,
            unpeeled_pixels: check.unpeeled_pixels,
            bands: check.bands,
            degraded_rows: check.degraded_rows + check.unfinished_rows,
            overflowed: check.rerender || check.finish,
        }))
    }

    /// Whether the oldest `frames` frames recorded and not completed have all run (the views
    /// of one engine frame, completed together). False when fewer are in flight.
    pub fn host_frames_ran(&self, frames: usize) -> Result<bool> {
        if frames > self.in_flight.len() {
            return Ok(false);
        }
        for &(slot, _) in self.in_flight.iter().take(frames) {
            if !self.completions[slot].ran()? || self.timestamps[slot].try_read()?.is_none() {
                return Ok(false);
            }
        }
        Ok(true)
    }

    /// The newest `frames` frames recorded and not completed will never run: the engine
    /// dropped their commands unsubmitted (as for an out-of-date swapchain), or let them
    /// finish without completing them. The renderer forgets them and keeps everything it
    /// built (pipelines, grown buffers): the next frame is recorded into the oldest one's
    /// slot and carries the uploads and moved vertices they carried.
    pub fn abandon_host(&mut self, frames: usize) -> Result<()> {
        if frames > self.in_flight.len() {
            return Err(Error::Internal(format!(
                "{frames} frame(s) to abandon; {} in flight",
                self.in_flight.len()
            )));
        }
        let abandoned = self.in_flight.split_off(self.in_flight.len() - frames);
        if let Some(&(oldest, _)) = abandoned.front() {
            self.slot = oldest;
        }
        let method_frames = abandoned
            .iter()
            .filter(|(_, kind)| *kind == HostFrameKind::Method)
            .count() as u64;
        self.gpu_scene.frames_abandoned(frames as u64);
        self.method.frames_abandoned(method_frames);
        Ok(())
    }

    /// Frames recorded on the engine's device and not completed yet.
    pub fn frames_in_flight(&self) -> usize {
        self.in_flight.len()
    }
}
