//! The bins' buffers, the resume lists of the rasters that read them and the state a raster
//! keeps of the rows it suspends (one descriptor set for every stage): sized from the frame,
//! grown when the GPU reports an overflow.

use super::layout::{
    record_bytes_per_triangle, BinCounters, BinDraw, BIN_SIZE, DISPATCH_BYTES, HOMOGENEOUS_BYTES,
    MOST_ATTRIBUTE_TEXELS, OVERFLOW_BIN_ENTRIES, OVERFLOW_HOMOGENEOUS, OVERFLOW_RESUME,
    RESUME_ITEM_BYTES, SCAN_GROUP_SIZE, TRIANGLE_BYTES, TRIANGLE_MATERIAL_SHIFT,
};
use super::SuspendedRows;
use crate::assets::ResidentAssets;
use crate::assets::{GpuScene, SampledViews};
use crate::frame::FrameTargets;
use crate::gpu::{
    image_barrier, memory_barrier, vk, Buffer, BufferView, DescriptorLayout, DescriptorSet, Gpu,
    GpuImage, MemoryLocation, Resource, Retirement, Sampler, ViewedBuffer as Viewed,
};
use crate::interface::bins::BINS_SET;
use crate::raster::model_view_projection;
use crate::scene::Scene;
use crate::{Error, Result};

/// Entries the growable buffers hold.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Capacities {
    /// Two per quad: setup can never write more.
    pub triangles: u32,
    /// Texels of each quad's attribute record (one record per two triangles): what the
    /// features' shading reads (`RasterFeatures::attribute_texels`).
    pub attribute_texels: u32,
    pub homogeneous: u32,
    pub bin_entries: u32,
    /// State slots of each of the two resume lists: rows a raster dispatch suspends with
    /// their state (the others start over when resumed); 0 for a raster that suspends none.
    pub resume: u32,
    /// Items each resume list holds: every row of the frame, so that no suspended row is
    /// lost (an item is 4 bytes).
    pub resume_items: u32,
}

impl Capacities {
    /// A first guess from the frame: two triangles per quad, and the bin entries `expected`
    /// and a quarter more (up to EXPECTED_BIN_ENTRIES), at least one per bin and what one
    /// block can take; `state_slots` for the rows the raster suspends (0: it suspends none).
    /// Overflow corrects it after one frame. Homogeneous records: `homogeneous`, the most
    /// the frame can need (features::homogeneous_triangles, within one storage buffer).
    pub fn initial(
        quads: u32,
        attribute_texels: u32,
        blocks: u32,
        expected: &super::features::FrameEstimate,
        homogeneous: u32,
        state_slots: u32,
        options: &super::BinOptions,
    ) -> Self {
        let triangles = quads.saturating_mul(2).max(1);
        let rows = blocks.saturating_mul(BIN_SIZE);
        let expected_entries = Self::expected_bin_entries(quads, expected);
        Self {
            resume: match state_slots {
                0 => 0,
                slots => options
                    .initial_resume_rows
                    .unwrap_or(slots)
                    .clamp(1, rows.max(1)),
            },
            resume_items: rows.max(1),
            triangles,
            attribute_texels,
            homogeneous: options.initial_homogeneous.unwrap_or(homogeneous).max(1),
            bin_entries: options
                .initial_bin_entries
                .unwrap_or(expected_entries.max(rows))
                .max(1),
        }
    }

    /// The bin entries a frame of `quads` transparent quads is expected to need: the
    /// `expected` ones and a quarter more (up to 128 MB, the least storage binding every
    /// Vulkan device allows), and at least one block's worth. Bands split a frame's lists
    /// between blocks, never inside one: a frame is right on its first recording only while
    /// every block's lists fit, and a block's take up to a row's entry from every triangle,
    /// whatever the camera.
    pub fn expected_bin_entries(quads: u32, expected: &super::features::FrameEstimate) -> u32 {
        const EXPECTED_BIN_ENTRIES: u64 = 1 << 25;
        let entries = expected.bin_entries;
        let one_block = quads.saturating_mul(2).max(1).saturating_mul(BIN_SIZE);
        ((entries + entries / 4).min(EXPECTED_BIN_ENTRIES) as u32).max(one_block)
    }

