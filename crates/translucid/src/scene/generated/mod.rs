//! Generated test scenes: deterministic, each with a camera, an opaque backdrop (a checkered
//! ground or wall, so that transparency shows against something) and a transparent layer that
//! stresses one aspect of order-independent transparency.
//!
//! | name         | what it tests                                                        |
//! |--------------|----------------------------------------------------------------------|
//! | `boxes`      | a grid of transparent boxes, varied colours and alphas, some lit     |
//! | `spheres`    | three overlapping cyan/magenta/yellow spheres, back halves visible   |
//! | `particles`  | a dense cloud of camera-facing quads, ≥ 32 layers deep               |
//! | `planes`     | large planes crossing each other: no draw order is right             |
//! | `hairball`   | tens of thousands of thin strands at low alpha                       |
//! | `layers`     | screen-facing quads submitted back to front: unsorted blend is exact |
//! | `polychrome` | transmissive quads with coloured (per-channel) transmittance         |
//! | `textured`   | textured quads: every sampler mode, mips, steep angles, texture alpha |
//!
//! Besides these, `draws<N>` (for example `draws1000`) is N small quads, each its own draw of
//! one shared mesh, over a wall: what an engine's many draw calls cost to record
//! (`translucid bench draws1000 draws10000`). N is 1 to [`MAX_DRAWS`]. The sized scenes
//! ([`SIZED`], `NAME:N`) include the hostile stacks of `stacks.rs`: `instanced:16384`,
//! `coincident:10000` and `random_draws:100000` at 160x120 are the hostile-input tests'.

mod stacks;
pub use stacks::one_draw_scene;
mod textured;

use super::{Camera, Draw, Material, Mesh, Scene};
use glam::{Mat4, Quat, Vec2, Vec3, Vec4};
use std::f32::consts::{PI, TAU};

/// The most draws a `draws<N>` scene has.
pub const MAX_DRAWS: u32 = 100_000;

/// Names accepted by [`generate`], besides `draws<N>`.
pub const NAMES: &[&str] = &[
    "boxes",
    "spheres",
    "particles",
    "planes",
    "hairball",
    "layers",
    "polychrome",
    "textured",
];

/// The generated scenes that take a size, `NAME:N`, and what N counts. Their triangles (or
/// planes) change with N, not the area they cover on screen, so that a sweep over N measures
/// what the triangles cost: `hairball:60000`, `particles:8192` and `planes:6` are
/// `hairball`, `particles` and `planes`.
pub const SIZED: &[(&str, &str)] = &[
    ("hairball", "transparent triangles, 2 to 20,000,000"),
    ("particles", "transparent triangles, 2 to 20,000,000"),
    ("planes", "intersecting planes of 512 triangles, 1 to 1,000"),
    (
        "instanced",
        "draws of one screen-filling quad at one place, 1 to 100,000",
    ),
    (
        "coincident",
        "screen-filling triangles at one depth in one mesh, 1 to 100,000",
    ),
    (
        "random_draws",
        "draws of a small triangle at random places and depths, 1 to 100,000",
    ),
];

/// The most triangles a sized scene takes: 20 M, past the frames' limits.
const MOST_SIZED_TRIANGLES: u64 = 20_000_000;

/// The generated scene called `name`, or `None` when there is no such scene.
/// The same name always gives the same scene.
pub fn generate(name: &str) -> Option<Scene> {
    let scene = match name {
        "boxes" => boxes(),
        "spheres" => spheres(),
        "particles" => particles(8192),
        "planes" => planes(6),
        "hairball" => hairball(60_000),
        "layers" => layers(),
        "polychrome" => polychrome(),
        "textured" => textured::textured(),
        other => draws(other.strip_prefix("draws")?.parse().ok()?)?,
    };
    Some(scene)
}

/// The sized scene `spec` (`NAME:N`, see [`SIZED`]): `None` when `spec` names none, an error
/// when its N is not a count it takes.
pub fn generate_sized(spec: &str) -> Option<Result<Scene, String>> {
    let (name, count) = spec.split_once(':')?;
    let (_, counts) = SIZED.iter().find(|(n, _)| *n == name)?;
    let n = match parse_count(count) {
        Some(n) => n,
        None => {
            return Some(Err(format!(
                "{spec}: {count:?} is not a count (digits, optionally ending in k or m)"
            )))
        }
    };
    let (least, most) = match name {
        "planes" => (1, 1_000),
        "instanced" | "coincident" | "random_draws" => (1, u64::from(MAX_DRAWS)),
        _ => (2, MOST_SIZED_TRIANGLES),
    };
    if !(least..=most).contains(&n) {
        return Some(Err(format!("{spec}: {name} takes {counts}")));
    }
    let n = n as u32;
    let mut scene = match name {
        "hairball" => hairball(n),
        "particles" => particles(n),
        "instanced" => stacks::instanced(n),
        "coincident" => stacks::coincident(n),
        "random_draws" => stacks::random_draws(n),
        _ => planes(n),
    };
    scene.name = spec.to_string();
    Some(Ok(scene))
}

