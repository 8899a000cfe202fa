//! Shader modules, descriptor layouts and sets, samplers, render passes and pipelines.

use super::error::vk_err;
use super::{Buffer, Gpu, Profile};
use crate::interface::specialization::{Specialization, RASTER_GROUP_SIZE, ROUNDED_DIVISION};
use crate::interface::{BindingType, SetDecl};
use crate::{scene, Result};
use ash::vk;
use std::sync::Arc;

/// What a descriptor binding holds.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum BindingKind {
    StorageBuffer,
    UniformBuffer,
    /// An array of this many combined image samplers.
    SampledImages(u32),
    StorageImage,
    /// A uniform texel buffer (`usamplerBuffer` and the like).
    TexelBuffer,
    /// A storage texel buffer (`uimageBuffer` and the like): written through texels, so that
    /// only the device's texels a view (not its storage-buffer range) bound it.
    StorageTexelBuffer,
}

impl BindingKind {
    fn descriptor_type(self) -> (vk::DescriptorType, u32) {
        match self {
            Self::StorageBuffer => (vk::DescriptorType::STORAGE_BUFFER, 1),
            Self::UniformBuffer => (vk::DescriptorType::UNIFORM_BUFFER, 1),
            Self::SampledImages(n) => (vk::DescriptorType::COMBINED_IMAGE_SAMPLER, n),
            Self::StorageImage => (vk::DescriptorType::STORAGE_IMAGE, 1),
            Self::TexelBuffer => (vk::DescriptorType::UNIFORM_TEXEL_BUFFER, 1),
            Self::StorageTexelBuffer => (vk::DescriptorType::STORAGE_TEXEL_BUFFER, 1),
        }
    }
}

impl From<BindingType> for BindingKind {
    fn from(ty: BindingType) -> Self {
        match ty {
            BindingType::Texels { .. } => Self::TexelBuffer,
            BindingType::StorageTexels(_) => Self::StorageTexelBuffer,
            BindingType::Buffer { .. } => Self::StorageBuffer,
            BindingType::Uniform { .. } => Self::UniformBuffer,
            BindingType::Sampled { count, .. } => Self::SampledImages(count),
            BindingType::StorageImage(_) => Self::StorageImage,
        }
    }
}

/// A descriptor set layout; binding `i` is `kinds[i]`.
pub struct DescriptorLayout {
    gpu: Gpu,
    pub raw: vk::DescriptorSetLayout,
    kinds: Vec<BindingKind>,
    stages: vk::ShaderStageFlags,
    /// The shader interface's declaration of the set, for layouts made from one.
    declaration: Option<&'static SetDecl>,
}