    /// The most of each growable buffer `gpu` binds (one storage buffer, one texel view):
    /// past them, bands and restarting rows answer within the frame. The raster keeps
    /// `state_bytes` of each row it suspends (0: it suspends none).
    pub fn most(gpu: &Gpu, state_bytes: u64) -> Self {
        let info = gpu.info();
        let storage = u64::from(info.max_storage_buffer_range);
        let texels = u64::from(info.max_texel_buffer_elements);
        // Items of `bytes` each in a buffer viewed as texels of `texel` bytes (0: no view).
        let fits = |bytes: u64, texel: u64| {
            let viewed = if texel == 0 {
                u64::MAX
            } else {
                texels * texel / bytes
            };
            (storage / bytes).min(viewed).min(u64::from(u32::MAX)) as u32
        };
        Self {
            // Written and read through texel views, not storage bindings.
            triangles: (texels * 16 / record_bytes_per_triangle(MOST_ATTRIBUTE_TEXELS))
                .min(u64::from(u32::MAX)) as u32,
            attribute_texels: MOST_ATTRIBUTE_TEXELS,
            homogeneous: fits(HOMOGENEOUS_BYTES, 16),
            bin_entries: fits(4, 4),
            // Both lists' row states in one buffer.
            resume: match state_bytes {
                0 => 0,
                bytes => fits(2 * bytes, 0),
            },
            resume_items: u32::MAX,
        }
    }

    /// These capacities within `most`, where a frame has an answer past it: bin lists past
    /// the capacity are rasterized in bands, suspended rows with no state slot restart, and
    /// near-plane records past it are counted. (Triangle records have none: they are not
    /// clamped.) A large frame then starts within one binding instead of being refused.
    pub fn within(self, most: &Self) -> Self {
        Self {
            resume: self.resume.min(most.resume),
            bin_entries: self.bin_entries.min(most.bin_entries),
            homogeneous: self.homogeneous.min(most.homogeneous),
            ..self
        }
    }

    /// Larger capacities when a frame recorded with capacities `recorded` overflowed, from
    /// what the GPU counted, up to `most`. A buffer already grown since that frame was
    /// recorded (by a frame completed before it, with frames in flight) is left alone:
    /// frames recorded with it will say whether it suffices.
    pub fn grown_for(&self, c: &BinCounters, recorded: &Self, most: &Self) -> Option<Self> {
        let with_headroom =
            |needed: u32, now: u32| needed.saturating_mul(2).max(now.saturating_mul(2));
        let grows = |bit: u32, now: u32, then: u32| c.overflow & bit != 0 && now == then;
        let mut next = *self;
        if grows(OVERFLOW_HOMOGENEOUS, self.homogeneous, recorded.homogeneous) {
            next.homogeneous = with_headroom(c.homogeneous_count, self.homogeneous)
                .min(most.homogeneous.max(self.homogeneous));
        }
        if grows(OVERFLOW_BIN_ENTRIES, self.bin_entries, recorded.bin_entries) {
            next.bin_entries = with_headroom(c.bin_entry_count, self.bin_entries)
                .min(most.bin_entries.max(self.bin_entries));
        } else if self.bin_entries == recorded.bin_entries
            && !fits_with_room(c.bin_entry_count, self.bin_entries)
        {
            // Lists that fit with less than half to spare: frames record one band only while
            // they have it (Bins::frame_done).
            // By half at least, so that a slowly growing frame does not regrow every frame.
            let roomy = c
                .bin_entry_count
                .saturating_mul(2)
                .max(self.bin_entries.saturating_add(self.bin_entries / 2));
            next.bin_entries = roomy.min(most.bin_entries).max(self.bin_entries);
        }
        if grows(OVERFLOW_RESUME, self.resume, recorded.resume) {
            next.resume =
                with_headroom(c.resume_needed, self.resume).min(most.resume.max(self.resume));
        }
        (next != *self).then_some(next)
    }
}

/// Whether `entries` bin entries leave half of `capacity` to spare.
pub fn fits_with_room(entries: u32, capacity: u32) -> bool {
    2 * u64::from(entries) <= u64::from(capacity)
}

/// Buffers that grow, each with the texel view the raster reads it through.
struct Growable {
    /// Resume lists of the raster's continuation dispatches (see `LOOP_BUDGET` in
    /// interface_bins.glsl): a header of six indirect dispatch commands (DISPATCH_BYTES), then
    /// the items.
    resume: Buffer,
    /// The raster's state of each suspended row that took a state slot (SuspendedRows).
    row_states: Option<Buffer>,
    triangles: Viewed,
    attributes: Viewed,
    homogeneous: Viewed,
    bin_entries: Viewed,
}

/// One frame slot's share: what a frame writes before it is recorded or reads after it
/// completed, while other frames are in flight.
struct BinSlot {
    draws: Viewed,
    /// A texel view of the scene's draw buffer of the same slot, and that buffer (replaced
    /// when the draws outgrow it).
    scene_draws: (vk::Buffer, BufferView),
    /// What the host reads after the frame: the counters, then the resume lists' counts.
    readback: Buffer,
    /// Set 1 over the slot's buffers and the shared ones of `generation`, and the opaque
    /// depth `depth` (the frame target's, or a view of the engine's image).
    set: DescriptorSet,
    generation: u64,
    depth: vk::ImageView,
    /// The resume list the frame's last continuation left unfinished rows on.
    pub pending_list: u32,
}

