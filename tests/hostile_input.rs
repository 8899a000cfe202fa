//! Input a user did not write and a library must still get right or refuse: scenes far from
//! the origin, scenes at extreme scales, extreme cameras and colours. Every method's output
//! is finite, and as right as the same input at an ordinary place and scale.

use glam::{Mat4, Vec3};
use translucid::methods::MethodKind;
use translucid::metrics;
use translucid::renderer::Renderer;
use translucid::scene::{Camera, Material, Mesh, Projection, Scene};
use translucid::shading::MAX_COLOUR;
use translucid::OpaqueLayer;
use translucid_tests::{against_reference, gpu, one_draw_scene, render, save_failure};

const SIZE: (u32, u32) = (64, 48);

/// One lit quad without normals (its face normal lights it), tilted towards the light and
/// large enough to cover the whole frame, seen from 3 units away; everything scaled by
/// `scale` and moved `offset` from the origin.
fn lit_quad(offset: Vec3, scale: f32) -> Scene {
    let corners = [
        Vec3::new(-4.0, -3.0, -0.5),
        Vec3::new(4.0, -3.0, -1.5),
        Vec3::new(4.0, 3.0, -1.0),
        Vec3::new(-4.0, 3.0, 0.0),
    ];
    let mesh = Mesh::from_quads("tilted", corners.to_vec(), vec![[0, 1, 2, 3]]);
    let material = Material {
        lit: true,
        ..Material::alpha(Vec3::new(0.9, 0.6, 0.3), 0.7)
    };
    let camera = Camera::look_at(
        offset + Vec3::new(0.0, 0.0, 3.0) * scale,
        offset,
        0.8,
        0.1 * scale,
        20.0 * scale,
    );
    let mut scene = one_draw_scene("lit quad", mesh, material, camera);
    scene.transparent[0].transform =
        Mat4::from_translation(offset) * Mat4::from_scale(Vec3::splat(scale));
    scene
}

/// A lit surface 10 km and 100 km from the origin, and scenes at scales 1e-9 to 1e19, shade
/// in every method (and in the reference) as the same surface at the origin at scale 1:
/// world positions 10 km out left the hardware methods' face normals noisy (38/255 on 9.5 %
/// of pixels), and squared lengths under- or overflowed at extreme scales, dropping the
/// diffuse term (31/255 everywhere; at 1e12 in the reference too, so compare passed it).
#[test]
fn far_and_extreme_scale_scenes_shade_as_at_the_origin() {
    let gpu = gpu();
    let at_origin = lit_quad(Vec3::ZERO, 1.0);
    let cases = [
        ("10 km", lit_quad(Vec3::new(1e4, 2e3, -7e3), 1.0)),
        ("100 km", lit_quad(Vec3::new(-1e5, 3e4, 6e4), 1.0)),
        ("scale 1e-9", lit_quad(Vec3::ZERO, 1e-9)),
        ("scale 1e10", lit_quad(Vec3::ZERO, 1e10)),
        ("scale 1e12", lit_quad(Vec3::ZERO, 1e12)),
        ("scale 1e19", lit_quad(Vec3::ZERO, 1e19)),
    ];
    for kind in MethodKind::ALL {
        let method = kind.name();
        let expected = render(&gpu, &at_origin, method, SIZE.0, SIZE.1).image;
        for (name, scene) in &cases {
            let frame = render(&gpu, scene, method, SIZE.0, SIZE.1);
            let m = metrics::compare(&frame.image, &expected).expect("same size");
            assert!(
                m.within(2.0 / 255.0),
                "{method} at {name}: {:.1}/255 off the origin's frame on {} pixels ({})",
                m.max_error * 255.0,
                m.pixels_over,
                save_failure(&format!("far_{method}_{name}"), &frame.image, &expected).display()
            );
        }
    }
    // No opaque draws: every scene's opaque layer is its background at the far plane.
    let frame = render(&gpu, &at_origin, "blend", SIZE.0, SIZE.1);
    let opaque = frame.opaque.as_ref().expect("opaque layer read back");
    let expected = translucid::reference::render(&at_origin, opaque).expect("reference");
    for (name, scene) in &cases {
        let got = translucid::reference::render(scene, opaque).expect("reference");
        let m = metrics::compare(&got, &expected).expect("same size");
        assert!(m.within(2.0 / 255.0), "the reference at {name}: {m:?}");
    }
}

