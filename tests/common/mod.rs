//! Shared helpers of the end-to-end tests.

use glam::{Mat4, Vec3};
use std::path::PathBuf;
use translucid::gpu::{Gpu, GpuOptions};
use translucid::metrics::{self, Metrics};
use translucid::renderer::{Frame, Renderer};
use translucid::scene::{Camera, Draw, Material, Mesh, Scene};
use translucid::Image;

/// The device under test, with the validation layer on: any validation error fails the test.
pub fn gpu() -> Gpu {
    gpu_with(None)
}

/// The tests' device with the variants of `profile` forced (`None`: its own, or
/// `TRANSLUCID_PROFILE`'s).
pub fn gpu_with(profile: Option<translucid::gpu::Profile>) -> Gpu {
    Gpu::new(&GpuOptions {
        device: std::env::var("TRANSLUCID_DEVICE").ok(),
        validation: true,
        profile,
        software_sampling: false,
        ..Default::default()
    })
    .expect("a Vulkan device with the Khronos validation layer (`make test` installs both)")
}

/// A vendored scene under assets/scenes.
pub fn asset(relative: &str) -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("../assets/scenes")
        .join(relative)
}

/// The shared scene collection beside the project (`../shared/scenes` from the workspace
/// root) when it is there: a clone of the project alone has only assets/scenes. Tests that
/// sweep it skip without it, and say so ([`say_skipped`]); every property they check has a
/// case on vendored or generated scenes that always runs.
pub fn shared_scenes() -> Option<PathBuf> {
    let root = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../../shared/scenes");
    root.is_dir().then_some(root)
}

/// Tells whoever runs the tests that `test` skipped `what`, and why. Written to the process's
/// stderr itself, past the test harness's capture of `eprintln!`, so that a skip shows in a
/// plain `cargo test` rather than passing silently.
pub fn say_skipped(test: &str, what: &str, why: &str) {
    use std::io::Write;
    let _ = writeln!(std::io::stderr(), "{test}: SKIPPED {what}: {why}");
}

/// [`say_skipped`] for a test that needs the shared scene collection.
pub fn say_no_shared_scenes(test: &str, what: &str) {
    say_skipped(
        test,
        what,
        "no shared scene collection at ../shared/scenes beside the project (a clone alone has \
         only assets/scenes)",
    );
}

/// One frame of `scene` with `method`, its opaque layer read back too.
pub fn render(gpu: &Gpu, scene: &Scene, method: &str, width: u32, height: u32) -> Frame {
    let kind = method.parse().expect("a method name");
    let mut renderer = Renderer::new(gpu, scene, kind, width, height)
        .unwrap_or_else(|e| panic!("{method} on {}: {e}", scene.name));
    renderer
        .render(true)
        .unwrap_or_else(|e| panic!("{method} on {}: {e}", scene.name))
}

/// The method's frame and the CPU reference rendered over the same opaque layer, compared.
pub fn against_reference(
    gpu: &Gpu,
    scene: &Scene,
    method: &str,
    width: u32,
    height: u32,
) -> (Metrics, Image, Image) {
    let frame = render(gpu, scene, method, width, height);
    let opaque = frame.opaque.as_ref().expect("opaque layer read back");
    let expected = translucid::reference::render(scene, opaque).expect("reference");
    let m = metrics::compare(&frame.image, &expected).expect("same size");
    (m, frame.image, expected)
}

/// Where a failing test leaves its pictures for a person to look at.
pub fn save_failure(name: &str, got: &Image, expected: &Image) -> PathBuf {
    let dir = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../target/test-failures");
    let path = dir.join(format!("{name}.png"));
    if let Ok(heat) = metrics::heat_map(got, expected) {
        let _ = metrics::side_by_side(&[got, expected, &heat]).save_png(&path);
    }
    path
}

