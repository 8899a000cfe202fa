//! `wavelet`: Haar-wavelet transmittance OIT (the README's "The approximate methods"; the math
//! is in [`math`], and [`model`] is the whole method on the CPU). Two variants, by where each
//! pixel's coefficients live ([`Storage`]):
//!
//! **Bins** (CPU drivers' default; [`Storage::for_profile`]): the bins the exact method reads ([`crate::methods::bins`]), with a
//! raster of its own (`shaders/common/wavelet_bins.glsl`, driven by `bin_raster.rs`) that
//! keeps each pixel's coefficients in registers and walks its row's triangle list three
//! times: bounds, coefficients, shading. No coefficient images, and every fragment is the CPU
//! reference's.
//!
//! **Images** (GPUs' default): four passes, each one draw of the scene or one full-screen triangle:
//! 1. **bounds**: each pixel's nearest and farthest transparent view depth (MAX blend).
//! 2. **transmittance**: every fragment adds its absorbance's Haar coefficients into
//!    full-screen coefficient images (ADD blend). The coefficients of the three channels are
//!    packed densely, 4 to a texel: rank 0–3 needs 2, 3, 6 or 12 texels; a draw writes at most
//!    8 (colour attachments), so rank 3 draws the scene twice.
//! 3. **resolve** (full screen): dims the opaque colour by the transmittance behind every
//!    fragment, and writes a depth buffer of its own: the opaque depth, or nearer, the depth at
//!    which every channel is absorbed.
//! 4. **shade**: every fragment in front of that depth (hidden ones fail the depth test before
//!    shading) adds its radiance times the transmittance in front of it, its own share
//!    removed, to the frame colour (ADD blend).
//!
//! The scene draws hand the driver the reference's snapped vertices (`mesh_vertex.glsl`), so it
//! covers the reference's samples; where the device has a geometry stage they order each
//! fragment by the reference's own depth (`scene/ordered.geom`), and textures are sampled at
//! the reference's level of detail: every fragment is the CPU model's, as on the bins (see
//! `passes::FragmentDepth` for a device without a geometry stage).
//!
//! Optional depth noise ([`WaveletOptions::noise`]) shifts each pixel's cell boundaries by a
//! fixed hash, trading banding for noise; it is off by default and in the image tests.

mod bin_raster;
pub mod math;
pub mod model;
mod passes;

use super::bins::BinOptions;
use super::{FrameCheck, FrameDone, FrameSetup, Method, MethodOptions, RecordContext};
use crate::assets::GpuScene;
use crate::frame::FrameTargets;
use crate::gpu::{Gpu, HeldPipelines, Profile, Retirement};
use crate::interface::specialization::{
    Specialization, WAVELET_ABSORBED, WAVELET_FIRST_TEXEL, WAVELET_NOISE,
};
use crate::scene::Scene;
use crate::{Error, Result};
use bin_raster::BinRaster;

/// Rank when none is asked for: 16 coefficients per channel.
pub const DEFAULT_RANK: u32 = 3;

/// A pixel counts as opaque once every channel's transmittance is below this: the fragments
/// behind it are not shaded, an error of at most 1/1024 of their radiance.
pub const ABSORBED_TRANSMITTANCE: f32 = 1.0 / 1024.0;

/// Storage of the coefficient images.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum Precision {
    /// RGBA16F: half the memory and bandwidth.
    #[default]
    Half,
    /// RGBA32F.
    Single,
}

/// Where each pixel's coefficients live. Unless an option names one, the device's profile
/// picks it ([`Storage::for_profile`]).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Storage {
    /// Registers of its own raster over the bins, in single precision (`precision` is the
    /// images' and does not apply). CPU drivers' storage: 3.1 to 13 times faster than the
    /// images on lavapipe at 1280x720 (docs/performance-log.md, 2026-12-06), about a third of
    /// their memory. It needs what the exact method needs
    /// of the device (64-bit shader arithmetic, subgroups of 8 or more); on a device without,
    /// and for frames with rows too crowded for its loop budget, the method keeps the
    /// coefficients in images instead.
    Bins,
    /// Full-screen coefficient images, written and read by four graphics passes: the
    /// hardware rasterizes and blends every fragment, where the bins' raster runs a row of 8
    /// pixels on each subgroup and walks its list three times. GPUs' storage.
    Images,
}

