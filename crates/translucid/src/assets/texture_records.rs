//! The software sampler's texture records (`BinTexture`, declared in
//! [`crate::interface::bins`]): how the compute rasters find a texture's texels and sample it.

#![deny(unsafe_code)]

use crate::scene::{Filter, MipFilter, Sampler, Texture, Wrap};

pub use crate::interface::bins::{
    BinTexture, SAMPLER_MAG_LINEAR, SAMPLER_MIN_LINEAR, SAMPLER_MIP_LINEAR, SAMPLER_MIP_NEAREST,
    SAMPLER_MIP_NONE, SAMPLER_MIP_SHIFT, SAMPLER_WRAP_CLAMP_TO_EDGE, SAMPLER_WRAP_MIRRORED_REPEAT,
    SAMPLER_WRAP_REPEAT, SAMPLER_WRAP_S_SHIFT, SAMPLER_WRAP_T_SHIFT,
};

/// A texture's sampler as the software sampler's word (`BinTexture.samplerBits`).
pub fn sampler_bits(s: &Sampler) -> u32 {
    let wrap = |w: Wrap| match w {
        Wrap::Repeat => SAMPLER_WRAP_REPEAT,
        Wrap::ClampToEdge => SAMPLER_WRAP_CLAMP_TO_EDGE,
        Wrap::MirroredRepeat => SAMPLER_WRAP_MIRRORED_REPEAT,
    };
    let linear = |f: Filter, bit: u32| if f == Filter::Linear { bit } else { 0 };
    let mip = match s.mip_filter {
        MipFilter::None => SAMPLER_MIP_NONE,
        MipFilter::Nearest => SAMPLER_MIP_NEAREST,
        MipFilter::Linear => SAMPLER_MIP_LINEAR,
    };
    wrap(s.wrap_s) << SAMPLER_WRAP_S_SHIFT
        | wrap(s.wrap_t) << SAMPLER_WRAP_T_SHIFT
        | linear(s.mag_filter, SAMPLER_MAG_LINEAR)
        | linear(s.min_filter, SAMPLER_MIN_LINEAR)
        | mip << SAMPLER_MIP_SHIFT
}

/// Texture `t`'s record, its texels starting at texel `first_texel` of the packed buffer.
pub(crate) fn bin_texture(t: &Texture, first_texel: u32) -> BinTexture {
    BinTexture {
        first_texel,
        width: t.width(),
        height: t.height(),
        levels: t.levels.len() as u32,
        srgb: u32::from(t.srgb),
        sampler_bits: sampler_bits(&t.sampler),
        pad: [0; 2],
    }
}

/// Every level's texels of `t`, packed RGBA8, level 0 first.
pub(crate) fn level_texels(t: &Texture) -> impl Iterator<Item = u32> + '_ {
    t.levels
        .iter()
        .flat_map(|level| level.texels.iter().map(|&t| u32::from_le_bytes(t)))
}

/// Records and texels of `textures`, packed one after another.
#[cfg(test)]
pub(crate) fn texture_data(textures: &[Texture]) -> (Vec<BinTexture>, Vec<u32>) {
    let mut infos = Vec::with_capacity(textures.len());
    let mut texels = Vec::new();
    for t in textures {
        infos.push(bin_texture(t, texels.len() as u32));
        texels.extend(level_texels(t));
    }
    (infos, texels)
}
