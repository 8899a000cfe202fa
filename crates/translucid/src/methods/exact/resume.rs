//! Rows the exact raster suspends at the loop budget, and the continuation dispatches that
//! resume them: the resume lists' state (`ExactPixelState`, in a binding that extends the
//! bins' set), how many continuations a band records, and how they are recorded.

use super::raster::Raster;
use crate::interface::bins::BIN_SIZE;
use crate::interface::exact::{ExactPixelState, EXACT_RASTER_SET};
use crate::methods::bins::{Bins, SuspendedRows};
use crate::methods::RecordContext;

/// State slots each resume list starts with, in rows' worth, in frames expected to be deep
/// (`Depth::is_deep`) and in the others (a tile of several rows takes one slot for all of
/// them). Rows suspend only where one walks tens of thousands of list entries
/// (pixels hundreds of fragments deep): none of the bench's six scenes at 1280x720 suspends
/// one, and a shallow frame only in a crowded bin, whose block has BIN_SIZE rows. A slot holds
/// a row's pixels (1.5 KB, and as much again on the other list), so slots for a sixteenth of a
/// 720p frame's rows took 21 MB that no frame used. A frame that needs more restarts the rows
/// it finds no slot for and grows the slots from what the GPU counted.
const DEEP_STATE_SLOTS: u32 = 256;
const SHALLOW_STATE_SLOTS: u32 = 4 * BIN_SIZE;

/// What the raster keeps of a suspended tile of 2^tile_shift rows: its pixels' states.
pub fn suspended_rows(deep: bool, tile_shift: u32) -> SuspendedRows {
    let pixels = u64::from(BIN_SIZE << tile_shift);
    SuspendedRows {
        set: &EXACT_RASTER_SET,
        binding: "PixelStateBlock",
        bytes_per_tile: pixels * std::mem::size_of::<ExactPixelState>() as u64,
        initial_slots: if deep {
            DEEP_STATE_SLOTS >> tile_shift
        } else {
            SHALLOW_STATE_SLOTS >> tile_shift
        },
    }
}

/// The work bound, per row: with a CPU driver's 60,000 loop iterations each (some 30 M list
/// entries in all; `DeviceInfo::loop_budget`), this many continuations finish a row of any frame this method renders in
/// reasonable time (10,000 full-screen layers take a few hundred); past it the frame fails
/// with an error. Continuations with no rows cost an empty indirect dispatch.
pub const MAX_CONTINUATIONS: u32 = 512;
/// The work bound, per frame: continuations times the rows they resume, at most (some 10 s
/// of lavapipe on 2 cores), so that a hostile frame with many deep rows is refused in
/// seconds, not hours.
pub const MAX_ROW_CONTINUATIONS: u64 = 1 << 12;
/// Continuations are multiplied by this when rows were left unfinished: a deep frame finds
/// its count in a few re-renders (1, 8, 64, 512).
const CONTINUATION_GROWTH: u32 = 8;

/// Continuation dispatches recorded after each band's raster, each multiplied when the rows
/// of its band were still unfinished after the last one.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Continuations {
    /// After the first band's raster, and in a finishing submission.
    pub first_band: u32,
    /// After each later band's: they have blocks only in frames past the lists' capacity (and
    /// when empty they go on resuming the last band's rows).
    pub later_bands: u32,
}

impl Continuations {
    pub const START: Self = Self {
        first_band: 1,
        later_bands: 1,
    };

    /// The continuations after band `band`'s raster.
    pub fn after_band(self, band: u32) -> u32 {
        if band == 0 {
            self.first_band
        } else {
            self.later_bands
        }
    }

    /// The most continuations a band records.
    pub fn most(self) -> u32 {
        self.first_band.max(self.later_bands)
    }

    /// The continuations after a submission that left rows unfinished: more for the band
    /// whose rows they were (the last band with blocks, of `bands`; the first band's for a
    /// finishing submission). `None` past MAX_CONTINUATIONS.
    pub fn grown(self, bands: u32, finishing: bool) -> Option<Self> {
        let grow = |count: u32| {
            (count < MAX_CONTINUATIONS)
                .then(|| (count * CONTINUATION_GROWTH).min(MAX_CONTINUATIONS))
        };
        Some(if finishing || bands <= 1 {
            Self {
                first_band: grow(self.first_band)?,
                ..self
            }
        } else {
            Self {
                later_bands: grow(self.later_bands)?,
                ..self
            }
        })
    }
}

/// Which of the two resume lists holds the rows still to resume. Each dispatch resumes the
/// rows on one list and suspends rows onto the other, which the next reads.
#[derive(Clone, Copy, Debug, Default)]
pub struct ResumeLists {
    pub pending: u32,
}

impl ResumeLists {
    /// The raster over the band's blocks, then `continuations` continuations (the
    /// recording's `last`). The raster suspends rows onto the pending list: the band's plan
    /// emptied it if the band has blocks; if not, it holds the rows the last band left, which
    /// these continuations go on resuming.
    pub fn record_band(
        &mut self,
        bins: &Bins,
        ctx: &RecordContext<'_>,
        raster: &Raster,
        continuations: u32,
        last: bool,
    ) {
        bins.record_raster(ctx, &raster.first, self.pending);
        self.record_continuations(bins, ctx, raster, continuations, last);
    }

    /// `count` continuation dispatches from the pending list. Each but the recording's last
    /// (`last`: nothing after them appends to the lists) empties the list it read for the rows
    /// the next one suspends. (The last one's list is left as it is: the host reads the other,
    /// the next frame empties both, and a further submission of continuations empties it
    /// first.)
    pub fn record_continuations(
        &mut self,
        bins: &Bins,
        ctx: &RecordContext<'_>,
        raster: &Raster,
        count: u32,
        last: bool,
    ) {
        for k in 0..count {
            bins.record_resumed(ctx, &raster.continuation, self.pending);
            if !(last && k + 1 == count) {
                bins.record_resume_list_empty(ctx.cmd, self.pending);
            }
            self.pending ^= 1;
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn continuations_grow_for_the_band_that_left_rows_unfinished() {
        let start = Continuations::START;
        let first = start.grown(1, false).expect("room");
        assert_eq!((first.first_band, first.later_bands), (8, 1));
        // Rows a later band left: its continuations grow, not the first band's, which would
        // otherwise climb to the limit in frames that stay banded.
        let later = start.grown(3, false).expect("room");
        assert_eq!((later.first_band, later.later_bands), (1, 8));
        // A finishing submission records the first band's count.
        let finishing = start.grown(3, true).expect("room");
        assert_eq!((finishing.first_band, finishing.later_bands), (8, 1));
        let mut c = start;
        for _ in 0..3 {
            c = c.grown(2, false).expect("room");
        }
        assert_eq!(c.later_bands, MAX_CONTINUATIONS);
        assert_eq!(c.grown(2, false), None);
        assert_eq!(c.grown(1, false).map(|c| c.first_band), Some(8));
    }
}
