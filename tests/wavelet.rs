//! The approximate methods, `wavelet` and `wboit`: the GPU against a CPU model of the same
//! math (within 2/255), and against the exact reference (a PSNR floor per scene, recorded
//! with the value measured when it was set; never lower one silently).

use glam::Vec3;
use translucid::gpu::Gpu;
use translucid::methods::bins::features::DeclaredContent;
use translucid::methods::wavelet::{model::Model, Precision, Settings, Storage, WaveletOptions};
use translucid::methods::{wboit, MethodKind, MethodOptions};
use translucid::metrics::{self, Metrics};
use translucid::renderer::{Frame, Renderer};
use translucid::scene::{self, Material, Scene, Texture};
use translucid::Image;
use translucid_tests::{asset, gpu, save_failure, stack_scene, tinted};

const TOLERANCE: f32 = 2.0 / 255.0;
/// Not a multiple of anything.
const SIZE: (u32, u32) = (213, 131);

fn render(gpu: &Gpu, scene: &Scene, method: &str, options: &MethodOptions) -> Frame {
    let kind = method.parse().expect("a method name");
    Renderer::with_options(gpu, scene, kind, SIZE.0, SIZE.1, options)
        .and_then(|mut r| r.render(true))
        .unwrap_or_else(|e| panic!("{method} on {}: {e}", scene.name))
}

fn compare(label: &str, got: &Image, expected: &Image) -> Metrics {
    let m = metrics::compare(got, expected).expect("same size");
    if m.max_error > TOLERANCE {
        save_failure(label, got, expected);
    }
    m
}

/// The coefficient-image variant.
fn wavelet_options(rank: u32, noise: f32, precision: Precision) -> MethodOptions {
    MethodOptions {
        wavelet: WaveletOptions {
            rank: Some(rank),
            noise,
            precision,
            storage: Some(Storage::Images),
        },
        ..MethodOptions::default()
    }
}

/// Every pixel within 2/255 of the CPU model. Both wavelet storages and wboit are held to it
/// on every scene, deep ones included: the bins rasterize by the reference's rules, and the
/// graphics passes hand the driver the reference's snapped vertices (`mesh_vertex.glsl`), so
/// that it covers the same samples. (Before, lavapipe snapped some vertices a sub-pixel away,
/// and particles had 2 of 27 903 pixels at 3.7/255 in both methods: a share of the pixels
/// was allowed there.)
fn assert_matches(label: &str, m: &Metrics) {
    assert!(
        m.max_error <= TOLERANCE,
        "{label}: GPU off its CPU model by {:.1}/255 on {} pixels ({:.3} %); see \
         target/test-failures/{label}.png",
        m.max_error * 255.0,
        m.pixels_over,
        m.share_over * 100.0
    );
}

/// The GPU's wavelet image against the CPU model of the same passes over the reference's
/// fragments.
fn check_wavelet_model(gpu: &Gpu, scene: &Scene, options: &MethodOptions) {
    let frame = render(gpu, scene, "wavelet", options);
    let opaque = frame.opaque.as_ref().expect("opaque layer");
    let settings = Settings::from_options(&options.wavelet, gpu.profile()).expect("valid settings");
    let expected = Model::new(settings, scene, opaque.width, opaque.height)
        .render(scene, opaque)
        .expect("model");
    let label = format!(
        "wavelet_model_{}_rank{}_{:?}_{:?}_noise{}",
        scene.name, settings.rank, settings.storage, settings.precision, settings.noise
    );
    let m = compare(&label, &frame.image, &expected);
    assert_matches(&label, &m);
}

#[test]
fn wavelet_matches_its_cpu_model_at_every_rank() {
    let gpu = gpu();
    for name in ["spheres", "polychrome"] {
        let scene = scene::load(name).expect("generated scene");
        for rank in 0..=3 {
            check_wavelet_model(&gpu, &scene, &wavelet_options(rank, 0.0, Precision::Half));
        }
    }
}

#[test]
fn wavelet_matches_its_cpu_model_deep_in_single_precision_and_with_noise() {
    let gpu = gpu();
    let scene = scene::load("particles").expect("generated scene");
    check_wavelet_model(&gpu, &scene, &wavelet_options(3, 0.0, Precision::Single));
    check_wavelet_model(&gpu, &scene, &wavelet_options(2, 1.0, Precision::Half));
    check_wavelet_model(&gpu, &scene, &wavelet_options(3, 0.0, Precision::Half));
}