pub struct Resources {
    pub capacities: Capacities,
    pub layout: DescriptorLayout,
    slots: Vec<BinSlot>,
    /// The slot being written and recorded.
    slot: usize,
    /// Bumped whenever a shared buffer is replaced: slot sets of older generations are
    /// rebuilt before their next frame.
    generation: u64,
    /// Replaced buffers that frames in flight may still use.
    pub retirement: Retirement,
    /// The scene's assets, kept alive for their texel views: vertices, quads, materials,
    /// texture records, texels and the sRGB table.
    _resident: std::sync::Arc<ResidentAssets>,
    asset_views: [vk::BufferView; 3],
    /// The software sampler's textures this renderer binds (kept alive while it does).
    sampled: SampledViews,
    counters: Buffer,
    bins: BinArrays,
    /// The blocks with a non-empty bin, listed by the scan for the raster and the composite.
    pub raster_bins: Buffer,
    /// What the rasters leave for the composite on an engine's device
    /// (transparent_layer.glsl), in GENERAL layout: radiance and transmittance, and the rest
    /// of transmittance with the stamps. 1x1 until the first such frame
    /// ([`Self::make_layer`]).
    pub transparent_layer: [GpuImage; 2],
    /// The largest frame's size, which the transparent layer is made for.
    capacity: vk::Extent2D,
    /// The frame target's colour, which standalone frames' rasters composite onto.
    target_colour: vk::ImageView,
    /// The farthest opaque depth over ever larger cells, for setup's occlusion cull.
    depth_pyramid: Viewed,
    depth_sampler: Sampler,
    growable: Growable,
    /// What the raster keeps of the rows it suspends, if it does.
    suspended: Option<SuspendedRows>,
}

const COUNTER_BYTES: u64 = std::mem::size_of::<BinCounters>() as u64;
/// The resume lists' indirect dispatch commands (x is the list's item count).
const RESUME_HEADER_BYTES: u64 = 32;
const STORAGE: vk::BufferUsageFlags = vk::BufferUsageFlags::STORAGE_BUFFER;
const TEXELS: vk::BufferUsageFlags = vk::BufferUsageFlags::UNIFORM_TEXEL_BUFFER;
const RGBA32UI: vk::Format = vk::Format::R32G32B32A32_UINT;
/// Empty indirect dispatch commands, (x, y, z) and a fourth word each, counted on the GPU:
/// resume lists of a workgroup per item (the fourth word counting the items, which take the
/// state slots in order; x and z split them past the workgroups a row), the listed blocks' (blocks, BIN_SIZE /
/// rows, 1) for raster workgroups of `rows` rows, binning's (triangle groups, slices of the
/// tallest triangle, 1), the scan's offset step's (groups of the band's blocks, 1, 1), the
/// band's fill (binning's, or empty); then the composite's draw (a quad for each of no
/// listed block yet).
fn empty_dispatches(rows: u32) -> [[u32; 4]; 7] {
    [
        [0, 1, 1, 0],
        [0, 1, 1, 0],
        [0, BIN_SIZE / rows, 1, 0],
        [0, 1, 1, 0],
        [0, 1, 1, 0],
        [0, 1, 1, 0],
        [6, 0, 0, 0],
    ]
}

/// A device-local buffer the stages write (and the raster may read through a view).
fn storage_buffer(gpu: &Gpu, name: &str, bytes: u64) -> Result<Buffer> {
    let limit = u64::from(gpu.info().max_storage_buffer_range);
    if bytes > limit {
        return Err(Error::TooLarge(format!(
            "the {name} need {} MB, over this device's {} MB storage-buffer limit",
            bytes >> 20,
            limit >> 20
        )));
    }
    gpu.create_buffer(
        name,
        bytes,
        STORAGE | TEXELS | vk::BufferUsageFlags::TRANSFER_DST,
        MemoryLocation::GpuOnly,
    )
}

/// A storage buffer with a view for the raster to read it through.
fn viewed_storage(gpu: &Gpu, name: &str, bytes: u64, format: vk::Format) -> Result<Viewed> {
    Viewed::new(gpu, storage_buffer(gpu, name, bytes)?, format)
}

/// A device-local buffer the stages read through texel views of `format`, which only the
/// device's texels a view bound (2 GB of RGBA32 on lavapipe, against 128 MB a storage
/// binding): what lets a frame hold millions of triangle records. Setup writes it as a
/// storage buffer while it fits one binding, else through a storage texel view
/// (`RECORDS_AS_TEXELS` of setup.comp; slower on lavapipe).
fn texel_storage(gpu: &Gpu, name: &str, bytes: u64, format: vk::Format) -> Result<Viewed> {
    let buffer = gpu.create_buffer(
        name,
        bytes,
        STORAGE | TEXELS | vk::BufferUsageFlags::STORAGE_TEXEL_BUFFER,
        MemoryLocation::GpuOnly,
    )?;
    Viewed::new(gpu, buffer, format)
}

