//! RGBA8 textures with a full mip chain, and sampling by Vulkan's rules.
//!
//! The rules, shared by this sampler, the compute stages' software sampler
//! (`shaders/common/texture_sampler.glsl`) and the hardware samplers the graphics passes use:
//!
//! - The level of detail is `λ = log2 ρ`, `ρ` the larger length of the UV's screen-space
//!   derivatives in level-0 texels. `λ ≤ 0` magnifies (the mag filter at level 0); `λ > 0`
//!   minifies (the min filter, at the levels its mipmap mode picks: level 0 without mipmaps,
//!   the nearest level, rounding halves down, or the two levels around `λ`, blended).
//! - Within a level, NEAREST takes the texel holding the sample and LINEAR weighs the four
//!   around it by their centres (at +0.5 texel).
//! - Each texel coordinate is wrapped on its own axis by the sampler's wrap mode: REPEAT,
//!   CLAMP_TO_EDGE or MIRRORED_REPEAT.
//! - sRGB texels are decoded to linear before filtering; mips are built in linear light.

use crate::image::{quantize, srgb_to_linear};
use glam::{Vec2, Vec4};
use rayon::prelude::*;
use std::sync::OnceLock;

/// How a texture coordinate outside [0, 1] maps into the texture (glTF `wrapS`/`wrapT`).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum Wrap {
    #[default]
    Repeat,
    ClampToEdge,
    MirroredRepeat,
}

/// Filtering within a level (glTF `magFilter`, and `minFilter`'s first half).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum Filter {
    Nearest,
    #[default]
    Linear,
}

/// Filtering between levels when minifying (`minFilter`'s second half).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum MipFilter {
    /// Level 0 only (glTF `NEAREST` and `LINEAR` min filters).
    None,
    /// The nearest level (`*_MIPMAP_NEAREST`).
    Nearest,
    /// The two nearest levels, blended (`*_MIPMAP_LINEAR`).
    #[default]
    Linear,
}

/// A texture's sampler. The default, trilinear with REPEAT, is what glTF suggests when a
/// file names no sampler or leaves a field out.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub struct Sampler {
    pub wrap_s: Wrap,
    pub wrap_t: Wrap,
    pub mag_filter: Filter,
    pub min_filter: Filter,
    pub mip_filter: MipFilter,
}

/// Largest texture width or height, as in the C API: an 8192² RGBA8 texture with its mips
/// takes 358 MB, and the software sampler's texel buffer holds 128 MB on lavapipe. Larger
/// images are refused from their header, before decoding.
pub const MAX_TEXTURE_SIZE: u32 = 8192;

/// Largest number of level-0 texels a scene's textures hold in all: two textures of the
/// largest size, or 32 of 2048² (the real scenes beside the project use at most 20 M).
/// Each texture counts once, whatever shares its image. It bounds import's memory (textures
/// and decoded images) and time. Checked from image headers, before anything is decoded.
pub const MAX_SCENE_TEXELS: u64 = 2 * (MAX_TEXTURE_SIZE as u64) * (MAX_TEXTURE_SIZE as u64);

#[derive(Clone, Debug, PartialEq)]
pub struct Texture {
    pub name: String,
    /// Whether texels are sRGB-encoded (glTF base colour is) and decoded to linear on sampling.
    pub srgb: bool,
    pub sampler: Sampler,
    /// Level 0 first; each level halves width and height (at least 1).
    pub levels: Vec<MipLevel>,
}

impl Texture {
    /// Bytes of its texels (RGBA8) over every level.
    pub fn texel_bytes(&self) -> u64 {
        self.levels.iter().map(|l| l.texels.len() as u64 * 4).sum()
    }

    /// The texture's name, sampler and level sizes, without texels.
    pub fn without_texels(&self) -> Self {
        Self {
            name: self.name.clone(),
            srgb: self.srgb,
            sampler: self.sampler,
            levels: self
                .levels
                .iter()
                .map(|l| MipLevel {
                    width: l.width,
                    height: l.height,
                    texels: Default::default(),
                })
                .collect(),
        }
    }
}

#[derive(Clone, Debug, PartialEq)]
pub struct MipLevel {
    pub width: u32,
    pub height: u32,
    /// Shared: a scene (or a C context's assets, each time a renderer is made over them)
    /// clones its textures without copying their texels.
    pub texels: std::sync::Arc<Vec<[u8; 4]>>,
}

