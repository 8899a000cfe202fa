//! The GLSL shading function (shaders/common/shading.glsl) and the Rust one
//! (src/shading.rs) must agree: every method and the CPU reference shade through them.

use bytemuck::{Pod, Zeroable};
use glam::{Vec3, Vec4};
use translucid::gpu::{
    vk, BindingKind, ComputePipeline, DescriptorLayout, Gpu, GpuOptions, Resource,
};
use translucid::scene::{Light, Material};
use translucid::shader_types::{GpuFrameInfo, GpuMaterial};
use translucid::shading;

#[repr(C)]
#[derive(Clone, Copy, Pod, Zeroable)]
struct Case {
    vertex_colour: [f32; 4],
    texel: [f32; 4],
    normal: [f32; 4],
    material: u32,
    pad: [u32; 3],
}

#[repr(C)]
#[derive(Clone, Copy, Pod, Zeroable, Debug)]
struct Outcome {
    radiance: [f32; 4],
    transmittance: [f32; 4],
    opaque: [f32; 4],
}

fn materials() -> Vec<Material> {
    vec![
        Material::alpha(Vec3::new(1.0, 0.5, 0.25), 0.5),
        Material {
            lit: true,
            ..Material::alpha(Vec3::new(0.2, 0.7, 0.9), 0.3)
        },
        Material {
            transmission: 0.9,
            transmission_tint: Vec3::new(0.9, 0.4, 0.1),
            reflectance: 0.04,
            lit: true,
            ..Material::alpha(Vec3::new(0.8, 1.0, 0.6), 1.0)
        },
        Material {
            alpha_cutoff: Some(0.5),
            lit: true,
            ..Material::alpha(Vec3::ONE, 0.4)
        },
        Material {
            alpha_cutoff: Some(0.5),
            ..Material::alpha(Vec3::new(0.3, 0.3, 0.3), 0.6)
        },
    ]
}

fn cases(material_count: u32) -> Vec<Case> {
    let normals = [
        Vec3::Z,
        Vec3::new(0.3, -0.8, 0.1),
        Vec3::new(-2.0, 0.5, 3.0),
        Vec3::ZERO,
        // Normals whose squared length under- or overflows f32 still light the surface.
        Vec3::new(3e-30, -1e-30, 2e-30),
        Vec3::new(-2e30, 5e29, 3e30),
        Vec3::new(f32::INFINITY, 0.0, 1.0),
        Vec3::splat(f32::NAN),
    ];
    let colours = [Vec4::ONE, Vec4::new(0.5, 0.9, 0.2, 0.7)];
    let texels = [Vec4::ONE, Vec4::new(0.1, 0.6, 1.0, 0.25)];
    let mut out = Vec::new();
    for m in 0..material_count {
        for n in normals {
            for c in colours {
                for t in texels {
                    out.push(Case {
                        vertex_colour: c.to_array(),
                        texel: t.to_array(),
                        normal: n.extend(0.0).to_array(),
                        material: m,
                        pad: [0; 3],
                    });
                }
            }
        }
    }
    out
}

fn close(a: Vec3, b: Vec3) -> bool {
    (a - b).abs().max_element() <= 1e-5
}

#[test]
fn glsl_and_rust_shading_agree() {
    let gpu = Gpu::new(&GpuOptions {
        device: std::env::var("TRANSLUCID_DEVICE").ok(),
        validation: true,
        profile: None,
        software_sampling: false,
        ..Default::default()
    })
    .expect("a Vulkan device with the validation layer");
    let light = Light {
        direction: Vec3::new(0.4, 0.7, -0.2).normalize(),
        ..Light::default()
    };
    let materials = materials();
    let cases = cases(materials.len() as u32);
    let gpu_materials: Vec<GpuMaterial> = materials.iter().map(GpuMaterial::new).collect();
    let frame = GpuFrameInfo::new(&translucid::scene::Camera::default(), &light, 1, 1);

    let usage = vk::BufferUsageFlags::STORAGE_BUFFER;
    let frame_buf = gpu
        .create_buffer_with_data(
            "frame",
            vk::BufferUsageFlags::UNIFORM_BUFFER,
            bytemuck::bytes_of(&frame),
        )
        .expect("buffer");
    let material_buf = gpu
        .create_buffer_with_data("materials", usage, bytemuck::cast_slice(&gpu_materials))
        .expect("buffer");
    let case_buf = gpu
        .create_buffer_with_data("cases", usage, bytemuck::cast_slice(&cases))
        .expect("buffer");
    let out_size = (cases.len() * std::mem::size_of::<Outcome>()) as u64;
    let out_buf = gpu
        .create_buffer(
            "outcomes",
            out_size,
            usage,
            translucid::gpu::MemoryLocation::GpuToCpu,
        )
        .expect("buffer");

    let layout = DescriptorLayout::new(
        &gpu,
        &[
            BindingKind::UniformBuffer,
            BindingKind::StorageBuffer,
            BindingKind::StorageBuffer,
            BindingKind::StorageBuffer,
        ],
        vk::ShaderStageFlags::COMPUTE,
    )
    .expect("layout");
    let set = layout
        .create_set(&[
            Resource::Buffer(&frame_buf),
            Resource::Buffer(&material_buf),
            Resource::Buffer(&case_buf),
            Resource::Buffer(&out_buf),
        ])
        .expect("set");
    let pipeline =
        ComputePipeline::new(&gpu, translucid::spirv!("test/shading.comp"), &[&layout], 4)
            .expect("pipeline");
    let count = cases.len() as u32;
    pipeline
        .dispatch_and_wait(&[set.raw], &count.to_ne_bytes(), [count.div_ceil(64), 1, 1])
        .expect("dispatch");
    let outcomes: Vec<Outcome> = bytemuck::pod_collect_to_vec(out_buf.read().expect("read"));

    for (i, (c, got)) in cases.iter().zip(&outcomes).enumerate() {
        let m = &materials[c.material as usize];
        let (vc, tx, n) = (
            Vec4::from(c.vertex_colour),
            Vec4::from(c.texel),
            Vec4::from(c.normal).truncate(),
        );
        let want = shading::shade_transparent(m, &light, vc, tx, n);
        let got_l = Vec4::from(got.radiance).truncate();
        let got_t = Vec4::from(got.transmittance).truncate();
        assert!(
            close(got_l, want.radiance),
            "case {i}: radiance GPU {got_l} vs Rust {}",
            want.radiance
        );
        assert!(
            close(got_t, want.transmittance),
            "case {i}: transmittance GPU {got_t} vs Rust {}",
            want.transmittance
        );
        let opaque = shading::shade_opaque(m, &light, vc, tx, n);
        let got_o = Vec4::from(got.opaque);
        match opaque {
            Some(colour) => assert!(
                got_o.w == 1.0 && close(got_o.truncate(), colour),
                "case {i}: opaque {got_o} vs {colour}"
            ),
            None => assert_eq!(
                got_o.w, 0.0,
                "case {i}: the GPU kept a fragment the cutoff discards"
            ),
        }
    }
}
