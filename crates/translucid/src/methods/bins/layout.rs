//! Host mirrors of `shaders/common/bins_layout.glsl`; `tests::layouts_match_glsl` checks them.

#![deny(unsafe_code)]

pub use crate::assets::texture_records::*;
use bytemuck::{Pod, Zeroable};

pub const BIN_SHIFT: u32 = 3;
pub const BIN_SIZE: u32 = 1 << BIN_SHIFT;
/// Depth slabs a bin's list may be ordered into; the counters keep a farthest depth for each.
pub const MAX_SLABS: u32 = 1024;
/// Slots of `BinCounters::statistics`, each a cache line (16 words).
pub const STATISTICS_SLOTS: u32 = 8;
/// A triangle record's flags keep its material above this bit.
pub const TRIANGLE_MATERIAL_SHIFT: u32 = 8;
pub const OVERFLOW_HOMOGENEOUS: u32 = 1;
pub const OVERFLOW_BIN_ENTRIES: u32 = 2;
pub const OVERFLOW_CROWDED_BIN: u32 = 4;
pub const OVERFLOW_RESUME: u32 = 8;
pub const OVERFLOW_BAND_LISTS: u32 = 16;
/// `LOOP_BUDGET` of bins_layout.glsl: loop iterations one invocation may spend.
pub const LOOP_BUDGET: u32 = 60_000;
// The raster may pass its budget by two searches over the slabs (a sweep's start) before it
// stops; lavapipe ends loops after 65535 iterations.
const _: () = assert!(LOOP_BUDGET + 2 * MAX_SLABS < 65_000);
/// Bytes of one resume item: block * BIN_SIZE + row (its index is its state slot).
pub const RESUME_ITEM_BYTES: u64 = 4;
/// Bytes of one `ExactPixelState`.
pub const PIXEL_STATE_BYTES: u64 = 192;
/// `MAX_SELECT_SIZE` of bins_layout.glsl: fragments a pixel's saved state can hold.
pub const MAX_SELECT_SIZE: u32 = 16;
/// Bytes of the indirect dispatch commands (each padded to 16) before the resume items:
/// resume list 0, resume list 1, the band's blocks, binning, bin offsets, the band's fill;
/// then the composite's draw command (`DRAW_COMPOSITE`).
pub const DISPATCH_BYTES: u64 = 112;
/// Byte offset of the current band's raster dispatch command (`DISPATCH_RASTER_BINS`).
pub const DISPATCH_RASTER_BINS_OFFSET: u64 = 32;
/// Byte offset of the binning passes' dispatch command (`DISPATCH_BINNING`).
pub const DISPATCH_BINNING_OFFSET: u64 = 48;
/// Byte offset of the scan's last step's dispatch command (`DISPATCH_BIN_OFFSETS`).
pub const DISPATCH_BIN_OFFSETS_OFFSET: u64 = 64;
/// Byte offset of the band's fill dispatch command (`DISPATCH_BAND_FILL`).
pub const DISPATCH_BAND_FILL_OFFSET: u64 = 80;
/// Byte offset of the composite's draw command (`DRAW_COMPOSITE`), a
/// `VkDrawIndirectCommand`.
pub const DRAW_COMPOSITE_OFFSET: u64 = 96;
/// The last stamp a submission takes before they start again from 1 (`LAST_STAMP` of
/// transparent_layer.glsl: texels keep 6 bits of it).
pub const LAST_STAMP: u32 = 63;
/// Invocations per workgroup of the binning passes (`local_size_x`).
pub const BINNING_GROUP_SIZE: u32 = 64;
/// Invocations per workgroup of the scan, and the multiple of blocks the bin arrays hold.
pub const SCAN_GROUP_SIZE: u32 = 256;
/// Bytes of one `BinTriangleRecord` and one `BinHomogeneous`.
pub const TRIANGLE_BYTES: u64 = 64;
pub const HOMOGENEOUS_BYTES: u64 = 192;
/// Texels (16 bytes) of each section of a quad's attribute record (bins_layout.glsl):
/// colours, one colour with flat colours, vertex normals, face normals alone, uvs.
pub const COLOUR_TEXELS: u32 = 4;
pub const FLAT_COLOUR_TEXELS: u32 = 1;
pub const NORMAL_TEXELS: u32 = 3;
pub const FACE_NORMAL_TEXELS: u32 = 2;
pub const UV_TEXELS: u32 = 2;
/// The most texels a quad's attribute record takes.
pub const MOST_ATTRIBUTE_TEXELS: u32 = COLOUR_TEXELS + NORMAL_TEXELS + UV_TEXELS;

