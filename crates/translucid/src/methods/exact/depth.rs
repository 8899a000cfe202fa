//! How the exact raster follows deep frames: the fragments a pixel selects per pass over its
//! row's list, and the depth slabs the bins order each list by. Both only ever grow, so that a
//! scene does not rebuild its pipelines back and forth.

use crate::interface::bins::{BIN_SIZE, MAX_SLABS};
use crate::interface::exact::MAX_SELECT_SIZE;

/// The selection size to start with, and the ones frames with deep pixels move to, a step at
/// a time while some pixel still needs more than two sweeps. (On lavapipe at 1280x720, with
/// the raster compositing after each slab: particles, 60 deep, take three sweeps of 16 and
/// are 5-10 % slower with 24, and 1.4x slower with 8; hairball is faster with 16 than 8.)
pub const SELECT_SIZE: u32 = 8;
const SELECT_STEPS: [u32; 2] = [SELECT_SIZE, DEEP_SELECT_SIZE];
pub const DEEP_SELECT_SIZE: u32 = 16;
// A suspended row saves its pixels' selections (ExactPixelState).
const _: () = assert!(DEEP_SELECT_SIZE <= MAX_SELECT_SIZE);
/// Frames averaging more fragments per pixel than this order their bins by depth slab:
/// there pixels need several sweeps, and compositing after each slab repays the longer scan of
/// 2^DEEP_SLAB_BITS slabs per bin. (On lavapipe at 1280x720, slabs take particles, about 18
/// per pixel, from 1.5 to 0.9 s of raster, and cost hairball, about 1, a fifth of its time.
/// Sixteen slabs took particles 4 % under eight, 2.5 % with `--threshold 0.05`; 32 were no
/// faster, their longer scan eating what the raster saved.)
pub const SLAB_FRAGMENTS_PER_PIXEL: u64 = 8;
pub const DEEP_SLAB_BITS: u32 = 4;
/// Deeper frames take more slabs: one per FRAGMENTS_PER_SLAB fragments of their average pixel,
/// rounded up to a power of two, while the (bin, slab) arrays stay within MAX_BIN_SLABS words
/// (16 MB each) and up to MAX_SLABS. A sweep composites at most a selection's worth of a
/// pixel's fragments per slab, so a pixel D deep in slabs of S of its fragments costs about
/// D S / DEEP_SELECT_SIZE triangle visits: with 16 slabs, 10,000 full-screen layers took 12x
/// blend's time.
const FRAGMENTS_PER_SLAB: u64 = 8;
const MAX_BIN_SLABS: u64 = 1 << 22;
const MAX_SLAB_BITS: u32 = MAX_SLABS.trailing_zeros();
const _: () = assert!(MAX_SLABS.is_power_of_two());
const _: () = assert!(DEEP_SLAB_BITS <= MAX_SLAB_BITS);

/// The selection and the slabs a frame is rendered with.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Depth {
    /// Fragments each pixel selects per pass over its row's list (the raster's SELECT_SIZE).
    pub select_size: u32,
    /// Each bin's list holds 2^slab_bits depth slabs (the bins' SLAB_BITS).
    pub slab_bits: u32,
}

impl Depth {
    /// A shallow frame's: the small selection, one slab.
    pub const SHALLOW: Self = Self {
        select_size: SELECT_SIZE,
        slab_bits: 0,
    };

    /// Whether a frame of `width` x `height` pixels with `fragments` fragments is deep enough
    /// to order its lists by slab.
    pub fn is_deep(fragments: u64, width: u32, height: u32) -> bool {
        fragments > SLAB_FRAGMENTS_PER_PIXEL * u64::from(width) * u64::from(height)
    }

    /// What the next frame should use after one of `width` x `height` pixels with
    /// `fragments` fragments in front of the opaque layer, some pixel needing `sweeps` sweeps.
    /// (Fragments found, not composited: with a threshold, pixels composite fewer than they
    /// have, and counting those kept the deep particles of `--threshold 0.2` from their
    /// slabs.)
    pub fn after_frame(self, sweeps: u32, fragments: u64, width: u32, height: u32) -> Self {
        let mut next = self;
        if sweeps > 2 {
            next.select_size = SELECT_STEPS
                .into_iter()
                .find(|&size| size > self.select_size)
                .unwrap_or(self.select_size);
        }
        let pixels = u64::from(width) * u64::from(height);
        let most = max_slab_bits(width, height);
        if Self::is_deep(fragments, width, height) {
            let slabs = (fragments / pixels / FRAGMENTS_PER_SLAB).next_power_of_two();
            let bits = slabs.trailing_zeros().min(most);
            next.slab_bits = self.slab_bits.max(bits).max(DEEP_SLAB_BITS);
        }
        // Pixels deeper than the average, or depths bunched in a few slabs: twice as many.
        // (In slabs, the first sweep's count stops where a pixel first drops a fragment.)
        if self.slab_bits > 0 && sweeps > 2 {
            next.slab_bits = next.slab_bits.max((self.slab_bits + 1).min(most));
        }
        next
    }

