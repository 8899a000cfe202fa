//! Host-device mode from Rust, for what the C test cannot reach: the exact method started with
//! bin lists far too small, so that its first recorded frame overflows (completion must say
//! so, and the same frame recorded again must match standalone mode); and 1, 2 and 3 frames
//! in flight over a moving sequence.
//!
//! The test plays the engine with ash: its own instance (with the validation layer and a
//! messenger that collects errors), device, command buffers and submissions.

use ash::vk;
use glam::{Mat4, Vec3};
use std::ffi::{c_void, CStr};
use std::sync::Mutex;
use translucid::gpu::{host_requirements_with, EngineImages, Gpu, GpuOptions, HostDevice};
use translucid::methods::wavelet::Storage;
use translucid::methods::{MethodKind, MethodOptions};
use translucid::renderer::Renderer;
use translucid::scene::motion::Orbit;
use translucid::scene::{Camera, Projection, Scene};
use translucid::OpaqueLayer;
use translucid_tests::{
    assert_only_per_frame_data_is_host_visible, asset, crowded_bin, near_plane_scene,
    one_depth_stack, staging_allocations,
};

const W: u32 = 96;
const H: u32 = 64;
/// Bin entries that the first frames of the moving spheres need two to four bands of.
const BANDED_ENTRIES: u32 = 2000;

static ERRORS: Mutex<Vec<String>> = Mutex::new(Vec::new());

unsafe extern "system" fn on_message(
    severity: vk::DebugUtilsMessageSeverityFlagsEXT,
    _types: vk::DebugUtilsMessageTypeFlagsEXT,
    data: *const vk::DebugUtilsMessengerCallbackDataEXT<'_>,
    _user: *mut c_void,
) -> vk::Bool32 {
    if severity.contains(vk::DebugUtilsMessageSeverityFlagsEXT::ERROR) {
        // SAFETY: the layer passes a valid callback-data struct with a NUL-terminated message.
        let message = unsafe { CStr::from_ptr((*data).p_message) };
        if let Ok(mut e) = ERRORS.lock() {
            e.push(message.to_string_lossy().into_owned());
        }
    }
    vk::FALSE
}

/// Fails on any validation error the engine's messenger collected.
fn assert_no_validation_errors() {
    let errors = ERRORS.lock().map(|e| e.clone()).unwrap_or_default();
    assert!(
        errors.is_empty(),
        "validation errors:\n{}",
        errors.join("\n")
    );
}

/// The engine: instance, device, queue, command buffer, fence.
struct Engine {
    _entry: ash::Entry,
    instance: ash::Instance,
    messenger: (ash::ext::debug_utils::Instance, vk::DebugUtilsMessengerEXT),
    physical: vk::PhysicalDevice,
    device: ash::Device,
    family: u32,
    queue: vk::Queue,
    pool: vk::CommandPool,
    /// One command buffer and fence per frame the engine keeps in flight (up to four).
    cmds: Vec<vk::CommandBuffer>,
    fences: Vec<vk::Fence>,
    features: vk::PhysicalDeviceFeatures,
    api_version: u32,
    /// `subgroupSizeControl` and `computeFullSubgroups` are enabled, and said so.
    subgroup_size_control: bool,
}

impl Engine {
    fn new() -> Self {
        Self::with(false, false, false)
    }

    /// An engine on Vulkan 1.3 with synchronization2 enabled when `sync2`, whose images may
    /// then be in its layouts (ATTACHMENT_OPTIMAL, READ_ONLY_OPTIMAL).
    fn with_synchronization2(sync2: bool) -> Self {
        Self::with(sync2, false, false)
    }

    /// An engine whose validation layer checks synchronization too (hazards between the
    /// engine's commands and translucid's are errors).
    fn with_synchronization_validation() -> Self {
        Self::with(false, true, false)
    }

    /// An engine that enables subgroup size control (`VK_EXT_subgroup_size_control` on
    /// Vulkan 1.2) and tells translucid so, as the requirements recommend.
    fn with_subgroup_size_control() -> Self {
        Self::with(false, false, true)
    }

    fn with(sync2: bool, sync_validation: bool, size_control: bool) -> Self {
        // An engine that uses every method: each one's features ORed in.
        let optional: Vec<_> = MethodKind::ALL
            .iter()
            .flat_map(|kind| kind.optional_features())
            .copied()
            .collect();
        let wanted = host_requirements_with(&optional);
        let api_version = if sync2 {
            vk::API_VERSION_1_3
        } else {
            wanted.api_version
        };
        // SAFETY: plain Vulkan object creation, each call given live parents and create infos
        // that outlive it; this is test code standing in for an engine.
        unsafe {
            let entry = ash::Entry::load().expect("the Vulkan loader");
            let app = vk::ApplicationInfo::default().api_version(api_version);
            let layers = [c"VK_LAYER_KHRONOS_validation".as_ptr()];
            let extensions = [ash::ext::debug_utils::NAME.as_ptr()];
            let enables = [vk::ValidationFeatureEnableEXT::SYNCHRONIZATION_VALIDATION];
            let mut validation =
                vk::ValidationFeaturesEXT::default().enabled_validation_features(&enables);
            let mut info = vk::InstanceCreateInfo::default()
                .application_info(&app)
                .enabled_layer_names(&layers)
                .enabled_extension_names(&extensions);
            if sync_validation {
                info = info.push_next(&mut validation);
            }
            let instance = entry
                .create_instance(&info, None)
                .expect("an instance with the validation layer (run `make test`)");
            let loader = ash::ext::debug_utils::Instance::new(&entry, &instance);
            let messenger = loader
                .create_debug_utils_messenger(
                    &vk::DebugUtilsMessengerCreateInfoEXT::default()
                        .message_severity(vk::DebugUtilsMessageSeverityFlagsEXT::ERROR)
                        .message_type(vk::DebugUtilsMessageTypeFlagsEXT::VALIDATION)
                        .pfn_user_callback(Some(on_message)),
                    None,
                )
                .expect("debug messenger");
            let physical = instance.enumerate_physical_devices().expect("devices")[0];
            let family = instance
                .get_physical_device_queue_family_properties(physical)
                .iter()
                .position(|f| {
                    f.queue_flags.contains(wanted.queue_flags) && f.timestamp_valid_bits > 0
                })
                .expect("a graphics+compute family with timestamps")
                as u32;
            let priorities = [1.0];
            let queues = [vk::DeviceQueueCreateInfo::default()
                .queue_family_index(family)
                .queue_priorities(&priorities)];
            let features = wanted.features;
            let mut vulkan13 = vk::PhysicalDeviceVulkan13Features::default().synchronization2(true);
            let mut size_features = vk::PhysicalDeviceSubgroupSizeControlFeatures::default()
                .subgroup_size_control(true)
                .compute_full_subgroups(true);
            let size_extension = [ash::ext::subgroup_size_control::NAME.as_ptr()];
            let mut info = vk::DeviceCreateInfo::default()
                .queue_create_infos(&queues)
                .enabled_features(&features);
            if sync2 {
                info = info.push_next(&mut vulkan13);
            }
            if size_control {
                info = info
                    .push_next(&mut size_features)
                    .enabled_extension_names(&size_extension);
            }
            let device = instance
                .create_device(physical, &info, None)
                .expect("device");
            let queue = device.get_device_queue(family, 0);
            let pool = device
                .create_command_pool(
                    &vk::CommandPoolCreateInfo::default()
                        .queue_family_index(family)
                        .flags(vk::CommandPoolCreateFlags::RESET_COMMAND_BUFFER),
                    None,
                )
                .expect("command pool");
            let cmds = device
                .allocate_command_buffers(
                    &vk::CommandBufferAllocateInfo::default()
                        .command_pool(pool)
                        .command_buffer_count(4),
                )
                .expect("command buffers");
            let fences = (0..4)
                .map(|_| {
                    device
                        .create_fence(&vk::FenceCreateInfo::default(), None)
                        .expect("fence")
                })
                .collect();
            Self {
                _entry: entry,
                instance,
                messenger: (loader, messenger),
                physical,
                device,
                family,
                queue,
                pool,
                cmds,
                fences,
                features,
                api_version,
                subgroup_size_control: size_control,
            }
        }
    }

    fn host_device(&self) -> HostDevice {
        HostDevice {
            get_instance_proc_addr: self._entry.static_fn().get_instance_proc_addr,
            instance: self.instance.handle(),
            physical_device: self.physical,
            device: self.device.handle(),
            queue_family: self.family,
            api_version: self.api_version,
            features: self.features,
            extensions: if self.subgroup_size_control {
                vec![ash::ext::subgroup_size_control::NAME.to_owned()]
            } else {
                Vec::new()
            },
            profile: None,
            subgroup_size_control: self.subgroup_size_control,
            software_sampling: false,
            memory_budget: None,
            allocation_callbacks: None,
        }
    }

