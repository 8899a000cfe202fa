//! Transparency methods, one module each, behind one small trait.
//!
//! A method is created for one uploaded scene and one frame size. Each frame it records its
//! passes into the frame's command buffer: it receives the opaque layer in the frame targets
//! (colour in COLOR_ATTACHMENT_OPTIMAL, depth in DEPTH_STENCIL_ATTACHMENT_OPTIMAL), depth-tests
//! against it, composites the transparent layer over the colour, and returns the targets in
//! the same layouts. It marks a timestamp after each of its stages. After the frame completes
//! it may ask for the frame to be rendered again (a buffer overflowed and was grown).

pub mod bins;
mod blend;
pub mod depth_peeling;
pub mod exact;
pub mod linked_list;
pub mod wavelet;
pub mod wboit;

use crate::assets::GpuScene;
use crate::frame::FrameTargets;
use crate::gpu::{vk, Gpu, HostImage, OptionalFeature, Timestamps};
use crate::scene::Scene;
use crate::{Error, Result};

/// Every method's name, as the CLI and the C API spell it.
pub const NAMES: &[&str] = &[
    "blend",
    "exact",
    "wavelet",
    "wboit",
    "linked_list",
    "depth_peeling",
];

/// The transparency methods.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum MethodKind {
    /// Unsorted hardware alpha blending: the baseline.
    Blend,
    /// The compute bin rasterizer: every pixel's fragments in the reference's order.
    Exact,
    /// Haar-wavelet transmittance, approximate.
    Wavelet,
    /// Weighted blended OIT, approximate.
    Wboit,
    /// Per-pixel linked lists sorted in a full-screen pass: exact while its node pool holds
    /// the frame's fragments.
    LinkedList,
    /// Dual depth peeling: N passes peel 2N layers, exact while the frame has no more.
    DepthPeeling,
}

impl MethodKind {
    pub const ALL: [Self; 6] = [
        Self::Blend,
        Self::Exact,
        Self::Wavelet,
        Self::Wboit,
        Self::LinkedList,
        Self::DepthPeeling,
    ];

    /// Device features the method needs beyond what every method needs.
    pub fn optional_features(self) -> &'static [OptionalFeature] {
        match self {
            // Stores from fragments for the lists; a geometry stage for the reference's order
            // depth (scene/ordered.geom), and gl_PrimitiveID, its tie-break.
            Self::LinkedList => &[
                OptionalFeature::FragmentStoresAndAtomics,
                OptionalFeature::GeometryShader,
            ],
            // The same geometry stage; MAX for the depth range and front-to-back compositing
            // for the layers, in one pass.
            Self::DepthPeeling => &[
                OptionalFeature::GeometryShader,
                OptionalFeature::IndependentBlend,
            ],
            Self::Blend | Self::Exact | Self::Wavelet | Self::Wboit => &[],
        }
    }

    /// The name the CLI and the C API use.
    pub fn name(self) -> &'static str {
        match self {
            Self::Blend => "blend",
            Self::Exact => "exact",
            Self::Wavelet => "wavelet",
            Self::Wboit => "wboit",
            Self::LinkedList => "linked_list",
            Self::DepthPeeling => "depth_peeling",
        }
    }
}

impl std::fmt::Display for MethodKind {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(self.name())
    }
}

impl std::str::FromStr for MethodKind {
    type Err = Error;

    /// A method by name; [`Error::UnknownMethod`] lists the names.
    fn from_str(name: &str) -> Result<Self> {
        Self::ALL
            .into_iter()
            .find(|m| m.name() == name)
            .ok_or_else(|| Error::UnknownMethod(name.to_string(), NAMES.join(", ")))
    }
}

/// Settings of the methods that have any, one struct each; the other methods ignore them.
#[derive(Clone, Debug, Default)]
pub struct MethodOptions {
    /// `exact`'s.
    pub exact: exact::ExactOptions,
    /// `wavelet`'s.
    pub wavelet: wavelet::WaveletOptions,
    /// `linked_list`'s.
    pub linked_list: linked_list::LinkedListOptions,
    /// `depth_peeling`'s.
    pub depth_peeling: depth_peeling::DepthPeelingOptions,
    /// The bins' (`exact`, and `wavelet` with [`wavelet::Storage::Bins`]): starting
    /// capacities and test settings.
    pub bins: bins::BinOptions,
}

