//! The exact method against the CPU reference: every pixel within 2/255, on every test scene,
//! at sizes that are not multiples of the bin size, including the overflow paths.

use glam::{Mat4, Vec3, Vec4};
use translucid::methods::{MethodKind, MethodOptions};
use translucid::metrics;
use translucid::renderer::Renderer;
use translucid::scene::{self, Camera, Draw, Material, Mesh, Scene};
use translucid_tests::{
    assert_matches_reference, asset, crowded_bin, gpu, gpu_with, near_plane_scene, one_depth_stack,
    one_draw_scene, save_failure, stack_scene, tinted, with_large_texture,
};

const TOLERANCE: f32 = 2.0 / 255.0;

fn check(
    scene: &Scene,
    label: &str,
    width: u32,
    height: u32,
    options: &MethodOptions,
) -> translucid::renderer::Frame {
    check_on(&gpu(), scene, label, (width, height), options)
}

/// [`check`] on `gpu`.
fn check_on(
    gpu: &translucid::gpu::Gpu,
    scene: &Scene,
    label: &str,
    (width, height): (u32, u32),
    options: &MethodOptions,
) -> translucid::renderer::Frame {
    let mut renderer =
        Renderer::with_options(gpu, scene, MethodKind::Exact, width, height, options)
            .unwrap_or_else(|e| panic!("exact on {label}: {e}"));
    let frame = renderer
        .render(true)
        .unwrap_or_else(|e| panic!("exact on {label}: {e}"));
    let opaque = frame.opaque.as_ref().expect("opaque layer");
    let expected = translucid::reference::render(scene, opaque).expect("reference");
    let m = metrics::compare(&frame.image, &expected).expect("same size");
    assert!(
        m.max_error <= TOLERANCE,
        "exact on {label} off by {:.1}/255 on {} pixels; see {}",
        m.max_error * 255.0,
        m.pixels_over,
        save_failure(&format!("exact_{label}"), &frame.image, &expected).display()
    );
    frame
}

#[test]
fn exact_matches_reference_on_generated_scenes() {
    for name in scene::generated::NAMES {
        let scene = scene::load(name).expect("generated scene");
        check(&scene, name, 213, 131, &MethodOptions::default());
    }
}

/// Tinted draws (an engine's per-instance colour): vertex colours, flat colours, textures
/// and plain materials each multiplied by their draw's tint, as the reference does it.
#[test]
fn exact_matches_reference_with_tinted_draws() {
    for name in ["spheres", "polychrome", "particles", "textured"] {
        let plain = scene::load(name).expect("generated scene");
        let scene = tinted(&plain);
        let frame = check(&scene, &scene.name, 213, 131, &MethodOptions::default());
        // The tint shows: the untinted scene's reference differs.
        let opaque = frame.opaque.as_ref().expect("opaque layer");
        let untinted = translucid::reference::render(&plain, opaque).expect("reference");
        let m = metrics::compare(&frame.image, &untinted).expect("same size");
        assert!(
            m.max_error > 8.0 / 255.0,
            "{name}: the tint changed nothing"
        );
    }
}

/// A glTF's opaque surfaces made transparent (`--blend-alpha`: the stress load of the cost
/// sweeps), the glass vase's textured and masked ones among them, match the reference.
#[test]
fn exact_matches_reference_with_opaque_surfaces_blended() {
    let file = asset("GlassVaseFlowers/GlassVaseFlowers.glb");
    let vase = scene::load(file.to_str().expect("utf-8 path")).expect("vendored scene");
    let blended = vase.opaque_as_transparent(0.4).expect("alpha in range");
    assert!(blended.opaque.is_empty());
    assert_eq!(
        blended.transparent.len(),
        vase.opaque.len() + vase.transparent.len()
    );
    check(
        &blended,
        "vase_blended",
        160,
        120,
        &MethodOptions::default(),
    );
    for bad in [0.0, 1.5, f32::NAN] {
        assert!(vase.opaque_as_transparent(bad).is_err(), "alpha {bad}");
    }
}

#[test]
fn exact_matches_reference_on_vendored_gltf() {
    for path in [
        "GlassVaseFlowers/GlassVaseFlowers.glb",
        "AttenuationTest/AttenuationTest.glb",
        "utah_teapot/utah_teapot_blend.gltf",
    ] {
        let file = asset(path);
        let scene = scene::load(file.to_str().expect("utf-8 path")).expect("vendored scene");
        check(
            &scene,
            path.split('/').next().unwrap_or(path),
            301,
            177,
            &MethodOptions::default(),
        );
    }
}

/// Frames with deep pixels select more fragments per pass and order their bins by depth
/// slab (bin_count.comp); starting with those settings checks them on every scene, including
/// near-plane triangles (which span every slab) and the overflow path. They run with one row
/// per raster workgroup, as on GPUs whose subgroups are wider than a row.
#[test]
fn exact_matches_reference_with_the_deep_frame_settings_and_one_row_workgroups() {
    let mut deep = MethodOptions::default();
    deep.exact.assume_deep_pixels = true;
    deep.bins.assume_wide_subgroups = true;
    // The frame ran with the deep settings and rows of one workgroup each.
    let deep_shape = |frame: &translucid::renderer::Frame, label: &str| {
        let shape = frame.bins.expect("exact reports its shape");
        assert_eq!(shape.select_size, 16, "{label}: {shape:?}");
        assert!(shape.slabs >= 16, "{label}: {shape:?}");
        assert_eq!(
            shape.rows_per_workgroup, shape.tile_rows,
            "{label}: {shape:?}"
        );
    };
    for name in scene::generated::NAMES {
        let scene = scene::load(name).expect("generated scene");
        let frame = check(&scene, &format!("deep_{name}"), 213, 131, &deep);
        deep_shape(&frame, name);
    }
    let vase = asset("GlassVaseFlowers/GlassVaseFlowers.glb");
    let vase = scene::load(vase.to_str().expect("utf-8 path")).expect("vendored scene");
    deep_shape(
        &check(&vase, "deep_GlassVaseFlowers", 301, 177, &deep),
        "vase",
    );
    deep_shape(
        &check(&near_plane_scene(), "deep_near_plane", 157, 119, &deep),
        "near plane",
    );
    let stack = check(&one_depth_stack(700), "deep_stack_one_row", 45, 37, &deep);
    deep_shape(&stack, "stack");
    let mut overflowing = deep;
    overflowing.bins.initial_bin_entries = Some(1);
    let hairball = scene::load("hairball").expect("hairball");
    let frame = check(&hairball, "deep_overflow_hairball", 199, 143, &overflowing);
    assert!(frame.rerenders >= 1, "the overflow path was not taken");
}