/// The growable buffers for `c`, with the state of `suspended` rows.
fn growable(gpu: &Gpu, c: Capacities, suspended: Option<SuspendedRows>) -> Result<Growable> {
    let triangles = u64::from(c.triangles);
    let resume_items = 2 * u64::from(c.resume_items);
    let row_states = |rows: SuspendedRows| {
        let bytes = 2 * u64::from(c.resume.max(1)) * rows.bytes_per_tile;
        storage_buffer(gpu, "suspended row states", bytes)
    };
    Ok(Growable {
        resume: gpu.create_buffer(
            "resume lists",
            DISPATCH_BYTES + resume_items * RESUME_ITEM_BYTES,
            STORAGE
                | vk::BufferUsageFlags::INDIRECT_BUFFER
                | vk::BufferUsageFlags::TRANSFER_DST
                | vk::BufferUsageFlags::TRANSFER_SRC,
            MemoryLocation::GpuOnly,
        )?,
        row_states: suspended.map(row_states).transpose()?,
        triangles: texel_storage(
            gpu,
            "triangle records",
            triangles * TRIANGLE_BYTES,
            RGBA32UI,
        )?,
        attributes: texel_storage(
            gpu,
            "quad attributes",
            triangles.div_ceil(2) * u64::from(c.attribute_texels) * 16,
            RGBA32UI,
        )?,
        homogeneous: viewed_storage(
            gpu,
            "homogeneous records",
            u64::from(c.homogeneous) * HOMOGENEOUS_BYTES,
            RGBA32UI,
        )?,
        bin_entries: viewed_storage(
            gpu,
            "bin lists",
            u64::from(c.bin_entries) * 4,
            vk::Format::R32_UINT,
        )?,
    })
}

/// The transparent layer's two images (transparent_layer.glsl) for frames of up to
/// `extent` (at least 1x1).
fn transparent_layer(gpu: &Gpu, extent: vk::Extent2D) -> Result<[GpuImage; 2]> {
    let extent = vk::Extent2D {
        width: extent.width.max(1),
        height: extent.height.max(1),
    };
    let usage = vk::ImageUsageFlags::STORAGE;
    Ok([
        gpu.create_image(
            "transparent layer",
            extent,
            vk::Format::R32G32_UINT,
            usage,
            1,
        )?,
        gpu.create_image(
            "transparent layer stamps",
            extent,
            vk::Format::R32_UINT,
            usage | vk::ImageUsageFlags::TRANSFER_DST,
            1,
        )?,
    ])
}

/// Per (bin, depth slab): triangle counts, turned into list offsets in place by the scan and
/// into list ends by the fill; per block, the scan's totals and offsets. Blocks are padded to
/// whole scan workgroups, with at least one past the frame's, which the scan's invocations
/// past a band write instead of a band's block (see bin_offsets.comp).
struct BinArrays {
    /// Blocks the arrays hold: the frame's, padded.
    blocks: u64,
    slabs: u32,
    ends: Viewed,
    block_totals: Viewed,
}

impl BinArrays {
    fn new(gpu: &Gpu, frame_blocks: u64, slabs: u32) -> Result<Self> {
        let blocks = (frame_blocks + 1).next_multiple_of(u64::from(SCAN_GROUP_SIZE));
        let bytes = blocks * u64::from(BIN_SIZE * slabs) * 4;
        let r32 = vk::Format::R32_UINT;
        Ok(Self {
            blocks,
            slabs,
            ends: viewed_storage(gpu, "bin list ends", bytes, r32)?,
            block_totals: viewed_storage(gpu, "block totals", blocks * 4, r32)?,
        })
    }
}

/// Cells of every level of the opaque depth pyramid over a frame of `bins_x` x `bins_y`
/// blocks (depth_pyramid.glsl): each level halves the sides, rounding up, down to one cell.
fn pyramid_cells(bins_x: u32, bins_y: u32) -> u32 {
    let (mut x, mut y) = (bins_x, bins_y);
    let mut cells = x * y;
    while x > 1 || y > 1 {
        x = x.div_ceil(2);
        y = y.div_ceil(2);
        cells += x * y;
    }
    cells
}

/// The transparent draws in the order the reference ranks them, with their model-view-
/// projection computed on the host exactly as the reference does, and their meshes' first
/// quads in the uploaded quads (`first_quad_of_mesh`).
fn bin_draws(scene: &Scene, first_quad_of_mesh: &[u32], width: u32, height: u32) -> Vec<BinDraw> {
    let view_projection = scene.camera.view_projection(width, height);
    let mut first_item = 0u32;
    scene
        .transparent
        .iter()
        .enumerate()
        .map(|(i, d)| {
            let quad_count = scene.meshes[d.mesh].quads.len() as u32;
            let draw = BinDraw {
                mvp: model_view_projection(&view_projection, &d.transform).to_cols_array(),
                draw_index: (scene.opaque.len() + i) as u32,
                first_item,
                quad_count,
                first_quad: first_quad_of_mesh[d.mesh],
            };
            first_item += quad_count;
            draw
        })
        .collect()
}

