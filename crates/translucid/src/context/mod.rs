//! The object model an engine drives translucid through (the C API is a thin layer over it):
//! assets created and destroyed by handle at any time, frames made from draws by handle, a
//! few renderers kept and shared between the frames that fit them, and frames recorded on the
//! engine's device tracked in flight until the engine says they ran.
//!
//! - [`handles`]: generational handles; a stale or foreign one is an error.
//! - [`assets`]: the live meshes, textures and materials.
//! - [`renderers`]: the renderers over the assets, each for one method and its settings, and
//!   the uploads they share (destroyed assets kept in place while most of them is alive).
//! - [`frames`]: what a frame keeps once made.
//! - [`flight`]: the order of the frames in flight on the engine's device.
//! - This module: [`Context`], which ties them together.

pub mod assets;
pub mod background;
pub mod flight;
pub mod frames;
pub mod handles;
pub mod renderers;

use crate::gpu::{Gpu, HostImage, HostTargets};
use crate::renderer::{HostFrame, Renderer};
use crate::scene::{Camera, Material, Mesh, Texture};
use crate::{Error, OpaqueLayer, Result};
use assets::{Assets, Destroyed, MaterialRecord};
use flight::Flight;
use frames::FrameRecord;
use handles::{Kind, Slots};
use renderers::{FrameRequest, Renderers};

/// What completing a frame in flight found.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Completion {
    /// Its commands have not all run yet: try again later.
    NotReady,
    /// Done, all of it right.
    Complete,
    /// Done, but past a documented limit: not all of it is right (the buffers have grown,
    /// and recording it again renders it right).
    Degraded,
}

/// What a frame on the engine's device records: the renderer's method, or the yardstick
/// (`Renderer::record_native_blend`).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Recording {
    Method,
    NativeBlend,
}

/// One view of a frame on the engine's device: its camera, and the engine's command buffer
/// and images with the place (layers, corner) it is drawn in.
pub struct HostView {
    pub camera: Camera,
    pub targets: HostTargets,
}

/// One device and every object made on it.
pub struct Context {
    /// First, so that it is dropped first: its threads are waited for before anything they
    /// use goes (the engine destroys its device once the context is gone).
    background: background::Background,
    gpu: Gpu,
    assets: Assets,
    renderers: Renderers,
    frames: Slots<FrameRecord>,
    /// Frames recorded on the engine's device and not yet completed.
    flight: Flight,
    /// The most views a frame on the engine's device may have.
    views_per_frame: u32,
    /// The largest frame index of a frame made so far.
    last_frame_index: u64,
    /// The pipelines alive at the last trim, kept for the renderers made after it.
    held_pipelines: Option<crate::gpu::HeldPipelines>,
}

/// The GPU memory a context holds, by what it is for (bytes).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct MemoryUse {
    /// Device-local: the assets (vertices, textures, materials), the frame targets and the
    /// methods' working buffers.
    pub device_local: u64,
    /// Host-visible, written by the host for each frame (one copy per frame in flight).
    pub per_frame: u64,
    /// Host-visible staging of uploads not known to have run yet.
    pub staging: u64,
    /// Host-visible memory the GPU writes for the host: counters, timestamps, readbacks.
    pub readback: u64,
}

impl MemoryUse {
    pub fn total(&self) -> u64 {
        self.device_local + self.per_frame + self.staging + self.readback
    }
}

impl Context {
    /// A context on `gpu` for up to `frames_in_flight` frames in flight of up to
    /// `views_per_frame` views each (engine's device; standalone frames complete as they are
    /// made, one view each). Each view of a frame in flight takes a slot of per-frame data
    /// in the renderer that records it.
    pub fn new(gpu: Gpu, frames_in_flight: u32, views_per_frame: u32) -> Self {
        let tag = handles::next_context_tag();
        Self {
            background: background::Background::default(),
            gpu,
            assets: Assets::new(tag),
            renderers: Renderers::new(frames_in_flight * views_per_frame),
            frames: Slots::new(Kind::Frame, tag),
            flight: Flight::new(frames_in_flight),
            views_per_frame,
            last_frame_index: 0,
            held_pipelines: None,
        }
    }

    /// The GPU memory the context holds now, by what it is for.
    pub fn memory(&self) -> MemoryUse {
        use crate::gpu::MemoryRole;
        let mut used = MemoryUse::default();
        for a in self.gpu.allocations() {
            let bytes = match a.role {
                MemoryRole::PerFrame => &mut used.per_frame,
                MemoryRole::Staging => &mut used.staging,
                MemoryRole::Resource if a.host_visible() => &mut used.readback,
                MemoryRole::Resource => &mut used.device_local,
            };
            *bytes += a.bytes;
        }
        used
    }

