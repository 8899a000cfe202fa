//! glTF 2.0 import: the node hierarchy flattened into draws, primitives into quad meshes,
//! materials mapped onto the fragment model (alpha, transmission, volume tint, ior).
//!
//! A malformed file is an [`Error`], never a panic. The gltf crate indexes, asserts and
//! `unreachable!`s on some inputs that its validation lets through (accessor types, ranges), so
//! every accessor is checked here before the crate reads it, and buffers and images are loaded
//! here rather than by `gltf::import`: only files inside the glTF file's folder
//! (`files.rs`), and only as much as the whole file's budget allows (`budget.rs`).

mod budget;
mod files;

use budget::{collect_fallibly, Amount, Budget};
pub use budget::{ImportLimits, ImportOptions};
use files::{shortened, Longer, UriRoots};

use super::{
    Camera, Draw, Filter, Material, Mesh, MipFilter, Projection, Sampler, Scene, Texture, Wrap,
    MAX_TEXTURE_SIZE,
};
use crate::{Error, Result};
use glam::{Mat4, Vec2, Vec3, Vec4};
use gltf::accessor::{DataType, Dimensions};
use gltf::mesh::Mode;
use std::collections::{HashMap, HashSet};
use std::path::Path;
use std::rc::Rc;

/// glTF extensions whose meaning translucid implements: a file may *require* only these.
/// Files that merely *use* others (clearcoat, sheen...) load, ignoring them.
pub const IMPLEMENTED_EXTENSIONS: &[&str] = &[
    "KHR_materials_transmission",
    "KHR_materials_volume",
    "KHR_materials_ior",
    "KHR_materials_unlit",
    "KHR_texture_transform",
];

/// Field of view used to frame files without a camera.
const DEFAULT_FOV_Y: f32 = 0.8;

/// Loads a `.gltf` or `.glb` file into a validated [`Scene`], with the default
/// [`ImportOptions`]: its URIs may name files in its own folder only.
///
/// The default scene (or the first) is flattened: every mesh primitive becomes a [`Mesh`]
/// drawn with its node's world transform; OPAQUE and MASK materials go to `scene.opaque`,
/// BLEND and transmissive ones to `scene.transparent`, in node traversal order. The camera is
/// the first perspective camera found, else one framing everything.
pub fn load(path: &Path) -> Result<Scene> {
    load_with(path, &ImportOptions::default())
}

/// [`load`] with the folders its URIs may reach and the amounts it may take.
///
/// A file passing a limit is refused with [`Error::ImportLimit`] before the memory for it is
/// taken; a URI naming a file outside the allowed folders, a pipe or a device, with
/// [`Error::InvalidGltf`].
pub fn load_with(path: &Path, options: &ImportOptions) -> Result<Scene> {
    // The last line of defence: a panic in the gltf crate on input no check here foresaw is
    // this file's error, not the caller's crash.
    std::panic::catch_unwind(|| load_unguarded(path, options)).unwrap_or_else(|panic| {
        let message = panic
            .downcast_ref::<&str>()
            .map(|s| s.to_string())
            .or_else(|| panic.downcast_ref::<String>().cloned())
            .unwrap_or_else(|| "no message".into());
        Err(invalid(
            path,
            format!("the glTF reader failed on this file ({message})"),
        ))
    })
}

fn load_unguarded(path: &Path, options: &ImportOptions) -> Result<Scene> {
    let mut budget = Budget::new(options.limits);
    // A missing or unreadable file is an I/O error; one that is not a regular file, or is
    // over the budget, is refused.
    let size = std::fs::metadata(path)
        .map_err(|source| Error::SceneIo {
            path: path.into(),
            source,
        })?
        .len();
    budget
        .take(Amount::Bytes, size, "the file itself")
        .map_err(|reason| over_limit(path, reason))?;
    let bytes = files::read_regular_file(path, size, Longer::Refuse)
        .map_err(|reason| invalid(path, reason))?;
    let roots =
        UriRoots::new(path, &options.allowed_dirs).map_err(|reason| invalid(path, reason))?;
    let gltf::Gltf { document, blob } = parse(path, &bytes)?;
    drop(bytes);
    // Counted from the accessors, before anything is read.
    let triangles = document
        .meshes()
        .flat_map(|m| m.primitives())
        .map(|p| {
            let elements = p.indices().or_else(|| p.get(&gltf::Semantic::Positions));
            elements.map_or(0, |a| a.count() as u64 / 3)
        })
        .fold(0u64, u64::saturating_add);
    budget
        .take(Amount::Triangles, triangles, "its meshes")
        .map_err(|reason| over_limit(path, reason))?;
    // Every buffer counts at its declared length (the most read of it), before any is read;
    // a GLB's own BIN chunk was counted with the file.
    let declared = document
        .buffers()
        .filter(|b| !matches!(b.source(), gltf::buffer::Source::Bin))
        .map(|b| b.length() as u64)
        .fold(0u64, u64::saturating_add);
    budget
        .take(Amount::Bytes, declared, "its buffers' byteLengths")
        .map_err(|reason| over_limit(path, reason))?;
    let buffers = load_buffers(&document, &roots, blob);
    let mut importer = Importer {
        path,
        roots,
        budget,
        buffers,
        scene: Scene {
            name: scene_name(path),
            background: Vec3::splat(0.6),
            ..Scene::default()
        },
        meshes: HashMap::new(),
        mirrored: HashMap::new(),
        morphed: HashMap::new(),
        skinned_nodes: 0,
        materials: HashMap::new(),
        textures: HashMap::new(),
        images: HashMap::new(),
        encoded: HashMap::new(),
        skipped_primitives: 0,
        camera: None,
    };
    importer.import(&document)?;
    let scene = importer.scene;
    scene.validate()?;
    Ok(scene)
}

fn scene_name(path: &Path) -> String {
    path.file_stem()
        .map(|s| s.to_string_lossy().into_owned())
        .unwrap_or_else(|| path.display().to_string())
}

fn invalid(path: &Path, reason: impl Into<String>) -> Error {
    Error::InvalidGltf {
        path: path.into(),
        reason: reason.into(),
    }
}

fn over_limit(path: &Path, reason: String) -> Error {
    Error::ImportLimit {
        path: path.into(),
        reason,
    }
}

/// Parses JSON or GLB, refuses unimplemented required extensions, then validates.
fn parse(path: &Path, bytes: &[u8]) -> Result<gltf::Gltf> {
    if bytes.starts_with(b"glTF") {
        check_glb_container(bytes).map_err(|reason| invalid(path, reason))?;
    }
    let gltf = gltf::Gltf::from_slice_without_validation(bytes)
        .map_err(|e| invalid(path, with_json_field(bytes, e)))?;
    // Checked before validation so that the error names the extension, not a JSON path.
    if let Some(ext) = gltf
        .extensions_required()
        .find(|e| !IMPLEMENTED_EXTENSIONS.contains(e))
    {
        return Err(Error::UnsupportedExtension {
            path: path.into(),
            extension: ext.to_string(),
        });
    }
    let root = gltf.document.as_json();
    check_what_readers_unwrap(root).map_err(|reason| invalid(path, reason))?;
    validate(root).map_err(|reason| invalid(path, reason))?;
    Ok(gltf)
}

/// The gltf crate's parse error, with the JSON field it is about when it is a JSON error
/// (serde gives only a line and column).
fn with_json_field(bytes: &[u8], error: gltf::Error) -> String {
    let gltf::Error::Deserialize(_) = &error else {
        return error.to_string();
    };
    let json = match gltf::Glb::from_slice(bytes) {
        Ok(glb) => glb.json.into_owned(),
        Err(_) => bytes.to_vec(),
    };
    let mut deserializer = serde_json::Deserializer::from_slice(&json);
    match serde_path_to_error::deserialize::<_, gltf::json::Root>(&mut deserializer) {
        Err(e) if e.path().iter().next().is_some() => format!("{}: {}", e.path(), e.inner()),
        _ => error.to_string(),
    }
}

/// " (name)" for a named glTF object, nothing for an unnamed one.
fn name_suffix(name: Option<&str>) -> String {
    name.map(|n| format!(" ({n})")).unwrap_or_default()
}