impl Resources {
    /// The buffers for `scene` (uploaded as `gpu_scene`, whose frame slots it takes) over
    /// `targets`, every slot holding the scene's own frame.
    pub fn new(
        gpu: &Gpu,
        scene: &Scene,
        gpu_scene: &GpuScene,
        targets: &FrameTargets,
        capacities: Capacities,
        slabs: u32,
        suspended: Option<SuspendedRows>,
    ) -> Result<Self> {
        // Arrays per block for the largest frame; the draws for the current one.
        let capacity = targets.capacity;
        let (blocks_x, blocks_y) = (
            capacity.width.div_ceil(BIN_SIZE),
            capacity.height.div_ceil(BIN_SIZE),
        );
        let blocks = u64::from(blocks_x) * u64::from(blocks_y);
        let (width, height) = (targets.extent.width, targets.extent.height);
        if scene.materials.len() as u64 > 1 << (32 - TRIANGLE_MATERIAL_SHIFT) {
            return Err(Error::TooLarge(format!(
                "{} materials; triangle records address at most {}",
                scene.materials.len(),
                1u32 << (32 - TRIANGLE_MATERIAL_SHIFT)
            )));
        }
        let draws = bin_draws(scene, &gpu_scene.resident.first_quads, width, height);
        // Counters and indirect arguments stay in device memory; the host reads a copy.
        let counters = gpu.create_buffer(
            "bin counters",
            COUNTER_BYTES,
            STORAGE | vk::BufferUsageFlags::TRANSFER_DST | vk::BufferUsageFlags::TRANSFER_SRC,
            MemoryLocation::GpuOnly,
        )?;

        let set = suspended.map_or(&BINS_SET, |rows| rows.set);
        let layout = DescriptorLayout::declared(gpu, set, vk::ShaderStageFlags::COMPUTE)?;
        let mut resources = Self {
            capacities,
            layout,
            slots: Vec::new(),
            slot: 0,
            generation: 0,
            retirement: Retirement::default(),
            _resident: gpu_scene.resident.clone(),
            asset_views: gpu_scene.resident.texel_views(),
            sampled: gpu_scene.resident.sampled_views(gpu, scene)?,
            counters,
            bins: BinArrays::new(gpu, blocks, slabs)?,
            raster_bins: storage_buffer(gpu, "non-empty blocks", blocks * 4)?,
            transparent_layer: transparent_layer(gpu, vk::Extent2D::default())?,
            capacity,
            target_colour: targets.colour.view,
            depth_pyramid: viewed_storage(
                gpu,
                "opaque depth pyramid",
                u64::from(pyramid_cells(blocks_x, blocks_y)) * 4,
                vk::Format::R32_SFLOAT,
            )?,
            depth_sampler: Sampler::nearest_clamp(gpu)?,
            growable: growable(gpu, capacities, suspended)?,
            suspended,
        };
        // Room for twice the draws, as the scene's draws have (GpuScene).
        let draw_bytes = (2 * draws.len()).max(crate::assets::FIRST_DRAWS) as u64
            * std::mem::size_of::<BinDraw>() as u64;
        for _ in 0..gpu_scene.slot_count() {
            let mut buffer = gpu.create_per_frame_buffer("bin draws", draw_bytes, TEXELS)?;
            buffer.write(0, bytemuck::cast_slice(&draws))?;
            let draws = Viewed::new(gpu, buffer, RGBA32UI)?;
            let scene_draws = (
                gpu_scene.draws().raw,
                gpu.create_buffer_view(gpu_scene.draws(), RGBA32UI)?,
            );
            let set = resources.make_set(&draws.view, &scene_draws.1, targets.depth.view)?;
            resources.slots.push(BinSlot {
                draws,
                scene_draws,
                readback: gpu.create_buffer(
                    "bin counters readback",
                    COUNTER_BYTES + RESUME_HEADER_BYTES,
                    vk::BufferUsageFlags::TRANSFER_DST,
                    MemoryLocation::GpuToCpu,
                )?,
                set,
                generation: 0,
                depth: targets.depth.view,
                pending_list: 0,
            });
        }
        Ok(resources)
    }

    /// Whether the triangle records pass what one storage binding holds, so that setup must
    /// write them through texel views.
    pub fn records_pass_a_binding(&self, gpu: &Gpu) -> bool {
        let bytes = u64::from(self.capacities.triangles)
            * record_bytes_per_triangle(self.capacities.attribute_texels);
        bytes > u64::from(gpu.info().max_storage_buffer_range)
    }