/// What to bind at one binding of a [`DescriptorSet`].
#[derive(Clone)]
pub enum Resource<'a> {
    Buffer(&'a Buffer),
    /// As much of a buffer as one storage binding holds, from its start: for a buffer the
    /// shaders reach past that only another way (through a texel view).
    BufferPrefix(&'a Buffer),
    /// Image views (in SHADER_READ_ONLY_OPTIMAL) with one sampler.
    Images(&'a [vk::ImageView], vk::Sampler),
    /// Image views (in SHADER_READ_ONLY_OPTIMAL), each with its own sampler.
    Textures(&'a [(vk::ImageView, vk::Sampler)]),
    StorageImage(vk::ImageView),
    /// A texel buffer's view, for a `TexelBuffer` or a `StorageTexelBuffer` binding.
    TexelBuffer(vk::BufferView),
}

/// A descriptor set with its own small pool, freed on drop.
pub struct DescriptorSet {
    gpu: Gpu,
    pool: vk::DescriptorPool,
    pub raw: vk::DescriptorSet,
}

impl DescriptorLayout {
    pub fn new(gpu: &Gpu, kinds: &[BindingKind], stages: vk::ShaderStageFlags) -> Result<Self> {
        let bindings: Vec<_> = kinds
            .iter()
            .enumerate()
            .map(|(i, k)| {
                let (ty, count) = k.descriptor_type();
                vk::DescriptorSetLayoutBinding::default()
                    .binding(i as u32)
                    .descriptor_type(ty)
                    .descriptor_count(count)
                    .stage_flags(stages)
            })
            .collect();
        let info = vk::DescriptorSetLayoutCreateInfo::default().bindings(&bindings);
        // SAFETY: valid device and create info.
        let raw = unsafe {
            gpu.device
                .create_descriptor_set_layout(&info, gpu.callbacks())
        }
        .map_err(vk_err("vkCreateDescriptorSetLayout"))?;
        Ok(Self {
            gpu: gpu.clone(),
            raw,
            kinds: kinds.to_vec(),
            stages,
            declaration: None,
        })
    }

    /// The layout of a set the shader interface declares (`crate::interface`), whose sets are
    /// then written by binding name ([`Self::create_named_set`]).
    pub fn declared(
        gpu: &Gpu,
        declaration: &'static SetDecl,
        stages: vk::ShaderStageFlags,
    ) -> Result<Self> {
        let kinds: Vec<BindingKind> = declaration
            .all_bindings()
            .iter()
            .map(|b| b.ty.into())
            .collect();
        let mut layout = Self::new(gpu, &kinds, stages)?;
        layout.declaration = Some(declaration);
        Ok(layout)
    }

    /// Allocates a set of a declared layout and writes each `(name, resource)`: every binding
    /// once, by the name the interface gives it. A name the interface does not declare, or a
    /// binding left out or written twice, is a bug, and panics.
    pub fn create_named_set(&self, resources: &[(&str, Resource<'_>)]) -> Result<DescriptorSet> {
        self.create_set(&self.in_binding_order(resources))
    }

    /// [`Self::write_set`] by binding name, as [`Self::create_named_set`] writes.
    pub fn write_named_set(
        &self,
        set: &DescriptorSet,
        resources: &[(&str, Resource<'_>)],
    ) -> Result<()> {
        self.write_set(set, &self.in_binding_order(resources))
    }

    /// `resources` by binding number.
    fn in_binding_order<'a>(&self, resources: &[(&str, Resource<'a>)]) -> Vec<Resource<'a>> {
        let declaration = self
            .declaration
            .expect("a layout the shader interface declares");
        let bindings = declaration.all_bindings();
        let mut ordered: Vec<Option<Resource<'a>>> = vec![None; bindings.len()];
        for (name, resource) in resources {
            let binding = bindings
                .iter()
                .position(|b| b.name == *name)
                .unwrap_or_else(|| panic!("set {} declares no binding {name}", declaration.set));
            let slot = &mut ordered[binding];
            assert!(slot.is_none(), "binding {name} written twice");
            *slot = Some(resource.clone());
        }
        ordered
            .into_iter()
            .zip(bindings)
            .map(|(r, b)| r.unwrap_or_else(|| panic!("binding {} left unwritten", b.name)))
            .collect()
    }

    /// What makes two layouts interchangeable: Vulkan lets a set allocated with one be bound
    /// to a pipeline made with another that is identically defined.
    pub fn definition(&self) -> (&[BindingKind], vk::ShaderStageFlags) {
        (&self.kinds, self.stages)
    }

    /// Allocates a set and writes `resources[i]` to binding `i`.
    pub fn create_set(&self, resources: &[Resource<'_>]) -> Result<DescriptorSet> {
        let sizes: Vec<_> = self
            .kinds
            .iter()
            .map(|k| {
                let (ty, count) = k.descriptor_type();
                vk::DescriptorPoolSize {
                    ty,
                    descriptor_count: count,
                }
            })
            .collect();
        let pool_info = vk::DescriptorPoolCreateInfo::default()
            .max_sets(1)
            .pool_sizes(&sizes);
        // SAFETY: valid device and create info.
        let pool = unsafe {
            self.gpu
                .device
                .create_descriptor_pool(&pool_info, self.gpu.callbacks())
        }
        .map_err(vk_err("vkCreateDescriptorPool"))?;
        let mut set = DescriptorSet {
            gpu: self.gpu.clone(),
            pool,
            raw: vk::DescriptorSet::null(),
        };
        let layouts = [self.raw];
        let alloc = vk::DescriptorSetAllocateInfo::default()
            .descriptor_pool(pool)
            .set_layouts(&layouts);
        // SAFETY: the pool has room for exactly this set.
        set.raw = unsafe { self.gpu.device.allocate_descriptor_sets(&alloc) }
            .map_err(vk_err("vkAllocateDescriptorSets"))?[0];
        self.write_set(&set, resources)?;
        Ok(set)
    }

    /// Writes `resources[i]` to binding `i` of `set`, a set of this layout that no pending
    /// work uses.
    pub fn write_set(&self, set: &DescriptorSet, resources: &[Resource<'_>]) -> Result<()> {
        assert_eq!(
            resources.len(),
            self.kinds.len(),
            "one resource per binding"
        );
        // A binding over the device's range is refused before it is written: writing one
        // is invalid, and the shader would read past its end.
        let range = u64::from(self.gpu.info().max_storage_buffer_range);
        for (kind, resource) in self.kinds.iter().zip(resources) {
            if let (BindingKind::StorageBuffer, Resource::Buffer(b)) = (kind, resource) {
                if b.size > range {
                    return Err(crate::Error::TooLarge(format!(
                        "{} takes {} MB, over the {} MB this device binds as one storage \
                         buffer",
                        b.name,
                        b.size >> 20,
                        range >> 20
                    )));
                }
            }
        }
        let buffer_infos: Vec<Vec<vk::DescriptorBufferInfo>> = resources
            .iter()
            .map(|r| match r {
                Resource::Buffer(b) => vec![vk::DescriptorBufferInfo {
                    buffer: b.raw,
                    offset: 0,
                    range: vk::WHOLE_SIZE,
                }],
                Resource::BufferPrefix(b) => vec![vk::DescriptorBufferInfo {
                    buffer: b.raw,
                    offset: 0,
                    range: b.size.min(range),
                }],
                _ => Vec::new(),
            })
            .collect();
        let image_infos: Vec<Vec<vk::DescriptorImageInfo>> = resources
            .iter()
            .map(|r| match r {
                Resource::Images(views, sampler) => views
                    .iter()
                    .map(|&v| vk::DescriptorImageInfo {
                        sampler: *sampler,
                        image_view: v,
                        image_layout: vk::ImageLayout::SHADER_READ_ONLY_OPTIMAL,
                    })
                    .collect(),
                Resource::Textures(textures) => textures
                    .iter()
                    .map(|&(v, sampler)| vk::DescriptorImageInfo {
                        sampler,
                        image_view: v,
                        image_layout: vk::ImageLayout::SHADER_READ_ONLY_OPTIMAL,
                    })
                    .collect(),
                Resource::StorageImage(v) => vec![vk::DescriptorImageInfo {
                    sampler: vk::Sampler::null(),
                    image_view: *v,
                    image_layout: vk::ImageLayout::GENERAL,
                }],
                Resource::Buffer(_) | Resource::BufferPrefix(_) | Resource::TexelBuffer(_) => {
                    Vec::new()
                }
            })
            .collect();
        let texel_views: Vec<[vk::BufferView; 1]> = resources
            .iter()
            .map(|r| match r {
                Resource::TexelBuffer(v) => [*v],
                _ => [vk::BufferView::null()],
            })
            .collect();
        let writes: Vec<_> = self
            .kinds
            .iter()
            .enumerate()
            .map(|(i, k)| {
                let w = vk::WriteDescriptorSet::default()
                    .dst_set(set.raw)
                    .dst_binding(i as u32)
                    .descriptor_type(k.descriptor_type().0);
                if matches!(
                    k,
                    BindingKind::TexelBuffer | BindingKind::StorageTexelBuffer
                ) {
                    w.texel_buffer_view(&texel_views[i])
                } else if buffer_infos[i].is_empty() {
                    w.image_info(&image_infos[i])
                } else {
                    w.buffer_info(&buffer_infos[i])
                }
            })
            .collect();
        for (i, (k, w)) in self.kinds.iter().zip(&writes).enumerate() {
            assert_eq!(
                w.descriptor_count,
                k.descriptor_type().1,
                "binding {i}: resource does not match its layout"
            );
        }
        // SAFETY: every write targets a binding of this set's layout with matching type/count,
        // and no pending work uses the set (the caller's contract).
        unsafe { self.gpu.device.update_descriptor_sets(&writes, &[]) };
        Ok(())
    }
}

impl Drop for DescriptorLayout {
    fn drop(&mut self) {
        // SAFETY: pipelines using the layout keep their own copy of it; no pending work.
        unsafe {
            self.gpu
                .device
                .destroy_descriptor_set_layout(self.raw, self.gpu.callbacks())
        };
    }
}

impl Drop for DescriptorSet {
    fn drop(&mut self) {
        // SAFETY: no pending submission uses the set once its owner drops it.
        unsafe {
            self.gpu
                .device
                .destroy_descriptor_pool(self.pool, self.gpu.callbacks())
        };
    }
}

/// Begins `pass` on `framebuffer` (of size `framebuffer_extent`) over its top-left `extent`
/// with `clears`, and sets the matching viewport and scissor (every pipeline here takes them
/// as dynamic state).
pub(super) fn begin_render_pass(
    gpu: &Gpu,
    cmd: vk::CommandBuffer,
    (pass, framebuffer): (vk::RenderPass, vk::Framebuffer),
    (extent, framebuffer_extent): (vk::Extent2D, vk::Extent2D),
    clears: &[vk::ClearValue],
) {
    assert!(
        extent.width <= framebuffer_extent.width && extent.height <= framebuffer_extent.height,
        "a {}x{} render area in a {}x{} framebuffer",
        extent.width,
        extent.height,
        framebuffer_extent.width,
        framebuffer_extent.height
    );
    let area = vk::Rect2D {
        offset: vk::Offset2D::default(),
        extent,
    };
    let begin = vk::RenderPassBeginInfo::default()
        .render_pass(pass)
        .framebuffer(framebuffer)
        .render_area(area)
        .clear_values(clears);
    let viewport = vk::Viewport {
        x: 0.0,
        y: 0.0,
        width: extent.width as f32,
        height: extent.height as f32,
        min_depth: 0.0,
        max_depth: 1.0,
    };
    // SAFETY: cmd is recording outside any render pass; the framebuffer belongs to `pass`.
    unsafe {
        gpu.device
            .cmd_begin_render_pass(cmd, &begin, vk::SubpassContents::INLINE);
        gpu.device.cmd_set_viewport(cmd, 0, &[viewport]);
        gpu.device.cmd_set_scissor(cmd, 0, &[area]);
    }
}

/// The subpass dependencies of every one-subpass render pass here: ordered after whatever
/// wrote or read the attachments before it, its writes visible to whatever follows.
pub(super) fn external_dependencies() -> [vk::SubpassDependency; 2] {
    let all = vk::PipelineStageFlags::ALL_COMMANDS;
    let graphics = vk::PipelineStageFlags::ALL_GRAPHICS;
    let rw = vk::AccessFlags::MEMORY_READ | vk::AccessFlags::MEMORY_WRITE;
    [
        vk::SubpassDependency::default()
            .src_subpass(vk::SUBPASS_EXTERNAL)
            .dst_subpass(0)
            .src_stage_mask(all)
            .dst_stage_mask(graphics)
            .src_access_mask(rw)
            .dst_access_mask(rw),
        vk::SubpassDependency::default()
            .src_subpass(0)
            .dst_subpass(vk::SUBPASS_EXTERNAL)
            .src_stage_mask(graphics)
            .dst_stage_mask(all)
            .src_access_mask(rw)
            .dst_access_mask(rw),
    ]
}

fn shader_module(gpu: &Gpu, spirv: &[u8]) -> Result<vk::ShaderModule> {
    let words = ash::util::read_spv(&mut std::io::Cursor::new(spirv))?;
    let info = vk::ShaderModuleCreateInfo::default().code(&words);
    // SAFETY: the words are SPIR-V produced by glslc at build time.
    unsafe { gpu.device.create_shader_module(&info, gpu.callbacks()) }
        .map_err(vk_err("vkCreateShaderModule"))
}

fn pipeline_layout(
    gpu: &Gpu,
    sets: &[&DescriptorLayout],
    push_bytes: u32,
    stages: vk::ShaderStageFlags,
) -> Result<vk::PipelineLayout> {
    let raw_sets: Vec<_> = sets.iter().map(|s| s.raw).collect();
    let ranges = [vk::PushConstantRange {
        stage_flags: stages,
        offset: 0,
        size: push_bytes,
    }];
    let info = vk::PipelineLayoutCreateInfo::default()
        .set_layouts(&raw_sets)
        .push_constant_ranges(if push_bytes > 0 { &ranges } else { &[] });
    // SAFETY: valid device and create info.
    unsafe { gpu.device.create_pipeline_layout(&info, gpu.callbacks()) }
        .map_err(vk_err("vkCreatePipelineLayout"))
}

/// A compute pipeline and its layout.
pub struct ComputePipeline {
    gpu: Gpu,
    pub raw: vk::Pipeline,
    pub layout: vk::PipelineLayout,
}

impl ComputePipeline {
    pub fn new(
        gpu: &Gpu,
        spirv: &[u8],
        sets: &[&DescriptorLayout],
        push_bytes: u32,
    ) -> Result<Self> {
        Self::specialized(gpu, spirv, sets, push_bytes, &Specialization::NONE)
    }

    /// A pipeline with the specialization constants `constants` sets (the others keep the
    /// shader's defaults).
    pub fn specialized(
        gpu: &Gpu,
        spirv: &[u8],
        sets: &[&DescriptorLayout],
        push_bytes: u32,
        constants: &Specialization,
    ) -> Result<Self> {
        let layout = pipeline_layout(gpu, sets, push_bytes, vk::ShaderStageFlags::COMPUTE)?;
        let module = match shader_module(gpu, spirv) {
            Ok(m) => m,
            Err(e) => {
                // SAFETY: the layout was just created and is unused.
                unsafe { gpu.device.destroy_pipeline_layout(layout, gpu.callbacks()) };
                return Err(e);
            }
        };
        let (entries, data) = specialization_entries(gpu, constants);
        let specialization = vk::SpecializationInfo::default()
            .map_entries(&entries)
            .data(&data);
        let mut stage = vk::PipelineShaderStageCreateInfo::default()
            .stage(vk::ShaderStageFlags::COMPUTE)
            .module(module)
            .name(c"main")
            .specialization_info(&specialization);
        let subgroup_size = gpu.info().subgroup_size;
        let mut required = vk::PipelineShaderStageRequiredSubgroupSizeCreateInfo::default()
            .required_subgroup_size(subgroup_size);
        // The bin rasters' workgroups (RASTER_GROUP_SIZE invocations) hold tiles of one
        // subgroup each: a driver free to split a workgroup into partial subgroups (lavapipe
        // does, at 32 lanes) would split tiles. Held to whole subgroups of the device's size
        // where it can be (`DeviceInfo::full_subgroups`; else tiles are a row: see
        // `methods::bins::features::tile_shift`).
        let group = constants.word(RASTER_GROUP_SIZE);
        if gpu.info().full_subgroups && group.is_some_and(|g| g % subgroup_size == 0) {
            stage = stage
                .flags(vk::PipelineShaderStageCreateFlags::REQUIRE_FULL_SUBGROUPS)
                .push_next(&mut required);
        }
        let info = [vk::ComputePipelineCreateInfo::default()
            .stage(stage)
            .layout(layout)];
        // SAFETY: valid module and layout.
        let created = gpu.with_pipeline_cache(|cache| unsafe {
            gpu.device
                .create_compute_pipelines(cache, &info, gpu.callbacks())
        });
        // SAFETY: the module is no longer needed once the pipeline exists (or failed).
        unsafe { gpu.device.destroy_shader_module(module, gpu.callbacks()) };
        match created {
            Ok(p) => {
                gpu.count_pipeline();
                Ok(Self {
                    gpu: gpu.clone(),
                    raw: p[0],
                    layout,
                })
            }
            Err((_, e)) => {
                // SAFETY: unused layout.
                unsafe { gpu.device.destroy_pipeline_layout(layout, gpu.callbacks()) };
                Err(vk_err("vkCreateComputePipelines")(e))
            }
        }
    }

    /// Binds the pipeline and its sets, pushes constants and dispatches.
    pub fn dispatch(
        &self,
        cmd: vk::CommandBuffer,
        sets: &[vk::DescriptorSet],
        push: &[u8],
        groups: [u32; 3],
    ) {
        self.bind(cmd, sets, push);
        self.gpu.count_dispatch();
        // SAFETY: cmd is recording outside a render pass with this pipeline bound.
        unsafe {
            self.gpu
                .device
                .cmd_dispatch(cmd, groups[0], groups[1], groups[2])
        };
    }

    /// Dispatches once on translucid's own device and waits, with what the shader wrote
    /// visible to the host on return: GPU unit tests and device probes that read results.
    pub fn dispatch_and_wait(
        &self,
        sets: &[vk::DescriptorSet],
        push: &[u8],
        groups: [u32; 3],
    ) -> Result<()> {
        self.gpu.submit_and_wait(|cmd| {
            self.dispatch(cmd, sets, push, groups);
            super::memory_barrier(&self.gpu, cmd, super::COMPUTE_WRITE, super::HOST_READ);
            Ok(())
        })
    }

    /// Dispatches as many workgroups as the `VkDispatchIndirectCommand` at `offset` in `args`
    /// says when the command runs.
    pub fn dispatch_indirect(
        &self,
        cmd: vk::CommandBuffer,
        sets: &[vk::DescriptorSet],
        push: &[u8],
        args: &Buffer,
        offset: u64,
    ) {
        self.bind(cmd, sets, push);
        self.gpu.count_dispatch();
        // SAFETY: as for dispatch; args was made with INDIRECT_BUFFER usage and holds the
        // command at offset (a multiple of 4).
        unsafe { self.gpu.device.cmd_dispatch_indirect(cmd, args.raw, offset) };
    }

    fn bind(&self, cmd: vk::CommandBuffer, sets: &[vk::DescriptorSet], push: &[u8]) {
        // SAFETY: cmd is recording outside a render pass; sets match the layout.
        unsafe {
            let d = &self.gpu.device;
            d.cmd_bind_pipeline(cmd, vk::PipelineBindPoint::COMPUTE, self.raw);
            if !sets.is_empty() {
                d.cmd_bind_descriptor_sets(
                    cmd,
                    vk::PipelineBindPoint::COMPUTE,
                    self.layout,
                    0,
                    sets,
                    &[],
                );
            }
            if !push.is_empty() {
                d.cmd_push_constants(cmd, self.layout, vk::ShaderStageFlags::COMPUTE, 0, push);
            }
        }
    }
}

impl Drop for ComputePipeline {
    fn drop(&mut self) {
        // SAFETY: no pending work uses the pipeline.
        unsafe {
            self.gpu
                .device
                .destroy_pipeline(self.raw, self.gpu.callbacks());
            self.gpu
                .device
                .destroy_pipeline_layout(self.layout, self.gpu.callbacks());
        }
    }
}

/// How a graphics pipeline blends into its single colour attachment.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Blend {
    /// Overwrite.
    None,
    /// `dst = src0 + src1 ⊙ dst` per channel: back-to-front compositing of premultiplied
    /// radiance (output 0) with per-channel transmittance (output 1, dual-source).
    PremultipliedTransmittance,
    /// `dst = src + dst`: order-independent sums.
    Add,
    /// `dst = max(src, dst)`.
    Max,
    /// `dst = src ⊙ dst`: order-independent products.
    Multiply,
    /// `dst.rgb += dst.a · src.rgb`, `dst.a *= src.a`: front-to-back compositing in the
    /// order fragments arrive (premultiplied radiance under what is there, transmittance in
    /// alpha), cleared to (0, 0, 0, 1).
    Under,
}

impl Blend {
    fn attachment_state(self) -> vk::PipelineColorBlendAttachmentState {
        let state = vk::PipelineColorBlendAttachmentState::default()
            .color_write_mask(vk::ColorComponentFlags::RGBA);
        let both = |src, dst, op| {
            state
                .blend_enable(true)
                .src_color_blend_factor(src)
                .dst_color_blend_factor(dst)
                .color_blend_op(op)
                .src_alpha_blend_factor(src)
                .dst_alpha_blend_factor(dst)
                .alpha_blend_op(op)
        };
        match self {
            Self::None => state,
            Self::PremultipliedTransmittance => state
                .blend_enable(true)
                .src_color_blend_factor(vk::BlendFactor::ONE)
                .dst_color_blend_factor(vk::BlendFactor::SRC1_COLOR)
                .color_blend_op(vk::BlendOp::ADD)
                .src_alpha_blend_factor(vk::BlendFactor::ZERO)
                .dst_alpha_blend_factor(vk::BlendFactor::ONE)
                .alpha_blend_op(vk::BlendOp::ADD),
            Self::Add => both(vk::BlendFactor::ONE, vk::BlendFactor::ONE, vk::BlendOp::ADD),
            // Factors are ignored by MAX.
            Self::Max => both(vk::BlendFactor::ONE, vk::BlendFactor::ONE, vk::BlendOp::MAX),
            Self::Multiply => both(
                vk::BlendFactor::ZERO,
                vk::BlendFactor::SRC_COLOR,
                vk::BlendOp::ADD,
            ),
            Self::Under => state
                .blend_enable(true)
                .src_color_blend_factor(vk::BlendFactor::DST_ALPHA)
                .dst_color_blend_factor(vk::BlendFactor::ONE)
                .color_blend_op(vk::BlendOp::ADD)
                .src_alpha_blend_factor(vk::BlendFactor::ZERO)
                .dst_alpha_blend_factor(vk::BlendFactor::SRC_ALPHA)
                .alpha_blend_op(vk::BlendOp::ADD),
        }
    }
}

/// How a pipeline tests and writes depth.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum DepthMode {
    /// No depth test (the pass may still have a depth attachment).
    Off,
    /// Test LESS; write when `true`.
    Less(bool),
    /// Test GREATER (depth growing towards the eye, reversed-Z); write when `true`.
    Greater(bool),
    /// Always pass and write (a full-screen pass writing gl_FragDepth).
    WriteAlways,
}

/// What [`GraphicsPipeline::with_state`] varies beyond [`GraphicsPipelineDesc`]: one blend
/// per colour attachment, the depth mode, the specialization constants (every stage's), and
/// whether there is vertex input at all (full-screen passes have none). The desc's `blend` and `depth_write` are ignored.
#[derive(Clone, Copy)]
pub struct PipelineState<'a> {
    pub blends: &'a [Blend],
    pub depth: DepthMode,
    pub constants: &'a Specialization,
    pub vertex_input: bool,
}

/// Everything a graphics pipeline of this crate varies in.
pub struct GraphicsPipelineDesc<'a> {
    pub vertex: &'a [u8],
    /// A geometry stage between the vertex and fragment stages, if any.
    pub geometry: Option<&'a [u8]>,
    pub fragment: &'a [u8],
    /// Bytes per vertex, and (location, format, offset) of each attribute.
    pub vertex_stride: u32,
    pub attributes: &'a [(u32, vk::Format, u32)],
    pub cull_back: bool,
    pub depth_write: bool,
    pub blend: Blend,
    pub render_pass: vk::RenderPass,
    pub sets: &'a [&'a DescriptorLayout],
    pub push_bytes: u32,
}

