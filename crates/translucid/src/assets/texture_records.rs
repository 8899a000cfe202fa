//! The software sampler's texture records (`BinTexture` of `shaders/common/bins_layout.glsl`,
//! checked there by `methods::bins::layout`'s tests): how the compute rasters find a
//! texture's texels and sample it.

#![deny(unsafe_code)]

use crate::scene::{Filter, MipFilter, Sampler, Texture, Wrap};
use bytemuck::{Pod, Zeroable};

#[repr(C)]
#[derive(Clone, Copy, Debug, Pod, Zeroable)]
pub struct BinTexture {
    pub first_texel: u32,
    pub width: u32,
    pub height: u32,
    pub levels: u32,
    pub srgb: u32,
    /// `SAMPLER_*` bits: [`sampler_bits`].
    pub sampler: u32,
    pub pad: [u32; 2],
}

pub const SAMPLER_WRAP_S_SHIFT: u32 = 0;
pub const SAMPLER_WRAP_T_SHIFT: u32 = 2;
pub const SAMPLER_WRAP_REPEAT: u32 = 0;
pub const SAMPLER_WRAP_CLAMP_TO_EDGE: u32 = 1;
pub const SAMPLER_WRAP_MIRRORED_REPEAT: u32 = 2;
pub const SAMPLER_MAG_LINEAR: u32 = 16;
pub const SAMPLER_MIN_LINEAR: u32 = 32;
pub const SAMPLER_MIP_SHIFT: u32 = 6;
pub const SAMPLER_MIP_NONE: u32 = 0;
pub const SAMPLER_MIP_NEAREST: u32 = 1;
pub const SAMPLER_MIP_LINEAR: u32 = 2;

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
        sampler: sampler_bits(&t.sampler),
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
