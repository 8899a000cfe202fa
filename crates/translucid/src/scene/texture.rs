//! RGBA8 textures with a full mip chain, and sampling by Vulkan's rules.

use crate::image::{linear_to_srgb, quantize, srgb_to_linear};
use glam::{Vec2, Vec4};
use std::sync::OnceLock;

#[derive(Clone, Debug, PartialEq)]
pub struct Texture {
    pub name: String,
    /// Whether texels are sRGB-encoded (glTF base colour is) and decoded to linear on sampling.
    pub srgb: bool,
    /// Level 0 first; each level halves width and height (at least 1).
    pub levels: Vec<MipLevel>,
}

#[derive(Clone, Debug, PartialEq)]
pub struct MipLevel {
    pub width: u32,
    pub height: u32,
    pub texels: Vec<[u8; 4]>,
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
            texels,
        }];
        while let Some(prev) = levels.last().filter(|l| l.width > 1 || l.height > 1) {
            levels.push(downsample(prev, srgb));
        }
        Self {
            name: name.into(),
            srgb,
            levels,
        }
    }

    pub fn width(&self) -> u32 {
        self.levels[0].width
    }

    pub fn height(&self) -> u32 {
        self.levels[0].height
    }

    /// Samples like a Vulkan sampler with `REPEAT` addressing, `LINEAR` min/mag filters,
    /// `LINEAR` mipmap mode, `minLod = 0`, `maxLod = levels − 1`, at level of detail `lod`
    /// (as `textureLod` would; NaN counts as 0). Texels are decoded to linear (sRGB textures)
    /// before filtering. Returns linear RGBA.
    pub fn sample(&self, uv: Vec2, lod: f32) -> Vec4 {
        let Some(top) = self.levels.len().checked_sub(1) else {
            return Vec4::ONE;
        };
        let lod = if lod > 0.0 { lod.min(top as f32) } else { 0.0 };
        let level = lod.floor();
        let blend = lod - level;
        let d = level as usize;
        let lower = self.bilinear(d, uv);
        if blend == 0.0 || d >= top {
            return lower;
        }
        lower * (1.0 - blend) + self.bilinear(d + 1, uv) * blend
    }

    /// Bilinear filtering of one level with repeat addressing; texel centres at +0.5.
    fn bilinear(&self, level: usize, uv: Vec2) -> Vec4 {
        let l = &self.levels[level];
        let u = uv.x * l.width as f32 - 0.5;
        let v = uv.y * l.height as f32 - 0.5;
        let (i, j) = (u.floor(), v.floor());
        let (a, b) = (u - i, v - j);
        let wrap = |c: f32, size: u32| (c as i64).rem_euclid(size as i64) as u32;
        let (i0, j0) = (wrap(i, l.width), wrap(j, l.height));
        let (i1, j1) = ((i0 + 1) % l.width, (j0 + 1) % l.height);
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
        for (i, l) in self.levels.iter().enumerate() {
            let expect = ((base.width >> i).max(1), (base.height >> i).max(1));
            if (l.width, l.height) != expect || l.texels.len() != (l.width * l.height) as usize {
                return Err(format!("mip level {i} has the wrong size"));
            }
        }
        Ok(())
    }
}

/// `srgb_to_linear(i / 255)` for every byte: the decode table the sampler (and the GPU's
/// software sampler, which uploads it) uses.
pub fn srgb_lut() -> &'static [f32; 256] {
    static LUT: OnceLock<[f32; 256]> = OnceLock::new();
    LUT.get_or_init(|| std::array::from_fn(|i| srgb_to_linear(i as f32 / 255.0)))
}

fn downsample(prev: &MipLevel, srgb: bool) -> MipLevel {
    let width = (prev.width / 2).max(1);
    let height = (prev.height / 2).max(1);
    let decode = |v: u8| {
        let f = v as f32 / 255.0;
        if srgb {
            srgb_to_linear(f)
        } else {
            f
        }
    };
    let encode = |v: f32| quantize(if srgb { linear_to_srgb(v) } else { v });
    let mut texels = Vec::with_capacity((width * height) as usize);
    for y in 0..height {
        for x in 0..width {
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
            texels.push([
                encode(sum[0] / 4.0),
                encode(sum[1] / 4.0),
                encode(sum[2] / 4.0),
                quantize(sum[3] / 4.0),
            ]);
        }
    }
    MipLevel {
        width,
        height,
        texels,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

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
    fn srgb_is_decoded_before_filtering() {
        let t = Texture::new("t", 2, 1, vec![[0, 0, 0, 0], [188, 188, 188, 255]], true);
        let mid = t.sample(Vec2::new(0.5, 0.5), 0.0);
        let lin = srgb_to_linear(188.0 / 255.0);
        assert!(close(mid, Vec4::new(lin / 2.0, lin / 2.0, lin / 2.0, 0.5)));
    }

    #[test]
    fn lod_blends_levels_and_clamps() {
        // 2x2 level 0 of one value, 1x1 level 1 of another (set by hand).
        let mut t = Texture::new("t", 2, 2, vec![[0, 0, 0, 255]; 4], false);
        t.levels[1].texels[0] = [255, 255, 255, 255];
        let uv = Vec2::new(0.3, 0.8);
        assert!(close(t.sample(uv, -3.0), Vec4::new(0.0, 0.0, 0.0, 1.0)));
        assert!(close(t.sample(uv, f32::NAN), Vec4::new(0.0, 0.0, 0.0, 1.0)));
        assert!(close(t.sample(uv, 0.25), Vec4::new(0.25, 0.25, 0.25, 1.0)));
        assert!(close(t.sample(uv, 1.0), Vec4::ONE));
        assert!(close(t.sample(uv, 9.0), Vec4::ONE));
    }
}