/// `10`, `30k`, `1m`: a count, in thousands or millions with a suffix.
pub fn parse_count(text: &str) -> Option<u64> {
    let lower = text.trim().to_ascii_lowercase();
    let (digits, scale) = match lower.strip_suffix('k') {
        Some(d) => (d, 1_000),
        None => match lower.strip_suffix('m') {
            Some(d) => (d, 1_000_000),
            None => (lower.as_str(), 1),
        },
    };
    if digits.is_empty() || !digits.bytes().all(|b| b.is_ascii_digit()) {
        return None;
    }
    digits.parse::<u64>().ok()?.checked_mul(scale)
}

/// splitmix64: tiny, fast, and the same on every platform.
struct Rng(u64);

impl Rng {
    fn next_u64(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^ (z >> 31)
    }

    /// Uniform in [0, 1).
    fn unit(&mut self) -> f32 {
        (self.next_u64() >> 40) as f32 / (1u64 << 24) as f32
    }

    fn range(&mut self, lo: f32, hi: f32) -> f32 {
        lo + (hi - lo) * self.unit()
    }

    /// Uniform direction on the unit sphere.
    fn direction(&mut self) -> Vec3 {
        let z = self.range(-1.0, 1.0);
        let phi = self.range(0.0, TAU);
        let r = (1.0 - z * z).max(0.0).sqrt();
        Vec3::new(r * phi.cos(), r * phi.sin(), z)
    }

    /// A saturated colour of random hue.
    fn hue(&mut self) -> Vec3 {
        hue(self.unit())
    }
}

/// Fully saturated colour at hue `h` in [0, 1).
fn hue(h: f32) -> Vec3 {
    let h6 = h.fract() * 6.0;
    let channel = |offset: f32| (((h6 + offset) % 6.0 - 3.0).abs() - 1.0).clamp(0.0, 1.0);
    Vec3::new(channel(0.0), channel(4.0), channel(2.0))
}

/// Quads accumulated with per-vertex normals and colours, turned into one [`Mesh`].
#[derive(Default)]
struct QuadSoup {
    positions: Vec<Vec3>,
    normals: Vec<Vec3>,
    colours: Vec<Vec4>,
    quads: Vec<[u32; 4]>,
}

impl QuadSoup {
    fn push_vertex(&mut self, position: Vec3, normal: Vec3, colour: Vec4) -> u32 {
        self.positions.push(position);
        self.normals.push(normal);
        self.colours.push(colour);
        (self.positions.len() - 1) as u32
    }

    /// A flat quad of one colour; corners in order around its edge.
    fn quad(&mut self, corners: [Vec3; 4], colour: Vec4) {
        let normal = (corners[1] - corners[0])
            .cross(corners[2] - corners[0])
            .normalize_or(Vec3::Z);
        self.quad_with_normals(corners, [normal; 4], colour);
    }

    fn quad_with_normals(&mut self, corners: [Vec3; 4], normals: [Vec3; 4], colour: Vec4) {
        let q = std::array::from_fn(|i| self.push_vertex(corners[i], normals[i], colour));
        self.quads.push(q);
    }

    /// A lone triangle, stored as the degenerate quad `[a, b, c, c]`.
    fn triangle_with_normals(&mut self, corners: [Vec3; 3], normals: [Vec3; 3], colour: Vec4) {
        let [a, b, c] = std::array::from_fn(|i| self.push_vertex(corners[i], normals[i], colour));
        self.quads.push([a, b, c, c]);
    }

    /// A parallelogram `origin + s·u + t·v` (s, t in [0, 1]) split into `cells`² quads.
    fn grid(
        &mut self,
        origin: Vec3,
        u: Vec3,
        v: Vec3,
        cells: u32,
        colour: impl Fn(u32, u32) -> Vec4,
    ) {
        let step = 1.0 / cells as f32;
        for j in 0..cells {
            for i in 0..cells {
                let at = |di: u32, dj: u32| {
                    origin + u * ((i + di) as f32 * step) + v * ((j + dj) as f32 * step)
                };
                self.quad([at(0, 0), at(1, 0), at(1, 1), at(0, 1)], colour(i, j));
            }
        }
    }

