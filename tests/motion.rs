//! Frames, not scenes: one renderer draws a sequence in which the camera circles the scene,
//! every third transparent draw moves and one mesh's vertices are rewritten, each frame held
//! to the CPU reference (wavelet to its CPU model), and a warm frame builds no pipeline and
//! allocates no GPU memory. Then
//! the projections engines use: reversed-Z, an infinite far plane, sub-pixel jitter.

use glam::{Mat4, Vec2, Vec3};
use translucid::gpu::Profile;
use translucid::image::Image;
use translucid::methods::wavelet::{model::Model, Settings, Storage, WaveletOptions};
use translucid::methods::{MethodKind, MethodOptions};
use translucid::metrics;
use translucid::renderer::{Frame, FrameShape, Renderer};
use translucid::scene::{self, motion::Orbit, Camera, Projection, Scene};
use translucid_tests::{gpu, save_failure, with_copied_assets};

const WIDTH: u32 = 96;
const HEIGHT: u32 = 64;
/// Frames after which a frame loop is warm: buffers grown, every shader variant built.
const WARM_UP: usize = 4;

/// Frame `i` of the orbit `bench --motion orbit` measures: the camera turned `i` steps
/// around the scene, every third transparent draw moved; and the first transparent draw's
/// mesh swelling and shrinking, its vertices rewritten.
fn moved(scene: &Scene, orbit: &Orbit, i: usize) -> Scene {
    let mut next = scene.clone();
    next.camera = orbit.camera(scene, i as u32);
    orbit.transparent(scene, i as u32, &mut next.transparent);
    let mesh = scene.transparent[0].mesh;
    next.meshes[mesh].positions = breathing(&scene.meshes[mesh].positions, i);
    next
}

/// `positions` scaled about their centre by a factor that changes every frame.
fn breathing(positions: &[Vec3], i: usize) -> Vec<Vec3> {
    let centre = positions.iter().copied().sum::<Vec3>() / positions.len().max(1) as f32;
    let scale = 1.0 + 0.15 * (i as f32 * 0.7).sin();
    positions
        .iter()
        .map(|&p| centre + (p - centre) * scale)
        .collect()
}

/// What `method`'s `frame` is held to, over that frame's opaque layer.
fn expected(method: &str, scene: &Scene, frame: &Frame) -> Image {
    let opaque = frame.opaque.as_ref().expect("opaque layer read back");
    match method {
        "exact" | "linked_list" | "depth_peeling" => translucid::reference::render(scene, opaque),
        "wavelet" => {
            // The default settings, on the storage the device's profile picked.
            let options = WaveletOptions {
                storage: Some(
                    frame
                        .wavelet_storage
                        .expect("a wavelet frame names its storage"),
                ),
                ..WaveletOptions::default()
            };
            let settings = Settings::from_options(&options, Profile::CpuDriver).expect("defaults");
            Model::new(settings, scene, opaque.width, opaque.height).render(scene, opaque)
        }
        _ => translucid::reference::render_in_submission_order(scene, opaque),
    }
    .expect("CPU image")
}

/// `frame` against the same frame from a renderer made for it alone (on `gpu`), within
/// 0.01/255: what a renderer's earlier frames left behind changes nothing.
fn check_against_alone(
    name: &str,
    gpu: &translucid::gpu::Gpu,
    (scene, kind): (&Scene, MethodKind),
    frame: &Frame,
) {
    let (width, height) = (frame.image.width, frame.image.height);
    let alone = Renderer::new(gpu, scene, kind, width, height)
        .and_then(|mut r| r.render(false))
        .expect("frame alone");
    let m = metrics::compare(&frame.image, &alone.image).expect("same size");
    assert!(
        m.max_error * 255.0 <= 0.01,
        "{name}: {:.3}/255 off the same frame from a renderer made for it alone ({})",
        m.max_error * 255.0,
        save_failure(name, &frame.image, &alone.image).display()
    );
}