/// The GPU profile's variants (the raster branching where its subgroup agrees), forced on
/// this device, with shallow and deep settings: right on every generated scene, the vase,
/// near-plane triangles and a stack whose rows suspend under a small loop budget. The
/// device's own profile here (lavapipe's) runs the masked variants.
#[test]
fn exact_matches_reference_with_the_gpu_profile() {
    use translucid::gpu::Profile;
    let own = check(
        &scene::load("spheres").expect("scene"),
        "own_profile",
        64,
        48,
        &MethodOptions::default(),
    );
    let expected_own = gpu().info().profile == Profile::Gpu;
    let own = own.bins.expect("exact reports its shape");
    assert_eq!(own.branching, expected_own);
    let texels_forced = translucid::methods::bins::features::texel_walk_forced().expect("env");
    assert_eq!(own.storage_walk, expected_own && !texels_forced);
    let global_forced = translucid::methods::bins::features::global_counts_forced().expect("env");
    let gpu = gpu_with(Some(Profile::Gpu));
    let mut deep = MethodOptions::default();
    deep.exact.assume_deep_pixels = true;
    let vase = asset("GlassVaseFlowers/GlassVaseFlowers.glb");
    let vase = scene::load(vase.to_str().expect("utf-8 path")).expect("vendored scene");
    for (settings, options) in [("shallow", MethodOptions::default()), ("deep", deep)] {
        let mut cases: Vec<(String, Scene, (u32, u32))> = scene::generated::NAMES
            .iter()
            .map(|&name| {
                (
                    name.to_string(),
                    scene::load(name).expect("scene"),
                    (213, 131),
                )
            })
            .collect();
        cases.push(("vase".into(), vase.clone(), (301, 177)));
        cases.push(("near_plane".into(), near_plane_scene(), (157, 119)));
        for (name, scene, size) in &cases {
            let label = format!("gpu_profile_{settings}_{name}");
            let frame = check_on(&gpu, scene, &label, *size, &options);
            let shape = frame.bins.expect("exact reports its shape");
            assert!(shape.branching, "{label}: {shape:?}");
            assert_eq!(shape.storage_walk, !texels_forced, "{label}: {shape:?}");
            // Binning tallies the entries of frames of one slab, and slices tall triangles,
            // as GPUs want.
            let tally =
                match translucid::methods::bins::features::bin_tally_bits(true, global_forced) {
                    bits if bits > 0 && shape.slabs == 1 => 1 << bits,
                    _ => 0,
                };
            assert_eq!(shape.tally_slots, tally, "{label}: {shape:?}");
            let blocks_across = size.0.div_ceil(8);
            let iterations = match shape.slabs {
                1 => translucid::methods::bins::GPU_SLICE_ITERATIONS,
                _ => translucid::methods::bins::SLICE_ITERATIONS,
            };
            let slice = (iterations / (blocks_across + 8)).max(1);
            assert_eq!(shape.rows_per_slice, slice, "{label}: {shape:?}");
        }
        let mut small_budget = options.clone();
        small_budget.bins.loop_budget = Some(4096);
        let label = format!("gpu_profile_{settings}_stack");
        let frame = check_on(&gpu, &one_depth_stack(300), &label, (45, 37), &small_budget);
        assert!(frame.suspended_rows > 0, "{label}: no row suspended");
    }
    // Rows that run to the device's own budget, which on lavapipe sits just under the
    // driver's loop limit: every loop the GPU variants add must be in the budget (a
    // correcting division's loop once ended lavapipe's rows early, 40/255 off).
    let frame = check_on(
        &gpu,
        &one_depth_stack(1200),
        "gpu_profile_device_budget_stack",
        (45, 37),
        &MethodOptions::default(),
    );
    // (A GPU's budget, 2^18, may hold these rows whole.)
    if gpu.info().loop_budget == translucid::gpu::CPU_DRIVER_LOOP_BUDGET {
        assert!(
            frame.suspended_rows > 0,
            "no row ran to the device's budget"
        );
    }
}

/// Bins are tiles of one subgroup's pixels, 8 across and 1 to 8 rows down: on lavapipe the
/// GPU profile's test above (shallow and deep frames, the vase, near-plane triangles,
/// suspended tiles) runs again at wider vectors, and this test checks that each took the
/// tiles its subgroups hold: 8x2 at 16 lanes (512 bits); at 1024 and 2048 bits lavapipe
/// reports 32 and 64 lanes but runs 16 (`gpu::subgroup_probe`), and tiles stay a row.
#[test]
fn exact_matches_reference_with_every_tile_shape() {
    let gpu = gpu();
    let scene = scene::load("spheres").expect("scene");
    let frame = check_on(&gpu, &scene, "tiles", (64, 48), &MethodOptions::default());
    translucid_tests::assert_device_tiles(&gpu, &frame);
    translucid_tests::rerun_at_lavapipe_subgroup_sizes(
        &gpu,
        &[
            "exact_matches_reference_with_the_gpu_profile",
            "exact_matches_reference_with_every_tile_shape",
        ],
    );
}

/// Rows suspend at the device's loop budget and continuation dispatches finish them. Under a
/// budget of 4096 iterations (a GPU's is 2^18, a CPU driver's 60,000), the rows of a
/// 300-layer stack run past a dispatch's budget, and the frame is still the reference's.
#[test]
fn exact_matches_reference_with_a_small_loop_budget() {
    let stack = one_depth_stack(300);
    let whole = check(
        &stack,
        "device_budget_stack",
        45,
        37,
        &MethodOptions::default(),
    );
    assert_eq!(
        whole.suspended_rows, 0,
        "the device's budget walks these rows whole"
    );
    let mut options = MethodOptions::default();
    options.bins.loop_budget = Some(4096);
    let frame = check(&stack, "small_budget_stack", 45, 37, &options);
    let shape = frame.bins.expect("exact reports its shape");
    assert_eq!(shape.loop_budget, 4096, "{shape:?}");
    assert!(
        frame.suspended_rows > 0,
        "no row ran past a dispatch's budget"
    );
}