/// A lit quad with vertex normals under a model matrix that flattens it (a zero scale on one
/// axis, as a fuzzed glTF node had): the normals' matrix is singular there. Every method
/// shades it as the reference does (the GPU took the 3x3's inverse, NaN, and dropped the
/// diffuse term: 4.9/255 off on the fuzzed vase), and under mirroring and huge or tiny
/// scales too.
#[test]
fn flattened_mirrored_and_scaled_draws_shade_their_normals_as_the_reference() {
    let gpu = gpu();
    let corners = vec![
        Vec3::new(-1.5, -1.0, -0.5),
        Vec3::new(1.5, -1.0, -1.5),
        Vec3::new(1.5, 1.0, -1.0),
        Vec3::new(-1.5, 1.0, 0.0),
    ];
    let mut mesh = Mesh::from_quads("tilted", corners, vec![[0, 1, 2, 3]]);
    mesh.normals = Some(vec![Vec3::new(0.3, 0.2, 1.0).normalize(); 4]);
    let material = Material {
        lit: true,
        double_sided: true,
        ..Material::alpha(Vec3::new(0.9, 0.6, 0.3), 0.7)
    };
    let camera = Camera::look_at(Vec3::new(0.0, 0.0, 3.0), Vec3::ZERO, 0.8, 0.1, 20.0);
    let base = one_draw_scene("normals", mesh, material, camera);
    let cases = [
        ("flattened in z", Vec3::new(1.0, 1.0, 0.0)),
        ("mirrored in x", Vec3::new(-1.0, 1.0, 1.0)),
        ("z scaled by 1e-30", Vec3::new(1.0, 1.0, 1e-30)),
        ("z scaled by 1e30", Vec3::new(1.0, 1.0, 1e30)),
    ];
    for (name, scale) in cases {
        let mut scene = base.clone();
        scene.transparent[0].transform = Mat4::from_scale(scale);
        for kind in MethodKind::ALL {
            let method = kind.name();
            let (m, got, want) = against_reference(&gpu, &scene, method, SIZE.0, SIZE.1);
            assert!(
                m.within(2.0 / 255.0),
                "{method}, {name}: {:.1}/255 off the reference on {} pixels ({})",
                m.max_error * 255.0,
                m.pixels_over,
                save_failure(&format!("normals_{method}_{name}"), &got, &want).display()
            );
        }
    }
}

/// A lit quad without normals 1e31 across, seen through a camera whose near plane is 1e30
/// and far plane 3e38: every method's frame is finite and matches the reference (exact and
/// wavelet gave NaN over such surfaces, and through an engine the pixels read back NaN).
#[test]
fn extreme_coordinates_and_planes_give_finite_frames() {
    let gpu = gpu();
    let mut scene = lit_quad(Vec3::ZERO, 1e31);
    scene.camera.view = Mat4::from_translation(Vec3::new(0.0, 0.0, -3e31));
    scene.camera.projection = Projection::Perspective {
        fov_y: 0.8,
        near: 1e30,
        far: 3e38,
    };
    for kind in MethodKind::ALL {
        let method = kind.name();
        let (m, got, want) = against_reference(&gpu, &scene, method, SIZE.0, SIZE.1);
        assert!(
            m.non_finite == 0 && m.within(2.0 / 255.0),
            "{method}: {m:?} ({})",
            save_failure(&format!("extreme_{method}"), &got, &want).display()
        );
    }
}

