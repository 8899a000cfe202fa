//! Hand-computed answers. The camera looks down -Z from (0, 0, EYE) with a 90° field of view
//! at a square viewport, so a point at distance `d` lands at `x_fb = S/2 + x · (S/2) / d`:
//! quads are placed by their pixel rectangle, with edges on pixel boundaries, away from the
//! pixel centres.

use super::{render, render_in_submission_order};
use crate::image::{Image, OpaqueLayer};
use crate::scene::{Camera, Draw, Material, Mesh, Scene, Texture};
use glam::{Mat4, Vec3, Vec4};

const EYE: f32 = 8.0;

fn camera(near: f32) -> Camera {
    Camera::look_at(
        Vec3::new(0.0, 0.0, EYE),
        Vec3::ZERO,
        std::f32::consts::FRAC_PI_2,
        near,
        100.0,
    )
}

/// World point at world depth `z` that projects to framebuffer `(x, y)` in a `size²` view.
fn world(size: u32, x: f32, y: f32, z: f32) -> Vec3 {
    let half = size as f32 / 2.0;
    let d = EYE - z;
    Vec3::new((x - half) * d / half, (half - y) * d / half, z)
}

/// A front-facing (counter-clockwise) quad covering pixel columns `x0..x1` and rows `y0..y1`.
fn rect(size: u32, [x0, y0, x1, y1]: [u32; 4], z: f32) -> Mesh {
    let p = |x: u32, y: u32| world(size, x as f32, y as f32, z);
    Mesh::from_quads(
        "rect",
        vec![p(x0, y1), p(x1, y1), p(x1, y0), p(x0, y0)],
        vec![[0, 1, 2, 3]],
    )
}

/// A scene of one draw per (mesh, material), in the order given.
fn scene(near: f32, layers: Vec<(Mesh, Material)>) -> Scene {
    let mut s = Scene {
        camera: camera(near),
        ..Scene::default()
    };
    for (i, (mesh, material)) in layers.into_iter().enumerate() {
        s.meshes.push(mesh);
        s.materials.push(material);
        s.transparent.push(Draw {
            mesh: i,
            material: i,
            transform: Mat4::IDENTITY,
            tint: glam::Vec4::ONE,
        });
    }
    s
}

fn alpha(r: f32, g: f32, b: f32, a: f32) -> Material {
    Material::alpha(Vec3::new(r, g, b), a)
}

fn draw(s: &Scene, size: u32, background: Vec3) -> Image {
    render(s, &OpaqueLayer::clear(size, size, background)).expect("renders")
}

#[track_caller]
fn assert_pixel(image: &Image, x: u32, y: u32, want: [f32; 3]) {
    let got = image.get(x, y);
    let want = Vec3::from_array(want).extend(1.0);
    assert!(
        (got - want).abs().max_element() < 1e-5,
        "pixel ({x}, {y}): got {got}, want {want}"
    );
}

#[test]
fn three_quads_in_the_wrong_order_composite_sorted() {
    // Columns: red (far, α .5) 0..6, green (middle, α .5) 2..8, blue (near, α .25) 4..6,
    // submitted near, far, middle, over grey 0.2.
    let s = scene(
        1.0,
        vec![
            (rect(8, [4, 0, 6, 8], 2.0), alpha(0.0, 0.0, 1.0, 0.25)),
            (rect(8, [0, 0, 6, 8], 0.0), alpha(1.0, 0.0, 0.0, 0.5)),
            (rect(8, [2, 0, 8, 8], 1.0), alpha(0.0, 1.0, 0.0, 0.5)),
        ],
    );
    let image = draw(&s, 8, Vec3::splat(0.2));
    for y in 0..8 {
        // red alone: 0.5 red + 0.5 · 0.2
        assert_pixel(&image, 1, y, [0.6, 0.1, 0.1]);
        // green over red: (0, .5, 0) + .5 (.5, 0, 0) + .25 · .2
        assert_pixel(&image, 3, y, [0.3, 0.55, 0.05]);
        // blue over green over red: L = (0, 0, .25) + .75 (0, .5, 0) + .375 (.5, 0, 0),
        // T = .1875
        assert_pixel(&image, 4, y, [0.225, 0.4125, 0.2875]);
        assert_pixel(&image, 5, y, [0.225, 0.4125, 0.2875]);
        // green alone
        assert_pixel(&image, 7, y, [0.1, 0.6, 0.1]);
    }
}

#[test]
fn coloured_transmission_filters_per_channel() {
    // A white glass tinted (1, .5, .25) behind a red α .5 quad, over white.
    let glass = Material {
        transmission: 1.0,
        transmission_tint: Vec3::new(1.0, 0.5, 0.25),
        ..Material::default()
    };
    let s = scene(
        1.0,
        vec![
            (rect(8, [0, 0, 8, 4], 1.0), alpha(1.0, 0.0, 0.0, 0.5)),
            (rect(8, [0, 0, 8, 8], 0.0), glass),
        ],
    );
    let image = draw(&s, 8, Vec3::ONE);
    // Red over the glass: (.5, 0, 0) + .5 · (1, .5, .25)
    assert_pixel(&image, 3, 1, [1.0, 0.25, 0.125]);
    // The glass alone.
    assert_pixel(&image, 3, 6, [1.0, 0.5, 0.25]);
}

