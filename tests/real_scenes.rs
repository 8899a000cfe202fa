//! Real scenes with textures on their transparent surfaces, end to end, each method against
//! the CPU model of its own math over the frame's opaque layer:
//!
//! - `exact` against the reference ([`reference::render`]): every pixel within 2/255;
//! - `wavelet` in each storage (the bins, and the coefficient images, whose graphics passes
//!   take the reference's fragments from the driver), default options otherwise, against its
//!   CPU model: every pixel within 2/255;
//! - `blend` against the reference's fragments composited in submission order
//!   ([`reference::render_in_submission_order`]): a bounded share of pixels over 2/255 and a
//!   PSNR floor (see [`BLEND_SHARE`]).
//!
//! First the three vendored textured scenes (always), then every glTF file of the shared scene
//! collection, `../shared/scenes` beside the project, when it is there (the sweeps say on the
//! terminal that they skipped when it is not). The compute methods once sampled every
//! textured fragment at UV (0, 0) (the host never set `DRAW_HAS_UVS`) and no test saw it:
//! these scenes show textures through their transparent surfaces.

use std::path::{Path, PathBuf};
use std::time::Instant;
use translucid::gpu::{Gpu, Profile};
use translucid::methods::bins::features::DeclaredContent;
use translucid::methods::wavelet::{model::Model, Settings, Storage, WaveletOptions};
use translucid::methods::MethodOptions;
use translucid::metrics::{self, Metrics};
use translucid::reference;
use translucid::renderer::{Frame, Renderer};
use translucid::scene::{self, Scene};
use translucid::{Image, OpaqueLayer};
use translucid_tests::{asset, gpu, save_failure, say_no_shared_scenes, shared_scenes};

/// The size the issue measured at. The whole file (three vendored scenes and 23 shared files,
/// three methods each) took 56 s in `cargo test` on 2 cores with lavapipe when it was set.
const SIZE: (u32, u32) = (480, 270);

const TOLERANCE: f32 = 2.0 / 255.0;

/// Share of pixels `blend` may have over 2/255 off its model, and its PSNR floor. The model
/// has the reference's coverage and shading; the GPU's differs in two ways that no blending
/// order explains:
///
/// - lavapipe's rasterizer covers some samples on shared edges differently from the
///   reference's fixed-point rules, so a pixel gains or loses a fragment: a lone pixel of a
///   deep stack may be far off (stanford_dragon_100k_blend: one pixel at 19.1/255);
/// - hardware texture level of detail comes from 2×2 finite differences, the reference's from
///   analytic derivatives, so a fine, high-contrast texture at a minified level differs a
///   little (ClearCoatTest's logo: 26 of 129 600 pixels, up to 6.1/255).
///
/// Measured at 480×270 when set: worst share 0.0201 % (ClearCoatTest), then 0.0093 %
/// (TransmissionTest), 0.0046 % (GlassHurricaneCandleHolder); lowest PSNR 72.08 dB
/// (TransmissionTest), then 72.87 dB (ClearCoatTest), 73.19 dB (stanford_dragon_100k_blend).
/// Against the depth-sorted reference instead, blend is off on up to 7.5 % of the pixels, at
/// 40 dB (spot_blend, stanford_bunny_blend), and exact with UVs dropped was off on 0.9–14 % of
/// the vendored scenes' pixels, at 30–43 dB: both far outside these bounds.
const BLEND_SHARE: f64 = 0.00025;
const BLEND_PSNR: f32 = 71.0;

/// Textured transparent surfaces, vendored under assets/scenes (see its README).
const VENDORED: [&str; 3] = [
    "spot/spot_blend.gltf",
    "AlphaBlendModeTest/AlphaBlendModeTest.glb",
    "GlassBrokenWindow/GlassBrokenWindow.glb",
];

/// Pixels that a vendored scene's transparent textures must change (over 2/255) in the
/// reference, against the same scene with those textures taken off: the scenes are here to
/// show textures. Measured when set: spot_blend 11 324, AlphaBlendModeTest 1 171,
/// GlassBrokenWindow 4 184.
const MIN_TEXTURED_PIXELS: u64 = 1000;