/// The frame against its CPU image, within 2/255 on every pixel; the exact peers the
/// driver rasterizes (linked_list, depth_peeling) may take crossing surfaces in the other
/// order on up to 4 pixels where they meet within its rounding (as in their own tests).
fn check(name: &str, method: &str, scene: &Scene, frame: &Frame) {
    let want = expected(method, scene, frame);
    let m = metrics::compare(&frame.image, &want).expect("same size");
    let driver_pixels = match method {
        "linked_list" | "depth_peeling" => 4,
        _ => 0,
    };
    if m.pixels_over > driver_pixels || (driver_pixels > 0 && m.psnr < 50.0) {
        let path = save_failure(name, &frame.image, &want);
        panic!(
            "{name}: {:.2}/255 off the CPU image on {} pixels ({})",
            m.max_error * 255.0,
            m.pixels_over,
            path.display()
        );
    }
}

fn moving_sequence(scene_name: &str, method: &str, frames: usize) {
    let gpu = gpu();
    let scene = scene::load(scene_name).expect("scene");
    let kind = method.parse().expect("a method name");
    let mut renderer = Renderer::new(&gpu, &scene, kind, WIDTH, HEIGHT).expect("renderer");
    let orbit = Orbit::new(&scene);
    let mut last = None;
    for i in 0..frames {
        let frame_scene = moved(&scene, &orbit, i);
        renderer
            .set_frame(&frame_scene.frame_input())
            .expect("set frame");
        let mesh = scene.transparent[0].mesh;
        renderer
            .update_mesh(mesh, &frame_scene.meshes[mesh].positions)
            .expect("update mesh");
        let frame = renderer.render(true).expect("frame");
        let name = format!("motion_{scene_name}_{method}_{i}");
        check(&name, method, &frame_scene, &frame);
        if i >= WARM_UP {
            assert_eq!(
                (frame.pipelines_created, frame.bytes_allocated),
                (0, 0),
                "{name}: a warm frame built pipelines or allocated GPU memory"
            );
        }
        last = Some((frame_scene, frame));
    }
    // The last frame is what a renderer made for it alone draws.
    let (frame_scene, frame) = last.expect("frames");
    let name = format!("motion_{scene_name}_{method}_last");
    check_against_alone(&name, &gpu, (&frame_scene, kind), &frame);
}

#[test]
fn exact_follows_a_moving_camera_and_moving_draws() {
    moving_sequence("spheres", "exact", 30);
}

/// The exact peers on the frame path: linked_list's pool and depth_peeling's passes, grown
/// in the first frames, follow the camera.
#[test]
fn linked_list_and_depth_peeling_follow_a_moving_camera_and_moving_draws() {
    moving_sequence("spheres", "linked_list", 16);
    moving_sequence("spheres", "depth_peeling", 16);
}

#[test]
fn exact_follows_motion_over_textured_surfaces() {
    moving_sequence("textured", "exact", 12);
}

#[test]
fn wavelet_follows_a_moving_camera_and_moving_draws() {
    moving_sequence("spheres", "wavelet", 12);
}

/// The wavelet method maps depth with the projection's near and far planes: frames whose
/// planes move every frame (as engines fit them to what is in view) are each held to the
/// model and, once warm, build nothing, in either storage.
#[test]
fn wavelet_builds_nothing_when_near_and_far_move() {
    let gpu = gpu();
    let scene = scene::load("spheres").expect("scene");
    let orbit = Orbit::new(&scene);
    for storage in [Storage::Bins, Storage::Images] {
        let options = MethodOptions {
            wavelet: WaveletOptions {
                storage: Some(storage),
                ..WaveletOptions::default()
            },
            ..MethodOptions::default()
        };
        let mut renderer =
            Renderer::with_options(&gpu, &scene, MethodKind::Wavelet, WIDTH, HEIGHT, &options)
                .expect("renderer");
        let settings = Settings::from_options(&options.wavelet, gpu.profile()).expect("settings");
        for i in 0..8u32 {
            let mut frame_scene = scene.clone();
            frame_scene.camera = orbit.camera(&scene, i);
            let Projection::Perspective { fov_y, .. } = frame_scene.camera.projection else {
                panic!("the orbit's camera has a perspective projection");
            };
            let step = i as f32;
            frame_scene.camera.projection = Projection::Perspective {
                fov_y,
                near: 0.05 + 0.03 * step,
                far: 12.0 + 4.0 * step,
            };
            renderer
                .set_frame(&frame_scene.frame_input())
                .expect("set frame");
            let frame = renderer.render(true).expect("frame");
            let name = format!("wavelet_near_far_{storage:?}_{i}");
            let opaque = frame.opaque.as_ref().expect("opaque layer read back");
            let want = Model::new(settings, &frame_scene, WIDTH, HEIGHT)
                .render(&frame_scene, opaque)
                .expect("model");
            let m = metrics::compare(&frame.image, &want).expect("same size");
            if m.max_error * 255.0 > 2.0 {
                let path = save_failure(&name, &frame.image, &want);
                panic!(
                    "{name}: {:.2}/255 off the model ({})",
                    m.max_error * 255.0,
                    path.display()
                );
            }
            if i > 0 {
                assert_eq!(
                    frame.pipelines_created, 0,
                    "{name}: new near and far planes built pipelines"
                );
            }
        }
    }
}