    /// Begins command buffer `i`, which must be idle (its last submission waited for).
    fn begin(&self, i: usize) {
        // SAFETY: the caller waited for the buffer's last submission.
        unsafe {
            self.device
                .begin_command_buffer(self.cmds[i], &vk::CommandBufferBeginInfo::default())
                .expect("begin");
        }
    }

    /// Ends and submits command buffer `i`, signalling fence `i`, without waiting.
    fn submit(&self, i: usize) {
        let cmds = [self.cmds[i]];
        // SAFETY: recorded by this thread; fence i is unsignalled (reset after each wait).
        unsafe {
            self.device.end_command_buffer(self.cmds[i]).expect("end");
            self.device
                .queue_submit(
                    self.queue,
                    &[vk::SubmitInfo::default().command_buffers(&cmds)],
                    self.fences[i],
                )
                .expect("submit");
        }
    }

    /// Waits for command buffer `i`'s submission and resets its fence.
    fn wait(&self, i: usize) {
        // SAFETY: fence i was submitted with command buffer i.
        unsafe {
            self.device
                .wait_for_fences(&[self.fences[i]], true, u64::MAX)
                .expect("wait");
            self.device.reset_fences(&[self.fences[i]]).expect("reset");
        }
    }

    fn submit_and_wait(&self) {
        self.submit(0);
        self.wait(0);
    }
}

impl Drop for Engine {
    fn drop(&mut self) {
        // SAFETY: the device is idle and every translucid object is gone (dropped first).
        unsafe {
            let _ = self.device.device_wait_idle();
            for &fence in &self.fences {
                self.device.destroy_fence(fence, None);
            }
            self.device.destroy_command_pool(self.pool, None);
            self.device.destroy_device(None);
            self.messenger
                .0
                .destroy_debug_utils_messenger(self.messenger.1, None);
            self.instance.destroy_instance(None);
        }
    }
}

/// An 8-bit RGBA image's pixels.
fn pixels(image: &[u8]) -> Vec<&[u8]> {
    image.chunks_exact(4).collect()
}

/// The largest difference between two images' bytes.
fn worst_difference(got: &[u8], want: &[u8]) -> u8 {
    got.iter()
        .zip(want)
        .map(|(a, b)| a.abs_diff(*b))
        .max()
        .unwrap_or(0)
}

/// Records one frame of `renderer` on the engine into `images` (slot 0), submits it, waits,
/// and completes it: what the frame reported.
fn one_engine_frame(
    engine: &Engine,
    gpu: &Gpu,
    images: &EngineImages,
    renderer: &mut Renderer,
) -> translucid::renderer::HostFrame {
    record_engine_frame(engine, gpu, images, renderer, 0);
    engine.submit_and_wait();
    renderer
        .complete_host()
        .expect("complete")
        .expect("the submission finished, so the commands ran")
}

/// Records `renderer`'s next frame into the engine's command buffer `k`: the opaque layer
/// into `images` (of at least the frame's size), the frame, and the colour's readback `k`.
fn record_engine_frame(
    engine: &Engine,
    gpu: &Gpu,
    images: &EngineImages,
    renderer: &mut Renderer,
    k: usize,
) {
    engine.begin(k);
    let cmd = engine.cmds[k];
    images.record_opaque(gpu, cmd);
    // SAFETY: the engine's recording command buffer and images of at least the frame's size.
    unsafe { renderer.record_host(&images.targets(cmd)) }.expect("record");
    images.record_readback(gpu, cmd, k);
}

/// Submits the engine's command buffers 0 to `count`, then waits for each and completes its
/// frame: what the frames reported, oldest first.
fn submit_and_complete(
    engine: &Engine,
    renderer: &mut Renderer,
    count: usize,
) -> Vec<translucid::renderer::HostFrame> {
    for k in 0..count {
        engine.submit(k);
    }
    (0..count)
        .map(|k| {
            engine.wait(k);
            renderer
                .complete_host()
                .expect("complete")
                .expect("the submission finished, so the commands ran")
        })
        .collect()
}

/// `spheres`, its opaque layer and exact's standalone frame over it, at the tests' size.
fn spheres_standalone() -> (Scene, OpaqueLayer, translucid::renderer::Frame) {
    let scene = translucid::scene::load("spheres").expect("generated scene");
    let standalone = Gpu::new(&GpuOptions {
        device: None,
        validation: true,
        profile: None,
        software_sampling: false,
        ..Default::default()
    })
    .expect("a Vulkan device with the validation layer");
    let mut reference =
        Renderer::new(&standalone, &scene, MethodKind::Exact, W, H).expect("renderer");
    let layer = reference
        .render(true)
        .expect("frame")
        .opaque
        .expect("opaque");
    let expected = reference.render_over(&layer).expect("frame over the layer");
    (scene, layer, expected)
}

/// Every method's frame over the engine's images writes only where the transparent layer
/// covers: everywhere the reference leaves the opaque colour as it is, the engine's colour
/// (every channel, alpha too) stays bit for bit what the engine drew, under validation and
/// synchronization validation. exact and wavelet blend onto the engine's image in place,
/// the others copy it in and out.
#[test]
fn every_method_leaves_the_engines_colour_bit_for_bit_where_nothing_transparent_covers() {
    let (scene, depth_layer, _) = spheres_standalone();
    // Colours no frame target would round to: every f16 in [0, 4) with a varied mantissa.
    let colour = |i: usize| {
        let bits = |k: usize| (0x3000 + (i * 7919 + k * 104_729) % 0x1000) as u16;
        let c = |k| half::f16::from_bits(bits(k)).to_f32();
        Vec3::new(c(0), c(1), c(2))
    };
    let layer = OpaqueLayer {
        colour: (0..depth_layer.depth.len()).map(colour).collect(),
        ..depth_layer
    };
    let expected = translucid::reference::render(&scene, &layer).expect("reference");
    let uncovered: Vec<bool> = expected
        .pixels
        .iter()
        .zip(&layer.colour)
        .map(|(p, c)| p.truncate() == *c)
        .collect();
    let count = uncovered.iter().filter(|u| **u).count();
    assert!(
        count > uncovered.len() / 10 && count < uncovered.len() * 9 / 10,
        "the frame should have both: {count} of {} pixels uncovered",
        uncovered.len()
    );
    let (drawn, _) = layer.texels();

    let engine = Engine::with_synchronization_validation();
    {
        // SAFETY: the engine's live objects, outliving `gpu` (dropped at the end of this block).
        let gpu = unsafe { Gpu::from_host(&engine.host_device()) }.expect("host device");
        let images = EngineImages::of_layer(&gpu, &layer, 1).expect("engine images");
        // Every method, wavelet in each storage (the bins composite in place, the images
        // copy in and out).
        let runs = MethodKind::ALL.into_iter().flat_map(|kind| {
            let storages: &[Option<Storage>] = if kind == MethodKind::Wavelet {
                &[Some(Storage::Bins), Some(Storage::Images)]
            } else {
                &[None]
            };
            storages.iter().map(move |&storage| (kind, storage))
        });
        for (kind, storage) in runs {
            let mut options = MethodOptions::default();
            options.wavelet.storage = storage;
            let mut renderer =
                Renderer::with_frames_in_flight(&gpu, &scene, kind, W, H, &options, 1)
                    .expect("renderer");
            let frame = one_engine_frame(&engine, &gpu, &images, &mut renderer);
            let got = images.outs[0].read().expect("readback");
            let changed = uncovered
                .iter()
                .enumerate()
                .filter(|&(i, &u)| u && got[i * 8..i * 8 + 8] != drawn[i * 8..i * 8 + 8])
                .count();
            assert_eq!(
                changed,
                0,
                "{}: {changed} uncovered pixels of the engine's colour changed",
                kind.name()
            );
            // Not a frame that wrote nothing at all.
            assert_ne!(got, drawn, "{}: the frame wrote nothing", kind.name());
            let in_place = frame.stages.iter().any(|(s, _)| *s == "composite");
            let copied = frame.stages.iter().any(|(s, _)| *s == "output");
            let expect_in_place = kind == MethodKind::Exact || storage == Some(Storage::Bins);
            assert_eq!(
                (in_place, copied),
                (
                    expect_in_place,
                    !expect_in_place && kind != MethodKind::Blend
                ),
                "{}: stages {:?}",
                kind.name(),
                frame.stages
            );
        }
    }
    assert_no_validation_errors();
}

