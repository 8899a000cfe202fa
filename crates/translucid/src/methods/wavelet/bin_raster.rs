//! The bins variant: the bins ([`crate::methods::bins`]) read by the wavelet raster
//! (`shaders/common/wavelet_bins.glsl`), which keeps each pixel's coefficients in registers
//! and walks its row's list three times: bounds, coefficients, shading.

use super::SpecConstants;
use crate::assets::GpuScene;
use crate::frame::FrameTargets;
use crate::gpu::{ComputePipeline, Gpu};
use crate::methods::bins::{features, BinOptions, Bins, RasterNeeds, RasterShader};
use crate::methods::{FrameCheck, FrameDone, FrameSetup, RecordContext};
use crate::scene::Scene;
use crate::Result;
use std::sync::Arc;

/// The raster of each rank.
fn raster_spirv(rank: u32) -> RasterShader {
    let (software, hardware_sampled): (&'static [u8], &'static [u8]) = match rank {
        0 => (
            crate::spirv!("wavelet/bins_rank0.comp"),
            crate::spirv!("wavelet/bins_rank0_sampled.comp"),
        ),
        1 => (
            crate::spirv!("wavelet/bins_rank1.comp"),
            crate::spirv!("wavelet/bins_rank1_sampled.comp"),
        ),
        2 => (
            crate::spirv!("wavelet/bins_rank2.comp"),
            crate::spirv!("wavelet/bins_rank2_sampled.comp"),
        ),
        _ => (
            crate::spirv!("wavelet/bins_rank3.comp"),
            crate::spirv!("wavelet/bins_rank3_sampled.comp"),
        ),
    };
    RasterShader {
        software,
        hardware_sampled,
    }
}

pub struct BinRaster {
    bins: Bins,
    rank: u32,
    constants: SpecConstants,
    raster: Arc<ComputePipeline>,
}

impl BinRaster {
    pub fn new(
        gpu: &Gpu,
        scene: &Scene,
        gpu_scene: &GpuScene,
        targets: &FrameTargets,
        options: &BinOptions,
        rank: u32,
        constants: SpecConstants,
    ) -> Result<Self> {
        // The raster has no selection and suspends no rows: lists of one slab.
        let (width, height) = (targets.extent.width, targets.extent.height);
        let expected = features::estimate(scene, width, height);
        let needs = RasterNeeds {
            method: "wavelet",
            slab_bits: 0,
            suspended_rows: None,
        };
        let mut bins = Bins::new(gpu, scene, gpu_scene, targets, options, &expected, needs)?;
        let raster = select(&mut bins, gpu_scene, rank, constants)?;
        bins.prebuild_texture_variant(gpu_scene, |bins| {
            select(bins, gpu_scene, rank, constants).map(drop)
        })?;
        bins.prebuild_superset(gpu_scene, |bins| {
            select(bins, gpu_scene, rank, constants).map(drop)
        })?;
        Ok(Self {
            bins,
            rank,
            constants,
            raster,
        })
    }

    pub fn set_frame(&mut self, f: &FrameSetup<'_>) -> Result<()> {
        if self.bins.set_frame(f)? {
            self.raster = select(&mut self.bins, f.gpu_scene, self.rank, self.constants)?;
        }
        Ok(())
    }

    /// The frame: the bins, and the raster over each band. The raster suspends no rows.
    /// See [`Bins::prepare_composite`].
    pub fn prepare_composite(&mut self, colour: &crate::gpu::HostImage) -> Result<()> {
        self.bins.prepare_composite(colour)
    }

    pub fn record(&mut self, ctx: &mut RecordContext<'_>) -> Result<()> {
        let cmd = ctx.cmd;
        self.bins.record_binning(ctx)?;
        for band in 0..self.bins.bands() {
            self.bins.record_band(ctx, band == 0, 0);
            self.bins.record_raster(ctx, &self.raster, 0);
            self.bins.compute_to_compute(cmd);
        }
        ctx.timestamps.mark(cmd, "wavelet raster");
        self.bins.record_end(ctx, 0)
    }

    /// Whether the completed frame had a row whose three walks would pass the loop budget
    /// (this raster does not resume rows as exact's does).
    pub fn crowded(&self, slot: usize) -> Result<bool> {
        self.bins.crowded(slot)
    }

    pub fn frames_abandoned(&mut self, frames: u64) {
        self.bins.frames_abandoned(frames);
    }

    pub fn frame_done(&mut self, done: &FrameDone<'_>) -> Result<FrameCheck> {
        let bins = self.bins.frame_done(done, |_, _| 0)?;
        if bins.features_changed {
            self.raster = select(&mut self.bins, done.gpu_scene, self.rank, self.constants)?;
        }
        let kept = |count: u64| if bins.rerender { 0 } else { count };
        Ok(FrameCheck {
            rerender: bins.rerender,
            degraded_rows: bins.degraded_rows,
            bands: bins.counters.bands,
            fragments: kept(bins.counters.fragments()),
            triangles: kept(u64::from(bins.counters.triangle_count)),
            bin_entries: kept(u64::from(bins.counters.bin_entry_count)),
            bins: Some(self.bins.shape(done.slot)),
            ..FrameCheck::default()
        })
    }

    pub fn learned(&self, options: &mut BinOptions) {
        self.bins.learned(options);
    }
}

/// The raster for `bins`' features and the wavelet constants.
fn select(
    bins: &mut Bins,
    gpu_scene: &GpuScene,
    rank: u32,
    constants: SpecConstants,
) -> Result<Arc<ComputePipeline>> {
    let constants = constants.add_to(bins.features().raster_constants());
    bins.pipeline(gpu_scene, raster_spirv(rank), &constants)
}
