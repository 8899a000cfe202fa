//! Frames, end to end: upload a scene's assets once, then per frame write what changed,
//! render the opaque layer, run a transparency method over it, read the result back, and time
//! every stage on the GPU.
//!
//! ```no_run
//! use translucid::{gpu::{Gpu, GpuOptions}, methods::MethodKind, renderer::Renderer};
//! use translucid::scene::{self, Camera, Projection};
//! let gpu = Gpu::new(&GpuOptions::from_env())?;
//! let scene = scene::load("particles")?;
//! let mut renderer = Renderer::new(&gpu, &scene, MethodKind::Exact, 1280, 720)?;
//! let orbit = scene::motion::Orbit::new(&scene);
//! let mut draws = Vec::new();
//! for index in 0..120 {
//!     orbit.transparent(&scene, index, &mut draws);
//!     let camera = Camera {
//!         // The engine's own matrix: reversed-Z, infinite far plane, TAA jitter.
//!         projection: Projection::Matrix(glam::Mat4::perspective_infinite_reverse_rh(
//!             0.8,
//!             16.0 / 9.0,
//!             0.1,
//!         )),
//!         jitter: glam::Vec2::new(0.25, -0.25),
//!         ..orbit.camera(&scene, index)
//!     };
//!     renderer.set_frame(&scene::FrameInput {
//!         camera,
//!         transparent: &draws,
//!         ..scene.frame_input()
//!     })?;
//!     let frame = renderer.render(false)?;
//!     if index >= 4 {
//!         assert_eq!((frame.pipelines_created, frame.bytes_allocated), (0, 0), "warm");
//!     }
//!     for (stage, ms) in &frame.stages { println!("{stage}: {ms:.3} ms"); }
//! }
//! # Ok::<(), translucid::Error>(())
//! ```
//!
//! (glam's `perspective_*` matrices are y up: this frame is upside down. An engine's Vulkan
//! projection has y negated; `Projection::Perspective` does that itself.)

mod host_device;
mod native_blend;
mod opaque_pass;
mod opaque_upload;

pub use crate::assets::{GpuScene, ResidentAssets};
pub use crate::frame::{FrameTargets, COLOUR_FORMAT, DEPTH_FORMAT};
pub use host_device::HostFrame;
pub use opaque_pass::Readback;

use crate::gpu::{vk, Gpu, Timestamps};
use crate::image::{Image, OpaqueLayer};
use crate::methods::{
    self, FrameDone, FrameSetup, InPlace, Method, MethodKind, MethodOptions, RecordContext,
};
use crate::scene::{FrameInput, Scene};
use crate::{Error, Result};
use glam::Vec3;
use opaque_pass::OpaquePass;
use std::sync::Arc;