#[test]
fn an_overflowing_frame_says_so_and_renders_right_when_recorded_again() {
    let (scene, layer, expected) = spheres_standalone();

    let engine = Engine::new();
    {
        // SAFETY: the engine's live objects, outliving `gpu` (dropped at the end of this block).
        let gpu = unsafe { Gpu::from_host(&engine.host_device()) }.expect("host device");
        let images = EngineImages::of_layer(&gpu, &layer, 1).expect("engine images");
        let mut options = MethodOptions::default();
        options.bins.initial_bin_entries = Some(16);
        let mut renderer = Renderer::with_options(&gpu, &scene, MethodKind::Exact, W, H, &options)
            .expect("renderer");
        let mut overflows = Vec::new();
        for _ in 0..3 {
            let done = one_engine_frame(&engine, &gpu, &images, &mut renderer);
            overflows.push(done.overflowed);
            if !done.overflowed {
                assert!(done.fragments > 0 && done.stages.len() >= 3, "{done:?}");
                break;
            }
        }
        assert_eq!(
            overflows.first(),
            Some(&true),
            "16 bin entries should overflow the first frame: {overflows:?}"
        );
        assert_eq!(overflows.last(), Some(&false), "{overflows:?}");

        let got = images.srgb(0).expect("readback");
        let want = expected.image.to_srgb8();
        let worst = worst_difference(&got, &want);
        assert!(
            worst <= 2,
            "host-device exact differs from standalone by {worst}/255"
        );
    }
    assert_no_validation_errors();
}

/// What the first batch of frames in flight shows when the bin lists start small.
#[derive(Clone, Copy, PartialEq)]
enum FirstBatch {
    /// The lists start large enough: every frame is right in one band.
    Fits,
    /// Every frame is right on its one recording, rasterized in several bands.
    InBands,
    /// The lists need more bands than the frame records: the frames say so, and each pixel
    /// is either right or the engine's colour, never anything else.
    Degraded,
}

/// An engine that keeps `in_flight` frames recorded before it submits any of them: 30 frames
/// of a moving camera, moving draws and one mesh's vertices moving, each read back from the
/// engine's colour image once completed, must each be what the CPU reference draws for that
/// frame.
/// `options` may start the bin lists too small for the first batch (`first_batch` says what
/// that batch must then show); the lists grow once for the whole batch (not once per frame),
/// and the later batches are right.
fn frames_in_flight_match_the_reference(
    in_flight: usize,
    options: MethodOptions,
    first_batch: FirstBatch,
) {
    const FRAMES: usize = 30;
    let scene = translucid::scene::load("spheres").expect("generated scene");
    let orbit = Orbit::new(&scene);
    let moving_mesh = scene.transparent[0].mesh;
    let frame_scene = |f: usize| {
        let mut s = scene.clone();
        s.camera = orbit.camera(&scene, f as u32);
        orbit.transparent(&scene, f as u32, &mut s.transparent);
        let positions = &mut s.meshes[moving_mesh].positions;
        let centre = positions.iter().copied().sum::<Vec3>() / positions.len() as f32;
        let scale = 1.0 + 0.2 * (f as f32 * 0.9).sin();
        for p in positions.iter_mut() {
            *p = centre + (*p - centre) * scale;
        }
        s
    };
    // Sets frame `f` on `renderer`: camera and draws, and the moving mesh's vertices.
    let set = |renderer: &mut Renderer, f: usize| {
        let s = frame_scene(f);
        renderer.set_frame(&s.frame_input()).expect("set frame");
        renderer
            .update_mesh(moving_mesh, &s.meshes[moving_mesh].positions)
            .expect("update mesh");
    };
    let layer = OpaqueLayer::clear(W, H, scene.background);
    let expected = |f: usize| {
        translucid::reference::render(&frame_scene(f), &layer)
            .expect("reference")
            .to_srgb8()
    };

    let engine = Engine::new();
    {
        // SAFETY: the engine's live objects, outliving `gpu` (dropped at the end of this block).
        let gpu = unsafe { Gpu::from_host(&engine.host_device()) }.expect("host device");
        let images = EngineImages::of_layer(&gpu, &layer, in_flight).expect("engine images");
        let mut renderer = Renderer::with_frames_in_flight(
            &gpu,
            &scene,
            MethodKind::Exact,
            W,
            H,
            &options,
            in_flight as u32,
        )
        .expect("renderer");
        let mut grown_to = None;
        for first in (0..FRAMES).step_by(in_flight) {
            let batch = first..(first + in_flight).min(FRAMES);
            // Every frame of the batch is recorded before any is submitted: each must keep
            // its own camera and draws.
            for (k, f) in batch.clone().enumerate() {
                set(&mut renderer, f);
                record_engine_frame(&engine, &gpu, &images, &mut renderer, k);
            }
            if batch.len() == in_flight {
                assert_eq!(renderer.frames_in_flight(), in_flight);
                let k = in_flight % 4;
                engine.begin(k);
                // SAFETY: as above; refused before anything is recorded.
                let refused = unsafe { renderer.record_host(&images.targets(engine.cmds[k])) };
                assert!(
                    refused.is_err(),
                    "a frame past the renderer's {in_flight} in flight"
                );
                // SAFETY: ended unsubmitted, reset by the next begin.
                unsafe { engine.device.end_command_buffer(engine.cmds[k]) }.expect("end");
            }
            for k in 0..batch.len() {
                engine.submit(k);
            }
            for (k, f) in batch.enumerate() {
                engine.wait(k);
                let done = renderer
                    .complete_host()
                    .expect("complete")
                    .expect("the submission finished, so the commands ran");
                let learned = renderer.learned_options(&options).bins.initial_bin_entries;
                let got = images.srgb(k).expect("readback");
                let want = expected(f);
                if first_batch != FirstBatch::Fits && first == 0 {
                    // The first completion grows the lists; the frames recorded with the
                    // same small lists leave them be.
                    assert_eq!(*grown_to.get_or_insert(learned), learned, "frame {f}");
                }
                if first_batch == FirstBatch::Degraded && first == 0 {
                    assert!(
                        done.overflowed && done.degraded_rows > 0,
                        "frame {f} had 16 bin entries: {done:?}"
                    );
                    let engine_colour = layer.to_image().to_srgb8();
                    let (got, want, engine_colour) =
                        (pixels(&got), pixels(&want), pixels(&engine_colour));
                    let untouched = (0..got.len())
                        .filter(|&i| worst_difference(got[i], engine_colour[i]) <= 2)
                        .count();
                    let wrong = (0..got.len())
                        .filter(|&i| {
                            worst_difference(got[i], want[i]) > 2
                                && worst_difference(got[i], engine_colour[i]) > 2
                        })
                        .count();
                    assert!(
                        untouched > 0,
                        "frame {f}: no pixel kept the engine's colour"
                    );
                    assert_eq!(
                        wrong, 0,
                        "frame {f}: pixels neither right nor the engine's colour"
                    );
                    continue;
                }
                assert!(!done.overflowed, "frame {f}: {done:?}");
                if first_batch == FirstBatch::InBands && first == 0 {
                    assert!(done.bands > 1, "frame {f} fit in one band: {done:?}");
                }
                let worst = worst_difference(&got, &want);
                assert!(
                    worst <= 2,
                    "{in_flight} in flight, frame {f}: {worst}/255 off the reference"
                );
            }
        }
        assert_eq!(renderer.frames_in_flight(), 0);
    }
    assert_no_validation_errors();
}

#[test]
fn one_frame_in_flight_matches_the_reference() {
    frames_in_flight_match_the_reference(1, MethodOptions::default(), FirstBatch::Fits);
}

#[test]
fn two_frames_in_flight_match_the_reference() {
    frames_in_flight_match_the_reference(2, MethodOptions::default(), FirstBatch::Fits);
}

#[test]
fn three_frames_in_flight_match_the_reference() {
    frames_in_flight_match_the_reference(3, MethodOptions::default(), FirstBatch::Fits);
}

/// Bin lists far too small for the first frames: each frame recorded once comes out right,
/// rasterized in bands, with two frames in flight; the lists grow once.
#[test]
fn frames_whose_bin_lists_overflow_are_right_on_their_one_recording() {
    frames_in_flight_match_the_reference(2, with_bin_entries(BANDED_ENTRIES), FirstBatch::InBands);
}

