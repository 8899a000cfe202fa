//! RGBA8 textures from C. Exports `translucid_texture_*`.

use crate::cast::{
    check_header, translucid_base_in_structure, translucid_context, try_out, try_ref, try_slice,
    try_str,
};
use crate::panic;
use crate::result::{translucid_result, Failure, FfiResult};
use crate::structure::translucid_structure_type;
use std::ffi::{c_char, c_void};
use translucid::scene::{Filter, MipFilter, Sampler, Texture, Wrap};

/// Texels are sRGB-encoded (as colour images usually are) and decoded to linear on sampling.
pub const TRANSLUCID_TEXTURE_SRGB: u32 = 1;
const TEXTURE_FLAGS: u32 = TRANSLUCID_TEXTURE_SRGB;
/// Largest texture width or height.
pub const TRANSLUCID_MAX_TEXTURE_SIZE: u32 = 8192;

/// A texture. Zero-initialise, then set `s_type`, the size and `texels`.
#[allow(non_camel_case_types)]
#[repr(C)]
pub struct translucid_texture_create_info {
    /// `TRANSLUCID_STRUCTURE_TYPE_TEXTURE_CREATE_INFO`.
    pub s_type: u32,
    /// NULL, or a `translucid_sampler_info` saying how the texture is sampled (without one:
    /// repeated, filtered trilinearly).
    pub next: *const c_void,
    /// 1 to `TRANSLUCID_MAX_TEXTURE_SIZE`.
    pub width: u32,
    /// 1 to `TRANSLUCID_MAX_TEXTURE_SIZE`.
    pub height: u32,
    /// `TRANSLUCID_TEXTURE_*` bits; other bits must be 0.
    pub flags: u32,
    /// Required: `width` x `height` x 4 bytes of RGBA, rows top first, tightly packed
    /// (copied; mipmaps are made by translucid).
    pub texels: *const u8,
    /// Optional name for messages (copied).
    pub name: *const c_char,
}

/// How texture coordinates outside [0, 1] map into a texture, per axis (glTF's `wrapS`,
/// `wrapT`).
#[allow(non_camel_case_types)]
#[repr(u32)]
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum translucid_wrap {
    Repeat = 0,
    ClampToEdge = 1,
    MirroredRepeat = 2,
}

/// Filtering within a mip level.
#[allow(non_camel_case_types)]
#[repr(u32)]
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum translucid_filter {
    Linear = 0,
    Nearest = 1,
}

/// Filtering between mip levels when a texture is minified.
#[allow(non_camel_case_types)]
#[repr(u32)]
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum translucid_mipmap_mode {
    /// The two levels around the level of detail, blended (glTF `*_MIPMAP_LINEAR`).
    Linear = 0,
    /// The nearest level (`*_MIPMAP_NEAREST`).
    Nearest = 1,
    /// Level 0 only (glTF's `NEAREST` and `LINEAR` min filters).
    None = 2,
}

/// How a texture is sampled, as a glTF sampler says it; chained to
/// `translucid_texture_create_info::next`. Zero-initialised, every field takes glTF's default:
/// repeat, linear filters, linear between mip levels. Every method and the CPU reference
/// follow the same rules (the README's "Textures and samplers").
#[allow(non_camel_case_types)]
#[repr(C)]
pub struct translucid_sampler_info {
    /// `TRANSLUCID_STRUCTURE_TYPE_SAMPLER_INFO`.
    pub s_type: u32,
    /// NULL.
    pub next: *const c_void,
    /// `translucid_wrap` along u.
    pub wrap_s: u32,
    /// `translucid_wrap` along v.
    pub wrap_t: u32,
    /// `translucid_filter` when magnified.
    pub mag_filter: u32,
    /// `translucid_filter` when minified.
    pub min_filter: u32,
    /// `translucid_mipmap_mode` when minified.
    pub mipmap_mode: u32,
}

impl translucid_wrap {
    fn from_raw(value: u32, field: &str) -> FfiResult<Self> {
        [Self::Repeat, Self::ClampToEdge, Self::MirroredRepeat]
            .into_iter()
            .find(|w| *w as u32 == value)
            .ok_or_else(|| {
                Failure::enumeration(&format!("translucid_sampler_info.{field} (wrap)"), value)
            })
    }

    fn core(self) -> Wrap {
        match self {
            Self::Repeat => Wrap::Repeat,
            Self::ClampToEdge => Wrap::ClampToEdge,
            Self::MirroredRepeat => Wrap::MirroredRepeat,
        }
    }
}

impl translucid_filter {
    fn from_raw(value: u32, field: &str) -> FfiResult<Self> {
        [Self::Linear, Self::Nearest]
            .into_iter()
            .find(|f| *f as u32 == value)
            .ok_or_else(|| {
                Failure::enumeration(&format!("translucid_sampler_info.{field} (filter)"), value)
            })
    }

    fn core(self) -> Filter {
        match self {
            Self::Linear => Filter::Linear,
            Self::Nearest => Filter::Nearest,
        }
    }
}