impl Storage {
    /// The storage a device of `profile` gets when no option names one: the bins on CPU
    /// drivers, where they are measured faster; the images on GPUs, whose rasterizer and
    /// blending do in fixed function what the bins' raster does in a shader (docs/gpu.md).
    pub fn for_profile(profile: Profile) -> Self {
        match profile {
            Profile::CpuDriver => Self::Bins,
            Profile::Gpu => Self::Images,
        }
    }

    /// `bins` or `images`.
    pub fn name(self) -> &'static str {
        match self {
            Self::Bins => "bins",
            Self::Images => "images",
        }
    }
}

/// Whether the coefficient images' fragments on `gpu` are the CPU reference's, coverage, order
/// depth and texture level of detail, as the bins' are: where the device has a geometry stage
/// (`passes::FragmentDepth`). Elsewhere they take the driver's depth, which differs in the
/// last bits: a pixel whose fragments meet at one depth may then be a few 255ths off the model.
pub fn images_match_the_model(gpu: &Gpu) -> bool {
    passes::FragmentDepth::of(gpu) == passes::FragmentDepth::Reference
}

/// The wavelet method's settings, as given.
#[derive(Clone, Debug, Default)]
pub struct WaveletOptions {
    /// Haar rank, 0 to 3 (2^(rank+1) coefficients per colour channel); `None` is
    /// [`DEFAULT_RANK`]. A larger rank is an error.
    pub rank: Option<u32>,
    /// Depth noise strength in cells (0, the default, is off); deterministic per pixel.
    pub noise: f32,
    /// Storage precision of the coefficient images.
    pub precision: Precision,
    /// Where the coefficients live (images, or registers in the bins' raster); `None` is the
    /// device profile's ([`Storage::for_profile`]).
    pub storage: Option<Storage>,
}

/// The method's settings, checked.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Settings {
    pub rank: u32,
    pub noise: f32,
    pub precision: Precision,
    pub storage: Storage,
}

impl Settings {
    /// The settings `options` ask for on a device of `profile`, which picks the storage when
    /// the options do not ([`Storage::for_profile`]; [`Gpu::profile`] is a device's).
    pub fn from_options(options: &WaveletOptions, profile: Profile) -> Result<Self> {
        let rank = options.rank.unwrap_or(DEFAULT_RANK);
        if rank > math::MAX_RANK {
            return Err(Error::InvalidOption(format!(
                "wavelet rank {rank} is over {} (ranks 0 to {0} keep 2 to 16 coefficients per channel)",
                math::MAX_RANK
            )));
        }
        if !(options.noise >= 0.0 && options.noise.is_finite()) {
            return Err(Error::InvalidOption(format!(
                "wavelet noise {} must be finite and at least 0",
                options.noise
            )));
        }
        Ok(Self {
            rank,
            noise: options.noise,
            precision: options.precision,
            storage: options
                .storage
                .unwrap_or_else(|| Storage::for_profile(profile)),
        })
    }

    /// Coefficient texels (RGBA) per pixel: 3 channels × 2^(rank+1), rounded up to 4.
    pub fn texels(&self) -> usize {
        (3 * math::coefficient_count(self.rank)).div_ceil(4)
    }

    /// The shaders' specialization constants (the same for every frame).
    pub fn constants(&self) -> SpecConstants {
        SpecConstants {
            first_texel: 0,
            noise: self.noise,
            absorbed: -ABSORBED_TRANSMITTANCE.ln(),
        }
    }
}

