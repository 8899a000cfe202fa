//! `textured`: transparent quads whose colour and alpha come from textures, one for each way
//! sampling can go wrong. Magnified and strongly minified textures, a plane at a grazing
//! angle (footprints far longer than wide), UVs outside [0, 1] under repeat, clamp and
//! mirrored repeat, nearest and linear filters and every mipmap mode, alpha taken from the
//! texture, vertex colours times texels, lit and unlit, over a checkered wall and crossing
//! each other so that order matters.

use super::{back_wall, hue, lit_ground, Builder};
use crate::scene::{Camera, Filter, Material, Mesh, MipFilter, Sampler, Scene, Texture, Wrap};
use glam::{Vec2, Vec3, Vec4};

impl Builder {
    fn texture(&mut self, texture: Texture) -> usize {
        self.scene.textures.push(texture);
        self.scene.textures.len() - 1
    }
}

/// A `size`² sRGB checker of `cells`² cells in colours `a` and `b` (RGBA bytes).
fn checker_texture(name: &str, size: u32, cells: u32, a: [u8; 4], b: [u8; 4]) -> Texture {
    let cell = size / cells;
    let texels = (0..size * size)
        .map(|i| {
            let (x, y) = (i % size, i / size);
            if (x / cell + y / cell) % 2 == 0 {
                a
            } else {
                b
            }
        })
        .collect();
    Texture::new(name, size, size, texels, true)
}

/// A `size`² sRGB texture: hue across, brightness down, alpha rising along the diagonal.
fn gradient_texture(name: &str, size: u32) -> Texture {
    let texels = (0..size * size)
        .map(|i| {
            let (x, y) = ((i % size) as f32, (i / size) as f32);
            let s = size as f32;
            let rgb = hue(x / s) * (0.3 + 0.7 * y / s);
            let alpha = 0.25 + 0.75 * (x + y) / (2.0 * s);
            let byte = |v: f32| (v.clamp(0.0, 1.0) * 255.0).round() as u8;
            [byte(rgb.x), byte(rgb.y), byte(rgb.z), byte(alpha)]
        })
        .collect();
    Texture::new(name, size, size, texels, true)
}

/// A `size`² white sprite whose alpha falls off from its centre to 0 at its edge.
fn sprite_texture(size: u32) -> Texture {
    let texels = (0..size * size)
        .map(|i| {
            let centre = (size as f32 - 1.0) / 2.0;
            let d = Vec2::new((i % size) as f32 - centre, (i / size) as f32 - centre);
            let alpha = (1.0 - d.length() / centre).clamp(0.0, 1.0);
            [255, 255, 255, (alpha * 255.0).round() as u8]
        })
        .collect();
    Texture::new("sprite", size, size, texels, false)
}

/// One quad with corners in order around its edge, their UVs and colours, and the face's
/// normal at every corner.
fn textured_quad(name: &str, corners: [Vec3; 4], uvs: [Vec2; 4], colours: [Vec4; 4]) -> Mesh {
    let normal = (corners[1] - corners[0])
        .cross(corners[2] - corners[0])
        .normalize_or(Vec3::Z);
    Mesh {
        normals: Some(vec![normal; 4]),
        colours: Some(colours.to_vec()),
        uvs: Some(uvs.to_vec()),
        ..Mesh::from_quads(name, corners.to_vec(), vec![[0, 1, 2, 3]])
    }
}

/// UVs from `lo` to `hi` over a quad's corners (in the order of [`rect`]).
fn uv_span(lo: Vec2, hi: Vec2) -> [Vec2; 4] {
    [
        Vec2::new(lo.x, hi.y),
        Vec2::new(hi.x, hi.y),
        Vec2::new(hi.x, lo.y),
        Vec2::new(lo.x, lo.y),
    ]
}

/// A screen-facing rectangle at depth `z` from corner `lo` to `hi` (x, y).
fn rect(lo: Vec2, hi: Vec2, z: f32) -> [Vec3; 4] {
    [
        Vec3::new(lo.x, lo.y, z),
        Vec3::new(hi.x, lo.y, z),
        Vec3::new(hi.x, hi.y, z),
        Vec3::new(lo.x, hi.y, z),
    ]
}

fn material(name: &str, texture: usize, alpha: f32, lit: bool) -> Material {
    Material {
        name: name.into(),
        base_colour: Vec3::ONE.extend(alpha),
        texture: Some(texture),
        lit,
        ..Material::default()
    }
}

