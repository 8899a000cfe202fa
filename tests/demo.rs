//! The demo picture is right: a real scene's transparent layer, drawn by the default method
//! (exact), over its opaque layer.

use translucid_tests::{asset, gpu, render};

#[test]
fn demo_scene_shows_its_transparent_layer() {
    let gpu = gpu();
    let scene = translucid::scene::load(
        asset("GlassVaseFlowers/GlassVaseFlowers.glb")
            .to_str()
            .expect("utf-8 path"),
    )
    .expect("the vendored demo scene loads");
    assert!(!scene.transparent.is_empty() && !scene.opaque.is_empty());
    let frame = render(&gpu, &scene, "exact", 320, 180);
    let opaque = frame.opaque.expect("opaque layer").to_image();

    let first = frame.image.pixels[0];
    let varied = frame
        .image
        .pixels
        .iter()
        .filter(|p| (**p - first).abs().max_element() > 4.0 / 255.0)
        .count();
    assert!(
        varied > frame.image.pixels.len() / 20,
        "the demo picture is (nearly) blank"
    );

    let changed = frame
        .image
        .pixels
        .iter()
        .zip(&opaque.pixels)
        .filter(|(a, b)| (**a - **b).abs().max_element() > 2.0 / 255.0)
        .count();
    assert!(
        changed > frame.image.pixels.len() / 100,
        "only {changed} pixels differ from the opaque layer: the transparent layer is missing"
    );
}