/// HDR colours up to the documented limit, 65504 (the largest half float) in the light, the
/// ambient, the base colour and the opaque layer, give finite frames in every method, each
/// pixel at most 65504 and matching the reference; past the limit each input is refused by
/// name. A light of 1.7e5 gave linked_list infinite pixels, an opaque 65520 every method,
/// a base colour of 1e35 wavelet.
#[test]
fn hdr_colours_up_to_the_limit_stay_finite_and_past_it_are_refused() {
    let gpu = gpu();
    let bright = Material {
        lit: true,
        ..Material::alpha(Vec3::splat(MAX_COLOUR), 0.5)
    };
    let mut scene = translucid_tests::stack_scene("hdr", 6, bright);
    scene.light.colour = Vec3::splat(MAX_COLOUR);
    scene.light.ambient = Vec3::splat(MAX_COLOUR);
    let opaque = OpaqueLayer::clear(SIZE.0, SIZE.1, Vec3::splat(MAX_COLOUR));
    let expected = translucid::reference::render(&scene, &opaque).expect("reference");
    assert!(expected.pixels.iter().all(|p| p.is_finite()));
    for kind in MethodKind::ALL {
        let method = kind.name();
        let mut renderer = Renderer::new(&gpu, &scene, kind, SIZE.0, SIZE.1).expect("renderer");
        let frame = renderer.render_over(&opaque).expect("frame");
        let largest = frame
            .image
            .pixels
            .iter()
            .map(|p| p.truncate().max_element())
            .fold(0.0f32, |a, b| if b.is_nan() { f32::NAN } else { a.max(b) });
        assert!(largest <= MAX_COLOUR, "{method}: a pixel of {largest}");
        let m = metrics::compare(&frame.image, &expected).expect("same size");
        assert!(m.within(2.0 / 255.0), "{method}: {m:?}");
    }

    let refused = |scene: &Scene, says: &str| {
        let err = Renderer::new(&gpu, scene, MethodKind::Blend, SIZE.0, SIZE.1)
            .err()
            .unwrap_or_else(|| panic!("{says}: accepted"));
        assert!(err.to_string().contains(says), "{says}: {err}");
    };
    let mut light = scene.clone();
    light.light.colour = Vec3::splat(1.7e5);
    refused(&light, "light colour");
    let mut base = scene.clone();
    base.materials[0].base_colour = glam::Vec4::new(1e35, 1.0, 1.0, 0.5);
    refused(&base, "base_colour");
    let mut renderer =
        Renderer::new(&gpu, &scene, MethodKind::Blend, SIZE.0, SIZE.1).expect("renderer");
    let over = OpaqueLayer::clear(SIZE.0, SIZE.1, Vec3::splat(65520.0));
    let err = renderer.render_over(&over).err().expect("refused");
    assert!(err.to_string().contains("opaque layer"), "{err}");
}

/// Texture coordinates past 2^24 are refused by name: past it an f32 holds no fraction of a
/// texture, and coordinates of 1e30 and more (a fuzzed file read its UVs from a misaligned
/// offset) overflowed the hardware sampler's derivatives, so the opaque pass returned NaN
/// pixels that every method composited over.
#[test]
fn texture_coordinates_past_their_limit_are_refused() {
    let gpu = gpu();
    let mut scene = translucid::scene::load("textured").expect("scene");
    let mesh = scene
        .meshes
        .iter_mut()
        .find(|m| m.uvs.is_some())
        .expect("a mesh with uvs");
    if let Some(uvs) = &mut mesh.uvs {
        uvs[0] = glam::Vec2::new(3e30, 0.5);
    }
    let err = Renderer::new(&gpu, &scene, MethodKind::Blend, 37, 23)
        .err()
        .expect("refused");
    assert!(err.to_string().contains("uv 0"), "{err}");
}

/// The CPU reference holds a bounded number of fragments per tile and says so past it: a
/// fuzzed file drawing one window 100,000 times made it ask for gigabytes and abort.
#[test]
fn the_reference_refuses_tiles_past_its_fragment_limit() {
    let quad = Mesh::from_quads(
        "screen",
        vec![
            Vec3::new(-5.0, -5.0, 0.0),
            Vec3::new(5.0, -5.0, 0.0),
            Vec3::new(5.0, 5.0, 0.0),
            Vec3::new(-5.0, 5.0, 0.0),
        ],
        vec![[0, 1, 2, 3]],
    );
    let camera = Camera::look_at(Vec3::new(0.0, 0.0, 3.0), Vec3::ZERO, 0.8, 0.1, 20.0);
    let mut scene = one_draw_scene("stack", quad, Material::alpha(Vec3::ONE, 0.01), camera);
    let side = translucid::reference::TILE;
    let per_pixel = translucid::reference::MAX_TILE_FRAGMENTS / (side * side) as usize;
    scene.transparent = vec![scene.transparent[0].clone(); per_pixel + 1];
    let opaque = OpaqueLayer::clear(side, side, Vec3::ZERO);
    let err = translucid::reference::render(&scene, &opaque).expect_err("too deep");
    assert!(err.to_string().contains("fragments in a tile"), "{err}");
}