/// The GLB container's header and chunk headers (glTF 2.0 §4.4), so that an error says which
/// value is wrong; the gltf crate's own errors name none.
fn check_glb_container(bytes: &[u8]) -> std::result::Result<(), String> {
    let word = |at: usize| {
        bytes
            .get(at..at + 4)
            .map(|b| u32::from_le_bytes([b[0], b[1], b[2], b[3]]))
    };
    let (Some(version), Some(length)) = (word(4), word(8)) else {
        return Err(format!("GLB header: {} bytes, a header is 12", bytes.len()));
    };
    if version != 2 {
        return Err(format!("GLB version {version}; only version 2 is glTF 2.0"));
    }
    if length as usize != bytes.len() {
        return Err(format!(
            "GLB header says the file has {length} bytes; it has {}",
            bytes.len()
        ));
    }
    const JSON: u32 = 0x4E4F_534A;
    const BIN: u32 = 0x004E_4942;
    let mut at = 12;
    let mut chunk = 0;
    while at < bytes.len() {
        let (Some(size), Some(kind)) = (word(at), word(at + 4)) else {
            return Err(format!(
                "GLB chunk {chunk} at byte {at}: its header is cut off"
            ));
        };
        // The first chunk is JSON, the second (if any) BIN; the gltf crate refuses others.
        let required = match chunk {
            0 => Some(("JSON", JSON)),
            1 => Some(("BIN", BIN)),
            _ => None,
        };
        if let Some((name, want)) = required.filter(|&(_, want)| want != kind) {
            return Err(format!(
                "GLB chunk {chunk} has type {kind:#010x}; it must be {name} ({want:#010x})"
            ));
        }
        let end = at + 8 + size as usize;
        if end > bytes.len() {
            return Err(format!(
                "GLB chunk {chunk} claims {size} bytes; only {} follow its header",
                bytes.len() - (at + 8).min(bytes.len())
            ));
        }
        at = end;
        chunk += 1;
    }
    if chunk == 0 {
        return Err("GLB file has no JSON chunk".into());
    }
    Ok(())
}

/// What the gltf crate indexes or unwraps without checking, in its validation or its
/// readers: primitives' accessor indices (its validation looks up POSITION's accessor before
/// checking the index), a camera's projection object, an embedded image's MIME type.
fn check_what_readers_unwrap(root: &gltf::json::Root) -> std::result::Result<(), String> {
    let accessors = root.accessors.len();
    for (m, mesh) in root.meshes.iter().enumerate() {
        let label = name_suffix(mesh.name.as_deref());
        for (p, primitive) in mesh.primitives.iter().enumerate() {
            let named = primitive.attributes.iter().map(|(semantic, index)| {
                let name = match semantic {
                    gltf::json::validation::Checked::Valid(s) => s.to_string(),
                    gltf::json::validation::Checked::Invalid => "an attribute".to_string(),
                };
                (name, index.value())
            });
            let indices = primitive
                .indices
                .map(|i| ("indices".to_string(), i.value()));
            let targets = primitive
                .targets
                .iter()
                .flatten()
                .enumerate()
                .flat_map(|(t, target)| {
                    [
                        ("POSITION", target.positions),
                        ("NORMAL", target.normals),
                        ("TANGENT", target.tangents),
                    ]
                    .into_iter()
                    .filter_map(move |(name, index)| {
                        index.map(|i| (format!("morph target {t} {name}"), i.value()))
                    })
                });
            for (what, index) in named.chain(indices).chain(targets) {
                if index >= accessors {
                    return Err(format!(
                        "mesh {m}{label} primitive {p}: {what} names accessor {index}, and the \
                         file has {accessors}"
                    ));
                }
            }
        }
    }
    for (i, camera) in root.cameras.iter().enumerate() {
        use gltf::json::camera::Type;
        use gltf::json::validation::Checked;
        let (kind, present) = match camera.type_ {
            Checked::Valid(Type::Perspective) => ("perspective", camera.perspective.is_some()),
            Checked::Valid(Type::Orthographic) => ("orthographic", camera.orthographic.is_some()),
            Checked::Invalid => continue, // validation names it
        };
        if !present {
            return Err(format!(
                "camera {i}: its type is {kind} but it has no {kind} object"
            ));
        }
    }
    for (i, image) in root.images.iter().enumerate() {
        let label = name_suffix(image.name.as_deref());
        if image.buffer_view.is_none() && image.uri.is_none() {
            return Err(format!(
                "image {i}{label} has neither a uri nor a bufferView"
            ));
        }
        if image.buffer_view.is_some() && image.mime_type.is_none() {
            return Err(format!(
                "image {i}{label} is in a bufferView but has no mimeType, which glTF requires \
                 there"
            ));
        }
    }
    Ok(())
}

/// The gltf crate's structural validation (index references, required fields, enums).
fn validate(root: &gltf::json::Root) -> std::result::Result<(), String> {
    use gltf::json::validation::{Error as V, Validate};
    let mut problems = Vec::new();
    root.validate(root, gltf::json::Path::new, &mut |path, error| {
        let path = path();
        // gltf-json does not list KHR_materials_volume among the extensions it enables, but
        // it parses it and we implement it; required extensions were checked by `parse`.
        let required = path.as_str().starts_with("extensionsRequired");
        if !(required && matches!(error, V::Unsupported)) {
            problems.push(format!("{path}: {error}"));
        }
    });
    if problems.is_empty() {
        return Ok(());
    }
    let shown = problems.len().min(5);
    let more = problems.len() - shown;
    let mut reason = problems[..shown].join("; ");
    if more > 0 {
        reason.push_str(&format!(" (and {more} more)"));
    }
    Err(reason)
}

/// Each buffer's bytes, or why they could not be read. A broken buffer is only an error when
/// a primitive or image actually reads it, so that the error can name what needed it.
type Buffers = Vec<std::result::Result<Vec<u8>, String>>;

fn load_buffers(document: &gltf::Document, roots: &UriRoots, mut blob: Option<Vec<u8>>) -> Buffers {
    document
        .buffers()
        .map(|buffer| {
            let data = match buffer.source() {
                gltf::buffer::Source::Bin => blob
                    .take()
                    .ok_or_else(|| "the GLB file has no BIN chunk".to_string()),
                // Bytes past byteLength are never read.
                gltf::buffer::Source::Uri(uri) => {
                    read_uri(roots, uri, buffer.length() as u64, Longer::Cut)
                }
            }?;
            if data.len() < buffer.length() {
                return Err(format!(
                    "has {} bytes, byteLength says {}",
                    data.len(),
                    buffer.length()
                ));
            }
            Ok(data)
        })
        .collect()
}

/// Largest image file read through a URI. Decoding is limited separately, by the image's
/// size ([`MAX_TEXTURE_SIZE`]).
const MAX_IMAGE_FILE_BYTES: u64 = 1 << 30;

/// Reads a `data:` URI, or at most `limit` bytes of a regular file the URI names inside the
/// allowed folders.
fn read_uri(
    roots: &UriRoots,
    uri: &str,
    limit: u64,
    longer: Longer,
) -> std::result::Result<Vec<u8>, String> {
    if uri.starts_with("data:") {
        // The gltf crate decodes base64 data URIs (without touching the file system).
        return gltf::buffer::Data::from_source(gltf::buffer::Source::Uri(uri), None)
            .map(|d| d.0)
            .map_err(|e| format!("bad data URI: {e}"));
    }
    roots.read(uri, limit, longer)
}

/// Flattening state: what has been converted so far, keyed by glTF indices so that reused
/// meshes, materials and textures are converted once.
struct Importer<'p> {
    path: &'p Path,
    /// The folders URIs may name files in.
    roots: UriRoots,
    budget: Budget,
    buffers: Buffers,
    scene: Scene,
    /// (glTF mesh, primitive) -> scene mesh, or `None` for skipped point/line primitives.
    meshes: HashMap<(usize, usize), Option<usize>>,
    /// Scene mesh -> its copy with every triangle's winding reversed, for nodes that mirror.
    mirrored: HashMap<usize, usize>,
    /// (scene mesh, morph weights' bits) -> its copy with the morph targets added.
    morphed: HashMap<(usize, Vec<u32>), usize>,
    /// Draws of nodes with a skin: drawn unskinned (said once).
    skinned_nodes: usize,
    /// (glTF material or default, node scale bits) -> scene material.
    materials: HashMap<(Option<usize>, u32), usize>,
    /// glTF texture -> scene texture.
    textures: HashMap<usize, usize>,
    /// glTF image -> its decoded texels, for textures that share an image.
    images: HashMap<usize, Rc<::image::RgbaImage>>,
    /// glTF image -> its encoded bytes, read by `check_textures`, until decoded.
    encoded: HashMap<usize, Vec<u8>>,
    skipped_primitives: usize,
    /// The first perspective camera met: its glTF data and the node's world transform.
    camera: Option<(gltf::Camera<'p>, Mat4)>,
}

impl<'p> Importer<'p> {
    fn import(&mut self, document: &'p gltf::Document) -> Result<()> {
        let Some(root) = document
            .default_scene()
            .or_else(|| document.scenes().next())
        else {
            return Err(invalid(self.path, "the file has no scene"));
        };
        self.check_textures(document)?;
        self.traverse(document, root)?;
        if self.skipped_primitives > 0 {
            log::warn!(
                "{}: skipped {} point/line primitives (only triangles are rendered)",
                self.path.display(),
                self.skipped_primitives
            );
        }
        if self.skinned_nodes > 0 {
            log::warn!(
                "{}: {} draws of skinned meshes are drawn unskinned, at their nodes' \
                 transforms (skins are not supported)",
                self.path.display(),
                self.skinned_nodes
            );
        }
        if self.scene.opaque.is_empty() && self.scene.transparent.is_empty() {
            return Err(invalid(self.path, "the scene draws no triangles"));
        }
        self.scene.camera = self.camera()?;
        Ok(())
    }