/// Under an orthographic camera (clip w constant) both variants take device depth as the
/// depth they map, and match the model on every pixel. A sphere's pole falls on a pixel
/// centre here, where a front and a back triangle meet at one depth: the images once took the
/// driver's depth, a few ulps apart for the two, and spread them over the whole cell range
/// where the model has them in one cell (3.2/255); they now take the reference's own.
#[test]
fn wavelet_matches_its_cpu_model_under_an_orthographic_camera() {
    let gpu = gpu();
    let mut scene = scene::load("spheres").expect("generated scene");
    let mut ortho = glam::Mat4::orthographic_rh(-4.0, 4.0, -3.0, 3.0, 0.5, 30.0);
    ortho.y_axis.y = -ortho.y_axis.y;
    scene.camera.projection = scene::Projection::Matrix(ortho);
    for storage in [Storage::Images, Storage::Bins] {
        let mut options = wavelet_options(3, 0.0, Precision::Single);
        options.wavelet.storage = Some(storage);
        check_wavelet_model(&gpu, &scene, &options);
    }
}

/// The bins, named: under `TRANSLUCID_PROFILE=gpu` the default storage is the images.
fn bins_options(rank: u32, noise: f32) -> MethodOptions {
    let mut options = MethodOptions::default();
    options.wavelet.storage = Some(Storage::Bins);
    options.wavelet.rank = Some(rank);
    options.wavelet.noise = noise;
    options
}

/// On the bins every pixel has the reference's fragments, so the GPU is held
/// to 2/255 everywhere, deep scenes and textures included.
#[test]
fn wavelet_in_bins_matches_its_cpu_model() {
    let gpu = gpu();
    for name in ["spheres", "polychrome"] {
        let scene = load(name);
        for rank in 0..=3 {
            check_wavelet_model(&gpu, &scene, &bins_options(rank, 0.0));
        }
    }
    for name in ["particles", "planes", "GlassVaseFlowers", "textured"] {
        check_wavelet_model(&gpu, &load(name), &bins_options(3, 0.0));
    }
    check_wavelet_model(&gpu, &load("particles"), &bins_options(2, 1.0));
}

/// Wavelet's bins with every tile shape: a tile is one subgroup's pixels, so on lavapipe
/// [`wavelet_in_bins_matches_its_cpu_model`] runs again at wider vectors (tiles of 8x2 at
/// 512 bits; exact.rs's tile test says why not wider).
#[test]
fn wavelet_in_bins_matches_its_cpu_model_with_every_tile_shape() {
    let gpu = gpu();
    let frame = render(&gpu, &load("spheres"), "wavelet", &bins_options(3, 0.0));
    translucid_tests::assert_device_tiles(&gpu, &frame);
    translucid_tests::rerun_at_lavapipe_subgroup_sizes(
        &gpu,
        &[
            "wavelet_in_bins_matches_its_cpu_model",
            "wavelet_in_bins_matches_its_cpu_model_with_every_tile_shape",
        ],
    );
}

/// Wavelet's bins with the GPU profile's variants forced on this device: the walk reads its
/// entries and records as storage buffers (`storage_walk`), textures are sampled in
/// hardware, and it is still the model's on every pixel of the deep and textured scenes.
#[test]
fn wavelet_in_bins_matches_its_cpu_model_with_the_gpu_profile() {
    let gpu = translucid_tests::gpu_with(Some(translucid::gpu::Profile::Gpu));
    let frame = render(&gpu, &load("particles"), "wavelet", &bins_options(3, 0.0));
    let shape = frame.bins.expect("the bins report their shape");
    let texels_forced = translucid::methods::bins::features::texel_walk_forced().expect("env");
    assert!(shape.branching, "{shape:?}");
    assert_eq!(shape.storage_walk, !texels_forced, "{shape:?}");
    for name in ["particles", "planes", "GlassVaseFlowers", "textured"] {
        check_wavelet_model(&gpu, &load(name), &bins_options(3, 0.0));
    }
    // Textures sampled in hardware there (docs/textures.md), unless asked otherwise.
    let textured = render(&gpu, &load("textured"), "wavelet", &bins_options(3, 0.0));
    let shape = textured.bins.expect("the bins report their shape");
    assert_eq!(
        shape.hardware_sampling,
        !gpu.info().software_sampling,
        "{shape:?}"
    );
}