impl Texture {
    /// A texture from level-0 texels, with mips built by a 2x2 box filter (in linear light for
    /// sRGB textures, so that mips do not darken).
    pub fn new(
        name: impl Into<String>,
        width: u32,
        height: u32,
        texels: Vec<[u8; 4]>,
        srgb: bool,
    ) -> Self {
        let mut levels = vec![MipLevel {
            width,
            height,
            texels: texels.into(),
        }];
        while let Some(prev) = levels.last().filter(|l| l.width > 1 || l.height > 1) {
            levels.push(downsample(prev, srgb));
        }
        Self {
            name: name.into(),
            srgb,
            sampler: Sampler::default(),
            levels,
        }
    }

    /// The same texture with another sampler.
    pub fn with_sampler(self, sampler: Sampler) -> Self {
        Self { sampler, ..self }
    }

    pub fn width(&self) -> u32 {
        self.levels[0].width
    }

    pub fn height(&self) -> u32 {
        self.levels[0].height
    }

    /// Samples like a Vulkan sampler made from [`Self::sampler`] (`minLod = 0`, `maxLod` the
    /// last level, or 0.25 without mipmaps, as Vulkan advises for glTF's non-mipmapped
    /// filters) at level of detail `lod`, as `textureLod` would; NaN counts as 0. Texels are
    /// decoded to linear (sRGB textures) before filtering. Returns linear RGBA.
    pub fn sample(&self, uv: Vec2, lod: f32) -> Vec4 {
        let Some(top) = self.levels.len().checked_sub(1) else {
            return Vec4::ONE;
        };
        let s = self.sampler;
        // Magnified at λ ≤ 0, and at NaN.
        if lod.partial_cmp(&0.0) != Some(std::cmp::Ordering::Greater) {
            return self.filter(0, uv, s.mag_filter);
        }
        let lod = lod.min(top as f32);
        match s.mip_filter {
            MipFilter::None => self.filter(0, uv, s.min_filter),
            // Vulkan's d = ceil(λ + 0.5) − 1: halves round down.
            MipFilter::Nearest => self.filter(nearest_level(lod), uv, s.min_filter),
            MipFilter::Linear => {
                let level = lod.floor();
                let blend = lod - level;
                let d = level as usize;
                let lower = self.filter(d, uv, s.min_filter);
                if blend == 0.0 || d >= top {
                    return lower;
                }
                lower * (1.0 - blend) + self.filter(d + 1, uv, s.min_filter) * blend
            }
        }
    }

    /// One level, nearest or bilinear; texel centres at +0.5, each axis wrapped on its own.
    fn filter(&self, level: usize, uv: Vec2, filter: Filter) -> Vec4 {
        let l = &self.levels[level];
        let linear = filter == Filter::Linear;
        let shift = if linear { 0.5 } else { 0.0 };
        let u = uv.x * l.width as f32 - shift;
        let v = uv.y * l.height as f32 - shift;
        let (i, j) = (u.floor(), v.floor());
        let (a, b) = if linear { (u - i, v - j) } else { (0.0, 0.0) };
        let (ws, wt) = (self.sampler.wrap_s, self.sampler.wrap_t);
        let (i, j) = (saturate(i), saturate(j));
        let (i0, i1) = (wrap(ws, i, l.width), wrap(ws, i + 1, l.width));
        let (j0, j1) = (wrap(wt, j, l.height), wrap(wt, j + 1, l.height));
        let t = |x: u32, y: u32| self.decode(l.texels[(y * l.width + x) as usize]);
        (t(i0, j0) * (1.0 - a) + t(i1, j0) * a) * (1.0 - b)
            + (t(i0, j1) * (1.0 - a) + t(i1, j1) * a) * b
    }

    /// A texel as linear RGBA in 0..=1.
    fn decode(&self, t: [u8; 4]) -> Vec4 {
        let unorm = |v: u8| v as f32 / 255.0;
        let colour = |v: u8| {
            if self.srgb {
                srgb_lut()[v as usize]
            } else {
                unorm(v)
            }
        };
        Vec4::new(colour(t[0]), colour(t[1]), colour(t[2]), unorm(t[3]))
    }