/// A hostile stack of `stacks.rs` (generated scenes), `NAME:N`.
fn stack(spec: &str) -> Scene {
    translucid::scene::generated::generate_sized(spec)
        .expect("a sized scene")
        .expect("a count it takes")
}

/// Stacks that no depth order splits, and deep random ones: exact right, and stacks at one
/// depth composited in one sweep over their lists (slabs split a depth by order key), however
/// deep. (Before: 16,384 instanced quads at 32x32 took exact 262 s, 10,000 coincident
/// triangles at 160x120 over 400 s against blend's 2 s, 100,000 random draws 20x blend.) What
/// they cost against blend is a bench row, not a test (wall time is noise on a busy machine):
/// `translucid bench instanced:16384 coincident:10000 random_draws:100000 --size 160x120
/// --method exact --method blend --motion static`.
#[test]
fn exact_renders_coincident_instanced_and_random_stacks_right_and_one_depth_in_one_sweep() {
    let gpu = gpu();
    for (scene, size) in [
        (stack("instanced:512"), (32, 32)),
        (stack("coincident:500"), (40, 30)),
        (stack("random_draws:3000"), (80, 60)),
    ] {
        let (m, got, expected) = against_reference(&gpu, &scene, "exact", size.0, size.1);
        assert!(
            m.max_error * 255.0 <= 2.0,
            "{}: {:.1}/255 off the reference; see {}",
            scene.name,
            m.max_error * 255.0,
            save_failure(&format!("stack_{}", scene.name), &got, &expected).display()
        );
    }
    for (scene, (width, height)) in [
        (stack("instanced:16384"), (32, 32)),
        (stack("coincident:10000"), (160, 120)),
    ] {
        let mut exact =
            Renderer::new(&gpu, &scene, MethodKind::Exact, width, height).expect("exact");
        // Warm: what the first frames learned (slabs, selection) is in place.
        let mut frame = exact.render(false).expect("a frame");
        for _ in 0..2 {
            frame = exact.render(false).expect("a frame");
        }
        assert_eq!(
            frame.sweeps, 1,
            "{}: pixels swept their lists again",
            scene.name
        );
    }
}

/// `count` copies of one screen-filling triangle in one mesh, tilted away from the camera:
/// at each pixel all at one depth, but a different one from pixel to pixel, so that the
/// depth slabs (planned on each triangle's nearest vertex) bound none of them, and every
/// sweep of a row walks the whole list for the 16 fragments it composites.
fn coincident_tilted_triangles(count: u32) -> Scene {
    let mut positions = Vec::new();
    let mut triangles = Vec::new();
    for i in 0..count {
        positions.extend([
            Vec3::new(-9.0, -9.0, -1.0),
            Vec3::new(9.0, -9.0, -3.0),
            Vec3::new(0.0, 9.0, -2.0),
        ]);
        triangles.push([3 * i, 3 * i + 1, 3 * i + 2]);
    }
    let camera = Camera::look_at(Vec3::new(0.0, 0.0, 3.0), Vec3::ZERO, 0.8, 0.1, 20.0);
    let mesh = Mesh::from_triangles("coincident tilted", positions, &triangles);
    one_draw_scene(
        "coincident tilted",
        mesh,
        Material::alpha(Vec3::ONE, 0.5),
        camera,
    )
}

/// The work bound holds a hostile frame to seconds: 20,000 coincident tilted triangles at
/// 16x16 need some 400 continuation dispatches for each of their 16 rows, past the frame's
/// bound of 4,096, so exact refuses the frame by name after its 64-continuation round (a
/// fuzzed glTF of 100,000 such instances at 37x23 took 14 minutes to be refused under the
/// per-row bound alone, and this frame 20 s to render). blend draws it.
#[test]
fn frames_past_the_work_bound_are_refused_in_seconds() {
    let gpu = gpu();
    let scene = coincident_tilted_triangles(20_000);
    let err = Renderer::new(&gpu, &scene, MethodKind::Exact, 16, 16)
        .and_then(|mut r| r.render(false))
        .err()
        .expect("exact refuses the frame");
    let message = err.to_string();
    assert!(
        message.contains("work bound") && message.contains("after 64 continuation"),
        "{message}"
    );
    let frame = render(&gpu, &scene, "blend", 16, 16);
    assert!(frame.image.pixels.iter().all(|p| p.is_finite()));
}