/// `layers` screen-facing quads of `material` stacked over one spot, each a little nearer and
/// shifted, so that pixels there are up to `layers` fragments deep.
pub fn stack_scene(name: &str, layers: u32, material: Material) -> Scene {
    let mut positions = Vec::new();
    let mut quads = Vec::new();
    for i in 0..layers {
        let z = -1.0 + i as f32 * 0.002;
        let shift = (i % 7) as f32 * 0.02;
        let first = positions.len() as u32;
        positions.extend([
            Vec3::new(-0.5 + shift, -0.4, z),
            Vec3::new(0.5 + shift, -0.4, z),
            Vec3::new(0.5 + shift, 0.4 - shift, z),
            Vec3::new(-0.5 + shift, 0.4 - shift, z),
        ]);
        quads.push([first, first + 1, first + 2, first + 3]);
    }
    one_draw_scene(
        name,
        Mesh::from_quads("stack", positions, quads),
        material,
        Camera::look_at(Vec3::new(0.0, 0.0, 3.0), Vec3::ZERO, 0.8, 0.1, 20.0),
    )
}

/// `layers` screen-facing quads stacked over one spot, at one depth but for one a hair behind
/// and the last far behind (so that no slab splits them: `crowded_bin` says why): pixels
/// about a thousand fragments deep in one slab sweep it about layers / 16 times, more loop
/// iterations than lavapipe allows one shader invocation (it ends loops silently after
/// 65535), so their rows are suspended and finished by continuation dispatches.
pub fn one_depth_stack(layers: u32) -> Scene {
    let mut scene = stack_scene(
        "deep stack",
        layers,
        Material::alpha(Vec3::new(0.9, 0.5, 0.2), 0.004),
    );
    let mesh = &mut scene.meshes[0];
    let quads = mesh.positions.len() / 4;
    for (i, p) in mesh.positions.iter_mut().enumerate() {
        p.z = match quads - i / 4 {
            1 => -8.0,
            2 => -1.00001,
            _ => -1.0,
        };
    }
    scene
}

pub use translucid::scene::generated::one_draw_scene;

/// A quad that passes through the camera plane: rasterized homogeneously, clipped by depth.
pub fn near_plane_scene() -> Scene {
    let positions = vec![
        Vec3::new(-3.0, -1.0, 6.0),
        Vec3::new(3.0, -1.0, 6.0),
        Vec3::new(3.0, 0.5, -6.0),
        Vec3::new(-3.0, 0.5, -6.0),
    ];
    let tilted = Mesh::from_quads("through the eye", positions, vec![[0, 1, 2, 3]]);
    let back = Mesh::from_quads(
        "back",
        vec![
            Vec3::new(-2.0, -2.0, -1.0),
            Vec3::new(2.0, -2.0, -1.0),
            Vec3::new(2.0, 2.0, -1.0),
            Vec3::new(-2.0, 2.0, -1.0),
        ],
        vec![[0, 1, 2, 3]],
    );
    Scene {
        name: "near plane".into(),
        meshes: vec![tilted, back],
        materials: vec![
            Material::alpha(Vec3::new(0.9, 0.3, 0.1), 0.6),
            Material::alpha(Vec3::new(0.1, 0.4, 0.9), 0.5),
        ],
        transparent: vec![
            Draw {
                mesh: 1,
                material: 1,
                transform: Mat4::IDENTITY,
                tint: glam::Vec4::ONE,
            },
            Draw {
                mesh: 0,
                material: 0,
                transform: Mat4::IDENTITY,
                tint: glam::Vec4::ONE,
            },
        ],
        camera: Camera::look_at(Vec3::new(0.0, 0.0, 2.0), Vec3::ZERO, 1.0, 0.1, 50.0),
        background: Vec3::splat(0.8),
        ..Scene::default()
    }
}