    /// Makes `slot` the frame slot the next frame is written into and recorded from. No frame
    /// of that slot may be in flight.
    pub fn use_slot(&mut self, slot: usize) {
        self.slot = slot % self.slots.len();
    }

    /// The current slot's descriptor set, made by [`Self::refresh_set`].
    pub fn set(&self) -> vk::DescriptorSet {
        self.slots[self.slot].set.raw
    }

    /// The resume list the current slot's frame left its unfinished rows on.
    pub fn set_pending_list(&mut self, list: u32) {
        self.slots[self.slot].pending_list = list;
    }

    /// Rebuilds the current slot's descriptor set if a buffer it names was replaced, or
    /// the opaque depth is another view; or in any case when `depth` was made for this
    /// frame (an engine's image: a view's handle may be one a destroyed view had).
    pub fn refresh_set(&mut self, depth: vk::ImageView, made_for_frame: bool) -> Result<()> {
        let slot = &self.slots[self.slot];
        if slot.generation == self.generation && slot.depth == depth && !made_for_frame {
            return Ok(());
        }
        let set = self.make_set(&slot.draws.view, &slot.scene_draws.1, depth)?;
        let slot = &mut self.slots[self.slot];
        // The slot's last frame has completed: its old set can go now.
        slot.set = set;
        slot.generation = self.generation;
        slot.depth = depth;
        Ok(())
    }

    /// Makes the transparent layer for the largest frame, once (frames on an engine's
    /// device need it, standalone ones not); the slots' sets then name it. Whether it made
    /// it (its images are then to be cleared).
    pub fn make_layer(&mut self, gpu: &Gpu) -> Result<bool> {
        if self.transparent_layer[0].extent == self.capacity {
            return Ok(false);
        }
        let layer = transparent_layer(gpu, self.capacity)?;
        for old in std::mem::replace(&mut self.transparent_layer, layer) {
            self.retirement.retire(old);
        }
        self.generation += 1;
        Ok(true)
    }

    /// Clears the transparent layer to no stamp (its stamps image to zero, the other moved
    /// to GENERAL), ordered after anything before and before the stages and the composite.
    pub fn record_layer_clear(&self, cmd: vk::CommandBuffer) {
        let gpu = self.counters.gpu();
        let [layer, stamps] = &self.transparent_layer;
        let transfer = (
            vk::PipelineStageFlags::TRANSFER,
            vk::AccessFlags::TRANSFER_WRITE,
        );
        // What it held is not kept: UNDEFINED is its layout for the first clear, and any
        // layout will do for the others.
        let any = (
            vk::PipelineStageFlags::ALL_COMMANDS,
            vk::AccessFlags::MEMORY_READ | vk::AccessFlags::MEMORY_WRITE,
        );
        let general = vk::ImageLayout::GENERAL;
        let undefined = vk::ImageLayout::UNDEFINED;
        image_barrier(gpu, cmd, layer, undefined, general, any, any);
        image_barrier(gpu, cmd, stamps, undefined, general, any, transfer);
        gpu.cmd_clear_to_zero(cmd, stamps, general);
        image_barrier(gpu, cmd, stamps, general, general, transfer, any);
    }

    /// Set 1 over a slot's draws and view of the scene's draws, and the shared buffers.
    fn make_set(
        &self,
        draws: &BufferView,
        scene_draws: &BufferView,
        depth: vk::ImageView,
    ) -> Result<DescriptorSet> {
        let g = &self.growable;
        let [vertices, quads, materials] = self.asset_views;
        let SampledViews {
            records: texture_records,
            texels: texels_view,
            srgb,
            ..
        } = self.sampled;
        let texels = |view: vk::BufferView| Resource::TexelBuffer(view);
        let depth = [depth];
        let mut bindings = vec![
            ("u_vertexTexels", texels(vertices)),
            ("u_quadTexels", texels(quads)),
            ("u_drawTexels", texels(scene_draws.raw)),
            ("u_binDrawTexels", texels(draws.raw)),
            ("u_materialTexels", texels(materials)),
            ("u_textureInfoTexels", texels(texture_records)),
            ("u_texels", texels(texels_view)),
            ("u_srgbToLinear", texels(srgb)),
            (
                "u_opaqueDepth",
                Resource::Images(&depth, self.depth_sampler.raw),
            ),
            (
                "DepthPyramidBlock",
                Resource::Buffer(&self.depth_pyramid.buffer),
            ),
            ("u_depthPyramidTexels", texels(self.depth_pyramid.view.raw)),
            ("TriangleBlock", Resource::BufferPrefix(&g.triangles.buffer)),
            (
                "AttributeBlock",
                Resource::BufferPrefix(&g.attributes.buffer),
            ),
            ("u_triangleRecords", texels(g.triangles.view.raw)),
            ("u_attributeRecords", texels(g.attributes.view.raw)),
            ("u_triangleTexels", texels(g.triangles.view.raw)),
            ("u_attributeTexels", texels(g.attributes.view.raw)),
            ("HomogeneousBlock", Resource::Buffer(&g.homogeneous.buffer)),
            ("u_homogeneousTexels", texels(g.homogeneous.view.raw)),
            ("CounterBlock", Resource::Buffer(&self.counters)),
            ("BinEndBlock", Resource::Buffer(&self.bins.ends.buffer)),
            ("u_binCountTexels", texels(self.bins.ends.view.raw)),
            (
                "BlockTotalBlock",
                Resource::Buffer(&self.bins.block_totals.buffer),
            ),
            (
                "u_blockTotalTexels",
                texels(self.bins.block_totals.view.raw),
            ),
            ("BinEntryBlock", Resource::Buffer(&g.bin_entries.buffer)),
            ("u_binEntryTexels", texels(g.bin_entries.view.raw)),
            ("RasterBinBlock", Resource::Buffer(&self.raster_bins)),
            ("DispatchBlock", Resource::Buffer(&g.resume)),
            ("u_colour", Resource::StorageImage(self.target_colour)),
            (
                "u_transparentLayer",
                Resource::StorageImage(self.transparent_layer[0].view),
            ),
            (
                "u_transparentLayerStamps",
                Resource::StorageImage(self.transparent_layer[1].view),
            ),
        ];
        if let (Some(rows), Some(states)) = (self.suspended, &g.row_states) {
            bindings.push((rows.binding, Resource::Buffer(states)));
        }
        self.layout.create_named_set(&bindings)
    }