#[derive(Clone, Copy, Debug)]
enum Method {
    Exact,
    /// Exact with every content declared (`Context::prepare`): its shaders' widest variants,
    /// which every frame of a declared loop draws with.
    ExactDeclaringAll,
    /// Exact in a prepared loop that declared nothing: every frame with content is past the
    /// declaration and draws with the superset variant.
    ExactPastTheDeclaration,
    /// The wavelet method with its coefficients in this storage (named, so that the test
    /// covers both whatever the device's profile picks).
    Wavelet(Storage),
    Blend,
}

const METHODS: [Method; 5] = [
    Method::Exact,
    Method::ExactPastTheDeclaration,
    Method::Wavelet(Storage::Bins),
    Method::Wavelet(Storage::Images),
    Method::Blend,
];

impl Method {
    fn name(self) -> &'static str {
        match self {
            Method::Exact | Method::ExactDeclaringAll | Method::ExactPastTheDeclaration => "exact",
            Method::Wavelet(_) => "wavelet",
            Method::Blend => "blend",
        }
    }

    /// The method and, for wavelet, its storage, for messages and file names.
    fn label(self) -> String {
        match self {
            Method::Wavelet(storage) => format!("wavelet {}", storage.name()),
            Method::ExactDeclaringAll => "exact declaring all content".into(),
            Method::ExactPastTheDeclaration => "exact past the declaration".into(),
            _ => self.name().into(),
        }
    }

    /// The options it runs with: the defaults, wavelet's storage, and the declaration.
    fn options(self) -> MethodOptions {
        let mut options = MethodOptions::default();
        match self {
            Method::Wavelet(storage) => options.wavelet.storage = Some(storage),
            Method::ExactDeclaringAll => options.bins.declared = DeclaredContent::ALL,
            Method::ExactPastTheDeclaration => options.bins.prepared = true,
            _ => {}
        }
        options
    }

    /// What the method's `frame` is held to, over that frame's opaque layer.
    fn model(self, scene: &Scene, frame: &Frame) -> translucid::Result<Image> {
        let opaque = frame.opaque.as_ref().expect("opaque layer read back");
        match self {
            Method::Exact | Method::ExactDeclaringAll | Method::ExactPastTheDeclaration => {
                reference::render(scene, opaque)
            }
            // The storage the frame ran on (the bins fall back to the images for a row too
            // crowded for them).
            Method::Wavelet(storage) => Model::new(
                Settings {
                    storage: frame.wavelet_storage.unwrap_or(storage),
                    ..Settings::from_options(&WaveletOptions::default(), Profile::CpuDriver)?
                },
                scene,
                opaque.width,
                opaque.height,
            )
            .render(scene, opaque),
            Method::Blend => reference::render_in_submission_order(scene, opaque),
        }
    }

    /// Why `m` fails the method's bound, if it does.
    fn judge(self, m: &Metrics) -> Option<String> {
        let ok = match self {
            Method::Exact
            | Method::ExactDeclaringAll
            | Method::ExactPastTheDeclaration
            | Method::Wavelet(_) => m.max_error <= TOLERANCE,
            // NaN fails both.
            Method::Blend => m.share_over <= BLEND_SHARE && m.psnr >= BLEND_PSNR,
        };
        (!ok).then(|| match self {
            Method::Exact
            | Method::ExactDeclaringAll
            | Method::ExactPastTheDeclaration
            | Method::Wavelet(_) => {
                format!("bound: every pixel within {}/255", TOLERANCE * 255.0)
            }
            Method::Blend => format!(
                "bound: at most {:.3} % of pixels over 2/255 and at least {BLEND_PSNR} dB",
                BLEND_SHARE * 100.0
            ),
        })
    }
}