    /// Depth-first, in document order, with an explicit stack so that a deep hierarchy cannot
    /// overflow ours. A node reached along two paths is drawn twice, as viewers do; a node
    /// that is its own ancestor, or a hierarchy that expands without bound, is an error.
    fn traverse(&mut self, document: &gltf::Document, root: gltf::Scene<'p>) -> Result<()> {
        enum Step<'p> {
            Enter(gltf::Node<'p>, Mat4),
            Leave(usize),
        }
        let mut on_path = vec![false; document.nodes().len()];
        let mut stack: Vec<Step<'p>> = root
            .nodes()
            .map(|n| Step::Enter(n, Mat4::IDENTITY))
            .collect();
        stack.reverse();
        while let Some(step) = stack.pop() {
            let (node, parent) = match step {
                Step::Leave(index) => {
                    on_path[index] = false;
                    continue;
                }
                Step::Enter(node, parent) => (node, parent),
            };
            let index = node.index();
            self.budget
                .take(Amount::NodeInstances, 1, "the node hierarchy")
                .map_err(|reason| over_limit(self.path, reason))?;
            if std::mem::replace(&mut on_path[index], true) {
                return Err(invalid(
                    self.path,
                    format!("node {index} is its own ancestor"),
                ));
            }
            let world = parent * local_transform(&node).map_err(|e| invalid(self.path, e))?;
            if !world.is_finite() {
                return Err(invalid(
                    self.path,
                    format!("node {index} has a non-finite transform"),
                ));
            }
            if world.row(3) != Vec4::W {
                // glTF 2.0 §5.25: a node's matrix must be decomposable into TRS.
                return Err(invalid(
                    self.path,
                    format!(
                        "node {index}'s transform is not affine (its last row is {:?})",
                        world.row(3).to_array()
                    ),
                ));
            }
            if let Some(camera) = node.camera() {
                self.note_camera(camera, world);
            }
            if let Some(mesh) = node.mesh() {
                // A node's morph weights override its mesh's.
                let weights = node.weights().or_else(|| mesh.weights()).unwrap_or(&[]);
                self.add_mesh(&mesh, world, weights)?;
                self.skinned_nodes += usize::from(node.skin().is_some());
            }
            stack.push(Step::Leave(index));
            let children: Vec<_> = node.children().collect();
            stack.extend(children.into_iter().rev().map(|c| Step::Enter(c, world)));
        }
        Ok(())
    }

    fn note_camera(&mut self, camera: gltf::Camera<'p>, world: Mat4) {
        if self.camera.is_some() {
            return;
        }
        match camera.projection() {
            gltf::camera::Projection::Perspective(_)
            | gltf::camera::Projection::Orthographic(_) => self.camera = Some((camera, world)),
        }
    }

    /// One draw per triangle primitive of `mesh`, in primitive order. Through a node whose
    /// transform mirrors (negative determinant), a primitive's front faces are those whose
    /// corners turn clockwise (glTF's rule): it draws a copy whose triangles turn the other
    /// way, so that culling and face normals see the faces the file means.
    ///
    /// Primitives with morph targets are drawn at the node's (or the mesh's default) weights.
    fn add_mesh(&mut self, mesh: &gltf::Mesh<'p>, world: Mat4, weights: &[f32]) -> Result<()> {
        let mirrors = glam::Mat3::from_mat4(world).determinant() < 0.0;
        for primitive in mesh.primitives() {
            let Some(mut mesh_index) = self.convert_primitive(mesh, &primitive)? else {
                continue;
            };
            // Weights past the primitive's targets weigh nothing.
            let weights = &weights[..weights.len().min(primitive.morph_targets().len())];
            if weights.iter().any(|&w| w != 0.0) {
                mesh_index = self.morphed_mesh(mesh_index, &primitive, weights)?;
            }
            if mirrors {
                mesh_index = self.mirrored_mesh(mesh_index)?;
            }
            let (material, transparent) = self.convert_material(primitive.material(), world)?;
            let draw = Draw {
                mesh: mesh_index,
                material,
                transform: world,
                tint: glam::Vec4::ONE,
            };
            if transparent {
                self.scene.transparent.push(draw);
            } else {
                self.scene.opaque.push(draw);
            }
        }
        Ok(())
    }