    /// Zeroes the counters and bin counts, writes the capacities and an empty depth range,
    /// and empties the indirect dispatch commands (the raster's first having workgroups of
    /// `rows` rows, binning one slice until setup finds a taller triangle), before setup.
    pub fn record_reset(&self, cmd: vk::CommandBuffer, rows: u32) {
        let gpu = self.counters.gpu();
        // One write of the whole record: separate writes to one buffer would need barriers
        // between them.
        let counters = BinCounters {
            triangle_capacity: self.capacities.triangles,
            homogeneous_capacity: self.capacities.homogeneous,
            bin_entry_capacity: self.capacities.bin_entries,
            resume_capacity: self.capacities.resume,
            resume_item_capacity: self.capacities.resume_items,
            depth_lo: u32::MAX,
            ..BinCounters::default()
        };
        gpu.cmd_update_buffer(cmd, &self.counters, 0, bytemuck::bytes_of(&counters));
        gpu.cmd_fill_buffer(cmd, &self.bins.ends.buffer, 0);
        gpu.cmd_update_buffer(
            cmd,
            &self.growable.resume,
            0,
            bytemuck::cast_slice(&empty_dispatches(rows)),
        );
        memory_barrier(
            gpu,
            cmd,
            (
                vk::PipelineStageFlags::TRANSFER,
                vk::AccessFlags::TRANSFER_WRITE,
            ),
            (
                vk::PipelineStageFlags::COMPUTE_SHADER,
                vk::AccessFlags::SHADER_READ | vk::AccessFlags::SHADER_WRITE,
            ),
        );
    }

    /// Empties resume list `list` (its items and state slots) once a continuation has
    /// consumed it, so that the next dispatch to append to it starts afresh.
    pub fn record_resume_list_reset(&self, cmd: vk::CommandBuffer, list: u32) {
        let resume = &self.growable.resume;
        let empty: [u32; 4] = [0, 1, 1, 0];
        resume.gpu().cmd_update_buffer(
            cmd,
            resume,
            u64::from(list) * 16,
            bytemuck::bytes_of(&empty),
        );
    }

    /// Records the copy of the counters and the resume lists' counts for the host, after
    /// the frame's last compute pass and before `(HOST, HOST_READ)`.
    pub fn record_readback(&self, cmd: vk::CommandBuffer) {
        let gpu = self.counters.gpu();
        let transfer_write = (
            vk::PipelineStageFlags::TRANSFER,
            vk::AccessFlags::TRANSFER_WRITE,
        );
        memory_barrier(
            gpu,
            cmd,
            (
                vk::PipelineStageFlags::COMPUTE_SHADER | vk::PipelineStageFlags::TRANSFER,
                vk::AccessFlags::SHADER_WRITE | vk::AccessFlags::TRANSFER_WRITE,
            ),
            (
                vk::PipelineStageFlags::TRANSFER,
                vk::AccessFlags::TRANSFER_READ,
            ),
        );
        let readback = &self.slots[self.slot].readback;
        gpu.cmd_copy_buffer(cmd, &self.counters, readback, 0, COUNTER_BYTES);
        gpu.cmd_copy_buffer(
            cmd,
            &self.growable.resume,
            readback,
            COUNTER_BYTES,
            RESUME_HEADER_BYTES,
        );
        memory_barrier(
            gpu,
            cmd,
            transfer_write,
            (vk::PipelineStageFlags::HOST, vk::AccessFlags::HOST_READ),
        );
    }