/// What a method reports once its frame has completed.
#[derive(Clone, Copy, Debug, Default)]
pub struct FrameCheck {
    /// The frame is not all right (past a limit of one recording; buffers have grown):
    /// render it again.
    pub rerender: bool,
    /// The frame's work is unfinished but intact: a submission of what `Method::record_finish`
    /// records completes it (on an engine's device, where translucid does not submit, the
    /// frame is rendered again instead).
    pub finish: bool,
    /// Pixel rows the frame left with the opaque colour, past a documented limit of the
    /// method (exact: bin lists needing more bands than it records).
    pub degraded_rows: u64,
    /// Pixel rows still unfinished after the frame's last continuation, untouched so far
    /// (what `finish` completes).
    pub unfinished_rows: u64,
    /// Bands the frame's bins were rasterized in (exact and wavelet's bins: more than one when
    /// their lists passed the capacity; 0 for other methods).
    pub bands: u32,
    /// Fragments composited, where the method counts them.
    pub fragments: u64,
    /// The most passes over its bin list a pixel needed (exact).
    pub sweeps: u32,
    /// Transparent triangles left to rasterize after culling, where the method culls.
    pub triangles: u64,
    /// Entries the bin methods' lists needed (for each triangle, each bin it may cover).
    pub bin_entries: u64,
    /// Fragments blended unsorted because they found no room (linked_list past its node
    /// pool): the frame is not exact where they fell.
    pub tail_fragments: u64,
    /// The bin methods' shape for the frame; `None` for the others.
    pub bins: Option<BinShape>,
    /// Rows suspended at the loop budget and resumed by a continuation (exact), counted each
    /// time.
    pub suspended_rows: u64,
    /// Pixels with more layers than the passes peeled (depth_peeling past its passes): their
    /// middle layers are missing.
    pub unpeeled_pixels: u64,
    /// Where the wavelet method kept the frame's coefficients; `None` for other methods.
    pub wavelet_storage: Option<wavelet::Storage>,
}

/// How the bin methods' stages were specialized and sized for a frame: what tests and tools
/// check to know a setting took effect.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct BinShape {
    /// Fragments each pixel selects per pass over its list (exact; 0 for wavelet's raster).
    pub select_size: u32,
    /// Depth slabs each bin's list is ordered by.
    pub slabs: u32,
    /// Pixel rows of a bin's tile: one subgroup's pixels (8 across).
    pub tile_rows: u32,
    /// Rows of a block per workgroup of a band's first raster dispatch.
    pub rows_per_workgroup: u32,
    /// Tile rows one binning invocation covers at most.
    pub rows_per_slice: u32,
    /// Loop iterations a raster's row took at most in one dispatch.
    pub loop_budget: u32,
    /// The raster branched where its subgroup agreed (the GPU profile's variant).
    pub branching: bool,
    /// The raster's walk read list entries and triangle records as storage buffers, not
    /// texels (`bins::features::storage_walk`).
    pub storage_walk: bool,
    /// The raster sampled textures in hardware (`bins::features::hardware_sampling`), not
    /// bit for bit as the reference.
    pub hardware_sampling: bool,
    /// Slots of a binning workgroup's tally of its entries (`bins::features::bin_tally_bits`;
    /// 0 without one, as in frames of several slabs).
    pub tally_slots: u32,
}

/// What a method is told when a frame it recorded has completed.
pub struct FrameDone<'a> {
    pub gpu_scene: &'a GpuScene,
    pub targets: &'a FrameTargets,
    /// The frame slot the frame was recorded in.
    pub slot: usize,
}

/// What a method records into.
pub struct RecordContext<'a> {
    pub gpu: &'a Gpu,
    pub cmd: vk::CommandBuffer,
    /// The frame slot: per-frame data written and read in this slot, shared buffers
    /// after a barrier against the frames before.
    pub slot: usize,
    pub gpu_scene: &'a GpuScene,
    pub targets: &'a FrameTargets,
    pub timestamps: &'a mut Timestamps,
    /// On the engine's device, for a method that composites in place
    /// ([`Method::composites_in_place`]): the engine's images, read and written where they
    /// are instead of the frame targets.
    pub in_place: Option<InPlace>,
}

/// The engine's images a frame composites onto in place.
#[derive(Clone, Copy, Debug)]
pub struct InPlace {
    /// The engine's colour image, which the composite blends onto (it has COLOR_ATTACHMENT
    /// usage and a format that blends).
    pub colour: HostImage,
    /// A view of the engine's depth image (its depth aspect), in SHADER_READ_ONLY_OPTIMAL,
    /// made for this frame.
    pub depth: vk::ImageView,
    /// That depth is reversed-Z (1 at the eye).
    pub reversed: bool,
}

