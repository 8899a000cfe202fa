//! A scene's assets on the GPU, uploaded once: vertices (rewritten in place when a mesh
//! moves), triangle indices, quads, materials, and textures twice over (images with their
//! hardware samplers for the graphics passes, packed texels for the compute rasters'
//! software sampler). Shared (`Arc`) by every renderer made over the same assets, so that a
//! renderer for another size, method or view uploads nothing.

#![deny(unsafe_code)]

use super::texture_records::texture_data;
use super::{MeshRange, SCENE_STORAGE};
use crate::gpu::{
    vk, BindingKind, Buffer, BufferView, DescriptorLayout, DescriptorSet, Gpu, GpuImage, Resource,
    Sampler, ViewedBuffer,
};
use crate::scene::{self, srgb_lut, Mesh, Scene, Texture};
use crate::shader_types::{GpuMaterial, GpuVertex};
use crate::{Error, Result};
use glam::{Vec2, Vec3, Vec4};
use std::sync::Mutex;

const RGBA32UI: vk::Format = vk::Format::R32G32B32A32_UINT;

pub struct ResidentAssets {
    pub vertices: Buffer,
    pub indices: Buffer,
    /// Every mesh's quads with absolute vertex indices (`DrawInfo::first_quad` points here).
    pub quads: Buffer,
    pub materials: Buffer,
    /// Texel views of the vertices, quads and materials, as the compute stages read them.
    pub vertex_view: BufferView,
    pub quad_view: BufferView,
    pub material_view: BufferView,
    /// The software sampler's texture records, every level's texels (RGBA8), and its sRGB
    /// decoding table.
    pub bin_textures: ViewedBuffer,
    pub bin_texels: ViewedBuffer,
    pub srgb: ViewedBuffer,
    textures: Vec<GpuImage>,
    /// The texture sets' samplers, kept alive with them.
    _samplers: Vec<Sampler>,
    /// Set 1 of the mesh pipelines: one base-colour texture.
    pub texture_layout: DescriptorLayout,
    /// One set per texture, then one for a white texture (materials without one).
    pub texture_sets: Vec<DescriptorSet>,
    /// Each mesh's triangles in the index buffer (and its first vertex), and its first quad
    /// in the quad buffer.
    pub ranges: Vec<MeshRange>,
    pub first_quads: Vec<u32>,
    /// Each mesh's vertices and quads, then the materials and textures: what a renderer's
    /// scene is checked against.
    mesh_sizes: Vec<(usize, usize)>,
    counts: [usize; 2],
    /// On the engine's device (which translucid never submits to), the texture uploads the
    /// first frame recorded over these assets carries.
    uploads: Mutex<Uploads>,
}

/// Texture uploads on the engine's device: their staging buffers, kept until the frame that
/// recorded the copies completed.
struct Uploads {
    staging: Vec<Buffer>,
    state: UploadState,
}

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum UploadState {
    /// No frame recorded the copies yet, or the one that did never ran.
    Pending,
    /// Recorded into a frame of the renderer with this id, not yet completed.
    Recorded(u64),
    Done,
}

fn vertices_of(mesh: &Mesh) -> impl Iterator<Item = GpuVertex> + '_ {
    (0..mesh.positions.len()).map(move |i| GpuVertex {
        position: mesh.positions[i].to_array(),
        normal: mesh
            .normals
            .as_ref()
            .map_or(Vec3::ZERO, |n| n[i])
            .to_array(),
        uv: mesh.uvs.as_ref().map_or(Vec2::ZERO, |u| u[i]).to_array(),
        colour: mesh.colours.as_ref().map_or(Vec4::ONE, |c| c[i]).to_array(),
    })
}

/// Each mesh's vertex and quad counts.
fn mesh_sizes(scene: &Scene) -> Vec<(usize, usize)> {
    scene
        .meshes
        .iter()
        .map(|m| (m.positions.len(), m.quads.len()))
        .collect()
}

/// Mesh `mesh`'s vertices as the vertex buffer holds them.
pub(crate) fn gpu_vertices(mesh: &Mesh) -> Vec<GpuVertex> {
    vertices_of(mesh).collect()
}