/// Binning splits a triangle taller than a slice of rows into several invocations (setup sizes
/// the dispatch to the tallest); slices of 5 rows split nearly every triangle of these scenes,
/// large and near-plane ones included.
#[test]
fn exact_matches_reference_with_triangles_binned_in_slices() {
    let mut sliced = MethodOptions::default();
    sliced.bins.bin_rows_per_slice = Some(5);
    let five_rows = |frame: translucid::renderer::Frame| {
        let shape = frame.bins.expect("exact reports its shape");
        assert_eq!(shape.rows_per_slice, 5, "{shape:?}");
    };
    for name in ["layers", "planes", "spheres"] {
        let scene = scene::load(name).expect("generated scene");
        five_rows(check(&scene, &format!("sliced_{name}"), 213, 131, &sliced));
    }
    five_rows(check(
        &near_plane_scene(),
        "sliced_near_plane",
        157,
        119,
        &sliced,
    ));
    let mut deep = sliced;
    deep.exact.assume_deep_pixels = true;
    let particles = scene::load("particles").expect("particles");
    five_rows(check(&particles, "sliced_deep_particles", 213, 131, &deep));
}

/// Binning workgroups that tally their entries in shared memory (the GPU profile's binning:
/// bin_tally.glsl) count and place the same entries as an atomic an entry: the lists need
/// as many and every frame matches the reference. With the GPU's table, and with one of two
/// slots, where most bins find no slot and take their own atomic beside tallied ones; with
/// near-plane triangles binned in slices, and a frame whose lists pass their capacity and
/// are filled in bands. Deep frames (slabs, a lane a row) do not tally.
#[test]
fn exact_matches_reference_with_tallied_binning() {
    let mut banded = MethodOptions::default();
    banded.bins.initial_bin_entries = Some(2000);
    banded.bins.bands = Some(64);
    let mut deep = MethodOptions::default();
    deep.exact.assume_deep_pixels = true;
    let mut sliced = MethodOptions::default();
    sliced.bins.bin_rows_per_slice = Some(5);
    let cases = [
        (
            "spheres",
            scene::load("spheres").expect("spheres"),
            MethodOptions::default(),
        ),
        (
            "hairball",
            scene::load("hairball").expect("hairball"),
            banded,
        ),
        (
            "particles",
            scene::load("particles").expect("particles"),
            deep.clone(),
        ),
        ("near_plane", near_plane_scene(), sliced),
    ];
    for (name, scene, mut plain) in cases {
        plain.bins.bin_tally_bits = Some(0);
        let untallied = check(&scene, &format!("untallied_{name}"), 213, 131, &plain);
        let shape = untallied.bins.expect("exact reports its shape");
        assert_eq!(shape.tally_slots, 0, "{name}: {shape:?}");
        assert!(untallied.bin_entries > 0, "{name}: nothing binned");
        for bits in [1, translucid::methods::bins::features::GPU_TALLY_BITS] {
            let mut tallied = plain.clone();
            tallied.bins.bin_tally_bits = Some(bits);
            let label = format!("tallied_{bits}_{name}");
            let frame = check(&scene, &label, 213, 131, &tallied);
            let shape = frame.bins.expect("exact reports its shape");
            let slots = if name == "particles" { 0 } else { 1 << bits };
            assert_eq!(shape.tally_slots, slots, "{label}: {shape:?}");
            assert_eq!(frame.bin_entries, untallied.bin_entries, "{label}");
            if name == "hairball" {
                assert!(frame.bands > 1, "{label}: filled in {} band", frame.bands);
            }
        }
    }
}

/// Textures sampled in hardware (the rasters' `HARDWARE_SAMPLING` variant, the GPU profile's
/// default: docs/gpu.md) stay within the reference's tolerance on the textured scenes: the
/// generated stack (minified under perspective, every wrap mode), the vase and spot, in
/// shallow and deep frames. Forced here on lavapipe's CPU profile, whose default stays the
/// software sampler; the software sampler can be forced where the profile would sample in
/// hardware.
#[test]
fn exact_matches_reference_with_textures_sampled_in_hardware() {
    let gpu = gpu();
    let info = gpu.info();
    let vase = asset("GlassVaseFlowers/GlassVaseFlowers.glb");
    let spot = asset("spot/spot_blend.gltf");
    let scenes = [
        (
            "textured",
            scene::load("textured").expect("scene"),
            (213, 131),
        ),
        (
            "vase",
            scene::load(vase.to_str().expect("utf-8")).expect("vase"),
            (301, 177),
        ),
        (
            "spot",
            scene::load(spot.to_str().expect("utf-8")).expect("spot"),
            (213, 131),
        ),
    ];
    let mut deep = MethodOptions::default();
    deep.exact.assume_deep_pixels = true;
    for (settings, mut options) in [("shallow", MethodOptions::default()), ("deep", deep)] {
        for (name, scene, size) in &scenes {
            options.bins.hardware_sampling = Some(true);
            let label = format!("hardware_sampled_{settings}_{name}");
            let frame = check_on(&gpu, scene, &label, *size, &options);
            let shape = frame.bins.expect("exact reports its shape");
            assert!(shape.hardware_sampling, "{label}: {shape:?}");
        }
    }
    let own = check(
        &scenes[0].1,
        "own_sampling",
        64,
        48,
        &MethodOptions::default(),
    );
    let own = own.bins.expect("exact reports its shape");
    assert_eq!(
        own.hardware_sampling,
        info.profile == translucid::gpu::Profile::Gpu && !info.software_sampling,
        "{own:?}"
    );
    let mut software = MethodOptions::default();
    software.bins.hardware_sampling = Some(false);
    let frame = check_on(
        &gpu_with(Some(translucid::gpu::Profile::Gpu)),
        &scenes[0].1,
        "gpu_profile_software_sampling",
        (64, 48),
        &software,
    );
    assert!(!frame.bins.expect("shape").hardware_sampling);
}