/// Two frames of one renderer with the method's options ([`Method::options`]), their opaque
/// layers read back: the second may run setup without its occlusion cull (left out after a
/// frame where it dropped little).
fn frames(gpu: &Gpu, scene: &Scene, method: Method) -> translucid::Result<[Frame; 2]> {
    let mut renderer = Renderer::with_options(
        gpu,
        scene,
        method.name().parse()?,
        SIZE.0,
        SIZE.1,
        &method.options(),
    )?;
    Ok([renderer.render(true)?, renderer.render(true)?])
}

/// Renders `scene` with `method` (two frames: [`frames`]), compares each with the method's
/// model and prints the numbers. `Err` says why it fails, with the numbers and where the
/// pictures are; `Ok` carries the first frame.
fn check(gpu: &Gpu, scene: &Scene, label: &str, method: Method) -> Result<Frame, String> {
    let fail = |e: translucid::Error| format!("{label}: {}: {e}", method.label());
    let started = Instant::now();
    let [first, second] = frames(gpu, scene, method).map_err(fail)?;
    check_frame(
        &second,
        scene,
        &format!("{label} (second frame)"),
        method,
        started,
    )?;
    check_frame(&first, scene, label, method, started)?;
    Ok(first)
}

/// One frame of [`check`].
fn check_frame(
    frame: &Frame,
    scene: &Scene,
    label: &str,
    method: Method,
    started: Instant,
) -> Result<(), String> {
    let fail = |e: translucid::Error| format!("{label}: {}: {e}", method.label());
    let expected = method.model(scene, frame).map_err(fail)?;
    let m = metrics::compare(&frame.image, &expected).expect("same size");
    let numbers = format!(
        "{label}: {} off its model by at most {:.2}/255, {} pixels over 2/255 ({:.4} %), \
         {:.2} dB",
        method.label(),
        m.max_error * 255.0,
        m.pixels_over,
        m.share_over * 100.0,
        m.psnr
    );
    eprintln!("{numbers} ({:.1} s)", started.elapsed().as_secs_f32());
    match method.judge(&m) {
        None => Ok(()),
        Some(bound) => {
            let name = format!(
                "real_{}_{}",
                method.label().replace(' ', "_"),
                label.replace(['/', '\\', '.'], "_")
            );
            let picture = save_failure(&name, &frame.image, &expected);
            Err(format!("{numbers}; {bound}; see {}", picture.display()))
        }
    }
}

fn load(path: &Path) -> translucid::Result<Scene> {
    scene::load(path.to_str().expect("utf-8 path"))
}

/// Pixels over 2/255 between the reference and the reference with the textures of the
/// transparent draws' materials taken off.
fn textured_pixels(scene: &Scene, opaque: &OpaqueLayer) -> u64 {
    let mut plain = scene.clone();
    for draw in &scene.transparent {
        plain.materials[draw.material].texture = None;
    }
    let with = reference::render(scene, opaque).expect("reference");
    let without = reference::render(&plain, opaque).expect("reference");
    metrics::compare(&with, &without)
        .expect("same size")
        .pixels_over
}

/// A vendored scene shows textures through its transparent surfaces, and every method draws
/// it within its bound.
fn check_vendored(path: &str) {
    let scene = load(&asset(path)).unwrap_or_else(|e| panic!("{path}: {e}"));
    let textured = scene.transparent.iter().any(|d| {
        scene.materials[d.material].texture.is_some() && scene.meshes[d.mesh].uvs.is_some()
    });
    assert!(textured, "{path}: no textured transparent draw with UVs");
    let gpu = gpu();
    let mut failures = Vec::new();
    for method in METHODS {
        match check(&gpu, &scene, path, method) {
            Ok(frame) if matches!(method, Method::Exact) => {
                let opaque = frame.opaque.as_ref().expect("opaque layer");
                let pixels = textured_pixels(&scene, opaque);
                eprintln!("{path}: textures change {pixels} pixels");
                if pixels < MIN_TEXTURED_PIXELS {
                    failures.push(format!(
                        "{path}: its transparent textures change only {pixels} pixels \
                         (want {MIN_TEXTURED_PIXELS})"
                    ));
                }
            }
            Ok(_) => {}
            Err(e) => failures.push(e),
        }
    }
    assert!(failures.is_empty(), "{}", failures.join("\n"));
}