#[test]
fn blend_follows_a_moving_camera_and_moving_draws() {
    moving_sequence("spheres", "blend", 8);
}

/// The scene's camera with `projection` instead of its own, and `jitter`.
fn with_projection(scene: &Scene, projection: Mat4, jitter: Vec2) -> Scene {
    let mut s = scene.clone();
    s.camera = Camera {
        projection: Projection::Matrix(projection),
        jitter,
        ..scene.camera
    };
    s
}

/// Vulkan's framebuffer Y points down.
fn flip_y(mut p: Mat4) -> Mat4 {
    p.y_axis.y = -p.y_axis.y;
    p
}

#[test]
fn engine_projections_match_the_reference() {
    let gpu = gpu();
    let scene = scene::load("spheres").expect("scene");
    let Projection::Perspective { fov_y, near, far } = scene.camera.projection else {
        panic!("spheres has a perspective camera");
    };
    let aspect = WIDTH as f32 / HEIGHT as f32;
    let cases = [
        (
            "reversed_z",
            flip_y(Mat4::perspective_rh(fov_y, aspect, far, near)),
            Vec2::ZERO,
        ),
        (
            "infinite_far",
            flip_y(Mat4::perspective_infinite_rh(fov_y, aspect, near)),
            Vec2::ZERO,
        ),
        (
            "reversed_infinite_jittered",
            flip_y(Mat4::perspective_infinite_reverse_rh(fov_y, aspect, near)),
            Vec2::new(0.375, -0.25),
        ),
    ];
    for method in ["exact", "wavelet", "blend"] {
        let plain = translucid_tests::render(&gpu, &scene, method, WIDTH, HEIGHT);
        for (name, projection, jitter) in cases {
            let s = with_projection(&scene, projection, jitter);
            let frame = translucid_tests::render(&gpu, &s, method, WIDTH, HEIGHT);
            let label = format!("projection_{name}_{method}");
            check(&label, method, &s, &frame);
            // Without jitter the picture is the scene camera's, whichever way depth runs.
            if jitter == Vec2::ZERO {
                let m = metrics::compare(&frame.image, &plain.image).expect("same size");
                assert!(
                    m.max_error * 255.0 <= 2.0,
                    "{label}: {:.2}/255 off the scene camera's picture",
                    m.max_error * 255.0
                );
            }
        }
    }
}

/// Orthographic projections (clip w constant): fragments are ordered by device depth, either
/// way round, and a jittered one too; CAD and tools engines draw so.
#[test]
fn orthographic_projections_match_the_reference() {
    let gpu = gpu();
    let scene = scene::load("spheres").expect("scene");
    let Projection::Perspective { near, far, .. } = scene.camera.projection else {
        panic!("spheres has a perspective camera");
    };
    let (half_w, half_h) = (3.0 * WIDTH as f32 / HEIGHT as f32, 3.0);
    let ortho = flip_y(Mat4::orthographic_rh(
        -half_w, half_w, -half_h, half_h, near, far,
    ));
    let mut reversed = ortho;
    for column in [&mut reversed.z_axis, &mut reversed.w_axis] {
        column.z = column.w - column.z;
    }
    for method in ["exact", "wavelet", "blend"] {
        let mut pictures = Vec::new();
        for (name, projection, jitter) in [
            ("orthographic", ortho, Vec2::ZERO),
            ("reversed_orthographic", reversed, Vec2::ZERO),
            ("orthographic_jittered", ortho, Vec2::new(-0.25, 0.375)),
        ] {
            let s = with_projection(&scene, projection, jitter);
            let frame = translucid_tests::render(&gpu, &s, method, WIDTH, HEIGHT);
            let label = format!("projection_{name}_{method}");
            if method == "exact" {
                assert!(
                    frame.fragments > 1000,
                    "{label}: {} fragments",
                    frame.fragments
                );
            }
            check(&label, method, &s, &frame);
            pictures.push(frame.image);
        }
        // The helper, whose aspect follows the render size, is the same projection.
        let mut helper = scene.clone();
        helper.camera.projection = Projection::Orthographic {
            half_height: half_h,
            near,
            far,
        };
        pictures.push(translucid_tests::render(&gpu, &helper, method, WIDTH, HEIGHT).image);
        for (k, name) in [
            (1, "reversed orthographic"),
            (3, "Projection::Orthographic"),
        ] {
            let m = metrics::compare(&pictures[0], &pictures[k]).expect("same size");
            assert!(
                m.max_error * 255.0 <= 2.0,
                "{method}: {name} {:.2}/255 off the orthographic matrix's picture",
                m.max_error * 255.0
            );
        }
    }
}