/// A graphics pipeline as the device knows it (see `pipeline_cache.rs`): its shaders, state,
/// descriptor layouts' definitions and its render pass's definition.
#[derive(Clone, Debug, PartialEq, Eq, Hash)]
pub(crate) struct GraphicsKey {
    vertex: (usize, u64),
    geometry: Option<(usize, u64)>,
    fragment: (usize, u64),
    vertex_stride: u32,
    attributes: Vec<(u32, i32, u32)>,
    cull_back: bool,
    blends: Vec<Blend>,
    depth: DepthMode,
    constants: Specialization,
    vertex_input: bool,
    render_pass: Vec<i64>,
    sets: Vec<(Vec<BindingKind>, u32)>,
    push_bytes: u32,
}

/// The graphics pipelines of a device.
pub(crate) type SharedGraphicsPipelines =
    super::pipeline_cache::SharedPipelines<GraphicsKey, GraphicsPipeline>;

/// What makes render passes compatible, as pipeline keys take it: each attachment's format
/// and samples, and the subpass's colour attachments and depth.
pub(crate) fn render_pass_definition(
    attachments: &[vk::AttachmentDescription],
    colours: usize,
    depth: bool,
) -> Vec<i64> {
    let mut words = vec![colours as i64, i64::from(depth)];
    for a in attachments {
        words.push(i64::from(a.format.as_raw()));
        words.push(i64::from(a.samples.as_raw()));
    }
    words
}