    pub fn validate(&self) -> Result<(), String> {
        let Some(base) = self.levels.first() else {
            return Err("texture has no levels".into());
        };
        if base.width == 0 || base.height == 0 {
            return Err("texture has zero size".into());
        }
        if base.width > MAX_TEXTURE_SIZE || base.height > MAX_TEXTURE_SIZE {
            return Err(format!(
                "texture is {}x{}; the largest width or height is {MAX_TEXTURE_SIZE}",
                base.width, base.height
            ));
        }
        for (i, l) in self.levels.iter().enumerate() {
            let expect = ((base.width >> i).max(1), (base.height >> i).max(1));
            if (l.width, l.height) != expect || l.texels.len() != (l.width * l.height) as usize {
                return Err(format!("mip level {i} has the wrong size"));
            }
        }
        Ok(())
    }
}

/// The level Vulkan's NEAREST mipmap mode picks at level of detail `lod` (in `(0, top]`).
fn nearest_level(lod: f32) -> usize {
    ((lod + 0.5).ceil() - 1.0) as usize
}

/// A texel coordinate as an integer: the float-to-i64 cast saturates, and the bounds leave
/// room for `+ 1` and for mirroring's doubled size.
fn saturate(c: f32) -> i64 {
    c.clamp(-4.0e18, 4.0e18) as i64
}

/// Texel coordinate `i` wrapped into `0..size`.
fn wrap(mode: Wrap, i: i64, size: u32) -> u32 {
    let n = i64::from(size);
    let wrapped = match mode {
        Wrap::Repeat => i.rem_euclid(n),
        Wrap::ClampToEdge => i.clamp(0, n - 1),
        Wrap::MirroredRepeat => {
            let r = i.rem_euclid(2 * n);
            if r < n {
                r
            } else {
                2 * n - 1 - r
            }
        }
    };
    wrapped as u32
}

/// `srgb_to_linear(i / 255)` for every byte: the decode table the sampler (and the GPU's
/// software sampler, which uploads it) uses.
pub fn srgb_lut() -> &'static [f32; 256] {
    static LUT: OnceLock<[f32; 256]> = OnceLock::new();
    LUT.get_or_init(|| std::array::from_fn(|i| srgb_to_linear(i as f32 / 255.0)))
}

/// The sRGB byte nearest in display encoding to linear `v`: `quantize(linear_to_srgb(v))`
/// without a power function, from the linear values where rounding moves to the next byte
/// (`steps`) and a table of where each 1/4096 of the range starts among them. (The mips of
/// an 8192² sRGB texture took 64 M power calls, then as many binary searches.)
fn encode_srgb(v: f32) -> u8 {
    const BINS: usize = 4096;
    struct Tables {
        steps: [f32; 255],
        first: [u8; BINS + 1],
    }
    static TABLES: OnceLock<Tables> = OnceLock::new();
    let t = TABLES.get_or_init(|| {
        let steps = std::array::from_fn(|k| srgb_to_linear((k as f32 + 0.5) / 255.0));
        let first = std::array::from_fn(|i| {
            let start = i as f32 / BINS as f32;
            steps.partition_point(|&step| step < start) as u8
        });
        Tables { steps, first }
    });
    if v.is_nan() || v < 0.0 {
        return 0; // as quantize does
    }
    let bin = ((v * BINS as f32) as usize).min(BINS);
    // Steps under the bin's start are at most v; the bin holds at most a few more.
    let mut byte = t.first[bin] as usize;
    while byte < t.steps.len() && t.steps[byte] <= v {
        byte += 1;
    }
    byte as u8
}

fn downsample(prev: &MipLevel, srgb: bool) -> MipLevel {
    let width = (prev.width / 2).max(1);
    let height = (prev.height / 2).max(1);
    let lut = srgb_lut();
    let decode = |v: u8| {
        if srgb {
            lut[v as usize]
        } else {
            v as f32 / 255.0
        }
    };
    let encode = |v: f32| if srgb { encode_srgb(v) } else { quantize(v) };
    // Rows in parallel: large textures' mips are most of a scene's import time.
    let mut texels = vec![[0u8; 4]; (width * height) as usize];
    texels
        .par_chunks_mut(width as usize)
        .enumerate()
        .for_each(|(y, row)| {
            let y = y as u32;
            for (x, out) in (0..width).zip(row) {
                let mut sum = [0.0f32; 4];
                for (dx, dy) in [(0, 0), (1, 0), (0, 1), (1, 1)] {
                    let sx = (2 * x + dx).min(prev.width - 1);
                    let sy = (2 * y + dy).min(prev.height - 1);
                    let t = prev.texels[(sy * prev.width + sx) as usize];
                    for c in 0..3 {
                        sum[c] += decode(t[c]);
                    }
                    sum[3] += t[3] as f32 / 255.0;
                }
                *out = [
                    encode(sum[0] / 4.0),
                    encode(sum[1] / 4.0),
                    encode(sum[2] / 4.0),
                    quantize(sum[3] / 4.0),
                ];
            }
        });
    MipLevel {
        width,
        height,
        texels: texels.into(),
    }
}