/// Past the bands a frame records, blocks keep the engine's colour, the frames say so, and
/// the lists grow once for all the frames in flight.
#[test]
fn frames_past_their_bands_keep_the_engines_colour_and_grow_the_lists_once() {
    frames_in_flight_match_the_reference(3, with_bin_entries(16), FirstBatch::Degraded);
}

/// An engine's dynamic resolution: one renderer, made for the largest frame, draws frames of
/// other sizes (other aspect ratios, a single pixel), two in flight at different sizes, each
/// within 2/255 of the reference, under validation: every other frame into the engine's
/// images of its size, the others into the top-left corner of images of the largest size,
/// whose other pixels keep the engine's colour. Once the first frames at the largest size
/// completed, nothing is built or allocated.
#[test]
fn frames_in_flight_at_different_sizes_match_the_reference() {
    frames_in_flight_at_different_sizes(MethodKind::Exact, "spheres");
}

/// The exact peers on an engine's device, two frames in flight, the camera moving and the
/// size changing: their first frames may find the pool or the passes too small (reported
/// overflowed, grown for the frames after), every later frame is within 2/255 of the
/// reference, and nothing is built or allocated once warm.
#[test]
fn the_exact_peers_in_flight_at_different_sizes_match_the_reference() {
    for kind in [MethodKind::LinkedList, MethodKind::DepthPeeling] {
        frames_in_flight_at_different_sizes(kind, "layers");
    }
}

/// Frames of `kind` over `scene_name` orbiting, two in flight, at sizes from 1x1 to the
/// renderer's largest, every other one into engine images larger than the frame.
fn frames_in_flight_at_different_sizes(kind: MethodKind, scene_name: &str) {
    /// The top-left `width` x `height` of RGBA8 `pixels`, `stride` pixels a row.
    fn corner_of(pixels: &[u8], stride: u32, (width, height): (u32, u32)) -> Vec<u8> {
        (0..height as usize)
            .flat_map(|y| {
                let row = y * stride as usize * 4;
                pixels[row..row + width as usize * 4].iter().copied()
            })
            .collect()
    }
    const IN_FLIGHT: usize = 2;
    let scene = translucid::scene::load(scene_name).expect("generated scene");
    let orbit = Orbit::new(&scene);
    let sizes = [
        (W, H),
        (W, H),
        (W, H),
        (W, H),
        (72, 40),
        (33, 61),
        (W, 20),
        (1, 1),
        (50, 50),
        (W, H),
    ];
    let frame_scene = |f: usize| {
        let mut s = scene.clone();
        s.camera = orbit.camera(&scene, f as u32);
        orbit.transparent(&scene, f as u32, &mut s.transparent);
        s
    };
    let layers: Vec<OpaqueLayer> = sizes
        .iter()
        .map(|&(w, h)| OpaqueLayer::clear(w, h, scene.background))
        .collect();
    let engine = Engine::new();
    {
        // SAFETY: the engine's live objects, outliving `gpu` (dropped at the end of this block).
        let gpu = unsafe { Gpu::from_host(&engine.host_device()) }.expect("host device");
        let sized: Vec<EngineImages> = layers
            .iter()
            .map(|layer| EngineImages::of_layer(&gpu, layer, IN_FLIGHT).expect("engine images"))
            .collect();
        let largest = OpaqueLayer::clear(W, H, scene.background);
        let shared = EngineImages::of_layer(&gpu, &largest, IN_FLIGHT).expect("engine images");
        let images = |f: usize| if f % 2 == 0 { &sized[f] } else { &shared };
        let options = MethodOptions::default();
        let mut renderer =
            Renderer::with_frames_in_flight(&gpu, &scene, kind, W, H, &options, IN_FLIGHT as u32)
                .expect("renderer");
        let mut warm = None;
        for first in (0..sizes.len()).step_by(IN_FLIGHT) {
            let batch = first..(first + IN_FLIGHT).min(sizes.len());
            for (k, f) in batch.clone().enumerate() {
                let (width, height) = sizes[f];
                renderer
                    .set_frame(&frame_scene(f).frame_input())
                    .expect("set frame");
                renderer.set_size(width, height).expect("a size within");
                record_engine_frame(&engine, &gpu, images(f), &mut renderer, k);
            }
            let completed = submit_and_complete(&engine, &mut renderer, batch.len());
            for ((k, f), done) in batch.enumerate().zip(completed) {
                if done.overflowed {
                    // Only the exact peers' first frames, whose buffers then grow.
                    assert!(
                        kind != MethodKind::Exact && f < IN_FLIGHT,
                        "{kind} frame {f}: {done:?}"
                    );
                    continue;
                }
                let want = translucid::reference::render(&frame_scene(f), &layers[f])
                    .expect("reference")
                    .to_srgb8();
                let (width, height) = sizes[f];
                let image = images(f);
                let got = image.srgb(k).expect("readback");
                let corner = corner_of(&got, image.extent.width, (width, height));
                let worst = worst_difference(&corner, &want);
                assert!(
                    worst <= 2,
                    "{kind} frame {f} at {width}x{height}: {worst}/255 off the reference"
                );
                let engine_colour = largest.to_image().to_srgb8();
                let outside = (0..got.len() / 4).filter(|&i| {
                    let (x, y) = (i as u32 % image.extent.width, i as u32 / image.extent.width);
                    x >= width || y >= height
                });
                for i in outside {
                    let (got, kept) = (&got[4 * i..4 * i + 4], &engine_colour[4 * i..4 * i + 4]);
                    assert_eq!(
                        got, kept,
                        "frame {f}: pixel {i}, outside the frame, changed"
                    );
                }
            }
            // Warm after the frames at the largest size.
            let built = (gpu.pipelines_created(), gpu.bytes_allocated());
            if let Some(warm) = warm {
                assert_eq!(
                    built, warm,
                    "{kind}: frames {first} and on built or allocated"
                );
            } else if first + IN_FLIGHT >= 4 {
                warm = Some(built);
            }
        }
    }
    assert_no_validation_errors();
}

/// One renderer's first two frames (the scene, then its camera a step along the orbit),
/// both recorded before either is submitted, each recorded once: both must match the
/// reference (stopped at `options.exact.threshold`) and report nothing degraded. The
/// renderer is made with the camera at `made_at` (the scene's own if `None`), which is what it
/// sizes its buffers and picks its shaders from.
fn first_frames_match_the_reference(
    scene: &translucid::scene::Scene,
    (width, height): (u32, u32),
    options: &MethodOptions,
    made_at: Option<translucid::scene::Camera>,
) -> FirstFrames {
    let mut bands = Vec::new();
    let mut fragments = Vec::new();
    let learned;
    let orbit = Orbit::new(scene);
    let frame_scene = |f: u32| {
        let mut s = scene.clone();
        s.camera = orbit.camera(scene, f);
        s
    };
    let layer = OpaqueLayer::clear(width, height, scene.background);
    let engine = Engine::new();
    {
        // SAFETY: the engine's live objects, outliving `gpu` (dropped at the end of this block).
        let gpu = unsafe { Gpu::from_host(&engine.host_device()) }.expect("host device");
        let images = EngineImages::of_layer(&gpu, &layer, 2).expect("engine images");
        let mut made_for = scene.clone();
        made_for.camera = made_at.unwrap_or(scene.camera);
        let mut renderer = Renderer::with_frames_in_flight(
            &gpu,
            &made_for,
            MethodKind::Exact,
            width,
            height,
            options,
            2,
        )
        .expect("renderer");
        for k in 0..2 {
            renderer
                .set_frame(&frame_scene(k as u32).frame_input())
                .expect("set frame");
            record_engine_frame(&engine, &gpu, &images, &mut renderer, k);
        }
        for (k, done) in submit_and_complete(&engine, &mut renderer, 2)
            .into_iter()
            .enumerate()
        {
            assert!(
                !done.overflowed && done.degraded_rows == 0,
                "{}, frame {k}: {done:?}",
                scene.name
            );
            let want = translucid::reference::render_until(
                &frame_scene(k as u32),
                &layer,
                options.exact.threshold,
            )
            .expect("reference")
            .to_srgb8();
            let worst = worst_difference(&images.srgb(k).expect("readback"), &want);
            assert!(worst <= 2, "{}, frame {k}: {worst}/255 off", scene.name);
            bands.push(done.bands);
            fragments.push(done.fragments);
        }
        learned = renderer.learned_options(options);
    }
    assert_no_validation_errors();
    FirstFrames {
        bands,
        fragments,
        learned,
    }
}