/// `count` triangles over all of an 8x8-pixel frame, all at one depth but the last, a
/// hair behind the others, so that every row's list holds all of them and no slab splits
/// it: slabs split a depth by order key only where all the triangles of its histogram
/// bucket share it (bin_lists.glsl), and a far triangle behind them all makes the
/// buckets wide.
pub fn crowded_bin(count: u32) -> Scene {
    let mut positions = Vec::new();
    let mut triangles = Vec::new();
    for i in 0..count {
        // Each a little turned, so that they are not all the same triangle.
        let turn = glam::Quat::from_rotation_z(i as f32 * 0.001);
        let z = if i + 1 == count { -2.00001 } else { -2.0 };
        let first = positions.len() as u32;
        // (z set after the turn, which would round it.)
        positions.extend(
            [
                Vec3::new(-6.0, -6.0, 0.0),
                Vec3::new(6.0, -6.0, 0.0),
                Vec3::new(0.0, 6.0, 0.0),
            ]
            .map(|p| (turn * p).truncate().extend(z)),
        );
        triangles.push([first, first + 1, first + 2]);
    }
    let first = positions.len() as u32;
    positions.extend([
        Vec3::new(-60.0, -60.0, -19.0),
        Vec3::new(60.0, -60.0, -19.0),
        Vec3::new(0.0, 60.0, -19.0),
    ]);
    triangles.push([first, first + 1, first + 2]);
    one_draw_scene(
        "crowded bin",
        Mesh::from_triangles("crowd", positions, &triangles),
        Material::alpha(Vec3::new(0.2, 0.6, 0.9), 0.5),
        Camera::look_at(Vec3::ZERO, Vec3::NEG_Z, 1.0, 0.1, 20.0),
    )
}

/// `scene` with every transparent draw tinted a colour of its own (linear RGB from 0.2 to 1,
/// alpha from 0.5 to 1), as an engine tints instances.
pub fn tinted(scene: &Scene) -> Scene {
    let mut tinted = scene.clone();
    tinted.name = format!("{} tinted", scene.name);
    for (i, d) in tinted.transparent.iter_mut().enumerate() {
        let k = i as f32;
        let wave = |phase: f32| 0.6 + 0.4 * (1.7 * k + phase).sin();
        d.tint = glam::Vec4::new(
            wave(0.0),
            wave(2.1),
            wave(4.2),
            0.75 + 0.25 * (0.9 * k).cos(),
        );
    }
    tinted
}

/// `scene` with a copy of the mesh, material and texture of a textured transparent draw (the
/// one with the last texture, whose texels are not the first ones) added after its own
/// assets, and that draw drawing the copies: the same picture, from assets appended later.
pub fn with_copied_assets(scene: &Scene) -> Scene {
    let mut grown = scene.clone();
    let (i, draw) = scene
        .transparent
        .iter()
        .enumerate()
        .filter(|(_, d)| scene.materials[d.material].texture.is_some())
        .max_by_key(|(_, d)| scene.materials[d.material].texture)
        .expect("a textured transparent draw");
    assert!(scene.materials[draw.material].texture > Some(0));
    let material = &scene.materials[draw.material];
    let texture = material.texture.expect("textured");
    grown.meshes.push(scene.meshes[draw.mesh].clone());
    grown.textures.push(scene.textures[texture].clone());
    grown.materials.push(translucid::scene::Material {
        texture: Some(scene.textures.len()),
        ..material.clone()
    });
    grown.transparent[i].mesh = scene.meshes.len();
    grown.transparent[i].material = scene.materials.len();
    grown
}

/// `scene` (`textured`) with one more texture, `size`² texels of a hue and alpha gradient,
/// and a material like that of its first transparent draw sampling it; and a draw of that
/// material, the first draw's quad moved towards the camera, to add to either layer.
pub fn with_large_texture(scene: &Scene, size: u32) -> (Scene, Draw) {
    assert!(size >= 2);
    let mut grown = scene.clone();
    let texels = (0..size * size)
        .map(|i| {
            let (x, y) = (i % size, i / size);
            let byte = |v: u32| (v * 255 / (size - 1)) as u8;
            [byte(x), byte(y), byte(size - 1 - x), 96 + byte(y) / 2]
        })
        .collect();
    grown.textures.push(translucid::scene::Texture::new(
        "large gradient",
        size,
        size,
        texels,
        true,
    ));
    let first = &scene.transparent[0];
    grown.materials.push(Material {
        texture: Some(scene.textures.len()),
        ..scene.materials[first.material].clone()
    });
    let draw = Draw {
        material: scene.materials.len(),
        transform: Mat4::from_translation(Vec3::new(0.05, 0.1, 0.3)) * first.transform,
        ..first.clone()
    };
    (grown, draw)
}