    fn into_mesh(self, name: &str) -> Mesh {
        Mesh {
            normals: Some(self.normals),
            colours: Some(self.colours),
            ..Mesh::from_quads(name, self.positions, self.quads)
        }
    }
}

/// A checkerboard parallelogram (see [`QuadSoup::grid`]) in two greys.
fn checker(origin: Vec3, u: Vec3, v: Vec3, cells: u32, light: f32, dark: f32) -> Mesh {
    let mut soup = QuadSoup::default();
    soup.grid(origin, u, v, cells, |i, j| {
        Vec3::splat(if (i + j) % 2 == 0 { light } else { dark }).extend(1.0)
    });
    soup.into_mesh("checker")
}

/// Scene assembly: meshes and materials pushed, draws recorded in submission order.
struct Builder {
    scene: Scene,
}

impl Builder {
    fn new(name: &str, camera: Camera, background: Vec3) -> Self {
        Self {
            scene: Scene {
                name: name.to_string(),
                camera,
                background,
                ..Scene::default()
            },
        }
    }

    fn mesh(&mut self, mesh: Mesh) -> usize {
        self.scene.meshes.push(mesh);
        self.scene.meshes.len() - 1
    }

    fn material(&mut self, material: Material) -> usize {
        self.scene.materials.push(material);
        self.scene.materials.len() - 1
    }

    fn opaque(&mut self, mesh: Mesh, material: Material) {
        let draw = self.draw(mesh, material);
        self.scene.opaque.push(draw);
    }

    fn transparent(&mut self, mesh: Mesh, material: Material) {
        let draw = self.draw(mesh, material);
        self.scene.transparent.push(draw);
    }

    fn draw(&mut self, mesh: Mesh, material: Material) -> Draw {
        Draw {
            mesh: self.mesh(mesh),
            material: self.material(material),
            transform: Mat4::IDENTITY,
            tint: glam::Vec4::ONE,
        }
    }

    fn finish(self) -> Scene {
        self.scene
    }
}

/// A lit, white, opaque material: vertex colours give the checker.
fn lit_ground() -> Material {
    Material {
        name: "ground".into(),
        lit: true,
        ..Material::default()
    }
}

/// Vertex colours carry colour and alpha; the material says lit or not.
fn vertex_coloured(name: &str, lit: bool) -> Material {
    Material {
        name: name.into(),
        lit,
        ..Material::default()
    }
}

/// A checkered ground plane `y = height`, centred on the origin, `size` on a side.
fn ground(height: f32, size: f32) -> Mesh {
    let h = size * 0.5;
    checker(
        Vec3::new(-h, height, h),
        Vec3::new(size, 0.0, 0.0),
        Vec3::new(0.0, 0.0, -size),
        16,
        0.7,
        0.3,
    )
}

/// A checkered wall `z = depth` facing +Z, centred on the origin.
fn back_wall(depth: f32, size: f32, light: f32, dark: f32) -> Mesh {
    let h = size * 0.5;
    checker(
        Vec3::new(-h, -h, depth),
        Vec3::new(size, 0.0, 0.0),
        Vec3::new(0.0, size, 0.0),
        16,
        light,
        dark,
    )
}

/// 5 × 3 × 5 boxes (450 quads) with random colours, alphas and slight rotations; the first
/// half of the draws is lit, the second unlit. One draw per box, as an engine would submit.
fn boxes() -> Scene {
    let camera = Camera::look_at(
        Vec3::new(5.0, 6.0, 9.0),
        Vec3::new(0.0, 0.5, 0.0),
        0.8,
        0.5,
        40.0,
    );
    let mut b = Builder::new("boxes", camera, Vec3::new(0.05, 0.05, 0.08));
    b.opaque(ground(-1.0, 14.0), lit_ground());
    let mut rng = Rng(1);
    let count = 5 * 3 * 5;
    for k in 0..count {
        let (x, y, z) = (k % 5, (k / 5) % 3, k / 15);
        let centre = Vec3::new(x as f32 - 2.0, y as f32, z as f32 - 2.0) * 1.4;
        let rotation = Quat::from_axis_angle(rng.direction(), rng.range(0.0, 0.6));
        let half = Vec3::new(
            rng.range(0.3, 0.6),
            rng.range(0.3, 0.6),
            rng.range(0.3, 0.6),
        );
        let colour = rng.hue().lerp(Vec3::ONE, rng.range(0.0, 0.4));
        let alpha = rng.range(0.2, 0.7);
        let mut soup = QuadSoup::default();
        push_box(&mut soup, centre, half, rotation, colour.extend(alpha));
        let lit = k < count / 2;
        b.transparent(
            soup.into_mesh(&format!("box {k}")),
            vertex_coloured("box", lit),
        );
    }
    b.finish()
}

