//! `linked_list`, the exact method engines ship today (per-pixel lists of fragments, sorted
//! and composited in a resolve pass): against the CPU reference while its node pool holds
//! every fragment, and its tail past a budget fixed too small.

use glam::Vec3;
use translucid::gpu::Gpu;
use translucid::methods::{MethodKind, MethodOptions};
use translucid::metrics;
use translucid::renderer::{Frame, Renderer};
use translucid::scene::{self, Scene};
use translucid_tests::{
    assert_every_pixel_matches, assert_one_depth_order, assert_within_the_drivers_rasterization,
    asset, gpu,
};

const WIDTH: u32 = 160;
const HEIGHT: u32 = 120;

/// Every pixel within 2/255 of the reference, over lists up to dozens deep (spheres, boxes,
/// 60-deep particles), coloured transmittance, crossing planes and the glass vase: the
/// fragments' order depth is the reference's. (Ordered by the driver's depth, planes,
/// particles and the vase were each off on a few pixels.)
#[test]
fn linked_list_matches_the_reference_on_every_pixel() {
    let vase = asset("GlassVaseFlowers/GlassVaseFlowers.glb");
    assert_every_pixel_matches(
        &gpu(),
        "linked_list",
        &[
            "layers",
            "spheres",
            "boxes",
            "polychrome",
            "planes",
            "particles",
            vase.to_str().expect("utf-8 path"),
        ],
        (WIDTH, HEIGHT),
    );
}

/// Hair and every sampler mode: the driver decides these fragments' coverage (its tie rule
/// where an edge runs through a pixel centre, on the hair's thin ribbons) and their texture
/// level of detail (from 2x2 differences), not the shared fixed-point rules the reference and
/// `exact` follow. `textured` is held to what blend's test allows for its sampler (at
/// 480x270, 0.25 % of the pixels; 219 are, the same as blend's); the hairball had 2 such
/// pixels when set. Every other pixel is within 2/255.
#[test]
fn linked_list_matches_the_reference_but_where_the_driver_rasterizes() {
    assert_within_the_drivers_rasterization(
        &gpu(),
        "linked_list",
        &[
            ("hairball", 4, (WIDTH, HEIGHT)),
            ("textured", 480 * 270 / 400, (480, 270)),
        ],
    );
}

/// Surfaces at one depth up to rounding composite in the reference's order: 40 quads turned
/// within one plane, and the spheres in frames one to three pixels wide, whose columns run
/// down the seam where two mirror-image spheres meet. Ordered by the driver's depth,
/// linked_list was 108/255 off on 43 % of the quads' pixels and 46/255 on a quarter of the
/// column; its fragments now take the reference's order depth (`scene/ordered.geom`). Where an
/// edge runs through a pixel centre the driver's tie rule may still take another triangle:
/// 1 pixel of the 3x2048 frame when set (at most 0.05 % of a frame is allowed, as
/// `conformance` allows the driver methods).
#[test]
fn surfaces_at_one_depth_composite_in_the_references_order() {
    assert_one_depth_order(&gpu(), "linked_list");
}

/// A frame of `scene` with `options`, its opaque layer read back.
fn frame_with(gpu: &Gpu, scene: &Scene, options: &MethodOptions) -> Frame {
    Renderer::with_options(gpu, scene, MethodKind::LinkedList, WIDTH, HEIGHT, options)
        .and_then(|mut r| r.render(true))
        .expect("frame")
}

fn with_budget(budget: Option<u64>) -> MethodOptions {
    let mut options = MethodOptions::default();
    options.linked_list.node_budget = budget;
    options
}

