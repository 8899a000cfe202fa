//! Stacks that no depth order splits, and deep random ones: what hostile files make of the
//! exact method's walks (`instanced:N`, `coincident:N`, `random_draws:N`; the hostile-input
//! tests render them against the reference, and `translucid bench` times them against blend).

use super::super::{Camera, Draw, Material, Mesh, Scene};
use glam::{Mat4, Vec3, Vec4};

/// A scene of one transparent draw of `mesh` in `material`, untransformed, over a grey
/// background (the tests build theirs with it too).
pub fn one_draw_scene(name: &str, mesh: Mesh, material: Material, camera: Camera) -> Scene {
    Scene {
        name: name.into(),
        meshes: vec![mesh],
        materials: vec![material],
        transparent: vec![Draw {
            mesh: 0,
            material: 0,
            transform: Mat4::IDENTITY,
            tint: Vec4::ONE,
        }],
        camera,
        background: Vec3::splat(0.2),
        ..Scene::default()
    }
}

/// The stacks' one draw, seen from in front.
fn one_draw(name: &str, mesh: Mesh, material: Material) -> Scene {
    let camera = Camera::look_at(Vec3::new(0.0, 0.0, 3.0), Vec3::ZERO, 0.8, 0.1, 20.0);
    one_draw_scene(name, mesh, material, camera)
}

/// `count` draws of one screen-filling quad at one place: a node graph that instances one
/// mesh many times over.
pub fn instanced(count: u32) -> Scene {
    let quad = Mesh::from_quads(
        "quad",
        vec![
            Vec3::new(-2.0, -2.0, 0.0),
            Vec3::new(2.0, -2.0, 0.0),
            Vec3::new(2.0, 2.0, 0.0),
            Vec3::new(-2.0, 2.0, 0.0),
        ],
        vec![[0, 1, 2, 3]],
    );
    let mut scene = one_draw("instanced", quad, Material::alpha(Vec3::ONE, 0.5));
    scene.transparent = vec![scene.transparent[0].clone(); count as usize];
    scene
}

/// `count` copies of one screen-filling triangle in one mesh, all at one depth.
pub fn coincident(count: u32) -> Scene {
    let mut positions = Vec::new();
    let mut triangles = Vec::new();
    for i in 0..count {
        positions.extend([
            Vec3::new(-9.0, -9.0, -1.0),
            Vec3::new(9.0, -9.0, -1.0),
            Vec3::new(0.0, 9.0, -1.0),
        ]);
        triangles.push([3 * i, 3 * i + 1, 3 * i + 2]);
    }
    let mesh = Mesh::from_triangles("coincident", positions, &triangles);
    one_draw("coincident", mesh, Material::alpha(Vec3::ONE, 0.5))
}

/// `count` draws of one small triangle, each moved to a random place and depth and tinted,
/// overlapping thousands deep in the middle of the frame.
pub fn random_draws(count: u32) -> Scene {
    let triangle = Mesh::from_triangles(
        "triangle",
        vec![
            Vec3::new(-0.5, -0.4, 0.0),
            Vec3::new(0.5, -0.4, 0.0),
            Vec3::new(0.0, 0.5, 0.0),
        ],
        &[[0, 1, 2]],
    );
    let material = Material::alpha(Vec3::new(0.9, 0.5, 0.2), 0.3);
    let mut scene = one_draw("random draws", triangle, material);
    let mut state = 12345u64;
    let mut random = move || {
        state = state
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        (state >> 40) as f32 / (1u64 << 24) as f32
    };
    let first = scene.transparent[0].clone();
    scene.transparent = (0..count)
        .map(|_| Draw {
            transform: Mat4::from_translation(Vec3::new(
                random() * 2.0 - 1.0,
                random() * 1.6 - 0.8,
                -random() * 2.0,
            )),
            tint: Vec4::new(random(), random(), random(), 1.0),
            ..first.clone()
        })
        .collect();
    scene
}