#[test]
fn spot_blend_is_right_with_every_method() {
    check_vendored(VENDORED[0]);
}

#[test]
fn alpha_blend_mode_test_is_right_with_every_method() {
    check_vendored(VENDORED[1]);
}

#[test]
fn glass_broken_window_is_right_with_every_method() {
    check_vendored(VENDORED[2]);
}

/// Every `.gltf` and `.glb` file under the shared collection, sorted, as (name relative to
/// it, path); `None`, said past the harness's capture, when there is no collection (the
/// vendored scenes above check every method's bound whether it is there or not).
fn shared_files(test: &str) -> Option<Vec<(String, PathBuf)>> {
    let Some(root) = shared_scenes() else {
        say_no_shared_scenes(test, "every shared scene");
        return None;
    };
    let mut files = Vec::new();
    walk(&root, &mut files);
    files.sort();
    assert!(
        !files.is_empty(),
        "{} holds no .gltf or .glb file",
        root.display()
    );
    Some(
        files
            .into_iter()
            .map(|path| {
                let name = path.strip_prefix(&root).unwrap_or(&path);
                (name.display().to_string(), path)
            })
            .collect(),
    )
}

fn walk(folder: &Path, found: &mut Vec<PathBuf>) {
    let entries =
        std::fs::read_dir(folder).unwrap_or_else(|e| panic!("reading {}: {e}", folder.display()));
    for entry in entries {
        let path = entry.expect("folder entry").path();
        if path.is_dir() {
            walk(&path, found);
        } else if path
            .extension()
            .is_some_and(|e| e.eq_ignore_ascii_case("gltf") || e.eq_ignore_ascii_case("glb"))
        {
            found.push(path);
        }
    }
}

/// `method` on every shared scene; every failing scene is listed before the test fails.
fn sweep_shared(test: &str, method: Method) {
    let Some(files) = shared_files(test) else {
        return;
    };
    let gpu = gpu();
    let mut failures = Vec::new();
    for (name, path) in &files {
        let result = load(path)
            .map_err(|e| format!("{name}: does not load: {e}"))
            .and_then(|scene| check(&gpu, &scene, name, method));
        if let Err(e) = result {
            failures.push(e);
        }
    }
    assert!(
        failures.is_empty(),
        "{} of {} shared scenes fail with {}:\n{}",
        failures.len(),
        files.len(),
        method.label(),
        failures.join("\n")
    );
}

#[test]
fn exact_matches_reference_on_shared_scenes() {
    sweep_shared("exact_matches_reference_on_shared_scenes", Method::Exact);
}

/// The declared loop's widest shaders draw every shared scene as the reference does: a
/// variant that covers content a frame lacks changes none of its pixels.
#[test]
fn exact_declaring_all_content_matches_reference_on_shared_scenes() {
    sweep_shared(
        "exact_declaring_all_content_matches_reference_on_shared_scenes",
        Method::ExactDeclaringAll,
    );
}

#[test]
fn wavelet_matches_its_model_on_shared_scenes() {
    sweep_shared(
        "wavelet_matches_its_model_on_shared_scenes",
        Method::Wavelet(Storage::Bins),
    );
}

/// The coefficient images, held to the same bound as the bins: before their graphics passes
/// took the reference's fragments (snapped vertices, its level of detail and order depth), 5
/// of the 23 shared scenes were up to 14.9/255 off the model (stanford_dragon_100k_blend).
#[test]
fn wavelet_images_match_their_model_on_shared_scenes() {
    sweep_shared(
        "wavelet_images_match_their_model_on_shared_scenes",
        Method::Wavelet(Storage::Images),
    );
}

#[test]
fn blend_matches_submission_order_on_shared_scenes() {
    sweep_shared(
        "blend_matches_submission_order_on_shared_scenes",
        Method::Blend,
    );
}