    /// The copy of scene mesh `index` (of `primitive`) with its morph targets added at
    /// `weights` (glTF: positions and normals plus the weighted sum of the targets'
    /// displacements; a missing weight is 0), made once per weights and counted against the
    /// import's limits.
    fn morphed_mesh(
        &mut self,
        index: usize,
        primitive: &gltf::Primitive<'p>,
        weights: &[f32],
    ) -> Result<usize> {
        let key = (
            index,
            weights.iter().map(|w| w.to_bits()).collect::<Vec<_>>(),
        );
        if let Some(&done) = self.morphed.get(&key) {
            return Ok(done);
        }
        let base = &self.scene.meshes[index];
        let what = format!("{}'s morph targets", base.name);
        if let Some(w) = weights.iter().find(|w| !w.is_finite()) {
            return Err(invalid(self.path, format!("{what}: a weight is {w}")));
        }
        let n = base.positions.len();
        // Each weighting is a mesh of its own, counted as the mesh was.
        self.budget
            .take(Amount::Elements, n as u64, &what)
            .and_then(|()| {
                self.budget
                    .take(Amount::Triangles, base.triangle_count() as u64, &what)
            })
            .map_err(|reason| over_limit(self.path, reason))?;
        let mut morphed = Mesh {
            name: format!("{} (morphed)", base.name),
            ..base.clone()
        };
        // Every displacement accessor is checked before any is read.
        for target in primitive.morph_targets().take(weights.len()) {
            for (accessor, attribute) in [
                (target.positions(), "POSITION"),
                (target.normals(), "NORMAL"),
            ] {
                let Some(accessor) = accessor else { continue };
                let label = format!("{what}, {attribute} (accessor {})", accessor.index());
                self.budget
                    .take(Amount::Elements, accessor.count() as u64, &label)
                    .map_err(|reason| over_limit(self.path, reason))?;
                check_accessor(attribute, &accessor, &self.buffers, DISPLACEMENT_TYPES)
                    .and_then(|()| same_count(attribute, &accessor, n))
                    .map_err(|e| invalid(self.path, format!("{what}: {e}")))?;
            }
        }
        let buffers = &self.buffers;
        let data = |b: gltf::Buffer<'_>| buffers.get(b.index()).and_then(|r| r.as_deref().ok());
        for (target, &weight) in primitive.morph_targets().zip(weights) {
            // Only the checked accessors are read (not, say, the targets' tangents).
            let read = |accessor: Option<gltf::Accessor<'_>>| {
                accessor.and_then(|a| gltf::accessor::Iter::<[f32; 3]>::new(a, data))
            };
            let (positions, normals) = (read(target.positions()), read(target.normals()));
            let add = |into: Option<&mut Vec<Vec3>>,
                       read: Option<gltf::accessor::Iter<'_, [f32; 3]>>| {
                let (Some(into), Some(read)) = (into, read) else {
                    return Ok(());
                };
                let read = collect_fallibly(n, read.map(Vec3::from), "displacements")?;
                if let Some(i) = read.iter().position(|d| !d.is_finite()) {
                    return Err(format!("displacement {i} is not finite: {:?}", read[i]));
                }
                for (v, d) in into.iter_mut().zip(read) {
                    *v += weight * d;
                }
                Ok(())
            };
            add(Some(&mut morphed.positions), positions)
                .and_then(|()| add(morphed.normals.as_mut(), normals))
                .map_err(|e| invalid(self.path, format!("{what}: {e}")))?;
        }
        morphed
            .validate()
            .map_err(|e| invalid(self.path, format!("{what}: {e}")))?;
        self.scene.meshes.push(morphed);
        let made = self.scene.meshes.len() - 1;
        self.morphed.insert(key, made);
        Ok(made)
    }

    /// The copy of scene mesh `index` with every triangle's winding reversed, made once and
    /// counted against the import's limits as the mesh was.
    fn mirrored_mesh(&mut self, index: usize) -> Result<usize> {
        if let Some(&done) = self.mirrored.get(&index) {
            return Ok(done);
        }
        let mesh = &self.scene.meshes[index];
        let what = format!("{} mirrored by a node", mesh.name);
        let elements = mesh.positions.len() as u64;
        let triangles = mesh.triangle_count() as u64;
        self.budget
            .take(Amount::Elements, elements, &what)
            .and_then(|()| self.budget.take(Amount::Triangles, triangles, &what))
            .map_err(|reason| over_limit(self.path, reason))?;
        let copy = Mesh {
            name: format!("{} (mirrored)", mesh.name),
            quads: mesh.quads.iter().map(|&q| Mesh::reversed_quad(q)).collect(),
            ..mesh.clone()
        };
        self.scene.meshes.push(copy);
        let copied = self.scene.meshes.len() - 1;
        self.mirrored.insert(index, copied);
        Ok(copied)
    }

    fn convert_primitive(
        &mut self,
        mesh: &gltf::Mesh<'p>,
        primitive: &gltf::Primitive<'p>,
    ) -> Result<Option<usize>> {
        let key = (mesh.index(), primitive.index());
        if let Some(&done) = self.meshes.get(&key) {
            return Ok(done);
        }
        let name = match mesh.name() {
            Some(n) => format!("{n}/{}", primitive.index()),
            None => format!("mesh {}/{}", mesh.index(), primitive.index()),
        };
        let converted = if is_triangles(primitive.mode()) {
            let base_colour = primitive
                .material()
                .pbr_metallic_roughness()
                .base_color_texture();
            let transform = base_colour
                .as_ref()
                .and_then(|t| t.texture_transform())
                .map(|t| UvTransform::of(&t))
                .transpose()
                .map_err(|e| invalid(self.path, format!("{name}'s base colour texture: {e}")))?;
            // KHR_texture_transform's texCoord overrides the texture's.
            let uv_set = match (&base_colour, &transform) {
                (_, Some(UvTransform { set: Some(set), .. })) => *set,
                (Some(t), _) => t.tex_coord(),
                (None, _) => 0,
            };
            // Primitives that share an accessor read it again, and count again.
            for (what, accessor) in accessors_read(primitive, uv_set) {
                let count = accessor.count() as u64;
                let what = format!("{name} {what} (accessor {}, {count})", accessor.index());
                self.budget
                    .take(Amount::Elements, count, &what)
                    .map_err(|reason| over_limit(self.path, reason))?;
            }
            let mut m = read_primitive(primitive, &self.buffers, &name, uv_set).map_err(|e| {
                let label = name_suffix(mesh.name());
                Error::InvalidScene(format!(
                    "{}: mesh {}{label} primitive {}: {e}",
                    self.path.display(),
                    mesh.index(),
                    primitive.index()
                ))
            })?;
            if let (Some(transform), Some(uvs)) = (&transform, m.uvs.as_mut()) {
                for uv in uvs {
                    *uv = transform.apply(*uv);
                }
            }
            self.scene.meshes.push(m);
            Some(self.scene.meshes.len() - 1)
        } else {
            self.skipped_primitives += 1;
            None
        };
        self.meshes.insert(key, converted);
        Ok(converted)
    }

    /// The scene material for a glTF material seen through a node of world transform `world`,
    /// and whether it belongs to the transparent layer.
    fn convert_material(
        &mut self,
        material: gltf::Material<'p>,
        world: Mat4,
    ) -> Result<(usize, bool)> {
        let transparent = is_transparent(&material);
        // Volume thickness is in mesh space: a scaled node sees a thicker (darker) volume,
        // so such materials are converted once per scale.
        let scale = if material.volume().is_some() {
            node_scale(world)
        } else {
            1.0
        };
        let key = (material.index(), scale.to_bits());
        if let Some(&done) = self.materials.get(&key) {
            return Ok((done, transparent));
        }
        let texture = match material.pbr_metallic_roughness().base_color_texture() {
            Some(info) => Some(self.convert_texture(info.texture())?),
            None => None,
        };
        let converted = Material {
            texture,
            ..material_parameters(&material, scale)
        };
        self.scene.materials.push(converted);
        let index = self.scene.materials.len() - 1;
        self.materials.insert(key, index);
        Ok((index, transparent))
    }

    /// Reads every image a material's base colour uses and checks its size from its header,
    /// and the texels of all those textures, before any image is decoded.
    fn check_textures(&mut self, document: &'p gltf::Document) -> Result<()> {
        let path = self.path;
        let mut seen = HashSet::new();
        for material in document.materials() {
            let Some(info) = material.pbr_metallic_roughness().base_color_texture() else {
                continue;
            };
            let texture = info.texture();
            if !seen.insert(texture.index()) {
                continue;
            }
            let label = texture_label(&texture);
            let failed = |e: String| invalid(path, format!("{label}: {e}"));
            let image = texture.source();
            if !self.encoded.contains_key(&image.index()) {
                let bytes = self.read_image(&image, &label)?;
                self.encoded.insert(image.index(), bytes);
            }
            let (width, height) = image_size(&self.encoded[&image.index()]).map_err(failed)?;
            let what = format!("{label}'s {width}x{height} image");
            self.budget
                .take(Amount::Texels, u64::from(width) * u64::from(height), &what)
                .map_err(|reason| over_limit(path, reason))?;
        }
        Ok(())
    }

    fn convert_texture(&mut self, texture: gltf::Texture<'p>) -> Result<usize> {
        if let Some(&done) = self.textures.get(&texture.index()) {
            return Ok(done);
        }
        let label = texture_label(&texture);
        let image = texture.source().index();
        let decoded = match self.images.get(&image) {
            Some(decoded) => decoded.clone(),
            None => {
                // check_textures read every base colour image.
                let encoded = self.encoded.remove(&image).unwrap_or_default();
                let decoded = Rc::new(
                    decode_image(&encoded)
                        .map_err(|e| invalid(self.path, format!("{label}: {e}")))?,
                );
                self.images.insert(image, decoded.clone());
                decoded
            }
        };
        let (width, height) = decoded.dimensions();
        let texels = decoded.pixels().map(|p| p.0).collect();
        let sampler = convert_sampler(&texture.sampler());
        self.scene
            .textures
            .push(Texture::new(label, width, height, texels, true).with_sampler(sampler));
        let index = self.scene.textures.len() - 1;
        self.textures.insert(texture.index(), index);
        Ok(index)
    }

    /// An image's encoded bytes, from its buffer view or URI; an image file counts against
    /// the bytes the import may read.
    fn read_image(&mut self, image: &gltf::Image<'p>, label: &str) -> Result<Vec<u8>> {
        let failed = |e: String| invalid(self.path, format!("{label}: {e}"));
        let encoded = match image.source() {
            gltf::image::Source::View { view, .. } => {
                view_bytes(&view, &self.buffers).map_err(failed)?.to_vec()
            }
            gltf::image::Source::Uri { uri, .. } => {
                let bytes = read_uri(&self.roots, uri, MAX_IMAGE_FILE_BYTES, Longer::Refuse)
                    .map_err(failed)?;
                if !uri.starts_with("data:") {
                    self.budget
                        .take(Amount::Bytes, bytes.len() as u64, label)
                        .map_err(|reason| over_limit(self.path, reason))?;
                }
                bytes
            }
        };
        if encoded.len() as u64 >= MAX_IMAGE_FILE_BYTES {
            return Err(failed(format!(
                "the image file is over the {} MiB translucid reads",
                MAX_IMAGE_FILE_BYTES >> 20
            )));
        }
        Ok(encoded)
    }

    /// The file's first camera (perspective or orthographic), else a camera framing every
    /// draw.
    fn camera(&self) -> Result<Camera> {
        let bounds = self.world_bounds();
        let framing = || {
            let (min, max) = bounds.unwrap_or((Vec3::splat(-1.0), Vec3::ONE));
            let camera = Camera::framing(min, max, DEFAULT_FOV_Y);
            // Finite vertices can still be too far apart to frame (1e30 squared is not).
            camera.validate().map_err(|e| {
                invalid(
                    self.path,
                    format!(
                        "the file has no camera, and none can frame its vertices \
                         from {min} to {max} ({e})"
                    ),
                )
            })?;
            Ok(camera)
        };
        let Some((gltf_camera, world)) = &self.camera else {
            return framing();
        };
        let index = gltf_camera.index();
        // The view is the inverse of the camera node's rigid transform; scale is dropped
        // because glTF cameras are defined unscaled.
        let (_, rotation, translation) = world.to_scale_rotation_translation();
        let camera_to_world = Mat4::from_rotation_translation(rotation.normalize(), translation);
        let projection = match gltf_camera.projection() {
            gltf::camera::Projection::Perspective(p) => {
                let near = p.znear();
                let far = match p.zfar() {
                    Some(far) => far,
                    None => far_plane_for(translation, near, bounds),
                };
                Projection::Perspective {
                    fov_y: p.yfov(),
                    near,
                    far,
                }
            }
            // The aspect follows the render size, as the perspective one's does: ymag is kept.
            gltf::camera::Projection::Orthographic(o) => Projection::Orthographic {
                half_height: o.ymag(),
                near: o.znear(),
                far: o.zfar(),
            },
        };
        let camera = Camera {
            view: camera_to_world.inverse(),
            projection,
            jitter: Vec2::ZERO,
        };
        camera
            .validate()
            .map_err(|e| invalid(self.path, format!("camera {index}: {e}")))?;
        Ok(camera)
    }

    /// World-space bounds of every draw's vertices.
    ///
    /// Every vertex of every draw is transformed while that is at most
    /// [`MAX_BOUNDS_VERTICES`] in all; past it (a mesh drawn by a million node instances)
    /// each draw contributes its mesh's box's corners instead: a little looser, and bounded.
    fn world_bounds(&self) -> Option<(Vec3, Vec3)> {
        let draws = || self.scene.opaque.iter().chain(&self.scene.transparent);
        let vertices: usize = draws()
            .map(|d| self.scene.meshes[d.mesh].positions.len())
            .sum();
        let boxes: Vec<Option<[Vec3; 8]>> = self.scene.meshes.iter().map(box_corners).collect();
        let mut bounds: Option<(Vec3, Vec3)> = None;
        let mut add = |w: Vec3| {
            bounds = Some(match bounds {
                Some((lo, hi)) => (lo.min(w), hi.max(w)),
                None => (w, w),
            });
        };
        for draw in draws() {
            let points: &[Vec3] = if vertices <= MAX_BOUNDS_VERTICES {
                &self.scene.meshes[draw.mesh].positions
            } else {
                boxes[draw.mesh].as_ref().map_or(&[], |c| c.as_slice())
            };
            for &p in points {
                add(draw.transform.transform_point3(p));
            }
        }
        bounds
    }
}

