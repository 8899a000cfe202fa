//! Frames past the device's limits end in a clear error before anything is recorded, never
//! in a validation error, a crash or minutes of work.

use glam::{Mat4, Vec3};
use translucid::renderer::Renderer;
use translucid::scene::{Draw, Material, Mesh, Scene};
use translucid::Error;
use translucid_tests::gpu;

/// Two million draws of one triangle (a node hierarchy that doubles 21 times gives as
/// many): their per-draw records pass the 128 MB one storage binding holds on lavapipe.
/// Writing that descriptor was a validation error, and without validation the frame ran
/// for over a minute.
#[test]
fn draws_past_a_storage_binding_are_refused_by_name() {
    let gpu = gpu();
    let range = u64::from(gpu.info().max_storage_buffer_range);
    let triangle =
        Mesh::from_triangles("triangle", vec![Vec3::ZERO, Vec3::X, Vec3::Y], &[[0, 1, 2]]);
    // Enough draws that any per-draw record of 64 bytes or more passes the binding.
    let count = usize::try_from(range / 64 + 1).expect("fits");
    let scene = Scene {
        name: "many draws".into(),
        meshes: vec![triangle],
        materials: vec![Material::alpha(Vec3::ONE, 0.5)],
        transparent: vec![
            Draw {
                mesh: 0,
                material: 0,
                transform: Mat4::from_translation(Vec3::new(0.0, 0.0, -3.0)),
            };
            count
        ],
        ..Scene::default()
    };
    for method in ["exact", "blend", "wavelet", "wboit"] {
        let err = Renderer::new(&gpu, &scene, method, 64, 48)
            .err()
            .unwrap_or_else(|| panic!("{method}: {count} draws were accepted"));
        let msg = err.to_string();
        assert!(
            matches!(err, Error::InvalidScene(_)) && msg.contains("MB") && msg.contains("storage"),
            "{method}: {msg}"
        );
    }
}
