//! `exact`: the compute bin rasterizer. Every pixel composites exactly the fragments the CPU
//! reference does, in the same order, under the same raster rules.
//!
//! The frame's transparent triangles are first sorted into per-bin lists by the bins
//! ([`super::bins`]: depth pyramid, setup, count, scan, fill, in bands). Then, per band,
//! `raster` (`shaders/exact/raster.comp`): one workgroup per block row with triangles, one
//! invocation per pixel; each pixel selects its nearest remaining fragments in registers,
//! composites them front to back over the opaque colour, and repeats until none is left (or
//! transmittance is under the threshold). On slab-ordered lists a row's walk ends once every
//! pixel holds fragments nearer than the next slab, and starts past the slabs its pixels have
//! composited. Rows of pixels that reach the driver's loop budget are saved where they stopped
//! (even inside one slab's part of a list, with their selections) and finished by
//! continuation dispatches of the same shader, sized on the GPU (indirect dispatch).
//!
//! Why this shape: on lavapipe (subgroups of 8, 32 KB shared memory) barrier-heavy
//! shared-memory phases cost more than blending itself, fixed-size register work is cheap, an
//! `if` runs both its sides, and data read in loops is cheapest through texel views
//! (`docs/performance-log.md`). Selection by key (view depth, draw, quad, triangle) is exact by
//! construction, so no pixel can come out of order and no fallback path is needed.
//!
//! Suspended rows always find room on the resume lists; those that find no slot for their
//! pixels' state start over when resumed. Bands without blocks go on resuming the last
//! band's rows with their one continuation. Rows still unfinished after the last
//! continuation are left untouched: a further submission of continuations finishes them (or,
//! on an engine's device, the frame reports them).

#![deny(clippy::unwrap_used)]

use super::bins::features::RasterFeatures;
use super::bins::{BinOptions, Bins, FINISHED_SUBMISSION_WRITES};
use super::{FrameCheck, FrameDone, FrameSetup, Method, RecordContext};
use crate::assets::GpuScene;
use crate::frame::FrameTargets;
use crate::gpu::ComputePipeline;
use crate::scene::Scene;
use crate::Result;
use std::sync::Arc;

/// The exact method's settings.
#[derive(Clone, Debug, Default)]
pub struct ExactOptions {
    /// Stop compositing a pixel once every channel of its transmittance is below this. 0 (the
    /// default) composites every fragment: the exact result.
    pub threshold: f32,
    /// Start with the settings frames with deep pixels move to (more fragments per pass, bins
    /// ordered by depth slab), so that tests can check them on every scene.
    #[doc(hidden)]
    pub assume_deep_pixels: bool,
}

const RASTER: &[u8] = crate::spirv!("exact/raster.comp");
/// The work bound, per row: with about 60,000 loop iterations each (some 30 M list entries
/// in all), this many continuations finish a row of any frame this method renders in
/// reasonable time (10,000 full-screen layers take a few hundred); past it the frame fails
/// with an error. Continuations with no rows cost an empty indirect dispatch.
const MAX_CONTINUATIONS: u32 = 512;
/// The work bound, per frame: continuations times the rows they resume, at most (some 10 s
/// of lavapipe on 2 cores), so that a hostile frame with many deep rows is refused in
/// seconds, not hours.
const MAX_ROW_CONTINUATIONS: u64 = 1 << 12;
/// Continuations are multiplied by this when rows were left unfinished: a deep frame finds
/// its count in a few re-renders (1, 8, 64, 512).
const CONTINUATION_GROWTH: u32 = 8;

pub struct Exact {
    bins: Bins,
    raster: Arc<ComputePipeline>,
    /// The raster shader again, specialized to resume suspended rows.
    continuation: Arc<ComputePipeline>,
    continuations: Continuations,
    /// The resume list holding the rows the last submission left unfinished.
    pending_list: u32,
    /// Per frame slot, the continuations its last submission was recorded with, and whether
    /// that submission was a frame's finishing one.
    recorded: Vec<(Continuations, bool)>,
}