impl Gpu {
    /// Notes `render_pass`'s definition, so that pipelines made for it are shared with the
    /// passes it is compatible with.
    pub(crate) fn note_render_pass(&self, render_pass: vk::RenderPass, definition: Vec<i64>) {
        let mut passes = self.render_passes.lock().unwrap_or_else(|e| e.into_inner());
        passes.insert(render_pass, definition);
    }

    /// Forgets `render_pass`, about to be destroyed.
    pub(crate) fn forget_render_pass(&self, render_pass: vk::RenderPass) {
        let mut passes = self.render_passes.lock().unwrap_or_else(|e| e.into_inner());
        passes.remove(&render_pass);
    }
}

/// A graphics pipeline (dynamic viewport and scissor) and its layout.
pub struct GraphicsPipeline {
    gpu: Gpu,
    pub raw: vk::Pipeline,
    pub layout: vk::PipelineLayout,
}

impl GraphicsPipeline {
    pub fn new(gpu: &Gpu, desc: &GraphicsPipelineDesc<'_>) -> Result<Self> {
        Self::with_state(
            gpu,
            desc,
            &PipelineState {
                blends: &[desc.blend],
                depth: DepthMode::Less(desc.depth_write),
                constants: &Specialization::NONE,
                vertex_input: true,
            },
        )
    }