/// One quad from x0 to x1 and from -y to y, at depth z, facing +z.
fn square(x0: f32, x1: f32, y: f32, z: f32) -> Mesh {
    Mesh::from_quads(
        "square",
        vec![
            Vec3::new(x0, -y, z),
            Vec3::new(x1, -y, z),
            Vec3::new(x1, y, z),
            Vec3::new(x0, y, z),
        ],
        vec![[0, 1, 2, 3]],
    )
}

/// Two overlapping quads whose corners differ in colour and alpha: the raster interpolates all
/// three colours of each triangle (scenes of flat-coloured quads read one).
#[test]
fn exact_interpolates_vertex_colours_that_vary_across_a_quad() {
    let quad = |z: f32, colours: [Vec4; 4]| {
        let mut mesh = square(-1.0, 1.0, 1.0, z);
        mesh.colours = Some(colours.to_vec());
        mesh
    };
    let draw = |mesh: usize| Draw {
        mesh,
        material: 0,
        transform: Mat4::from_rotation_z(0.3 * mesh as f32),
        tint: glam::Vec4::ONE,
    };
    let scene = Scene {
        name: "gradient".into(),
        meshes: vec![
            quad(
                -0.5,
                [
                    Vec4::new(1.0, 0.0, 0.0, 0.9),
                    Vec4::new(0.0, 1.0, 0.0, 0.2),
                    Vec4::new(0.0, 0.0, 1.0, 0.6),
                    Vec4::new(1.0, 1.0, 0.0, 0.4),
                ],
            ),
            quad(
                0.0,
                [
                    Vec4::new(0.0, 1.0, 1.0, 0.3),
                    Vec4::new(1.0, 0.0, 1.0, 0.8),
                    Vec4::new(0.5, 0.5, 0.5, 0.5),
                    Vec4::new(0.1, 0.9, 0.2, 0.7),
                ],
            ),
        ],
        materials: vec![Material::alpha(Vec3::ONE, 1.0)],
        transparent: vec![draw(0), draw(1)],
        camera: Camera::look_at(Vec3::new(0.0, 0.0, 3.0), Vec3::ZERO, 1.0, 0.1, 50.0),
        background: Vec3::splat(0.2),
        ..Scene::default()
    };
    check(&scene, "gradient", 123, 97, &MethodOptions::default());
}

/// An opaque wall at z = -1 hiding the left half of the view, and three transparent quads:
/// wholly behind it, straddling its edge (partly visible), and in front of it.
fn occluded_scene() -> Scene {
    let draw = |mesh: usize, material: usize| Draw {
        mesh,
        material,
        transform: Mat4::IDENTITY,
        tint: glam::Vec4::ONE,
    };
    Scene {
        name: "occluded".into(),
        meshes: vec![
            square(-10.0, 0.2, 10.0, -1.0),
            square(-2.0, -0.5, 1.0, -2.0),
            square(-1.0, 0.5, 1.0, -2.0),
            square(-1.5, 1.0, 1.0, 0.0),
        ],
        materials: vec![
            Material::default(),
            Material::alpha(Vec3::new(0.9, 0.3, 0.1), 0.6),
        ],
        opaque: vec![draw(0, 0)],
        transparent: vec![draw(1, 1), draw(2, 1), draw(3, 1)],
        camera: Camera::look_at(Vec3::new(0.0, 0.0, 3.0), Vec3::ZERO, 1.0, 0.1, 50.0),
        background: Vec3::splat(0.8),
        ..Scene::default()
    }
}

#[test]
fn exact_culls_triangles_behind_the_opaque_layer() {
    let frame = check(
        &occluded_scene(),
        "occluded",
        203,
        117,
        &MethodOptions::default(),
    );
    assert_eq!(
        frame.triangles, 4,
        "the quad behind the wall should be culled, the other two kept"
    );
}

#[test]
fn exact_matches_reference_across_the_near_plane() {
    check(
        &near_plane_scene(),
        "near_plane",
        157,
        119,
        &MethodOptions::default(),
    );
}

/// Tiny first capacities of the bin lists and of the near-plane (homogeneous) records force
/// both to overflow; the frame is rendered again with grown buffers and must still match.
/// Both capacities grew (the hairball has no near-plane triangle: its lists alone). The
/// resume lists' overflow is `exact_finishes_pixels_deeper_than_the_loop_limit`'s.
#[test]
fn exact_recovers_from_bin_list_and_near_plane_record_overflows() {
    let gpu = gpu();
    let mut options = MethodOptions::default();
    options.bins.initial_bin_entries = Some(1);
    options.bins.initial_homogeneous = Some(1);
    let cases = [
        (near_plane_scene(), "overflow_near_plane", (157, 119), true),
        (
            scene::load("hairball").expect("hairball"),
            "overflow_hairball",
            (199, 143),
            false,
        ),
    ];
    for (scene, label, (width, height), near_plane) in cases {
        let mut renderer =
            Renderer::with_options(&gpu, &scene, MethodKind::Exact, width, height, &options)
                .unwrap_or_else(|e| panic!("exact on {label}: {e}"));
        let frame = renderer
            .render(true)
            .unwrap_or_else(|e| panic!("exact on {label}: {e}"));
        assert_matches_reference(&format!("exact_{label}"), &scene, &frame);
        assert!(
            frame.rerenders >= 1,
            "{label}: the overflow path was not taken"
        );
        let learned = renderer.learned_options(&options).bins;
        assert!(
            learned.initial_bin_entries > Some(1),
            "{label}: the bin lists did not grow: {learned:?}"
        );
        if near_plane {
            assert!(
                learned.initial_homogeneous > Some(1),
                "{label}: the near-plane records did not grow: {learned:?}"
            );
        }
    }
}

/// Near-plane triangles past the most records the bins can hold are refused at once, by
/// name: 720 k of them once failed after 40 s with "still unfinished after 8 more
/// submissions", which named no limit.
#[test]
fn near_plane_triangles_past_their_limit_are_refused_by_name() {
    let gpu = gpu();
    let mut options = MethodOptions::default();
    options.bins.initial_homogeneous = Some(1);
    options.bins.most_homogeneous = Some(1);
    let mut renderer = Renderer::with_options(
        &gpu,
        &near_plane_scene(),
        MethodKind::Exact,
        64,
        48,
        &options,
    )
    .expect("renderer");
    let err = renderer
        .render(false)
        .err()
        .expect("two near-plane triangles, one record");
    let message = err.to_string();
    assert!(
        message.contains("crossing the near plane") && message.contains("at most 1"),
        "{message}"
    );
}