/// Transformed vertices [`Importer::world_bounds`] takes exactly (some seconds' work).
const MAX_BOUNDS_VERTICES: usize = 50_000_000;

/// The corners of a mesh's bounding box, if it has vertices.
fn box_corners(mesh: &Mesh) -> Option<[Vec3; 8]> {
    let first = *mesh.positions.first()?;
    let (lo, hi) = mesh
        .positions
        .iter()
        .fold((first, first), |(lo, hi), &p| (lo.min(p), hi.max(p)));
    Some(std::array::from_fn(|i| {
        Vec3::new(
            if i & 1 == 0 { lo.x } else { hi.x },
            if i & 2 == 0 { lo.y } else { hi.y },
            if i & 4 == 0 { lo.z } else { hi.z },
        )
    }))
}

/// A far plane beyond everything in the scene, for cameras without `zfar`.
fn far_plane_for(eye: Vec3, near: f32, bounds: Option<(Vec3, Vec3)>) -> f32 {
    // Per axis, the farther of the two box faces gives the farthest corner.
    let farthest = bounds.map_or(0.0, |(lo, hi)| {
        (eye - lo).abs().max((eye - hi).abs()).length()
    });
    (farthest * 1.5).max(near * 1000.0)
}

/// The file's sampler; absent fields take glTF's suggested defaults (REPEAT, trilinear).
/// A texture as messages name it: by index, and by its image's or its own name.
fn texture_label(texture: &gltf::Texture<'_>) -> String {
    let image = texture.source();
    match image.name().or(texture.name()) {
        Some(n) => format!("texture {} ({n})", texture.index()),
        None => format!("texture {} (image {})", texture.index(), image.index()),
    }
}

fn image_reader(
    encoded: &[u8],
) -> std::result::Result<::image::ImageReader<std::io::Cursor<&[u8]>>, String> {
    ::image::ImageReader::new(std::io::Cursor::new(encoded))
        .with_guessed_format()
        .map_err(|e| format!("cannot read image: {e}"))
}

/// An image's size from its header, within [`MAX_TEXTURE_SIZE`].
fn image_size(encoded: &[u8]) -> std::result::Result<(u32, u32), String> {
    let (width, height) = image_reader(encoded)?
        .into_dimensions()
        .map_err(|e| format!("cannot decode image: {e}"))?;
    if width > MAX_TEXTURE_SIZE || height > MAX_TEXTURE_SIZE {
        return Err(format!(
            "image is {width}x{height}; the largest width or height translucid takes is \
             {MAX_TEXTURE_SIZE}"
        ));
    }
    Ok((width, height))
}

fn decode_image(encoded: &[u8]) -> std::result::Result<::image::RgbaImage, String> {
    image_size(encoded)?;
    image_reader(encoded)?
        .decode()
        .map(|i| i.into_rgba8())
        .map_err(|e| format!("cannot decode image: {e}"))
}

fn convert_sampler(sampler: &gltf::texture::Sampler<'_>) -> Sampler {
    use gltf::texture::{MagFilter, MinFilter, WrappingMode};
    let wrap = |mode| match mode {
        WrappingMode::Repeat => Wrap::Repeat,
        WrappingMode::ClampToEdge => Wrap::ClampToEdge,
        WrappingMode::MirroredRepeat => Wrap::MirroredRepeat,
    };
    let mag_filter = match sampler.mag_filter() {
        Some(MagFilter::Nearest) => Filter::Nearest,
        Some(MagFilter::Linear) | None => Filter::Linear,
    };
    let (min_filter, mip_filter) = match sampler.min_filter() {
        Some(MinFilter::Nearest) => (Filter::Nearest, MipFilter::None),
        Some(MinFilter::Linear) => (Filter::Linear, MipFilter::None),
        Some(MinFilter::NearestMipmapNearest) => (Filter::Nearest, MipFilter::Nearest),
        Some(MinFilter::LinearMipmapNearest) => (Filter::Linear, MipFilter::Nearest),
        Some(MinFilter::NearestMipmapLinear) => (Filter::Nearest, MipFilter::Linear),
        Some(MinFilter::LinearMipmapLinear) | None => (Filter::Linear, MipFilter::Linear),
    };
    Sampler {
        wrap_s: wrap(sampler.wrap_s()),
        wrap_t: wrap(sampler.wrap_t()),
        mag_filter,
        min_filter,
        mip_filter,
    }
}

fn is_triangles(mode: Mode) -> bool {
    matches!(
        mode,
        Mode::Triangles | Mode::TriangleStrip | Mode::TriangleFan
    )
}

fn is_transparent(material: &gltf::Material<'_>) -> bool {
    material.transmission().is_some() || material.alpha_mode() == gltf::material::AlphaMode::Blend
}

/// A base colour texture's `KHR_texture_transform`, applied to the primitive's texture
/// coordinates when it is read: the transform is affine, so transformed corners interpolate
/// to the transformed coordinates of every pixel, and their differences (the sampler's level
/// of detail) follow too.
struct UvTransform {
    /// Columns of the 2x2 part (rotation times scale), and the offset.
    x: glam::Vec2,
    y: glam::Vec2,
    offset: glam::Vec2,
    /// The texture coordinate set it reads instead of the texture's.
    set: Option<u32>,
}

impl UvTransform {
    fn of(t: &gltf::texture::TextureTransform<'_>) -> std::result::Result<Self, String> {
        Self::new(t.offset(), t.rotation(), t.scale(), t.tex_coord())
    }

    fn new(
        [ox, oy]: [f32; 2],
        r: f32,
        [sx, sy]: [f32; 2],
        set: Option<u32>,
    ) -> std::result::Result<Self, String> {
        if ![ox, oy, sx, sy, r].iter().all(|v| v.is_finite()) {
            return Err(format!(
                "KHR_texture_transform has a non-finite offset, rotation or scale \
                 ({:?}, {r}, {:?})",
                [ox, oy],
                [sx, sy]
            ));
        }
        // translation * rotation * scale, the rotation [cos sin; -sin cos] by rows: as viewers
        // and exporters turn it, and TextureTransformTest expects (the extension's GLSL
        // listing turns the other way: KhronosGroup/glTF issue 1563).
        let (sin, cos) = r.sin_cos();
        Ok(Self {
            x: glam::Vec2::new(cos * sx, -sin * sx),
            y: glam::Vec2::new(sin * sy, cos * sy),
            offset: glam::Vec2::new(ox, oy),
            set,
        })
    }

    fn apply(&self, uv: glam::Vec2) -> glam::Vec2 {
        self.x * uv.x + self.y * uv.y + self.offset
    }
}

/// Geometric mean of a transform's axis scales: how much a mesh-space length grows.
/// Rounded to 4 decimals so that rounding noise in rotations does not split materials.
fn node_scale(world: Mat4) -> f32 {
    let s = glam::Mat3::from_mat4(world).determinant().abs().cbrt();
    if s.is_finite() && s > 0.0 {
        ((s * 1e4).round() / 1e4).max(1e-4)
    } else {
        1.0
    }
}

/// Every material field but the texture, from glTF's factors and extensions.
fn material_parameters(material: &gltf::Material<'_>, scale: f32) -> Material {
    let pbr = material.pbr_metallic_roughness();
    let [r, g, b, a] = pbr.base_color_factor();
    let base = Vec4::new(r.max(0.0), g.max(0.0), b.max(0.0), a.clamp(0.0, 1.0));
    let transmission = material
        .transmission()
        .map_or(0.0, |t| t.transmission_factor().clamp(0.0, 1.0));
    let transmissive = material.transmission().is_some();
    let reflectance = match material.ior() {
        Some(ior) => fresnel_reflectance(ior),
        None if transmissive => 0.04,
        None => 0.0,
    };
    let transmission_tint = match material.volume() {
        Some(v) if transmissive => volume_tint(
            Vec3::from(v.attenuation_color()),
            v.thickness_factor() * scale,
            v.attenuation_distance(),
        ),
        _ => Vec3::ONE,
    };
    let alpha_cutoff = match material.alpha_mode() {
        gltf::material::AlphaMode::Mask => Some(material.alpha_cutoff().unwrap_or(0.5)),
        _ => None,
    };
    Material {
        name: material
            .name()
            .map_or_else(|| material_label(material), str::to_string),
        base_colour: base,
        texture: None,
        transmission,
        transmission_tint,
        reflectance,
        lit: !material.unlit(),
        double_sided: material.double_sided(),
        alpha_cutoff,
    }
}