/// The coefficient images on the scenes the bins are held to: deep (particles, planes) and
/// textured (the vase, the generated textured stack, whose textures are minified under
/// perspective): every pixel within 2/255. The images sample at the reference's level of
/// detail; with the hardware's own (2x2 differences of the UV) minified textures differed.
#[test]
fn wavelet_in_images_matches_its_cpu_model_on_deep_and_textured_scenes() {
    let gpu = gpu();
    for name in ["particles", "planes", "GlassVaseFlowers", "textured"] {
        check_wavelet_model(&gpu, &load(name), &wavelet_options(3, 0.0, Precision::Half));
    }
}

/// Tinted draws, in both storages: the bins' setup and the images' vertex shader each
/// multiply the tint in.
#[test]
fn wavelet_matches_its_cpu_model_with_tinted_draws() {
    let gpu = gpu();
    for name in ["spheres", "polychrome"] {
        let scene = tinted(&load(name));
        check_wavelet_model(&gpu, &scene, &bins_options(3, 0.0));
        check_wavelet_model(&gpu, &scene, &wavelet_options(3, 0.0, Precision::Half));
    }
}

/// The bins' lists overflow on the first frame and grow; the second frame is right.
#[test]
fn wavelet_in_bins_recovers_from_overflow() {
    let gpu = gpu();
    let mut options = bins_options(3, 0.0);
    options.bins.initial_bin_entries = Some(1);
    let frame = render(&gpu, &load("planes"), "wavelet", &options);
    assert!(frame.rerenders > 0, "the first frame did not overflow");
    check_wavelet_model(&gpu, &load("planes"), &options);
}

/// `layers` textured quads stacked over one spot: each row of the stack lists two triangles
/// a layer, and with textures (the software sampler's loops) the bins' three walks over more
/// than about 700 of them would pass lavapipe's loop limit.
fn textured_stack_scene(layers: u32) -> Scene {
    let texels = vec![
        [255, 200, 120, 255],
        [120, 200, 255, 255],
        [200, 255, 120, 255],
        [255; 4],
    ];
    let material = Material {
        texture: Some(0),
        ..Material::alpha(Vec3::new(0.9, 0.6, 0.3), 0.004)
    };
    Scene {
        textures: vec![Texture::new("checker", 2, 2, texels, true)],
        ..stack_scene("textured stack", layers, material)
    }
}

/// A row too crowded for the bins' walks renders with coefficient images instead: the frame
/// is rendered again, and matches the images' model.
#[test]
fn wavelet_in_bins_falls_back_to_images_for_crowded_rows() {
    let gpu = gpu();
    let scene = textured_stack_scene(800);
    let options = bins_options(3, 0.0);
    let mut renderer = Renderer::with_options(&gpu, &scene, MethodKind::Wavelet, 45, 37, &options)
        .expect("renderer");
    let frame = renderer.render(true).expect("frame");
    assert!(
        frame.rerenders >= 1,
        "the crowded frame was not rendered again"
    );
    // A renderer made for this scene's next input starts on the images.
    assert_eq!(
        renderer.learned_options(&options).wavelet.storage,
        Some(Storage::Images)
    );
    assert!(
        frame
            .stages
            .iter()
            .any(|(name, _)| *name == "wavelet resolve"),
        "the frame did not fall back to the images: {:?}",
        frame.stages
    );
    let opaque = frame.opaque.as_ref().expect("opaque layer");
    let settings = Settings::from_options(
        &WaveletOptions {
            storage: Some(Storage::Images),
            ..options.wavelet
        },
        gpu.profile(),
    )
    .expect("valid settings");
    let expected = Model::new(settings, &scene, opaque.width, opaque.height)
        .render(&scene, opaque)
        .expect("model");
    let m = compare("wavelet_crowded_fallback", &frame.image, &expected);
    assert_matches("wavelet_crowded_fallback", &m);
    // Half as many layers fit the bins.
    let shallower = render(&gpu, &textured_stack_scene(200), "wavelet", &options);
    assert!(
        !shallower
            .stages
            .iter()
            .any(|(name, _)| *name == "wavelet resolve"),
        "200 layers fell back too"
    );
}

