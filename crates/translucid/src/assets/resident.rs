//! A scene's assets on the GPU, uploaded once: vertices (rewritten in place when a mesh
//! moves), triangle indices, quads, materials, and textures twice over (images with their
//! hardware samplers for the graphics passes, packed texels for the compute rasters'
//! software sampler). Shared (`Arc`) by every renderer made over the same assets, so that a
//! renderer for another size, method or view uploads nothing.
//!
//! Assets added later extend them ([`ResidentAssets::extended`]): the new version appends
//! the new data to the same buffers (which have room to spare) and keeps the textures made
//! before, so that adding a mesh uploads that mesh, not every asset again.
//!
//! Every buffer and image here is device-local, filled by uploads (`gpu::staging`): at once
//! on translucid's own device; on an engine's, by the next frame recorded over any version
//! of the assets, their staging kept until that frame completed.

#![deny(unsafe_code)]

use super::sampled::{SampledTextures, SampledViews};
use super::texture_array::TextureArray;
use super::{MeshRange, SCENE_STORAGE};
use crate::gpu::{
    vk, AppendBuffer, Buffer, BufferView, DescriptorLayout, DescriptorSet, Gpu, GpuImage, Resource,
    Sampler, Upload, Uploads,
};
use crate::interface::methods::BASE_TEXTURE_SET;
use crate::scene::{self, Mesh, Scene, Texture};
use crate::shader_types::{GpuMaterial, GpuVertex};
use crate::{Error, Result};
use glam::{Vec2, Vec3, Vec4};
use std::sync::{Arc, Mutex};

const RGBA32UI: vk::Format = vk::Format::R32G32B32A32_UINT;
const MATERIAL_BYTES: u64 = std::mem::size_of::<GpuMaterial>() as u64;

/// The buffers every version of a context's assets appends to.
struct Buffers {
    vertices: AppendBuffer,
    indices: AppendBuffer,
    /// Every mesh's quads with absolute vertex indices (`DrawInfo::first_quad` points here).
    quads: AppendBuffer,
    materials: AppendBuffer,
    /// Texel views of the vertices and quads, as the compute stages read them.
    vertex_view: BufferView,
    quad_view: BufferView,
    /// The textures as the compute rasters' software sampler reads them, made for the first
    /// renderer whose method has one, holding those transparent draws use.
    sampled: Mutex<Option<SampledTextures>>,
    /// The uploads into these buffers, the textures of every version and the sampled
    /// textures that no frame is known to have run yet (on the engine's device).
    uploads: Uploads,
}

/// A texture's image and the descriptor set that binds it with its sampler.
pub(super) struct ResidentTexture {
    // Declared first so that it is freed before the image its view names.
    set: DescriptorSet,
    sampler: Arc<Sampler>,
    // Kept while the set (whose view names it) lives.
    image: Arc<GpuImage>,
}

impl ResidentTexture {
    /// Its view and sampler, for another set that binds it ([`TextureArray`]).
    pub(super) fn descriptor(&self) -> (vk::ImageView, vk::Sampler) {
        (self.image.view, self.sampler.raw)
    }
}

