//! The context's renderers. Each is made for one method and its settings over every asset the
//! context holds (meshes, materials, textures: uploaded once for all the renderers of a
//! generation, `ResidentAssets`), and draws any frame with those settings up to the largest
//! size it was made for: a frame only names its size, which assets it draws, where, and from
//! which camera (`Renderer::set_size`, `Renderer::set_frame`: nothing rebuilt, no shader
//! compiled). A frame larger than the renderer in either side gets a new renderer for the
//! larger of both sizes, which then serves both. Creating assets extends the
//! uploads, and the renderers adopt the extended ones (`Renderer::adopt_assets`). A destroyed
//! asset keeps its place in the uploads (its data in a graveyard) while most of them is
//! alive; past that, the renderers go stale: each frame after it gets a new renderer over a
//! new upload (made before the stale one is freed, so that it takes its compute pipelines),
//! while a stale one lives on until no frame in flight uses it (so that destroying an asset
//! a frame in flight draws is safe). A context keeps a few renderers, so that views of
//! different methods in one frame loop each keep theirs.

use super::assets::{Assets, Destroyed, MaterialRecord};
use crate::gpu::Gpu;
use crate::methods::bins::features::DeclaredContent;
use crate::methods::{MethodKind, MethodOptions};
use crate::renderer::{FrameShape, Renderer, ResidentAssets};
use crate::scene::{Camera, Draw, FrameInput, Light, Mesh, Scene, Texture};
use crate::{Error, Result};
use std::collections::{HashMap, HashSet};
use std::sync::Arc;

/// Renderers kept per context; past this, the least recently used one no frame in flight
/// uses is freed.
const MAX_RENDERERS: usize = 4;

/// What decides whether a renderer can draw a frame, besides the assets and its size: the
/// method and its settings, as words.
pub type SettingsKey = Vec<u64>;

/// A frame as a renderer takes it: the settings it needs, and what it draws.
pub struct FrameRequest {
    pub key: SettingsKey,
    pub method: MethodKind,
    pub width: u32,
    pub height: u32,
    pub options: MethodOptions,
    pub camera: Camera,
    pub light: Light,
    pub background: glam::Vec3,
    pub draws: Vec<DrawRequest>,
    /// The engine's frame number (0: none): views of one frame share it.
    pub frame_index: u64,
}

/// Which layer a draw is in.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Layer {
    /// Drawn into the opaque layer (standalone frames without a caller's opaque layer).
    Opaque,
    Transparent,
}

/// One draw of a frame, by handle: a mesh with a material, placed by `transform` (finite)
/// and tinted by `tint` (a colour: ONE for none).
#[derive(Clone, Copy, Debug)]
pub struct DrawRequest {
    pub mesh: u64,
    pub material: u64,
    pub transform: glam::Mat4,
    pub tint: glam::Vec4,
    pub layer: Layer,
}

/// Where each asset handle sits in a renderer's scene.
#[derive(Clone, Default)]
struct AssetIndex {
    meshes: HashMap<u64, usize>,
    materials: HashMap<u64, usize>,
    textures: HashMap<u64, usize>,
}

/// One renderer and what it was made for.
pub struct Kept {
    pub id: u64,
    key: SettingsKey,
    generation: u64,
    pub renderer: Renderer,
    index: AssetIndex,
    /// Host-device frames recorded with it and not yet completed or abandoned.
    pub in_flight: usize,
    /// False once it must take no new frame: its assets are stale, a frame recorded with it
    /// was abandoned, a recording failed, or a larger renderer with its settings replaced it.
    usable: bool,
    /// A completion failed: the core renderer must not be asked again.
    pub failed: bool,
    last_used: u64,
    /// The options it was made with (its settings, and what earlier ones learned).
    made_with: MethodOptions,
}

/// Destroyed assets the uploads still hold, by handle: a scene over the uploads keeps them
/// in their places (never drawn), so that the uploads stay valid and go on growing.
#[derive(Default)]
struct Graveyard {
    meshes: HashMap<u64, Mesh>,
    textures: HashMap<u64, Texture>,
    materials: HashMap<u64, MaterialRecord>,
    /// Their vertices' and texels' bytes.
    bytes: u64,
}