/// Bytes per triangle of the larger of the two record arrays, triangle records and quad
/// attribute records of `attribute_texels`: what one binding or texel view must hold of each
/// triangle.
pub fn record_bytes_per_triangle(attribute_texels: u32) -> u64 {
    TRIANGLE_BYTES.max(u64::from(attribute_texels) * 16 / 2)
}

#[repr(C)]
#[derive(Clone, Copy, Debug, Pod, Zeroable)]
pub struct BinDraw {
    pub mvp: [f32; 16],
    pub draw_index: u32,
    pub first_item: u32,
    pub quad_count: u32,
    pub first_quad: u32,
}

#[repr(C)]
#[derive(Clone, Copy, Debug, Pod, Zeroable, PartialEq, Eq)]
pub struct BinCounters {
    pub triangle_count: u32,
    pub homogeneous_count: u32,
    pub bin_entry_count: u32,
    pub overflow: u32,
    pub triangle_capacity: u32,
    pub homogeneous_capacity: u32,
    pub bin_entry_capacity: u32,
    pub resume_capacity: u32,
    pub resume_needed: u32,
    pub depth_lo: u32,
    pub depth_hi: u32,
    pub listed_blocks: u32,
    pub band_first: u32,
    pub band_count: u32,
    pub band_base: u32,
    pub band_first_block: u32,
    pub band_last_block: u32,
    pub band_next: u32,
    pub bands: u32,
    pub skipped_blocks: u32,
    pub abandoned_rows: u32,
    pub crowded_rows: u32,
    pub restarted_rows: u32,
    pub resume_item_capacity: u32,
    /// Blocks under the bounds of the triangles setup's occlusion cull dropped.
    pub occluded_blocks: u32,
    /// Workgroups of the depth pyramid, of the scan's first step and of the slab histogram
    /// that have finished (the last one goes on alone).
    pub groups_done: [u32; 3],
    pub pad: [u32; 4],
    pub statistics: [[u32; 16]; STATISTICS_SLOTS as usize],
    pub slab_farthest: [u32; MAX_SLABS as usize],
    pub slab_last_order: [u32; MAX_SLABS as usize],
    pub slab_floor_bits: [u32; MAX_SLABS as usize],
    pub slab_floor_order: [u32; MAX_SLABS as usize],
    pub bucket_weight_lo: [u32; MAX_SLABS as usize],
    pub bucket_weight_hi: [u32; MAX_SLABS as usize],
    /// Complemented, as the other `_least`.
    pub bucket_nearest_least: [u32; MAX_SLABS as usize],
    pub bucket_nearest_most: [u32; MAX_SLABS as usize],
    pub bucket_order_least: [u32; MAX_SLABS as usize],
    pub bucket_order_most: [u32; MAX_SLABS as usize],
}

impl Default for BinCounters {
    fn default() -> Self {
        Self::zeroed()
    }
}

impl BinCounters {
    /// Fragments the raster composited.
    pub fn fragments(&self) -> u64 {
        self.statistics.iter().map(|slot| u64::from(slot[0])).sum()
    }

    /// Fragments in front of the opaque layer that the raster's first sweep found, composited
    /// or not (a threshold stops pixels early); fewer where a pixel had to drop some.
    pub fn fragments_in_front(&self) -> u64 {
        self.statistics.iter().map(|slot| u64::from(slot[2])).sum()
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
        self.statistics
            .iter()
            .map(|slot| slot[1])
            .max()
            .unwrap_or(0)
    }
}

