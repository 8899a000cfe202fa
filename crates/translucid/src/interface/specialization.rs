//! Every specialization constant of every shader, each with one id and one meaning
//! (`interface_specialization.glsl`); a pipeline sets those it needs by name
//! ([`Specialization`]) and the rest keep their defaults.

use super::{Include, StructDecl};

/// A specialization constant of type `T`.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct SpecConstant<T> {
    pub id: u32,
    _type: std::marker::PhantomData<T>,
}

impl<T> SpecConstant<T> {
    const fn new(id: u32) -> Self {
        Self {
            id,
            _type: std::marker::PhantomData,
        }
    }
}

/// What a specialization constant's value is as the 32-bit word Vulkan takes.
pub trait SpecWord: Copy {
    fn word(self) -> u32;
}

impl SpecWord for bool {
    fn word(self) -> u32 {
        u32::from(self)
    }
}

impl SpecWord for u32 {
    fn word(self) -> u32 {
        self
    }
}

impl SpecWord for i32 {
    fn word(self) -> u32 {
        self as u32
    }
}

impl SpecWord for f32 {
    fn word(self) -> u32 {
        self.to_bits()
    }
}

/// The constants a pipeline sets: `(id, word)` in id order. Constants it does not set keep
/// the shader's defaults, so a stage is specialized by exactly what it reads.
#[derive(Clone, Debug, Default, PartialEq, Eq, Hash)]
pub struct Specialization {
    words: Vec<(u32, u32)>,
}

impl Specialization {
    /// No constant set: every one keeps its default.
    pub const NONE: Self = Self { words: Vec::new() };

    pub fn new() -> Self {
        Self::default()
    }

    /// The same, with `constant` set to `value` (replacing a value set before).
    pub fn with<T: SpecWord>(mut self, constant: SpecConstant<T>, value: T) -> Self {
        let word = value.word();
        match self.words.binary_search_by_key(&constant.id, |&(id, _)| id) {
            Ok(i) => self.words[i].1 = word,
            Err(i) => self.words.insert(i, (constant.id, word)),
        }
        self
    }

    /// `(id, word)` of every constant set, in id order.
    pub fn words(&self) -> &[(u32, u32)] {
        &self.words
    }

    /// The word `constant` is set to, if it is set.
    pub fn word<T: SpecWord>(&self, constant: SpecConstant<T>) -> Option<u32> {
        let i = self
            .words
            .binary_search_by_key(&constant.id, |&(id, _)| id)
            .ok()?;
        Some(self.words[i].1)
    }
}

/// A constant's declaration, for the GLSL include.
pub struct SpecDecl {
    pub id: u32,
    pub name: &'static str,
    /// `None` for a workgroup size (`local_size_x_id = NAME_ID`), which is not declared as a
    /// constant.
    pub glsl: Option<(&'static str, String)>,
    pub doc: &'static [&'static str],
}