    /// Frees what no frame in flight uses: the renderers idle now, with their frame targets
    /// and working buffers, sized for the largest frame each drew. Their pipelines and what
    /// their buffers learned are kept, and the assets stay uploaded: the next frame builds
    /// no pipeline, and allocates its buffers anew for its own size (after a resolution
    /// drop, less). Returns the bytes freed.
    pub fn trim(&mut self) -> u64 {
        let before = self.memory().total();
        self.held_pipelines = Some(self.gpu.hold_pipelines());
        self.renderers.free_idle();
        before.saturating_sub(self.memory().total())
    }

    pub fn gpu(&self) -> &Gpu {
        &self.gpu
    }

    /// The largest frame index of a frame made so far: later frames may not go below it.
    pub fn last_frame_index(&self) -> u64 {
        self.last_frame_index
    }

    /// Makes `mesh` an asset (validated by the caller: `Mesh::validate`).
    pub fn create_mesh(&mut self, mesh: Mesh) -> Result<u64> {
        let handle = self.assets.meshes.insert(mesh)?;
        self.assets.generation += 1;
        Ok(handle)
    }

    pub fn mesh(&self, handle: u64) -> Result<&Mesh> {
        self.assets.meshes.get(handle)
    }

    /// Moves the mesh's vertices from `first` on to `positions` (finite), in every renderer
    /// that takes new frames; frames in flight keep the old ones.
    pub fn update_mesh(
        &mut self,
        handle: u64,
        first: usize,
        positions: &[glam::Vec3],
    ) -> Result<()> {
        let mesh = self.assets.meshes.get_mut(handle)?;
        let total = mesh.positions.len();
        let end = first
            .checked_add(positions.len())
            .filter(|&end| end <= total);
        let Some(end) = end.filter(|_| !positions.is_empty()) else {
            return Err(Error::TooLarge(format!(
                "vertices {first} to {} of a mesh of {total}: vertex_count must be at least 1 \
                 and first_vertex + vertex_count at most the mesh's vertex_count",
                first as u64 + positions.len() as u64
            )));
        };
        if let Some(i) = positions.iter().position(|p| !p.is_finite()) {
            return Err(Error::InvalidArgument(format!(
                "vertex {i} of the positions is {}; positions must be finite",
                positions[i]
            )));
        }
        mesh.positions[first..end].copy_from_slice(positions);
        // The mesh's positions, not a copy: particles update every frame.
        let positions = &self.assets.meshes.get(handle)?.positions;
        self.renderers.update_mesh(handle, positions)
    }

    pub fn destroy_mesh(&mut self, handle: u64) -> Result<()> {
        let mesh = self.assets.meshes.remove(handle)?;
        self.asset_destroyed(Destroyed::Mesh(handle, mesh));
        Ok(())
    }

    /// Makes `texture` an asset (validated by the caller).
    pub fn create_texture(&mut self, texture: Texture) -> Result<u64> {
        let handle = self.assets.textures.insert(texture)?;
        self.assets.generation += 1;
        Ok(handle)
    }

    /// A material using a texture is no longer drawn once the texture is destroyed.
    pub fn destroy_texture(&mut self, handle: u64) -> Result<()> {
        let texture = self.assets.textures.remove(handle)?;
        self.asset_destroyed(Destroyed::Texture(handle, texture));
        Ok(())
    }

    /// Makes `material` an asset, with texture `texture` (a live texture's handle).
    pub fn create_material(&mut self, material: Material, texture: Option<u64>) -> Result<u64> {
        if let Some(texture) = texture {
            self.assets.textures.get(texture)?;
        }
        let handle = self
            .assets
            .materials
            .insert(MaterialRecord { material, texture })?;
        self.assets.generation += 1;
        Ok(handle)
    }

    pub fn destroy_material(&mut self, handle: u64) -> Result<()> {
        let record = self.assets.materials.remove(handle)?;
        self.asset_destroyed(Destroyed::Material(handle, record));
        Ok(())
    }

    /// Notes that an asset was destroyed (removed from its slots): the uploads keep its
    /// place while most of them is alive, else the next frame uploads the assets anew.
    fn asset_destroyed(&mut self, destroyed: Destroyed) {
        self.assets.generation += 1;
        if !self.renderers.bury(destroyed) {
            self.assets.last_destroyed = self.assets.generation;
        }
    }

