//! The textures as the compute rasters' software sampler reads them: a record per texture,
//! found by texture index, and every level's texels packed RGBA8 into one buffer read through
//! a texel view. Only textures a frame's transparent draws use are copied, when a frame first
//! uses them: an engine's textures are mostly on opaque surfaces, which the graphics passes
//! sample from their images, and a second copy of them all cost exact more memory than a
//! linked-list method uses in all (48 MB of StainedGlassLamp's 77, none of it sampled).
//!
//! One set of buffers is shared by every renderer over the same assets. A texture is added
//! in place when it fits: its texels go past every byte written before and its record was
//! never read, so no frame in flight is written under. One that does not fit makes a new,
//! larger set, which each renderer binds from its next frame on, keeping the old one until
//! its frames in flight have completed. The buffers are device-local, written by uploads
//! (`gpu::staging`): at once on translucid's own device, by the frame that first uses the
//! textures on an engine's (it is recorded after them).

use super::texture_records::{bin_texture, level_texels, BinTexture};
use super::SCENE_STORAGE;
use crate::gpu::{vk, AppendBuffer, Gpu, Upload, Uploads};
use crate::scene::{srgb_lut, Scene, Texture};
use crate::{Error, Result};
use bytemuck::Zeroable;
use std::sync::Arc;

const RECORD_BYTES: u64 = std::mem::size_of::<BinTexture>() as u64;
/// Texel room a set is made with beyond what it holds, at least: textures a later frame
/// first uses are added in place until it runs out.
const SPARE_TEXEL_BYTES: u64 = 64 << 10;

/// The buffers one set of sampled textures lives in.
pub struct SampledBuffers {
    /// One record per texture index up to the capacity: zero until the texture is packed.
    records: AppendBuffer,
    record_capacity: usize,
    texels: AppendBuffer,
    srgb: AppendBuffer,
}

/// What a renderer binds: the views of one set of buffers, which it keeps alive while bound.
#[derive(Clone)]
pub struct SampledViews {
    pub records: vk::BufferView,
    pub texels: vk::BufferView,
    pub srgb: vk::BufferView,
    pub buffers: Arc<SampledBuffers>,
}

impl SampledViews {
    /// Whether these are the views of `other`'s buffers.
    pub fn same_buffers(&self, other: &Self) -> bool {
        Arc::ptr_eq(&self.buffers, &other.buffers)
    }
}

/// The current set of buffers and which textures it holds (kept behind the assets' lock).
pub struct SampledTextures {
    buffers: Arc<SampledBuffers>,
    /// Per texture index: whether its texels are in `buffers`.
    packed: Vec<bool>,
}

impl SampledTextures {
    /// A set holding the textures of `textures` (the assets', with their texels) that
    /// `scene`'s transparent draws use, uploaded through `uploads`.
    pub fn new(gpu: &Gpu, uploads: &Uploads, textures: &[Texture], scene: &Scene) -> Result<Self> {
        let used = used_textures(textures, scene)?;
        Self::holding(gpu, uploads, textures, &used)
    }

    /// A set holding the textures of `used` (indices into `textures`).
    fn holding(gpu: &Gpu, uploads: &Uploads, textures: &[Texture], used: &[usize]) -> Result<Self> {
        let mut packed = vec![false; textures.len()];
        for &t in used {
            packed[t] = true;
        }
        let bytes: u64 = packed_textures(textures, &packed)
            .map(Texture::texel_bytes)
            .sum();
        let most = most_texel_bytes(gpu);
        if bytes > most {
            return Err(Error::TooLarge(format!(
                "the textures of the transparent draws take {} MB, over the {} MB this \
                 device's texel views hold",
                bytes >> 20,
                most >> 20
            )));
        }
        let record_capacity = textures.len() + textures.len() / 2 + 16;
        let mut records = vec![BinTexture::zeroed(); record_capacity];
        let mut texels = Vec::with_capacity((bytes / 4) as usize);
        for (index, texture) in textures.iter().enumerate().filter(|(i, _)| packed[*i]) {
            records[index] = bin_texture(texture, texels.len() as u32);
            texels.extend(texels_of(texture)?);
        }
        let texel_capacity = (bytes + bytes / 4 + SPARE_TEXEL_BYTES).min(most.max(bytes));
        let texel_view = vk::BufferUsageFlags::UNIFORM_TEXEL_BUFFER;
        // Every record's room is taken: a texture added later rewrites its own.
        let (records, records_upload) = AppendBuffer::new(
            gpu,
            "sampled texture records",
            texel_view,
            record_capacity as u64 * RECORD_BYTES,
            Some(vk::Format::R32G32B32A32_UINT),
            bytemuck::cast_slice(&records),
        )?;
        let (texels, texels_upload) = AppendBuffer::new(
            gpu,
            "sampled texels",
            SCENE_STORAGE,
            texel_capacity,
            Some(vk::Format::R32_UINT),
            bytemuck::cast_slice(&texels),
        )?;
        let lut: &[u8] = bytemuck::cast_slice(srgb_lut());
        let (srgb, srgb_upload) = AppendBuffer::new(
            gpu,
            "sRGB table",
            texel_view,
            lut.len() as u64,
            Some(vk::Format::R32_SFLOAT),
            lut,
        )?;
        uploads.submit(gpu, vec![records_upload, texels_upload, srgb_upload])?;
        let buffers = SampledBuffers {
            records,
            record_capacity,
            texels,
            srgb,
        };
        Ok(Self {
            buffers: Arc::new(buffers),
            packed,
        })
    }