/// Bytes of a mesh's vertices and quads as uploaded, and of a texture's texels (every
/// level).
fn mesh_bytes(mesh: &Mesh) -> u64 {
    mesh.positions.len() as u64 * 48 + mesh.quads.len() as u64 * 40
}

fn scene_bytes(scene: &Scene) -> u64 {
    scene.meshes.iter().map(mesh_bytes).sum::<u64>()
        + scene.textures.iter().map(Texture::texel_bytes).sum::<u64>()
}

/// The context's assets on the GPU, as the renderers of one generation share them.
struct Resident {
    generation: u64,
    assets: Arc<ResidentAssets>,
    /// Where each asset sits in them, destroyed ones kept in place included.
    places: AssetIndex,
    /// The destroyed ones, kept while most of the uploads' bytes (`bytes`) are alive.
    graveyard: Graveyard,
    bytes: u64,
    /// Meshes moved (`translucid_mesh_update`) since the assets were uploaded: a renderer
    /// made later copies their vertices in with its first frame.
    moved: HashSet<u64>,
}

/// What a renderer is made from, owned, so that another thread can make it
/// ([`Renderers::inputs_for`]).
pub struct RendererInputs {
    gpu: Gpu,
    resident: Arc<ResidentAssets>,
    scene: Scene,
    method: MethodKind,
    shape: FrameShape,
    options: MethodOptions,
}

impl RendererInputs {
    pub fn gpu(&self) -> &Gpu {
        &self.gpu
    }

    /// Makes the renderer, and with `engine_images` (colour, depth) what its first frame
    /// into such images builds ([`Renderer::prepare_host`]).
    pub fn build(
        &self,
        engine_images: Option<(crate::gpu::HostImage, crate::gpu::HostImage)>,
    ) -> Result<Renderer> {
        let mut renderer = Renderer::sharing(
            &self.gpu,
            self.resident.clone(),
            &self.scene,
            self.method,
            self.shape,
            &self.options,
        )?;
        if let Some((colour, depth)) = engine_images {
            renderer.prepare_host(&colour, &depth)?;
        }
        Ok(renderer)
    }
}

/// The context's renderers.
pub struct Renderers {
    kept: Vec<Kept>,
    /// The assets the renderers of the current generation share.
    resident: Option<Resident>,
    next_id: u64,
    uses: u64,
    /// The most frames in flight each renderer serves (the context's).
    frames_in_flight: u32,
    /// What the engine declared its frames may draw: every renderer's shaders cover it.
    declared: DeclaredContent,
    /// The engine prepared the loop: frames past the declaration draw with the superset
    /// variant (`BinOptions::prepared`).
    prepared: bool,
    /// The device's pipelines when a renderer was last made to replace others: those its
    /// first frames build on first use (the passes made for the engine's images) are the
    /// replaced ones', kept for it after they go.
    replaced_pipelines: Option<crate::gpu::HeldPipelines>,
    /// What the frames prepared with each settings drew, declared for the renderers with
    /// those settings alone (so that preparing another method does not widen them).
    drawn: HashMap<SettingsKey, DeclaredContent>,
    /// What the renderers freed by a trim learned (buffer sizes, passes), by their settings:
    /// the next ones with those settings start there.
    learned: HashMap<SettingsKey, MethodOptions>,
}

impl Renderers {
    pub fn new(frames_in_flight: u32) -> Self {
        Self {
            kept: Vec::new(),
            resident: None,
            next_id: 1,
            uses: 0,
            frames_in_flight,
            declared: DeclaredContent::default(),
            prepared: false,
            drawn: HashMap::new(),
            replaced_pipelines: None,
            learned: HashMap::new(),
        }
    }

    /// Adds `content` to what frames may draw, the loop prepared from now on. Renderers
    /// made before a declaration that adds to it (or before the first) take no new frame:
    /// the next ones cover all of it.
    pub fn declare(&mut self, content: DeclaredContent) {
        let declared = self.declared.union(content);
        if declared != self.declared || !self.prepared {
            self.declared = declared;
            self.prepared = true;
            for k in &mut self.kept {
                k.usable = false;
            }
            self.free_unused(None);
        }
    }