#[cfg(test)]
mod tests {
    use super::hand_cases::{hand_cases, levels};
    use super::*;
    use glam::Vec3;

    /// The power-free sRGB encoding rounds as the transfer function does, but within float
    /// noise of a rounding step.
    #[test]
    fn srgb_encoding_matches_the_transfer_function() {
        use crate::image::linear_to_srgb;
        let mut differing = 0;
        for i in 0..=100_000 {
            let v = i as f32 / 100_000.0;
            let exact = quantize(linear_to_srgb(v));
            if encode_srgb(v) != exact {
                let step = srgb_to_linear((exact.min(encode_srgb(v)) as f32 + 0.5) / 255.0);
                assert!(
                    (v - step).abs() < 1e-6,
                    "{v}: {} vs {exact}",
                    encode_srgb(v)
                );
                differing += 1;
            }
        }
        assert!(differing < 10, "{differing}");
        assert_eq!(encode_srgb(-1.0), 0);
        assert_eq!(encode_srgb(2.0), 255);
        assert_eq!(encode_srgb(f32::NAN), quantize(f32::NAN));
    }

    #[test]
    fn mip_chain_reaches_one_texel() {
        let t = Texture::new("t", 5, 3, vec![[255, 0, 0, 255]; 15], true);
        let sizes: Vec<_> = t.levels.iter().map(|l| (l.width, l.height)).collect();
        assert_eq!(sizes, vec![(5, 3), (2, 1), (1, 1)]);
        assert_eq!(t.levels[2].texels[0], [255, 0, 0, 255]);
        t.validate().expect("valid");
    }

    fn close(a: Vec4, b: Vec4) -> bool {
        (a - b).abs().max_element() < 1e-6
    }

    #[test]
    fn bilinear_repeat_weights_texel_centres() {
        // 2x1 linear texture: black, white. At u = 0.5 we sit between the two centres
        // (0.25, 0.75) -> 0.5; at u = 0 (and u = 1) between texel 1 (wrapped) and texel 0.
        let t = Texture::new("t", 2, 1, vec![[0, 0, 0, 0], [255, 255, 255, 255]], false);
        assert!(close(t.sample(Vec2::new(0.25, 0.5), 0.0), Vec4::ZERO));
        assert!(close(t.sample(Vec2::new(0.75, 0.5), 0.0), Vec4::ONE));
        assert!(close(t.sample(Vec2::new(0.5, 0.5), 0.0), Vec4::splat(0.5)));
        assert!(close(t.sample(Vec2::new(0.0, 0.5), 0.0), Vec4::splat(0.5)));
        assert!(close(
            t.sample(Vec2::new(0.375, 0.5), 0.0),
            Vec4::splat(0.25)
        ));
        assert!(close(
            t.sample(Vec2::new(-1.625, 7.5), 0.0),
            Vec4::splat(0.25)
        ));
    }

    #[test]
    fn lod_blends_levels_and_clamps() {
        // 2x2 level 0 of one value, 1x1 level 1 of another (set by hand).
        let mut t = Texture::new("t", 2, 2, vec![[0, 0, 0, 255]; 4], false);
        std::sync::Arc::make_mut(&mut t.levels[1].texels)[0] = [255, 255, 255, 255];
        let uv = Vec2::new(0.3, 0.8);
        assert!(close(t.sample(uv, -3.0), Vec4::new(0.0, 0.0, 0.0, 1.0)));
        assert!(close(t.sample(uv, f32::NAN), Vec4::new(0.0, 0.0, 0.0, 1.0)));
        assert!(close(t.sample(uv, 0.25), Vec4::new(0.25, 0.25, 0.25, 1.0)));
        assert!(close(t.sample(uv, 1.0), Vec4::ONE));
        assert!(close(t.sample(uv, 9.0), Vec4::ONE));
    }