    /// Like [`Self::with_state`], but shared: a renderer on the same device holding a pipeline
    /// made from the same shaders and state, for a compatible render pass and identically
    /// defined descriptor layouts, hands it over instead of a new one being compiled.
    pub fn shared(
        gpu: &Gpu,
        desc: &GraphicsPipelineDesc<'_>,
        state: &PipelineState<'_>,
    ) -> Result<Arc<Self>> {
        let pass = {
            let passes = gpu.render_passes.lock().unwrap_or_else(|e| e.into_inner());
            passes.get(&desc.render_pass).cloned()
        };
        let Some(render_pass) = pass else {
            return Ok(Arc::new(Self::with_state(gpu, desc, state)?));
        };
        use super::pipeline_cache::{layout_definitions, spirv_hash};
        let key = GraphicsKey {
            vertex: (desc.vertex.len(), spirv_hash(desc.vertex)),
            geometry: desc.geometry.map(|g| (g.len(), spirv_hash(g))),
            fragment: (desc.fragment.len(), spirv_hash(desc.fragment)),
            vertex_stride: desc.vertex_stride,
            attributes: desc
                .attributes
                .iter()
                .map(|&(l, f, o)| (l, f.as_raw(), o))
                .collect(),
            cull_back: desc.cull_back,
            blends: state.blends.to_vec(),
            depth: state.depth,
            constants: state.constants.clone(),
            vertex_input: state.vertex_input,
            render_pass,
            sets: layout_definitions(desc.sets),
            push_bytes: desc.push_bytes,
        };
        if let Some(p) = gpu.graphics_pipelines.get(&key) {
            return Ok(p);
        }
        let p = Arc::new(Self::with_state(gpu, desc, state)?);
        gpu.graphics_pipelines.insert(key, &p);
        Ok(p)
    }