/// What a method is given when the frame changes (see [`Method::set_frame`]).
pub struct FrameSetup<'a> {
    pub gpu: &'a Gpu,
    /// The renderer's scene: its assets, and the new frame's camera, light and draws.
    pub scene: &'a Scene,
    /// The same, on the GPU, with the new frame already written.
    pub gpu_scene: &'a GpuScene,
    pub targets: &'a FrameTargets,
    /// The frame slot the frame is written into (no frame of it in flight).
    pub slot: usize,
}

pub trait Method {
    fn name(&self) -> &'static str;
    /// Takes the frame `setup.scene` now describes: another camera, light or set of draws
    /// over the same assets. Called between frames, never while one the method recorded may
    /// still run. Buffers only grow; pipelines come from what the method built before
    /// whenever the frame needs a variant it already has.
    fn set_frame(&mut self, _setup: &FrameSetup<'_>) -> Result<()> {
        Ok(())
    }
    /// Records the transparent pass of one frame.
    fn record(&mut self, ctx: &mut RecordContext<'_>) -> Result<()>;
    /// Records what completes a frame whose check asked to `finish` it, into a submission
    /// after the frame's.
    fn record_finish(&mut self, _ctx: &mut RecordContext<'_>) -> Result<()> {
        Ok(())
    }
    /// Called after the frame's submission completed, for each frame recorded and not
    /// abandoned, in the order they were recorded.
    fn frame_done(&mut self, _done: &FrameDone<'_>) -> Result<FrameCheck> {
        Ok(FrameCheck::default())
    }
    /// The newest `frames` this method recorded will never run (the engine abandoned them):
    /// what the method keeps for frames in flight forgets them; everything it built stays.
    fn frames_abandoned(&mut self, _frames: u64) {}
    /// Writes into `options` the buffer sizes this method's frames turned out to need, so
    /// that a method made for the next, similar frame starts there instead of overflowing.
    fn learned(&self, _options: &mut MethodOptions) {}
    /// Whether, on an engine's device, the method is one hardware pass of the scene's
    /// transparent draws blended straight into the engine's images (the renderer records
    /// that pass itself, `renderer/native_blend.rs`), with no copy in or out.
    fn blends_in_place(&self) -> bool {
        false
    }

    /// Whether, on an engine's device, the method reads the engine's depth and composites
    /// onto its colour where they are ([`RecordContext::in_place`]), with no copy in or out.
    fn composites_in_place(&self) -> bool {
        false
    }

    /// For a method that composites in place: builds now what its first frame onto colour
    /// images like `colour` (format and layouts) would build.
    fn prepare_composite(&mut self, _colour: &HostImage) -> Result<()> {
        Ok(())
    }
}

/// Creates method `kind` for `scene` (uploaded as `gpu_scene`) and `targets`.
pub fn create(
    kind: MethodKind,
    gpu: &Gpu,
    scene: &Scene,
    gpu_scene: &GpuScene,
    targets: &FrameTargets,
    options: &MethodOptions,
) -> Result<Box<dyn Method>> {
    Ok(match kind {
        MethodKind::Blend => Box::new(blend::Blend::new(gpu, gpu_scene, targets)?),
        MethodKind::Exact => Box::new(exact::Exact::new(
            gpu,
            scene,
            gpu_scene,
            targets,
            &options.bins,
            &options.exact,
        )?),
        MethodKind::Wavelet => Box::new(wavelet::Wavelet::new(
            gpu,
            scene,
            gpu_scene,
            targets,
            &options.bins,
            &options.wavelet,
        )?),
        MethodKind::Wboit => Box::new(wboit::Wboit::new(gpu, gpu_scene, targets)?),
        MethodKind::LinkedList => Box::new(linked_list::LinkedList::new(
            gpu,
            scene,
            gpu_scene,
            targets,
            &options.linked_list,
        )?),
        MethodKind::DepthPeeling => Box::new(depth_peeling::DepthPeeling::new(
            gpu,
            scene,
            gpu_scene,
            targets,
            &options.depth_peeling,
        )?),
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_method_round_trips_by_name_and_unknown_names_are_listed() {
        for kind in MethodKind::ALL {
            assert_eq!(kind.name().parse::<MethodKind>().ok(), Some(kind));
        }
        assert_eq!(MethodKind::ALL.map(MethodKind::name), NAMES);
        let err = "nope".parse::<MethodKind>().expect_err("unknown");
        assert!(err.to_string().contains("nope") && err.to_string().contains("wboit"));
    }
}
