//! RGBA8 textures with a full mip chain.

use crate::image::{linear_to_srgb, quantize, srgb_to_linear};

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
}
