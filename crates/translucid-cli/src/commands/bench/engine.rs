//! The bench's engine: a frame loop as an engine runs one, on a device translucid made and
//! then takes as the engine's (`Gpu::as_host_device`). The engine owns a colour image
//! (R16G16B16A16_SFLOAT) and a depth image (D32_SFLOAT, growing away from the eye), the
//! images the tests' engine uses (`translucid::gpu::EngineImages`); each frame its opaque
//! pass fills them (a copy of the frame's opaque layer, not timed), then it records
//! the method's frame (`Renderer::record_host`: everything translucid records, copies in and
//! out included, is the whole pass) and submits it; and the same again with the yardstick,
//! `native_blend` (`Renderer::record_native_blend`), on the same renderer and frame, before
//! or after the method's by turns.

use translucid::gpu::{vk, EngineImages, Gpu};
use translucid::renderer::{HostFrame, Renderer};
use translucid::OpaqueLayer;

/// One method's frames on the engine.
pub struct EngineLoop {
    /// Made on `host`; dropped first.
    pub renderer: Renderer,
    /// translucid over the engine's device.
    pub host: Gpu,
    images: EngineImages,
    /// The engine: the device translucid made, which submits.
    engine: Gpu,
    /// Frames so far: the yardstick goes first in odd ones, so that neither side always
    /// finds what the other left in the caches.
    frames: u64,
}

/// What one engine frame measured: the method's frame and the yardstick's, and the host
/// time each submission took from submission to completion.
pub struct EngineFrame {
    pub method: HostFrame,
    pub native: HostFrame,
    pub method_wall_ms: f64,
    pub native_wall_ms: f64,
    /// Host time recording the method's frame.
    pub record_ms: f64,
}

impl EngineLoop {
    /// The engine on `engine` (a device translucid made) with images of `width` x `height`,
    /// and a renderer made by `make` on translucid over it.
    pub fn new(
        engine: Gpu,
        (width, height): (u32, u32),
        make: impl FnOnce(&Gpu) -> translucid::Result<Renderer>,
    ) -> translucid::Result<Self> {
        let handles = engine.as_host_device().ok_or_else(|| {
            translucid::Error::HostFrame("the bench's engine needs a device of its own".into())
        })?;
        // SAFETY: the handles are `engine`'s live instance and device, which outlive `host`:
        // `Self` drops `renderer` and `host` before `engine`.
        let host = unsafe { Gpu::from_host(&handles) }?;
        let renderer = make(&host)?;
        let extent = vk::Extent2D { width, height };
        let images = EngineImages::new(&engine, extent, vk::Format::D32_SFLOAT, 0)?;
        Ok(Self {
            renderer,
            host,
            images,
            engine,
            frames: 0,
        })
    }

    /// One frame over `layer` (the frame's opaque layer, at the images' size): the method's
    /// and the yardstick's, taking turns at going first, each submitted and waited for.
    pub fn frame(&mut self, layer: &OpaqueLayer) -> translucid::Result<EngineFrame> {
        self.images.set_opaque(layer)?;
        let native_first = self.frames % 2 == 1;
        self.frames += 1;
        let mut native_frame = None;
        if native_first {
            native_frame = Some(self.submit(true)?);
        }
        let (record_ms, method_wall_ms, method) = self.submit(false)?;
        let (_, native_wall_ms, native) = match native_frame {
            Some(done) => done,
            None => self.submit(true)?,
        };
        Ok(EngineFrame {
            method,
            native,
            method_wall_ms,
            native_wall_ms,
            record_ms,
        })
    }

    /// Records the opaque pass and the method's frame (the yardstick's when `native`),
    /// submits, waits and completes it: host time recording, host time from submission to
    /// completion, and what the frame reported.
    fn submit(&mut self, native: bool) -> translucid::Result<(f64, f64, HostFrame)> {
        let (engine, images, renderer) = (&self.engine, &self.images, &mut self.renderer);
        let mut record_ms = 0.0;
        let mut submitted = std::time::Instant::now();
        engine.submit_and_wait(|cmd| {
            images.record_opaque(engine, cmd);
            let targets = images.targets(cmd);
            let started = std::time::Instant::now();
            // SAFETY: the engine's recording command buffer, outside a render pass, and its
            // live images of the renderer's size, in the layouts named, made with the usages
            // both recordings need; the submission is waited for before anything is dropped.
            unsafe {
                if native {
                    renderer.record_native_blend(&targets)
                } else {
                    renderer.record_host(&targets)
                }
            }?;
            record_ms = started.elapsed().as_secs_f64() * 1e3;
            submitted = std::time::Instant::now();
            Ok(())
        })?;
        let wall_ms = submitted.elapsed().as_secs_f64() * 1e3;
        let frame = renderer.complete_host()?.ok_or_else(|| {
            translucid::Error::HostFrame("a frame waited for did not complete".into())
        })?;
        Ok((record_ms, wall_ms, frame))
    }
}