pub struct ResidentAssets {
    /// The first textures for the rasters that sample in hardware, where the device can
    /// bind them ([`TextureArray::new`]). Declared before the textures it names.
    texture_array: Option<Arc<TextureArray>>,
    buffers: Arc<Buffers>,
    textures: Vec<Arc<ResidentTexture>>,
    /// The same textures on the host, their texels shared with the scene's (not copied):
    /// what the software sampler copies when a transparent draw first uses one. (Renderers
    /// keep their scenes without texels.)
    host_textures: Vec<Texture>,
    /// Bound for materials without a texture.
    white: Arc<ResidentTexture>,
    /// One hardware sampler for each distinct sampler the textures use.
    samplers: Vec<(scene::Sampler, Arc<Sampler>)>,
    /// Set 1 of the mesh pipelines: one base-colour texture.
    pub texture_layout: Arc<DescriptorLayout>,
    /// Each mesh's triangles in the index buffer (and its first vertex), and its first quad
    /// in the quad buffer.
    pub ranges: Vec<MeshRange>,
    pub first_quads: Vec<u32>,
    /// Each mesh's vertices and quads, then the materials and textures: what a renderer's
    /// scene is checked against.
    mesh_sizes: Vec<(usize, usize)>,
    counts: [usize; 2],
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

/// Some meshes and materials in the layout of the assets' buffers: vertices, triangle
/// indices (local to their mesh), quads (with vertex indices from `first_vertex`) and
/// materials.
struct Packed {
    vertices: Vec<GpuVertex>,
    indices: Vec<u32>,
    quads: Vec<[u32; 4]>,
    materials: Vec<GpuMaterial>,
    /// Per mesh: its index range and first vertex (relative to the packed data), its first
    /// quad.
    ranges: Vec<MeshRange>,
    first_quads: Vec<u32>,
}

impl Packed {
    fn new(meshes: &[Mesh], materials: &[scene::Material], first_vertex: u32) -> Self {
        let mut p = Packed {
            vertices: Vec::new(),
            indices: Vec::new(),
            quads: Vec::new(),
            materials: materials.iter().map(GpuMaterial::new).collect(),
            ranges: Vec::with_capacity(meshes.len()),
            first_quads: Vec::with_capacity(meshes.len()),
        };
        for mesh in meshes {
            let first_index = p.indices.len() as u32;
            let vertex_offset = p.vertices.len() as u32;
            p.vertices.extend(vertices_of(mesh));
            p.first_quads.push(p.quads.len() as u32);
            for &q in &mesh.quads {
                p.indices
                    .extend(Mesh::quad_triangles(q).into_iter().flatten().flatten());
                p.quads.push(q.map(|i| i + first_vertex + vertex_offset));
            }
            p.ranges.push(MeshRange {
                first_index,
                index_count: p.indices.len() as u32 - first_index,
                vertex_offset: vertex_offset as i32,
            });
        }
        p
    }
}

/// Room the buffers are made with beyond what they hold first, for assets added later: at
/// least this many bytes, and half as much again. Past it, the assets are uploaded anew
/// with room again, so that a context growing one asset at a time uploads everything a few
/// times (logarithmically often), not every time.
const SPARE_BYTES: u64 = 1 << 20;

fn with_room(bytes: usize) -> u64 {
    let bytes = bytes as u64;
    bytes + (bytes / 2).max(SPARE_BYTES)
}

/// The textures' images (with their sets over `layout` and a sampler from `samplers`,
/// made there when new), and the uploads of their texels.
fn make_textures(
    gpu: &Gpu,
    layout: &DescriptorLayout,
    samplers: &mut Vec<(scene::Sampler, Arc<Sampler>)>,
    textures: &[Texture],
) -> Result<(Vec<Arc<ResidentTexture>>, Vec<Upload>)> {
    let (images, uploads) = super::create_textures(gpu, textures.iter())?;
    let mut made = Vec::with_capacity(textures.len());
    for (image, t) in images.into_iter().zip(textures) {
        let sampler = match samplers.iter().find(|(s, _)| *s == t.sampler) {
            Some((_, sampler)) => sampler.clone(),
            None => {
                let sampler = Arc::new(Sampler::for_texture(gpu, &t.sampler)?);
                samplers.push((t.sampler, sampler.clone()));
                sampler
            }
        };
        let set = layout.create_named_set(&[(
            "u_baseTexture",
            Resource::Images(&[image.view], sampler.raw),
        )])?;
        made.push(Arc::new(ResidentTexture {
            set,
            sampler,
            image,
        }));
    }
    Ok((made, uploads))
}

impl ResidentAssets {
    /// Uploads `scene`'s assets (validated first): on translucid's own device now, on the
    /// engine's with the first frame recorded.
    pub fn new(gpu: &Gpu, scene: &Scene) -> Result<Self> {
        scene.validate()?;
        let packed = Packed::new(&scene.meshes, &scene.materials, 0);
        let mut uploads = Vec::new();
        let mut append = |name: &str, usage, data: &[u8], format| {
            let (buffer, upload) =
                AppendBuffer::new(gpu, name, usage, with_room(data.len()), format, data)?;
            uploads.push(upload);
            Ok::<_, Error>(buffer)
        };
        let vertices = append(
            "scene vertices",
            vk::BufferUsageFlags::VERTEX_BUFFER
                | vk::BufferUsageFlags::TRANSFER_DST
                | SCENE_STORAGE,
            bytemuck::cast_slice(&packed.vertices),
            None,
        )?;
        let quads = append(
            "scene quads",
            SCENE_STORAGE,
            bytemuck::cast_slice(&packed.quads),
            None,
        )?;
        let indices = append(
            "scene indices",
            vk::BufferUsageFlags::INDEX_BUFFER | SCENE_STORAGE,
            bytemuck::cast_slice(&packed.indices),
            None,
        )?;
        let materials = append(
            "scene materials",
            SCENE_STORAGE,
            bytemuck::cast_slice(&packed.materials),
            Some(RGBA32UI),
        )?;
        let buffers = Buffers {
            vertex_view: gpu.create_buffer_view(vertices.buffer(), RGBA32UI)?,
            quad_view: gpu.create_buffer_view(quads.buffer(), RGBA32UI)?,
            vertices,
            quads,
            indices,
            materials,
            sampled: Mutex::new(None),
            uploads: Uploads::default(),
        };
        let stages = vk::ShaderStageFlags::VERTEX
            | vk::ShaderStageFlags::FRAGMENT
            | vk::ShaderStageFlags::COMPUTE;
        let texture_layout = Arc::new(DescriptorLayout::declared(gpu, &BASE_TEXTURE_SET, stages)?);
        let mut samplers = Vec::new();
        let white = Texture::new("white", 1, 1, vec![[255; 4]], false);
        let (mut white, white_upload) =
            make_textures(gpu, &texture_layout, &mut samplers, &[white])?;
        let (textures, texture_uploads) =
            make_textures(gpu, &texture_layout, &mut samplers, &scene.textures)?;
        uploads.extend(white_upload);
        uploads.extend(texture_uploads);
        buffers.uploads.submit(gpu, uploads)?;
        let white = white
            .pop()
            .ok_or_else(|| Error::Internal("no white texture made".into()))?;
        Ok(Self {
            texture_array: TextureArray::new(gpu, &textures, &white)?.map(Arc::new),
            buffers: Arc::new(buffers),
            textures,
            host_textures: scene.textures.clone(),
            white,
            samplers,
            texture_layout,
            ranges: packed.ranges,
            first_quads: packed.first_quads,
            mesh_sizes: mesh_sizes(scene),
            counts: [scene.materials.len(), scene.textures.len()],
        })
    }