fn material_label(material: &gltf::Material<'_>) -> String {
    match material.index() {
        Some(i) => format!("material {i}"),
        None => "default material".to_string(),
    }
}

/// Normal-incidence Fresnel reflectance `((ior - 1) / (ior + 1))^2`.
fn fresnel_reflectance(ior: f32) -> f32 {
    let r = ((ior - 1.0) / (ior + 1.0)).powi(2);
    if r.is_finite() {
        r.clamp(0.0, 1.0)
    } else {
        0.04
    }
}

/// Beer–Lambert transmittance through `thickness` of a medium that turns white light into
/// `colour` after `distance`: `colour ^ (thickness / distance)` per channel.
fn volume_tint(colour: Vec3, thickness: f32, distance: f32) -> Vec3 {
    let exponent = thickness / distance;
    if !exponent.is_finite() || exponent <= 0.0 {
        return Vec3::ONE;
    }
    let c = colour.clamp(Vec3::ZERO, Vec3::ONE);
    Vec3::new(c.x.powf(exponent), c.y.powf(exponent), c.z.powf(exponent))
}

/// The accessors [`read_primitive`] reads, named: every attribute it converts, and the
/// indices.
fn accessors_read<'a>(
    primitive: &gltf::Primitive<'a>,
    uv_set: u32,
) -> impl Iterator<Item = (&'static str, gltf::Accessor<'a>)> {
    let attributes = [
        ("POSITION", gltf::Semantic::Positions),
        ("NORMAL", gltf::Semantic::Normals),
        ("COLOR_0", gltf::Semantic::Colors(0)),
        ("TEXCOORD", gltf::Semantic::TexCoords(uv_set)),
    ]
    .map(|(name, semantic)| (name, primitive.get(&semantic)));
    attributes
        .into_iter()
        .chain([("indices", primitive.indices())])
        .filter_map(|(name, accessor)| Some((name, accessor?)))
}

/// Converts one triangle primitive, checking everything the gltf reader would trip over.
fn read_primitive(
    primitive: &gltf::Primitive<'_>,
    buffers: &Buffers,
    name: &str,
    uv_set: u32,
) -> std::result::Result<Mesh, String> {
    let reader = primitive.reader(|b| buffers.get(b.index()).and_then(|r| r.as_deref().ok()));
    let attr = |semantic: gltf::Semantic| primitive.get(&semantic);

    let pos_accessor = attr(gltf::Semantic::Positions).ok_or("no POSITION attribute")?;
    check_accessor(
        "POSITION",
        &pos_accessor,
        buffers,
        &[(DataType::F32, Dimensions::Vec3)],
    )?;
    let positions: Vec<Vec3> = collect_fallibly(
        pos_accessor.count(),
        reader
            .read_positions()
            .ok_or("POSITION data missing")?
            .map(Vec3::from),
        "positions",
    )?;
    if let Some(i) = positions.iter().position(|p| !p.is_finite()) {
        return Err(format!("POSITION {i} is not finite: {:?}", positions[i]));
    }
    let n = positions.len();

    let normals = match attr(gltf::Semantic::Normals) {
        Some(a) => {
            check_accessor("NORMAL", &a, buffers, &[(DataType::F32, Dimensions::Vec3)])?;
            same_count("NORMAL", &a, n)?;
            let read = reader.read_normals().ok_or("NORMAL data missing")?;
            Some(collect_fallibly(n, read.map(Vec3::from), "normals")?)
        }
        None => None,
    };
    let colours = match attr(gltf::Semantic::Colors(0)) {
        Some(a) => {
            check_accessor("COLOR_0", &a, buffers, COLOUR_TYPES)?;
            same_count("COLOR_0", &a, n)?;
            let read = reader.read_colors(0).ok_or("COLOR_0 data missing")?;
            Some(collect_fallibly(
                n,
                read.into_rgba_f32().map(Vec4::from),
                "colours",
            )?)
        }
        None => None,
    };
    let uvs = match attr(gltf::Semantic::TexCoords(uv_set)) {
        Some(a) => {
            check_accessor("TEXCOORD", &a, buffers, UV_TYPES)?;
            same_count("TEXCOORD", &a, n)?;
            let read = reader
                .read_tex_coords(uv_set)
                .ok_or("TEXCOORD data missing")?;
            Some(collect_fallibly(n, read.into_f32().map(Vec2::from), "uvs")?)
        }
        None => None,
    };

    let indices: Vec<u32> = match primitive.indices() {
        Some(a) => {
            check_accessor("indices", &a, buffers, INDEX_TYPES)?;
            let read = reader.read_indices().ok_or("index data missing")?;
            collect_fallibly(a.count(), read.into_u32(), "indices")?
        }
        None => collect_fallibly(n, 0..n as u32, "indices")?,
    };
    if let Some(i) = indices.iter().position(|&v| v as usize >= n) {
        return Err(format!(
            "index {i} is {}, out of range for {n} vertices",
            indices[i]
        ));
    }
    let triangles = assemble_triangles(primitive.mode(), &indices);
    let mut mesh = Mesh::from_triangles(name, positions, &triangles);
    mesh.normals = normals;
    mesh.colours = colours;
    mesh.uvs = uvs;
    mesh.validate()?;
    Ok(mesh)
}

/// Morph targets' position and normal displacements.
const DISPLACEMENT_TYPES: &[(DataType, Dimensions)] = &[(DataType::F32, Dimensions::Vec3)];
const COLOUR_TYPES: &[(DataType, Dimensions)] = &[
    (DataType::U8, Dimensions::Vec3),
    (DataType::U16, Dimensions::Vec3),
    (DataType::F32, Dimensions::Vec3),
    (DataType::U8, Dimensions::Vec4),
    (DataType::U16, Dimensions::Vec4),
    (DataType::F32, Dimensions::Vec4),
];
const UV_TYPES: &[(DataType, Dimensions)] = &[
    (DataType::U8, Dimensions::Vec2),
    (DataType::U16, Dimensions::Vec2),
    (DataType::F32, Dimensions::Vec2),
];
const INDEX_TYPES: &[(DataType, Dimensions)] = &[
    (DataType::U8, Dimensions::Scalar),
    (DataType::U16, Dimensions::Scalar),
    (DataType::U32, Dimensions::Scalar),
];

/// A vertex attribute has one element per position: checked before it is read, so that a
/// huge count costs nothing.
fn same_count(
    what: &str,
    accessor: &gltf::Accessor<'_>,
    positions: usize,
) -> std::result::Result<(), String> {
    if accessor.count() != positions {
        return Err(format!(
            "{what} accessor {} has {} elements for {positions} positions",
            accessor.index(),
            accessor.count()
        ));
    }
    Ok(())
}

/// Checks an accessor's type and that every byte it reads lies inside its buffer view and
/// buffer, so that the gltf reader neither asserts nor silently returns nothing.
fn check_accessor(
    what: &str,
    accessor: &gltf::Accessor<'_>,
    buffers: &Buffers,
    types: &[(DataType, Dimensions)],
) -> std::result::Result<(), String> {
    let ty = (accessor.data_type(), accessor.dimensions());
    if !types.contains(&ty) {
        return Err(format!(
            "{what} accessor {} has unsupported type {ty:?}",
            accessor.index()
        ));
    }
    let fail = |e: String| format!("{what} accessor {}: {e}", accessor.index());
    if accessor.count() == 0 {
        return Err(fail("it is empty".into()));
    }
    if let Some(view) = accessor.view() {
        check_range(
            &view,
            accessor.offset(),
            accessor.count(),
            accessor.size(),
            buffers,
        )
        .map_err(fail)?;
    }
    if let Some(sparse) = accessor.sparse() {
        let indices = sparse.indices();
        let index_size = match indices.index_type() {
            gltf::accessor::sparse::IndexType::U8 => 1,
            gltf::accessor::sparse::IndexType::U16 => 2,
            gltf::accessor::sparse::IndexType::U32 => 4,
        };
        let (count, values) = (sparse.count(), sparse.values());
        if count == 0 {
            return Err(fail("sparse with no entries".into()));
        }
        check_range(
            &indices.view(),
            indices.offset(),
            count,
            index_size,
            buffers,
        )
        .map_err(|e| fail(format!("sparse indices: {e}")))?;
        check_range(
            &values.view(),
            values.offset(),
            count,
            accessor.size(),
            buffers,
        )
        .map_err(|e| fail(format!("sparse values: {e}")))?;
    } else if accessor.view().is_none() {
        return Err(fail("no bufferView and no sparse data".into()));
    }
    // Without a bufferView every element the sparse entries leave is zero, and the reader
    // allocates them all: the file's bytes do not bound the count, this does.
    if accessor.view().is_none() && accessor.count() > MAX_ZERO_FILLED_ELEMENTS {
        return Err(fail(format!(
            "{} elements with no bufferView; such accessors may have at most {}",
            accessor.count(),
            MAX_ZERO_FILLED_ELEMENTS
        )));
    }
    Ok(())
}