/// The six faces of a box, outward-facing.
fn push_box(soup: &mut QuadSoup, centre: Vec3, half: Vec3, rotation: Quat, colour: Vec4) {
    let corner = |sx: f32, sy: f32, sz: f32| centre + rotation * (half * Vec3::new(sx, sy, sz));
    let faces: [[(f32, f32, f32); 4]; 6] = [
        [(1., -1., -1.), (1., 1., -1.), (1., 1., 1.), (1., -1., 1.)],
        [
            (-1., -1., 1.),
            (-1., 1., 1.),
            (-1., 1., -1.),
            (-1., -1., -1.),
        ],
        [(-1., 1., -1.), (-1., 1., 1.), (1., 1., 1.), (1., 1., -1.)],
        [
            (-1., -1., 1.),
            (-1., -1., -1.),
            (1., -1., -1.),
            (1., -1., 1.),
        ],
        [(-1., -1., 1.), (1., -1., 1.), (1., 1., 1.), (-1., 1., 1.)],
        [
            (1., -1., -1.),
            (-1., -1., -1.),
            (-1., 1., -1.),
            (1., 1., -1.),
        ],
    ];
    for face in faces {
        soup.quad(face.map(|(x, y, z)| corner(x, y, z)), colour);
    }
}

/// Cyan, magenta and yellow spheres at alpha 0.5, overlapping in the middle; lit and
/// double-sided so the inner back halves show. 3 × 48 × 24 = 3456 quads.
fn spheres() -> Scene {
    let camera = Camera::look_at(
        Vec3::new(0.0, 1.2, 6.5),
        Vec3::new(0.0, 0.1, 0.0),
        0.8,
        0.5,
        30.0,
    );
    let mut b = Builder::new("spheres", camera, Vec3::new(0.05, 0.05, 0.08));
    b.opaque(back_wall(-3.0, 12.0, 0.8, 0.4), lit_ground());
    let colours = [
        Vec3::new(0.0, 1.0, 1.0),
        Vec3::new(1.0, 0.0, 1.0),
        Vec3::new(1.0, 1.0, 0.0),
    ];
    for (i, colour) in colours.into_iter().enumerate() {
        let angle = PI / 2.0 + i as f32 * TAU / 3.0;
        let centre = Vec3::new(angle.cos(), angle.sin(), 0.0) * 0.7;
        let mut soup = QuadSoup::default();
        push_sphere(&mut soup, centre, 1.2, 48, 24, colour.extend(0.5));
        let material = Material {
            name: format!("sphere {i}"),
            lit: true,
            double_sided: true,
            ..Material::default()
        };
        b.transparent(soup.into_mesh(&format!("sphere {i}")), material);
    }
    b.finish()
}

/// A latitude–longitude sphere; the rings at the poles are triangles.
fn push_sphere(
    soup: &mut QuadSoup,
    centre: Vec3,
    radius: f32,
    segments: u32,
    rings: u32,
    colour: Vec4,
) {
    let dir = |seg: u32, ring: u32| {
        let theta = PI * ring as f32 / rings as f32;
        let phi = TAU * seg as f32 / segments as f32;
        Vec3::new(
            theta.sin() * phi.cos(),
            theta.cos(),
            -theta.sin() * phi.sin(),
        )
    };
    for ring in 0..rings {
        for seg in 0..segments {
            let n = [
                dir(seg, ring),
                dir(seg, ring + 1),
                dir(seg + 1, ring + 1),
                dir(seg + 1, ring),
            ];
            let p = n.map(|n| centre + n * radius);
            if ring == 0 {
                soup.triangle_with_normals([p[0], p[1], p[2]], [n[0], n[1], n[2]], colour);
            } else if ring == rings - 1 {
                soup.triangle_with_normals([p[0], p[1], p[3]], [n[0], n[1], n[3]], colour);
            } else {
                soup.quad_with_normals(p, n, colour);
            }
        }
    }
}