/// A renderer made for the next frame starts from the buffer sizes the last one grew to, so
/// that a moving camera does not overflow again every frame.
#[test]
fn exact_passes_learned_buffer_sizes_to_the_next_renderer() {
    let gpu = gpu();
    let scene = scene::load("hairball").expect("hairball");
    let mut tiny = MethodOptions::default();
    tiny.bins.initial_bin_entries = Some(1);
    let mut first =
        Renderer::with_options(&gpu, &scene, MethodKind::Exact, 199, 143, &tiny).expect("renderer");
    assert!(first.render(false).expect("frame").rerenders >= 1);
    let learned = first.learned_options(&tiny);
    assert!(learned.bins.initial_bin_entries > Some(1), "{learned:?}");
    drop(first);
    let mut next = Renderer::with_options(&gpu, &scene, MethodKind::Exact, 199, 143, &learned)
        .expect("renderer");
    assert_eq!(next.render(false).expect("frame").rerenders, 0);
}

#[test]
fn exact_finishes_pixels_deeper_than_the_loop_limit() {
    // Its rows suspend, and the frame's own continuation dispatches finish them.
    let frame = check(
        &one_depth_stack(1200),
        "deep_stack",
        45,
        37,
        &MethodOptions::default(),
    );
    assert_eq!(frame.rerenders, 0, "{:?}", frame.stages);

    // Resume lists of one row force their overflow path, which shows that rows suspend
    // (1200 layers suspend more than one). Both stacks are deep enough that a raster which
    // never suspends fails them: 700 and 600 layers had stopped running out of the loop
    // budget once the walk got cheaper, and layers at distinct depths once slabs were
    // planned from the frame's depths.
    let mut options = MethodOptions::default();
    options.bins.initial_resume_rows = Some(1);
    let frame = check(
        &one_depth_stack(1200),
        "deep_stack_small_lists",
        45,
        37,
        &options,
    );
    assert!(frame.rerenders >= 1, "the resume lists did not overflow");

    // Resume lists dispatched 3 workgroups to a row (65535 on devices), the rest in z, as
    // lists of more rows than a row of workgroups holds are: the 240 rows all suspend.
    let mut options = MethodOptions::default();
    options.bins.groups_x = Some(3);
    let stack = stack_scene(
        "deep stack",
        2000,
        Material::alpha(Vec3::new(0.9, 0.5, 0.2), 0.004),
    );
    check(&stack, "deep_stack_split_lists", 45, 37, &options);
}

/// When the host's estimate leaves the near-plane path out of the setup and raster shaders
/// and setup meets such a triangle anyway, they are rebuilt and the frame rendered again.
#[test]
fn exact_rebuilds_the_raster_shader_for_unexpected_near_plane_triangles() {
    let mut options = MethodOptions::default();
    options.bins.assume_fixed_path = true;
    let frame = check(
        &near_plane_scene(),
        "assumed_fixed_near_plane",
        157,
        119,
        &options,
    );
    // Once to rebuild; setup skipped the near-plane triangle in the first frame, so the bin
    // lists may only learn their size in the second.
    assert!(
        (1..=2).contains(&frame.rerenders),
        "the fallback should render the frame once or twice more, not {} times",
        frame.rerenders
    );
    // The rebuilt setup and raster pipelines (and the raster's continuation) are counted.
    assert!(
        frame.pipelines_created >= 2,
        "{} pipelines created",
        frame.pipelines_created
    );
}

/// In a prepared loop that did not declare near-plane triangles, the frame that finds one the
/// host missed is rendered again with the superset variant, built up front: right, and
/// building at least the two pipelines fewer that the unprepared frame builds.
#[test]
fn a_prepared_loop_renders_missed_near_plane_triangles_with_the_superset() {
    let mut options = MethodOptions::default();
    options.bins.assume_fixed_path = true;
    let unprepared = check(
        &near_plane_scene(),
        "assumed_fixed_near_plane_unprepared",
        157,
        119,
        &options,
    );
    options.bins.prepared = true;
    let prepared = check(
        &near_plane_scene(),
        "assumed_fixed_near_plane_prepared",
        157,
        119,
        &options,
    );
    assert!(prepared.rerenders >= 1, "the frame was not rendered again");
    assert!(
        prepared.pipelines_created + 2 <= unprepared.pipelines_created,
        "prepared: {} pipelines created, unprepared: {}",
        prepared.pipelines_created,
        unprepared.pipelines_created
    );
}

/// The software sampler copies only the textures transparent draws use, when a frame first
/// uses one: a large texture on an opaque draw costs exact nothing over blend; the first
/// frame whose transparent draws use it copies it, and draws it as the reference does.
#[test]
fn exact_copies_only_the_textures_transparent_draws_use() {
    const SIZE: u32 = 1024;
    // Level 0 alone.
    let texture_bytes = u64::from(SIZE * SIZE * 4);
    let (mut scene, large) = with_large_texture(&scene::load("textured").expect("scene"), SIZE);
    scene.opaque.push(large.clone());
    let first_frame = |kind| {
        let gpu = gpu();
        let mut renderer = Renderer::new(&gpu, &scene, kind, 96, 64).expect("renderer");
        renderer.render(false).expect("frame").peak_gpu_bytes
    };
    let over_blend = first_frame(MethodKind::Exact) as i64 - first_frame(MethodKind::Blend) as i64;
    assert!(
        over_blend < texture_bytes as i64 / 2,
        "exact takes {over_blend} bytes over blend: a {texture_bytes}-byte texture only an \
         opaque draw uses was copied"
    );

    let gpu = gpu();
    let mut renderer = Renderer::new(&gpu, &scene, MethodKind::Exact, 96, 64).expect("renderer");
    renderer.render(false).expect("frame");
    let mut drawn = scene.clone();
    drawn.transparent.push(large);
    renderer.set_frame(&drawn.frame_input()).expect("set frame");
    let frame = renderer.render(true).expect("frame");
    assert!(
        frame.bytes_allocated >= texture_bytes,
        "the frame that first draws the texture transparent allocated {} bytes",
        frame.bytes_allocated
    );
    assert_matches_reference("exact_large_texture_drawn_transparent", &drawn, &frame);
}

