//! The unsorted-blending baseline against the CPU reference.

use translucid::scene;
use translucid_tests::{against_reference, gpu, save_failure};

/// Where submission order is back to front and nothing interpenetrates, unsorted blending
/// is exact: every pixel within 2/255 of the reference. Sizes are not multiples of anything.
#[test]
fn blend_matches_reference_on_sorted_layers() {
    let gpu = gpu();
    let scene = scene::load("layers").expect("layers scene");
    let (m, got, expected) = against_reference(&gpu, &scene, "blend", 253, 190);
    let failure = || {
        save_failure("blend_layers", &got, &expected)
            .display()
            .to_string()
    };
    assert!(
        m.max_error <= 2.0 / 255.0,
        "blend off by {:.1}/255 on {} pixels of sorted layers; see {}",
        m.max_error * 255.0,
        m.pixels_over,
        failure()
    );
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
