//! The specialization constants every wavelet shader takes, in `constant_id` order; mirrored
//! by `shaders/common/wavelet_constants.glsl` (a test compares the two). The rank is not
//! among them: each rank has its own SPIR-V (see [`super::passes`]). None changes with the
//! camera: the depth mapping is in the frame constants (`FrameInfo.depthMapping`), so a
//! camera whose near and far planes move builds nothing.

use bytemuck::{Pod, Zeroable};

#[repr(C)]
#[derive(Clone, Copy, Debug, Default, Pod, Zeroable)]
pub struct SpecConstants {
    /// `WAVELET_FIRST_TEXEL`: the first coefficient texel an accumulation draw writes.
    pub first_texel: i32,
    /// `WAVELET_NOISE`: depth noise strength, in cells; 0 is off.
    pub noise: f32,
    /// `WAVELET_ABSORBED`: absorbance from which a pixel counts as opaque.
    pub absorbed: f32,
}

/// GLSL (type, name) of each field, in order.
pub const GLSL_NAMES: [(&str, &str); 3] = [
    ("int", "WAVELET_FIRST_TEXEL"),
    ("float", "WAVELET_NOISE"),
    ("float", "WAVELET_ABSORBED"),
];

impl SpecConstants {
    /// The 32-bit words a pipeline's specialization info takes, constant 0 first.
    pub fn words(&self) -> [u32; 3] {
        bytemuck::cast(*self)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    const SRC: &str = include_str!("../../../../../shaders/common/wavelet_constants.glsl");

    /// `(id, type, name)` of every `layout(constant_id = WAVELET_CONSTANT_ID + N) const TYPE NAME`
    /// in the include.
    fn glsl_constants() -> Vec<(usize, String, String)> {
        SRC.lines()
            .filter_map(|line| {
                let rest = line
                    .trim()
                    .strip_prefix("layout(constant_id = WAVELET_CONSTANT_ID + ")?;
                let (id, decl) = rest.split_once(')')?;
                let mut words = decl.split_whitespace();
                (words.next()? == "const").then_some(())?;
                let ty = words.next()?.to_string();
                let name = words.next()?.to_string();
                Some((id.trim().parse().ok()?, ty, name))
            })
            .collect()
    }

    /// The bin raster numbers the wavelet constants after the exact raster's own.
    #[test]
    fn bin_raster_constants_follow_the_exact_rasters() {
        let bins = include_str!("../../../../../shaders/common/wavelet_bins.glsl");
        let first = bins
            .lines()
            .find_map(|l| l.trim().strip_prefix("#define WAVELET_CONSTANT_ID "))
            .and_then(|v| v.trim().parse::<usize>().ok())
            .expect("wavelet_bins.glsl defines WAVELET_CONSTANT_ID");
        assert_eq!(first, crate::methods::bins::features::RASTER_CONSTANTS);
    }

    #[test]
    fn constants_match_glsl() {
        let glsl = glsl_constants();
        assert_eq!(
            glsl.len(),
            GLSL_NAMES.len(),
            "wavelet.glsl and SpecConstants disagree on the number of constants: {glsl:?}"
        );
        for (i, ((id, ty, name), (want_ty, want_name))) in glsl.iter().zip(GLSL_NAMES).enumerate() {
            assert_eq!(
                (*id, ty.as_str(), name.as_str()),
                (i, want_ty, want_name),
                "constant {i}: fix SpecConstants or wavelet.glsl so they list the same constants"
            );
        }
        assert_eq!(std::mem::size_of::<SpecConstants>(), 4 * GLSL_NAMES.len());
    }
}