/// Continuation dispatches recorded after each band's raster, each multiplied when the rows
/// of its band were still unfinished after the last one.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
struct Continuations {
    /// After the first band's raster, and in a finishing submission.
    first_band: u32,
    /// After each later band's: they have blocks only in frames past the lists' capacity (and
    /// when empty they go on resuming the last band's rows).
    later_bands: u32,
}

impl Continuations {
    const START: Self = Self {
        first_band: 1,
        later_bands: 1,
    };

    /// The most continuations a band records.
    fn most(self) -> u32 {
        self.first_band.max(self.later_bands)
    }

    /// The continuations after a submission that left rows unfinished: more for the band
    /// whose rows they were (the last band with blocks, of `bands`; the first band's for a
    /// finishing submission). `None` past MAX_CONTINUATIONS.
    fn grown(self, bands: u32, finishing: bool) -> Option<Self> {
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

impl Exact {
    pub fn new(
        gpu: &crate::gpu::Gpu,
        scene: &Scene,
        gpu_scene: &GpuScene,
        targets: &FrameTargets,
        bins: &BinOptions,
        options: &ExactOptions,
    ) -> Result<Self> {
        let (width, height) = (targets.extent.width, targets.extent.height);
        let deep = options.assume_deep_pixels;
        let shape = |features: RasterFeatures, expected: u64| {
            let features = features.expecting(expected, width, height);
            if deep {
                features.deep()
            } else {
                features
            }
        };
        let mut bins = Bins::new(gpu, scene, gpu_scene, targets, bins, "exact", shape)?;
        bins.set_threshold(options.threshold);
        let (raster, continuation) = select(&mut bins, gpu_scene)?;
        Ok(Self {
            bins,
            raster,
            continuation,
            continuations: Continuations::START,
            pending_list: 0,
            recorded: vec![(Continuations::START, false); gpu_scene.slot_count()],
        })
    }

    /// The raster's pipelines for the bins' features.
    fn select_raster(&mut self, gpu_scene: &GpuScene) -> Result<()> {
        (self.raster, self.continuation) = select(&mut self.bins, gpu_scene)?;
        Ok(())
    }

    /// The raster over the band's blocks, then `continuations` continuations (the
    /// recording's `last`). The raster suspends rows onto the pending list: the band's plan
    /// emptied it if the band has blocks; if not, it holds the rows the last band left, which
    /// these continuations go on resuming.
    fn record_raster(&mut self, ctx: &RecordContext<'_>, continuations: u32, last: bool) {
        self.bins
            .record_raster(ctx, &self.raster, self.pending_list);
        self.record_continuations(ctx, continuations, last);
    }

    /// `count` continuation dispatches from the pending list: each resumes the rows on one
    /// list and suspends rows onto the other, which the next reads. `last`: nothing after
    /// them in the recording appends to the lists.
    fn record_continuations(&mut self, ctx: &RecordContext<'_>, count: u32, last: bool) {
        for k in 0..count {
            let final_one = last && k + 1 == count;
            self.bins
                .record_continuation(ctx, &self.continuation, self.pending_list, final_one);
            self.pending_list ^= 1;
        }
    }
}

/// The raster and its continuation, specialized for `bins`' features.
fn select(
    bins: &mut Bins,
    gpu_scene: &GpuScene,
) -> Result<(Arc<ComputePipeline>, Arc<ComputePipeline>)> {
    let features = bins.features();
    Ok((
        bins.pipeline(gpu_scene, RASTER, &features.constants(false))?,
        bins.pipeline(gpu_scene, RASTER, &features.constants(true))?,
    ))
}

impl Method for Exact {
    fn name(&self) -> &'static str {
        "exact"
    }

    fn composites_in_place(&self) -> bool {
        true
    }

    fn set_frame(&mut self, f: &FrameSetup<'_>) -> Result<()> {
        if self.bins.set_frame(f)? {
            self.select_raster(f.gpu_scene)?;
        }
        Ok(())
    }

    fn record(&mut self, ctx: &mut RecordContext<'_>) -> Result<()> {
        let cmd = ctx.cmd;
        self.bins.record_binning(ctx)?;
        self.recorded[ctx.slot] = (self.continuations, false);
        // Both resume lists start empty.
        self.pending_list = 0;
        let bands = self.bins.bands();
        for band in 0..bands {
            let first = band == 0;
            self.bins.record_band(ctx, first, self.pending_list);
            let continuations = if first {
                self.continuations.first_band
            } else {
                self.continuations.later_bands
            };
            self.record_raster(ctx, continuations, band + 1 == bands);
            self.bins.compute_to_compute(cmd);
        }
        ctx.timestamps.mark(cmd, "raster");
        self.bins.record_end(ctx, self.pending_list)
    }

    fn record_finish(&mut self, ctx: &mut RecordContext<'_>) -> Result<()> {
        self.recorded[ctx.slot] = (self.continuations, true);
        self.bins.targets_to_raster(ctx, FINISHED_SUBMISSION_WRITES);
        // The submission before left the list its last continuation read as it was.
        self.bins
            .record_resume_list_empty(ctx.cmd, self.pending_list ^ 1);
        self.record_continuations(ctx, self.continuations.first_band, true);
        ctx.timestamps.mark(ctx.cmd, "raster finished");
        self.bins.record_end(ctx, self.pending_list)
    }

    fn frame_done(&mut self, done: &FrameDone<'_>) -> Result<FrameCheck> {
        let (recorded, finishing) = self.recorded[done.slot % self.recorded.len()];
        // A row of a shallow frame whose list is too long for one pass of the loop budget:
        // the continuations walked it in parts (this frame is right), and later frames bin
        // in depth slabs, where the first dispatch does too. Deep pixels: select more
        // fragments per pass, or order the bins by depth slab, from the next frame on (this
        // one is right either way).
        let bins = self
            .bins
            .frame_done(done, |features, counters, (width, height)| {
                let features = if counters.overflow & super::bins::layout::OVERFLOW_CROWDED_BIN != 0
                {
                    features.deep()
                } else {
                    features
                };
                features.after_frame(
                    counters.sweeps(),
                    counters.fragments_in_front(),
                    width,
                    height,
                )
            })?;
        if bins.features_changed {
            self.select_raster(done.gpu_scene)?;
        }
        let counters = bins.counters;
        // Rows the last dispatch left on the pending list are unfinished.
        let unfinished = self.bins.unfinished_rows(done.slot)?;
        // (Continuations already multiplied since the frame was recorded are left alone.)
        if unfinished > 0 && recorded == self.continuations {
            let too_deep = |more: String| {
                crate::Error::TooLarge(format!(
                    "exact: {unfinished} pixel rows still unfinished after {} continuation \
                     dispatches; {more} would pass the frame's work bound (README, \"The work \
                     bound\")",
                    recorded.most()
                ))
            };
            let Some(grown) = self.continuations.grown(counters.bands, finishing) else {
                return Err(too_deep(format!("more than {MAX_CONTINUATIONS} a row")));
            };
            if u64::from(unfinished) * u64::from(grown.most()) > MAX_ROW_CONTINUATIONS {
                return Err(too_deep(format!(
                    "{} for each of them (at most {MAX_ROW_CONTINUATIONS} in all)",
                    grown.most()
                )));
            }
            self.continuations = grown;
            log::info!(
                "exact: {unfinished} rows unfinished; {:?} continuations next",
                self.continuations
            );
        }
        // Unfinished rows are finished by another submission of continuations, unless the
        // frame must be rendered again anyway, or its pipelines changed under the saved rows.
        // (A finishing submission reads the buffers the frame used: not after they grew.)
        let finish = unfinished > 0 && !bins.rerender && !bins.features_changed && !bins.grown;
        let rerender = bins.rerender || (unfinished > 0 && !finish);
        let kept = |count: u64| if rerender || finish { 0 } else { count };
        Ok(FrameCheck {
            rerender,
            finish,
            degraded_rows: bins.degraded_rows,
            unfinished_rows: u64::from(unfinished),
            bands: counters.bands,
            fragments: kept(counters.fragments()),
            sweeps: counters.sweeps(),
            triangles: kept(u64::from(counters.triangle_count)),
            ..FrameCheck::default()
        })
    }

    fn learned(&self, options: &mut super::MethodOptions) {
        self.bins.learned(&mut options.bins);
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