/// Where deep content is declared, a frame too crowded for the bins' raster moves to the
/// coefficient images without compiling a shader: their pipelines were built with the
/// renderer.
#[test]
fn wavelet_declared_deep_moves_to_images_without_compiling() {
    let gpu = gpu();
    let mut options = bins_options(3, 0.0);
    options.bins.declared = DeclaredContent {
        textures: true,
        deep: true,
        ..DeclaredContent::default()
    };
    let renderer = |layers| {
        Renderer::with_options(
            &gpu,
            &textured_stack_scene(layers),
            MethodKind::Wavelet,
            45,
            37,
            &options,
        )
        .expect("renderer")
    };
    // What every frame with these settings builds on its first render (the opaque pass), by
    // a frame that stays on the bins; the renderer lives on, holding it.
    let mut shallow = renderer(200);
    shallow.render(true).expect("shallow frame");
    let mut crowded = renderer(800);
    let before = gpu.pipelines_created();
    let frame = crowded.render(true).expect("crowded frame");
    assert!(
        frame
            .stages
            .iter()
            .any(|(name, _)| *name == "wavelet resolve"),
        "the frame did not move to the images: {:?}",
        frame.stages
    );
    assert_eq!(
        gpu.pipelines_created() - before,
        0,
        "moving to the images compiled"
    );
}

/// Frames repeat bit for bit, with noise too. The images blend in submission order; the bins
/// sum in the order of their lists, which atomics choose anew each frame, so they round what
/// they sum to make the sums exact (without that, two frames of planes differed).
#[test]
fn wavelet_frames_repeat_exactly() {
    let gpu = gpu();
    let cases = [
        ("planes", wavelet_options(1, 1.0, Precision::Half)),
        ("planes", bins_options(1, 1.0)),
        ("particles", bins_options(3, 0.0)),
    ];
    for (name, options) in cases {
        let scene = load(name);
        let a = render(&gpu, &scene, "wavelet", &options);
        let b = render(&gpu, &scene, "wavelet", &options);
        assert!(
            a.image.pixels == b.image.pixels,
            "{name}: two frames differ ({:?}, noise {})",
            options.wavelet.storage,
            options.wavelet.noise
        );
    }
}

#[test]
fn wavelet_rejects_ranks_over_three() {
    let gpu = gpu();
    let scene = scene::load("spheres").expect("generated scene");
    let options = wavelet_options(4, 0.0, Precision::Half);
    let err = Renderer::with_options(&gpu, &scene, MethodKind::Wavelet, 16, 16, &options)
        .err()
        .expect("rank 4 must fail");
    assert!(err.to_string().contains("rank 4"), "unhelpful error: {err}");
}

#[test]
fn wboit_matches_its_cpu_model() {
    let gpu = gpu();
    for name in ["spheres", "polychrome", "particles"] {
        let scene = scene::load(name).expect("generated scene");
        let frame = render(&gpu, &scene, "wboit", &MethodOptions::default());
        let opaque = frame.opaque.as_ref().expect("opaque layer");
        let expected = wboit::model::render(&scene, opaque).expect("model");
        let label = format!("wboit_model_{name}");
        let m = compare(&label, &frame.image, &expected);
        assert_matches(&label, &m);
    }
}