impl translucid_mipmap_mode {
    fn from_raw(value: u32) -> FfiResult<Self> {
        [Self::Linear, Self::Nearest, Self::None]
            .into_iter()
            .find(|m| *m as u32 == value)
            .ok_or_else(|| Failure::enumeration("translucid_sampler_info.mipmap_mode", value))
    }

    fn core(self) -> MipFilter {
        match self {
            Self::Linear => MipFilter::Linear,
            Self::Nearest => MipFilter::Nearest,
            Self::None => MipFilter::None,
        }
    }
}

/// A texture handle. `{0}` is the NULL handle (no texture).
#[allow(non_camel_case_types)]
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct translucid_texture {
    pub id: u64,
}

fn texture_from_info(info: &translucid_texture_create_info) -> FfiResult<Texture> {
    // `next` may hold a sampler: sampler_from_chain reads it.
    check_header(
        info.s_type,
        std::ptr::null(),
        translucid_structure_type::TextureCreateInfo,
        "translucid_texture_create_info",
    )?;
    let (w, h) = (info.width, info.height);
    let limit = 1..=TRANSLUCID_MAX_TEXTURE_SIZE;
    if !limit.contains(&w) || !limit.contains(&h) {
        return Err(Failure::size(format!(
            "texture is {w}x{h}; width and height must be 1 to {TRANSLUCID_MAX_TEXTURE_SIZE}"
        )));
    }
    if info.flags & !TEXTURE_FLAGS != 0 {
        return Err(Failure::argument(format!(
            "unknown texture flags {:#x}",
            info.flags & !TEXTURE_FLAGS
        )));
    }
    let texel_count = usize::try_from(u64::from(w) * u64::from(h))
        .map_err(|_| Failure::size("texture too large for this machine"))?;
    let bytes = try_slice(info.texels, texel_count * 4, "texels")?;
    let texels = bytes
        .chunks_exact(4)
        .map(|t| [t[0], t[1], t[2], t[3]])
        .collect();
    let name = try_str(info.name, "name")?.unwrap_or("");
    let srgb = info.flags & TRANSLUCID_TEXTURE_SRGB != 0;
    let sampler = sampler_from_chain(info.next)?;
    Ok(Texture::new(name, w, h, texels, srgb).with_sampler(sampler))
}

/// The sampler chained to a texture create-info, or the default when `next` is NULL.
fn sampler_from_chain(next: *const c_void) -> FfiResult<Sampler> {
    if next.is_null() {
        return Ok(Sampler::default());
    }
    let link = try_ref(next.cast::<translucid_base_in_structure>(), "next")?;
    if link.s_type != translucid_structure_type::SamplerInfo as u32 {
        return Err(Failure::new(
            translucid_result::ErrorInvalidStructureType,
            format!(
                "translucid_texture_create_info.next holds structure type {}; it accepts only \
                 a translucid_sampler_info (TRANSLUCID_STRUCTURE_TYPE_SAMPLER_INFO, {})",
                link.s_type,
                translucid_structure_type::SamplerInfo as u32
            ),
        ));
    }
    let info = try_ref(next.cast::<translucid_sampler_info>(), "next")?;
    check_header(
        info.s_type,
        info.next,
        translucid_structure_type::SamplerInfo,
        "translucid_sampler_info",
    )?;
    let wrap = |value, field| translucid_wrap::from_raw(value, field).map(translucid_wrap::core);
    let filter =
        |value, field| translucid_filter::from_raw(value, field).map(translucid_filter::core);
    let mip_filter = translucid_mipmap_mode::from_raw(info.mipmap_mode)?.core();
    Ok(Sampler {
        wrap_s: wrap(info.wrap_s, "wrap_s")?,
        wrap_t: wrap(info.wrap_t, "wrap_t")?,
        mag_filter: filter(info.mag_filter, "mag_filter")?,
        min_filter: filter(info.min_filter, "min_filter")?,
        mip_filter,
    })
}

impl translucid_texture {
    /// Creates a texture (copying the texels) and writes its handle to `*out_texture`.
    #[no_mangle]
    #[must_use]
    pub extern "C" fn translucid_texture_create(
        context: *mut translucid_context,
        info: *const translucid_texture_create_info,
        out_texture: *mut translucid_texture,
    ) -> translucid_result {
        panic::with_context(context, |objects| {
            let info = try_ref(info, "info")?;
            let out = try_out(out_texture, "out_texture")?;
            let id = objects.core.create_texture(texture_from_info(info)?)?;
            out.write(translucid_texture { id });
            Ok(translucid_result::Success)
        })
    }

    /// Destroys a texture; its handle becomes stale. A material still using it can no longer
    /// be drawn (the frame fails with `TRANSLUCID_RESULT_ERROR_STALE_HANDLE`).
    #[no_mangle]
    pub extern "C" fn translucid_texture_destroy(
        context: *mut translucid_context,
        texture: translucid_texture,
    ) -> translucid_result {
        panic::with_context(context, |objects| {
            objects.core.destroy_texture(texture.id)?;
            Ok(translucid_result::Success)
        })
    }
}
