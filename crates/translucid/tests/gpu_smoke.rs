//! The GPU path end to end on a scene whose answer is known by hand.

use glam::{Mat4, Vec3, Vec4};
use translucid::gpu::{Gpu, GpuOptions};
use translucid::methods::MethodKind;
use translucid::renderer::Renderer;
use translucid::scene::{Camera, Draw, Material, Mesh, Scene};

fn gpu() -> Gpu {
    Gpu::new(&GpuOptions {
        device: std::env::var("TRANSLUCID_DEVICE").ok(),
        validation: true,
        profile: None,
        software_sampling: false,
        ..Default::default()
    })
    .expect("a Vulkan device with the validation layer (run `make test`, which installs both)")
}

/// A unit square in the XY plane at depth z, facing +Z.
fn square(z: f32) -> Mesh {
    Mesh::from_quads(
        "square",
        vec![
            Vec3::new(-1.0, -1.0, z),
            Vec3::new(1.0, -1.0, z),
            Vec3::new(1.0, 1.0, z),
            Vec3::new(-1.0, 1.0, z),
        ],
        vec![[0, 1, 2, 3]],
    )
}

fn two_layer_scene() -> Scene {
    Scene {
        name: "two layers".into(),
        meshes: vec![square(0.0), square(0.5)],
        materials: vec![
            Material::alpha(Vec3::new(0.0, 0.0, 1.0), 1.0),
            Material::alpha(Vec3::new(1.0, 0.0, 0.0), 0.5),
        ],
        opaque: vec![Draw {
            mesh: 0,
            material: 0,
            transform: Mat4::IDENTITY,
            tint: glam::Vec4::ONE,
        }],
        transparent: vec![Draw {
            mesh: 1,
            material: 1,
            transform: Mat4::IDENTITY,
            tint: glam::Vec4::ONE,
        }],
        camera: Camera::look_at(Vec3::new(0.0, 0.0, 4.0), Vec3::ZERO, 1.0, 0.1, 10.0),
        background: Vec3::new(0.0, 1.0, 0.0),
        ..Scene::default()
    }
}

#[test]
fn blend_composites_over_the_opaque_layer() {
    let gpu = gpu();
    let mut renderer =
        Renderer::new(&gpu, &two_layer_scene(), MethodKind::Blend, 64, 48).expect("renderer");
    let frame = renderer.render(true).expect("frame");
    let centre = frame.image.get(32, 24);
    assert!(
        (centre - Vec4::new(0.5, 0.0, 0.5, 1.0)).abs().max_element() < 1e-3,
        "centre {centre}"
    );
    let corner = frame.image.get(0, 0);
    assert!(
        (corner - Vec4::new(0.0, 1.0, 0.0, 1.0)).abs().max_element() < 1e-3,
        "corner {corner}"
    );
    let opaque = frame.opaque.expect("opaque layer");
    assert!(
        (opaque.colour[24 * 64 + 32] - Vec3::new(0.0, 0.0, 1.0))
            .abs()
            .max_element()
            < 1e-3
    );
    assert!(opaque.depth[24 * 64 + 32] < 1.0 && opaque.depth[0] == 1.0);
    assert!(
        frame.stages.iter().any(|(s, _)| *s == "blend"),
        "{:?}",
        frame.stages
    );
    assert!(frame.peak_gpu_bytes > 0);
}

#[test]
fn zero_and_oversized_viewports_are_refused() {
    let gpu = gpu();
    let scene = two_layer_scene();
    for (w, h) in [(0, 10), (10, 0), (1 << 20, 10)] {
        let err = Renderer::new(&gpu, &scene, MethodKind::Blend, w, h)
            .err()
            .expect("refused");
        assert!(
            matches!(err, translucid::Error::InvalidViewport { .. }),
            "{err}"
        );
    }
}

#[test]
fn unknown_method_is_named() {
    let err = "nope".parse::<MethodKind>().expect_err("refused");
    assert!(
        err.to_string().contains("nope") && err.to_string().contains("blend"),
        "{err}"
    );
}