/// An engine saves the pipeline cache after a run and hands it back on the next: the data
/// names this device, merges, and other data is turned away without harm.
#[test]
fn the_pipeline_cache_survives_a_restart() {
    let first = gpu();
    let scene = scene::load("spheres").expect("scene");
    Renderer::new(&first, &scene, MethodKind::Exact, WIDTH, HEIGHT)
        .and_then(|mut r| r.render(false))
        .expect("frame");
    let data = first.pipeline_cache_data().expect("cache data");
    // At least the header naming the device (lavapipe 22 keeps nothing after it).
    assert!(data.len() >= 32, "{} bytes", data.len());
    let next = gpu();
    assert!(next.merge_pipeline_cache(&data).expect("merge"));
    let mut foreign = data.clone();
    foreign[16] ^= 0xFF;
    assert!(!next.merge_pipeline_cache(&foreign).expect("foreign data"));
    assert!(!next.merge_pipeline_cache(&data[..20]).expect("cut data"));
    assert!(!next.merge_pipeline_cache(&[]).expect("no data"));
    Renderer::new(&next, &scene, MethodKind::Exact, WIDTH, HEIGHT)
        .and_then(|mut r| r.render(false))
        .expect("frame with the merged cache");
}

/// A mesh moved (`update_mesh`) from in front of the camera to through its plane: the
/// frame that draws it there knows, from the moved vertices, that it needs the near-plane
/// path, so it is right without being rendered again.
#[test]
fn a_mesh_moved_through_the_camera_plane_is_right_on_its_first_frame() {
    let gpu = gpu();
    let mut scene = translucid_tests::near_plane_scene();
    let through = scene.meshes[0].positions.clone();
    // The same quad, 20 units further away: wholly in front of the camera.
    let ahead: Vec<Vec3> = through.iter().map(|p| *p - Vec3::Z * 20.0).collect();
    scene.meshes[0].positions = ahead;
    let mut renderer =
        Renderer::new(&gpu, &scene, MethodKind::Exact, WIDTH, HEIGHT).expect("renderer");
    renderer.render(false).expect("first frame");
    renderer.update_mesh(0, &through).expect("move");
    scene.meshes[0].positions = through;
    let frame = renderer.render(true).expect("moved frame");
    check("moved_through_the_camera_plane", "exact", &scene, &frame);
    assert_eq!(frame.rerenders, 0, "{:?}", frame.stages);
}

/// A renderer made while another on the same device holds the pipelines it needs (another
/// size: a second view, or a dynamic resolution) compiles none, compute or graphics (the
/// opaque pass and blending's passes, for render passes compatible with the other's), and
/// draws right.
#[test]
fn a_renderer_takes_the_pipelines_another_holds() {
    let gpu = gpu();
    let scene = scene::load("particles").expect("scene");
    for kind in MethodKind::ALL {
        let method = kind.name();
        let mut first = Renderer::new(&gpu, &scene, kind, WIDTH, HEIGHT).expect("renderer");
        first.render(true).expect("frame");
        let before = gpu.pipelines_created();
        let (width, height) = (WIDTH + 32, HEIGHT - 16);
        let mut second = Renderer::new(&gpu, &scene, kind, width, height).expect("renderer");
        let frame = second.render(true).expect("frame");
        assert_eq!(
            gpu.pipelines_created() - before,
            0,
            "{method}: a second renderer compiled its own pipelines"
        );
        if method == "exact" || method == "wavelet" {
            check(
                &format!("shared_pipelines_{method}"),
                method,
                &scene,
                &frame,
            );
        }
    }
}