impl ResidentAssets {
    /// Uploads `scene`'s assets (validated first): on translucid's own device now, on the
    /// engine's with the first frame recorded.
    pub fn new(gpu: &Gpu, scene: &Scene) -> Result<Self> {
        scene.validate()?;
        let mut vertices = Vec::new();
        let mut indices: Vec<u32> = Vec::new();
        let mut quads: Vec<[u32; 4]> = Vec::new();
        let mut ranges = Vec::with_capacity(scene.meshes.len());
        let mut first_quads = Vec::with_capacity(scene.meshes.len());
        let mut quad_total = 0u32;
        for mesh in &scene.meshes {
            let first_index = indices.len() as u32;
            let vertex_offset = vertices.len() as i32;
            vertices.extend(vertices_of(mesh));
            for &q in &mesh.quads {
                indices.extend(Mesh::quad_triangles(q).into_iter().flatten().flatten());
                quads.push(q.map(|i| i + vertex_offset as u32));
            }
            ranges.push(MeshRange {
                first_index,
                index_count: indices.len() as u32 - first_index,
                vertex_offset,
            });
            first_quads.push(quad_total);
            quad_total += mesh.quads.len() as u32;
        }
        let materials: Vec<GpuMaterial> = scene.materials.iter().map(GpuMaterial::new).collect();

        // Moved vertices are copied in by the frame that first draws them.
        let vertices = gpu.create_buffer_with_data(
            "scene vertices",
            vk::BufferUsageFlags::VERTEX_BUFFER
                | vk::BufferUsageFlags::TRANSFER_DST
                | SCENE_STORAGE,
            bytemuck::cast_slice(&vertices),
        )?;
        let indices = gpu.create_buffer_with_data(
            "scene indices",
            vk::BufferUsageFlags::INDEX_BUFFER | SCENE_STORAGE,
            bytemuck::cast_slice(&indices),
        )?;
        let quads = gpu.create_buffer_with_data(
            "scene quads",
            SCENE_STORAGE,
            bytemuck::cast_slice(&quads),
        )?;
        let materials = gpu.create_buffer_with_data(
            "scene materials",
            SCENE_STORAGE,
            bytemuck::cast_slice(&materials),
        )?;

        let white = Texture::new("white", 1, 1, vec![[255; 4]], false);
        let all_textures = || scene.textures.iter().chain(std::iter::once(&white));
        let (textures, staging) = super::create_textures(gpu, all_textures())?;
        // A device of translucid's own uploads now; on the engine's, the first frame does.
        let uploads = if gpu.is_host_device() {
            Uploads {
                staging,
                state: UploadState::Pending,
            }
        } else {
            gpu.submit_and_wait(|cmd| {
                super::record_texture_uploads(gpu, cmd, &textures, &staging);
                Ok(())
            })?;
            Uploads {
                staging: Vec::new(),
                state: UploadState::Done,
            }
        };
        // One hardware sampler for each distinct sampler the textures use.
        let mut samplers: Vec<(scene::Sampler, Sampler)> = Vec::new();
        for t in all_textures() {
            if !samplers.iter().any(|(s, _)| *s == t.sampler) {
                samplers.push((t.sampler, Sampler::for_texture(gpu, &t.sampler)?));
            }
        }
        let sampler_of = |t: &Texture| {
            samplers
                .iter()
                .find(|(s, _)| *s == t.sampler)
                .map_or(vk::Sampler::null(), |(_, made)| made.raw)
        };
        let stages = vk::ShaderStageFlags::VERTEX
            | vk::ShaderStageFlags::FRAGMENT
            | vk::ShaderStageFlags::COMPUTE;
        let texture_layout = DescriptorLayout::new(gpu, &[BindingKind::SampledImages(1)], stages)?;
        let texture_sets = textures
            .iter()
            .zip(all_textures())
            .map(|(image, t)| {
                texture_layout.create_set(&[Resource::Images(&[image.view], sampler_of(t))])
            })
            .collect::<Result<Vec<_>>>()?;

        let (texture_infos, texels) = texture_data(&scene.textures);
        let texel_bytes = texels.len() as u64 * 4;
        if texel_bytes > u64::from(gpu.info().max_storage_buffer_range) {
            return Err(Error::InvalidScene(format!(
                "the scene's textures take {} MB, over this device's {} MB storage-buffer limit",
                texel_bytes >> 20,
                gpu.info().max_storage_buffer_range >> 20
            )));
        }
        Ok(Self {
            vertex_view: gpu.create_buffer_view(&vertices, RGBA32UI)?,
            quad_view: gpu.create_buffer_view(&quads, RGBA32UI)?,
            material_view: gpu.create_buffer_view(&materials, RGBA32UI)?,
            vertices,
            indices,
            quads,
            materials,
            bin_textures: ViewedBuffer::with_data(
                gpu,
                "bin textures",
                bytemuck::cast_slice(&texture_infos),
                RGBA32UI,
            )?,
            bin_texels: ViewedBuffer::with_data(
                gpu,
                "bin texels",
                bytemuck::cast_slice(&texels),
                vk::Format::R32_UINT,
            )?,
            srgb: ViewedBuffer::with_data(
                gpu,
                "sRGB table",
                bytemuck::cast_slice(srgb_lut()),
                vk::Format::R32_SFLOAT,
            )?,
            textures,
            _samplers: samplers.into_iter().map(|(_, made)| made).collect(),
            texture_layout,
            texture_sets,
            ranges,
            first_quads,
            mesh_sizes: mesh_sizes(scene),
            counts: [scene.materials.len(), scene.textures.len()],
            uploads: Mutex::new(uploads),
        })
    }