    /// Declares that the frames may draw `content` and what `request` draws (added to what
    /// was declared before), and builds now what frames like `request` need: the renderer
    /// for its method and settings up to its size, over the current assets, with every
    /// shader of every frame within the declaration, and the superset variant
    /// ([`RasterFeatures::superset`]) that frames past it draw with. Frames of that method
    /// and those settings, up to that size, then build no pipeline, also when assets
    /// streamed in bring content they did not draw before (see [`DeclaredContent`] for what
    /// it covers). Frames draw with the declared variants whether or not they need all of
    /// them, textures apart (both their variants are built, and a frame takes its own).
    /// Returns the pipelines built and the bytes of GPU memory allocated.
    ///
    /// On an engine's device, `engine_images` (colour, depth) are images like those the
    /// frames will record into (their formats and layouts; the handles are not used): what
    /// the first frame into such images would build for them is built now too
    /// ([`crate::renderer::Renderer::prepare_host`]).
    ///
    /// [`DeclaredContent`]: crate::methods::bins::features::DeclaredContent
    /// [`RasterFeatures::superset`]: crate::methods::bins::features::RasterFeatures::superset
    pub fn prepare(
        &mut self,
        request: &FrameRequest,
        content: crate::methods::bins::features::DeclaredContent,
        engine_images: Option<(HostImage, HostImage)>,
    ) -> Result<(u64, u64)> {
        self.check_engine_images(engine_images)?;
        let before = built_so_far(&self.gpu);
        let drawn = self.renderers.drawn_content(&self.assets, request)?;
        self.renderers.declare(content);
        self.renderers.declare_drawn(&request.key, drawn);
        let kept = self.renderers.for_frame(&self.gpu, &self.assets, request)?;
        if let Some((colour, depth)) = &engine_images {
            kept.renderer.prepare_host(colour, depth)?;
        }
        Ok(built_since(&self.gpu, before))
    }

    /// As [`Self::prepare`], but on a thread of its own: returns once the work has started.
    /// Frames recorded meanwhile draw with what was declared before (content past it with
    /// the superset variant where the loop was prepared before, else built when first
    /// drawn, as without preparing). The work takes effect only where
    /// [`Self::prepare_status`] finds it finished, so that the engine chooses the frame:
    /// `content` is declared, and the renderers made from then on find every pipeline built
    /// (the next frame of each method makes its renderer anew without compiling; its
    /// buffers are allocated again).
    pub fn prepare_in_background(
        &mut self,
        request: &FrameRequest,
        content: crate::methods::bins::features::DeclaredContent,
        engine_images: Option<(HostImage, HostImage)>,
    ) -> Result<()> {
        self.check_engine_images(engine_images)?;
        let (inputs, drawn) =
            self.renderers
                .inputs_for(&self.gpu, &self.assets, request, content)?;
        let declaration = background::Declaration {
            content,
            drawn: (request.key.clone(), drawn),
        };
        self.background.start(inputs, engine_images, declaration)
    }

    /// Where the background preparation stands, taking in (declaring the content of) the
    /// jobs that finished: building, or every job taken in (and the pipelines those taken in
    /// since the last call built); a job that failed gives its error once, and its content
    /// is not declared.
    pub fn prepare_status(&mut self) -> Result<background::PrepareStatus> {
        for declaration in self.background.take_finished() {
            self.renderers.declare(declaration.content);
            self.renderers
                .declare_drawn(&declaration.drawn.0, declaration.drawn.1);
        }
        self.background.status()
    }

    fn check_engine_images(&self, engine_images: Option<(HostImage, HostImage)>) -> Result<()> {
        let Some((colour, depth)) = engine_images else {
            return Ok(());
        };
        if !self.gpu.is_host_device() {
            return Err(Error::InvalidArgument(
                "engine images are prepared for on a context on the engine's device \
                 (host-device mode); a standalone context has none"
                    .into(),
            ));
        }
        self.gpu.check_host_formats(&colour, &depth)
    }

    /// Renders `request` on translucid's own device, over `layer` (else over its opaque
    /// draws), and waits for it; the frame's handle.
    pub fn render(&mut self, request: &FrameRequest, layer: Option<&OpaqueLayer>) -> Result<u64> {
        if self.gpu.is_host_device() {
            return Err(Error::InvalidArgument(
                "rendering on translucid's own device needs a standalone context; on the \
                 engine's device frames are recorded"
                    .into(),
            ));
        }
        let before = built_so_far(&self.gpu);
        let kept = self.renderers.for_frame(&self.gpu, &self.assets, request)?;
        let id = kept.id;
        let rendered = match layer {
            Some(layer) => kept.renderer.render_over(layer),
            None => kept.renderer.render(false),
        };
        // A renderer whose frame failed is not kept: the next frame starts afresh.
        let frame = rendered.inspect_err(|_| self.renderers.retire(id))?;
        let mut record = FrameRecord::rendered(request.method, frame, id, request.frame_index);
        record.built = built_since(&self.gpu, before);
        let handle = self.frames.insert(record)?;
        self.note_frame_index(request.frame_index);
        Ok(handle)
    }