    /// Rows slot `slot`'s completed frame left unfinished (on its pending resume list).
    pub fn unfinished_rows(&self, slot: usize) -> Result<u32> {
        let slot = &self.slots[slot];
        // The list's item count: its command's fourth word.
        let at = (COUNTER_BYTES + u64::from(slot.pending_list) * 16 + 12) as usize;
        Ok(bytemuck::pod_read_unaligned(
            &slot.readback.read()?[at..at + 4],
        ))
    }

    /// The buffer holding the indirect dispatch commands.
    pub fn dispatches(&self) -> &Buffer {
        &self.growable.resume
    }

    /// The counters of slot `slot`'s completed frame.
    pub fn counters(&self, slot: usize) -> Result<BinCounters> {
        Ok(bytemuck::pod_read_unaligned(
            &self.slots[slot].readback.read()?[..std::mem::size_of::<BinCounters>()],
        ))
    }

    /// Writes the frame's draws into the current slot (`gpu_scene` holding the frame in the
    /// same slot already), and renews the slot's descriptor set if a buffer it names moved.
    pub fn set_frame(
        &mut self,
        gpu: &Gpu,
        scene: &Scene,
        gpu_scene: &GpuScene,
        targets: &FrameTargets,
    ) -> Result<()> {
        let (width, height) = (targets.extent.width, targets.extent.height);
        let draws = bin_draws(scene, &gpu_scene.resident.first_quads, width, height);
        let bytes: &[u8] = bytemuck::cast_slice(&draws);
        let slot = &mut self.slots[self.slot];
        if bytes.len() as u64 > slot.draws.buffer.size {
            // Room for twice as many, so that a growing draw count reallocates rarely.
            let buffer =
                gpu.create_per_frame_buffer("bin draws", 2 * bytes.len() as u64, TEXELS)?;
            slot.draws = Viewed::new(gpu, buffer, RGBA32UI)?;
            slot.generation = u64::MAX;
        }
        slot.draws.buffer.write(0, bytes)?;
        // Textures the frame's transparent draws use for the first time are copied for the
        // software sampler; when they took a new set of buffers, every slot binds it.
        let sampled = gpu_scene.resident.sampled_views(gpu, scene)?;
        if !sampled.same_buffers(&self.sampled) {
            let old = std::mem::replace(&mut self.sampled, sampled);
            self.retirement.retire(old);
            self.generation += 1;
        }
        let slot = &mut self.slots[self.slot];
        if slot.scene_draws.0 != gpu_scene.draws().raw {
            slot.scene_draws = (
                gpu_scene.draws().raw,
                gpu.create_buffer_view(gpu_scene.draws(), RGBA32UI)?,
            );
            slot.generation = u64::MAX;
        }
        // (The slot's set is made anew when the frame is recorded: Self::refresh_set.)
        Ok(())
    }

    /// Makes room for `slabs` depth slabs per bin; the old arrays stay until the frames in
    /// flight complete.
    pub fn set_slabs(&mut self, gpu: &Gpu, slabs: u32) -> Result<()> {
        if slabs != self.bins.slabs {
            let bins = BinArrays::new(gpu, self.bins.blocks, slabs)?;
            let old = std::mem::replace(&mut self.bins, bins);
            self.retirement.retire(old);
            self.generation += 1;
        }
        Ok(())
    }

    /// Replaces the growable buffers with ones of `capacities`; the old ones stay until the
    /// frames in flight complete.
    pub fn grow(&mut self, gpu: &Gpu, capacities: Capacities) -> Result<()> {
        let grown = growable(gpu, capacities, self.suspended)?;
        let old = std::mem::replace(&mut self.growable, grown);
        self.retirement.retire(old);
        self.generation += 1;
        self.capacities = capacities;
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn pyramid_levels_halve_down_to_one_cell() {
        // 5x3 blocks: 5x3, 3x2, 2x1, 1x1.
        assert_eq!(pyramid_cells(5, 3), 15 + 6 + 2 + 1);
        assert_eq!(pyramid_cells(1, 1), 1);
    }

    /// farthestOpaque climbs at most PYRAMID_MAX_LEVELS - 1 levels: enough for the largest
    /// frame the method takes (65535 pixels a side).
    #[test]
    fn pyramid_lookup_reaches_the_top_of_the_largest_frame() {
        let max_levels = crate::interface::bins::PYRAMID_MAX_LEVELS;
        let mut side = 0xFFFF_u32.div_ceil(BIN_SIZE);
        let mut levels = 1;
        while side > 1 {
            side = side.div_ceil(2);
            levels += 1;
        }
        assert!(
            levels <= max_levels,
            "{levels} levels, lookup climbs {max_levels}"
        );
    }
}