/// Declares the specialization constants: a typed [`SpecConstant`] each, and `declarations`,
/// their GLSL. `workgroup_size` is a `u32` the shaders use as `local_size_x_id = NAME_ID`.
macro_rules! spec_constants {
    (@rust workgroup_size) => { u32 };
    (@rust $ty:ident) => { $ty };
    (@glsl workgroup_size, $default:expr) => { None };
    (@glsl bool, $default:expr) => { Some(("bool", format!("{}", $default))) };
    (@glsl u32, $default:expr) => { Some(("uint", format!("{}u", $default))) };
    (@glsl i32, $default:expr) => { Some(("int", format!("{}", $default))) };
    (@glsl f32, $default:expr) => { Some(("float", format!("{:?}", $default as f32))) };
    ($(
        $(#[doc = $doc:literal])*
        $id:literal => pub const $name:ident: $ty:ident = $default:expr;
    )*) => {
        $(
            $(#[doc = $doc])*
            pub const $name: SpecConstant<spec_constants!(@rust $ty)> = SpecConstant::new($id);
        )*

        const IDS: &[u32] = &[$($id),*];
        const _: () = assert!(ids_count_up(IDS), "specialization constant ids must be 0, 1, 2, ...");

        /// The constants' GLSL declarations.
        pub fn declarations() -> Vec<SpecDecl> {
            vec![$(
                SpecDecl {
                    id: $id,
                    name: stringify!($name),
                    glsl: spec_constants!(@glsl $ty, $default),
                    doc: &[$($doc),*],
                }
            ),*]
        }
    };
}

/// Whether `ids` are 0, 1, 2, ... in order: each constant its own id, none skipped.
const fn ids_count_up(ids: &[u32]) -> bool {
    let mut i = 0;
    while i < ids.len() {
        if ids[i] != i as u32 {
            return false;
        }
        i += 1;
    }
    true
}

spec_constants! {
    /// What the bin stages may meet, fixed when the pipeline is made from the frame's draws
    /// (methods/bins/features.rs): some triangle may need the homogeneous path (near plane,
    /// behind the eye, guard band).
    0 => pub const HOMOGENEOUS_PATH: bool = true;
    /// Some material has a texture.
    1 => pub const TEXTURES: bool = true;
    /// Some lit draw has vertex normals.
    2 => pub const VERTEX_NORMALS: bool = true;
    /// Some lit draw has none.
    3 => pub const FACE_NORMALS: bool = true;
    /// Some material transmits light.
    4 => pub const TRANSMISSION: bool = true;
    /// Some mesh has vertex colours.
    5 => pub const VERTEX_COLOURS: bool = true;
    /// Every quad has one colour at all its corners: records keep one colour per quad.
    6 => pub const FLAT_COLOURS: bool = false;
    /// Each bin's list holds 2^SLAB_BITS depth slabs (bin_lists.glsl).
    7 => pub const SLAB_BITS: u32 = 0;
    /// Binning invocations per triangle once bins hold slabs (bin_lists.glsl).
    8 => pub const DEEP_BINNING_LANES: u32 = 1;
    /// Setup: the occlusion cull is off (setup.comp).
    9 => pub const SKIP_OCCLUSION_CULL: bool = false;
    /// Setup writes its records through texel views (they pass one storage binding).
    10 => pub const RECORDS_AS_TEXELS: bool = false;
    /// The exact raster: this dispatch resumes the items of a resume list.
    11 => pub const CONTINUATION: bool = false;
    /// The exact raster: fragments a pixel keeps as it walks its row's list.
    12 => pub const SELECT_SIZE: i32 = 8;
    /// The rasters: invocations per workgroup, whole rows of a block's pixels (a subgroup
    /// must see one tile: raster_tile.glsl).
    13 => pub const RASTER_GROUP_SIZE: workgroup_size = 8;
    /// linked_list: nodes are written through a texel view (they pass one storage binding).
    14 => pub const NODES_AS_TEXELS: bool = false;
    /// The engine's depth import: the engine's depth is reversed-Z.
    15 => pub const IMPORTED_DEPTH_REVERSED: bool = false;
    /// wavelet: the first coefficient texel an accumulation draw writes.
    16 => pub const WAVELET_FIRST_TEXEL: i32 = 0;
    /// wavelet: depth noise strength, in cells; 0 is off.
    17 => pub const WAVELET_NOISE: f32 = 0.0;
    /// wavelet: absorbance from which a pixel counts as opaque.
    18 => pub const WAVELET_ABSORBED: f32 = 7.6;
    /// The rasters: loop iterations a row may take in one dispatch (`DeviceInfo::loop_budget`).
    /// The exact raster counts its iterations against it (with room for the few it does not
    /// count) and, before it would run out, saves the row and leaves the rest to a
    /// continuation dispatch; wavelet's reports a row that would pass it as crowded.
    19 => pub const LOOP_BUDGET: u32 = 60_000;
    /// The rasters: branch where the subgroup agrees, as GPUs do for free (the GPU profile),
    /// instead of running both sides under a mask (CPU drivers: `gpu::Profile`).
    20 => pub const BRANCHING: bool = false;
    /// Quotients that must be the reference's are corrected to the nearest float
    /// (rounded_division.glsl): Vulkan lets a division be 2.5 ulp off, and only CPU drivers
    /// divide exactly. Every pipeline gets it from the profile (`gpu::pipeline`).
    21 => pub const ROUNDED_DIVISION: bool = false;
    /// A bin is a tile of 2^TILE_SHIFT pixel rows of a block, one subgroup's pixels
    /// (bin_lists.glsl): the device's subgroup size over BIN_SIZE.
    22 => pub const TILE_SHIFT: u32 = 0;
    /// The rasters' walks read list entries and triangle records as storage buffers, not
    /// texels (`methods::bins::features::storage_walk`).
    23 => pub const STORAGE_WALK: bool = false;
    /// Binning: each workgroup tallies its bin entries in a shared-memory table of
    /// 2^BIN_TALLY_BITS slots, one global atomic a bin (bin_tally.glsl); 0 is off, an atomic
    /// an entry (`methods::bins::features::bin_tally_bits`).
    24 => pub const BIN_TALLY_BITS: u32 = 0;
}

/// The GLSL of every constant.
pub fn glsl() -> String {
    let mut out = String::new();
    for d in declarations() {
        out.push('\n');
        super::comment(&mut out, "", d.doc);
        match &d.glsl {
            Some((ty, default)) => out.push_str(&format!(
                "layout(constant_id = {}) const {ty} {} = {default};\n",
                d.id, d.name
            )),
            None => out.push_str(&format!("#define {}_ID {}\n", d.name, d.id)),
        }
    }
    out
}

pub fn include() -> Include {
    const STRUCTS: &[&StructDecl] = &[];
    Include {
        file: "interface_specialization.glsl",
        source: "specialization.rs",
        constants: &[],
        structs: STRUCTS,
        sets: vec![],
        more: Some(glsl),
        needs: &[],
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_specialization_keeps_one_word_per_constant_in_id_order() {
        let s = Specialization::new()
            .with(SELECT_SIZE, 16)
            .with(HOMOGENEOUS_PATH, false)
            .with(WAVELET_NOISE, 0.5)
            .with(SELECT_SIZE, 8);
        assert_eq!(
            s.words(),
            [
                (0, 0),
                (SELECT_SIZE.id, 8),
                (WAVELET_NOISE.id, 0.5f32.to_bits())
            ]
        );
    }

    #[test]
    fn every_constant_is_declared_once() {
        let text = glsl();
        for d in declarations() {
            let declared = match d.glsl {
                Some(_) => format!("layout(constant_id = {}) const", d.id),
                None => format!("#define {}_ID {}", d.name, d.id),
            };
            assert_eq!(text.matches(&declared).count(), 1, "{}", d.name);
        }
    }
}