#[test]
fn triangles_sharing_edges_draw_their_union_once() {
    // A 2x2 grid of quads over the whole 8x8 view, the middle vertex on the pixel centre
    // (3.5, 4.5), every diagonal through pixel centres; white α .5 over black.
    let p = |x: f32, y: f32| world(8, x, y, 0.0);
    let positions = vec![
        p(0.0, 8.0),
        p(3.5, 8.0),
        p(8.0, 8.0),
        p(0.0, 4.5),
        p(3.5, 4.5),
        p(8.0, 4.5),
        p(0.0, 0.0),
        p(3.5, 0.0),
        p(8.0, 0.0),
    ];
    let quads = vec![[0, 1, 4, 3], [1, 2, 5, 4], [4, 5, 8, 7], [3, 4, 7, 6]];
    let s = scene(
        1.0,
        vec![(
            Mesh::from_quads("grid", positions, quads),
            alpha(1.0, 1.0, 1.0, 0.5),
        )],
    );
    let image = draw(&s, 8, Vec3::ZERO);
    for y in 0..8 {
        for x in 0..8 {
            assert_pixel(&image, x, y, [0.5; 3]);
        }
    }
}

#[test]
fn quad_crossing_the_near_plane_is_clipped_not_dropped() {
    // A floor tilted towards the eye (z = -y), from y = 4 to y = -12 (behind the eye, at
    // z = 12 > EYE). Near = 6 clips everything with z > 2, i.e. y < -2: visible rows run
    // from y_fb = 8 - 32/12 = 5.33 to y_fb = 8 + 16/6 = 10.67, rows 5..=10.
    let floor = |y_near: f32| {
        Mesh::from_quads(
            "floor",
            vec![
                Vec3::new(-4.0, y_near, -y_near),
                Vec3::new(4.0, y_near, -y_near),
                Vec3::new(4.0, 4.0, -4.0),
                Vec3::new(-4.0, 4.0, -4.0),
            ],
            vec![[0, 1, 2, 3]],
        )
    };
    let white = alpha(1.0, 1.0, 1.0, 0.5);
    let whole = draw(
        &scene(6.0, vec![(floor(-12.0), white.clone())]),
        16,
        Vec3::ZERO,
    );
    let by_hand = draw(&scene(6.0, vec![(floor(-2.0), white)]), 16, Vec3::ZERO);
    for y in 0..16 {
        let drawn = (5..=10).contains(&y);
        assert_pixel(&whole, 7, y, if drawn { [0.5; 3] } else { [0.0; 3] });
    }
    assert_eq!(whole, by_hand);
}

#[test]
fn back_faces_of_single_sided_materials_are_culled() {
    let front = rect(8, [0, 0, 8, 8], 0.0);
    let mut back = front.clone();
    back.quads = vec![[3, 2, 1, 0]];
    let single = Material {
        double_sided: false,
        ..alpha(1.0, 1.0, 1.0, 0.5)
    };
    let double = alpha(1.0, 1.0, 1.0, 0.5);
    let cases = [
        (front.clone(), single.clone(), 0.5),
        (back.clone(), single, 0.0),
        (back, double, 0.5),
    ];
    for (mesh, material, want) in cases {
        let image = draw(&scene(1.0, vec![(mesh, material)]), 8, Vec3::ZERO);
        assert_pixel(&image, 2, 5, [want; 3]);
    }
}

#[test]
fn opaque_depth_hides_fragments_behind_it() {
    let s = scene(
        1.0,
        vec![
            (rect(8, [0, 0, 8, 8], 0.0), alpha(1.0, 0.0, 0.0, 0.5)),
            (rect(8, [0, 0, 8, 8], 4.0), alpha(0.0, 0.0, 1.0, 0.5)),
        ],
    );
    // Opaque depth between the two quads on the left half, far on the right half.
    let depth_at = |z: f32| {
        let clip = s.camera.view_projection(8, 8) * Vec4::new(0.0, 0.0, z, 1.0);
        clip.z / clip.w
    };
    let mut opaque = OpaqueLayer::clear(8, 8, Vec3::splat(0.2));
    for y in 0..8 {
        for x in 0..4 {
            opaque.depth[y * 8 + x] = depth_at(2.0);
        }
    }
    let image = render(&s, &opaque).expect("renders");
    // Left: blue alone. Right: blue over red over grey.
    assert_pixel(&image, 1, 3, [0.1, 0.1, 0.6]);
    assert_pixel(&image, 6, 3, [0.3, 0.05, 0.55]);
}