/// `frame` (rendered with its opaque layer read back) against the CPU reference over that
/// layer: every pixel within 2/255, else the pictures are saved as `name`.
pub fn assert_matches_reference(name: &str, scene: &Scene, frame: &Frame) {
    let opaque = frame.opaque.as_ref().expect("opaque layer read back");
    let reference = translucid::reference::render(scene, opaque).expect("reference");
    let m = metrics::compare(&frame.image, &reference).expect("same size");
    assert!(
        m.max_error <= 2.0 / 255.0,
        "{name}: {:.1}/255 off the reference on {} pixels ({})",
        m.max_error * 255.0,
        m.pixels_over,
        save_failure(name, &frame.image, &reference).display()
    );
}

/// Every generated scene of `names` with `method` at `width` x `height`, every pixel within
/// 2/255 of the reference.
pub fn assert_every_pixel_matches(gpu: &Gpu, method: &str, names: &[&str], size: (u32, u32)) {
    for name in names {
        let scene = translucid::scene::load(name).expect("generated scene");
        let frame = render(gpu, &scene, method, size.0, size.1);
        assert_matches_reference(&format!("{method}_{name}"), &scene, &frame);
    }
}

/// The exact peers the driver rasterizes (linked_list, depth_peeling) on scenes where that
/// shows: each `(scene, most pixels over 2/255, size)` case has at most that many pixels over
/// and a PSNR of at least 50 dB.
pub fn assert_within_the_drivers_rasterization(
    gpu: &Gpu,
    method: &str,
    cases: &[(&str, u64, (u32, u32))],
) {
    for &(spec, most_over, (width, height)) in cases {
        let scene = translucid::scene::load(spec).expect("scene");
        let (m, got, want) = against_reference(gpu, &scene, method, width, height);
        assert!(
            m.pixels_over <= most_over && m.psnr >= 50.0,
            "{method} on {spec}: {} pixels over 2/255 (at most {most_over}), up to {:.1}/255, \
             {:.1} dB ({})",
            m.pixels_over,
            m.max_error * 255.0,
            m.psnr,
            save_failure(&format!("{method}_driver"), &got, &want).display()
        );
    }
}

/// `count` quads in one tilted plane, each turned a little further about the plane's normal,
/// each of its own colour at alpha 0.4, in one draw: they overlap everywhere at one depth
/// up to rounding, so the order they composite in is the reference's tie rule (depth as it
/// rounds, then submission order).
pub fn coplanar_turned_quads(count: u32) -> Scene {
    let (u, v) = (Vec3::new(1.0, 0.0, 0.3), Vec3::new(0.0, 1.0, -0.2));
    let mut positions = Vec::new();
    let mut colours = Vec::new();
    let mut quads = Vec::new();
    for i in 0..count {
        let angle = i as f32 * std::f32::consts::PI / count as f32;
        let (s, c) = angle.sin_cos();
        let first = positions.len() as u32;
        for (x, y) in [(-0.6, -0.6), (0.6, -0.6), (0.6, 0.6), (-0.6, 0.6)] {
            let (x, y) = (c * x - s * y, s * x + c * y);
            positions.push(u * x + v * y);
        }
        let hue = i as f32 / count as f32;
        let colour = glam::Vec4::new(hue, 1.0 - hue, (hue * 3.0).fract(), 0.4);
        colours.extend([colour; 4]);
        quads.push([first, first + 1, first + 2, first + 3]);
    }
    let mut mesh = Mesh::from_quads("coplanar", positions, quads);
    mesh.colours = Some(colours);
    let material = Material {
        double_sided: true,
        ..Material::default()
    };
    let camera = Camera::look_at(Vec3::new(0.4, 0.3, 2.5), Vec3::ZERO, 0.8, 0.1, 20.0);
    one_draw_scene("coplanar", mesh, material, camera)
}