    /// Whether another frame may be recorded on the engine's device: not while as many as the
    /// context was made for are in flight.
    pub fn flight_room(&self) -> Result<()> {
        self.flight.room()
    }

    /// Whether a frame of `count` views may be recorded: 1 to the views per frame the context
    /// was made for.
    pub fn check_view_count(&self, count: usize) -> Result<()> {
        if count == 0 || count > self.views_per_frame as usize {
            return Err(Error::InvalidArgument(format!(
                "{count} view(s) in one frame; the context was made for 1 to {} \
                 (translucid_host_views_create_info.views_per_frame)",
                self.views_per_frame
            )));
        }
        Ok(())
    }

    /// Records `request` into the engine's command buffer, once for each of `views` (the
    /// method, or the yardstick), in flight until [`Self::complete`] or [`Self::abandon`];
    /// the frame's handle. The views share the frame's uploads; each is recorded after the
    /// one before it, with its own camera and its own slot of per-frame data.
    ///
    /// # Safety
    /// As [`crate::renderer::Renderer::record_host`], for each view: its targets name a
    /// recording command buffer outside a render pass and images of the frame's size or
    /// larger with the documented usages, all of the engine's device this context wraps;
    /// an image a view shares with an earlier one is in the layout that one left it in.
    pub unsafe fn record(
        &mut self,
        request: &mut FrameRequest,
        views: &[HostView],
        recording: Recording,
    ) -> Result<u64> {
        self.flight_room()?;
        self.check_view_count(views.len())?;
        let count = views.len();
        let before = built_so_far(&self.gpu);
        request.camera = views[0].camera;
        let kept = self.renderers.for_frame(&self.gpu, &self.assets, request)?;
        let id = kept.id;
        // SAFETY: the caller's, above.
        if let Err(e) = unsafe { record_views(&mut kept.renderer, views, recording) } {
            // Part of the frame may be recorded (the engine resets its command buffer), and
            // the renderer believes it: it takes no new frame.
            self.renderers.retire(id);
            return Err(e);
        }
        kept.in_flight += count;
        let size = (request.width, request.height);
        let mut record = FrameRecord::recorded(request.method, size, id, request.frame_index);
        record.views = count as u32;
        record.built = built_since(&self.gpu, before);
        let handle = self.frames.insert(record).inspect_err(|_| {
            // Recorded but untracked: the renderer must not be trusted again.
            self.renderers.frames_abandoned(id, count);
            self.renderers.retire(id);
        })?;
        self.flight.recorded(handle);
        self.note_frame_index(request.frame_index);
        Ok(handle)
    }

    /// Completes `frame`, whose commands the engine says have run, and the frames recorded
    /// before it (they ran first, on one queue).
    pub fn complete(&mut self, frame: u64) -> Result<Completion> {
        self.frames.get(frame)?;
        for older in self.flight.to_complete(frame)? {
            let result = self.complete_oldest();
            if older == frame {
                return result;
            }
            match result {
                Ok(Completion::NotReady) => return Ok(Completion::NotReady),
                Err(e) => return Err(e.prefixed("completing an older frame in flight first")),
                Ok(_) => {}
            }
        }
        Err(Error::Internal(
            "a frame in flight was not completed".into(),
        ))
    }