    #[test]
    fn every_mode_matches_values_computed_by_hand() {
        for case in hand_cases() {
            let got = case.texture.sample(case.uv, case.lod);
            assert!(
                (got.truncate() - Vec3::splat(case.want))
                    .abs()
                    .max_element()
                    < 1e-6,
                "{}: got {got}, want {}",
                case.what,
                case.want
            );
        }
    }

    #[test]
    fn ties_and_nan_follow_vulkan() {
        // Nearest mipmap mode at λ = 0.5: ceil(1.0) − 1 = level 0; NaN magnifies.
        let t = levels(MipFilter::Nearest);
        assert_eq!(t.sample(Vec2::new(0.3, 0.6), 0.5).x, 0.0);
        let pair =
            Texture::new("pair", 2, 1, vec![[0; 4], [255; 4]], false).with_sampler(Sampler {
                mag_filter: Filter::Nearest,
                ..Sampler::default()
            });
        assert_eq!(pair.sample(Vec2::new(0.375, 0.5), f32::NAN).x, 0.0);
    }
}

/// Sampling cases whose results were worked out by hand, one or more for every wrap mode,
/// filter and mipmap mode. The GPU samplers' test (`renderer::sampling_tests`) runs them too.
#[cfg(test)]
pub(crate) mod hand_cases {
    use super::*;

    pub(crate) struct HandCase {
        pub what: String,
        pub texture: Texture,
        pub uv: Vec2,
        pub lod: f32,
        /// Every colour channel's value.
        pub want: f32,
    }

    /// A 4×1 linear ramp 0, 1/3, 2/3, 1 (every channel) sampled with `sampler`.
    fn ramp(sampler: Sampler) -> Texture {
        let texels = [0u8, 85, 170, 255].map(|v| [v; 4]).to_vec();
        Texture::new("ramp", 4, 1, texels, false).with_sampler(sampler)
    }

    /// 4×4 with levels of one value each, set by hand: 0, 0.4, 1.
    pub(crate) fn levels(mip_filter: MipFilter) -> Texture {
        let mut t = Texture::new("levels", 4, 4, vec![[0, 0, 0, 255]; 16], false);
        std::sync::Arc::make_mut(&mut t.levels[1].texels).fill([102, 102, 102, 255]);
        std::sync::Arc::make_mut(&mut t.levels[2].texels).fill([255, 255, 255, 255]);
        t.with_sampler(Sampler {
            mip_filter,
            ..Sampler::default()
        })
    }

    const WRAPS: [(Wrap, &str); 3] = [
        (Wrap::Repeat, "repeat"),
        (Wrap::ClampToEdge, "clamp"),
        (Wrap::MirroredRepeat, "mirror"),
    ];