    /// Checks that `scene` has the assets these were made from: as many meshes, of as many
    /// vertices and quads each, materials and textures.
    pub fn check_scene(&self, scene: &Scene) -> Result<()> {
        let counts = [scene.materials.len(), scene.textures.len()];
        if mesh_sizes(scene) != self.mesh_sizes || counts != self.counts {
            return Err(Error::InvalidScene(format!(
                "the scene ({} meshes, {} materials, {} textures) does not have the assets the \
                 resident ones were made from ({} meshes, {} materials, {} textures, or meshes \
                 of other sizes)",
                scene.meshes.len(),
                counts[0],
                counts[1],
                self.mesh_sizes.len(),
                self.counts[0],
                self.counts[1]
            )));
        }
        Ok(())
    }

    fn uploads(&self) -> std::sync::MutexGuard<'_, Uploads> {
        self.uploads.lock().unwrap_or_else(|e| e.into_inner())
    }

    /// On the engine's device: records the texture uploads into the command buffer of a frame
    /// of renderer `renderer`, unless a frame recorded them already.
    pub fn record_pending_uploads(&self, gpu: &Gpu, cmd: vk::CommandBuffer) {
        let uploads = self.uploads();
        if uploads.state == UploadState::Pending {
            super::record_texture_uploads(gpu, cmd, &self.textures, &uploads.staging);
        }
    }

    /// The frame of renderer `renderer` that recorded the pending uploads was recorded
    /// whole: later frames, of any renderer, need not record them. A recording that failed
    /// leaves them pending.
    pub fn uploads_recorded(&self, renderer: u64) {
        let mut uploads = self.uploads();
        if uploads.state == UploadState::Pending {
            uploads.state = UploadState::Recorded(renderer);
        }
    }

    /// A frame of renderer `renderer` completed: if that renderer recorded the uploads, they
    /// ran (its frames complete in order), and their staging goes.
    pub fn uploads_completed(&self, renderer: u64) {
        let mut uploads = self.uploads();
        if uploads.state == UploadState::Recorded(renderer) {
            uploads.state = UploadState::Done;
            uploads.staging.clear();
        }
    }

    /// Renderer `renderer` is gone without completing the frame that recorded the uploads
    /// (it was abandoned): the next frame recorded over these assets records them again.
    pub fn uploads_lost(&self, renderer: u64) {
        let mut uploads = self.uploads();
        if uploads.state == UploadState::Recorded(renderer) {
            uploads.state = UploadState::Pending;
        }
    }
}
