//! The unsorted-blending baseline against the CPU reference.

use translucid::{metrics, reference, scene};
use translucid_tests::{against_reference, gpu, save_failure, tinted};

/// Where submission order is back to front and nothing interpenetrates, unsorted blending
/// is exact: every pixel within 2/255 of the reference. Sizes are not multiples of anything.
#[test]
fn blend_matches_reference_on_sorted_layers() {
    let gpu = gpu();
    let plain = scene::load("layers").expect("layers scene");
    // Tinted too: the vertex shader multiplies each draw's tint in.
    for scene in [plain.clone(), tinted(&plain)] {
        let (m, got, expected) = against_reference(&gpu, &scene, "blend", 253, 190);
        let failure = || {
            save_failure("blend_layers", &got, &expected)
                .display()
                .to_string()
        };
        assert!(
            m.max_error <= 2.0 / 255.0,
            "blend off by {:.1}/255 on {} pixels of {}; see {}",
            m.max_error * 255.0,
            m.pixels_over,
            scene.name,
            failure()
        );
    }
}

/// Polychrome transmittance goes through dual-source blending; sorted, it must match too.
#[test]
fn blend_matches_reference_on_sorted_polychrome_layers() {
    let gpu = gpu();
    let scene = scene::load("polychrome").expect("polychrome scene");
    let (m, got, expected) = against_reference(&gpu, &scene, "blend", 201, 149);
    assert!(
        m.max_error <= 2.0 / 255.0,
        "blend off by {:.1}/255 on polychrome layers; see {}",
        m.max_error * 255.0,
        save_failure("blend_polychrome", &got, &expected).display()
    );
}

/// On interpenetrating planes no submission order is right: blending is measurably wrong.
/// That error is why this project exists.
#[test]
fn blend_is_wrong_on_interpenetrating_planes() {
    let gpu = gpu();
    let scene = scene::load("planes").expect("planes scene");
    let (m, _, _) = against_reference(&gpu, &scene, "blend", 256, 192);
    assert!(
        m.max_error > 16.0 / 255.0 && m.share_over > 0.01,
        "blend should be visibly wrong on planes, but max error is {:.1}/255 over {:.2} % of pixels",
        m.max_error * 255.0,
        m.share_over * 100.0
    );
}

/// Blending's hardware samplers on every sampler mode (`textured`), against the reference's
/// fragments composited in submission order, as blending composites them. Hardware level of
/// detail comes from 2×2 differences, the reference's from analytic derivatives, so the rows
/// where the grazing floor's nearest-mip level changes differ (and a few pixels of the
/// floor's side edges, where lavapipe's coverage differs): those are the pixels allowed off.
/// Measured when set, at 480×270: 219 pixels (0.169 %) over 2/255, at most 12.5/255, 64.05 dB.
/// A sampler that ignored the file's wrap modes or filters is off on thousands.
#[test]
fn blend_samples_textures_as_the_reference_does() {
    const SHARE: f64 = 0.0025;
    const PSNR: f32 = 62.0;
    let gpu = gpu();
    let scene = scene::load("textured").expect("textured scene");
    let frame = translucid_tests::render(&gpu, &scene, "blend", 480, 270);
    let opaque = frame.opaque.as_ref().expect("opaque layer");
    let expected = reference::render_in_submission_order(&scene, opaque).expect("model");
    let m = metrics::compare(&frame.image, &expected).expect("same size");
    // NaN fails both.
    assert!(
        m.share_over <= SHARE && m.psnr >= PSNR,
        "blend off its model on textured by up to {:.1}/255 on {} pixels ({:.3} %), {:.2} dB; \
         see {}",
        m.max_error * 255.0,
        m.pixels_over,
        m.share_over * 100.0,
        m.psnr,
        save_failure("blend_textured", &frame.image, &expected).display()
    );
}