    pub(crate) fn hand_cases() -> Vec<HandCase> {
        let mut out = Vec::new();
        let mut case = |what: String, texture: &Texture, uv: Vec2, lod: f32, want: f32| {
            out.push(HandCase {
                what,
                texture: texture.clone(),
                uv,
                lod,
                want,
            })
        };

        // NEAREST: the floor of u · 4, wrapped, picks the texel (values i / 3).
        let nearest = [
            // (u, texel under repeat, clamp, mirrored repeat)
            (0.1, [0, 0, 0]),
            (0.9, [3, 3, 3]),
            (1.1, [0, 3, 3]),  // 4.4 -> 4
            (1.3, [1, 3, 2]),  // 5.2 -> 5
            (2.1, [0, 3, 0]),  // 8.4 -> 8
            (-0.1, [3, 0, 0]), // -0.4 -> -1
            (-0.3, [2, 0, 1]), // -1.2 -> -2
            (-1.9, [0, 0, 0]), // -7.6 -> -8, a whole mirrored period
        ];
        for (u, texels) in nearest {
            for ((wrap, name), texel) in WRAPS.into_iter().zip(texels) {
                let t = ramp(Sampler {
                    wrap_s: wrap,
                    mag_filter: Filter::Nearest,
                    ..Sampler::default()
                });
                let want = texel as f32 / 3.0;
                case(
                    format!("nearest {name} at u {u}"),
                    &t,
                    Vec2::new(u, 0.5),
                    0.0,
                    want,
                );
            }
        }

        // LINEAR: u · 4 − 0.5 = i + a weighs texels i and i + 1, each wrapped, by 1 − a and a.
        let linear = [
            // (u, value under repeat, clamp, mirrored repeat)
            (0.0, [0.5, 0.0, 0.0]),   // -0.5: texels -1, 0 at 0.5 each
            (1.0, [0.5, 1.0, 1.0]),   // 3.5: texels 3, 4
            (1.125, [0.0, 1.0, 1.0]), // 4.0: texel 4 alone
            (1.25, [1.0 / 6.0, 1.0, 5.0 / 6.0]), // 4.5: texels 4, 5
            (-0.125, [1.0, 0.0, 0.0]), // -1.0: texel -1 alone
            (0.3125, [0.25, 0.25, 0.25]), // 0.75: texels 0, 1 at 0.25, 0.75
        ];
        for (u, values) in linear {
            for ((wrap, name), want) in WRAPS.into_iter().zip(values) {
                let t = ramp(Sampler {
                    wrap_s: wrap,
                    ..Sampler::default()
                });
                case(
                    format!("linear {name} at u {u}"),
                    &t,
                    Vec2::new(u, 0.5),
                    0.0,
                    want,
                );
            }
        }

        // Each axis has its own mode: a 1×4 column ramp repeated along s, clamped along t.
        let texels = [0u8, 85, 170, 255].map(|v| [v; 4]).to_vec();
        let column = Texture::new("column", 1, 4, texels, false).with_sampler(Sampler {
            wrap_s: Wrap::Repeat,
            wrap_t: Wrap::ClampToEdge,
            mag_filter: Filter::Nearest,
            ..Sampler::default()
        });
        case(
            "clamped t above".into(),
            &column,
            Vec2::new(7.3, 1.1),
            0.0,
            1.0,
        );
        case(
            "clamped t below".into(),
            &column,
            Vec2::new(-7.3, -0.1),
            0.0,
            0.0,
        );

        // Mipmap modes on levels of 0, 0.4 and 1.
        let uv = Vec2::new(0.3, 0.6);
        let t = levels(MipFilter::Linear);
        case("mip linear at 1.25".into(), &t, uv, 1.25, 0.75 * 0.4 + 0.25);
        case("mip linear at 0.5".into(), &t, uv, 0.5, 0.2);
        case("mip linear past the last level".into(), &t, uv, 7.0, 1.0);
        let t = levels(MipFilter::Nearest);
        // d = ceil(λ + 0.5) − 1
        for (lod, want) in [(0.4, 0.0), (0.6, 0.4), (1.4, 0.4), (1.6, 1.0), (9.0, 1.0)] {
            case(format!("mip nearest at {lod}"), &t, uv, lod, want);
        }
        let t = levels(MipFilter::None);
        case("no mipmaps at 3".into(), &t, uv, 3.0, 0.0);

        // Mag and min filters split at λ = 0: a 2×1 black, white at u = 0.375 is 0.25
        // bilinear and black nearest.
        let pair = |mag_filter, min_filter| {
            Texture::new("pair", 2, 1, vec![[0; 4], [255; 4]], false).with_sampler(Sampler {
                mag_filter,
                min_filter,
                mip_filter: MipFilter::None,
                ..Sampler::default()
            })
        };
        let uv = Vec2::new(0.375, 0.5);
        let t = pair(Filter::Nearest, Filter::Linear);
        case("λ = 0 magnifies".into(), &t, uv, 0.0, 0.0);
        case("λ < 0 magnifies".into(), &t, uv, -2.0, 0.0);
        case("λ > 0 minifies".into(), &t, uv, 0.1, 0.25);
        let t = pair(Filter::Linear, Filter::Nearest);
        case("magnified, linear".into(), &t, uv, -1.0, 0.25);
        case("minified, nearest".into(), &t, uv, 2.0, 0.0);

        // sRGB texels are decoded before filtering: halfway between black and sRGB 188.
        let srgb = Texture::new(
            "srgb",
            2,
            1,
            vec![[0, 0, 0, 255], [188, 188, 188, 255]],
            true,
        );
        let half = srgb_to_linear(188.0 / 255.0) / 2.0;
        case(
            "sRGB decoded first".into(),
            &srgb,
            Vec2::new(0.5, 0.5),
            0.0,
            half,
        );
        out
    }
}