/// Texture coordinates at the largest a mesh may have ([`translucid::scene::MAX_UV`]) on a
/// 200-texel texture put the sampler's texel coordinates past 2^31 either way, where the
/// software sampler leaves its 32-bit wrap for a 64-bit one; they must wrap as the
/// reference's do. Every vertex takes the same coordinates, so that the level of detail is
/// the first (a minified level would have fewer texels and smaller coordinates), and an odd
/// one, so that a saturated or truncated coordinate picks another texel. Also where the
/// raster samples in hardware, whose float coordinates cannot resolve texels that far: the
/// software sampler takes those fragments.
#[test]
fn exact_wraps_texture_coordinates_billions_of_texels_away() {
    let (mut scene, large) = with_large_texture(&scene::load("textured").expect("scene"), 200);
    scene.transparent.push(large);
    let far = glam::Vec2::new(16_777_215.0, -16_777_215.0);
    for mesh in &mut scene.meshes {
        for uv in mesh.uvs.iter_mut().flatten() {
            *uv = far;
        }
    }
    let texels = far.x * 200.0;
    assert!(
        texels > 2f32.powi(31),
        "texel coordinates of {texels} stay within 32 bits"
    );
    for hardware in [false, true] {
        let mut options = MethodOptions::default();
        options.bins.hardware_sampling = Some(hardware);
        let label = format!("far_texture_coordinates_hardware_{hardware}");
        let frame = check(&scene, &label, 96, 64, &options);
        let shape = frame.bins.expect("exact reports its shape");
        assert_eq!(shape.hardware_sampling, hardware, "{label}: {shape:?}");
    }
}

/// A frame rendered again unchanged creates no pipeline: everything it needs was built with
/// the renderer or by the frames before.
#[test]
fn exact_creates_no_pipeline_in_a_warm_frame_and_counts_its_dispatches() {
    let gpu = gpu();
    let scene = scene::load("particles").expect("generated scene");
    let mut renderer = Renderer::new(&gpu, &scene, MethodKind::Exact, 96, 64).expect("renderer");
    // The first frames may rebuild for what they find (deeper pixels than expected); the
    // later ones none. (The near-plane test above checks that rebuilds are counted.)
    let frames: Vec<(u64, u64)> = (0..4)
        .map(|_| {
            let frame = renderer.render(false).expect("frame");
            (frame.pipelines_created, frame.dispatches)
        })
        .collect();
    assert_eq!(
        frames[2..].iter().map(|f| f.0).collect::<Vec<_>>(),
        [0, 0],
        "(pipelines created, dispatches) per frame: {frames:?}"
    );
    // The chain of compute dispatches a warm frame records is counted, the same each frame,
    // and short: a frame that fits its lists records one band and no empty ones.
    assert!(
        frames[2].1 > 0 && frames[2].1 == frames[3].1 && frames[3].1 <= 8,
        "(pipelines created, dispatches) per frame: {frames:?}"
    );
}

/// Warm frames that fit their lists with room to spare record one band. A frame whose lists
/// then pass the capacity (a stack of quads grown from a speck to the whole frame at once,
/// as after a camera cut) leaves the blocks past that band unrasterized: it is rendered
/// again, every band recorded and the lists grown, and is right. (Grown to a third of the
/// frame, tiles of two rows, which enter a triangle once for both, stayed within the room.)
#[test]
fn exact_one_band_frames_are_right_when_the_lists_outgrow_them() {
    let gpu = gpu();
    let scene = stack_scene(
        "growing stack",
        16,
        Material::alpha(Vec3::new(0.2, 0.6, 0.9), 0.3),
    );
    let mut speck = scene.clone();
    let centre = Vec3::new(0.0, 0.0, -1.0);
    speck.transparent[0].transform = Mat4::from_translation(centre)
        * Mat4::from_scale(Vec3::new(0.05, 0.05, 1.0))
        * Mat4::from_translation(-centre);
    let mut renderer = Renderer::new(&gpu, &speck, MethodKind::Exact, 96, 64).expect("renderer");
    let warm: Vec<u64> = (0..3)
        .map(|_| renderer.render(false).expect("frame").dispatches)
        .collect();
    assert!(warm[2] <= 8, "dispatches per frame: {warm:?}");
    let mut grown = scene.clone();
    grown.transparent[0].transform = Mat4::from_translation(centre)
        * Mat4::from_scale(Vec3::new(4.0, 4.0, 1.0))
        * Mat4::from_translation(-centre);
    renderer.set_frame(&grown.frame_input()).expect("set frame");
    let frame = renderer.render(true).expect("frame");
    assert_eq!(frame.rerenders, 1, "{:?}", frame.stages);
    assert!(
        frame.dispatches > warm[2],
        "{} dispatches",
        frame.dispatches
    );
    assert_matches_reference("exact_one_band_outgrown", &grown, &frame);
}

/// With the threshold on, each pixel stops as soon as its transmittance is under it, as the
/// reference's early stop does: every pixel within 2/255 of that, with fewer fragments.
#[test]
fn exact_threshold_stops_where_the_reference_stops() {
    let gpu = gpu();
    for (name, threshold) in [("particles", 0.02), ("particles", 0.3), ("spheres", 0.5)] {
        let scene = scene::load(name).expect("generated scene");
        let mut options = MethodOptions::default();
        options.exact.threshold = threshold;
        let mut with = Renderer::with_options(&gpu, &scene, MethodKind::Exact, 160, 120, &options)
            .expect("renderer");
        let early = with.render(true).expect("frame");
        let opaque = early.opaque.as_ref().expect("opaque layer");
        let expected =
            translucid::reference::render_until(&scene, opaque, threshold).expect("reference");
        let m = metrics::compare(&early.image, &expected).expect("same size");
        if m.max_error > TOLERANCE {
            save_failure(
                &format!("threshold_{name}_{threshold}"),
                &early.image,
                &expected,
            );
        }
        assert!(
            m.max_error <= TOLERANCE,
            "{name} with threshold {threshold}: {:.1}/255 off the reference's early stop",
            m.max_error * 255.0
        );
        assert!(
            early.fragments < exact_fragments(&gpu, &scene),
            "{name}: threshold {threshold} composited as many fragments"
        );
    }
}