#[test]
fn interpenetrating_quads_sort_per_pixel() {
    // Red tilts away on the left (z = x/4), blue the other way (z = -x/4); they cross at
    // x = 0, which projects onto the boundary between columns 3 and 4. Both cover the view.
    let tilted = |slope: f32| {
        let p = |x: f32, y: f32| Vec3::new(x, y, slope * x);
        Mesh::from_quads(
            "tilted",
            vec![
                p(-20.0, -20.0),
                p(20.0, -20.0),
                p(20.0, 20.0),
                p(-20.0, 20.0),
            ],
            vec![[0, 1, 2, 3]],
        )
    };
    let s = scene(
        0.5,
        vec![
            (tilted(0.25), alpha(1.0, 0.0, 0.0, 0.5)),
            (tilted(-0.25), alpha(0.0, 0.0, 1.0, 0.5)),
        ],
    );
    let image = draw(&s, 8, Vec3::ZERO);
    for y in 0..8 {
        for x in 0..8 {
            let want = if x < 4 {
                [0.25, 0.0, 0.5] // blue in front
            } else {
                [0.5, 0.0, 0.25] // red in front
            };
            assert_pixel(&image, x, y, want);
        }
    }
}

#[test]
fn equal_depths_keep_submission_order() {
    let quad = rect(8, [0, 0, 8, 8], 0.0);
    let s = scene(
        1.0,
        vec![
            (quad.clone(), alpha(1.0, 0.0, 0.0, 0.5)),
            (quad, alpha(0.0, 0.0, 1.0, 0.5)),
        ],
    );
    // The first draw counts as nearer: red over blue over black.
    assert_pixel(&draw(&s, 8, Vec3::ZERO), 4, 4, [0.5, 0.0, 0.25]);
}

#[test]
fn submission_order_puts_the_last_draw_in_front_whatever_the_depths() {
    // Red (α .5, near) over columns 0..6, blue (α .25, far) over 2..8, submitted near first,
    // over grey 0.2.
    let red = || (rect(8, [0, 0, 6, 8], 1.0), alpha(1.0, 0.0, 0.0, 0.5));
    let blue = || (rect(8, [2, 0, 8, 8], 0.0), alpha(0.0, 0.0, 1.0, 0.25));
    let front_first = scene(1.0, vec![red(), blue()]);
    let opaque = OpaqueLayer::clear(8, 8, Vec3::splat(0.2));
    let sorted = render(&front_first, &opaque).expect("renders");
    let unsorted = render_in_submission_order(&front_first, &opaque).expect("renders");
    for y in 0..8 {
        // One layer: the order does not matter. Red: (.5, 0, 0) + .5 · .2; blue:
        // (0, 0, .25) + .75 · .2.
        for image in [&sorted, &unsorted] {
            assert_pixel(image, 1, y, [0.6, 0.1, 0.1]);
            assert_pixel(image, 7, y, [0.15, 0.15, 0.4]);
        }
        // By depth, red over blue: (.5, 0, 0) + .5 (0, 0, .25) + .5 · .75 · .2.
        assert_pixel(&sorted, 3, y, [0.575, 0.075, 0.2]);
        // In submission order blue, drawn last, lands over red:
        // (0, 0, .25) + .75 (.5, 0, 0) + .75 · .5 · .2.
        assert_pixel(&unsorted, 3, y, [0.45, 0.075, 0.325]);
    }

    // Submitted back to front, the two agree.
    let back_first = scene(1.0, vec![blue(), red()]);
    assert_eq!(
        render_in_submission_order(&back_first, &opaque).expect("renders"),
        sorted
    );

    // Within one draw the order is by quad: the same two quads as one mesh, their colours
    // from the vertices, the near one listed first, give the same two answers.
    let (near, far) = (red().0, blue().0);
    let mut positions = near.positions;
    positions.extend(far.positions);
    let mut both = Mesh::from_quads("both", positions, vec![[0, 1, 2, 3], [4, 5, 6, 7]]);
    let mut colours = vec![Vec4::new(1.0, 0.0, 0.0, 0.5); 4];
    colours.extend([Vec4::new(0.0, 0.0, 1.0, 0.25); 4]);
    both.colours = Some(colours);
    let one_draw = scene(1.0, vec![(both, alpha(1.0, 1.0, 1.0, 1.0))]);
    let sorted = render(&one_draw, &opaque).expect("renders");
    let unsorted = render_in_submission_order(&one_draw, &opaque).expect("renders");
    assert_pixel(&sorted, 3, 4, [0.575, 0.075, 0.2]);
    assert_pixel(&unsorted, 3, 4, [0.45, 0.075, 0.325]);
}

#[test]
fn vertex_colours_and_textures_multiply_the_base_colour() {
    let mut mesh = rect(8, [0, 0, 8, 8], 0.0);
    mesh.colours = Some(vec![Vec4::new(0.5, 1.0, 1.0, 1.0); 4]);
    mesh.uvs = Some(vec![glam::Vec2::ZERO; 4]);
    let mut s = scene(1.0, vec![(mesh, alpha(1.0, 1.0, 1.0, 1.0))]);
    s.textures
        .push(Texture::new("t", 1, 1, vec![[255, 51, 255, 255]], false));
    s.materials[0].texture = Some(0);
    assert_pixel(&draw(&s, 8, Vec3::ZERO), 3, 3, [0.5, 0.2, 1.0]);
}

#[test]
fn zero_size_is_an_error() {
    let s = scene(1.0, vec![]);
    assert!(render(&s, &OpaqueLayer::clear(0, 4, Vec3::ZERO)).is_err());
}