    /// Adds `drawn` to what the frames with settings `key` may draw. Their renderers made
    /// before a declaration that adds to it take no new frame.
    pub fn declare_drawn(&mut self, key: &SettingsKey, drawn: DeclaredContent) {
        let declared = self.drawn.entry(key.clone()).or_default();
        let widened = declared.union(drawn);
        if widened != *declared {
            *declared = widened;
            for k in &mut self.kept {
                k.usable &= k.key != *key;
            }
            self.free_unused(None);
        }
    }

    pub fn get_mut(&mut self, id: u64) -> Option<&mut Kept> {
        self.kept.iter_mut().find(|k| k.id == id)
    }

    fn position(&self, id: u64) -> usize {
        self.kept
            .iter()
            .position(|k| k.id == id)
            .expect("a usable renderer is never freed")
    }

    /// The renderer for `request`, set to that frame: the kept one with its settings over
    /// the current assets, else a new one (starting from the buffer sizes the last one with
    /// the same settings learned).
    pub fn for_frame(
        &mut self,
        gpu: &Gpu,
        assets: &Assets,
        request: &FrameRequest,
    ) -> Result<&mut Kept> {
        self.uses += 1;
        self.adopt_created_assets(gpu, assets, request)?;
        for k in &mut self.kept {
            k.usable &= k.generation == assets.generation;
        }
        // A renderer with the settings serves frames up to its size; a larger frame makes one
        // for the larger of both, which replaces it.
        let size = (request.width, request.height);
        let mut largest = size;
        let mut found = None;
        for (i, k) in self.kept.iter().enumerate() {
            if k.usable && k.key == request.key {
                let (width, height) = k.renderer.max_size();
                if width >= size.0 && height >= size.1 {
                    found = Some(i);
                }
                largest = (largest.0.max(width), largest.1.max(height));
            }
        }
        let position = match found {
            Some(i) => {
                let k = &mut self.kept[i];
                k.renderer.set_size(size.0, size.1)?;
                let (opaque, transparent) = resolve_draws(&k.index, assets, &request.draws)?;
                k.renderer.set_frame(&FrameInput {
                    camera: request.camera,
                    light: request.light,
                    background: request.background,
                    opaque: &opaque,
                    transparent: &transparent,
                })?;
                let id = k.id;
                self.free_unused(None);
                self.position(id)
            }
            None => {
                let built = self.scene_for(assets, request)?;
                let options = self.options_for(request, self.declared);
                let (resident, moved) = self.resident_for(gpu, assets, &built)?;
                let AssetScene {
                    scene,
                    lookup: index,
                    ..
                } = built;
                // The renderers it replaces are freed only after it is made: it takes the
                // compute pipelines they hold instead of compiling its own.
                let shape = FrameShape {
                    width: largest.0,
                    height: largest.1,
                    frames_in_flight: self.frames_in_flight,
                };
                let mut renderer =
                    Renderer::sharing(gpu, resident, &scene, request.method, shape, &options)?;
                renderer.set_size(size.0, size.1)?;
                // The smaller ones with the settings take no new frame (and go once none in
                // flight uses them).
                for k in &mut self.kept {
                    k.usable &= k.key != request.key;
                }
                // Vertices moved since the upload are copied in by its first frame.
                for mesh in &moved {
                    if let Some(&i) = index.meshes.get(mesh) {
                        renderer.update_mesh(i, &scene.meshes[i].positions)?;
                    }
                }
                self.kept.push(Kept {
                    id: self.next_id,
                    key: request.key.clone(),
                    generation: assets.generation,
                    renderer,
                    index,
                    in_flight: 0,
                    usable: true,
                    failed: false,
                    last_used: self.uses,
                    made_with: options,
                });
                self.next_id += 1;
                self.replaced_pipelines = Some(gpu.hold_pipelines());
                self.free_unused(Some(MAX_RENDERERS));
                self.kept.len() - 1
            }
        };
        let k = &mut self.kept[position];
        k.last_used = self.uses;
        Ok(k)
    }

    /// The scene of every asset for `request`: over the current uploads, it keeps their
    /// places (destroyed assets' included); otherwise it is made, to be uploaded, anew.
    fn scene_for(&self, assets: &Assets, request: &FrameRequest) -> Result<AssetScene> {
        let base = self
            .resident
            .as_ref()
            .filter(|r| r.generation == assets.generation)
            .map(|r| (&r.places, &r.graveyard));
        asset_scene(assets, request, base)
    }