    /// Completes the oldest frame in flight.
    fn complete_oldest(&mut self) -> Result<Completion> {
        let Some(frame) = self.flight.oldest() else {
            return Err(Error::InvalidArgument("no frame is in flight".into()));
        };
        let renderer = self.frames.get(frame)?.renderer;
        // Pipelines a completion builds (the variants the frame's counters call for) stall
        // the engine as a recording's would: the frame's statistics count them too.
        let before = built_so_far(&self.gpu);
        let kept = self
            .renderers
            .get_mut(renderer)
            .ok_or_else(|| Error::Internal("the frame's renderer is gone".into()))?;
        let views = self.frames.get(frame)?.views as usize;
        let done = if kept.failed {
            Err(Error::InvalidArgument(
                "an earlier frame recorded with the same renderer failed to complete; this \
                 frame's image is not known to be right"
                    .into(),
            ))
        } else {
            match complete_views(&mut kept.renderer, views) {
                Ok(None) => return Ok(Completion::NotReady),
                Ok(Some(done)) => Ok(done),
                Err(e) => {
                    kept.failed = true;
                    Err(e)
                }
            }
        };
        // The commands ran: the frame's flight is over whatever the method reports.
        let failed = kept.failed;
        for _ in 0..views {
            self.renderers.frame_ended(renderer);
        }
        self.flight.oldest_completed();
        if failed {
            self.renderers.retire(renderer);
        } else {
            self.renderers.free_unused(None);
        }
        let record = self.frames.get_mut(frame)?;
        record.in_flight = false;
        let done = done?;
        let degraded = done.iter().any(|view| view.overflowed);
        record.completed(done);
        let completion = built_since(&self.gpu, before);
        record.built = (record.built.0 + completion.0, record.built.1 + completion.1);
        Ok(if degraded {
            Completion::Degraded
        } else {
            Completion::Complete
        })
    }

    /// Ends `frame` and every frame recorded after it without completing them, and destroys
    /// `frame` (the later ones keep their handles, without statistics). Their renderers
    /// forget them and keep what they built: the next frames build nothing for them.
    pub fn abandon(&mut self, frame: u64) -> Result<()> {
        self.frames.get(frame)?;
        let mut abandoned: Vec<(u64, usize)> = Vec::new();
        for f in self.flight.abandon(frame)? {
            let record = self.frames.get(f)?;
            let (renderer, views) = (record.renderer, record.views as usize);
            match abandoned.iter_mut().find(|(id, _)| *id == renderer) {
                Some((_, frames)) => *frames += views,
                None => abandoned.push((renderer, views)),
            }
            if f == frame {
                self.frames.remove(f)?;
            } else {
                let record = self.frames.get_mut(f)?;
                record.in_flight = false;
                record.abandoned = true;
            }
        }
        // The frames abandoned are the newest in flight, so each renderer's are its newest
        // (a view is a frame to a renderer).
        for (renderer, frames) in abandoned {
            self.renderers.frames_abandoned(renderer, frames);
        }
        Ok(())
    }

    pub fn frame(&self, handle: u64) -> Result<&FrameRecord> {
        self.frames.get(handle)
    }

    /// Frees a frame; not one in flight, whose commands the GPU may still be running.
    pub fn destroy_frame(&mut self, handle: u64) -> Result<()> {
        if self.frames.get(handle)?.in_flight {
            return Err(Error::FrameInFlight(
                "the frame is in flight: complete it after its submission finished, or \
                 abandon it (translucid_frame_abandon) if the GPU is not running it"
                    .into(),
            ));
        }
        self.frames.remove(handle)?;
        Ok(())
    }

    fn note_frame_index(&mut self, index: u64) {
        self.last_frame_index = self.last_frame_index.max(index);
    }
}

/// Records each of `views` with `renderer`, set to the frame (the first view's camera): the
/// frame's draws are resolved once, and each view after the first changes only the camera.
///
/// # Safety
/// As [`Context::record`].
unsafe fn record_views(
    renderer: &mut Renderer,
    views: &[HostView],
    recording: Recording,
) -> Result<()> {
    for (i, view) in views.iter().enumerate() {
        if i > 0 {
            renderer.set_camera(view.camera)?;
        }
        // SAFETY: the caller's.
        unsafe {
            match recording {
                Recording::Method => renderer.record_host(&view.targets),
                Recording::NativeBlend => renderer.record_native_blend(&view.targets),
            }
        }?;
    }
    Ok(())
}

/// Completes the oldest `views` frames `renderer` recorded: the views of one frame, in one
/// command buffer. `None`, changing nothing, until all of them ran.
fn complete_views(renderer: &mut Renderer, views: usize) -> Result<Option<Vec<HostFrame>>> {
    if !renderer.host_frames_ran(views)? {
        return Ok(None);
    }
    (0..views)
        .map(|_| {
            renderer
                .complete_host()?
                .ok_or_else(|| Error::Internal("a view that ran had no timestamps to read".into()))
        })
        .collect::<Result<Vec<_>>>()
        .map(Some)
}

/// What the device has built so far: pipelines created, and bytes of GPU memory allocated.
fn built_so_far(gpu: &Gpu) -> (u64, u64) {
    (gpu.pipelines_created(), gpu.bytes_allocated())
}

/// What the device built since `before` ([`built_so_far`]).
fn built_since(gpu: &Gpu, before: (u64, u64)) -> (u64, u64) {
    let now = built_so_far(gpu);
    (now.0 - before.0, now.1 - before.1)
}