/// Camera-facing quads (4096, `triangles` 8192) at low alpha in a disc-shaped cloud seen face
/// on, so that the interior of the cloud is about 70 layers deep (at least 32 over most
/// covered pixels). With more quads each is smaller, covering as much of the screen in all.
fn particles(triangles: u32) -> Scene {
    let eye = Vec3::new(0.0, 0.0, 10.0);
    let camera = Camera::look_at(eye, Vec3::ZERO, 0.8, 1.0, 30.0);
    let mut b = Builder::new("particles", camera, Vec3::new(0.02, 0.02, 0.04));
    b.opaque(back_wall(-4.0, 14.0, 0.5, 0.25), lit_ground());
    let mut rng = Rng(3);
    let mut soup = QuadSoup::default();
    let quads = (triangles / 2).max(1);
    let scale = (4096.0 / quads as f32).sqrt();
    for _ in 0..quads {
        // Uniform in a disc across the view, uniform in depth: even depth complexity.
        let r = 3.0 * rng.unit().sqrt();
        let phi = rng.range(0.0, TAU);
        let centre = Vec3::new(r * phi.cos(), r * phi.sin(), rng.range(-2.5, 2.5));
        let half = rng.range(0.25, 0.45) * scale;
        let forward = (eye - centre).normalize();
        let right = Vec3::Y.cross(forward).normalize() * half;
        let up = forward.cross(right).normalize() * half;
        let colour = rng.hue().lerp(Vec3::ONE, 0.3).extend(rng.range(0.04, 0.12));
        soup.quad(
            [
                centre - right - up,
                centre + right - up,
                centre + right + up,
                centre - right + up,
            ],
            colour,
        );
    }
    b.transparent(
        soup.into_mesh("particles"),
        vertex_coloured("particles", false),
    );
    b.finish()
}

/// Large planes (six, or `count`) through the origin at different angles, each cutting the
/// others, so that every plane is partly behind and partly in front of every other: any draw
/// order is wrong somewhere. Each plane is 16 × 16 quads (1536 in all for six); odd planes
/// are lit.
fn planes(count: u32) -> Scene {
    let camera = Camera::look_at(Vec3::new(3.5, 2.5, 7.0), Vec3::ZERO, 0.8, 0.5, 30.0);
    let mut b = Builder::new("planes", camera, Vec3::new(0.05, 0.05, 0.08));
    b.opaque(ground(-2.6, 16.0), lit_ground());
    let mut rng = Rng(4);
    for i in 0..count {
        let rotation = Quat::from_rotation_y(i as f32 * PI / count as f32)
            * Quat::from_rotation_x(rng.range(-0.7, 0.7))
            * Quat::from_rotation_z(rng.range(-0.4, 0.4));
        let u = rotation * Vec3::new(4.4, 0.0, 0.0);
        let v = rotation * Vec3::new(0.0, 3.6, 0.0);
        let colour = hue(i as f32 / count as f32)
            .lerp(Vec3::ONE, 0.15)
            .extend(rng.range(0.35, 0.6));
        let mut soup = QuadSoup::default();
        soup.grid(-(u + v) * 0.5, u, v, 16, |_, _| colour);
        let lit = i % 2 == 1;
        b.transparent(
            soup.into_mesh(&format!("plane {i}")),
            vertex_coloured("plane", lit),
        );
    }
    b.finish()
}

/// 3000 strands of 10 thin ribbons each (30 000 quads, `triangles` 60 000) curling out of a
/// ball, at low alpha. Other counts cut the same strands into more or fewer ribbons (and use
/// fewer strands below 3000 quads).
fn hairball(triangles: u32) -> Scene {
    let eye = Vec3::new(0.0, 0.4, 5.0);
    let camera = Camera::look_at(eye, Vec3::ZERO, 0.8, 0.5, 20.0);
    let mut b = Builder::new("hairball", camera, Vec3::new(0.03, 0.03, 0.05));
    b.opaque(ground(-1.9, 10.0), lit_ground());
    let mut rng = Rng(5);
    let mut soup = QuadSoup::default();
    let quads = (triangles / 2).max(1);
    let strands = quads.min(3000);
    for strand in 0..strands {
        // The strands share the quads out; each is as long, its turns as sharp, however many
        // ribbons it is cut into.
        let ribbons = quads / strands + u32::from(strand < quads % strands);
        let step = 10.0 / ribbons as f32;
        let root = rng.direction();
        let colour = hue(rng.range(0.0, 0.15)).lerp(Vec3::new(0.9, 0.8, 0.6), rng.unit());
        let alpha = rng.range(0.08, 0.25);
        let curl = rng.direction() * 0.35;
        let mut at = root * 0.6;
        let mut dir = root;
        for _ in 0..ribbons {
            dir = (dir + curl * step + rng.direction() * (0.15 * step)).normalize();
            let next = at + dir * (0.12 * step);
            // Ribbons face the eye so they stay visible however they turn.
            let side = (next - at).cross(eye - at).normalize_or(Vec3::X) * 0.006;
            soup.quad_with_normals(
                [at - side, at + side, next + side, next - side],
                [at.normalize_or(Vec3::Y); 4],
                colour.extend(alpha),
            );
            at = next;
        }
    }
    b.transparent(soup.into_mesh("hair"), vertex_coloured("hair", true));
    b.finish()
}