fn exact_fragments(gpu: &translucid::gpu::Gpu, scene: &Scene) -> u64 {
    let mut r = Renderer::new(gpu, scene, MethodKind::Exact, 160, 120).expect("renderer");
    r.render(false).expect("frame").fragments
}

/// `count` screen-filling quads, one behind another, faint enough that none hides the rest.
fn full_screen_layers(count: u32) -> Scene {
    let mut positions = Vec::new();
    let mut quads = Vec::new();
    for i in 0..count {
        let z = -1.0 - i as f32 * (4.0 / count as f32);
        let first = positions.len() as u32;
        positions.extend([
            Vec3::new(-9.0, -9.0, z),
            Vec3::new(9.0, -9.0, z),
            Vec3::new(9.0, 9.0, z),
            Vec3::new(-9.0, 9.0, z),
        ]);
        quads.push([first, first + 1, first + 2, first + 3]);
    }
    one_draw_scene(
        "full-screen layers",
        Mesh::from_quads("layers", positions, quads),
        Material::alpha(Vec3::new(0.9, 0.5, 0.2), 0.001),
        Camera::look_at(Vec3::new(0.0, 0.0, 3.0), Vec3::ZERO, 0.8, 0.1, 20.0),
    )
}

/// 10,000 layers over every pixel, right, with every pixel's list walked at most twice: the
/// rows' lists, ordered into fine depth slabs, are walked about once. (With 16 slabs a pixel
/// swept its list again for every 16 fragments it composited, about 10,000 / 16 sweeps, and
/// the frame took 12x blend's time; before that, the renderer gave up after four re-renders, with
/// "buffers still overflow".) Time is `translucid bench`'s to measure (`translucid bench
/// particles --method exact --method blend` reports exact over blend, by GPU and wall time):
/// a wall-time bound here could fail on a busy machine (exact took about blend's time on this
/// scene, on lavapipe with 2 cores, when it was taken out).
#[test]
fn exact_renders_ten_thousand_full_screen_layers_in_at_most_two_sweeps() {
    let scene = full_screen_layers(10_000);
    let frame = check(
        &scene,
        "ten_thousand_layers",
        16,
        12,
        &MethodOptions::default(),
    );
    assert_eq!(frame.fragments, 16 * 12 * 10_000);
    assert!(
        (1..=2).contains(&frame.sweeps),
        "pixels swept their lists {} times",
        frame.sweeps
    );
}

/// `layers` layers over the left part of the frame, each a little wider than the last, at one
/// depth but for the last, a hair behind (so that slabs do not split them: `crowded_bin`
/// says why), behind them two full-screen layers far apart: the bunch falls in one slab and
/// its pixels need many sweeps, while the pixels beside it finish after two fragments.
fn bunched_layers(layers: u32) -> Scene {
    let mut positions = Vec::new();
    let mut quads = Vec::new();
    let mut quad = |right: f32, z: f32| {
        let first = positions.len() as u32;
        positions.extend([
            Vec3::new(-9.0, -9.0, z),
            Vec3::new(right, -9.0, z),
            Vec3::new(right, 9.0, z),
            Vec3::new(-9.0, 9.0, z),
        ]);
        quads.push([first, first + 1, first + 2, first + 3]);
    };
    for i in 0..layers {
        let z = if i + 1 == layers { -1.00001 } else { -1.0 };
        quad(-0.5 + (i % 13) as f32 * 0.05, z);
    }
    quad(9.0, -1.5);
    quad(9.0, -8.0);
    one_draw_scene(
        "bunched layers",
        Mesh::from_quads("bunch", positions, quads),
        Material::alpha(Vec3::new(1.0, 0.9, 0.8), 0.0002),
        Camera::look_at(Vec3::new(0.0, 0.0, 3.0), Vec3::ZERO, 0.8, 0.1, 20.0),
    )
}

/// Rows suspended in one sweep, resumed, and suspended again in a later one resume where the
/// later sweep stopped. (Pixels that had finished kept the first resumption point, which was
/// further down the list, and the row's took the furthest: a sixth of the bunch's fragments
/// were skipped, 21/255 off, and 43/255 on 100,000 random single-triangle draws.)
#[test]
fn exact_resumes_rows_where_their_last_sweep_stopped() {
    // One band: the continuations of further bands would finish the rows within the frame,
    // where the test cannot see how many there were.
    let mut one_band = MethodOptions::default();
    one_band.bins.bands = Some(1);
    let frame = check(&bunched_layers(6000), "bunched_layers", 16, 12, &one_band);
    assert!(
        frame
            .stages
            .iter()
            .any(|(stage, _)| *stage == "raster finished"),
        "rows were not suspended more than once: {:?}",
        frame.stages
    );
}

/// The 8x8 frame of `crowded_bin(count)` rendered with a transmittance threshold of 0.01 (and
/// `bands` recorded), checked against the reference stopped at the same threshold.
fn crowded_bin_frame(count: u32, label: &str, bands: Option<u32>) -> translucid::renderer::Frame {
    let gpu = gpu();
    let scene = crowded_bin(count);
    let threshold = 0.01;
    let mut options = MethodOptions::default();
    options.exact.threshold = threshold;
    options.bins.bands = bands;
    let mut renderer =
        Renderer::with_options(&gpu, &scene, MethodKind::Exact, 8, 8, &options).expect("renderer");
    let frame = renderer.render(true).expect("a crowded bin renders");
    let opaque = frame.opaque.as_ref().expect("opaque layer");
    let expected =
        translucid::reference::render_until(&scene, opaque, threshold).expect("reference");
    let m = metrics::compare(&frame.image, &expected).expect("same size");
    assert!(
        m.max_error <= TOLERANCE,
        "{label} off by {:.1}/255; see {}",
        m.max_error * 255.0,
        save_failure(&format!("exact_{label}"), &frame.image, &expected).display()
    );
    frame
}