    /// The options a new renderer for `request` starts from: where the last one with its
    /// settings left its buffers (or what a trim kept of them), with `declared` content.
    fn options_for(&self, request: &FrameRequest, declared: DeclaredContent) -> MethodOptions {
        let mut options = self
            .kept
            .iter()
            .filter(|k| k.key == request.key)
            .max_by_key(|k| k.last_used)
            .map_or_else(
                || {
                    self.learned
                        .get(&request.key)
                        .cloned()
                        .unwrap_or_else(|| request.options.clone())
                },
                |k| k.renderer.learned_options(&request.options),
            );
        let drawn = self.drawn.get(&request.key).copied().unwrap_or_default();
        options.bins.declared = declared.union(drawn);
        options.bins.prepared = self.prepared;
        options
    }

    /// What `request`'s frame draws over the current assets: a prepared loop declares it
    /// besides what the engine names.
    pub fn drawn_content(
        &self,
        assets: &Assets,
        request: &FrameRequest,
    ) -> Result<DeclaredContent> {
        let built = self.scene_for(assets, request)?;
        Ok(DeclaredContent::drawn_by(
            &built.scene,
            request.width,
            request.height,
        ))
    }

    /// What a renderer for `request` over the current assets would be made from, were
    /// `content` and what the frame draws declared besides what is: for building its
    /// pipelines on another thread ([`RendererInputs::build`]); and what the frame draws.
    /// Uploads the assets if no renderer drew them yet.
    pub fn inputs_for(
        &mut self,
        gpu: &Gpu,
        assets: &Assets,
        request: &FrameRequest,
        content: DeclaredContent,
    ) -> Result<(RendererInputs, DeclaredContent)> {
        self.adopt_created_assets(gpu, assets, request)?;
        let built = self.scene_for(assets, request)?;
        let drawn = DeclaredContent::drawn_by(&built.scene, request.width, request.height);
        let declared = self.declared.union(content).union(drawn);
        let mut options = self.options_for(request, declared);
        options.bins.prepared = true;
        let (resident, _moved) = self.resident_for(gpu, assets, &built)?;
        let inputs = RendererInputs {
            gpu: gpu.clone(),
            resident,
            scene: built.scene,
            method: request.method,
            shape: FrameShape {
                width: request.width,
                height: request.height,
                frames_in_flight: self.frames_in_flight,
            },
            options,
        };
        Ok((inputs, drawn))
    }

    /// When assets were created, or destroyed with the uploads keeping their places, since
    /// the uploads were made, extends the uploads with the new ones and has every renderer
    /// of the uploads' generation draw from the extended ones: nothing is rebuilt, and the
    /// new assets alone are uploaded. (Past the uploads' room, the renderers go stale and
    /// the next ones upload everything anew.)
    fn adopt_created_assets(
        &mut self,
        gpu: &Gpu,
        assets: &Assets,
        request: &FrameRequest,
    ) -> Result<()> {
        let Some(resident) = self
            .resident
            .as_mut()
            .filter(|r| r.generation != assets.generation)
            .filter(|r| assets.last_destroyed <= r.generation)
        else {
            return Ok(());
        };
        let built = asset_scene(
            assets,
            request,
            Some((&resident.places, &resident.graveyard)),
        )?;
        if !built.on_base {
            return Ok(());
        }
        let Some(extended) = resident.assets.extended(gpu, &built.scene)? else {
            return Ok(());
        };
        let extended = Arc::new(extended);
        let before = resident.generation;
        for k in self
            .kept
            .iter_mut()
            .filter(|k| k.usable && k.generation == before)
        {
            k.renderer.adopt_assets(extended.clone(), &built.scene)?;
            k.index = built.lookup.clone();
            k.generation = assets.generation;
        }
        resident.generation = assets.generation;
        resident.assets = extended;
        resident.bytes = scene_bytes(&built.scene);
        resident.places = built.places;
        Ok(())
    }