/// Eight screen-facing quads at distinct depths, partly overlapping, submitted strictly back
/// to front with plain unlit alpha: the one scene where unsorted blending is exactly right.
fn layers() -> Scene {
    let camera = Camera::look_at(Vec3::new(0.0, 0.0, 6.0), Vec3::ZERO, 0.8, 0.5, 20.0);
    let mut b = Builder::new("layers", camera, Vec3::new(0.05, 0.05, 0.08));
    b.opaque(
        back_wall(-3.0, 12.0, 0.75, 0.35),
        vertex_coloured("wall", false),
    );
    for i in 0..8 {
        let z = -2.0 + i as f32 * 0.5;
        let angle = i as f32 * TAU / 8.0;
        let centre = Vec3::new(angle.cos(), angle.sin(), 0.0) * 0.55 + Vec3::Z * z;
        let (w, h) = (1.1, 0.8);
        let corner = |sx: f32, sy: f32| centre + Vec3::new(sx * w, sy * h, 0.0);
        let mut soup = QuadSoup::default();
        let colour = hue(i as f32 * 0.37);
        soup.quad(
            [
                corner(-1.0, -1.0),
                corner(1.0, -1.0),
                corner(1.0, 1.0),
                corner(-1.0, 1.0),
            ],
            Vec4::ONE,
        );
        let material = Material::alpha(colour, 0.3 + 0.05 * i as f32);
        b.transparent(
            soup.into_mesh(&format!("layer {i}")),
            Material {
                name: format!("layer {i}"),
                ..material
            },
        );
    }
    b.finish()
}

/// `count` small quads in a square grid facing the camera, each its own draw of one shared
/// quad mesh (the materials cycle through eight), slightly apart in depth, over a wall.
/// `None` unless `count` is 1 to MAX_DRAWS.
fn draws(count: u32) -> Option<Scene> {
    if !(1..=MAX_DRAWS).contains(&count) {
        return None;
    }
    let camera = Camera::look_at(Vec3::new(0.0, 0.0, 3.0), Vec3::ZERO, 0.8, 0.1, 20.0);
    let mut b = Builder::new(
        &format!("draws{count}"),
        camera,
        Vec3::new(0.05, 0.05, 0.08),
    );
    b.opaque(
        back_wall(-1.0, 8.0, 0.75, 0.35),
        vertex_coloured("wall", false),
    );
    let columns = (count as f32).sqrt().ceil() as u32;
    // The grid spans 2 units at the origin; each quad is a column's width across.
    let step = 2.0 / columns as f32;
    let mut soup = QuadSoup::default();
    let half = 0.5 * step;
    soup.quad(
        [
            Vec3::new(-half, -half, 0.0),
            Vec3::new(half, -half, 0.0),
            Vec3::new(half, half, 0.0),
            Vec3::new(-half, half, 0.0),
        ],
        Vec4::ONE,
    );
    // The first draw's mesh and material; every draw is pushed below.
    let first = b.draw(soup.into_mesh("quad"), Material::alpha(hue(0.0), 0.5));
    let materials: Vec<usize> = std::iter::once(first.material)
        .chain((1..8).map(|i| b.material(Material::alpha(hue(i as f32 * 0.37), 0.5))))
        .collect();
    for i in 0..count {
        let (column, row) = (i % columns, i / columns);
        let centre = Vec3::new(
            -1.0 + (column as f32 + 0.5) * step,
            -1.0 + (row as f32 + 0.5) * step,
            // Overlapping neighbours (the quads are 1.5 steps wide) differ in depth.
            -0.5 * i as f32 / count as f32,
        );
        b.scene.transparent.push(Draw {
            material: materials[i as usize % materials.len()],
            transform: Mat4::from_translation(centre) * Mat4::from_scale(Vec3::splat(1.5)),
            ..first
        });
    }
    Some(b.finish())
}

