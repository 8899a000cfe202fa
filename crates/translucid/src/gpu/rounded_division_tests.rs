//! `shaders/common/rounded_division.glsl` against Rust's `/`: every quotient the GPU profile
//! corrects must come out as the reference's, bit for bit, from estimates up to 3 ulps off
//! either way (Vulkan allows 2.5). lavapipe divides exactly, so the estimates are made off
//! here, by hand, and the shader is run by `shaders/test/division.comp`.

use super::{vk, BindingKind, ComputePipeline, DescriptorLayout, Gpu, GpuOptions};
use super::{MemoryLocation, Resource};
use bytemuck::{Pod, Zeroable};

#[repr(C)]
#[derive(Clone, Copy, Pod, Zeroable)]
struct DivisionCase {
    a: f32,
    b: f32,
    estimate: f32,
    pad: f32,
}

/// The float `ulps` steps from `x` away from zero (towards it when negative).
fn nudged(x: f32, ulps: i32) -> f32 {
    let bits = x.to_bits();
    let magnitude = (bits & 0x7FFF_FFFF) as i64 + i64::from(ulps);
    f32::from_bits((bits & 0x8000_0000) | magnitude.clamp(0, 0x7F80_0000) as u32)
}

/// Operand pairs: quotients that land on or next to powers of two, the divisions the
/// rasterizer makes (reciprocals of areas and of w, NDC from clip space, barycentrics) and
/// a spread of random normal floats of either sign.
fn operand_pairs() -> Vec<(f32, f32)> {
    let mut pairs = vec![
        (1.0, 1.0),
        (1.0, 0.5),
        (6.0, 3.0),
        (1.0, 3.0),
        (2.0, 3.0),
        (-1.0, 3.0),
        (1.0, -7.0),
        (1.0, nudged(1.0, 1)),
        (1.0, nudged(1.0, -1)),
        (nudged(2.0, -1), 2.0),
        (nudged(1.0, 1), 1.0),
        (1.0, 65025.0),
        (1.0, 1.0e-6),
        (3.0e7, 7.0e-3),
        (0.1, 0.3),
        (1.0, 16_777_215.0),
    ];
    // A xorshift stream: reproducible, and no crate for it.
    let mut state = 0x2545_F491_4F6C_DD1Du64;
    let mut next = move || {
        state ^= state << 13;
        state ^= state >> 7;
        state ^= state << 17;
        state
    };
    let mut random_float = |exponent_span: u64| {
        let r = next();
        let exponent = 127 - exponent_span / 2 + (r >> 40) % exponent_span;
        let sign = (r >> 63) as u32;
        f32::from_bits(sign << 31 | (exponent as u32) << 23 | (r as u32 & 0x7F_FFFF))
    };
    for _ in 0..3000 {
        pairs.push((random_float(40), random_float(40)));
    }
    for _ in 0..1000 {
        // Reciprocals, as of areas and w.
        pairs.push((1.0, random_float(60)));
    }
    pairs
}

#[test]
fn rounded_quotients_are_rusts_from_estimates_a_few_ulps_off() {
    let gpu = Gpu::new(&GpuOptions {
        device: std::env::var("TRANSLUCID_DEVICE").ok(),
        validation: true,
        profile: None,
        software_sampling: false,
        ..Default::default()
    })
    .expect("a Vulkan device with the validation layer");
    let mut cases = Vec::new();
    let mut wanted = Vec::new();
    for (a, b) in operand_pairs() {
        let q = a / b;
        assert!(
            q.is_normal(),
            "{a} / {b}: the cases keep to normal quotients"
        );
        for ulps in -3..=3 {
            cases.push(DivisionCase {
                a,
                b,
                estimate: nudged(q, ulps),
                pad: 0.0,
            });
            wanted.push(q);
        }
    }
    // Outside what it corrects it keeps the estimate, or gives a signed zero for 0 / b.
    for (a, b, estimate, want) in [
        (0.0, 3.0, 1.0e-30, 0.0),
        (-0.0, 3.0, 1.0e-30, -0.0),
        (0.0, -3.0, 1.0e-30, -0.0),
        (1.0, 0.0, 5.0, 5.0),
        (f32::INFINITY, 2.0, 7.0, 7.0),
        (1.0, 1.0e-40, 9.0, 9.0),
    ] {
        cases.push(DivisionCase {
            a,
            b,
            estimate,
            pad: 0.0,
        });
        wanted.push(want);
    }

    let storage = vk::BufferUsageFlags::STORAGE_BUFFER;
    let case_buffer = gpu
        .create_buffer_with_data("division cases", storage, bytemuck::cast_slice(&cases))
        .expect("buffer");
    let result_buffer = gpu
        .create_buffer(
            "division results",
            (cases.len() * size_of::<f32>()) as u64,
            storage,
            MemoryLocation::GpuToCpu,
        )
        .expect("buffer");
    let layout = DescriptorLayout::new(
        &gpu,
        &[BindingKind::StorageBuffer, BindingKind::StorageBuffer],
        vk::ShaderStageFlags::COMPUTE,
    )
    .expect("layout");
    let set = layout
        .create_set(&[
            Resource::Buffer(&case_buffer),
            Resource::Buffer(&result_buffer),
        ])
        .expect("set");
    let pipeline = ComputePipeline::new(&gpu, crate::spirv!("test/division.comp"), &[&layout], 4)
        .expect("pipeline");
    let count = cases.len() as u32;
    pipeline
        .dispatch_and_wait(&[set.raw], &count.to_ne_bytes(), [count.div_ceil(64), 1, 1])
        .expect("dispatch");
    let results: Vec<f32> = bytemuck::pod_collect_to_vec(result_buffer.read().expect("read"));

    let failures: Vec<String> = cases
        .iter()
        .zip(&wanted)
        .zip(&results)
        .filter(|((_, want), got)| want.to_bits() != got.to_bits())
        .map(|((c, want), got)| {
            format!(
                "{:e} / {:e} from {:e}: got {got:e}, want {want:e}",
                c.a, c.b, c.estimate
            )
        })
        .take(20)
        .collect();
    assert!(failures.is_empty(), "{}", failures.join("\n"));
    gpu.check_validation().expect("no validation errors");
}
