//! Sizes and offsets the host derives from the bins' shader interface
//! ([`crate::interface::bins`], which declares the records, counters and constants).

#![deny(unsafe_code)]

pub use crate::assets::texture_records::*;
pub use crate::interface::bins::*;

/// Bytes of one resume item: block * BIN_SIZE + row (its index is its state slot).
pub const RESUME_ITEM_BYTES: u64 = 4;
/// Bytes of the indirect commands (g_dispatch) before the resume items.
pub const DISPATCH_BYTES: u64 = DISPATCH_WORDS as u64 * 4;
/// Byte offset of the indirect command at index `command` of g_dispatch (`DISPATCH_*`,
/// `DRAW_COMPOSITE`).
const fn command_offset(command: u32) -> u64 {
    command as u64 * 16
}
pub const DISPATCH_RASTER_BINS_OFFSET: u64 = command_offset(DISPATCH_RASTER_BINS);
pub const DISPATCH_BINNING_OFFSET: u64 = command_offset(DISPATCH_BINNING);
pub const DISPATCH_BIN_OFFSETS_OFFSET: u64 = command_offset(DISPATCH_BIN_OFFSETS);
pub const DISPATCH_BAND_FILL_OFFSET: u64 = command_offset(DISPATCH_BAND_FILL);
/// The composite's `VkDrawIndirectCommand`.
pub const DRAW_COMPOSITE_OFFSET: u64 = command_offset(DRAW_COMPOSITE);
/// Bytes of one `BinTriangleRecord` and one `BinHomogeneous`.
pub const TRIANGLE_BYTES: u64 = std::mem::size_of::<BinTriangleRecord>() as u64;
pub const HOMOGENEOUS_BYTES: u64 = std::mem::size_of::<BinHomogeneous>() as u64;
/// The most texels a quad's attribute record takes.
pub const MOST_ATTRIBUTE_TEXELS: u32 = COLOUR_TEXELS + NORMAL_TEXELS + UV_TEXELS;

/// Bytes per triangle of the larger of the two record arrays, triangle records and quad
/// attribute records of `attribute_texels`: what one binding or texel view must hold of each
/// triangle.
pub fn record_bytes_per_triangle(attribute_texels: u32) -> u64 {
    TRIANGLE_BYTES.max(u64::from(attribute_texels) * 16 / 2)
}

impl BinCounters {
    /// The raster's statistic at word `word` of each slot (BinCounters.statistics).
    fn statistic(&self, word: usize) -> impl Iterator<Item = u32> + '_ {
        self.statistics.chunks_exact(16).map(move |slot| slot[word])
    }

    /// Fragments the raster composited.
    pub fn fragments(&self) -> u64 {
        self.statistic(0).map(u64::from).sum()
    }

    /// Fragments in front of the opaque layer that the raster's first sweep found, composited
    /// or not (a threshold stops pixels early); fewer where a pixel had to drop some.
    pub fn fragments_in_front(&self) -> u64 {
        self.statistic(2).map(u64::from).sum()
    }

    /// Pixel rows the frame left with the opaque colour: those of blocks its bands did not
    /// reach or skipped (a block's lists alone past the capacity), and rows a band left
    /// unfinished. (Rows the last band left unfinished are counted apart.)
    pub fn degraded_rows(&self) -> u64 {
        let blocks = u64::from(self.skipped_blocks)
            + u64::from(self.listed_blocks.saturating_sub(self.band_next));
        blocks * u64::from(BIN_SIZE) + u64::from(self.abandoned_rows)
    }

    /// The most sweeps of its row's list any pixel needed (raster.comp).
    pub fn sweeps(&self) -> u32 {
        self.statistic(1).max().unwrap_or(0)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scene::{Filter, MipFilter, Sampler, Wrap};
    use std::mem::size_of;

    #[test]
    fn statistics_add_up_over_the_slots() {
        let mut c = BinCounters::default();
        for (k, slot) in c.statistics.chunks_exact_mut(16).enumerate() {
            let k = k as u32;
            slot[0] = 10 + k;
            slot[1] = k % 3;
            slot[2] = 100 * (k + 1);
        }
        let slots = u64::from(STATISTICS_SLOTS);
        assert_eq!(c.fragments(), 10 * slots + slots * (slots - 1) / 2);
        assert_eq!(c.sweeps(), 2);
        assert_eq!(c.fragments_in_front(), 100 * slots * (slots + 1) / 2);
    }

    /// bins_bindings.glsl and bin_fragment.glsl read these records texel by texel (16 bytes
    /// each) in field order; their loaders are right only while every field sits where they
    /// expect.
    #[test]
    fn texel_loaders_match_the_records() {
        use crate::shader_types::GpuMaterial;
        use std::mem::offset_of;
        let msg = "a record changed: update its loaders (bins_bindings.glsl, bin_fragment.glsl) \
                   and this test";
        let t = [
            offset_of!(BinTriangleRecord, vertices01),
            offset_of!(BinTriangleRecord, vertex2),
            offset_of!(BinTriangleRecord, flags),
            offset_of!(BinTriangleRecord, bounds_min),
            offset_of!(BinTriangleRecord, z_ndc),
            offset_of!(BinTriangleRecord, bounds_end),
            offset_of!(BinTriangleRecord, inv_w),
            offset_of!(BinTriangleRecord, inv_area),
        ];
        assert_eq!(t, [0, 16, 24, 28, 32, 44, 48, 60], "{msg}");
        assert_eq!(TRIANGLE_BYTES, 64, "{msg}");
        let h = [
            offset_of!(BinHomogeneous, line0),
            offset_of!(BinHomogeneous, line1),
            offset_of!(BinHomogeneous, line2),
            offset_of!(BinHomogeneous, z_inv_det),
            offset_of!(BinHomogeneous, fixed_c),
            offset_of!(BinHomogeneous, fixed_a),
            offset_of!(BinHomogeneous, fixed_b),
        ];
        assert_eq!(h, [0, 16, 32, 48, 64, 96, 112], "{msg}");
        assert_eq!(HOMOGENEOUS_BYTES, 128, "{msg}");
        assert_eq!(size_of::<BinTexture>(), 32, "{msg}");
        assert_eq!(offset_of!(BinTexture, sampler_bits), 20, "{msg}");
        let m = [
            offset_of!(GpuMaterial, base_colour),
            offset_of!(GpuMaterial, tint_transmission),
            offset_of!(GpuMaterial, reflectance),
            offset_of!(GpuMaterial, alpha_cutoff),
            offset_of!(GpuMaterial, texture_index),
            offset_of!(GpuMaterial, flags),
        ];
        assert_eq!(m, [0, 16, 32, 36, 40, 44], "{msg}");
        assert_eq!(size_of::<GpuMaterial>(), 48, "{msg}");
    }

    #[test]
    fn sampler_fields_do_not_overlap() {
        let all = Sampler {
            wrap_s: Wrap::MirroredRepeat,
            wrap_t: Wrap::MirroredRepeat,
            mag_filter: Filter::Linear,
            min_filter: Filter::Linear,
            mip_filter: MipFilter::Linear,
        };
        assert_eq!(sampler_bits(&all), 2 | 2 << 2 | 16 | 32 | 2 << 6);
        assert_eq!(
            SAMPLER_WRAP_MASK << SAMPLER_WRAP_T_SHIFT & SAMPLER_MAG_LINEAR,
            0
        );
        assert_eq!(
            SAMPLER_MIP_MASK << SAMPLER_MIP_SHIFT & SAMPLER_MIN_LINEAR,
            0
        );
    }
}
