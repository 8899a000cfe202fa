//! `exact`: the compute bin rasterizer. Every pixel composites exactly the fragments the CPU
//! reference does, in the same order, under the same raster rules.
//!
//! The frame's transparent triangles are first sorted into per-bin lists by the bins
//! ([`super::bins`]: depth pyramid, setup, count, scan, fill, in bands). Then, per band,
//! the raster (`shaders/exact/raster.comp`; [`raster`]): one workgroup per block row with
//! triangles, one invocation per pixel; each pixel selects its nearest remaining fragments in registers,
//! composites them front to back over the opaque colour, and repeats until none is left (or
//! transmittance is under the threshold). On slab-ordered lists a row's walk ends once every
//! pixel holds fragments nearer than the next slab, and starts past the slabs its pixels have
//! composited. Rows of pixels that reach the driver's loop budget are saved where they stopped
//! (even inside one slab's part of a list, with their selections) and finished by
//! continuation dispatches of the same shader, sized on the GPU (indirect dispatch;
//! [`resume`]). How many fragments a pixel selects per pass, and how many depth slabs the bins
//! order lists by, follow the frames' depth ([`depth`]).
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

mod depth;
mod raster;
mod resume;

use super::bins::features::{self, FrameEstimate};
use super::bins::layout::OVERFLOW_CROWDED_BIN;
use super::bins::{BinOptions, Bins, RasterNeeds, FINISHED_SUBMISSION_WRITES};
use super::{BinShape, FrameCheck, FrameDone, FrameSetup, Method, RecordContext};
use crate::assets::GpuScene;
use crate::frame::FrameTargets;
use crate::scene::Scene;
use crate::Result;
use depth::Depth;
use raster::Raster;
use resume::{Continuations, ResumeLists, MAX_CONTINUATIONS, MAX_ROW_CONTINUATIONS};

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
    /// The selection size and slab bits the renderer this one replaces drew with: a
    /// prepared loop that did not declare deep pixels starts there (where its pipelines
    /// are), not where the new scene's estimate would take it.
    #[doc(hidden)]
    pub learned_depth: Option<(u32, u32)>,
}

pub struct Exact {
    bins: Bins,
    /// The selection and slabs frames are rendered with.
    depth: Depth,
    raster: Raster,
    continuations: Continuations,
    lists: ResumeLists,
    /// Per frame slot, what its last submission was recorded with.
    recorded: Vec<Recorded>,
    /// A prepared loop's frames were deeper than declared (said once).
    deeper_than_declared: bool,
}

/// What a submission was recorded with.
#[derive(Clone, Copy, Debug)]
struct Recorded {
    continuations: Continuations,
    /// It was a frame's finishing submission (continuations alone).
    finishing: bool,
    /// The selection its raster made.
    select_size: u32,
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
        let expected: FrameEstimate = features::estimate(scene, width, height);
        let mut depth = Depth::SHALLOW.expecting(expected.fragments, width, height);
        if options.assume_deep_pixels {
            depth = depth.deep();
        }
        if bins.declared.deep {
            depth = depth.declared();
        } else if let (true, Some((select_size, slab_bits))) =
            (bins.prepared, options.learned_depth)
        {
            depth = Depth {
                select_size,
                slab_bits,
            };
        }
        let deep = Depth::is_deep(expected.fragments, width, height);
        let needs = RasterNeeds {
            method: "exact",
            slab_bits: depth.slab_bits,
            suspended_rows: Some(resume::suspended_rows(
                deep,
                features::tile_shift(gpu.info().into()),
            )),
        };
        let mut bins = Bins::new(gpu, scene, gpu_scene, targets, bins, &expected, needs)?;
        bins.set_threshold(options.threshold);
        let raster = Raster::new(&mut bins, gpu_scene, depth)?;
        bins.prebuild_texture_variant(gpu_scene, |bins| Raster::prebuild(bins, gpu_scene, depth))?;
        if bins.declared().deep {
            // Every depth the frames may move to is built now: they never build one.
            for declared in Depth::DECLARED {
                Raster::prebuild(&mut bins, gpu_scene, declared)?;
                bins.prebuild_texture_variant(gpu_scene, |bins| {
                    Raster::prebuild(bins, gpu_scene, declared)
                })?;
            }
        }
        bins.prebuild_superset(gpu_scene, |bins| {
            Raster::prebuild(bins, gpu_scene, depth)?;
            if bins.declared().deep {
                for declared in Depth::DECLARED {
                    Raster::prebuild(bins, gpu_scene, declared)?;
                }
            }
            Ok(())
        })?;
        Ok(Self {
            bins,
            depth,
            raster,
            continuations: Continuations::START,
            lists: ResumeLists::default(),
            recorded: vec![
                Recorded {
                    continuations: Continuations::START,
                    finishing: false,
                    select_size: depth.select_size,
                };
                gpu_scene.slot_count()
            ],
            deeper_than_declared: false,
        })
    }
}