/// `method` on surfaces at one depth up to rounding (linked_list.rs,
/// `surfaces_at_one_depth_composite_in_the_references_order`): 40 quads turned within one
/// plane at 160x120, the planes' 1x1 frame (its one pixel where the planes cross), and the
/// spheres at 1x64, 1x2047 and 3x2048, each within 2/255 of the reference but for 0.05 % of
/// its pixels (the driver's tie rule on edges).
pub fn assert_one_depth_order(gpu: &Gpu, method: &str) {
    let coplanar = coplanar_turned_quads(40);
    let planes = translucid::scene::load("planes").expect("generated scene");
    let spheres = translucid::scene::load("spheres").expect("generated scene");
    let cases = [
        ("coplanar", &coplanar, (160, 120)),
        ("planes_1x1", &planes, (1, 1)),
        ("spheres_1x64", &spheres, (1, 64)),
        ("spheres_1x2047", &spheres, (1, 2047)),
        ("spheres_3x2048", &spheres, (3, 2048)),
    ];
    for (name, scene, (width, height)) in cases {
        let (m, got, want) = against_reference(gpu, scene, method, width, height);
        let most_over = u64::from(width * height) / 2000;
        assert!(
            m.pixels_over <= most_over,
            "{method} on {name}: {} pixels over 2/255 (at most {most_over}), up to {:.1}/255 \
             ({})",
            m.pixels_over,
            m.max_error * 255.0,
            save_failure(&format!("{method}_{name}"), &got, &want).display()
        );
    }
}

/// `frame`, a bin method's, ran on the tiles `gpu` gets (`features::tile_shift`): 8x2 on
/// lavapipe at 512 bits, whose subgroups really hold 16 lanes.
pub fn assert_device_tiles(gpu: &Gpu, frame: &Frame) {
    let shape = frame.bins.expect("a bin method reports its shape");
    let tile_rows = 1 << translucid::methods::bins::features::tile_shift(gpu.info().into());
    assert_eq!(shape.tile_rows, tile_rows, "{shape:?}");
    if std::env::var("LP_NATIVE_VECTOR_WIDTH").as_deref() == Ok("512") {
        assert_eq!(shape.tile_rows, 2, "16 lanes: {shape:?}");
    }
}

/// Lavapipe's reported subgroups follow `LP_NATIVE_VECTOR_WIDTH` (bits): 16, 32 and 64
/// lanes at 512, 1024 and 2048 (8, the default, at 256).
const LAVAPIPE_WIDTHS: [(&str, u32); 3] = [("512", 16), ("1024", 32), ("2048", 64)];

/// The test that draws one plain frame, which every test binary that reruns itself at
/// lavapipe's wider sizes defines (calling [`draw_one_plain_frame`]).
pub const DRAW_PROBE_TEST: &str = "lavapipe_draws_a_plain_frame";

/// One blended frame of the generated spheres: what [`DRAW_PROBE_TEST`] runs.
pub fn draw_one_plain_frame() {
    let gpu = gpu();
    let scene = translucid::scene::load("spheres").expect("generated scene");
    render(&gpu, &scene, "blend", 64, 64);
}

/// A new, empty shader cache for a child process at lavapipe's vector width `width`:
/// lavapipe 22.3 keys its cache without the width, so a shared cache hands one width's
/// code to a process at another (docs/gpu.md); an empty one makes the child compile what it
/// runs.
fn fresh_shader_cache(width: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!(
        "translucid-tests-mesa-cache-{width}-{}",
        std::process::id()
    ));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).expect("a shader cache folder");
    dir
}

/// Runs `tests` of this test binary in a child process at lavapipe's vector width `width`,
/// with a shader cache of its own.
fn run_at_width(tests: &[&str], width: &str) -> std::process::Output {
    let cache = fresh_shader_cache(width);
    let out = std::process::Command::new(std::env::current_exe().expect("the test binary"))
        .args(tests)
        .args(["--exact", "--nocapture"])
        .env("LP_NATIVE_VECTOR_WIDTH", width)
        .env("MESA_SHADER_CACHE_DIR", &cache)
        .output()
        .expect("the test binary runs");
    let _ = std::fs::remove_dir_all(&cache);
    out
}