/// A pool fixed too small: the fragments past it are blended unsorted under the sorted ones
/// and counted, the frame is not rendered again, and nothing is garbage; a pool that holds
/// them all is exact, and budgets of 0 or past what the pool can bind are refused.
#[test]
fn past_a_fixed_budget_the_tail_is_blended_and_counted() {
    let gpu = gpu();
    let scene = scene::load("spheres").expect("generated scene");
    let frame = |budget: Option<u64>| frame_with(&gpu, &scene, &with_budget(budget));
    let whole = frame(None);
    assert_eq!(whole.tail_fragments, 0);
    let fragments = whole.fragments;
    assert!(fragments > 1000, "{fragments} fragments");

    let exact_budget = frame(Some(fragments));
    assert_eq!(exact_budget.tail_fragments, 0);
    let opaque = exact_budget.opaque.as_ref().expect("opaque layer");
    let reference = translucid::reference::render(&scene, opaque).expect("reference");
    let m = metrics::compare(&exact_budget.image, &reference).expect("same size");
    assert!(m.max_error <= 2.0 / 255.0, "{:.1}/255", m.max_error * 255.0);

    let budget = fragments / 3;
    let short = frame(Some(budget));
    assert_eq!(short.fragments, fragments);
    assert_eq!(short.tail_fragments, fragments - budget);
    assert_eq!(short.rerenders, 0, "a fixed budget is not grown");
    let m = metrics::compare(&short.image, &reference).expect("same size");
    assert!(m.pixels_over > 0, "a third of the pool changed nothing");
    // Blending the tail unsorted is still blending: no pixel leaves the range of the scene's
    // colours.
    let brightest = reference
        .pixels
        .iter()
        .chain(&opaque.to_image().pixels)
        .map(|p| p.truncate().max_element())
        .fold(0.0f32, f32::max);
    for p in &short.image.pixels {
        let rgb: Vec3 = p.truncate();
        assert!(
            rgb.is_finite() && rgb.min_element() >= 0.0 && rgb.max_element() <= brightest * 1.5,
            "{rgb}"
        );
    }

    for bad in [0, u64::MAX] {
        let err = Renderer::with_options(
            &gpu,
            &scene,
            MethodKind::LinkedList,
            WIDTH,
            HEIGHT,
            &with_budget(Some(bad)),
        )
        .err()
        .unwrap_or_else(|| panic!("a budget of {bad} was taken"));
        assert!(err.to_string().contains("linked_list"), "{err}");
    }
}

/// The pool reached through its texel view, as pools past one storage binding are, forced on
/// small frames: the same picture as through the storage binding, bit for bit, on lists
/// dozens deep, crossing hair and textured surfaces.
#[test]
fn the_pool_through_its_texel_view_draws_what_its_storage_binding_draws() {
    let gpu = gpu();
    for name in ["spheres", "hairball", "particles", "textured"] {
        let scene = scene::load(name).expect("generated scene");
        let frame = |nodes_as_texels: bool| {
            let mut options = MethodOptions::default();
            options.linked_list.nodes_as_texels = nodes_as_texels;
            frame_with(&gpu, &scene, &options)
        };
        let (through_texels, through_binding) = (frame(true), frame(false));
        assert_eq!(through_texels.tail_fragments, 0, "{name}");
        let m = metrics::compare(&through_texels.image, &through_binding.image).expect("size");
        assert!(
            m.max_error == 0.0,
            "{name}: {:.2}/255 off the frame through the storage binding",
            m.max_error * 255.0
        );
    }
}

/// Particles at 1280x720, 16 million fragments: a pool past one storage binding, grown to
/// hold them all, so that every pixel is the reference's but where the driver rasterizes
/// (surfaces crossing within its rounding, as above).
#[test]
fn a_pool_past_one_storage_binding_holds_every_fragment() {
    let gpu = gpu();
    let scene = scene::load("particles").expect("generated scene");
    let mut renderer =
        Renderer::new(&gpu, &scene, MethodKind::LinkedList, 1280, 720).expect("renderer");
    let frame = renderer.render(true).expect("frame");
    let binding_nodes = u64::from(gpu.info().max_storage_buffer_range) / 28;
    assert!(
        frame.fragments > binding_nodes,
        "{} fragments fit one storage binding of {binding_nodes} nodes",
        frame.fragments
    );
    assert_eq!(frame.tail_fragments, 0, "{} fragments", frame.fragments);
    let opaque = frame.opaque.as_ref().expect("opaque layer");
    let reference = translucid::reference::render(&scene, opaque).expect("reference");
    let m = metrics::compare(&frame.image, &reference).expect("same size");
    assert!(
        m.pixels_over <= 16,
        "{} pixels over 2/255 (worst {:.1}/255)",
        m.pixels_over,
        m.max_error * 255.0
    );
}