/// Elements an accessor without a bufferView (zeros but for its sparse entries) may have:
/// 16 M, more vertices than any one primitive of a real scene.
const MAX_ZERO_FILLED_ELEMENTS: usize = 1 << 24;

/// `count` elements of `size` bytes at `offset` (with the view's stride) fit in the view,
/// and the view fits in its loaded buffer.
fn check_range(
    view: &gltf::buffer::View<'_>,
    offset: usize,
    count: usize,
    size: usize,
    buffers: &Buffers,
) -> std::result::Result<(), String> {
    let stride = view.stride().unwrap_or(size);
    if stride < size {
        return Err(format!(
            "byteStride {stride} is smaller than an element ({size} bytes)"
        ));
    }
    let end = count
        .checked_sub(1)
        .and_then(|last| last.checked_mul(stride))
        .and_then(|b| b.checked_add(offset))
        .and_then(|b| b.checked_add(size));
    match end {
        Some(end) if end <= view.length() => {}
        _ => {
            return Err(format!(
                "{count} elements at offset {offset} overrun bufferView {} ({} bytes)",
                view.index(),
                view.length()
            ))
        }
    }
    view_bytes(view, buffers).map(|_| ())
}

/// The bytes of a buffer view, or why they are unavailable.
fn view_bytes<'b>(
    view: &gltf::buffer::View<'_>,
    buffers: &'b Buffers,
) -> std::result::Result<&'b [u8], String> {
    let buffer = view.buffer();
    let data = match buffers.get(buffer.index()) {
        Some(Ok(data)) => data,
        Some(Err(e)) => return Err(format!("buffer {} {e}", buffer_label(&buffer))),
        None => return Err(format!("buffer {} does not exist", buffer.index())),
    };
    view.offset()
        .checked_add(view.length())
        .and_then(|end| data.get(view.offset()..end))
        .ok_or_else(|| {
            format!(
                "bufferView {} overruns buffer {} ({} bytes)",
                view.index(),
                buffer_label(&buffer),
                data.len()
            )
        })
}

fn buffer_label(buffer: &gltf::Buffer<'_>) -> String {
    match buffer.source() {
        gltf::buffer::Source::Uri(uri) if !uri.starts_with("data:") => {
            format!("{} ({})", buffer.index(), shortened(uri))
        }
        _ => buffer.index().to_string(),
    }
}

/// A node's transform relative to its parent. A rotation is made a unit quaternion, as glTF
/// requires and as exporters nearly write it: a fuzzed x of 4294967297 otherwise scaled the
/// node by 1.8e19.
fn local_transform(node: &gltf::Node<'_>) -> std::result::Result<Mat4, String> {
    match node.transform() {
        gltf::scene::Transform::Matrix { matrix } => Ok(Mat4::from_cols_array_2d(&matrix)),
        gltf::scene::Transform::Decomposed {
            translation,
            rotation,
            scale,
        } => {
            let q = glam::Quat::from_array(rotation);
            let length = q.length();
            if !(length > 0.0 && length.is_finite()) {
                return Err(format!(
                    "node {}'s rotation {rotation:?} is not a quaternion with a direction",
                    node.index()
                ));
            }
            Ok(Mat4::from_scale_rotation_translation(
                Vec3::from(scale),
                q / length,
                Vec3::from(translation),
            ))
        }
    }
}