    /// The assets on the GPU for `built`: those of its generation when `built` keeps their
    /// places, else `built`'s assets uploaded anew; and the meshes moved since the upload.
    /// (Assets created since the uploads were extended with them before, when they fit:
    /// `adopt_created_assets`.)
    fn resident_for(
        &mut self,
        gpu: &Gpu,
        assets: &Assets,
        built: &AssetScene,
    ) -> Result<(Arc<ResidentAssets>, HashSet<u64>)> {
        let current = self.resident.as_ref().map(|r| r.generation);
        if current != Some(assets.generation) || !built.on_base {
            self.resident = Some(Resident {
                generation: assets.generation,
                assets: Arc::new(ResidentAssets::new(gpu, &built.scene)?),
                places: built.places.clone(),
                graveyard: Graveyard::default(),
                bytes: scene_bytes(&built.scene),
                moved: HashSet::new(),
            });
        }
        self.resident
            .as_ref()
            .map(|r| (r.assets.clone(), r.moved.clone()))
            .ok_or_else(|| Error::Internal("no resident assets".into()))
    }

    /// Keeps a destroyed asset's place in the uploads. False when the uploads should be
    /// made anew: most of their bytes are destroyed assets.
    pub fn bury(&mut self, destroyed: Destroyed) -> bool {
        let Some(r) = &mut self.resident else {
            return true;
        };
        let g = &mut r.graveyard;
        let bytes = match destroyed {
            Destroyed::Mesh(h, m) if r.places.meshes.contains_key(&h) => {
                let bytes = mesh_bytes(&m);
                g.meshes.insert(h, m);
                bytes
            }
            Destroyed::Texture(h, t) if r.places.textures.contains_key(&h) => {
                let bytes = t.texel_bytes();
                g.textures.insert(h, t);
                bytes
            }
            Destroyed::Material(h, m) if r.places.materials.contains_key(&h) => {
                g.materials.insert(h, m);
                0
            }
            // Never uploaded: nothing to keep.
            _ => return true,
        };
        g.bytes += bytes;
        2 * g.bytes <= r.bytes
    }

    /// A frame in flight recorded with renderer `id` ended (completed or abandoned).
    pub fn frame_ended(&mut self, id: u64) {
        if let Some(k) = self.get_mut(id) {
            k.in_flight = k.in_flight.saturating_sub(1);
        }
    }

    /// The newest `frames` frames in flight recorded with renderer `id` were abandoned: it
    /// forgets them and takes the next frame with everything it built (pipelines, grown
    /// buffers). A renderer that failed, or cannot forget them, takes no new frame.
    pub fn frames_abandoned(&mut self, id: u64, frames: usize) {
        if let Some(k) = self.get_mut(id) {
            k.in_flight = k.in_flight.saturating_sub(frames);
            if k.failed || k.renderer.abandon_host(frames).is_err() {
                k.usable = false;
            }
        }
        self.free_unused(None);
    }

    /// Frees every renderer no frame in flight uses (their frame targets and working
    /// buffers), keeping what they learned for the next ones with their settings. The
    /// assets stay uploaded.
    pub fn free_idle(&mut self) {
        let mut idle: Vec<&Kept> = self
            .kept
            .iter()
            .filter(|k| k.in_flight == 0 && !k.failed)
            .collect();
        // The most recently used one of some settings is the one that learned last.
        idle.sort_by_key(|k| k.last_used);
        for k in idle {
            self.learned
                .insert(k.key.clone(), k.renderer.learned_options(&k.made_with));
        }
        self.kept.retain(|k| k.in_flight > 0);
    }

    /// Makes the renderer take no new frame (freed once no frame in flight uses it).
    pub fn retire(&mut self, id: u64) {
        if let Some(k) = self.get_mut(id) {
            k.usable = false;
        }
        self.free_unused(None);
    }

    /// Frees the renderers that take no new frame and serve none in flight; with `keep`, also
    /// the least recently used idle ones past that many, the last one made aside.
    pub fn free_unused(&mut self, keep: Option<usize>) {
        self.kept.retain(|k| k.usable || k.in_flight > 0);
        if let Some(keep) = keep {
            let newest = self.next_id - 1;
            while self.kept.len() > keep {
                let Some(oldest) = self
                    .kept
                    .iter()
                    .enumerate()
                    .filter(|(_, k)| k.in_flight == 0 && k.id != newest)
                    .min_by_key(|(_, k)| k.last_used)
                    .map(|(i, _)| i)
                else {
                    break;
                };
                self.kept.remove(oldest);
            }
        }
    }

