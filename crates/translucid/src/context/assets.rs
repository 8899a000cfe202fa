//! The context's assets by handle: meshes, textures and materials, created and destroyed by
//! the engine at any time, and the count of those changes that tells a renderer its uploads
//! are behind.

use super::handles::{Kind, Slots};
use crate::scene::{Material, Mesh, Texture};

/// A material as the context keeps it: its texture by handle.
#[derive(Clone, Debug)]
pub struct MaterialRecord {
    pub material: Material,
    pub texture: Option<u64>,
}

/// An asset just destroyed, with its data, for the uploads to keep its place.
pub enum Destroyed {
    Mesh(u64, Mesh),
    Texture(u64, Texture),
    Material(u64, MaterialRecord),
}

/// The live assets.
pub struct Assets {
    pub meshes: Slots<Mesh>,
    pub textures: Slots<Texture>,
    pub materials: Slots<MaterialRecord>,
    /// Counts the creations and destructions of assets: a renderer drawing an older
    /// generation takes no new frame.
    pub generation: u64,
    /// The generation the last destruction of an asset the uploads could not keep began.
    pub last_destroyed: u64,
}

impl Assets {
    /// No assets, their handles tagged `tag` (the context's).
    pub fn new(tag: u16) -> Self {
        Self {
            meshes: Slots::new(Kind::Mesh, tag),
            textures: Slots::new(Kind::Texture, tag),
            materials: Slots::new(Kind::Material, tag),
            generation: 0,
            last_destroyed: 0,
        }
    }
}