    /// Makes sure the textures `scene`'s transparent draws use are held: added in place, or,
    /// when they do not fit, in a new set with every texture held so far. `textures` are
    /// the assets' (with their texels): a renderer's version of them, which may be older
    /// (fewer) than the version that made the set.
    pub fn hold_used(
        &mut self,
        gpu: &Gpu,
        uploads: &Uploads,
        textures: &[Texture],
        scene: &Scene,
    ) -> Result<()> {
        let missing = |packed: &[bool], t: usize| !packed.get(t).copied().unwrap_or(false);
        if !scene_textures(scene)
            .flatten()
            .any(|t| missing(&self.packed, t))
        {
            return Ok(());
        }
        let mut new = used_textures(textures, scene)?;
        new.retain(|&t| missing(&self.packed, t));
        self.packed
            .resize(textures.len().max(self.packed.len()), false);
        if !self.add_in_place(gpu, uploads, textures, &new)? {
            // Textures a newer version of the assets added are left out here, and added
            // again by the frames that use them.
            new.extend((0..textures.len()).filter(|&t| self.packed[t]));
            *self = Self::holding(gpu, uploads, textures, &new)?;
        }
        Ok(())
    }

    /// Adds textures `new` to the current set, uploaded through `uploads`; false when they
    /// do not fit (some may have been marked added, their room wasted and nothing uploaded:
    /// the caller makes a new set).
    fn add_in_place(
        &mut self,
        gpu: &Gpu,
        uploads: &Uploads,
        textures: &[Texture],
        new: &[usize],
    ) -> Result<bool> {
        let b = &self.buffers;
        if new.iter().any(|&t| t >= b.record_capacity) {
            return Ok(false);
        }
        let mut added = Vec::with_capacity(2 * new.len());
        for &t in new {
            let texture = &textures[t];
            let texels = texels_of(texture)?;
            let Some((at, texels)) = b.texels.append(gpu, bytemuck::cast_slice(&texels), 4)? else {
                return Ok(false);
            };
            let record = bin_texture(texture, (at / 4) as u32);
            // Record `t` is read only by frames whose transparent draws use texture `t`, and
            // no frame was recorded with one yet: it would have added the texture. The upload
            // is recorded before the frame that first does (or run now).
            let record: Upload =
                b.records
                    .rewrite(gpu, t as u64 * RECORD_BYTES, bytemuck::bytes_of(&record))?;
            added.extend([texels, record]);
            self.packed[t] = true;
        }
        uploads.submit(gpu, added)?;
        Ok(true)
    }

    pub fn views(&self) -> SampledViews {
        let b = &self.buffers;
        let raw = |buffer: &AppendBuffer| buffer.view().map_or(vk::BufferView::null(), |v| v.raw);
        SampledViews {
            records: raw(&b.records),
            texels: raw(&b.texels),
            srgb: raw(&b.srgb),
            buffers: b.clone(),
        }
    }
}

/// The texture of each of `scene`'s transparent draws' materials, if it has one.
pub(super) fn scene_textures(scene: &Scene) -> impl Iterator<Item = Option<usize>> + '_ {
    scene
        .transparent
        .iter()
        .map(|d| scene.materials.get(d.material).and_then(|m| m.texture))
}

/// The textures (indices into `textures`) `scene`'s transparent draws use, each once.
fn used_textures(textures: &[Texture], scene: &Scene) -> Result<Vec<usize>> {
    let mut used: Vec<usize> = scene_textures(scene).flatten().collect();
    used.sort_unstable();
    used.dedup();
    match used.last() {
        Some(&t) if t >= textures.len() => Err(Error::InvalidScene(format!(
            "a transparent draw samples texture {t}, past the {} the assets hold",
            textures.len()
        ))),
        _ => Ok(used),
    }
}

fn packed_textures<'a>(
    textures: &'a [Texture],
    packed: &'a [bool],
) -> impl Iterator<Item = &'a Texture> + 'a {
    textures
        .iter()
        .zip(packed)
        .filter(|(_, p)| **p)
        .map(|(t, _)| t)
}

/// Every level's texels of `texture`, packed; an error for a texture whose texels the host
/// no longer holds (a renderer's scene keeps none), which would be sampled as garbage.
fn texels_of(texture: &Texture) -> Result<Vec<u32>> {
    let texels: Vec<u32> = level_texels(texture).collect();
    let expected: u64 = texture
        .levels
        .iter()
        .map(|l| u64::from(l.width) * u64::from(l.height))
        .sum();
    if texels.len() as u64 != expected {
        return Err(Error::InvalidScene(format!(
            "texture '{}' has {} of its {expected} texels on the host: the software sampler \
             cannot copy it",
            texture.name,
            texels.len()
        )));
    }
    Ok(texels)
}

/// The most bytes of texels the software sampler reads: one texel view of R32 texels.
fn most_texel_bytes(gpu: &Gpu) -> u64 {
    u64::from(gpu.info().max_texel_buffer_elements) * 4
}