    /// Moves mesh `handle`'s vertices in every renderer that takes new frames (the others
    /// draw what they were recorded with and are freed once done).
    pub fn update_mesh(&mut self, handle: u64, positions: &[glam::Vec3]) -> Result<()> {
        if let Some(resident) = &mut self.resident {
            resident.moved.insert(handle);
        }
        for k in self.kept.iter_mut().filter(|k| k.usable) {
            if let Some(&mesh) = k.index.meshes.get(&handle) {
                k.renderer.update_mesh(mesh, positions)?;
            }
        }
        Ok(())
    }
}

/// The context's assets as one scene, and where each handle sits in it.
struct AssetScene {
    scene: Scene,
    /// Every asset of the scene, the destroyed ones kept in place included.
    places: AssetIndex,
    /// What a frame may draw: live assets, and materials whose texture is live.
    lookup: AssetIndex,
    /// Whether the uploads' assets (`base`) are first, in their places.
    on_base: bool,
}

/// The context's assets as one scene, with the frame of `request`: every mesh and texture,
/// and every material (drawing one whose texture was destroyed is an error of the frame).
/// With `base` (the uploads' places and the destroyed assets they keep), those assets come
/// first in their places, then the others.
fn asset_scene(
    assets: &Assets,
    request: &FrameRequest,
    base: Option<(&AssetIndex, &Graveyard)>,
) -> Result<AssetScene> {
    let places = base.map(|(p, _)| p);
    let graveyard = base.map(|(_, g)| g);
    let meshes = in_place(
        assets.meshes.iter(),
        places.map(|p| &p.meshes),
        graveyard.map(|g| &g.meshes),
    );
    let textures = in_place(
        assets.textures.iter(),
        places.map(|p| &p.textures),
        graveyard.map(|g| &g.textures),
    );
    let materials = in_place(
        assets.materials.iter(),
        places.map(|p| &p.materials),
        graveyard.map(|g| &g.materials),
    );
    let on_base = base.is_some() && meshes.is_some() && textures.is_some() && materials.is_some();
    let (meshes, textures, materials) = match (meshes, textures, materials) {
        (Some(m), Some(t), Some(ma)) => (m, t, ma),
        // A place the uploads had is lost: the assets as they come.
        _ => (
            in_place(assets.meshes.iter(), None, None).unwrap_or_default(),
            in_place(assets.textures.iter(), None, None).unwrap_or_default(),
            in_place(assets.materials.iter(), None, None).unwrap_or_default(),
        ),
    };
    let mut places = AssetIndex::default();
    let mut index = AssetIndex::default();
    let mut scene = Scene {
        name: "C API assets".into(),
        camera: request.camera,
        light: request.light,
        background: request.background,
        ..Scene::default()
    };
    for (handle, mesh, live) in meshes {
        places.meshes.insert(handle, scene.meshes.len());
        if live {
            index.meshes.insert(handle, scene.meshes.len());
        }
        scene.meshes.push(mesh.clone());
    }
    for (handle, texture, live) in textures {
        places.textures.insert(handle, scene.textures.len());
        if live {
            index.textures.insert(handle, scene.textures.len());
        }
        scene.textures.push(texture.clone());
    }
    for (handle, record, live) in materials {
        // A material whose texture is gone keeps its place over the uploads (the texture
        // kept too); a scene made anew leaves it out.
        let (texture, drawable) = match record.texture {
            None => (None, true),
            Some(t) => match (index.textures.get(&t), places.textures.get(&t)) {
                (Some(&i), _) => (Some(i), true),
                (None, Some(&i)) => (Some(i), false),
                _ => continue,
            },
        };
        places.materials.insert(handle, scene.materials.len());
        if live && drawable {
            index.materials.insert(handle, scene.materials.len());
        }
        scene.materials.push(crate::scene::Material {
            texture,
            ..record.material.clone()
        });
    }
    let (opaque, transparent) = resolve_draws(&index, assets, &request.draws)?;
    scene.opaque = opaque;
    scene.transparent = transparent;
    scene.validate()?;
    Ok(AssetScene {
        scene,
        places,
        lookup: index,
        on_base,
    })
}

