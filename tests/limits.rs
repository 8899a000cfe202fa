//! Frames past the device's limits end in a clear error before anything is recorded, never
//! in a validation error, a crash or minutes of work.

use glam::{Mat4, Vec3};
use translucid::methods::wavelet::Storage;
use translucid::methods::{MethodKind, MethodOptions};
use translucid::metrics;
use translucid::renderer::Renderer;
use translucid::scene::{Draw, Material, Mesh, Scene};
use translucid::Error;
use translucid_tests::{assert_matches_reference, gpu, save_failure};

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
                tint: glam::Vec4::ONE,
            };
            count
        ],
        ..Scene::default()
    };
    for method in ["exact", "blend", "wavelet", "wboit"] {
        let err = Renderer::new(&gpu, &scene, method.parse().expect("a method name"), 64, 48)
            .err()
            .unwrap_or_else(|| panic!("{method}: {count} draws were accepted"));
        let msg = err.to_string();
        assert!(
            matches!(err, Error::TooLarge(_)) && msg.contains("MB") && msg.contains("storage"),
            "{method}: {msg}"
        );
    }
}

/// The most draws a frame may have is what one storage binding of draw records holds, and
/// a frame of exactly that many is accepted: the records' room once doubled past the
/// binding, so frames failed from 419 k draws where 838 k fit on lavapipe (and the C API
/// promised a million).
#[test]
fn a_frame_of_the_most_draws_is_accepted_and_one_more_refused() {
    let gpu = gpu();
    let most = translucid::assets::most_draws(&gpu);
    let triangle =
        Mesh::from_triangles("triangle", vec![Vec3::ZERO, Vec3::X, Vec3::Y], &[[0, 1, 2]]);
    let draw = Draw {
        mesh: 0,
        material: 0,
        transform: Mat4::from_translation(Vec3::new(0.0, 0.0, -3.0)),
        tint: glam::Vec4::ONE,
    };
    let mut scene = Scene {
        name: "the most draws".into(),
        meshes: vec![triangle],
        materials: vec![Material::alpha(Vec3::ONE, 0.5)],
        transparent: vec![draw.clone(); most],
        ..Scene::default()
    };
    Renderer::new(&gpu, &scene, MethodKind::Blend, 16, 16).expect("the most draws");
    scene.transparent.push(draw);
    let err = Renderer::new(&gpu, &scene, MethodKind::Blend, 16, 16)
        .err()
        .expect("one draw too many");
    assert!(
        err.to_string().contains(&format!("fit at most {most}")),
        "{err}"
    );
}

/// Frames smaller than a GPU buffer's 16-byte minimum read back exactly their own pixels,
/// and match the reference (a 1x1 frame came back with two pixels, so the C API asked for
/// twice the bytes it documents).
#[test]
fn tiny_frames_read_back_their_own_pixels() {
    let gpu = gpu();
    let scene = translucid::scene::load("layers").expect("layers scene");
    for method in ["blend", "exact", "wavelet", "wboit"] {
        for (width, height) in [(1, 1), (1, 3), (3, 1)] {
            let frame = translucid_tests::render(&gpu, &scene, method, width, height);
            let pixels = (width * height) as usize;
            assert_eq!(
                frame.image.pixels.len(),
                pixels,
                "{method} at {width}x{height}"
            );
            let opaque = frame.opaque.as_ref().expect("opaque layer read back");
            assert_eq!(opaque.depth.len(), pixels, "{method} at {width}x{height}");
        }
    }
}

/// A limit of the bin stages that wavelet shares with exact is said as wavelet's own, and
/// as exact's under exact: textures the transparent draws sample, over what the software
/// sampler's texel view holds. The same textures on opaque draws alone are not copied for
/// it, and take no part in the limit.
#[test]
fn limits_of_the_shared_bin_stages_name_the_method() {
    let gpu = gpu();
    // The software sampler reads its texels (RGBA8 in R32 texels) through one texel view.
    let range = u64::from(gpu.info().max_texel_buffer_elements) * 4;
    // RGBA8 texels with mips take 4/3 of level 0: enough textures of 4096² to pass the view.
    let side = 4096u32;
    let per_texture = u64::from(side) * u64::from(side) * 4 * 4 / 3;
    let count = range / per_texture + 1;
    let texture = translucid::scene::Texture::new(
        "large",
        side,
        side,
        vec![[128, 128, 128, 255]; (side * side) as usize],
        true,
    );
    let triangle =
        Mesh::from_triangles("triangle", vec![Vec3::ZERO, Vec3::X, Vec3::Y], &[[0, 1, 2]]);
    let draw = |material: usize| Draw {
        mesh: 0,
        material,
        transform: Mat4::from_translation(Vec3::new(0.0, 0.0, -3.0)),
        tint: glam::Vec4::ONE,
    };
    let textured = (0..count as usize).map(|t| Material {
        texture: Some(t),
        ..Material::alpha(Vec3::ONE, 0.5)
    });
    let scene = Scene {
        name: "large textures".into(),
        meshes: vec![triangle],
        materials: std::iter::once(Material::alpha(Vec3::ONE, 0.5))
            .chain(textured)
            .collect(),
        textures: vec![texture; count as usize],
        transparent: (1..=count as usize).map(draw).collect(),
        ..Scene::default()
    };
    let mut opaque_only = scene.clone();
    opaque_only.opaque = std::mem::take(&mut opaque_only.transparent);
    opaque_only.transparent = vec![draw(0)];
    translucid_tests::render(&gpu, &opaque_only, "exact", 64, 48);
    // Wavelet on the bins, whatever the profile's default storage.
    let mut options = MethodOptions::default();
    options.wavelet.storage = Some(Storage::Bins);
    for method in ["exact", "wavelet"] {
        let kind = method.parse().expect("a method name");
        let err = Renderer::with_options(&gpu, &scene, kind, 64, 48, &options)
            .err()
            .unwrap_or_else(|| panic!("{method}: {count} textures of {side}² were accepted"));
        let msg = err.to_string();
        let other = if method == "exact" {
            "wavelet"
        } else {
            "exact"
        };
        assert!(
            msg.contains(&format!("{method}: "))
                && !msg.contains(other)
                && msg.contains("textures"),
            "{method}: {msg}"
        );
    }
}