/// What [`first_frames_match_the_reference`] saw of its two frames.
struct FirstFrames {
    bands: Vec<u32>,
    /// Fragments composited, as each frame reported them.
    fragments: Vec<u64>,
    /// The options the renderer learned (the buffers it grew).
    learned: MethodOptions,
}

/// Every way a frame's work can outgrow what its renderer expected, each forced on a
/// renderer's first frames, recorded once with two frames in flight: the frames are right.
/// - Bin lists far too small: the frames are rasterized in bands.
/// - Pixels 720 fragments deep in one slab, past the loop budget, with state slots for 4 of
///   the rows that suspend: those keep their state, the others start over when resumed.
/// - One bin whose list no loop budget walks in one pass, in a frame of a renderer made
///   looking away from it (so expecting shallow pixels): its rows are suspended before
///   walking and walked in parts by the continuations.
/// - 200 quads through the camera plane: their homogeneous records are sized from the draws
///   that cross it (they were a 64th of the frame's triangles, or 64).
#[test]
fn every_overflow_on_a_first_and_only_recording_matches_the_reference() {
    let spheres = translucid::scene::load("spheres").expect("generated scene");
    let small_lists = with_bin_entries(BANDED_ENTRIES);
    let bands = first_frames_match_the_reference(&spheres, (W, H), &small_lists, None).bands;
    assert!(bands.iter().all(|&b| b > 1), "bands {bands:?}");

    let deep = one_depth_stack(720);
    // Lists that fit, so that the rows' continuations are all in one band.
    let mut few_states = with_bin_entries(1 << 20);
    few_states.bins.initial_resume_rows = Some(4);
    let restarted = first_frames_match_the_reference(&deep, (45, 37), &few_states, None);
    assert!(
        restarted.learned.bins.initial_resume_rows > Some(4),
        "no row went without a state slot: {:?}",
        restarted.learned
    );
    // A row that started over counts its fragments once, as with a state slot for every row.
    let mut every_state = few_states.clone();
    every_state.bins.initial_resume_rows = Some(1 << 12);
    let kept = first_frames_match_the_reference(&deep, (45, 37), &every_state, None);
    assert_eq!(restarted.fragments, kept.fragments);

    let mut stopped_early = MethodOptions::default();
    stopped_early.exact.threshold = 0.01;
    let crowd = crowded_bin(100_000);
    let looking_away = Camera::look_at(Vec3::ZERO, Vec3::Z, 1.0, 0.1, 20.0);
    first_frames_match_the_reference(&crowd, (8, 8), &stopped_early, Some(looking_away));
    let mut through_the_eye = near_plane_scene();
    let tilted = through_the_eye.transparent[1].clone();
    through_the_eye
        .transparent
        .extend((0..200).map(|i| translucid::scene::Draw {
            transform: glam::Mat4::from_translation(Vec3::new(i as f32 * 0.01 - 1.0, 0.0, 0.0)),
            ..tilted.clone()
        }));
    first_frames_match_the_reference(
        &through_the_eye,
        (157, 119),
        &MethodOptions::default(),
        None,
    );
}

/// Default options with the bins' lists starting at `entries`.
fn with_bin_entries(entries: u32) -> MethodOptions {
    let mut options = MethodOptions::default();
    options.bins.initial_bin_entries = Some(entries);
    options
}

/// One engine depth format: its texel bytes for device depth `v`, and the depth translucid
/// reads back from them.
fn encode_depth(format: vk::Format, v: f32) -> (Vec<u8>, f32) {
    match format {
        vk::Format::D16_UNORM => {
            let k = (v * 65535.0).round() as u16;
            (k.to_le_bytes().to_vec(), f32::from(k) / 65535.0)
        }
        vk::Format::X8_D24_UNORM_PACK32 | vk::Format::D24_UNORM_S8_UINT => {
            let k = (v * 16_777_215.0).round() as u32;
            (k.to_le_bytes().to_vec(), k as f32 / 16_777_215.0)
        }
        _ => (v.to_le_bytes().to_vec(), v),
    }
}

/// `scene`'s camera with the same field of view and planes as a reversed-Z matrix.
fn reversed_camera(scene: &Scene) -> Camera {
    let Projection::Perspective { fov_y, near, far } = scene.camera.projection else {
        panic!("the scene has a perspective camera");
    };
    Camera {
        projection: Projection::Matrix({
            let mut p = Mat4::perspective_rh(fov_y, W as f32 / H as f32, far, near);
            p.y_axis.y = -p.y_axis.y;
            p
        }),
        ..scene.camera
    }
}

/// `layer` with a wall for depth, `wall(x)` in column x (device depth growing away from the
/// eye), held in `format` (turned around when `reversed`): the texels, and the layer with
/// the depth translucid reads back from them.
fn wall_layer(
    layer: &OpaqueLayer,
    format: vk::Format,
    reversed: bool,
    wall: impl Fn(u32) -> f32,
) -> (OpaqueLayer, Vec<u8>) {
    let mut layer = layer.clone();
    let mut bytes = Vec::new();
    for (i, depth) in layer.depth.iter_mut().enumerate() {
        let d = wall(i as u32 % W);
        let (texel, read) = encode_depth(format, if reversed { 1.0 - d } else { d });
        bytes.extend(texel);
        *depth = if reversed { 1.0 - read } else { read };
    }
    (layer, bytes)
}

/// The engine's depth in each format translucid reads, growing away from the eye and
/// reversed-Z (sampled and turned around), one frame of each on a renderer per direction:
/// each frame is the reference's over the depth the image holds. The opaque depth is a wall slanting through the spheres, so that it hides
/// part of them.
#[test]
fn engine_depth_in_every_format_and_direction_matches_the_reference() {
    let scene = translucid::scene::load("spheres").expect("generated scene");
    // The wall: at view distances from the nearest to the farthest transparent vertex,
    // left to right.
    let eye = scene.camera.view.inverse().w_axis.truncate();
    let distances: Vec<f32> = scene
        .transparent
        .iter()
        .flat_map(|d| {
            let positions = &scene.meshes[d.mesh].positions;
            positions
                .iter()
                .map(move |&p| d.transform.transform_point3(p))
        })
        .map(|p| p.distance(eye))
        .collect();
    let nearest = distances.iter().copied().fold(f32::MAX, f32::min);
    let farthest = distances.iter().copied().fold(0.0, f32::max);
    let (a, b, _) = scene.camera.depth_mapping(W, H);
    let wall = |x: u32| {
        let z = nearest + (farthest - nearest) * (x as f32 + 0.5) / W as f32;
        a - b / z
    };
    let far_layer = OpaqueLayer::clear(W, H, scene.background);
    let reversed_camera = reversed_camera(&scene);
    let engine = Engine::new();
    {
        // SAFETY: the engine's live objects, outliving `gpu` (dropped at the end of this block).
        let gpu = unsafe { Gpu::from_host(&engine.host_device()) }.expect("host device");
        for reversed in [false, true] {
            let mut frame_scene = scene.clone();
            if reversed {
                frame_scene.camera = reversed_camera;
            }
            // One renderer for the formats, a frame each: its slot's import is made, then
            // rewritten for another image.
            let mut renderer =
                Renderer::new(&gpu, &frame_scene, MethodKind::Exact, W, H).expect("renderer");
            for format in translucid::gpu::HOST_DEPTH_FORMATS {
                let (layer, bytes) = wall_layer(&far_layer, format, reversed, wall);
                let label = format!("{format:?}{}", if reversed { " reversed" } else { "" });
                let images = EngineImages::of_layer_with_depth(&gpu, &layer, 1, format, &bytes)
                    .expect("engine images");
                let done = one_engine_frame(&engine, &gpu, &images, &mut renderer);
                assert!(!done.overflowed, "{label}: {done:?}");
                let want = translucid::reference::render(&frame_scene, &layer).expect("reference");
                let worst = worst_difference(&images.srgb(0).expect("readback"), &want.to_srgb8());
                assert!(worst <= 2, "{label}: {worst}/255 off the reference");
                // The wall hides part of the spheres: the depth read matters.
                let unhidden = translucid::reference::render(&frame_scene, &far_layer)
                    .expect("reference")
                    .to_srgb8();
                let hidden = pixels(&want.to_srgb8())
                    .iter()
                    .zip(pixels(&unhidden))
                    .filter(|(a, b)| worst_difference(a, b) > 8)
                    .count();
                assert!(
                    hidden > (W * H / 20) as usize,
                    "{label}: {hidden} pixels hidden"
                );
            }
        }
    }
    assert_no_validation_errors();
}