/// The frame's draws as indices into a renderer's scene, opaque and transparent.
fn resolve_draws(
    index: &AssetIndex,
    assets: &Assets,
    draws: &[DrawRequest],
) -> Result<(Vec<Draw>, Vec<Draw>)> {
    let mut opaque = Vec::new();
    let mut transparent = Vec::new();
    for (i, d) in draws.iter().enumerate() {
        let in_draw = |e: Error| e.prefixed(&format!("draws[{i}]"));
        let mesh = match index.meshes.get(&d.mesh) {
            Some(&m) => m,
            None => {
                // Not in the renderer's scene: the handle is bad (say how) or stale.
                assets.meshes.get(d.mesh).map_err(in_draw)?;
                return Err(in_draw(Error::InvalidArgument(
                    "mesh unknown to the renderer".into(),
                )));
            }
        };
        let material = match index.materials.get(&d.material) {
            Some(&m) => m,
            None => {
                assets.materials.get(d.material).map_err(in_draw)?;
                return Err(in_draw(Error::StaleHandle(
                    "its material's texture was destroyed".into(),
                )));
            }
        };
        let draw = Draw {
            mesh,
            material,
            transform: d.transform,
            tint: d.tint,
        };
        match d.layer {
            Layer::Transparent => transparent.push(draw),
            Layer::Opaque => opaque.push(draw),
        }
    }
    Ok((opaque, transparent))
}

/// `live` (handle, asset) with, when `places` are given, the assets placed there first in
/// their order (live, or from `buried`), then the others as they come; each marked live or
/// not. `None` when a place is neither.
fn in_place<'a, T>(
    live: impl Iterator<Item = (u64, &'a T)>,
    places: Option<&HashMap<u64, usize>>,
    buried: Option<&'a HashMap<u64, T>>,
) -> Option<Vec<(u64, &'a T, bool)>> {
    let live: Vec<(u64, &T)> = live.collect();
    let Some(places) = places else {
        return Some(live.into_iter().map(|(h, t)| (h, t, true)).collect());
    };
    let by_handle: HashMap<u64, &T> = live.iter().copied().collect();
    let mut placed: Vec<(usize, u64)> = places.iter().map(|(&h, &i)| (i, h)).collect();
    placed.sort_unstable();
    let mut out = Vec::with_capacity(live.len().max(placed.len()));
    for (_, handle) in placed {
        match (by_handle.get(&handle), buried.and_then(|b| b.get(&handle))) {
            (Some(t), _) => out.push((handle, *t, true)),
            (None, Some(t)) => out.push((handle, t, false)),
            (None, None) => return None,
        }
    }
    out.extend(
        live.into_iter()
            .filter(|(h, _)| !places.contains_key(h))
            .map(|(h, t)| (h, t, true)),
    );
    Some(out)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Over the uploads' places, live assets keep theirs, destroyed ones come from the
    /// graveyard (not drawable), new ones follow; a place neither live nor buried means the
    /// uploads cannot be kept.
    #[test]
    fn assets_keep_their_places_over_the_uploads() {
        let live: Vec<(u64, &str)> = vec![(10, "a"), (30, "c"), (40, "d")];
        let places: HashMap<u64, usize> = [(10, 0), (20, 1), (30, 2)].into();
        let buried: HashMap<u64, &str> = [(20, "b")].into();
        let placed = in_place(
            live.iter().map(|(h, t)| (*h, t)),
            Some(&places),
            Some(&buried),
        )
        .expect("every place is live or buried");
        let order: Vec<(u64, &str, bool)> = placed.iter().map(|(h, t, l)| (*h, **t, *l)).collect();
        assert_eq!(
            order,
            [
                (10, "a", true),
                (20, "b", false),
                (30, "c", true),
                (40, "d", true)
            ]
        );
        // Without the graveyard, the destroyed asset's place is lost.
        assert!(in_place(live.iter().map(|(h, t)| (*h, t)), Some(&places), None).is_none());
        // Without places, the live assets as they come.
        let fresh = in_place(live.iter().map(|(h, t)| (*h, t)), None, None).expect("fresh");
        assert_eq!(fresh.len(), 3);
        assert!(fresh.iter().all(|(_, _, live)| *live));
    }
}