/// What one rendered frame produced.
pub struct Frame {
    /// The final image: the transparent layer over the opaque layer.
    pub image: Image,
    /// The opaque layer alone (colour and depth), when asked for.
    pub opaque: Option<OpaqueLayer>,
    /// GPU time of each stage in milliseconds, in order.
    pub stages: Vec<(&'static str, f64)>,
    /// Peak bytes of GPU memory allocated while the frame was rendered (scene, targets,
    /// method buffers and readback included).
    pub peak_gpu_bytes: u64,
    /// Times the frame was submitted again: rendered again because a buffer overflowed (and
    /// was grown), or finished by a method whose work ran long.
    pub rerenders: u32,
    /// Fragments composited, for methods that count them (0 otherwise).
    pub fragments: u64,
    /// The most passes over its bin list a pixel needed, for exact (0 for other methods): 1
    /// or 2 where the depth slabs split the lists finely enough, more where a pixel has more
    /// fragments in one slab than its selection holds, each pass walking the list again.
    pub sweeps: u32,
    /// Transparent triangles left to rasterize after culling (back faces, off screen, behind
    /// the opaque layer), for methods that cull them (0 otherwise).
    pub triangles: u64,
    /// Entries the bin methods' lists needed: for each triangle left, each bin it may cover
    /// (0 for other methods).
    pub bin_entries: u64,
    /// Bands the bin methods rasterized the frame in: more than one when their bin lists
    /// passed the capacity (they grow for later frames); 0 for other methods.
    pub bands: u32,
    /// Compute dispatches the frame's last rendering recorded (with the submissions that
    /// finished it): the length of the method's chain, each dispatch a fixed cost on the
    /// GPU whatever it does.
    pub dispatches: u64,
    /// Fragments blended unsorted for want of room (linked_list past a fixed node budget):
    /// where they fell the frame is not exact; 0 for other methods.
    pub tail_fragments: u64,
    /// Pixels with more layers than depth_peeling's fixed passes peel: their middle layers
    /// are missing; 0 for other methods.
    pub unpeeled_pixels: u64,
    /// How the bin methods' stages were specialized and sized for the frame's last
    /// recording; `None` for the other methods.
    pub bins: Option<crate::methods::BinShape>,
    /// Where the wavelet method kept the coefficients of the frame's last recording (the
    /// option's storage, the device profile's, or the images a crowded frame fell back to);
    /// `None` for the other methods.
    pub wavelet_storage: Option<crate::methods::wavelet::Storage>,
    /// Rows exact suspended at the device's loop budget and resumed by a continuation
    /// dispatch in the frame's last recording, counted each time (0 for other methods).
    pub suspended_rows: u64,
    /// Pipelines created on the renderer's device since its last frame ended, its
    /// `set_frame` included (a shader variant this frame was the first to need): each
    /// compiles a shader, which a frame loop should pay only in its first frames.
    pub pipelines_created: u64,
    /// Bytes of GPU memory allocated on the device over the same span (buffers grown for
    /// this frame), the opaque layer's readback aside: 0 in a warm frame loop.
    pub bytes_allocated: u64,
    /// Host time spent writing the frame's data into its slot and recording its command
    /// buffers, in milliseconds: the renderer's share of an engine's CPU frame.
    pub record_ms: f64,
    /// Host wall-clock time from the last submission to its completion, in milliseconds. On
    /// CPU devices GPU timestamps are written as commands are issued, not as asynchronous
    /// raster work finishes, so this is the fairer measure of a whole frame there.
    pub wall_ms: f64,
}

impl Frame {
    /// GPU time of the transparency method alone (every stage but the opaque layer,
    /// readback and, on the engine's device, the output copy), in milliseconds.
    pub fn method_ms(&self) -> f64 {
        method_ms(&self.stages)
    }
}

/// The sum of the method's stages among `stages`: every stage but "opaque", "readback" and
/// "output".
fn method_ms(stages: &[(&'static str, f64)]) -> f64 {
    stages
        .iter()
        .filter(|(s, _)| !matches!(*s, "opaque" | "readback" | "output"))
        .map(|(_, ms)| ms)
        .sum()
}

/// Renders frames of one scene's assets with one method at one size. Each frame may move the
/// camera, change the light and draw other meshes and materials of the scene, anywhere
/// ([`Renderer::set_frame`]): the assets stay uploaded, pipelines are kept, buffers grow.
pub struct Renderer {
    gpu: Gpu,
    /// The scene's assets (texels aside: they are on the GPU) and the current frame's camera,
    /// light and draws.
    scene: Scene,
    gpu_scene: GpuScene,
    targets: FrameTargets,
    /// Made for the first frame that draws the scene's opaque layer itself (none on an
    /// engine's device, or over an opaque layer given).
    opaque_pass: Option<OpaquePass>,
    /// Where standalone frames are read back; none on an engine's device, whose frames stay
    /// in the engine's images (12 bytes a pixel saved).
    readback: Option<Readback>,
    method: Box<dyn Method>,
    /// Per frame slot: the frame's stage timestamps.
    timestamps: Vec<Timestamps>,
    /// The slot the next frame is written into and recorded from.
    slot: usize,
    /// Bumped by every change of the frame ([`Self::set_frame`], [`Self::update_mesh`]);
    /// each slot remembers the one its data was written for.
    frame_serial: u64,
    slot_serials: Vec<u64>,
    /// Host-device mode: per slot, how a completed frame is told from one whose commands
    /// never ran; and the slots of the frames in flight, oldest first.
    completions: Vec<host_device::Completion>,
    in_flight: std::collections::VecDeque<(usize, host_device::HostFrameKind)>,
    /// Host-device mode: per slot, the compute dispatches its last frame recorded.
    slot_dispatches: Vec<u64>,
    /// Host-device mode: the yardstick's passes and pipelines, which `blend` draws with too,
    /// one per kind of engine image, made for the first frame into one
    /// ([`Renderer::record_native_blend`]) or by [`Renderer::prepare_host`].
    native_blend: native_blend::NativeBlend,
    /// Host-device mode: the pass that samples engine depth images it cannot copy, made
    /// for the first frame that needs it.
    depth_import: Option<crate::gpu::DepthImport>,
    /// Views of the engine's depth images, per frame slot, for the methods that sample it
    /// in place.
    engine_depth_views: Option<crate::gpu::EngineDepthViews>,
    /// The device's pipelines created and bytes allocated when the last frame ended (the
    /// renderer was made), readbacks for the opaque layer not counted.
    counted: (u64, u64),
}

/// Checks a viewport against the device's limits.
pub fn check_viewport(gpu: &Gpu, width: u32, height: u32) -> Result<()> {
    let bad = |reason: String| {
        Err(Error::InvalidViewport {
            width,
            height,
            reason,
        })
    };
    let max = gpu.info().max_image_dimension_2d;
    if width == 0 || height == 0 {
        return bad("width and height must be at least 1".into());
    }
    if width > max || height > max {
        return bad(format!("the device's largest image is {max}x{max}"));
    }
    Ok(())
}

/// The frames a renderer draws: their largest size (the first frame's; later ones may be
/// smaller, [`Renderer::set_size`]), and how many may be in flight at once (1 to
/// [`MAX_FRAMES_IN_FLIGHT`]; more than 1 only on an engine's device).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct FrameShape {
    pub width: u32,
    pub height: u32,
    pub frames_in_flight: u32,
}

/// The most frames an engine may keep recorded and not completed on one renderer: its frames
/// in flight times the views each records (4 frames of 4 views, or 3 frames of stereo with
/// the yardstick beside each eye). Each costs a slot of per-frame data (the frame's and its
/// draws' constants, timestamps, counters); the working buffers are shared.
pub const MAX_FRAMES_IN_FLIGHT: u32 = 16;

/// Submits a frame again at most this many times: rendered again when buffers overflow or
/// a method must change its passes (buffers grow to at least what the GPU counted, so once
/// normally suffices), or finished by the method when its work ran long (exact's
/// continuations, for the deepest frames, take up to four more).
const MAX_RERENDERS: u32 = 8;

impl Renderer {
    pub fn new(
        gpu: &Gpu,
        scene: &Scene,
        method: MethodKind,
        width: u32,
        height: u32,
    ) -> Result<Self> {
        Self::with_options(gpu, scene, method, width, height, &MethodOptions::default())
    }

    pub fn with_options(
        gpu: &Gpu,
        scene: &Scene,
        method: MethodKind,
        width: u32,
        height: u32,
        options: &MethodOptions,
    ) -> Result<Self> {
        Self::with_frames_in_flight(gpu, scene, method, width, height, options, 1)
    }

    /// A renderer whose engine keeps up to `frames` frames (1 to [`MAX_FRAMES_IN_FLIGHT`])
    /// recorded and not yet completed (host-device mode): per-frame data lives in that
    /// many slots; buffers the frames share are used one frame after another on the queue.
    pub fn with_frames_in_flight(
        gpu: &Gpu,
        scene: &Scene,
        method: MethodKind,
        width: u32,
        height: u32,
        options: &MethodOptions,
        frames: u32,
    ) -> Result<Self> {
        let shape = FrameShape {
            width,
            height,
            frames_in_flight: frames,
        };
        Self::build(gpu, scene, None, method, shape, options)
    }

    /// A renderer over assets uploaded before (for a scene with the same meshes, materials
    /// and textures: checked), shared with the renderers made over them: it uploads nothing,
    /// and takes the compute pipelines they hold.
    pub fn sharing(
        gpu: &Gpu,
        resident: Arc<ResidentAssets>,
        scene: &Scene,
        method: MethodKind,
        shape: FrameShape,
        options: &MethodOptions,
    ) -> Result<Self> {
        Self::build(gpu, scene, Some(resident), method, shape, options)
    }

    /// Draws from `resident` from now on: these assets extended with others
    /// ([`ResidentAssets::extended`]), uploaded for `scene` (which has them all, and whose
    /// camera, light and draws become the frame's). Nothing is rebuilt: the assets added
    /// were appended to the buffers this renderer binds. Frames in flight keep drawing what
    /// they were recorded with.
    pub fn adopt_assets(&mut self, resident: Arc<ResidentAssets>, scene: &Scene) -> Result<()> {
        scene.validate()?;
        self.gpu_scene.adopt(resident, scene)?;
        self.scene = scene.without_texels();
        self.frame_serial += 1;
        Ok(())
    }

    /// The assets this renderer draws from, for a renderer made to share them.
    pub fn resident(&self) -> &Arc<ResidentAssets> {
        &self.gpu_scene.resident
    }

    fn build(
        gpu: &Gpu,
        scene: &Scene,
        resident: Option<Arc<ResidentAssets>>,
        method: MethodKind,
        shape: FrameShape,
        options: &MethodOptions,
    ) -> Result<Self> {
        let FrameShape {
            width,
            height,
            frames_in_flight: frames,
        } = shape;
        if !(1..=MAX_FRAMES_IN_FLIGHT).contains(&frames) {
            return Err(Error::InvalidOption(format!(
                "{frames} frames in flight; 1 to {MAX_FRAMES_IN_FLIGHT} are supported"
            )));
        }
        let slots = frames as usize;
        check_viewport(gpu, width, height)?;
        let resident = match resident {
            Some(r) => r,
            None => Arc::new(ResidentAssets::new(gpu, scene)?),
        };
        let gpu_scene = GpuScene::over(gpu, resident, scene, width, height, slots)?;
        let targets = FrameTargets::new(gpu, width, height)?;
        let readback = if gpu.is_host_device() {
            None
        } else {
            Some(Readback::new(gpu, &targets)?)
        };
        let method = methods::create(method, gpu, scene, &gpu_scene, &targets, options)?;
        let timestamps = (0..slots)
            .map(|_| Timestamps::new(gpu, 32))
            .collect::<Result<Vec<_>>>()?;
        gpu.check_validation()?;
        // Slot 0 holds the scene's own frame; the others are written before their first use.
        // A prepared loop's methods start from the declared variants: its first frame is set
        // like any other, taking the superset where it draws past the declaration.
        let mut slot_serials = vec![u64::MAX; slots];
        if !options.bins.prepared {
            slot_serials[0] = 0;
        }
        Ok(Self {
            gpu: gpu.clone(),
            scene: scene.without_texels(),
            gpu_scene,
            targets,
            opaque_pass: None,
            readback,
            method,
            timestamps,
            slot: 0,
            frame_serial: 0,
            slot_serials,
            completions: Vec::new(),
            depth_import: None,
            engine_depth_views: None,
            native_blend: native_blend::NativeBlend::default(),
            slot_dispatches: vec![0; slots],
            in_flight: std::collections::VecDeque::new(),
            counted: (gpu.pipelines_created(), gpu.bytes_allocated()),
        })
    }

    /// `options` with the buffer sizes this renderer's frames turned out to need, for a
    /// renderer made for the next, similar frame.
    pub fn learned_options(&self, options: &MethodOptions) -> MethodOptions {
        let mut learned = options.clone();
        self.method.learned(&mut learned);
        learned
    }

    /// Makes `input` the frame the next [`Self::render`] (or `record_host`) draws: a camera,
    /// light and draws over the assets this renderer was made with, checked now. Nothing is
    /// rebuilt: the frame's data is written into its slot when it is recorded, buffers grow
    /// when the frame needs more, and pipelines come from those built before (a frame
    /// needing a shader variant no earlier frame needed builds it once). Frames in flight
    /// keep drawing what they were recorded with.
    pub fn set_frame(&mut self, input: &FrameInput<'_>) -> Result<()> {
        self.scene.set_frame(input)?;
        self.frame_serial += 1;
        Ok(())
    }

    /// Makes `camera` the camera of the frame set last ([`Self::set_frame`]), as for the next
    /// view of a frame of several: its draws stay as they were set.
    pub fn set_camera(&mut self, camera: crate::scene::Camera) -> Result<()> {
        camera.validate().map_err(Error::InvalidScene)?;
        self.scene.camera = camera;
        self.frame_serial += 1;
        Ok(())
    }

    /// Makes `width` x `height` the size of the frames from the next one recorded: any size
    /// from 1x1 up to the one the renderer was made for, as an engine's dynamic resolution
    /// moves it. Nothing is rebuilt or allocated for it: the frames draw into the top-left
    /// corner of targets and buffers made for the largest. Frames in flight keep their size.
    pub fn set_size(&mut self, width: u32, height: u32) -> Result<()> {
        let extent = vk::Extent2D { width, height };
        if extent != self.targets.extent {
            self.targets.set_extent(extent)?;
            self.frame_serial += 1;
        }
        Ok(())
    }

    /// The size of the frames recorded next.
    pub fn size(&self) -> (u32, u32) {
        (self.targets.extent.width, self.targets.extent.height)
    }

    /// The largest frame this renderer draws: the size it was made for.
    pub fn max_size(&self) -> (u32, u32) {
        (self.targets.capacity.width, self.targets.capacity.height)
    }

    /// Writes the current frame into `slot` unless the slot holds it already, and makes it
    /// the slot recorded from. No frame of that slot may be in flight.
    fn prepare_slot(&mut self, slot: usize) -> Result<()> {
        self.gpu_scene.use_slot(slot);
        if self.slot_serials[slot] == self.frame_serial {
            return Ok(());
        }
        // A failure below leaves the slot to be written again.
        self.slot_serials[slot] = u64::MAX;
        let extent = self.targets.extent;
        self.gpu_scene.set_extent(extent.width, extent.height);
        self.gpu_scene.set_frame(&self.gpu, &self.scene)?;
        self.method.set_frame(&FrameSetup {
            gpu: &self.gpu,
            scene: &self.scene,
            gpu_scene: &self.gpu_scene,
            targets: &self.targets,
            slot,
        })?;
        self.slot_serials[slot] = self.frame_serial;
        Ok(())
    }

    /// Moves mesh `mesh`'s vertices to `positions` (one per vertex, as many as it has; its
    /// normals, colours and texture coordinates stay) from the next frame recorded on, as
    /// particle systems and skinned meshes do every frame. That frame copies them into the
    /// vertex buffer after the frames in flight before it: nothing is rebuilt, and GPU memory
    /// is allocated only for the first move (a staging buffer per frame slot).
    pub fn update_mesh(&mut self, mesh: usize, positions: &[Vec3]) -> Result<()> {
        let meshes = self.scene.meshes.len();
        let target = self.scene.meshes.get_mut(mesh).ok_or_else(|| {
            Error::InvalidArgument(format!("mesh {mesh} to update; the scene has {meshes}"))
        })?;
        if positions.len() != target.positions.len() {
            return Err(Error::InvalidArgument(format!(
                "mesh {mesh} ({}) has {} vertices; {} positions given",
                target.name,
                target.positions.len(),
                positions.len()
            )));
        }
        if let Some(i) = positions.iter().position(|p| !p.is_finite()) {
            return Err(Error::InvalidArgument(format!(
                "mesh {mesh} ({}): position {i} is not finite",
                target.name
            )));
        }
        target.positions.copy_from_slice(positions);
        // The uploads and the method's view of the frame (near-plane estimate, bounds) follow
        // the vertices.
        self.gpu_scene.mesh_moved(mesh);
        self.frame_serial += 1;
        Ok(())
    }

    pub fn method_name(&self) -> &'static str {
        self.method.name()
    }

    /// Renders one frame. With `with_opaque`, the opaque layer is read back too (for the CPU
    /// reference), timed as its own "readback" stage.
    pub fn render(&mut self, with_opaque: bool) -> Result<Frame> {
        self.gpu.reset_peak_memory();
        let before = self.gpu.bytes_allocated();
        let opaque_readback = if with_opaque {
            Some(Readback::new(&self.gpu, &self.targets)?)
        } else {
            None
        };
        self.counted.1 += self.gpu.bytes_allocated() - before;
        let mut frame = self.run(OpaqueSource::Scene {
            readback: opaque_readback.as_ref(),
        })?;
        frame.opaque = opaque_readback
            .as_ref()
            .map(Readback::opaque_layer)
            .transpose()?;
        Ok(frame)
    }

    /// Records and submits one frame, again while the method reports an overflow, and reads
    /// the result back.
    fn run(&mut self, source: OpaqueSource<'_>) -> Result<Frame> {
        let gpu = self.gpu.clone();
        // Fail before submitting anything.
        self.readback()?;
        if matches!(source, OpaqueSource::Scene { .. }) && self.opaque_pass.is_none() {
            self.opaque_pass = Some(OpaquePass::new(&gpu, &self.targets, &self.gpu_scene)?);
        }
        // Standalone frames complete before the call returns: one slot serves them all.
        let slot = self.slot;
        let preparing = std::time::Instant::now();
        self.prepare_slot(slot)?;
        let mut record_ms = preparing.elapsed().as_secs_f64() * 1e3;
        let mut rerenders = 0;
        let mut wall_ms = 0.0;
        // A frame the method finishes in further submissions: their stages, after the
        // frame's own.
        let mut finishing = false;
        let mut stages = Vec::new();
        let mut rendering_from = gpu.dispatches_recorded();
        let check = loop {
            let started = std::time::Instant::now();
            if !finishing {
                rendering_from = gpu.dispatches_recorded();
            }
            gpu.submit_and_wait(|cmd| {
                let recording = std::time::Instant::now();
                let _timed = OnDrop(|| record_ms += recording.elapsed().as_secs_f64() * 1e3);
                self.timestamps[slot].begin(cmd);
                if finishing {
                    self.record_finish(&gpu, cmd)?;
                    self.readback()?.record(&gpu, cmd, &self.targets, false);
                    return Ok(());
                }
                self.gpu_scene
                    .record_moved_vertices(&gpu, cmd, &self.scene)?;
                match &source {
                    OpaqueSource::Scene { readback } => {
                        // Made above.
                        if let Some(pass) = &self.opaque_pass {
                            pass.record(
                                &gpu,
                                cmd,
                                (&self.gpu_scene, &self.targets),
                                self.scene.background,
                            );
                        }
                        self.timestamps[slot].mark(cmd, "opaque");
                        if let Some(r) = readback {
                            r.record(&gpu, cmd, &self.targets, true);
                            self.timestamps[slot].mark(cmd, "readback");
                        }
                    }
                    OpaqueSource::Host { colour, depth } => {
                        opaque_upload::record_upload(&gpu, cmd, &self.targets, colour, depth);
                        self.timestamps[slot].mark(cmd, "opaque");
                    }
                }
                self.record_method(&gpu, cmd, None)?;
                self.readback()?.record(&gpu, cmd, &self.targets, false);
                Ok(())
            })?;
            self.gpu_scene.uploads_recorded();
            let elapsed = started.elapsed().as_secs_f64() * 1e3;
            wall_ms = if finishing {
                wall_ms + elapsed
            } else {
                elapsed
            };
            if !finishing {
                stages.clear();
            }
            stages.extend(self.timestamps[slot].read()?);
            let check = self.method.frame_done(&FrameDone {
                gpu_scene: &self.gpu_scene,
                targets: &self.targets,
                slot,
            })?;
            finishing = check.finish;
            if !check.rerender && !check.finish {
                break check;
            }
            rerenders += 1;
            if rerenders > MAX_RERENDERS {
                return Err(Error::TooLarge(format!(
                    "{}: the frame is still unfinished after {MAX_RERENDERS} more submissions",
                    self.method.name()
                )));
            }
        };
        let counted = self.counted;
        self.counted = (gpu.pipelines_created(), gpu.bytes_allocated());
        Ok(Frame {
            image: self.readback()?.colour()?,
            opaque: None,
            stages,
            peak_gpu_bytes: gpu.memory_in_use().1,
            rerenders,
            fragments: check.fragments,
            sweeps: check.sweeps,
            triangles: check.triangles,
            bin_entries: check.bin_entries,
            bands: check.bands,
            dispatches: gpu.dispatches_recorded() - rendering_from,
            tail_fragments: check.tail_fragments,
            unpeeled_pixels: check.unpeeled_pixels,
            bins: check.bins,
            wavelet_storage: check.wavelet_storage,
            suspended_rows: check.suspended_rows,
            pipelines_created: self.counted.0 - counted.0,
            bytes_allocated: self.counted.1 - counted.1,
            record_ms,
            wall_ms,
        })
    }

    /// Where standalone frames are read back; an error on an engine's device.
    fn readback(&self) -> Result<&Readback> {
        self.readback.as_ref().ok_or_else(|| {
            Error::HostFrame(
                "on an engine's device frames are recorded (record_host), not rendered".into(),
            )
        })
    }

    /// Records what completes the method's unfinished frame.
    fn record_finish(&mut self, gpu: &Gpu, cmd: vk::CommandBuffer) -> Result<()> {
        self.with_method(gpu, (cmd, None), |method, ctx| method.record_finish(ctx))
    }

    /// Records the method's passes over the frame targets, or over the engine's images
    /// `in_place`.
    fn record_method(
        &mut self,
        gpu: &Gpu,
        cmd: vk::CommandBuffer,
        in_place: Option<InPlace>,
    ) -> Result<()> {
        self.with_method(gpu, (cmd, in_place), |method, ctx| method.record(ctx))
    }

    /// Calls `record` with the method and a context for recording into `cmd`.
    fn with_method(
        &mut self,
        gpu: &Gpu,
        (cmd, in_place): (vk::CommandBuffer, Option<InPlace>),
        record: impl FnOnce(&mut dyn Method, &mut RecordContext<'_>) -> Result<()>,
    ) -> Result<()> {
        let slot = self.gpu_scene.slot();
        let mut ctx = RecordContext {
            gpu,
            cmd,
            slot,
            gpu_scene: &self.gpu_scene,
            targets: &self.targets,
            timestamps: &mut self.timestamps[slot],
            in_place,
        };
        record(self.method.as_mut(), &mut ctx)
    }
}

/// Where a frame's opaque layer comes from.
enum OpaqueSource<'a> {
    /// The scene's opaque draws, optionally read back for the CPU reference.
    Scene { readback: Option<&'a Readback> },
    /// The host's colour (RGBA16F texels) and depth (D32 texels), copied in.
    Host {
        colour: &'a crate::gpu::Buffer,
        depth: &'a crate::gpu::Buffer,
    },
}

/// Runs its closure when dropped: times a scope however it is left.
struct OnDrop<F: FnMut()>(F);

impl<F: FnMut()> Drop for OnDrop<F> {
    fn drop(&mut self) {
        (self.0)();
    }
}
