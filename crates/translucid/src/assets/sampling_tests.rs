//! The GPU's samplers against values worked out by hand: the compute stages' software sampler
//! (`shaders/common/texture_sampler.glsl`, fed by the exact method's texture records) and the
//! hardware sampler the graphics passes bind (`Sampler::for_texture`, on textures uploaded as
//! the renderer uploads them), both run by `shaders/test/sampler.comp`.

use super::create_textures;
use super::texture_records::texture_data;
use crate::gpu::{
    memory_barrier, vk, BindingKind, ComputePipeline, DescriptorLayout, Gpu, GpuOptions,
    MemoryLocation, Resource, Sampler, COMPUTE_WRITE, HOST_READ,
};
use crate::scene::srgb_lut;
use crate::scene::texture_hand::hand_cases;
use crate::scene::Texture;
use bytemuck::{Pod, Zeroable};
use glam::{Vec3, Vec4};

#[repr(C)]
#[derive(Clone, Copy, Pod, Zeroable)]
struct SamplerCase {
    uv: [f32; 2],
    lod: f32,
    pad: u32,
}

/// The software sampler repeats the reference's arithmetic, so it is held to rounding.
const SOFTWARE_TOLERANCE: f32 = 1e-5;
/// Hardware filtering may quantize its weights (lavapipe: 8 bits); every hand-worked weight
/// here is a multiple of 1/4, so this only covers the texels' own rounding.
const HARDWARE_TOLERANCE: f32 = 1.0 / 255.0;

#[test]
fn gpu_samplers_match_values_computed_by_hand() {
    let gpu = Gpu::new(&GpuOptions {
        device: std::env::var("TRANSLUCID_DEVICE").ok(),
        validation: true,
        profile: None,
        software_sampling: false,
        ..Default::default()
    })
    .expect("a Vulkan device with the validation layer");
    let cases = hand_cases();
    let textures: Vec<Texture> = cases.iter().map(|c| c.texture.clone()).collect();

    // The hardware side: images and samplers as the renderer makes them.
    let (images, uploads) = create_textures(&gpu, textures.iter()).expect("textures");
    crate::gpu::Uploads::default()
        .submit(&gpu, uploads)
        .expect("upload");
    let samplers: Vec<Sampler> = textures
        .iter()
        .map(|t| Sampler::for_texture(&gpu, &t.sampler).expect("sampler"))
        .collect();

    // The software side: the exact method's texture records.
    let (infos, texels) = texture_data(&textures);
    let texel_usage = vk::BufferUsageFlags::UNIFORM_TEXEL_BUFFER;
    let storage = vk::BufferUsageFlags::STORAGE_BUFFER;
    let texel_buffer = gpu
        .create_buffer_with_data("texels", texel_usage, bytemuck::cast_slice(&texels))
        .expect("buffer");
    let texel_view = gpu
        .create_buffer_view(&texel_buffer, vk::Format::R32_UINT)
        .expect("view");
    let srgb_buffer = gpu
        .create_buffer_with_data("sRGB table", texel_usage, bytemuck::cast_slice(srgb_lut()))
        .expect("buffer");
    let srgb_view = gpu
        .create_buffer_view(&srgb_buffer, vk::Format::R32_SFLOAT)
        .expect("view");
    let info_buffer = gpu
        .create_buffer_with_data("texture records", storage, bytemuck::cast_slice(&infos))
        .expect("buffer");
    let gpu_cases: Vec<SamplerCase> = cases
        .iter()
        .map(|c| SamplerCase {
            uv: c.uv.to_array(),
            lod: c.lod,
            pad: 0,
        })
        .collect();
    let case_buffer = gpu
        .create_buffer_with_data("cases", storage, bytemuck::cast_slice(&gpu_cases))
        .expect("buffer");
    let result_buffer = gpu
        .create_buffer(
            "results",
            (cases.len() * 2 * size_of::<Vec4>()) as u64,
            storage,
            MemoryLocation::GpuToCpu,
        )
        .expect("buffer");

    let layout = DescriptorLayout::new(
        &gpu,
        &[
            BindingKind::TexelBuffer,
            BindingKind::TexelBuffer,
            BindingKind::StorageBuffer,
            BindingKind::StorageBuffer,
            BindingKind::StorageBuffer,
            BindingKind::SampledImages(1),
        ],
        vk::ShaderStageFlags::COMPUTE,
    )
    .expect("layout");
    let sets: Vec<_> = images
        .iter()
        .zip(&samplers)
        .map(|(image, sampler)| {
            layout
                .create_set(&[
                    Resource::TexelBuffer(texel_view.raw),
                    Resource::TexelBuffer(srgb_view.raw),
                    Resource::Buffer(&info_buffer),
                    Resource::Buffer(&case_buffer),
                    Resource::Buffer(&result_buffer),
                    Resource::Images(&[image.view], sampler.raw),
                ])
                .expect("set")
        })
        .collect();
    let pipeline = ComputePipeline::new(&gpu, crate::spirv!("test/sampler.comp"), &[&layout], 8)
        .expect("pipeline");
    gpu.submit_and_wait(|cmd| {
        for (i, set) in sets.iter().enumerate() {
            // Case i samples texture i.
            let push = [i as u32, i as u32];
            pipeline.dispatch(cmd, &[set.raw], bytemuck::bytes_of(&push), [1, 1, 1]);
        }
        memory_barrier(&gpu, cmd, COMPUTE_WRITE, HOST_READ);
        Ok(())
    })
    .expect("dispatch");
    let results: Vec<Vec4> =
        bytemuck::pod_collect_to_vec::<u8, [f32; 4]>(result_buffer.read().expect("read"))
            .into_iter()
            .map(Vec4::from)
            .collect();

    let mut failures = Vec::new();
    for (case, got) in cases.iter().zip(results.chunks(2)) {
        let want = Vec3::splat(case.want);
        for (sampler, value, tolerance) in [
            ("software", got[0], SOFTWARE_TOLERANCE),
            ("hardware", got[1], HARDWARE_TOLERANCE),
        ] {
            let error = (value.truncate() - want).abs().max_element();
            // NaN fails too.
            if error.is_nan() || error > tolerance {
                failures.push(format!(
                    "{sampler} sampler, {}: got {value}, want {}",
                    case.what, case.want
                ));
            }
        }
    }
    assert!(failures.is_empty(), "{}", failures.join("\n"));
}
