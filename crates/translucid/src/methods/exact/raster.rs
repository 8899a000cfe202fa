//! The exact raster's pipelines: `shaders/exact/raster.comp`, specialized for the bins'
//! features and the frame's [`Depth`], as each band's first dispatch and as the
//! continuations that resume the rows it suspends.

use super::depth::Depth;
use crate::assets::GpuScene;
use crate::gpu::ComputePipeline;
use crate::interface::bins::BIN_SIZE;
use crate::interface::specialization::{
    Specialization, CONTINUATION, RASTER_GROUP_SIZE, SELECT_SIZE,
};
use crate::methods::bins::features::RasterFeatures;
use crate::methods::bins::{Bins, RasterShader};
use crate::Result;
use std::sync::Arc;

const RASTER: RasterShader = RasterShader {
    software: crate::spirv!("exact/raster.comp"),
    hardware_sampled: crate::spirv!("exact/raster_sampled.comp"),
};

pub struct Raster {
    /// Over a band's blocks.
    pub first: Arc<ComputePipeline>,
    /// Over the tiles on a resume list, one workgroup each.
    pub continuation: Arc<ComputePipeline>,
    /// What they were specialized for.
    built_for: (RasterFeatures, Depth),
}

impl Raster {
    /// The raster for `bins`' features and `depth`, built unless built before.
    pub fn new(bins: &mut Bins, gpu_scene: &GpuScene, depth: Depth) -> Result<Self> {
        let features = bins.features();
        Self::with_features(bins, gpu_scene, features, depth)
    }

    /// Builds now the raster of frames at `depth` (its slabs too), with the bins' features
    /// otherwise, so that a later move there builds nothing.
    pub fn prebuild(bins: &mut Bins, gpu_scene: &GpuScene, depth: Depth) -> Result<()> {
        bins.prebuild_stages(gpu_scene, depth.slab_bits)?;
        let features = RasterFeatures {
            slab_bits: depth.slab_bits,
            ..bins.features()
        };
        Self::with_features(bins, gpu_scene, features, depth).map(drop)
    }

    fn with_features(
        bins: &mut Bins,
        gpu_scene: &GpuScene,
        features: RasterFeatures,
        depth: Depth,
    ) -> Result<Self> {
        Ok(Self {
            first: bins.pipeline(gpu_scene, RASTER, &constants(&features, depth, false))?,
            continuation: bins.pipeline(gpu_scene, RASTER, &constants(&features, depth, true))?,
            built_for: (features, depth),
        })
    }

    /// Follows the bins' features and `depth` where they moved.
    pub fn follow(&mut self, bins: &mut Bins, gpu_scene: &GpuScene, depth: Depth) -> Result<()> {
        if self.built_for != (bins.features(), depth) {
            *self = Self::new(bins, gpu_scene, depth)?;
        }
        Ok(())
    }
}

/// The raster's constants: those of every raster over the bins, the selection, and whether
/// it is a continuation (a workgroup a tile).
fn constants(features: &RasterFeatures, depth: Depth, continuation: bool) -> Specialization {
    let constants = features
        .raster_constants()
        .with(SELECT_SIZE, depth.select_size as i32)
        .with(CONTINUATION, continuation);
    if continuation {
        constants.with(RASTER_GROUP_SIZE, BIN_SIZE << features.tile_shift)
    } else {
        constants
    }
}