/// An engine on synchronization2 leaves its images in ATTACHMENT_OPTIMAL (colour) and
/// READ_ONLY_OPTIMAL (depth): translucid takes them from and back to those layouts, copying
/// D32 depth and sampling D16, and the frames match the reference.
#[test]
fn engine_images_in_synchronization2_layouts() {
    let (scene, layer, _) = spheres_standalone();
    let engine = Engine::with_synchronization2(true);
    {
        // SAFETY: the engine's live objects, outliving `gpu` (dropped at the end of this block).
        let gpu = unsafe { Gpu::from_host(&engine.host_device()) }.expect("host device");
        let mut renderer = Renderer::new(&gpu, &scene, MethodKind::Exact, W, H).expect("renderer");
        // D16 holds the layer's depth rounded: the reference is rendered over what it holds.
        for format in [vk::Format::D32_SFLOAT, vk::Format::D16_UNORM] {
            let mut held = layer.clone();
            let mut bytes = Vec::new();
            for depth in held.depth.iter_mut() {
                let (texel, read) = encode_depth(format, *depth);
                bytes.extend(texel);
                *depth = read;
            }
            let images = EngineImages::of_layer_with_depth(&gpu, &held, 1, format, &bytes)
                .expect("engine images")
                .in_layouts(
                    vk::ImageLayout::ATTACHMENT_OPTIMAL,
                    vk::ImageLayout::READ_ONLY_OPTIMAL,
                );
            let done = one_engine_frame(&engine, &gpu, &images, &mut renderer);
            assert!(!done.overflowed, "{format:?}: {done:?}");
            let want = translucid::reference::render(&scene, &held)
                .expect("reference")
                .to_srgb8();
            let worst = worst_difference(&images.srgb(0).expect("readback"), &want);
            assert!(worst <= 2, "{format:?}: {worst}/255 off");
        }
    }
    assert_no_validation_errors();
}

/// An engine that enables subgroup size control and says so gets tiles of one subgroup's
/// pixels for exact and wavelet, as translucid's own device does: 8x2 at lavapipe's 16 lanes
/// (512 bits), where an engine that does not say so gets rows; a row at 8 lanes, and at
/// 1024 and 2048 bits, where lavapipe runs 16 of the lanes it reports (docs/gpu.md). The
/// frames match the reference under validation, which checks the pipelines' required
/// subgroup sizes against what the engine enabled. Rerun at lavapipe's wider sizes.
#[test]
fn an_engine_with_subgroup_size_control_gets_subgroup_tiles() {
    let (scene, layer, _) = spheres_standalone();
    let width = std::env::var("LP_NATIVE_VECTOR_WIDTH").ok();
    let expected_rows = if width.as_deref() == Some("512") {
        2
    } else {
        1
    };
    let tile_rows =
        |gpu: &Gpu| 1 << translucid::methods::bins::features::tile_shift(gpu.info().into());
    let on_lavapipe;
    {
        let plain = Engine::new();
        // SAFETY: the engine's live objects, outliving `gpu` (dropped at the end of this block).
        let gpu = unsafe { Gpu::from_host(&plain.host_device()) }.expect("host device");
        assert_eq!(tile_rows(&gpu), 1, "no size control said: rows");
        on_lavapipe = gpu.info().name.contains("llvmpipe");
        // SAFETY: a physical device of the engine's live instance.
        let extensions = unsafe {
            plain
                .instance
                .enumerate_device_extension_properties(plain.physical)
        }
        .expect("extensions");
        let listed = extensions
            .iter()
            .any(|e| e.extension_name_as_c_str() == Ok(ash::ext::subgroup_size_control::NAME));
        if !listed {
            assert!(!on_lavapipe, "lavapipe lists VK_EXT_subgroup_size_control");
            eprintln!("{}: no subgroup size control to enable", gpu.info().name);
            return;
        }
    }
    let engine = Engine::with_subgroup_size_control();
    {
        // SAFETY: as above.
        let gpu = unsafe { Gpu::from_host(&engine.host_device()) }.expect("host device");
        if on_lavapipe {
            assert_eq!(tile_rows(&gpu), expected_rows, "{:?}", gpu.info());
        }
        // Wavelet in its bins, whose raster is the one with tiles, against its CPU model.
        let mut options = MethodOptions::default();
        options.wavelet.storage = Some(Storage::Bins);
        let settings =
            translucid::methods::wavelet::Settings::from_options(&options.wavelet, gpu.profile())
                .expect("settings");
        let model = translucid::methods::wavelet::model::Model::new(settings, &scene, W, H)
            .render(&scene, &layer)
            .expect("model");
        let reference = translucid::reference::render(&scene, &layer).expect("reference");
        for (kind, want) in [
            (MethodKind::Exact, reference.to_srgb8()),
            (MethodKind::Wavelet, model.to_srgb8()),
        ] {
            let mut renderer =
                Renderer::with_frames_in_flight(&gpu, &scene, kind, W, H, &options, 1)
                    .expect("renderer");
            let images = EngineImages::of_layer(&gpu, &layer, 1).expect("engine images");
            let done = one_engine_frame(&engine, &gpu, &images, &mut renderer);
            assert!(!done.overflowed, "{kind:?}: {done:?}");
            let worst = worst_difference(&images.srgb(0).expect("readback"), &want);
            assert!(worst <= 2, "{kind:?}: {worst}/255 off");
        }
    }
    assert_no_validation_errors();
    if on_lavapipe {
        let gpu = Gpu::new(&GpuOptions::default()).expect("device");
        translucid_tests::rerun_at_lavapipe_subgroup_sizes(
            &gpu,
            &["an_engine_with_subgroup_size_control_gets_subgroup_tiles"],
        );
    }
}

/// On the engine's device, a texture added after the first frame (`ResidentAssets::extended`)
/// is copied into its image by the next frame recorded over the grown assets, and again by a
/// later one when the frame that carried it was never submitted (its staging kept until
/// then, freed once that frame completes), whether the renderer that recorded it was dropped
/// or told that the frame was abandoned and kept; so is the mesh added with it, into the
/// device-local vertex and index buffers. `blend` samples the images: its frame over the
/// copies is the frame over the originals.
#[test]
fn textures_added_later_are_uploaded_by_the_next_frame() {
    for recorder_kept in [false, true] {
        textures_added_later_are_uploaded_after_an_abandoned_frame(recorder_kept);
    }
}

fn textures_added_later_are_uploaded_after_an_abandoned_frame(recorder_kept: bool) {
    let scene = translucid::scene::load("textured").expect("generated scene");
    let grown = translucid_tests::with_copied_assets(&scene);
    let layer = OpaqueLayer::clear(W, H, scene.background);
    let engine = Engine::new();
    {
        // SAFETY: the engine's live objects, outliving `gpu` (dropped at the end of this block).
        let gpu = unsafe { Gpu::from_host(&engine.host_device()) }.expect("host device");
        let images = EngineImages::of_layer(&gpu, &layer, 1).expect("engine images");
        let engines = staging_allocations(&gpu);
        let mut first = Renderer::new(&gpu, &scene, MethodKind::Blend, W, H).expect("renderer");
        one_engine_frame(&engine, &gpu, &images, &mut first);
        let expected = images.srgb(0).expect("readback");
        assert_eq!(
            staging_allocations(&gpu),
            engines,
            "the first frame's uploads ran"
        );
        let extended = std::sync::Arc::new(
            first
                .resident()
                .extended(&gpu, &grown)
                .expect("extended")
                .expect("room for one more texture"),
        );
        let shape = translucid::renderer::FrameShape {
            width: W,
            height: H,
            frames_in_flight: 1,
        };
        let options = MethodOptions::default();
        let sharing = || {
            Renderer::sharing(
                &gpu,
                extended.clone(),
                &grown,
                MethodKind::Blend,
                shape,
                &options,
            )
            .expect("renderer over the grown assets")
        };
        // A frame that carries the texture's upload is recorded, never submitted, and
        // abandoned: its renderer dropped, or told so (`abandon_host`) and kept while another
        // renderer's frame, the next, uploads it.
        let mut abandoned = sharing();
        engine.begin(0);
        images.record_opaque(&gpu, engine.cmds[0]);
        // SAFETY: as above; the commands are never submitted.
        unsafe { abandoned.record_host(&images.targets(engine.cmds[0])) }.expect("record");
        // SAFETY: ended unsubmitted, reset by the next begin.
        unsafe { engine.device.end_command_buffer(engine.cmds[0]) }.expect("end");
        let recorder = if recorder_kept {
            abandoned.abandon_host(1).expect("abandon");
            Some(abandoned)
        } else {
            drop(abandoned);
            None
        };
        // The abandoned frame's uploads are pending again, their staging kept for the next.
        let pending = staging_allocations(&gpu);
        assert!(
            pending.len() > engines.len(),
            "the added texture's staging went with the abandoned frame: {pending:?}"
        );
        one_engine_frame(&engine, &gpu, &images, &mut sharing());
        assert_eq!(
            staging_allocations(&gpu),
            engines,
            "the next frame's uploads completed"
        );
        let got = images.srgb(0).expect("readback");
        let worst = worst_difference(&got, &expected);
        assert_eq!(
            worst, 0,
            "{worst}/255 off the frame over the original assets (recorder kept: {recorder_kept})"
        );
        drop(recorder);
    }
    assert_no_validation_errors();
}