    /// These assets and those `scene` adds after them (its first meshes, materials and
    /// textures being these ones), appended to the same buffers: only the new ones are
    /// uploaded. `None` when the buffers have no room left for them (upload `scene` anew,
    /// with [`Self::new`]). The frames recorded over these assets stay right; on the
    /// engine's device the next frame recorded over either version carries the uploads.
    pub fn extended(&self, gpu: &Gpu, scene: &Scene) -> Result<Option<Self>> {
        scene.validate()?;
        let [materials, textures] = self.counts;
        let meshes = self.mesh_sizes.len();
        let sizes = mesh_sizes(scene);
        if sizes.len() < meshes
            || sizes[..meshes] != self.mesh_sizes[..]
            || scene.materials.len() < materials
            || scene.textures.len() < textures
        {
            return Err(Error::InvalidArgument(
                "the scene does not start with the assets it extends".into(),
            ));
        }
        let b = &self.buffers;
        let vertex_stride = std::mem::size_of::<GpuVertex>() as u64;
        // The next free vertex, quad and texel: appends land there or later.
        let first_vertex = b.vertices.used().div_ceil(vertex_stride);
        let packed = Packed::new(
            &scene.meshes[meshes..],
            &scene.materials[materials..],
            first_vertex as u32,
        );
        // (Room reserved for data that then does not fit with the rest is never read.)
        let mut uploads = Vec::new();
        let mut at = |buffer: &AppendBuffer, data: &[u8], align: u64| {
            Ok::<_, Error>(buffer.append(gpu, data, align)?.map(|(at, upload)| {
                uploads.push(upload);
                at
            }))
        };
        let Some(vertex_at) = at(
            &b.vertices,
            bytemuck::cast_slice(&packed.vertices),
            vertex_stride,
        )?
        else {
            return Ok(None);
        };
        let Some(index_at) = at(&b.indices, bytemuck::cast_slice(&packed.indices), 4)? else {
            return Ok(None);
        };
        let Some(quad_at) = at(&b.quads, bytemuck::cast_slice(&packed.quads), 16)? else {
            return Ok(None);
        };
        // Materials are found by their index: they follow the ones before without a gap.
        let material_at = materials as u64 * MATERIAL_BYTES;
        if vertex_at != first_vertex * vertex_stride
            || b.materials.used() != material_at
            || at(
                &b.materials,
                bytemuck::cast_slice(&packed.materials),
                MATERIAL_BYTES,
            )? != Some(material_at)
        {
            return Ok(None);
        }
        // (The software sampler's copies are made as frames first use the new textures.)
        let mut samplers = self.samplers.clone();
        let (made, texture_uploads) = make_textures(
            gpu,
            &self.texture_layout,
            &mut samplers,
            &scene.textures[textures..],
        )?;
        uploads.extend(texture_uploads);
        let mut all_textures = self.textures.clone();
        all_textures.extend(made);
        // Shared by every version: uploads a frame over an earlier version carried and that
        // may yet be abandoned stay queued until it completes.
        b.uploads.submit(gpu, uploads)?;
        let first_index = (index_at / 4) as u32;
        let first_quad = (quad_at / 16) as u32;
        let mut ranges = self.ranges.clone();
        ranges.extend(packed.ranges.iter().map(|r| MeshRange {
            first_index: r.first_index + first_index,
            index_count: r.index_count,
            vertex_offset: r.vertex_offset + first_vertex as i32,
        }));
        let mut first_quads = self.first_quads.clone();
        first_quads.extend(packed.first_quads.iter().map(|q| q + first_quad));
        Ok(Some(Self {
            texture_array: TextureArray::new(gpu, &all_textures, &self.white)?.map(Arc::new),
            buffers: self.buffers.clone(),
            textures: all_textures,
            host_textures: scene.textures.clone(),
            white: self.white.clone(),
            samplers,
            texture_layout: self.texture_layout.clone(),
            ranges,
            first_quads,
            mesh_sizes: sizes,
            counts: [scene.materials.len(), scene.textures.len()],
        }))
    }