/// Five overlapping transmissive filters with coloured tints over a light grey wall,
/// submitted back to front: per-channel transmittance, beyond plain alpha.
fn polychrome() -> Scene {
    let camera = Camera::look_at(Vec3::new(0.0, 0.0, 5.0), Vec3::ZERO, 0.8, 0.5, 20.0);
    let mut b = Builder::new("polychrome", camera, Vec3::splat(0.9));
    b.opaque(
        back_wall(-1.5, 10.0, 0.9, 0.7),
        vertex_coloured("wall", false),
    );
    let filters = [
        (Vec3::new(1.0, 0.25, 0.2), Vec2::new(-0.6, 0.4)),
        (Vec3::new(0.25, 1.0, 0.3), Vec2::new(0.6, 0.4)),
        (Vec3::new(0.2, 0.35, 1.0), Vec2::new(0.0, -0.5)),
        (Vec3::new(1.0, 0.8, 0.15), Vec2::new(-0.3, -0.1)),
        (Vec3::new(0.7, 0.3, 1.0), Vec2::new(0.4, -0.1)),
    ];
    for (i, (tint, offset)) in filters.into_iter().enumerate() {
        let centre = offset.extend(-1.0 + 0.3 * i as f32);
        let half = Vec3::new(0.8, 0.6, 0.0);
        let mut soup = QuadSoup::default();
        soup.quad(
            [
                centre - half,
                centre + Vec3::new(half.x, -half.y, 0.0),
                centre + half,
                centre + Vec3::new(-half.x, half.y, 0.0),
            ],
            Vec4::ONE,
        );
        let material = Material {
            name: format!("filter {i}"),
            transmission: 1.0,
            transmission_tint: tint,
            reflectance: 0.04,
            ..Material::default()
        };
        b.transparent(soup.into_mesh(&format!("filter {i}")), material);
    }
    b.finish()
}

#[cfg(test)]
mod tests {
    use super::*;

    fn scene(name: &str) -> Scene {
        generate(name).unwrap_or_else(|| panic!("{name} missing"))
    }

    #[test]
    fn every_scene_validates_and_has_both_layers() {
        for name in NAMES {
            let s = scene(name);
            s.validate().unwrap_or_else(|e| panic!("{name}: {e}"));
            assert!(!s.opaque.is_empty(), "{name} has no opaque layer");
            assert!(s.transparent_quads() >= 5, "{name} has too few quads");
            assert_eq!(s.name, *name);
        }
        assert!(generate("nonesuch").is_none());
    }

    #[test]
    fn scenes_are_deterministic() {
        for name in NAMES {
            assert_eq!(scene(name).meshes, scene(name).meshes, "{name}");
        }
    }

    #[test]
    fn sized_scenes_have_the_triangles_asked_for() {
        let triangles = |spec: &str| {
            generate_sized(spec)
                .expect("a sized scene")
                .expect("a count it takes")
                .transparent_quads()
                * 2
        };
        assert_eq!(triangles("hairball:1000"), 1_000);
        assert_eq!(triangles("hairball:30k"), 30_000);
        assert_eq!(triangles("hairball:100001"), 100_000);
        assert_eq!(triangles("particles:2"), 2);
        assert_eq!(triangles("particles:1m"), 1_000_000);
        assert_eq!(triangles("planes:10"), 10 * 512);
        // The unsized names are these sizes.
        for (name, spec) in [
            ("hairball", "hairball:60000"),
            ("particles", "particles:8192"),
            ("planes", "planes:6"),
        ] {
            let sized = generate_sized(spec).expect("sized").expect("valid");
            assert_eq!(sized.meshes, scene(name).meshes, "{spec}");
            assert_eq!(sized.name, spec);
        }
        for bad in [
            "hairball:0",
            "hairball:1",
            "particles:21m",
            "planes:0",
            "planes:1001",
        ] {
            let err = generate_sized(bad)
                .expect("sized")
                .expect_err("out of range");
            assert!(err.contains(bad), "{err}");
        }
        assert!(generate_sized("hairball:ten")
            .expect("sized")
            .is_err_and(|e| e.contains("not a count")));
        assert!(generate_sized("boxes:10").is_none());
        assert_eq!(parse_count("30K"), Some(30_000));
        assert_eq!(parse_count("k"), None);
        assert_eq!(parse_count("-3"), None);
    }

    /// More triangles, the same surface: the sweep over triangles measures them, not deeper
    /// pixels.
    #[test]
    fn sized_scenes_keep_their_area() {
        let area = |spec: &str| {
            let s = generate_sized(spec).expect("sized").expect("valid");
            let mut total = 0.0f64;
            for d in &s.transparent {
                let mesh = &s.meshes[d.mesh];
                for &q in &mesh.quads {
                    for [a, b, c] in Mesh::quad_triangles(q).into_iter().flatten() {
                        let p = |i: u32| mesh.positions[i as usize];
                        total += f64::from((p(b) - p(a)).cross(p(c) - p(a)).length() / 2.0);
                    }
                }
            }
            total
        };
        for (small, large) in [
            ("particles:2000", "particles:200k"),
            ("hairball:6k", "hairball:600k"),
        ] {
            let (a, b) = (area(small), area(large));
            assert!(
                (a / b).max(b / a) < 1.1,
                "{small}: area {a:.2}, {large}: {b:.2}"
            );
        }
    }