/// The push constants of every bin stage and of the rasters that read the bins.
#[repr(C)]
#[derive(Clone, Copy, Debug, Pod, Zeroable)]
pub struct BinPush {
    pub item_count: u32,
    pub draw_count: u32,
    pub width: u32,
    pub height: u32,
    pub bins_x: u32,
    pub bins_y: u32,
    pub threshold: f32,
    pub resume_list: u32,
    pub bin_rows_per_slice: u32,
    /// Workgroups the dispatches over triangles take in x; past it they go on in z.
    pub groups_x: u32,
    /// The submission's stamp, which the rasters write (transparent_layer.glsl).
    pub stamp: u32,
    /// 1 when the opaque depth bound is reversed-Z (the engine's own image).
    pub opaque_depth_reversed: u32,
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::glsl_layout::std430_offsets;
    use crate::scene::{Filter, MipFilter, Sampler, Wrap};
    use std::mem::{offset_of, size_of};

    const SRC: &str = include_str!("../../../../../shaders/common/bins_layout.glsl");
    const SRC_BINDINGS: &str = include_str!("../../../../../shaders/common/bins_bindings.glsl");

    fn define(name: &str) -> u32 {
        let line = SRC
            .lines()
            .find(|l| l.starts_with(&format!("#define {name} ")))
            .unwrap_or_else(|| panic!("{name} missing from bins_layout.glsl"));
        let value = line.split_whitespace().nth(2).expect("value");
        value.trim_end_matches('u').parse().expect("number")
    }

    fn offsets(name: &str) -> Vec<usize> {
        std430_offsets(SRC, name)
            .0
            .into_iter()
            .map(|(_, o)| o)
            .collect()
    }

    #[test]
    fn statistics_add_up_over_the_slots() {
        let mut c = BinCounters::default();
        for (k, slot) in c.statistics.iter_mut().enumerate() {
            let k = k as u32;
            *slot = [0; 16];
            slot[0] = 10 + k;
            slot[1] = k % 3;
            slot[2] = 100 * (k + 1);
        }
        let slots = u64::from(STATISTICS_SLOTS);
        assert_eq!(c.fragments(), 10 * slots + slots * (slots - 1) / 2);
        assert_eq!(c.sweeps(), 2);
        assert_eq!(c.fragments_in_front(), 100 * slots * (slots + 1) / 2);
    }

    #[test]
    fn constants_match_glsl() {
        assert_eq!(define("BIN_SHIFT"), BIN_SHIFT);
        assert_eq!(define("BIN_SIZE"), BIN_SIZE);
        assert_eq!(define("OVERFLOW_HOMOGENEOUS"), OVERFLOW_HOMOGENEOUS);
        assert_eq!(define("OVERFLOW_BIN_ENTRIES"), OVERFLOW_BIN_ENTRIES);
        assert_eq!(define("OVERFLOW_CROWDED_BIN"), OVERFLOW_CROWDED_BIN);
        assert_eq!(define("OVERFLOW_RESUME"), OVERFLOW_RESUME);
        assert_eq!(define("OVERFLOW_BAND_LISTS"), OVERFLOW_BAND_LISTS);
        assert_eq!(define("LOOP_BUDGET"), LOOP_BUDGET);
        assert_eq!(define("MAX_SELECT_SIZE"), MAX_SELECT_SIZE);
        assert_eq!(define("MAX_SLABS"), MAX_SLABS);
        assert_eq!(define("STATISTICS_SLOTS"), STATISTICS_SLOTS);
        assert_eq!(define("STATISTICS_WORDS"), STATISTICS_SLOTS * 16);
        assert_eq!(define("TRIANGLE_MATERIAL_SHIFT"), TRIANGLE_MATERIAL_SHIFT);
        assert_eq!(define("BINNING_GROUP_SIZE"), BINNING_GROUP_SIZE);
        assert_eq!(define("SCAN_GROUP_SIZE"), SCAN_GROUP_SIZE);
        assert_eq!(define("COLOUR_TEXELS"), COLOUR_TEXELS);
        assert_eq!(define("FLAT_COLOUR_TEXELS"), FLAT_COLOUR_TEXELS);
        assert_eq!(define("NORMAL_TEXELS"), NORMAL_TEXELS);
        assert_eq!(define("FACE_NORMAL_TEXELS"), FACE_NORMAL_TEXELS);
        assert_eq!(define("UV_TEXELS"), UV_TEXELS);
        let layer = include_str!("../../../../../shaders/common/transparent_layer.glsl");
        assert!(layer.contains(&format!("const uint LAST_STAMP = {LAST_STAMP}u;")));
        let commands = u64::from(define("DRAW_COMPOSITE")) + 1;
        assert_eq!(commands * 16, DISPATCH_BYTES);
        assert_eq!(
            u64::from(define("DRAW_COMPOSITE")) * 16,
            DRAW_COMPOSITE_OFFSET
        );
        let words = SRC_BINDINGS
            .split("uint g_dispatch[")
            .nth(1)
            .and_then(|rest| rest.split(']').next())
            .and_then(|n| n.parse::<u64>().ok());
        assert_eq!(words, Some(DISPATCH_BYTES / 4));
        assert_eq!(
            u64::from(define("DISPATCH_BAND_FILL")) * 16,
            DISPATCH_BAND_FILL_OFFSET
        );
        assert_eq!(
            u64::from(define("DISPATCH_BIN_OFFSETS")) * 16,
            DISPATCH_BIN_OFFSETS_OFFSET
        );
        assert_eq!(
            u64::from(define("DISPATCH_BINNING")) * 16,
            DISPATCH_BINNING_OFFSET
        );
        let bins = u64::from(define("DISPATCH_RASTER_BINS")) * 16;
        assert_eq!(bins, DISPATCH_RASTER_BINS_OFFSET);
    }