    /// What a first frame should use when the scene's triangles are expected to put
    /// `fragments` fragments over its `width` x `height` pixels: frames deep enough for
    /// slabs start with them and the deep selection, instead of being rendered once without
    /// and then again.
    pub fn expecting(self, fragments: u64, width: u32, height: u32) -> Self {
        let next = self.after_frame(0, fragments, width, height);
        if next.slab_bits > self.slab_bits {
            Self {
                select_size: DEEP_SELECT_SIZE,
                ..next
            }
        } else {
            next
        }
    }

    /// The depths a declared loop with deep pixels moves between, all built up front: the
    /// two selections, with and without DEEP_SLAB_BITS of slabs.
    pub const DECLARED: [Self; 4] = [
        Self::SHALLOW,
        Self {
            select_size: DEEP_SELECT_SIZE,
            slab_bits: 0,
        },
        Self {
            select_size: SELECT_SIZE,
            slab_bits: DEEP_SLAB_BITS,
        },
        Self {
            select_size: DEEP_SELECT_SIZE,
            slab_bits: DEEP_SLAB_BITS,
        },
    ];

    /// This depth within what a declared loop built up front ([`Self::DECLARED`]): fewer
    /// slabs than the frame would take, where it would take more (as right, a little slower).
    pub fn declared(self) -> Self {
        Self {
            slab_bits: self.slab_bits.min(DEEP_SLAB_BITS),
            ..self
        }
    }

    /// At least everything deep frames move to.
    pub fn deep(self) -> Self {
        Self {
            select_size: self.select_size.max(DEEP_SELECT_SIZE),
            slab_bits: self.slab_bits.max(DEEP_SLAB_BITS),
        }
    }
}

/// The most slab bits a frame of `width` x `height` pixels takes: as many as keep its (bin,
/// slab) arrays within MAX_BIN_SLABS words, but at least DEEP_SLAB_BITS and at most the
/// counters' MAX_SLABS.
fn max_slab_bits(width: u32, height: u32) -> u32 {
    let bins = u64::from(width.div_ceil(BIN_SIZE))
        * u64::from(height.div_ceil(BIN_SIZE))
        * u64::from(BIN_SIZE);
    let fit = (MAX_BIN_SLABS / bins.max(1)).max(1).ilog2();
    fit.clamp(DEEP_SLAB_BITS, MAX_SLAB_BITS)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn deep_frames_step_the_selection_up_and_never_down() {
        let start = Depth::SHALLOW;
        let (w, h) = (640, 360);
        let pixels = u64::from(w * h);
        let sizes: Vec<u32> =
            std::iter::successors(Some(start), |d| Some(d.after_frame(3, 0, w, h)))
                .map(|d| d.select_size)
                .take(5)
                .collect();
        assert_eq!(sizes, [8, 16, 16, 16, 16]);
        let shallow = start.after_frame(2, 0, w, h);
        assert_eq!(shallow.select_size, 8, "two sweeps keep the size");
        assert_eq!(shallow.slab_bits, 0);
        assert_eq!(
            start.after_frame(1, 9 * pixels, w, h).slab_bits,
            DEEP_SLAB_BITS
        );
    }

    #[test]
    fn deeper_frames_take_more_slabs_within_the_arrays_bound() {
        let bits = |w: u32, h: u32, depth: u64| {
            Depth::SHALLOW
                .after_frame(1, depth * u64::from(w * h), w, h)
                .slab_bits
        };
        assert_eq!(bits(32, 24, 60), DEEP_SLAB_BITS);
        assert_eq!(bits(32, 24, 1000), 7, "1000 / 8 rounds up to 128 slabs");
        assert_eq!(bits(32, 24, 10_000), MAX_SLAB_BITS);
        // 1280x720 has 115,200 row bins: 32 slabs each fit in 2^22 words, 64 do not.
        assert_eq!(bits(1280, 720, 10_000), 5);
        // Never fewer than deep frames start with, even where the bound is smaller.
        assert_eq!(bits(7680, 4320, 10_000), DEEP_SLAB_BITS);
        // Only ever more.
        let deep = Depth::SHALLOW.after_frame(1, 1000 * 32 * 24, 32, 24);
        assert_eq!(deep.after_frame(1, 9 * 32 * 24, 32, 24).slab_bits, 7);
        assert_eq!(deep.deep().slab_bits, 7);
        // Pixels that still need several sweeps double the slabs, up to the bound.
        assert_eq!(deep.after_frame(3, 9 * 32 * 24, 32, 24).slab_bits, 8);
        let wide = Depth::SHALLOW.after_frame(1, 60 * 1280 * 720, 1280, 720);
        assert_eq!(wide.slab_bits, DEEP_SLAB_BITS);
        assert_eq!(wide.after_frame(3, 0, 1280, 720).slab_bits, 5);
        assert_eq!(
            wide.after_frame(3, 0, 1280, 720)
                .after_frame(3, 0, 1280, 720)
                .slab_bits,
            5
        );
    }

    #[test]
    fn a_frame_expected_deep_starts_with_slabs_and_the_deep_selection() {
        let (w, h) = (64, 48);
        let pixels = u64::from(w * h);
        assert_eq!(Depth::SHALLOW.expecting(2 * pixels, w, h), Depth::SHALLOW);
        let deep = Depth::SHALLOW.expecting(20 * pixels, w, h);
        assert_eq!(deep.select_size, DEEP_SELECT_SIZE);
        assert_eq!(deep.slab_bits, DEEP_SLAB_BITS);
    }
}
