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
/// With about 60,000 loop iterations each, this many continuations finish any pixel this
/// method can render in reasonable time (10,000 full-screen layers take a few hundred);
/// past it the frame fails with an error. Continuations with no rows cost an empty
/// indirect dispatch.
const MAX_CONTINUATIONS: u32 = 4096;
/// Continuations are multiplied by this when rows were left unfinished: a deep frame finds
/// its count in a few re-renders (1, 8, 64, 512, 4096).
const CONTINUATION_GROWTH: u32 = 8;

pub struct Exact {
    bins: Bins,
    raster: Arc<ComputePipeline>,
    /// The raster shader again, specialized to resume suspended rows.
    continuation: Arc<ComputePipeline>,
    /// Continuation dispatches recorded after the first band's raster; multiplied when some
    /// row was still unfinished after the last one.
    continuations: u32,
    /// The resume list holding the rows the last submission left unfinished.
    pending_list: u32,
    /// Per frame slot, the continuations its last frame was recorded with.
    recorded_continuations: Vec<u32>,
}

impl Exact {
    pub fn new(
        gpu: &crate::gpu::Gpu,
        scene: &Scene,
        uploaded: &GpuScene,
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
        let mut bins = Bins::new(gpu, scene, uploaded, targets, bins, "exact", shape)?;
        bins.set_threshold(options.threshold);
        let (raster, continuation) = select(&mut bins, uploaded)?;
        Ok(Self {
            bins,
            raster,
            continuation,
            continuations: 1,
            pending_list: 0,
            recorded_continuations: vec![1; uploaded.slot_count()],
        })
    }

    /// The raster's pipelines for the bins' features.
    fn select_raster(&mut self, uploaded: &GpuScene) -> Result<()> {
        (self.raster, self.continuation) = select(&mut self.bins, uploaded)?;
        Ok(())
    }

    /// The raster over the band's blocks, then `continuations` continuations. The raster
    /// suspends rows onto the pending list: the band's plan emptied it if the band has
    /// blocks; if not, it holds the rows the last band left, which these continuations go on
    /// resuming.
    fn record_raster(&mut self, ctx: &RecordContext<'_>, continuations: u32) {
        self.bins
            .record_raster(ctx, &self.raster, self.pending_list ^ 1);
        self.record_continuations(ctx, continuations);
    }

    /// `count` continuation dispatches from the pending list: each resumes the rows on one
    /// list and suspends rows onto the other, which the next reads.
    fn record_continuations(&mut self, ctx: &RecordContext<'_>, count: u32) {
        for _ in 0..count {
            self.bins
                .record_continuation(ctx, &self.continuation, self.pending_list);
            self.pending_list ^= 1;
        }
    }
}

/// The raster and its continuation, specialized for `bins`' features.
fn select(
    bins: &mut Bins,
    uploaded: &GpuScene,
) -> Result<(Arc<ComputePipeline>, Arc<ComputePipeline>)> {
    let features = bins.features();
    Ok((
        bins.pipeline(uploaded, RASTER, &features.constants(false))?,
        bins.pipeline(uploaded, RASTER, &features.constants(true))?,
    ))
}

impl Method for Exact {
    fn name(&self) -> &'static str {
        "exact"
    }

    fn set_frame(&mut self, f: &FrameSetup<'_>) -> Result<()> {
        if self.bins.set_frame(f)? {
            self.select_raster(f.uploaded)?;
        }
        Ok(())
    }

    fn record(&mut self, ctx: &mut RecordContext<'_>) -> Result<()> {
        let cmd = ctx.cmd;
        self.bins.record_binning(ctx)?;
        self.recorded_continuations[ctx.slot] = self.continuations;
        // Both resume lists start empty.
        self.pending_list = 0;
        for band in 0..self.bins.bands() {
            let first = band == 0;
            self.bins.record_band(ctx, first, self.pending_list);
            // Later bands take one continuation each: they have blocks only in frames past
            // the lists' capacity, and when empty they go on resuming the last band's rows.
            let continuations = if first { self.continuations } else { 1 };
            self.record_raster(ctx, continuations);
            self.bins.compute_to_compute(cmd);
        }
        self.bins.record_end(ctx, self.pending_list);
        ctx.timestamps.mark(cmd, "raster");
        Ok(())
    }

    fn record_finish(&mut self, ctx: &mut RecordContext<'_>) -> Result<()> {
        self.recorded_continuations[ctx.slot] = self.continuations;
        self.bins.targets_to_raster(ctx, FINISHED_SUBMISSION_WRITES);
        self.record_continuations(ctx, self.continuations);
        self.bins.record_end(ctx, self.pending_list);
        ctx.timestamps.mark(ctx.cmd, "raster finished");
        Ok(())
    }

    fn frame_done(&mut self, done: &FrameDone<'_>) -> Result<FrameCheck> {
        let recorded_continuations =
            self.recorded_continuations[done.slot % self.recorded_continuations.len()];
        let (width, height) = self.bins.size();
        // A row of a shallow frame whose list is too long for one pass of the loop budget:
        // the continuations walked it in parts (this frame is right), and later frames bin
        // in depth slabs, where the first dispatch does too. Deep pixels: select more
        // fragments per pass, or order the bins by depth slab, from the next frame on (this
        // one is right either way).
        let bins = self.bins.frame_done(done, |features, counters| {
            let features = if counters.overflow & super::bins::layout::OVERFLOW_CROWDED_BIN != 0 {
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
            self.select_raster(done.uploaded)?;
        }
        let counters = bins.counters;
        // Rows the last dispatch left on the pending list are unfinished.
        let unfinished = self.bins.unfinished_rows(done.slot)?;
        // (Continuations already multiplied since the frame was recorded are left alone.)
        if unfinished > 0 && recorded_continuations == self.continuations {
            if self.continuations >= MAX_CONTINUATIONS {
                return Err(crate::Error::InvalidScene(format!(
                    "exact: {unfinished} pixel rows still unfinished after {MAX_CONTINUATIONS} \
                     continuation dispatches; the frame is too deep for this driver"
                )));
            }
            self.continuations = (self.continuations * CONTINUATION_GROWTH).min(MAX_CONTINUATIONS);
            log::info!(
                "exact: {unfinished} rows unfinished; {} continuations next",
                self.continuations
            );
        }
        // Unfinished rows are finished by another submission of continuations, unless the
        // frame must be rendered again anyway, or its pipelines changed under the saved rows.
        // (A finishing submission reads the buffers the frame used: not after they grew.)
        let finish = unfinished > 0 && !bins.again && !bins.features_changed && !bins.grown;
        let rerender = bins.again || (unfinished > 0 && !finish);
        let kept = |count: u64| if rerender || finish { 0 } else { count };
        Ok(FrameCheck {
            rerender,
            finish,
            degraded_rows: bins.degraded_rows,
            unfinished_rows: u64::from(unfinished),
            bands: counters.bands,
            fragments: kept(counters.fragments()),
            triangles: kept(u64::from(counters.triangle_count)),
        })
    }

    fn learned(&self, options: &mut super::MethodOptions) {
        self.bins.learned(&mut options.bins);
    }
}