impl Method for Exact {
    fn name(&self) -> &'static str {
        "exact"
    }

    fn composites_in_place(&self) -> bool {
        true
    }

    fn prepare_composite(&mut self, colour: &crate::gpu::HostImage) -> Result<()> {
        self.bins.prepare_composite(colour)
    }

    fn set_frame(&mut self, f: &FrameSetup<'_>) -> Result<()> {
        self.bins.set_frame(f)?;
        self.raster.follow(&mut self.bins, f.gpu_scene, self.depth)
    }

    /// The frame: the bins up to their bands; per band, its lists, the raster over its
    /// blocks and the continuations of the rows it suspended; then the composite.
    fn record(&mut self, ctx: &mut RecordContext<'_>) -> Result<()> {
        let cmd = ctx.cmd;
        self.bins.record_binning(ctx)?;
        self.recorded[ctx.slot] = Recorded {
            continuations: self.continuations,
            finishing: false,
            select_size: self.depth.select_size,
        };
        // Both resume lists start empty.
        self.lists = ResumeLists::default();
        let bands = self.bins.bands();
        for band in 0..bands {
            self.bins.record_band(ctx, band == 0, self.lists.pending);
            let continuations = self.continuations.after_band(band);
            let last = band + 1 == bands;
            self.lists
                .record_band(&self.bins, ctx, &self.raster, continuations, last);
            self.bins.compute_to_compute(cmd);
        }
        ctx.timestamps.mark(cmd, "raster");
        self.bins.record_end(ctx, self.lists.pending)
    }

    /// Continuations alone, for the rows the frame's submission left unfinished.
    fn record_finish(&mut self, ctx: &mut RecordContext<'_>) -> Result<()> {
        self.recorded[ctx.slot] = Recorded {
            continuations: self.continuations,
            finishing: true,
            select_size: self.depth.select_size,
        };
        self.bins.targets_to_raster(ctx, FINISHED_SUBMISSION_WRITES);
        // The submission before left the list its last continuation read as it was.
        self.bins
            .record_resume_list_empty(ctx.cmd, self.lists.pending ^ 1);
        let count = self.continuations.first_band;
        self.lists
            .record_continuations(&self.bins, ctx, &self.raster, count, true);
        ctx.timestamps.mark(ctx.cmd, "raster finished");
        self.bins.record_end(ctx, self.lists.pending)
    }

    fn frames_abandoned(&mut self, frames: u64) {
        self.bins.frames_abandoned(frames);
    }

    fn frame_done(&mut self, done: &FrameDone<'_>) -> Result<FrameCheck> {
        let Recorded {
            continuations: recorded,
            finishing,
            select_size,
        } = self.recorded[done.slot % self.recorded.len()];
        // A row of a shallow frame whose list is too long for one pass of the loop budget:
        // the continuations walked it in parts (this frame is right), and later frames bin
        // in depth slabs, where the first dispatch does too. Deep pixels: select more
        // fragments per pass, or order the bins by depth slab, from the next frame on (this
        // one is right either way).
        let depth = &mut self.depth;
        let declared_deep = self.bins.declared().deep;
        // A prepared loop builds nothing in its frames: without deep pixels declared, it
        // stays at the depth it has (right, slower on deep frames).
        let stays = self.bins.prepared() && !declared_deep;
        let deeper_noted = &mut self.deeper_than_declared;
        let bins = self.bins.frame_done(done, |counters, (width, height)| {
            let before = *depth;
            if counters.overflow & OVERFLOW_CROWDED_BIN != 0 {
                *depth = depth.deep();
            }
            *depth = depth.after_frame(
                counters.sweeps(),
                counters.fragments_in_front(),
                width,
                height,
            );
            if declared_deep {
                *depth = depth.declared();
            }
            if stays && *depth != before {
                if !*deeper_noted {
                    log::warn!(
                        "exact: the loop's frames are deeper than declared; they stay at \
                         the variants built (declare deep pixels for the faster ones)"
                    );
                    *deeper_noted = true;
                }
                *depth = before;
            }
            depth.slab_bits
        })?;
        self.raster
            .follow(&mut self.bins, done.gpu_scene, self.depth)?;
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
            bin_entries: kept(u64::from(counters.bin_entry_count)),
            suspended_rows: u64::from(counters.suspended_rows),
            bins: Some(BinShape {
                select_size,
                ..self.bins.shape(done.slot)
            }),
            ..FrameCheck::default()
        })
    }

    fn learned(&self, options: &mut super::MethodOptions) {
        self.bins.learned(&mut options.bins);
        options.exact.learned_depth = Some((self.depth.select_size, self.depth.slab_bits));
    }
}