/// The specialization constants every wavelet shader takes. None changes with the camera:
/// the depth mapping is in the frame constants (`FrameInfo.depthMapping`), so a camera whose
/// near and far planes move builds nothing. The rank is not among them: each rank has its
/// own SPIR-V (see [`passes`]).
#[derive(Clone, Copy, Debug, Default)]
pub struct SpecConstants {
    /// The first coefficient texel an accumulation draw writes.
    pub first_texel: i32,
    /// Depth noise strength, in cells; 0 is off.
    pub noise: f32,
    /// Absorbance from which a pixel counts as opaque.
    pub absorbed: f32,
}

impl SpecConstants {
    /// These constants added to `constants`.
    pub fn add_to(&self, constants: Specialization) -> Specialization {
        constants
            .with(WAVELET_FIRST_TEXEL, self.first_texel)
            .with(WAVELET_NOISE, self.noise)
            .with(WAVELET_ABSORBED, self.absorbed)
    }

    pub fn specialization(&self) -> Specialization {
        self.add_to(Specialization::new())
    }
}

pub struct Wavelet {
    gpu: Gpu,
    settings: Settings,
    variant: Variant,
    /// Passes replaced while frames in flight may still run them.
    retirement: Retirement,
    /// Per frame slot, whether its last frame ran on the bins (a frame in flight when the
    /// method moved to images must still be checked as a bins frame).
    recorded_on_bins: Vec<bool>,
    /// Where deep content is declared, the coefficient images' pipelines, built up front so
    /// that moving to them mid-loop compiles nothing.
    _images_pipelines: Option<HeldPipelines>,
}

enum Variant {
    Images(Box<passes::Passes>),
    Bins(Box<BinRaster>),
}

impl Wavelet {
    pub fn new(
        gpu: &Gpu,
        scene: &Scene,
        gpu_scene: &GpuScene,
        targets: &FrameTargets,
        bin_options: &BinOptions,
        options: &WaveletOptions,
    ) -> Result<Self> {
        let mut settings = Settings::from_options(options, gpu.profile())?;
        let constants = settings.constants();
        let bins = match settings.storage {
            Storage::Images => None,
            Storage::Bins => {
                let rank = settings.rank;
                match BinRaster::new(gpu, scene, gpu_scene, targets, bin_options, rank, constants) {
                    Ok(raster) => Some(raster),
                    // The images need nothing of the device beyond blending.
                    Err(Error::DeviceLacks(why)) => {
                        log::warn!("wavelet: {why}; keeping the coefficients in images");
                        settings.storage = Storage::Images;
                        None
                    }
                    Err(e) => return Err(e),
                }
            }
        };
        let variant = match bins {
            Some(raster) => Variant::Bins(Box::new(raster)),
            None => Variant::Images(Box::new(passes::Passes::new(
                gpu, gpu_scene, targets, &settings, constants,
            )?)),
        };
        // Deep content may crowd a row past the bins' raster, which then moves to the images.
        let images_pipelines = match &variant {
            Variant::Bins(_) if bin_options.declared.deep => {
                Some(images_pipelines(gpu, gpu_scene, targets, settings)?)
            }
            _ => None,
        };
        Ok(Self {
            gpu: gpu.clone(),
            settings,
            variant,
            retirement: Retirement::default(),
            recorded_on_bins: Vec::new(),
            _images_pipelines: images_pipelines,
        })
    }
}

/// The pipelines of the coefficient images' passes with `settings` but for the storage, held:
/// the passes are made (their images allocated for the while) and dropped.
fn images_pipelines(
    gpu: &Gpu,
    gpu_scene: &GpuScene,
    targets: &FrameTargets,
    settings: Settings,
) -> Result<HeldPipelines> {
    let settings = Settings {
        storage: Storage::Images,
        ..settings
    };
    let passes = passes::Passes::new(gpu, gpu_scene, targets, &settings, settings.constants())?;
    let held = gpu.hold_pipelines();
    drop(passes);
    Ok(held)
}