/// Triangle lists from triangles, strips and fans (glTF 2.0 §3.7.2.1), dropping degenerate
/// triangles (strips use them as restarts).
fn assemble_triangles(mode: Mode, indices: &[u32]) -> Vec<[u32; 3]> {
    let tris: Vec<[u32; 3]> = match mode {
        Mode::TriangleStrip => (0..indices.len().saturating_sub(2))
            .map(|i| {
                let odd = i % 2;
                [indices[i], indices[i + 1 + odd], indices[i + 2 - odd]]
            })
            .collect(),
        Mode::TriangleFan => (1..indices.len().saturating_sub(1))
            .map(|i| [indices[i], indices[i + 1], indices[0]])
            .collect(),
        _ => indices
            .chunks_exact(3)
            .map(|t| [t[0], t[1], t[2]])
            .collect(),
    };
    tris.into_iter()
        .filter(|t| t[0] != t[1] && t[1] != t[2] && t[2] != t[0])
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Loads `json` written as a `.gltf` file into a folder of its own, with `files` (name,
    /// bytes) beside it; the folder goes afterwards.
    fn load_written(name: &str, json: &str, files: &[(&str, &[u8])]) -> Result<Scene> {
        load_written_with(name, json, files, &ImportOptions::default())
    }

    /// [`load_written`] with `options`.
    fn load_written_with(
        name: &str,
        json: &str,
        files: &[(&str, &[u8])],
        options: &ImportOptions,
    ) -> Result<Scene> {
        let dir = std::env::temp_dir().join(format!("translucid-{name}-{}", std::process::id()));
        std::fs::create_dir_all(&dir).expect("temp folder");
        for (file, bytes) in files {
            std::fs::write(dir.join(file), bytes).expect("write a file beside it");
        }
        let path = dir.join(format!("{name}.gltf"));
        std::fs::write(&path, json).expect("write the file");
        let scene = load_with(&path, options);
        std::fs::remove_dir_all(&dir).ok();
        scene
    }

    /// KHR_texture_transform worked out by hand: a quarter turn, a scale of (2, 1) and an
    /// offset of (0.25, 0.5) take (1, 0) to (0.25, -1.5) and (0, 1) to (1.25, 0.5).
    #[test]
    fn a_texture_transform_scales_turns_then_offsets() {
        let t = UvTransform::new([0.25, 0.5], std::f32::consts::FRAC_PI_2, [2.0, 1.0], None)
            .expect("finite");
        let near = |uv: [f32; 2], want: [f32; 2]| {
            let got = t.apply(glam::Vec2::from(uv));
            assert!(
                (got - glam::Vec2::from(want)).abs().max_element() < 1e-6,
                "{got}"
            );
        };
        near([1.0, 0.0], [0.25, -1.5]);
        near([0.0, 1.0], [1.25, 0.5]);
        assert!(UvTransform::new([f32::NAN, 0.0], 0.0, [1.0, 1.0], None).is_err());
    }

    /// A file that requires KHR_texture_transform loads, its base colour texture's transform
    /// (here reading TEXCOORD_1 through the transform's texCoord) applied to the mesh's
    /// coordinates as the hand-worked test above has it.
    #[test]
    fn a_base_colour_texture_transform_moves_the_texture_coordinates() {
        let positions: [[f32; 3]; 3] = [[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]];
        let uv0: [[f32; 2]; 3] = [[9.0, 9.0], [9.0, 9.0], [9.0, 9.0]];
        let uv1: [[f32; 2]; 3] = [[0.0, 0.0], [1.0, 0.0], [0.0, 1.0]];
        let mut bin: Vec<u8> = positions
            .iter()
            .flatten()
            .flat_map(|v| v.to_le_bytes())
            .collect();
        for uvs in [uv0, uv1] {
            bin.extend(uvs.iter().flatten().flat_map(|v| v.to_le_bytes()));
        }
        let json = r#"{
            "asset": {"version": "2.0"},
            "extensionsUsed": ["KHR_texture_transform"],
            "extensionsRequired": ["KHR_texture_transform"],
            "scenes": [{"nodes": [0]}],
            "nodes": [{"mesh": 0}],
            "images": [{"uri": "texels.png"}],
            "textures": [{"source": 0}],
            "materials": [{"alphaMode": "BLEND", "pbrMetallicRoughness": {
                "baseColorTexture": {"index": 0, "extensions": {"KHR_texture_transform": {
                    "offset": [0.25, 0.5], "rotation": 1.5707964, "scale": [2, 1],
                    "texCoord": 1}}}}}],
            "meshes": [{"primitives": [{"attributes": {"POSITION": 0, "TEXCOORD_0": 1,
                "TEXCOORD_1": 2}, "material": 0}]}],
            "buffers": [{"uri": "quad.bin", "byteLength": 84}],
            "bufferViews": [{"buffer": 0, "byteOffset": 0, "byteLength": 36},
                {"buffer": 0, "byteOffset": 36, "byteLength": 24},
                {"buffer": 0, "byteOffset": 60, "byteLength": 24}],
            "accessors": [
                {"bufferView": 0, "componentType": 5126, "count": 3, "type": "VEC3",
                    "min": [0, 0, 0], "max": [1, 1, 0]},
                {"bufferView": 1, "componentType": 5126, "count": 3, "type": "VEC2"},
                {"bufferView": 2, "componentType": 5126, "count": 3, "type": "VEC2"}
            ]
        }"#;
        let mut png = std::io::Cursor::new(Vec::new());
        ::image::RgbaImage::from_pixel(2, 2, ::image::Rgba([200, 100, 50, 255]))
            .write_to(&mut png, ::image::ImageFormat::Png)
            .expect("encode the texture");
        let files: [(&str, &[u8]); 2] = [("quad.bin", &bin), ("texels.png", png.get_ref())];
        let scene = load_written("uv-transform", json, &files).expect("loads");
        let uvs = scene.meshes[0].uvs.as_ref().expect("texture coordinates");
        let want = [[0.25, 0.5], [0.25, -1.5], [1.25, 0.5]];
        for (got, want) in uvs.iter().zip(want) {
            assert!(
                (*got - glam::Vec2::from(want)).abs().max_element() < 1e-6,
                "{uvs:?}"
            );
        }
    }

    /// A triangle with one morph target (every vertex up by 1, normals turned): drawn at
    /// the mesh's default weight 0.5, and at weight 1 by a node that overrides it, each a
    /// mesh of its own; the base mesh stays as it is.
    #[test]
    fn morph_targets_are_drawn_at_the_nodes_or_the_meshs_weights() {
        let positions: [[f32; 3]; 3] = [[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]];
        let normals: [[f32; 3]; 3] = [[0.0, 0.0, 1.0]; 3];
        let up: [[f32; 3]; 3] = [[0.0, 1.0, 0.0]; 3];
        let turn: [[f32; 3]; 3] = [[0.0, 2.0, 0.0]; 3];
        let bin: Vec<u8> = [positions, normals, up, turn]
            .iter()
            .flatten()
            .flatten()
            .flat_map(|v| v.to_le_bytes())
            .collect();
        let json = r#"{
            "asset": {"version": "2.0"},
            "scenes": [{"nodes": [0, 1]}],
            "nodes": [{"mesh": 0}, {"mesh": 0, "weights": [1.0]}],
            "materials": [{"alphaMode": "BLEND"}],
            "meshes": [{"weights": [0.5], "primitives": [{
                "attributes": {"POSITION": 0, "NORMAL": 1},
                "targets": [{"POSITION": 2, "NORMAL": 3}], "material": 0}]}],
            "buffers": [{"uri": "quad.bin", "byteLength": 144}],
            "bufferViews": [{"buffer": 0, "byteOffset": 0, "byteLength": 36},
                {"buffer": 0, "byteOffset": 36, "byteLength": 36},
                {"buffer": 0, "byteOffset": 72, "byteLength": 36},
                {"buffer": 0, "byteOffset": 108, "byteLength": 36}],
            "accessors": [
                {"bufferView": 0, "componentType": 5126, "count": 3, "type": "VEC3",
                    "min": [0, 0, 0], "max": [1, 1, 0]},
                {"bufferView": 1, "componentType": 5126, "count": 3, "type": "VEC3"},
                {"bufferView": 2, "componentType": 5126, "count": 3, "type": "VEC3",
                    "min": [0, 1, 0], "max": [0, 1, 0]},
                {"bufferView": 3, "componentType": 5126, "count": 3, "type": "VEC3"}
            ]
        }"#;
        let scene = load_written("morph", json, &[("quad.bin", &bin)]).expect("loads");
        let drawn: Vec<&Mesh> = scene
            .transparent
            .iter()
            .map(|d| &scene.meshes[d.mesh])
            .collect();
        let ys = |m: &Mesh| m.positions.iter().map(|p| p.y).collect::<Vec<_>>();
        assert_eq!(ys(drawn[0]), [0.5, 0.5, 1.5], "the mesh's weight");
        assert_eq!(ys(drawn[1]), [1.0, 1.0, 2.0], "the node's weight");
        let normal = |m: &Mesh| m.normals.as_ref().expect("normals")[0];
        assert_eq!(normal(drawn[0]), Vec3::new(0.0, 1.0, 1.0));
        assert_eq!(normal(drawn[1]), Vec3::new(0.0, 2.0, 1.0));
        assert_eq!(ys(&scene.meshes[0]), [0.0, 0.0, 1.0], "the base mesh");
        // Each weighting counts as a mesh of its own: the file's one triangle and two
        // weightings pass a limit of two triangles.
        let mut options = ImportOptions::default();
        options.limits.triangles = 2;
        let refused = load_written_with("morph-limit", json, &[("quad.bin", &bin)], &options)
            .expect_err("past the triangle limit");
        assert!(refused.to_string().contains("triangles"), "{refused}");
    }

    /// A single-sided blended quad drawn by two nodes, the second mirrored in x (glTF's
    /// NegativeScaleTest): both show, the same from the camera on the axis between them.
    /// (Without the mirrored copy the second one's faces turn away, and it is culled.)
    #[test]
    fn a_mirroring_node_draws_the_faces_the_file_means() {
        use crate::image::OpaqueLayer;
        // A unit quad in z = 0 turning counter-clockwise seen from +z, then its indices.
        let positions: [[f32; 3]; 4] = [
            [-0.5, -0.5, 0.0],
            [0.5, -0.5, 0.0],
            [0.5, 0.5, 0.0],
            [-0.5, 0.5, 0.0],
        ];
        let indices: [u16; 6] = [0, 1, 2, 0, 2, 3];
        let mut bin: Vec<u8> = positions
            .iter()
            .flatten()
            .flat_map(|v| v.to_le_bytes())
            .collect();
        bin.extend(indices.iter().flat_map(|i| i.to_le_bytes()));
        let json = r#"{
            "asset": {"version": "2.0"},
            "scene": 0,
            "scenes": [{"nodes": [0, 1, 2]}],
            "nodes": [
                {"mesh": 0, "translation": [-0.75, 0, 0]},
                {"mesh": 0, "translation": [0.75, 0, 0], "scale": [-1, 1, 1]},
                {"camera": 0, "translation": [0, 0, 3]}
            ],
            "cameras": [{"type": "perspective",
                "perspective": {"yfov": 0.8, "znear": 0.1, "zfar": 10, "aspectRatio": 2}}],
            "materials": [{"alphaMode": "BLEND", "doubleSided": false,
                "pbrMetallicRoughness": {"baseColorFactor": [1, 0, 0, 0.5]}}],
            "meshes": [{"primitives": [{"attributes": {"POSITION": 0}, "indices": 1,
                "material": 0}]}],
            "buffers": [{"uri": "quad.bin", "byteLength": 60}],
            "bufferViews": [{"buffer": 0, "byteOffset": 0, "byteLength": 48},
                {"buffer": 0, "byteOffset": 48, "byteLength": 12}],
            "accessors": [
                {"bufferView": 0, "componentType": 5126, "count": 4, "type": "VEC3",
                    "min": [-0.5, -0.5, 0], "max": [0.5, 0.5, 0]},
                {"bufferView": 1, "componentType": 5123, "count": 6, "type": "SCALAR"}
            ]
        }"#;
        let scene = load_written("mirrored", json, &[("quad.bin", &bin)]).expect("loads");
        assert_eq!(scene.transparent.len(), 2);
        let (width, height) = (64, 32);
        let background = glam::Vec3::splat(0.25);
        let image =
            crate::reference::render(&scene, &OpaqueLayer::clear(width, height, background))
                .expect("renders");
        let covered = |xs: std::ops::Range<u32>| {
            (0..height)
                .flat_map(|y| xs.clone().map(move |x| (x, y)))
                .filter(|&(x, y)| {
                    let p = image.pixels[(y * width + x) as usize];
                    (p.truncate() - background).abs().max_element() > 0.01
                })
                .count()
        };
        let (left, right) = (covered(0..width / 2), covered(width / 2..width));
        assert!(left > 0, "the quad itself is drawn");
        assert_eq!(left, right, "the mirrored quad covers what the quad does");
    }

    #[test]
    fn strips_and_fans_keep_winding() {
        let strip = assemble_triangles(Mode::TriangleStrip, &[0, 1, 2, 3]);
        assert_eq!(strip, vec![[0, 1, 2], [1, 3, 2]]);
        let fan = assemble_triangles(Mode::TriangleFan, &[0, 1, 2, 3]);
        assert_eq!(fan, vec![[1, 2, 0], [2, 3, 0]]);
        let list = assemble_triangles(Mode::Triangles, &[0, 1, 2, 2, 2, 3]);
        assert_eq!(list, vec![[0, 1, 2]]);
    }

    #[test]
    fn volume_tint_follows_beer_lambert() {
        let t = volume_tint(Vec3::new(0.25, 0.5, 1.0), 2.0, 1.0);
        assert!((t - Vec3::new(0.0625, 0.25, 1.0)).abs().max_element() < 1e-6);
        assert_eq!(volume_tint(Vec3::ZERO, 1.0, f32::INFINITY), Vec3::ONE);
        assert_eq!(volume_tint(Vec3::ZERO, 0.0, 1.0), Vec3::ONE);
    }

    #[test]
    fn ior_gives_fresnel_reflectance() {
        assert!((fresnel_reflectance(1.5) - 0.04).abs() < 1e-6);
        assert_eq!(fresnel_reflectance(1.0), 0.0);
    }
}