    #[test]
    fn scene_sizes_are_as_documented() {
        let quads = |n: &str| scene(n).transparent_quads();
        assert_eq!(quads("boxes"), 450);
        assert_eq!(quads("spheres"), 3 * 48 * 24);
        assert_eq!(quads("particles"), 4096);
        assert_eq!(quads("planes"), 6 * 256);
        assert_eq!(quads("hairball"), 30_000);
        assert_eq!(quads("layers"), 8);
        assert_eq!(quads("polychrome"), 5);
    }

    /// Whether the ray `origin + t·dir` (t > 0) crosses triangle `abc` (either side).
    fn ray_hits(origin: Vec3, dir: Vec3, [a, b, c]: [Vec3; 3]) -> bool {
        let (e1, e2) = (b - a, c - a);
        let p = dir.cross(e2);
        let det = e1.dot(p);
        if det.abs() < 1e-12 {
            return false;
        }
        let s = origin - a;
        let u = s.dot(p) / det;
        let q = s.cross(e1);
        let v = dir.dot(q) / det;
        let t = e2.dot(q) / det;
        u >= 0.0 && v >= 0.0 && u + v <= 1.0 && t > 0.0
    }

    /// Transparent quads crossed by the ray through the centre of the view.
    fn centre_ray_depth(s: &Scene) -> usize {
        let to_world = s.camera.view.inverse();
        let eye = to_world.transform_point3(Vec3::ZERO);
        let dir = to_world.transform_vector3(Vec3::NEG_Z);
        s.transparent
            .iter()
            .flat_map(|d| s.meshes[d.mesh].quads.iter().map(move |q| (d, q)))
            .filter(|(d, &q)| {
                let mesh = &s.meshes[d.mesh];
                Mesh::quad_triangles(q).into_iter().flatten().any(|t| {
                    let corners =
                        t.map(|i| d.transform.transform_point3(mesh.positions[i as usize]));
                    ray_hits(eye, dir, corners)
                })
            })
            .count()
    }

    #[test]
    fn draws_scenes_have_their_draws_of_one_mesh() {
        for count in [1, 1000, 10_000] {
            let s = generate(&format!("draws{count}")).expect("a draws scene");
            assert_eq!(s.transparent.len(), count);
            assert!(s
                .transparent
                .iter()
                .all(|d| d.mesh == s.transparent[0].mesh));
            assert!(s.validate().is_ok());
        }
        for name in ["draws0", "draws100001", "draws", "drawsx", "draws-1"] {
            assert!(generate(name).is_none(), "{name}");
        }
    }

    #[test]
    fn particles_are_at_least_32_deep_at_the_centre() {
        let depth = centre_ray_depth(&scene("particles"));
        assert!(depth >= 32, "only {depth} layers at the centre");
    }

    #[test]
    fn layers_are_submitted_back_to_front() {
        let s = scene("layers");
        // View-space z is negative in front of the camera; nearer means larger.
        let depths: Vec<(f32, f32)> = s
            .transparent
            .iter()
            .map(|d| {
                let z = s.meshes[d.mesh]
                    .positions
                    .iter()
                    .map(|&p| (s.camera.view * d.transform).transform_point3(p).z);
                z.fold((f32::MAX, f32::MIN), |(lo, hi), z| (lo.min(z), hi.max(z)))
            })
            .collect();
        for pair in depths.windows(2) {
            assert!(
                pair[0].1 < pair[1].0,
                "layers overlap in depth or are out of order: {depths:?}"
            );
        }
        assert!(s
            .materials
            .iter()
            .all(|m| m.texture.is_none() && m.transmission == 0.0));
        assert!(s.transparent.iter().all(|d| !s.materials[d.material].lit));
        assert_eq!(
            centre_ray_depth(&s),
            8,
            "every layer should cover the centre"
        );
    }

    #[test]
    fn polychrome_has_coloured_transmittance() {
        let s = scene("polychrome");
        let tinted = s
            .transparent
            .iter()
            .filter(|d| {
                let m = &s.materials[d.material];
                m.transmission > 0.0
                    && m.transmission_tint.max_element() - m.transmission_tint.min_element() > 0.3
            })
            .count();
        assert_eq!(tinted, s.transparent.len());
    }
}