/// On an engine's device, which translucid never submits to, the assets are device-local
/// too: a vendored scene with a textured transparent surface (spot) is uploaded by staged
/// copies that exact's first frame records into the engine's command buffer. Their staging
/// lives until translucid knows that frame completed (a submission that ran is not enough),
/// then goes: live memory drops by exactly its bytes, and only the engine's own staging (its
/// opaque layer's) is left. The frame over the copies matches the reference, and nothing the
/// pipelines read is host-visible but per-frame data.
#[test]
fn assets_are_device_local_and_their_staging_goes_when_the_first_frame_completes() {
    let path = asset("spot/spot_blend.gltf");
    let scene = translucid::scene::load(path.to_str().expect("utf-8 path")).expect("spot");
    let layer = OpaqueLayer::clear(W, H, scene.background);
    let engine = Engine::new();
    {
        // SAFETY: the engine's live objects, outliving `gpu` (dropped at the end of this block).
        let gpu = unsafe { Gpu::from_host(&engine.host_device()) }.expect("host device");
        let images = EngineImages::of_layer(&gpu, &layer, 1).expect("engine images");
        let engines = staging_allocations(&gpu);
        let mut renderer = Renderer::new(&gpu, &scene, MethodKind::Exact, W, H).expect("renderer");
        let staged: Vec<_> = staging_allocations(&gpu)
            .into_iter()
            .filter(|s| !engines.contains(s))
            .collect();
        let texture_bytes = scene.textures[0].texel_bytes();
        let staged_bytes: u64 = staged.iter().map(|(_, bytes)| bytes).sum();
        assert!(
            staged_bytes >= texture_bytes,
            "the texture's {texture_bytes} bytes wait in staging for the first frame: {staged:?}"
        );
        record_engine_frame(&engine, &gpu, &images, &mut renderer, 0);
        engine.submit_and_wait();
        assert_eq!(
            staging_allocations(&gpu).len(),
            engines.len() + staged.len(),
            "the staging goes only when translucid knows the frame completed"
        );
        let live = gpu.memory_in_use().0;
        let done = renderer
            .complete_host()
            .expect("complete")
            .expect("the submission finished, so the commands ran");
        assert!(!done.overflowed, "{done:?}");
        assert_eq!(
            staging_allocations(&gpu),
            engines,
            "the uploads' staging outlived the frame that carried them"
        );
        assert_eq!(
            live - gpu.memory_in_use().0,
            staged_bytes,
            "completing the frame freed other than the staging"
        );
        assert_only_per_frame_data_is_host_visible(
            &gpu,
            "exact on the engine's device",
            &[
                "scene vertices",
                "scene quads",
                "scene materials",
                "sampled texels",
                "sampled texture records",
                scene.textures[0].name.as_str(),
            ],
        );
        let want = translucid::reference::render(&scene, &layer)
            .expect("reference")
            .to_srgb8();
        let worst = worst_difference(&images.srgb(0).expect("readback"), &want);
        assert!(worst <= 2, "{worst}/255 off the reference");
    }
    assert_no_validation_errors();
}

/// The software sampler copies a texture when a frame's transparent draws first use it, on an
/// engine's device, two frames in flight: `textured`'s draws join one a frame, each with its
/// own texture, added in place while the frame before is recorded and not yet submitted;
/// then a 256² texture too large for the room left, which takes a new set of buffers while
/// a frame recorded with the old set is in flight. Every frame is within 2/255 of the
/// reference, under validation.
#[test]
fn textures_first_used_by_frames_in_flight_match_the_reference() {
    const IN_FLIGHT: usize = 2;
    let textured = translucid::scene::load("textured").expect("generated scene");
    let (scene, large) = translucid_tests::with_large_texture(&textured, 256);
    let joined = scene.transparent.len();
    // Frame f draws the first f + 1 transparent draws, and the last frames the large one too.
    let frames = joined + 3;
    let frame_scene = |f: usize| {
        let mut s = scene.clone();
        s.transparent.truncate(f + 1);
        if f >= joined {
            s.transparent.push(large.clone());
        }
        s
    };
    let layer = OpaqueLayer::clear(W, H, scene.background);
    let engine = Engine::new();
    {
        // SAFETY: the engine's live objects, outliving `gpu` (dropped at the end of this block).
        let gpu = unsafe { Gpu::from_host(&engine.host_device()) }.expect("host device");
        let images = EngineImages::of_layer(&gpu, &layer, IN_FLIGHT).expect("engine images");
        let mut renderer = Renderer::with_frames_in_flight(
            &gpu,
            &frame_scene(0),
            MethodKind::Exact,
            W,
            H,
            &MethodOptions::default(),
            IN_FLIGHT as u32,
        )
        .expect("renderer");
        for first in (0..frames).step_by(IN_FLIGHT) {
            let batch = first..(first + IN_FLIGHT).min(frames);
            for (k, f) in batch.clone().enumerate() {
                let allocated = gpu.bytes_allocated();
                renderer
                    .set_frame(&frame_scene(f).frame_input())
                    .expect("set frame");
                record_engine_frame(&engine, &gpu, &images, &mut renderer, k);
                if f == joined {
                    // Level 0 alone: the large texture was copied, into a new set.
                    assert!(
                        gpu.bytes_allocated() - allocated >= 256 * 256 * 4,
                        "frame {f} first draws the large texture and copied none of it"
                    );
                }
            }
            let completed = submit_and_complete(&engine, &mut renderer, batch.len());
            for ((k, f), done) in batch.enumerate().zip(completed) {
                assert!(!done.overflowed, "frame {f}: {done:?}");
                let want = translucid::reference::render(&frame_scene(f), &layer)
                    .expect("reference")
                    .to_srgb8();
                let worst = worst_difference(&images.srgb(k).expect("readback"), &want);
                assert!(worst <= 2, "frame {f}: {worst}/255 off the reference");
            }
        }
    }
    assert_no_validation_errors();
}