pub(super) fn textured() -> Scene {
    let camera = Camera::look_at(Vec3::new(0.0, 0.0, 6.0), Vec3::ZERO, 0.8, 0.5, 30.0);
    let mut b = Builder::new("textured", camera, Vec3::new(0.05, 0.05, 0.08));
    b.opaque(back_wall(-4.0, 16.0, 0.8, 0.4), lit_ground());
    let white = [Vec4::ONE; 4];

    // Magnified: a 16² red and white checker of 4² cells, a texel some 10 pixels wide at
    // 480×270.
    let checker = checker_texture("checker", 16, 4, [220, 40, 40, 255], [250, 250, 250, 255]);
    let t = b.texture(checker);
    let quad = textured_quad(
        "magnified",
        rect(Vec2::new(-4.2, 0.3), Vec2::new(-2.0, 2.4), 0.5),
        uv_span(Vec2::ZERO, Vec2::ONE),
        white,
    );
    b.transparent(quad, material("magnified", t, 0.7, false));

    // Nearest and magnified, UVs well outside [0, 1]: clamped across, mirrored down.
    let gradient = gradient_texture("gradient 4", 4).with_sampler(Sampler {
        wrap_s: Wrap::ClampToEdge,
        wrap_t: Wrap::MirroredRepeat,
        mag_filter: Filter::Nearest,
        ..Sampler::default()
    });
    let t = b.texture(gradient);
    let quad = textured_quad(
        "clamped and mirrored",
        rect(Vec2::new(-2.4, 0.1), Vec2::new(0.2, 2.3), 0.2),
        uv_span(Vec2::new(-0.63, -0.71), Vec2::new(1.77, 2.29)),
        white,
    );
    b.transparent(quad, material("clamped and mirrored", t, 0.6, true));

    // Minified many levels down: a 128² checker of 2-texel cells repeated 13 times across
    // about 90 pixels, with alpha from the texture (opaque and faint cells).
    let fine = checker_texture(
        "fine checker",
        128,
        64,
        [30, 90, 220, 255],
        [250, 230, 60, 70],
    );
    let t = b.texture(fine);
    let quad = textured_quad(
        "minified",
        rect(Vec2::new(0.3, 0.2), Vec2::new(2.6, 2.4), -1.0),
        uv_span(Vec2::new(0.17, -0.3), Vec2::new(13.4, 12.93)),
        white,
    );
    b.transparent(quad, material("minified", t, 1.0, false));

    // A floor at a grazing angle, repeated, nearest mip level: footprints far longer than
    // wide, level changing along its depth. Lit, with vertex colours.
    let floor_texture = gradient_texture("gradient 64", 64).with_sampler(Sampler {
        mip_filter: MipFilter::Nearest,
        ..Sampler::default()
    });
    let t = b.texture(floor_texture);
    let floor = textured_quad(
        "grazing floor",
        [
            Vec3::new(-5.0, -2.3, 3.5),
            Vec3::new(5.0, -2.3, 3.5),
            Vec3::new(5.0, -0.4, -4.0),
            Vec3::new(-5.0, -0.4, -4.0),
        ],
        uv_span(Vec2::new(-2.0, 0.0), Vec2::new(8.0, 24.0)),
        [
            Vec4::new(1.0, 0.8, 0.8, 1.0),
            Vec4::new(0.8, 1.0, 0.8, 1.0),
            Vec4::new(0.8, 0.8, 1.0, 1.0),
            Vec4::ONE,
        ],
    );
    b.transparent(floor, material("grazing floor", t, 0.55, true));

    // Minified without mipmaps, nearest: level 0 alone, aliasing as the file asks.
    let aliased = checker_texture("aliased", 64, 16, [250, 250, 250, 255], [20, 20, 20, 255])
        .with_sampler(Sampler {
            min_filter: Filter::Nearest,
            mip_filter: MipFilter::None,
            ..Sampler::default()
        });
    let t = b.texture(aliased);
    let quad = textured_quad(
        "unmipped",
        rect(Vec2::new(-2.2, -1.9), Vec2::new(-0.6, -0.5), 1.0),
        uv_span(Vec2::new(0.0, 0.0), Vec2::new(5.3, 4.1)),
        white,
    );
    b.transparent(quad, material("unmipped", t, 0.5, false));

    // Soft sprites: alpha from the texture times vertex colours, overlapping one another
    // and the minified quad, at staggered depths, submitted front to back.
    let t = b.texture(sprite_texture(32));
    for k in 0..5 {
        let f = k as f32;
        let centre = Vec2::new(2.4 + 0.45 * f, -1.4 + 0.6 * f);
        let half = Vec2::splat(0.9);
        let z = 1.2 - 0.7 * f;
        let colours = [0.0, 0.25, 0.5, 0.75].map(|h| hue(h + 0.13 * f).extend(0.9));
        let quad = textured_quad(
            &format!("sprite {k}"),
            rect(centre - half, centre + half, z),
            uv_span(Vec2::ZERO, Vec2::ONE),
            colours,
        );
        b.transparent(quad, material(&format!("sprite {k}"), t, 1.0, k % 2 == 0));
    }
    b.finish()
}