/// (scene, method, wavelet rank, PSNR floor in dB, PSNR measured when the floor was set) at
/// 213×131 against the exact reference. Floors sit 1 dB under the measurement. "wavelet" is
/// the default variant, on the bins; "wavelet images" the coefficient images.
const FLOORS: &[(&str, &str, u32, f32, f32)] = &[
    ("spheres", "wavelet", 3, 45.2, 46.25),
    ("spheres", "wavelet", 1, 38.0, 39.00),
    ("spheres", "wavelet images", 3, 45.3, 46.27),
    ("spheres", "wavelet images", 1, 38.0, 39.03),
    ("spheres", "wboit", 0, 36.2, 37.22),
    ("particles", "wavelet", 3, 48.8, 49.86),
    ("particles", "wavelet", 1, 29.1, 30.16),
    ("particles", "wavelet images", 3, 50.5, 51.50),
    ("particles", "wavelet images", 1, 29.4, 30.44),
    ("particles", "wboit", 0, 38.7, 39.73),
    ("planes", "wavelet", 3, 48.3, 49.39),
    ("planes", "wavelet", 1, 38.5, 39.59),
    ("planes", "wavelet images", 3, 48.0, 48.95),
    ("planes", "wavelet images", 1, 38.6, 39.58),
    ("planes", "wboit", 0, 31.4, 32.36),
    ("polychrome", "wavelet", 3, 88.1, 89.12),
    ("polychrome", "wavelet images", 3, 80.9, 81.94),
    ("polychrome", "wboit", 0, 45.8, 46.81),
    ("GlassVaseFlowers", "wavelet", 3, 87.1, 88.15),
    ("GlassVaseFlowers", "wavelet images", 3, 78.7, 79.70),
    ("GlassVaseFlowers", "wboit", 0, 68.7, 69.67),
];

fn load(name: &str) -> Scene {
    if name == "GlassVaseFlowers" {
        let path = asset("GlassVaseFlowers/GlassVaseFlowers.glb");
        scene::load(path.to_str().expect("utf-8 path")).expect("vendored scene")
    } else {
        scene::load(name).expect("generated scene")
    }
}

#[test]
fn approximate_methods_stay_above_their_psnr_floors() {
    let gpu = gpu();
    let mut failures = Vec::new();
    for &(name, label, rank, floor, measured) in FLOORS {
        let scene = load(name);
        let (method, options) = match label {
            "wavelet images" => ("wavelet", wavelet_options(rank, 0.0, Precision::Half)),
            _ => (label, bins_options(rank, 0.0)),
        };
        let frame = render(&gpu, &scene, method, &options);
        let opaque = frame.opaque.as_ref().expect("opaque layer");
        let expected = translucid::reference::render(&scene, opaque).expect("reference");
        let m = metrics::compare(&frame.image, &expected).expect("same size");
        eprintln!("{name} {label} rank {rank}: {:.2} dB", m.psnr);
        if m.psnr.is_nan() || m.psnr < floor {
            save_failure(
                &format!("psnr_{name}_{}{rank}", label.replace(' ', "_")),
                &frame.image,
                &expected,
            );
            failures.push(format!(
                "{name} with {label} (rank {rank}): {:.2} dB, under its floor {floor} dB \
                 (measured {measured} dB when set)",
                m.psnr
            ));
        }
    }
    assert!(failures.is_empty(), "{}", failures.join("\n"));
}

/// One surface of alpha 1 over the opaque layer is exact at every rank, in both storages:
/// its own share of absorbance is removed, and nothing hides it. Its opacity cut once mapped
/// back onto its own depth and culled it at random (black, noisy), in the CPU model too, so
/// this compares with the exact reference.
#[test]
fn wavelet_draws_a_lone_opaque_surface_exactly() {
    let gpu = gpu();
    let scene = stack_scene("opaque", 1, Material::alpha(Vec3::new(0.9, 0.5, 0.1), 1.0));
    for rank in 0..=3 {
        for options in [
            bins_options(rank, 0.0),
            wavelet_options(rank, 0.0, Precision::Half),
        ] {
            let frame = render(&gpu, &scene, "wavelet", &options);
            let opaque = frame.opaque.as_ref().expect("opaque layer");
            let expected = translucid::reference::render(&scene, opaque).expect("reference");
            let label = format!(
                "wavelet_lone_opaque_rank{rank}_{:?}",
                options.wavelet.storage
            );
            let m = compare(&label, &frame.image, &expected);
            assert!(
                m.max_error <= TOLERANCE,
                "{label}: off the exact reference by {:.1}/255 on {} pixels; see \
                 target/test-failures/{label}.png",
                m.max_error * 255.0,
                m.pixels_over
            );
        }
    }
}

/// One plain blended frame: what the reruns at lavapipe's wider sizes run, where a rerun dies,
/// to tell lavapipe's own compiler dying on any draw there from this binary's tests failing
/// (`translucid_tests::rerun_at_lavapipe_subgroup_sizes`).
#[test]
fn lavapipe_draws_a_plain_frame() {
    translucid_tests::draw_one_plain_frame();
}