/// A 4096x4096 frame with `exact`: its buffers start within one storage binding, and the
/// frame is right: `layers` is the scene unsorted blending draws right, so exact must match
/// blend.
#[test]
fn a_4096_square_frame_starts_within_the_bindings() {
    let gpu = gpu();
    let scene = translucid::scene::load("layers").expect("generated scene");
    let side = 4096;
    let frame = |method: &str| {
        Renderer::new(
            &gpu,
            &scene,
            method.parse().expect("a method name"),
            side,
            side,
        )
        .and_then(|mut r| r.render(false))
        .unwrap_or_else(|e| panic!("{method} at {side}x{side}: {e}"))
    };
    let exact = frame("exact");
    let blend = frame("blend");
    let m = translucid::metrics::compare(&exact.image, &blend.image).expect("same size");
    assert!(
        m.max_error <= 2.0 / 255.0,
        "exact {:.1}/255 off blend on {} pixels",
        m.max_error * 255.0,
        m.pixels_over
    );
}

/// Setup and binning dispatch a workgroup per 64 triangles (and binning lanes), the rasters
/// one per block of a band; past the 65535 workgroups every device allows in x they go on in
/// z (a band past one row ends on a whole row). With the row lowered to 3 and to 64
/// workgroups, so that every frame splits and bands end early, exact and wavelet draw what
/// they draw unsplit, and exact stays within 2/255 of the reference: shallow and deep frames
/// (particles bins with a lane per row), from 1,800 to 60,000 triangles.
#[test]
fn dispatches_go_on_in_z_past_the_workgroups_in_x() {
    let gpu = gpu();
    let (width, height) = (160, 120);
    for name in ["spheres", "particles", "hairball"] {
        let scene = translucid::scene::load(name).expect("generated scene");
        for method in [MethodKind::Exact, MethodKind::Wavelet] {
            let frame = |groups_x: Option<u32>| {
                let mut options = MethodOptions::default();
                options.bins.groups_x = groups_x;
                Renderer::with_options(&gpu, &scene, method, width, height, &options)
                    .and_then(|mut r| r.render(true))
                    .unwrap_or_else(|e| panic!("{name} with {method}: {e}"))
            };
            let whole = frame(None);
            for row in [3, 64] {
                let split = frame(Some(row));
                let m = metrics::compare(&split.image, &whole.image).expect("same size");
                assert!(
                    m.max_error * 255.0 <= 0.01,
                    "{name} with {method}, rows of {row}: {:.3}/255 off unsplit on {} pixels ({})",
                    m.max_error * 255.0,
                    m.pixels_over,
                    save_failure(
                        &format!("split_{name}_{method}"),
                        &split.image,
                        &whole.image
                    )
                    .display()
                );
                if method == MethodKind::Exact {
                    assert_matches_reference(&format!("split_{name}_{row}"), &scene, &split);
                }
            }
        }
    }
}

/// Five million transparent triangles in one frame (`hairball:5m`, 2.5 million quads): their
/// records (320 MB of coverage records, and the quads' shading attributes) are written
/// through texel views, past the 128 MB one storage binding holds on lavapipe, and binning,
/// sized to the last triangle setup keeps (its record at the triangle's place among the five
/// million), takes about 78,000 workgroups, which go on in z past the 65,535 a device allows
/// in x. The frame matches the CPU reference. (At 320x180
/// setup keeps about half a million: the rest are back faces or cover no pixel centre.)
#[test]
fn a_five_million_triangle_frame_is_right() {
    let gpu = gpu();
    let scene = translucid::scene::load("hairball:5m").expect("generated scene");
    let (width, height) = (320, 180);
    let frame = Renderer::new(&gpu, &scene, MethodKind::Exact, width, height)
        .and_then(|mut r| r.render(true))
        .expect("a 5 M-triangle frame");
    assert!(
        frame.triangles > 100_000,
        "{} triangles rasterized",
        frame.triangles
    );
    assert_matches_reference("five_million", &scene, &frame);
}

