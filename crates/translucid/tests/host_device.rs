//! Host-device mode from Rust, for what the C test cannot reach: the exact method started with
//! bin lists far too small, so that its first recorded frame overflows. Completion must say so,
//! and the same frame recorded again must match standalone mode.
//!
//! The test plays the engine with ash: its own instance (with the validation layer and a
//! messenger that collects errors), device, command buffer and submission.

use ash::vk;
use std::ffi::{c_void, CStr};
use std::sync::Mutex;
use translucid::gpu::{
    host_requirements, image_barrier, Gpu, GpuImage, GpuOptions, HostDevice, HostImage,
    HostTargets, MemoryLocation,
};
use translucid::methods::MethodOptions;
use translucid::renderer::Renderer;
use translucid::OpaqueLayer;

const W: u32 = 96;
const H: u32 = 64;

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
    cmd: vk::CommandBuffer,
    fence: vk::Fence,
    features: vk::PhysicalDeviceFeatures,
}

impl Engine {
    fn new() -> Self {
        let wanted = host_requirements();
        // SAFETY: plain Vulkan object creation, each call given live parents and create infos
        // that outlive it; this is test code standing in for an engine.
        unsafe {
            let entry = ash::Entry::load().expect("the Vulkan loader");
            let app = vk::ApplicationInfo::default().api_version(wanted.api_version);
            let layers = [c"VK_LAYER_KHRONOS_validation".as_ptr()];
            let extensions = [ash::ext::debug_utils::NAME.as_ptr()];
            let instance = entry
                .create_instance(
                    &vk::InstanceCreateInfo::default()
                        .application_info(&app)
                        .enabled_layer_names(&layers)
                        .enabled_extension_names(&extensions),
                    None,
                )
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
            let device = instance
                .create_device(
                    physical,
                    &vk::DeviceCreateInfo::default()
                        .queue_create_infos(&queues)
                        .enabled_features(&features),
                    None,
                )
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
            let cmd = device
                .allocate_command_buffers(
                    &vk::CommandBufferAllocateInfo::default()
                        .command_pool(pool)
                        .command_buffer_count(1),
                )
                .expect("command buffer")[0];
            let fence = device
                .create_fence(&vk::FenceCreateInfo::default(), None)
                .expect("fence");
            Self {
                _entry: entry,
                instance,
                messenger: (loader, messenger),
                physical,
                device,
                family,
                queue,
                pool,
                cmd,
                fence,
                features,
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
            api_version: host_requirements().api_version,
            features: self.features,
            extensions: Vec::new(),
        }
    }

    fn begin(&self) {
        // SAFETY: the command buffer is idle (every submission was waited for).
        unsafe {
            self.device
                .begin_command_buffer(self.cmd, &vk::CommandBufferBeginInfo::default())
                .expect("begin");
        }
    }

    fn submit_and_wait(&self) {
        let cmds = [self.cmd];
        // SAFETY: recorded by this thread; the fence is unsignalled and reset after the wait.
        unsafe {
            self.device.end_command_buffer(self.cmd).expect("end");
            self.device
                .queue_submit(
                    self.queue,
                    &[vk::SubmitInfo::default().command_buffers(&cmds)],
                    self.fence,
                )
                .expect("submit");
            self.device
                .wait_for_fences(&[self.fence], true, u64::MAX)
                .expect("wait");
            self.device.reset_fences(&[self.fence]).expect("reset");
        }
    }
}

impl Drop for Engine {
    fn drop(&mut self) {
        // SAFETY: the device is idle and every translucid object is gone (dropped first).
        unsafe {
            let _ = self.device.device_wait_idle();
            self.device.destroy_fence(self.fence, None);
            self.device.destroy_command_pool(self.pool, None);
            self.device.destroy_device(None);
            self.messenger
                .0
                .destroy_debug_utils_messenger(self.messenger.1, None);
            self.instance.destroy_instance(None);
        }
    }
}

fn texels(layer: &OpaqueLayer) -> (Vec<u8>, Vec<u8>) {
    let colour = layer
        .colour
        .iter()
        .flat_map(|c| [c.x, c.y, c.z, 1.0])
        .flat_map(|v| half::f16::from_f32(v).to_le_bytes())
        .collect();
    let depth = layer.depth.iter().flat_map(|d| d.to_le_bytes()).collect();
    (colour, depth)
}

/// The engine's opaque pass: copies `layer` into its images, left as attachments.
fn record_opaque(
    gpu: &Gpu,
    cmd: vk::CommandBuffer,
    images: [(&GpuImage, &translucid::gpu::Buffer, vk::ImageLayout); 2],
) {
    let any = (
        vk::PipelineStageFlags::ALL_COMMANDS,
        vk::AccessFlags::MEMORY_READ | vk::AccessFlags::MEMORY_WRITE,
    );
    let write = (
        vk::PipelineStageFlags::TRANSFER,
        vk::AccessFlags::TRANSFER_WRITE,
    );
    for (image, buffer, layout) in images {
        let undefined = vk::ImageLayout::UNDEFINED;
        let dst = vk::ImageLayout::TRANSFER_DST_OPTIMAL;
        image_barrier(gpu, cmd, image, undefined, dst, any, write);
        gpu.cmd_copy_buffer_to_image(cmd, buffer, image);
        image_barrier(gpu, cmd, image, dst, layout, write, any);
    }
}

#[test]
fn an_overflowing_frame_says_so_and_renders_right_when_recorded_again() {
    let scene = translucid::scene::load("spheres").expect("generated scene");
    let standalone = Gpu::new(&GpuOptions {
        device: None,
        validation: true,
    })
    .expect("a Vulkan device with the validation layer");
    let mut reference = Renderer::new(&standalone, &scene, "exact", W, H).expect("renderer");
    let layer = reference
        .render(true)
        .expect("frame")
        .opaque
        .expect("opaque");
    let expected = reference.render_over(&layer).expect("frame over the layer");

    let engine = Engine::new();
    {
        // SAFETY: the engine's live objects, outliving `gpu` (dropped at the end of this block).
        let gpu = unsafe { Gpu::from_host(&engine.host_device()) }.expect("host device");
        let extent = vk::Extent2D {
            width: W,
            height: H,
        };
        let transfer = vk::ImageUsageFlags::TRANSFER_SRC | vk::ImageUsageFlags::TRANSFER_DST;
        let colour_format = vk::Format::R16G16B16A16_SFLOAT;
        let colour = gpu
            .create_image(
                "engine colour",
                extent,
                colour_format,
                transfer | vk::ImageUsageFlags::COLOR_ATTACHMENT,
                1,
            )
            .expect("colour");
        let depth = gpu
            .create_image(
                "engine depth",
                extent,
                vk::Format::D32_SFLOAT,
                transfer | vk::ImageUsageFlags::DEPTH_STENCIL_ATTACHMENT,
                1,
            )
            .expect("depth");
        let (colour_texels, depth_texels) = texels(&layer);
        let src = vk::BufferUsageFlags::TRANSFER_SRC;
        let colour_in = gpu
            .create_buffer_with_data("opaque colour", src, &colour_texels)
            .expect("upload buffer");
        let depth_in = gpu
            .create_buffer_with_data("opaque depth", src, &depth_texels)
            .expect("upload buffer");
        let out = gpu
            .create_buffer(
                "readback",
                colour_texels.len() as u64,
                vk::BufferUsageFlags::TRANSFER_DST,
                MemoryLocation::GpuToCpu,
            )
            .expect("readback buffer");
        let options = MethodOptions {
            initial_bin_entries: Some(16),
            ..Default::default()
        };
        let mut renderer =
            Renderer::with_options(&gpu, &scene, "exact", W, H, &options).expect("renderer");
        let attachment = vk::ImageLayout::COLOR_ATTACHMENT_OPTIMAL;
        let depth_attachment = vk::ImageLayout::DEPTH_STENCIL_ATTACHMENT_OPTIMAL;
        let targets = HostTargets {
            cmd: engine.cmd,
            colour: HostImage {
                image: colour.raw,
                format: colour_format,
                layout: attachment,
                final_layout: vk::ImageLayout::TRANSFER_SRC_OPTIMAL,
            },
            depth: HostImage {
                image: depth.raw,
                format: vk::Format::D32_SFLOAT,
                layout: depth_attachment,
                final_layout: depth_attachment,
            },
        };
        let mut overflows = Vec::new();
        for _ in 0..3 {
            engine.begin();
            record_opaque(
                &gpu,
                engine.cmd,
                [
                    (&colour, &colour_in, attachment),
                    (&depth, &depth_in, depth_attachment),
                ],
            );
            // SAFETY: the engine's recording command buffer and images of the frame's size.
            unsafe { renderer.record_host(&targets) }.expect("record");
            gpu.cmd_copy_image_to_buffer(engine.cmd, &colour, &out);
            translucid::gpu::memory_barrier(
                &gpu,
                engine.cmd,
                (
                    vk::PipelineStageFlags::TRANSFER,
                    vk::AccessFlags::TRANSFER_WRITE,
                ),
                (vk::PipelineStageFlags::HOST, vk::AccessFlags::HOST_READ),
            );
            engine.submit_and_wait();
            let done = renderer
                .complete_host()
                .expect("complete")
                .expect("the submission finished, so the commands ran");
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

        let bytes = out.read().expect("readback");
        let pixels = bytes
            .chunks_exact(8)
            .map(|p| {
                let c = |i: usize| half::f16::from_le_bytes([p[2 * i], p[2 * i + 1]]).to_f32();
                glam::Vec4::new(c(0), c(1), c(2), 1.0)
            })
            .collect();
        let got = translucid::Image {
            width: W,
            height: H,
            pixels,
        }
        .to_srgb8();
        let want = expected.image.to_srgb8();
        let worst = got
            .iter()
            .zip(&want)
            .map(|(a, b)| a.abs_diff(*b))
            .max()
            .unwrap_or(0);
        assert!(
            worst <= 2,
            "host-device exact differs from standalone by {worst}/255"
        );
    }
    let errors = ERRORS.lock().map(|e| e.clone()).unwrap_or_default();
    assert!(
        errors.is_empty(),
        "validation errors:\n{}",
        errors.join("\n")
    );
}