/// Assets added after a renderer's are appended to its uploads (`ResidentAssets::extended`):
/// a renderer over the grown assets draws the copies (other vertices, quads, materials and
/// textures, at other places in the same buffers) exactly as the first renderer draws the
/// originals, with every method, and `exact` and `wavelet` as their references do.
#[test]
fn assets_added_later_draw_like_the_first_ones() {
    let gpu = gpu();
    let scene = scene::load("textured").expect("scene");
    let grown = with_copied_assets(&scene);
    for kind in MethodKind::ALL {
        let method = kind.name();
        let mut first = Renderer::new(&gpu, &scene, kind, WIDTH, HEIGHT).expect("renderer");
        let before = first.render(false).expect("frame");
        let extended = first
            .resident()
            .extended(&gpu, &grown)
            .expect("extended")
            .expect("room for the copies");
        let shape = FrameShape {
            width: WIDTH,
            height: HEIGHT,
            frames_in_flight: 1,
        };
        let options = MethodOptions::default();
        let mut second = Renderer::sharing(
            &gpu,
            std::sync::Arc::new(extended),
            &grown,
            kind,
            shape,
            &options,
        )
        .expect("renderer over the grown assets");
        let frame = second.render(true).expect("frame");
        let name = format!("appended_assets_{method}");
        let m = metrics::compare(&frame.image, &before.image).expect("same size");
        assert!(
            m.max_error == 0.0,
            "{name}: {:.2}/255 off the frame over the original assets ({})",
            m.max_error * 255.0,
            save_failure(&name, &frame.image, &before.image).display()
        );
        if method == "exact" || method == "wavelet" {
            check(&name, method, &grown, &frame);
        }
    }
}

/// One renderer, made for the largest frame, draws smaller ones as an engine's dynamic
/// resolution asks, with every method: each size (other aspect ratios, a single pixel) as a
/// renderer made for it alone draws it, `exact` and `wavelet` also as their references do,
/// while the camera and draws move; once the frames at the largest size are warm, nothing
/// is built or allocated for the others. A size past the largest is refused, and the
/// renderer keeps its size.
#[test]
fn a_renderer_draws_every_size_up_to_its_largest() {
    let gpu = gpu();
    // The renderers of one size each, on a device of their own: what they allocate is not
    // the frames'.
    let other_gpu = translucid_tests::gpu();
    let scene = scene::load("textured").expect("scene");
    let orbit = Orbit::new(&scene);
    let warm = [(WIDTH, HEIGHT); WARM_UP];
    let sizes = [(72, 40), (33, 61), (WIDTH, 20), (1, 1), (WIDTH, HEIGHT)];
    for kind in MethodKind::ALL {
        let method = kind.name();
        let mut renderer = Renderer::new(&gpu, &scene, kind, WIDTH, HEIGHT).expect("renderer");
        for (i, &(width, height)) in warm.iter().chain(&sizes).enumerate() {
            let mut frame_scene = scene.clone();
            frame_scene.camera = orbit.camera(&scene, i as u32);
            orbit.transparent(&scene, i as u32, &mut frame_scene.transparent);
            renderer
                .set_frame(&frame_scene.frame_input())
                .expect("set frame");
            renderer.set_size(width, height).expect("a size within");
            let frame = renderer.render(true).expect("frame");
            let name = format!("sizes_{method}_{i}_{width}x{height}");
            assert_eq!((frame.image.width, frame.image.height), (width, height));
            if i >= WARM_UP {
                assert_eq!(
                    (frame.pipelines_created, frame.bytes_allocated),
                    (0, 0),
                    "{name}: a new size built pipelines or allocated GPU memory"
                );
            }
            check_against_alone(&name, &other_gpu, (&frame_scene, kind), &frame);
            if method == "exact" || method == "wavelet" {
                check(&name, method, &frame_scene, &frame);
            }
        }
        let err = renderer
            .set_size(WIDTH + 1, HEIGHT)
            .expect_err("a size past the largest");
        assert!(
            err.to_string().contains(&format!("up to {WIDTH}x{HEIGHT}")),
            "{err}"
        );
        assert_eq!(renderer.size(), (WIDTH, HEIGHT));
    }
}