    /// A pipeline with several colour attachments, another depth mode, specialization
    /// constants or no vertex input.
    pub fn with_state(
        gpu: &Gpu,
        desc: &GraphicsPipelineDesc<'_>,
        state: &PipelineState<'_>,
    ) -> Result<Self> {
        let stages_flags = vk::ShaderStageFlags::VERTEX | vk::ShaderStageFlags::FRAGMENT;
        let layout = pipeline_layout(gpu, desc.sets, desc.push_bytes, stages_flags)?;
        let mut sources = vec![(vk::ShaderStageFlags::VERTEX, desc.vertex)];
        if let Some(geometry) = desc.geometry {
            sources.push((vk::ShaderStageFlags::GEOMETRY, geometry));
        }
        sources.push((vk::ShaderStageFlags::FRAGMENT, desc.fragment));
        let destroy_modules = |modules: &[vk::ShaderModule]| {
            for &m in modules {
                // SAFETY: modules are not needed once the pipeline is made (or not).
                unsafe { gpu.device.destroy_shader_module(m, gpu.callbacks()) };
            }
        };
        let mut modules = Vec::with_capacity(sources.len());
        for (_, spirv) in &sources {
            match shader_module(gpu, spirv) {
                Ok(m) => modules.push(m),
                Err(e) => {
                    destroy_modules(&modules);
                    // SAFETY: unused layout.
                    unsafe { gpu.device.destroy_pipeline_layout(layout, gpu.callbacks()) };
                    return Err(e);
                }
            }
        }
        let (entries, data) = specialization_entries(gpu, state.constants);
        let specialization = vk::SpecializationInfo::default()
            .map_entries(&entries)
            .data(&data);
        let stages: Vec<_> = sources
            .iter()
            .zip(&modules)
            .map(|(&(stage, _), &module)| {
                vk::PipelineShaderStageCreateInfo::default()
                    .stage(stage)
                    .module(module)
                    .name(c"main")
                    .specialization_info(&specialization)
            })
            .collect();
        let bindings = [vk::VertexInputBindingDescription {
            binding: 0,
            stride: desc.vertex_stride,
            input_rate: vk::VertexInputRate::VERTEX,
        }];
        let attributes: Vec<_> = desc
            .attributes
            .iter()
            .map(
                |&(location, format, offset)| vk::VertexInputAttributeDescription {
                    location,
                    binding: 0,
                    format,
                    offset,
                },
            )
            .collect();
        let vertex_input = if state.vertex_input {
            vk::PipelineVertexInputStateCreateInfo::default()
                .vertex_binding_descriptions(&bindings)
                .vertex_attribute_descriptions(&attributes)
        } else {
            vk::PipelineVertexInputStateCreateInfo::default()
        };
        let assembly = vk::PipelineInputAssemblyStateCreateInfo::default()
            .topology(vk::PrimitiveTopology::TRIANGLE_LIST);
        let viewport = vk::PipelineViewportStateCreateInfo::default()
            .viewport_count(1)
            .scissor_count(1);
        let raster = vk::PipelineRasterizationStateCreateInfo::default()
            .polygon_mode(vk::PolygonMode::FILL)
            .cull_mode(if desc.cull_back {
                vk::CullModeFlags::BACK
            } else {
                vk::CullModeFlags::NONE
            })
            .front_face(vk::FrontFace::COUNTER_CLOCKWISE)
            .line_width(1.0);
        let multisample = vk::PipelineMultisampleStateCreateInfo::default()
            .rasterization_samples(vk::SampleCountFlags::TYPE_1);
        let (test, write, compare) = match state.depth {
            DepthMode::Off => (false, false, vk::CompareOp::ALWAYS),
            DepthMode::Less(write) => (true, write, vk::CompareOp::LESS),
            DepthMode::Greater(write) => (true, write, vk::CompareOp::GREATER),
            DepthMode::WriteAlways => (true, true, vk::CompareOp::ALWAYS),
        };
        let depth = vk::PipelineDepthStencilStateCreateInfo::default()
            .depth_test_enable(test)
            .depth_write_enable(write)
            .depth_compare_op(compare);
        let attachments: Vec<_> = state.blends.iter().map(|b| b.attachment_state()).collect();
        let blend = vk::PipelineColorBlendStateCreateInfo::default().attachments(&attachments);
        let dynamic_states = [vk::DynamicState::VIEWPORT, vk::DynamicState::SCISSOR];
        let dynamic = vk::PipelineDynamicStateCreateInfo::default().dynamic_states(&dynamic_states);
        let info = [vk::GraphicsPipelineCreateInfo::default()
            .stages(&stages)
            .vertex_input_state(&vertex_input)
            .input_assembly_state(&assembly)
            .viewport_state(&viewport)
            .rasterization_state(&raster)
            .multisample_state(&multisample)
            .depth_stencil_state(&depth)
            .color_blend_state(&blend)
            .dynamic_state(&dynamic)
            .layout(layout)
            .render_pass(desc.render_pass)
            .subpass(0)];
        // SAFETY: every pointee lives until the call returns.
        let created = gpu.with_pipeline_cache(|cache| unsafe {
            gpu.device
                .create_graphics_pipelines(cache, &info, gpu.callbacks())
        });
        destroy_modules(&modules);
        match created {
            Ok(p) => {
                gpu.count_pipeline();
                Ok(Self {
                    gpu: gpu.clone(),
                    raw: p[0],
                    layout,
                })
            }
            Err((_, e)) => {
                // SAFETY: unused layout.
                unsafe { gpu.device.destroy_pipeline_layout(layout, gpu.callbacks()) };
                Err(vk_err("vkCreateGraphicsPipelines")(e))
            }
        }
    }
}

impl Drop for GraphicsPipeline {
    fn drop(&mut self) {
        // SAFETY: no pending work uses the pipeline.
        unsafe {
            self.gpu
                .device
                .destroy_pipeline(self.raw, self.gpu.callbacks());
            self.gpu
                .device
                .destroy_pipeline_layout(self.layout, self.gpu.callbacks());
        }
    }
}

/// A sampler object.
pub struct Sampler {
    gpu: Gpu,
    pub raw: vk::Sampler,
}