    /// bins_bindings.glsl and bin_fragment.glsl read these records texel by texel (16 bytes
    /// each) in field order; their loaders are right only while every field sits where they
    /// expect.
    #[test]
    fn texel_loaders_match_the_records() {
        let msg = "a record changed: update its loaders (bins_bindings.glsl, bin_fragment.glsl) \
                   and this test";
        assert_eq!(
            offsets("BinTriangleRecord"),
            [0, 16, 24, 28, 32, 44, 48, 60],
            "{msg}"
        );
        assert_eq!(
            offsets("BinHomogeneous"),
            [0, 32, 64, 96, 128, 160, 176],
            "{msg}"
        );
        assert_eq!(offsets("BinTexture")[..6], [0, 4, 8, 12, 16, 20], "{msg}");
        let scene = include_str!("../../../../../shaders/common/layout.glsl");
        let material: Vec<usize> = std430_offsets(scene, "Material")
            .0
            .into_iter()
            .map(|(_, o)| o)
            .collect();
        assert_eq!(material, [0, 16, 32, 36, 40, 44], "{msg}");
        assert_eq!(std430_offsets(scene, "Material").1, 48, "{msg}");
    }

    #[test]
    fn layouts_match_glsl() {
        let msg = "methods/bins/layout.rs and bins_layout.glsl disagree; update both";
        assert_eq!(
            std430_offsets(SRC, "BinTriangleRecord").1 as u64,
            TRIANGLE_BYTES,
            "{msg}"
        );
        assert_eq!(
            std430_offsets(SRC, "BinHomogeneous").1 as u64,
            HOMOGENEOUS_BYTES,
            "{msg}"
        );
        assert_eq!(
            offsets("BinDraw"),
            [
                offset_of!(BinDraw, mvp),
                offset_of!(BinDraw, draw_index),
                offset_of!(BinDraw, first_item),
                offset_of!(BinDraw, quad_count),
                offset_of!(BinDraw, first_quad)
            ],
            "{msg}"
        );
        assert_eq!(
            std430_offsets(SRC, "BinDraw").1,
            size_of::<BinDraw>(),
            "{msg}"
        );
        let counters = [
            offset_of!(BinCounters, triangle_count),
            offset_of!(BinCounters, homogeneous_count),
            offset_of!(BinCounters, bin_entry_count),
            offset_of!(BinCounters, overflow),
            offset_of!(BinCounters, triangle_capacity),
            offset_of!(BinCounters, homogeneous_capacity),
            offset_of!(BinCounters, bin_entry_capacity),
            offset_of!(BinCounters, resume_capacity),
            offset_of!(BinCounters, resume_needed),
            offset_of!(BinCounters, depth_lo),
            offset_of!(BinCounters, depth_hi),
            offset_of!(BinCounters, listed_blocks),
            offset_of!(BinCounters, band_first),
            offset_of!(BinCounters, band_count),
            offset_of!(BinCounters, band_base),
            offset_of!(BinCounters, band_first_block),
            offset_of!(BinCounters, band_last_block),
            offset_of!(BinCounters, band_next),
            offset_of!(BinCounters, bands),
            offset_of!(BinCounters, skipped_blocks),
            offset_of!(BinCounters, abandoned_rows),
            offset_of!(BinCounters, crowded_rows),
            offset_of!(BinCounters, restarted_rows),
            offset_of!(BinCounters, resume_item_capacity),
            offset_of!(BinCounters, occluded_blocks),
            offset_of!(BinCounters, groups_done),
            offset_of!(BinCounters, pad),
            offset_of!(BinCounters, statistics),
            offset_of!(BinCounters, slab_farthest),
            offset_of!(BinCounters, slab_last_order),
            offset_of!(BinCounters, slab_floor_bits),
            offset_of!(BinCounters, slab_floor_order),
            offset_of!(BinCounters, bucket_weight_lo),
            offset_of!(BinCounters, bucket_weight_hi),
            offset_of!(BinCounters, bucket_nearest_least),
            offset_of!(BinCounters, bucket_nearest_most),
            offset_of!(BinCounters, bucket_order_least),
            offset_of!(BinCounters, bucket_order_most),
        ];
        assert_eq!(offsets("BinCounters"), counters, "{msg}");
        assert_eq!(
            std430_offsets(SRC, "BinCounters").1,
            size_of::<BinCounters>(),
            "{msg}"
        );
        assert_eq!(
            std430_offsets(SRC, "BinTexture").1,
            size_of::<BinTexture>(),
            "{msg}"
        );
        assert_eq!(
            std430_offsets(SRC, "ExactPixelState").1 as u64,
            PIXEL_STATE_BYTES,
            "{msg}"
        );
        assert_eq!(
            offsets("BinTexture")[4..6],
            [
                offset_of!(BinTexture, srgb),
                offset_of!(BinTexture, sampler)
            ],
            "{msg}"
        );
    }