/// Runs `tests`, tests of this test binary, again in a child process for each of lavapipe's
/// wider subgroup sizes, and fails if any fails there. Only from a process on lavapipe at its
/// own width (else it runs nothing and says so): a GPU runs the tests at its own size, and a
/// child does not start children.
///
/// On some machines lavapipe 22.3's compiler dies on any draw at those widths
/// (docs/gpu.md). Where a child dies of a signal, the binary's [`DRAW_PROBE_TEST`] runs at
/// that width too: if one plain blended frame dies the same way, lavapipe cannot draw there
/// and the width is skipped, saying so; else the child's death fails the test.
pub fn rerun_at_lavapipe_subgroup_sizes(gpu: &Gpu, tests: &[&str]) {
    if !gpu.info().name.contains("llvmpipe") || std::env::var_os("LP_NATIVE_VECTOR_WIDTH").is_some()
    {
        eprintln!(
            "{} with subgroups of {}: not rerun at other sizes",
            gpu.info().name,
            gpu.info().subgroup_size
        );
        return;
    }
    for (width, lanes) in LAVAPIPE_WIDTHS {
        let out = run_at_width(tests, width);
        let stdout = String::from_utf8_lossy(&out.stdout);
        let passed = format!("{} passed; 0 failed", tests.len());
        if out.status.success() && stdout.contains(&passed) {
            continue;
        }
        let failure = format!(
            "{tests:?} with subgroups of {lanes} (LP_NATIVE_VECTOR_WIDTH={width}): {}\n{stdout}\n{}",
            out.status,
            String::from_utf8_lossy(&out.stderr)
        );
        if died_of_a_signal(&out.status) {
            let probe = run_at_width(&[DRAW_PROBE_TEST], width);
            if died_of_a_signal(&probe.status) {
                say_skipped(
                    &format!("{tests:?}"),
                    &format!("subgroups of {lanes} (LP_NATIVE_VECTOR_WIDTH={width})"),
                    &format!(
                        "lavapipe's compiler dies on one plain blended frame at that width \
                         on this machine ({}; docs/gpu.md)",
                        probe.status
                    ),
                );
                continue;
            }
        }
        panic!("{failure}");
    }
}

/// Whether a child process was killed by a signal rather than exiting.
#[cfg(unix)]
fn died_of_a_signal(status: &std::process::ExitStatus) -> bool {
    use std::os::unix::process::ExitStatusExt;
    status.signal().is_some()
}

#[cfg(not(unix))]
fn died_of_a_signal(_: &std::process::ExitStatus) -> bool {
    false
}

/// Checks where `gpu`'s live memory is (docs/gpu.md, "Memory"): no allocation the GPU's
/// pipelines read (vertices, indices, uniforms, storage, texel buffers, images) was asked in
/// host-visible memory unless it is per-frame data, written by the host for each frame
/// ([`MemoryRole::PerFrame`]: frame info, draws). Everything else host-visible is staging
/// or a readback, which only copies touch. Lavapipe's memory is all host-visible, so what
/// is checked is the memory each allocation asked for, which is what a GPU gives.
///
/// Not vacuous: each of `device_local` (names of allocations, such as the scene's vertex
/// buffer) must be live and device-local, and some per-frame buffer must be live.
/// `what` names the case in the messages.
pub fn assert_only_per_frame_data_is_host_visible(gpu: &Gpu, what: &str, device_local: &[&str]) {
    use translucid::gpu::MemoryRole;
    let live = gpu.allocations();
    let offenders: Vec<String> = live
        .iter()
        .filter(|a| a.read_by_pipelines() && a.host_visible() && a.role != MemoryRole::PerFrame)
        .map(|a| {
            format!(
                "{} ({} bytes, {:?}, {:?})",
                a.name, a.bytes, a.location, a.usage
            )
        })
        .collect();
    assert!(
        offenders.is_empty(),
        "{what}: the pipelines read {} host-visible allocation(s) that are not per-frame \
         data:\n  {}",
        offenders.len(),
        offenders.join("\n  ")
    );
    for name in device_local {
        assert!(
            live.iter()
                .any(|a| a.name == *name && a.read_by_pipelines() && !a.host_visible()),
            "{what}: no device-local allocation named {name:?} is live (live: {:?})",
            live.iter().map(|a| &a.name).collect::<Vec<_>>()
        );
    }
    assert!(
        live.iter()
            .any(|a| a.role == MemoryRole::PerFrame && a.host_visible() && a.read_by_pipelines()),
        "{what}: no per-frame allocation is live, so the check above saw no frame's data"
    );
}

/// The live staging allocations of `gpu` (host-visible data on its way into device-local
/// memory), as (name, bytes).
pub fn staging_allocations(gpu: &Gpu) -> Vec<(String, u64)> {
    gpu.allocations()
        .into_iter()
        .filter(|a| a.role == translucid::gpu::MemoryRole::Staging)
        .map(|a| (a.name, a.bytes))
        .collect()
}