impl Sampler {
    /// The hardware sampler of a texture's [`scene::Sampler`], by the rules
    /// `scene::Texture::sample` states: without mipmaps `maxLod` is 0.25 (as the Vulkan spec
    /// advises for GL's non-mipmapped filters), so that the level of detail still tells
    /// magnification (λ ≤ 0) from minification, and only level 0 is read.
    pub fn for_texture(gpu: &Gpu, sampler: &scene::Sampler) -> Result<Self> {
        let filter = |f| match f {
            scene::Filter::Nearest => vk::Filter::NEAREST,
            scene::Filter::Linear => vk::Filter::LINEAR,
        };
        let wrap = |w| match w {
            scene::Wrap::Repeat => vk::SamplerAddressMode::REPEAT,
            scene::Wrap::ClampToEdge => vk::SamplerAddressMode::CLAMP_TO_EDGE,
            scene::Wrap::MirroredRepeat => vk::SamplerAddressMode::MIRRORED_REPEAT,
        };
        let (mipmap_mode, max_lod) = match sampler.mip_filter {
            scene::MipFilter::None => (vk::SamplerMipmapMode::NEAREST, 0.25),
            scene::MipFilter::Nearest => (vk::SamplerMipmapMode::NEAREST, vk::LOD_CLAMP_NONE),
            scene::MipFilter::Linear => (vk::SamplerMipmapMode::LINEAR, vk::LOD_CLAMP_NONE),
        };
        let info = vk::SamplerCreateInfo::default()
            .mag_filter(filter(sampler.mag_filter))
            .min_filter(filter(sampler.min_filter))
            .mipmap_mode(mipmap_mode)
            .address_mode_u(wrap(sampler.wrap_s))
            .address_mode_v(wrap(sampler.wrap_t))
            .address_mode_w(vk::SamplerAddressMode::REPEAT)
            .min_lod(0.0)
            .max_lod(max_lod);
        // SAFETY: valid device and create info.
        let raw = unsafe { gpu.device.create_sampler(&info, gpu.callbacks()) }
            .map_err(vk_err("vkCreateSampler"))?;
        Ok(Self {
            gpu: gpu.clone(),
            raw,
        })
    }
}

impl Sampler {
    /// Nearest filtering, clamped: for `texelFetch`-style reads of depth and colour.
    pub fn nearest_clamp(gpu: &Gpu) -> Result<Self> {
        let info = vk::SamplerCreateInfo::default()
            .mag_filter(vk::Filter::NEAREST)
            .min_filter(vk::Filter::NEAREST)
            .mipmap_mode(vk::SamplerMipmapMode::NEAREST)
            .address_mode_u(vk::SamplerAddressMode::CLAMP_TO_EDGE)
            .address_mode_v(vk::SamplerAddressMode::CLAMP_TO_EDGE)
            .address_mode_w(vk::SamplerAddressMode::CLAMP_TO_EDGE);
        // SAFETY: valid device and create info.
        let raw = unsafe { gpu.device.create_sampler(&info, gpu.callbacks()) }
            .map_err(vk_err("vkCreateSampler"))?;
        Ok(Self {
            gpu: gpu.clone(),
            raw,
        })
    }
}

impl Drop for Sampler {
    fn drop(&mut self) {
        // SAFETY: no pending work uses the sampler.
        unsafe {
            self.gpu
                .device
                .destroy_sampler(self.raw, self.gpu.callbacks())
        };
    }
}

/// A render pass with one colour and one depth attachment, and a framebuffer for it.
pub struct RenderTarget {
    gpu: Gpu,
    pub render_pass: vk::RenderPass,
    pub framebuffer: vk::Framebuffer,
    pub extent: vk::Extent2D,
}

/// How a [`RenderTarget`] treats its attachments.
pub struct RenderTargetDesc {
    pub colour_format: vk::Format,
    pub depth_format: vk::Format,
    /// Clear (true) or load (false) the attachments at the start.
    pub clear: bool,
    pub store_depth: bool,
    /// Layouts the attachments are in before (when loading) and after the pass.
    pub colour_layouts: (vk::ImageLayout, vk::ImageLayout),
    pub depth_layouts: (vk::ImageLayout, vk::ImageLayout),
}

impl RenderTarget {
    pub fn new(
        gpu: &Gpu,
        desc: &RenderTargetDesc,
        colour: &super::GpuImage,
        depth: &super::GpuImage,
    ) -> Result<Self> {
        let (load, initial_c, initial_d) = if desc.clear {
            (
                vk::AttachmentLoadOp::CLEAR,
                vk::ImageLayout::UNDEFINED,
                vk::ImageLayout::UNDEFINED,
            )
        } else {
            (
                vk::AttachmentLoadOp::LOAD,
                desc.colour_layouts.0,
                desc.depth_layouts.0,
            )
        };
        let attachments = [
            vk::AttachmentDescription::default()
                .format(desc.colour_format)
                .samples(vk::SampleCountFlags::TYPE_1)
                .load_op(load)
                .store_op(vk::AttachmentStoreOp::STORE)
                .initial_layout(initial_c)
                .final_layout(desc.colour_layouts.1),
            vk::AttachmentDescription::default()
                .format(desc.depth_format)
                .samples(vk::SampleCountFlags::TYPE_1)
                .load_op(load)
                .store_op(if desc.store_depth {
                    vk::AttachmentStoreOp::STORE
                } else {
                    vk::AttachmentStoreOp::DONT_CARE
                })
                .stencil_load_op(vk::AttachmentLoadOp::DONT_CARE)
                .stencil_store_op(vk::AttachmentStoreOp::DONT_CARE)
                .initial_layout(initial_d)
                .final_layout(desc.depth_layouts.1),
        ];
        let colour_ref = [vk::AttachmentReference {
            attachment: 0,
            layout: vk::ImageLayout::COLOR_ATTACHMENT_OPTIMAL,
        }];
        let depth_layout = if desc.store_depth {
            vk::ImageLayout::DEPTH_STENCIL_ATTACHMENT_OPTIMAL
        } else {
            vk::ImageLayout::DEPTH_STENCIL_READ_ONLY_OPTIMAL
        };
        let depth_ref = vk::AttachmentReference {
            attachment: 1,
            layout: depth_layout,
        };
        let subpass = [vk::SubpassDescription::default()
            .pipeline_bind_point(vk::PipelineBindPoint::GRAPHICS)
            .color_attachments(&colour_ref)
            .depth_stencil_attachment(&depth_ref)];
        let dependencies = external_dependencies();
        let info = vk::RenderPassCreateInfo::default()
            .attachments(&attachments)
            .subpasses(&subpass)
            .dependencies(&dependencies);
        // SAFETY: valid device; pointees live for the call.
        let render_pass = unsafe { gpu.device.create_render_pass(&info, gpu.callbacks()) }
            .map_err(vk_err("vkCreateRenderPass"))?;
        gpu.note_render_pass(render_pass, render_pass_definition(&attachments, 1, true));
        let views = [colour.view, depth.view];
        let fb_info = vk::FramebufferCreateInfo::default()
            .render_pass(render_pass)
            .attachments(&views)
            .width(colour.extent.width)
            .height(colour.extent.height)
            .layers(1);
        // SAFETY: the views are live and match the pass's formats.
        let framebuffer = match unsafe { gpu.device.create_framebuffer(&fb_info, gpu.callbacks()) }
        {
            Ok(f) => f,
            Err(e) => {
                gpu.forget_render_pass(render_pass);
                // SAFETY: unused render pass.
                unsafe { gpu.device.destroy_render_pass(render_pass, gpu.callbacks()) };
                return Err(vk_err("vkCreateFramebuffer")(e));
            }
        };
        Ok(Self {
            gpu: gpu.clone(),
            render_pass,
            framebuffer,
            extent: colour.extent,
        })
    }