    /// Whether these assets are `earlier` ones extended ([`Self::extended`]): the same
    /// buffers, with the same assets first.
    pub fn extends(&self, earlier: &Self) -> bool {
        Arc::ptr_eq(&self.buffers, &earlier.buffers)
            && self.mesh_sizes.starts_with(&earlier.mesh_sizes)
            && self.counts[0] >= earlier.counts[0]
            && self.counts[1] >= earlier.counts[1]
    }

    pub fn vertices(&self) -> &Buffer {
        self.buffers.vertices.buffer()
    }

    pub fn indices(&self) -> &Buffer {
        self.buffers.indices.buffer()
    }

    pub fn materials(&self) -> &Buffer {
        self.buffers.materials.buffer()
    }

    /// Texel views of the vertices, quads and materials, as the compute stages bind them.
    pub fn texel_views(&self) -> [vk::BufferView; 3] {
        let b = &self.buffers;
        [
            b.vertex_view.raw,
            b.quad_view.raw,
            b.materials.view().map_or(vk::BufferView::null(), |v| v.raw),
        ]
    }

    /// The textures as the software sampler reads them, holding every texture `scene`'s
    /// transparent draws use (copied now when they were not), shared by every renderer over
    /// these assets. `scene` has these assets, or more ([`Self::extended`]).
    pub fn sampled_views(&self, gpu: &Gpu, scene: &Scene) -> Result<SampledViews> {
        let mut sampled = self
            .buffers
            .sampled
            .lock()
            .unwrap_or_else(|e| e.into_inner());
        let sampled = match sampled.as_mut() {
            Some(s) => {
                s.hold_used(gpu, &self.buffers.uploads, &self.host_textures, scene)?;
                s
            }
            None => sampled.insert(SampledTextures::new(
                gpu,
                &self.buffers.uploads,
                &self.host_textures,
                scene,
            )?),
        };
        Ok(sampled.views())
    }

    /// The first textures in one set, where the device can bind them so
    /// ([`TextureArray::new`]).
    pub fn texture_array(&self) -> Option<&Arc<TextureArray>> {
        self.texture_array.as_ref()
    }

    /// The set binding texture `index`, or the white texture for `index` = the number of
    /// textures.
    pub fn texture_set(&self, index: usize) -> vk::DescriptorSet {
        self.textures.get(index).unwrap_or(&self.white).set.raw
    }

    /// Checks that `scene` has the assets these were made from: as many meshes, of as many
    /// vertices and quads each, materials and textures.
    pub fn check_scene(&self, scene: &Scene) -> Result<()> {
        let counts = [scene.materials.len(), scene.textures.len()];
        if mesh_sizes(scene) != self.mesh_sizes || counts != self.counts {
            return Err(Error::InvalidArgument(format!(
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

    /// On the engine's device: records into frame `frame` of recorder `by` (a renderer's
    /// scene) the uploads no frame carries (`gpu::Uploads::record_pending`).
    pub fn record_pending_uploads(&self, gpu: &Gpu, cmd: vk::CommandBuffer, by: u64, frame: u64) {
        self.buffers.uploads.record_pending(gpu, cmd, by, frame);
    }

    /// Recorder `by`'s frames up to `frame` completed: the uploads they carried ran, and
    /// their staging goes.
    pub fn uploads_completed(&self, by: u64, frame: u64) {
        self.buffers.uploads.completed(by, frame);
    }

    /// Recorder `by`'s frames after `frame` were abandoned: the next frame recorded over
    /// these assets records their uploads again.
    pub fn uploads_abandoned(&self, by: u64, frame: u64) {
        self.buffers.uploads.abandoned(by, frame);
    }

    /// Recorder `by` is gone without completing the frames that carried uploads (they were
    /// abandoned): the next frame recorded over these assets records them again.
    pub fn uploads_lost(&self, by: u64) {
        self.buffers.uploads.lost(by);
    }
}