/// 100,000 triangles over one 8x8-pixel bin at one depth: one pass over a row's list is
/// longer than lavapipe's shader loop limit and no depth slab splits it, so rows are
/// suspended inside the pass, their selections saved, and resumed by continuations (exact
/// refused the frame: "exceeds the shader loop limit"). The threshold ends every pixel
/// after its first pass; without it each is 100,000 fragments deep.
#[test]
fn exact_renders_a_hundred_thousand_triangles_in_one_bin() {
    let frame = crowded_bin_frame(100_000, "crowded_bin", None);
    assert!(frame.fragments >= 64 * 7, "{}", frame.fragments);
}

/// A quarter of a million triangles over one 8x8-pixel bin at one depth: walking a row's list
/// takes five budgets, more than the first frame's continuation dispatches (one band's: the
/// empty bands after it would resume the rows too), so the rows left unfinished are finished
/// by more continuations in another submission, not by rendering the frame again.
#[test]
fn exact_finishes_unfinished_rows_in_another_submission() {
    let frame = crowded_bin_frame(250_000, "crowded_bin_finished", Some(1));
    let stages: Vec<&str> = frame.stages.iter().map(|(stage, _)| *stage).collect();
    assert!(stages.contains(&"raster finished"), "{stages:?}");
    assert_eq!(
        frame.rerenders, 1,
        "one finishing submission, nothing rendered again"
    );
}

/// The same quarter million with the bands a frame records by default: the bands after the
/// one with blocks have none, and their continuations go on resuming its rows, which finish
/// within the frame.
#[test]
fn exact_resumes_the_last_bands_rows_in_the_empty_bands_after_it() {
    let frame = crowded_bin_frame(250_000, "crowded_bin_in_bands", None);
    assert_eq!(frame.rerenders, 0, "{:?}", frame.stages);
    assert_eq!(frame.bands, 1);
}

/// Frames recorded without setup's occlusion cull (left out while what it drops is worth less
/// than its depth pyramid costs) are as right as culled ones: the raster depth-tests every
/// fragment. Over opaque layers with a near patch: a large one (the cull drops triangles over
/// 18,816 blocks, against the frame's 96, and stays), an 8x8 one (15 blocks: less than a
/// fifth of the frame's, so the cull is left out), then that one moved, where a cull reading
/// the last pyramid would drop triangles now in view, then the large one again, unculled.
/// Then the same from a renderer made for larger frames, which draws these into the corner
/// of its targets (the pyramid reads only the frame's part of the depth).
///
/// Which frames ran the cull shows in the triangles they kept: a culled frame drops those
/// behind its patch, an unculled one keeps every triangle a frame over a layer that hides
/// nothing keeps (when set: 390 and 8,177 of 8,192, then 8,192 twice).
#[test]
fn frames_with_and_without_the_occlusion_cull_match_the_reference() {
    let gpu = gpu();
    let scene = scene::load("particles").expect("scene");
    let (width, height) = (96u32, 64u32);
    let patches = [
        (8, 8, 80, 56),
        (24, 16, 32, 24),
        (40, 56, 56, 64),
        (8, 8, 80, 56),
    ];
    let culled = [true, true, false, false];
    for (max_width, max_height) in [(width, height), (width + 40, height + 24)] {
        let renderer = || {
            let mut renderer =
                Renderer::new(&gpu, &scene, MethodKind::Exact, max_width, max_height)
                    .expect("renderer");
            renderer.set_size(width, height).expect("a smaller frame");
            renderer
        };
        // On a renderer of its own: over a layer that hides nothing, the cull drops nothing
        // and leaves the frames after it unculled.
        let clear = translucid::OpaqueLayer::clear(width, height, Vec3::new(0.1, 0.2, 0.3));
        let unoccluded = renderer().render_over(&clear).expect("frame").triangles;
        let kept = occlusion_patches(&scene, &mut renderer(), &patches);
        for (i, (&kept, culled)) in kept.iter().zip(culled).enumerate() {
            let label = format!("frame {i} (renderer for {max_width}x{max_height})");
            if culled {
                assert!(
                    kept < unoccluded,
                    "{label} kept all {unoccluded} triangles: it ran without the cull"
                );
            } else {
                assert_eq!(
                    kept, unoccluded,
                    "{label} dropped triangles behind its patch: it ran with the cull"
                );
            }
        }
    }
}

/// Renders `scene` over opaque layers whose depth is 0 in each of `patches` (x0, y0, x1, y1)
/// in turn, each frame held to the reference; the triangles each frame kept.
fn occlusion_patches(
    scene: &Scene,
    renderer: &mut Renderer,
    patches: &[(u32, u32, u32, u32)],
) -> Vec<u64> {
    let (width, height) = renderer.size();
    let mut kept = Vec::new();
    for (i, &(x0, y0, x1, y1)) in patches.iter().enumerate() {
        let mut layer = translucid::OpaqueLayer::clear(width, height, Vec3::new(0.1, 0.2, 0.3));
        for y in y0..y1 {
            for x in x0..x1 {
                layer.depth[(y * width + x) as usize] = 0.0;
            }
        }
        let frame = renderer.render_over(&layer).expect("frame");
        let expected = translucid::reference::render(scene, &layer).expect("reference");
        let m = metrics::compare(&frame.image, &expected).expect("same size");
        let (max_width, max_height) = renderer.max_size();
        assert!(
            m.max_error <= TOLERANCE,
            "frame {i} (renderer for {max_width}x{max_height}) off by {:.1}/255 on {} pixels; \
             see {}",
            m.max_error * 255.0,
            m.pixels_over,
            save_failure(&format!("exact_occlusion_{i}"), &frame.image, &expected).display()
        );
        kept.push(frame.triangles);
    }
    kept
}

/// One plain blended frame: what the reruns at lavapipe's wider sizes run, where a rerun dies,
/// to tell lavapipe's own compiler dying on any draw there from this binary's tests failing
/// (`translucid_tests::rerun_at_lavapipe_subgroup_sizes`).
#[test]
fn lavapipe_draws_a_plain_frame() {
    translucid_tests::draw_one_plain_frame();
}