/// The yardstick, `Renderer::record_native_blend`, draws straight into the engine's images
/// what translucid's `blend` draws in a standalone frame over the same opaque layer (through
/// its own targets), and the `blend` method on the engine's device draws the same (it is the
/// same pass): in each depth format the engine may hold, growing away from the eye and
/// reversed-Z (the wall of the depth-format test hides part of the spheres); and both leave
/// every pixel no transparent fragment covers bit for bit as the engine's opaque pass left
/// it.
#[test]
fn native_blend_and_blend_draw_into_the_engines_images_what_standalone_blend_draws() {
    let scene = translucid::scene::load("spheres").expect("generated scene");
    let background = OpaqueLayer::clear(W, H, scene.background);
    // The wall slants from just in front of the spheres' centre (left) to behind them.
    let (a, b, _) = scene.camera.depth_mapping(W, H);
    let eye = scene.camera.view.inverse().w_axis.truncate();
    let centre = eye.length();
    let wall = |x: u32| {
        let z = centre * (0.8 + 0.4 * (x as f32 + 0.5) / W as f32);
        a - b / z
    };
    let reversed_camera = reversed_camera(&scene);
    // Pixels that no transparent fragment covers: the reference leaves the background.
    let uncovered: Vec<bool> = {
        let marked = OpaqueLayer::clear(W, H, glam::Vec3::new(0.25, 0.5, 0.75));
        let over = translucid::reference::render(&scene, &marked).expect("reference");
        over.pixels
            .iter()
            .map(|p| *p == glam::Vec4::new(0.25, 0.5, 0.75, 1.0))
            .collect()
    };
    assert!(uncovered.iter().any(|&u| u) && uncovered.iter().any(|&u| !u));
    let standalone = Gpu::new(&GpuOptions {
        device: None,
        validation: true,
        profile: None,
        software_sampling: false,
        ..Default::default()
    })
    .expect("a Vulkan device with the validation layer");
    let engine = Engine::new();
    {
        // SAFETY: the engine's live objects, outliving `gpu` (dropped at the end of this block).
        let gpu = unsafe { Gpu::from_host(&engine.host_device()) }.expect("host device");
        for reversed in [false, true] {
            let mut frame_scene = scene.clone();
            if reversed {
                frame_scene.camera = reversed_camera;
            }
            let mut renderer =
                Renderer::new(&gpu, &frame_scene, MethodKind::Blend, W, H).expect("renderer");
            let mut alone = Renderer::new(&standalone, &frame_scene, MethodKind::Blend, W, H)
                .expect("standalone renderer");
            for format in translucid::gpu::HOST_DEPTH_FORMATS {
                let (layer, bytes) = wall_layer(&background, format, reversed, wall);
                let label = format!("{format:?}{}", if reversed { " reversed" } else { "" });
                let in_place = EngineImages::of_layer_with_depth(&gpu, &layer, 1, format, &bytes)
                    .expect("engine images");
                let done = one_engine_frame(&engine, &gpu, &in_place, &mut renderer);
                assert_eq!(
                    done.stages.iter().map(|(s, _)| *s).collect::<Vec<_>>(),
                    ["blend"],
                    "{label}: blend on the engine's device copies nothing"
                );
                let native = EngineImages::of_layer_with_depth(&gpu, &layer, 1, format, &bytes)
                    .expect("engine images");
                engine.begin(0);
                let cmd = engine.cmds[0];
                native.record_opaque(&gpu, cmd);
                // SAFETY: the engine's recording command buffer and images of the frame's
                // size, made with attachment usage.
                unsafe { renderer.record_native_blend(&native.targets(cmd)) }.expect("record");
                native.record_readback(&gpu, cmd, 0);
                engine.submit_and_wait();
                let done = renderer
                    .complete_host()
                    .expect("complete")
                    .expect("the submission finished, so the commands ran");
                assert_eq!(
                    done.stages.iter().map(|(s, _)| *s).collect::<Vec<_>>(),
                    ["native blend"]
                );

                // The blend method on the engine's device is the same pass.
                let got = native.srgb(0).expect("readback");
                assert_eq!(got, in_place.srgb(0).expect("readback"), "{label}");
                // Against blend through its own targets: the depth test is the same but for
                // the rounding of D16 and D24 depth, which may flip a pixel on the wall's edge.
                let want = alone.render_over(&layer).expect("frame").image.to_srgb8();
                let off = pixels(&got)
                    .iter()
                    .zip(pixels(&want))
                    .filter(|(g, w)| worst_difference(g, w) > 1)
                    .count();
                assert!(
                    off <= (W * H / 200) as usize,
                    "{label}: {off} pixels differ from blend's"
                );
                // The wall hides part of the spheres: the depth test ran.
                let unhidden =
                    translucid::reference::render_in_submission_order(&frame_scene, &background)
                        .expect("reference")
                        .to_srgb8();
                let hidden = pixels(&got)
                    .iter()
                    .zip(pixels(&unhidden))
                    .filter(|(g, u)| worst_difference(g, u) > 8)
                    .count();
                assert!(hidden > (W * H / 20) as usize, "{label}: {hidden} hidden");
                // Uncovered pixels keep the engine's colour bit for bit.
                for images in [&native, &in_place] {
                    let held = images.outs[0].read().expect("readback");
                    let given = images.colour_in.read().expect("upload buffer");
                    for (i, _) in uncovered.iter().enumerate().filter(|(_, &u)| u) {
                        assert_eq!(
                            held[8 * i..8 * i + 8],
                            given[8 * i..8 * i + 8],
                            "{label}: pixel {i} outside the transparent layer changed"
                        );
                    }
                }
            }
        }
    }
    assert_no_validation_errors();
}

/// An engine that asks for the software sampler (`HostDevice::software_sampling`, the C
/// flag in host-device mode) keeps it where the GPU profile would sample textures in
/// hardware, as translucid's own devices do (`GpuOptions::software_sampling`).
#[test]
fn an_engine_that_asks_for_the_software_sampler_keeps_it() {
    let engine = Engine::new();
    let from_env = translucid::gpu::software_sampling_asked().expect("environment");
    for asked in [false, true] {
        let host = HostDevice {
            software_sampling: asked,
            profile: Some(translucid::gpu::Profile::Gpu),
            ..engine.host_device()
        };
        // SAFETY: the engine's live objects, outliving `gpu` (dropped in this iteration).
        let gpu = unsafe { Gpu::from_host(&host) }.expect("host device");
        assert_eq!(
            gpu.info().software_sampling,
            asked || from_env,
            "asked: {asked}"
        );
    }
}

/// One plain blended frame: what the reruns at lavapipe's wider sizes run, where a rerun dies,
/// to tell lavapipe's own compiler dying on any draw there from this binary's tests failing
/// (`translucid_tests::rerun_at_lavapipe_subgroup_sizes`).
#[test]
fn lavapipe_draws_a_plain_frame() {
    translucid_tests::draw_one_plain_frame();
}

/// The methods sized from the frames before, which cannot have counted this one: a camera
/// moving into a cloud of particles (the same draws, more of the screen and more layers
/// every frame), 3 frames in flight, each recorded once. linked_list's pool and
/// depth_peeling's passes follow each frame's estimate, made before it is recorded: no frame
/// overflows, blends a fragment unsorted or leaves a layer unpeeled. (Before the estimate,
/// linked_list's frame 1 left 4,956 fragments unsorted, and depth_peeling's first frame,
/// 72 layers deep, 576 pixels unpeeled.)
#[test]
fn a_camera_moving_into_a_cloud_is_right_on_every_frame_in_flight() {
    const FRAMES: usize = 9;
    const IN_FLIGHT: usize = 3;
    let scene = translucid::scene::load("particles").expect("generated scene");
    // Along the camera's axis, from where it stands to a tenth of the way from the cloud's
    // centre.
    let centre = {
        let points: Vec<Vec3> = scene
            .transparent
            .iter()
            .flat_map(|d| {
                scene.meshes[d.mesh]
                    .positions
                    .iter()
                    .map(|&p| d.transform.transform_point3(p))
            })
            .collect();
        points.iter().copied().sum::<Vec3>() / points.len() as f32
    };
    let depth = -scene.camera.view.transform_point3(centre).z;
    let frame_scene = |f: usize| {
        let mut s = scene.clone();
        let forward = depth * 0.9 * f as f32 / (FRAMES - 1) as f32;
        s.camera.view = Mat4::from_translation(Vec3::new(0.0, 0.0, forward)) * scene.camera.view;
        s
    };
    let layer = OpaqueLayer::clear(W, H, scene.background);
    let engine = Engine::new();
    for kind in [MethodKind::LinkedList, MethodKind::DepthPeeling] {
        // SAFETY: the engine's live objects, outliving `gpu` (dropped at the end of the loop).
        let gpu = unsafe { Gpu::from_host(&engine.host_device()) }.expect("host device");
        let images = EngineImages::of_layer(&gpu, &layer, IN_FLIGHT).expect("engine images");
        let options = MethodOptions::default();
        // The first frame is the scene the renderer is made with, as a context's first frame
        // of a method is: nothing sets it.
        let first_scene = frame_scene(0);
        let frames = IN_FLIGHT as u32;
        let mut renderer =
            Renderer::with_frames_in_flight(&gpu, &first_scene, kind, W, H, &options, frames)
                .expect("renderer");
        let mut fragments = Vec::new();
        for first in (0..FRAMES).step_by(IN_FLIGHT) {
            let batch = first..(first + IN_FLIGHT).min(FRAMES);
            for (k, f) in batch.clone().enumerate() {
                if f > 0 {
                    renderer
                        .set_frame(&frame_scene(f).frame_input())
                        .expect("set frame");
                }
                record_engine_frame(&engine, &gpu, &images, &mut renderer, k);
            }
            for (f, done) in batch.zip(submit_and_complete(&engine, &mut renderer, IN_FLIGHT)) {
                assert!(
                    !done.overflowed && done.tail_fragments == 0 && done.unpeeled_pixels == 0,
                    "{kind:?}, frame {f}: {done:?}"
                );
                fragments.push(done.fragments);
            }
        }
        if kind == MethodKind::LinkedList {
            // The camera did come into the cloud: the deepest frame has three times the
            // first's fragments (the last ones fewer: part of the cloud is behind it).
            let deepest = fragments.iter().copied().max().unwrap_or(0);
            assert!(
                deepest > 3 * fragments[0],
                "fragments per frame: {fragments:?}"
            );
        }
    }
    assert_no_validation_errors();
}
