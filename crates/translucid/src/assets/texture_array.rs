//! The assets' first textures in one descriptor set, by texture index, for the bin rasters
//! that sample in hardware (`HARDWARE_SAMPLING`, docs/gpu.md): each texture's own image and
//! sampler, as the graphics passes bind them one at a time.

#![deny(unsafe_code)]

use super::resident::ResidentTexture;
use crate::gpu::{vk, DescriptorLayout, DescriptorSet, Gpu, Resource};
use crate::interface::bins::{TEXTURE_ARRAY_SET, TEXTURE_ARRAY_SLOTS};
use crate::Result;
use std::sync::Arc;

/// Sampled images a bin raster binds besides the array (its texel views), with room to
/// spare: a device that cannot bind as many with the array samples in software.
const RASTER_OWN_SAMPLED_IMAGES: u32 = 32;
/// Samplers a bin raster binds besides the array (the opaque depth's).
const RASTER_OWN_SAMPLERS: u32 = 1;

pub struct TextureArray {
    /// Declared first: freed before the images its descriptors name.
    pub set: DescriptorSet,
    pub layout: DescriptorLayout,
    /// Textures the array holds: indices below this.
    pub textures: usize,
    _textures: Vec<Arc<ResidentTexture>>,
}

impl TextureArray {
    /// The set of the first TEXTURE_ARRAY_SLOTS of `textures` by index, `white` in the slots
    /// past them; `None` where a compute stage cannot bind that many samplers besides the
    /// rasters' own (such frames sample in software). Made without textures too, so that
    /// the rasters keep their variant when the first texture streams in.
    pub(super) fn new(
        gpu: &Gpu,
        textures: &[Arc<ResidentTexture>],
        white: &Arc<ResidentTexture>,
    ) -> Result<Option<Self>> {
        let info = gpu.info();
        if info.max_stage_samplers < TEXTURE_ARRAY_SLOTS + RASTER_OWN_SAMPLERS
            || info.max_stage_sampled_images < TEXTURE_ARRAY_SLOTS + RASTER_OWN_SAMPLED_IMAGES
        {
            return Ok(None);
        }
        let layout =
            DescriptorLayout::declared(gpu, &TEXTURE_ARRAY_SET, vk::ShaderStageFlags::COMPUTE)?;
        let slots = TEXTURE_ARRAY_SLOTS as usize;
        let held: Vec<Arc<ResidentTexture>> = textures
            .iter()
            .take(slots)
            .chain(std::iter::once(white))
            .cloned()
            .collect();
        let descriptors: Vec<(vk::ImageView, vk::Sampler)> = (0..slots)
            .map(|i| textures.get(i).unwrap_or(white).descriptor())
            .collect();
        let set =
            layout.create_named_set(&[("u_textureArray", Resource::Textures(&descriptors))])?;
        Ok(Some(Self {
            set,
            layout,
            textures: textures.len().min(slots),
            _textures: held,
        }))
    }

    /// Whether the array holds every texture `scene`'s transparent draws use.
    pub fn holds_textures_of(&self, scene: &crate::scene::Scene) -> bool {
        super::sampled::scene_textures(scene)
            .flatten()
            .all(|t| t < self.textures)
    }
}