    #[test]
    fn sampler_bits_match_glsl() {
        let defines = [
            ("SAMPLER_WRAP_S_SHIFT", SAMPLER_WRAP_S_SHIFT.to_string()),
            ("SAMPLER_WRAP_T_SHIFT", SAMPLER_WRAP_T_SHIFT.to_string()),
            ("SAMPLER_WRAP_MASK", "3u".into()),
            ("SAMPLER_WRAP_REPEAT", format!("{SAMPLER_WRAP_REPEAT}u")),
            (
                "SAMPLER_WRAP_CLAMP_TO_EDGE",
                format!("{SAMPLER_WRAP_CLAMP_TO_EDGE}u"),
            ),
            (
                "SAMPLER_WRAP_MIRRORED_REPEAT",
                format!("{SAMPLER_WRAP_MIRRORED_REPEAT}u"),
            ),
            ("SAMPLER_MAG_LINEAR", format!("{SAMPLER_MAG_LINEAR}u")),
            ("SAMPLER_MIN_LINEAR", format!("{SAMPLER_MIN_LINEAR}u")),
            ("SAMPLER_MIP_SHIFT", SAMPLER_MIP_SHIFT.to_string()),
            ("SAMPLER_MIP_MASK", "3u".into()),
            ("SAMPLER_MIP_NONE", format!("{SAMPLER_MIP_NONE}u")),
            ("SAMPLER_MIP_NEAREST", format!("{SAMPLER_MIP_NEAREST}u")),
            ("SAMPLER_MIP_LINEAR", format!("{SAMPLER_MIP_LINEAR}u")),
        ];
        for (name, value) in defines {
            let line = format!("#define {name} {value}\n");
            assert!(
                SRC.contains(&line),
                "bins_layout.glsl lacks `{}`: update it and layout.rs together",
                line.trim()
            );
        }
        // The fields do not overlap.
        let all = Sampler {
            wrap_s: Wrap::MirroredRepeat,
            wrap_t: Wrap::MirroredRepeat,
            mag_filter: Filter::Linear,
            min_filter: Filter::Linear,
            mip_filter: MipFilter::Linear,
        };
        assert_eq!(sampler_bits(&all), 2 | 2 << 2 | 16 | 32 | 2 << 6);
    }
}
