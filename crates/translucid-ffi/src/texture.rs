//! RGBA8 textures from C. Exports `translucid_texture_*`.

use crate::cast::{check_header, translucid_context, try_out, try_ref, try_slice, try_str};
use crate::panic;
use crate::result::{translucid_result, Failure, FfiResult};
use crate::structure::translucid_structure_type;
use std::ffi::{c_char, c_void};
use translucid::scene::Texture;

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
    /// NULL.
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

/// A texture handle. `{0}` is the NULL handle (no texture).
#[allow(non_camel_case_types)]
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct translucid_texture {
    pub id: u64,
}

fn texture_from_info(info: &translucid_texture_create_info) -> FfiResult<Texture> {
    check_header(
        info.s_type,
        info.next,
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
    Ok(Texture::new(name, w, h, texels, srgb))
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
            let id = objects.textures.insert(texture_from_info(info)?)?;
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
            objects.textures.remove(texture.id)?;
            Ok(translucid_result::Success)
        })
    }
}