impl Method for Wavelet {
    fn name(&self) -> &'static str {
        "wavelet"
    }

    fn composites_in_place(&self) -> bool {
        matches!(self.variant, Variant::Bins(_))
    }

    fn prepare_composite(&mut self, colour: &crate::gpu::HostImage) -> Result<()> {
        match &mut self.variant {
            Variant::Bins(raster) => raster.prepare_composite(colour),
            Variant::Images(_) => Ok(()),
        }
    }

    fn set_frame(&mut self, f: &FrameSetup<'_>) -> Result<()> {
        // The camera's depth mapping is in the frame constants: the coefficient images'
        // passes take any frame as they are.
        match &mut self.variant {
            Variant::Bins(raster) => raster.set_frame(f),
            Variant::Images(_) => Ok(()),
        }
    }

    fn record(&mut self, ctx: &mut RecordContext<'_>) -> Result<()> {
        self.retirement.recorded();
        if self.recorded_on_bins.len() <= ctx.slot {
            self.recorded_on_bins.resize(ctx.slot + 1, false);
        }
        self.recorded_on_bins[ctx.slot] = matches!(self.variant, Variant::Bins(_));
        let p = match &mut self.variant {
            Variant::Images(p) => p,
            Variant::Bins(raster) => return raster.record(ctx),
        };
        p.bounds(ctx);
        ctx.timestamps.mark(ctx.cmd, "wavelet bounds");
        p.transmittance(ctx);
        ctx.timestamps.mark(ctx.cmd, "wavelet transmittance");
        p.resolve(ctx);
        ctx.timestamps.mark(ctx.cmd, "wavelet resolve");
        p.shade(ctx);
        ctx.timestamps.mark(ctx.cmd, "wavelet shade");
        Ok(())
    }

    fn frames_abandoned(&mut self, frames: u64) {
        self.retirement.abandoned(frames);
        if let Variant::Bins(raster) = &mut self.variant {
            raster.frames_abandoned(frames);
        }
    }

    fn frame_done(&mut self, done: &FrameDone<'_>) -> Result<FrameCheck> {
        self.retirement.completed();
        let on_bins = self
            .recorded_on_bins
            .get(done.slot)
            .copied()
            .unwrap_or(false);
        let Variant::Bins(raster) = &mut self.variant else {
            // A frame recorded on the bins before the move to images may be truncated too:
            // its counters went with the bins, so it is reported for drawing again.
            return Ok(FrameCheck {
                rerender: on_bins,
                wavelet_storage: Some(if on_bins {
                    Storage::Bins
                } else {
                    Storage::Images
                }),
                ..FrameCheck::default()
            });
        };
        if !raster.crowded(done.slot)? {
            return Ok(FrameCheck {
                wavelet_storage: Some(Storage::Bins),
                ..raster.frame_done(done)?
            });
        }
        // A row's three walks would pass the loop budget (the bins' raster does not resume
        // rows as exact's does): the coefficient images have no such limit. The renderer
        // keeps them from here on, and `learned` hands them to the next one.
        log::warn!(
            "wavelet: a bin of this frame is too crowded for the bins' raster; rendering it \
             with coefficient images instead"
        );
        self.settings.storage = Storage::Images;
        let images = Variant::Images(Box::new(passes::Passes::new(
            &self.gpu,
            done.gpu_scene,
            done.targets,
            &self.settings,
            self.settings.constants(),
        )?));
        // Frames in flight may still run the bins' passes.
        self.retirement
            .retire(std::mem::replace(&mut self.variant, images));
        Ok(FrameCheck {
            rerender: true,
            wavelet_storage: Some(Storage::Bins),
            ..FrameCheck::default()
        })
    }

    fn learned(&self, options: &mut MethodOptions) {
        options.wavelet.storage = Some(self.settings.storage);
        if let Variant::Bins(raster) = &self.variant {
            raster.learned(&mut options.bins);
        }
    }
}