    /// Begins the pass over the top-left `area` of the targets (clearing it to `clear_colour`
    /// and depth 1 when the pass clears) and sets the matching viewport and scissor.
    pub fn begin(&self, cmd: vk::CommandBuffer, area: vk::Extent2D, clear_colour: [f32; 4]) {
        let clears = [
            vk::ClearValue {
                color: vk::ClearColorValue {
                    float32: clear_colour,
                },
            },
            vk::ClearValue {
                depth_stencil: vk::ClearDepthStencilValue {
                    depth: 1.0,
                    stencil: 0,
                },
            },
        ];
        begin_render_pass(
            &self.gpu,
            cmd,
            (self.render_pass, self.framebuffer),
            (area, self.extent),
            &clears,
        );
    }

    pub fn end(&self, cmd: vk::CommandBuffer) {
        // SAFETY: cmd is inside this render pass.
        unsafe { self.gpu.device.cmd_end_render_pass(cmd) };
    }
}

impl Drop for RenderTarget {
    fn drop(&mut self) {
        // SAFETY: no pending work uses them.
        unsafe {
            self.gpu
                .device
                .destroy_framebuffer(self.framebuffer, self.gpu.callbacks());
            self.gpu.forget_render_pass(self.render_pass);
            self.gpu
                .device
                .destroy_render_pass(self.render_pass, self.gpu.callbacks());
        }
    }
}

/// Indexed mesh draws inside a render pass.
impl Gpu {
    /// Binds `vertices` as vertex buffer 0 and `indices` as 32-bit indices.
    pub fn cmd_bind_mesh_buffers(
        &self,
        cmd: vk::CommandBuffer,
        vertices: &Buffer,
        indices: &Buffer,
    ) {
        // SAFETY: cmd is recording; both buffers are alive and were made with vertex and
        // index usage by the caller.
        unsafe {
            self.device
                .cmd_bind_vertex_buffers(cmd, 0, &[vertices.raw], &[0]);
            self.device
                .cmd_bind_index_buffer(cmd, indices.raw, 0, vk::IndexType::UINT32);
        }
    }

    pub fn cmd_bind_graphics_pipeline(&self, cmd: vk::CommandBuffer, pipeline: &GraphicsPipeline) {
        // SAFETY: cmd is recording inside a render pass compatible with the pipeline's.
        unsafe {
            self.device
                .cmd_bind_pipeline(cmd, vk::PipelineBindPoint::GRAPHICS, pipeline.raw)
        };
    }

    /// Pushes `bytes` at offset 0 for the vertex and fragment stages of `pipeline`'s layout.
    pub fn cmd_push_draw_constants(
        &self,
        cmd: vk::CommandBuffer,
        pipeline: &GraphicsPipeline,
        bytes: &[u8],
    ) {
        // SAFETY: cmd is recording; the layout's push-constant range covers `bytes` for both
        // stages (the caller made the pipeline with them).
        unsafe {
            self.device.cmd_push_constants(
                cmd,
                pipeline.layout,
                vk::ShaderStageFlags::VERTEX | vk::ShaderStageFlags::FRAGMENT,
                0,
                bytes,
            )
        };
    }

    /// One instance of `index_count` indices from `first_index`, offset by `vertex_offset`.
    pub fn cmd_draw_indexed(
        &self,
        cmd: vk::CommandBuffer,
        index_count: u32,
        first_index: u32,
        vertex_offset: i32,
    ) {
        // SAFETY: cmd is recording inside a render pass with a graphics pipeline and the
        // buffers it reads bound; the caller keeps the range within the bound index buffer.
        unsafe {
            self.device
                .cmd_draw_indexed(cmd, index_count, 1, first_index, vertex_offset, 0)
        };
    }

    /// One indexed draw whose VkDrawIndexedIndirectCommand is at `offset` of `args` (made
    /// with INDIRECT_BUFFER usage), written by the host or by an earlier pass.
    pub fn cmd_draw_indexed_indirect(&self, cmd: vk::CommandBuffer, args: &Buffer, offset: u64) {
        let size = std::mem::size_of::<vk::DrawIndexedIndirectCommand>() as u64;
        assert!(
            offset % 4 == 0 && offset + size <= args.size,
            "indirect draw past {}",
            args.name
        );
        // SAFETY: cmd is recording inside a render pass with a graphics pipeline and the
        // buffers it reads bound; the command lies within args (asserted), and whoever
        // writes it keeps its range within the bound index buffer.
        unsafe {
            self.device
                .cmd_draw_indexed_indirect(cmd, args.raw, offset, 1, size as u32)
        };
    }
}

/// Vulkan's map entries and data for `constants`, a 32-bit word each, with those every
/// pipeline takes from the device's profile. Ids a stage does not declare are ignored.
fn specialization_entries(
    gpu: &Gpu,
    constants: &Specialization,
) -> (Vec<vk::SpecializationMapEntry>, Vec<u8>) {
    let constants = constants
        .clone()
        .with(ROUNDED_DIVISION, gpu.profile() == Profile::Gpu);
    let words = constants.words();
    let entries = (0..words.len() as u32)
        .zip(words)
        .map(|(i, &(id, _))| vk::SpecializationMapEntry {
            constant_id: id,
            offset: i * 4,
            size: 4,
        })
        .collect();
    let data = words.iter().flat_map(|&(_, w)| w.to_ne_bytes()).collect();
    (entries, data)
}