/// Textures past one storage binding: three 4096x4096 textures with their mips (256 MB of
/// texels, twice what one binding holds on lavapipe) on three overlapping transparent quads.
/// The software sampler reads them through one texel view, which only the device's texels a
/// view bound; the frame matches the CPU reference.
#[test]
fn textures_past_a_storage_binding_are_sampled_right() {
    let gpu = gpu();
    let side = 4096u32;
    let texture = |k: u32| {
        let texels = (0..side * side)
            .map(|i| {
                let (x, y) = (i % side, i / side);
                let cell = ((x >> (4 + k)) ^ (y >> 5)) & 1;
                [
                    (x >> 4) as u8,
                    (y >> 4) as u8,
                    (cell * 200 + 40 * k) as u8,
                    255,
                ]
            })
            .collect();
        translucid::scene::Texture::new(format!("large {k}"), side, side, texels, false)
    };
    let mut positions = Vec::new();
    let mut uvs = Vec::new();
    let mut meshes = Vec::new();
    for k in 0..3 {
        let (x, z) = (k as f32 * 0.3 - 0.3, -(k as f32) * 0.1);
        positions.clear();
        positions.extend([
            Vec3::new(x - 0.5, -0.4, z),
            Vec3::new(x + 0.5, -0.4, z),
            Vec3::new(x + 0.5, 0.4, z),
            Vec3::new(x - 0.5, 0.4, z),
        ]);
        uvs.clear();
        uvs.extend([
            glam::Vec2::new(0.0, 1.0),
            glam::Vec2::new(1.0, 1.0),
            glam::Vec2::new(1.0, 0.0),
            glam::Vec2::new(0.0, 0.0),
        ]);
        let mut mesh = Mesh::from_quads("quad", positions.clone(), vec![[0, 1, 2, 3]]);
        mesh.uvs = Some(uvs.clone());
        meshes.push(mesh);
    }
    let scene = Scene {
        name: "large textures".into(),
        transparent: (0..3)
            .map(|k| Draw {
                mesh: k,
                material: k,
                transform: Mat4::IDENTITY,
                tint: glam::Vec4::ONE,
            })
            .collect(),
        materials: (0..3)
            .map(|k| Material {
                name: format!("large {k}"),
                base_colour: glam::Vec4::new(1.0, 1.0, 1.0, 0.6),
                texture: Some(k),
                ..Material::default()
            })
            .collect(),
        textures: (0..3).map(|k| texture(k as u32)).collect(),
        meshes,
        camera: translucid::scene::Camera::look_at(
            Vec3::new(0.0, 0.0, 2.0),
            Vec3::ZERO,
            0.8,
            0.1,
            20.0,
        ),
        background: Vec3::splat(0.2),
        ..Scene::default()
    };
    let frame = Renderer::new(&gpu, &scene, MethodKind::Exact, 160, 120)
        .and_then(|mut r| r.render(true))
        .expect("a frame over 256 MB of textures");
    assert_matches_reference("large_textures", &scene, &frame);
}

/// A frame that draws more quads than translucid draws in a frame (a mesh drawn many times
/// counted each time) is refused by name before any work: a 1.6 KB glTF file listing a
/// node 100,000 times drew a 10,000-quad mesh as often and ran for hours.
#[test]
fn frames_drawing_too_many_quads_are_refused_by_name() {
    let quads = 1000u32;
    let positions: Vec<Vec3> = (0..quads * 4)
        .map(|i| Vec3::new((i / 4) as f32, (i % 2) as f32, ((i / 2) % 2) as f32))
        .collect();
    let indices: Vec<[u32; 4]> = (0..quads)
        .map(|q| [4 * q, 4 * q + 1, 4 * q + 3, 4 * q + 2])
        .collect();
    let draws = translucid::scene::MAX_FRAME_QUADS / u64::from(quads) + 1;
    let scene = Scene {
        name: "many instances".into(),
        meshes: vec![Mesh::from_quads("strip", positions, indices)],
        materials: vec![Material::alpha(Vec3::ONE, 0.5)],
        transparent: vec![
            Draw {
                mesh: 0,
                material: 0,
                transform: Mat4::IDENTITY,
                tint: glam::Vec4::ONE,
            };
            usize::try_from(draws).expect("fits")
        ],
        ..Scene::default()
    };
    let err = scene.validate().expect_err("too many quads");
    assert!(
        err.to_string().contains("quads") && err.to_string().contains("at most"),
        "{err}"
    );
}
