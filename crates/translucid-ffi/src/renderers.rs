//! The context's renderers. Each is made for one method, size and settings over every asset
//! the context holds (meshes, materials, textures: uploaded once for all the renderers of a
//! generation, `ResidentAssets`), and draws any frame with
//! those settings: a frame only names which assets it draws, where, and from which camera
//! (`Renderer::set_frame`: nothing rebuilt, no shader compiled). Creating assets extends the
//! uploads, and the renderers adopt the extended ones (`Renderer::adopt_assets`). Destroying
//! an asset makes the renderers stale: each frame after it gets a new renderer over a new
//! upload (made before the stale one is freed, so that it takes its compute pipelines),
//! while a stale one lives on until no frame in flight uses it (so that destroying an asset
//! a frame in flight draws is safe). A context keeps a few renderers, so that views of different sizes
//! or methods in one frame loop each keep theirs.

use crate::context::Assets;
use crate::frame::translucid_draw;
use crate::frame::translucid_layer;
use crate::result::{translucid_result, Failure, FfiResult};
use std::collections::{HashMap, HashSet};
use std::sync::Arc;
use translucid::gpu::Gpu;
use translucid::methods::{MethodKind, MethodOptions};
use translucid::renderer::{FrameShape, Renderer, ResidentAssets};
use translucid::scene::{Camera, Draw, FrameInput, Light, Scene};

/// Renderers kept per context; past this, the least recently used one no frame in flight
/// uses is freed.
const MAX_RENDERERS: usize = 4;

/// What decides whether a renderer can draw a frame, besides the assets: method, size and
/// the method's settings, as words.
pub type SettingsKey = Vec<u64>;

/// A frame as a renderer takes it: the settings it needs, and what it draws.
pub struct FrameRequest<'a> {
    pub key: SettingsKey,
    pub method: MethodKind,
    pub width: u32,
    pub height: u32,
    pub options: MethodOptions,
    pub camera: Camera,
    pub light: Light,
    pub background: glam::Vec3,
    pub draws: &'a [translucid_draw],
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
    /// was abandoned, or a recording failed.
    usable: bool,
    /// A completion failed: the core renderer must not be asked again.
    pub failed: bool,
    last_used: u64,
}

/// The context's assets on the GPU, as the renderers of one generation share them.
struct Resident {
    generation: u64,
    assets: Arc<ResidentAssets>,
    /// Where each asset sits in them.
    index: AssetIndex,
    /// Meshes moved (`translucid_mesh_update`) since the assets were uploaded: a renderer
    /// made later copies their vertices in with its first frame.
    moved: HashSet<u64>,
    /// Their buffers had no room for the assets created since: upload everything anew.
    full: bool,
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
}

impl Renderers {
    pub fn new(frames_in_flight: u32) -> Self {
        Self {
            kept: Vec::new(),
            resident: None,
            next_id: 1,
            uses: 0,
            frames_in_flight,
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
        assets: &Assets<'_>,
        request: &FrameRequest<'_>,
    ) -> FfiResult<&mut Kept> {
        self.uses += 1;
        self.adopt_created_assets(gpu, assets, request)?;
        for k in &mut self.kept {
            k.usable &= k.generation == assets.generation;
        }
        let found = self
            .kept
            .iter()
            .position(|k| k.usable && k.key == request.key);
        let position = match found {
            Some(i) => {
                let k = &mut self.kept[i];
                let (opaque, transparent) = resolve_draws(&k.index, assets, request.draws)?;
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
                // Assets only added since the resident ones were made keep their places, so
                // that the new ones are appended to them.
                let base = self
                    .resident
                    .as_ref()
                    .filter(|r| assets.last_destroyed <= r.generation)
                    .map(|r| &r.index);
                let (scene, index) = asset_scene(assets, request, base)?;
                let options = self
                    .kept
                    .iter()
                    .filter(|k| k.key == request.key)
                    .max_by_key(|k| k.last_used)
                    .map_or_else(
                        || request.options.clone(),
                        |k| k.renderer.learned_options(&request.options),
                    );
                let (resident, moved) = self.resident_for(gpu, assets, &scene, &index)?;
                // The renderers it replaces are freed only after it is made: it takes the
                // compute pipelines they hold instead of compiling its own.
                let shape = FrameShape {
                    width: request.width,
                    height: request.height,
                    frames_in_flight: self.frames_in_flight,
                };
                let mut renderer =
                    Renderer::sharing(gpu, resident, &scene, request.method, shape, &options)?;
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
                });
                self.next_id += 1;
                self.free_unused(Some(MAX_RENDERERS));
                self.kept.len() - 1
            }
        };
        let k = &mut self.kept[position];
        k.last_used = self.uses;
        Ok(k)
    }

    /// When assets were only created since the uploads were made, extends the uploads with
    /// them and has every renderer of the uploads' generation draw from the extended ones:
    /// nothing is rebuilt, and the new assets alone are uploaded. (Past the uploads' room,
    /// the renderers go stale and the next ones upload everything anew.)
    fn adopt_created_assets(
        &mut self,
        gpu: &Gpu,
        assets: &Assets<'_>,
        request: &FrameRequest<'_>,
    ) -> FfiResult {
        let Some(resident) = self
            .resident
            .as_mut()
            .filter(|r| r.generation != assets.generation && !r.full)
            .filter(|r| assets.last_destroyed <= r.generation)
        else {
            return Ok(());
        };
        let (scene, index) = asset_scene(assets, request, Some(&resident.index))?;
        let Some(extended) = resident.assets.extended(gpu, &scene)? else {
            resident.full = true;
            return Ok(());
        };
        let extended = Arc::new(extended);
        let before = resident.generation;
        for k in self
            .kept
            .iter_mut()
            .filter(|k| k.usable && k.generation == before)
        {
            k.renderer.adopt_assets(extended.clone(), &scene)?;
            k.index = index.clone();
            k.generation = assets.generation;
        }
        resident.generation = assets.generation;
        resident.assets = extended;
        resident.index = index;
        Ok(())
    }

    /// The assets on the GPU for `scene` (the context's assets in `index`'s places): those
    /// of its generation, else the last ones extended with the assets created since (none
    /// destroyed), else all of them uploaded anew; and the meshes moved since the upload.
    fn resident_for(
        &mut self,
        gpu: &Gpu,
        assets: &Assets<'_>,
        scene: &Scene,
        index: &AssetIndex,
    ) -> FfiResult<(Arc<ResidentAssets>, HashSet<u64>)> {
        let current = self.resident.as_ref().map(|r| r.generation);
        if current != Some(assets.generation) {
            let extended = match self
                .resident
                .as_ref()
                .filter(|r| assets.last_destroyed <= r.generation && !r.full)
            {
                Some(r) => r.assets.extended(gpu, scene)?,
                None => None,
            };
            let moved = match (&extended, self.resident.take()) {
                (Some(_), Some(r)) => r.moved,
                _ => HashSet::new(),
            };
            let uploaded = match extended {
                Some(assets) => assets,
                None => ResidentAssets::new(gpu, scene)?,
            };
            self.resident = Some(Resident {
                generation: assets.generation,
                assets: Arc::new(uploaded),
                index: index.clone(),
                moved,
                full: false,
            });
        }
        self.resident
            .as_ref()
            .map(|r| (r.assets.clone(), r.moved.clone()))
            .ok_or_else(|| Failure::argument("no resident assets"))
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
    pub fn update_mesh(&mut self, handle: u64, positions: &[glam::Vec3]) -> FfiResult {
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

/// The context's assets as one scene, with the frame of `request`: every mesh and texture,
/// and every material whose texture is alive (drawing one whose texture was destroyed is an
/// error of the frame).
fn asset_scene(
    assets: &Assets<'_>,
    request: &FrameRequest<'_>,
    base: Option<&AssetIndex>,
) -> FfiResult<(Scene, AssetIndex)> {
    let mut index = AssetIndex::default();
    let mut scene = Scene {
        name: "C API assets".into(),
        camera: request.camera,
        light: request.light,
        background: request.background,
        ..Scene::default()
    };
    for (handle, mesh) in in_place(assets.meshes.iter(), base.map(|b| &b.meshes)) {
        index.meshes.insert(handle, scene.meshes.len());
        scene.meshes.push(mesh.clone());
    }
    for (handle, texture) in in_place(assets.textures.iter(), base.map(|b| &b.textures)) {
        index.textures.insert(handle, scene.textures.len());
        scene.textures.push(texture.clone());
    }
    for (handle, record) in in_place(assets.materials.iter(), base.map(|b| &b.materials)) {
        let texture = match record.texture {
            None => None,
            Some(t) => match index.textures.get(&t) {
                Some(&i) => Some(i),
                None => continue,
            },
        };
        index.materials.insert(handle, scene.materials.len());
        scene.materials.push(translucid::scene::Material {
            texture,
            ..record.material.clone()
        });
    }
    let (opaque, transparent) = resolve_draws(&index, assets, request.draws)?;
    scene.opaque = opaque;
    scene.transparent = transparent;
    scene.validate()?;
    Ok((scene, index))
}

/// The frame's draws as indices into a renderer's scene, opaque and transparent.
fn resolve_draws(
    index: &AssetIndex,
    assets: &Assets<'_>,
    draws: &[translucid_draw],
) -> FfiResult<(Vec<Draw>, Vec<Draw>)> {
    let mut opaque = Vec::new();
    let mut transparent = Vec::new();
    for (i, d) in draws.iter().enumerate() {
        let in_draw = |f: Failure| Failure::new(f.code, format!("draws[{i}]: {}", f.message));
        let mesh = match index.meshes.get(&d.mesh.id) {
            Some(&m) => m,
            None => {
                // Not in the renderer's scene: the handle is bad (say how) or stale.
                assets.meshes.get(d.mesh.id).map_err(in_draw)?;
                return Err(in_draw(Failure::argument("mesh unknown to the renderer")));
            }
        };
        let material = match index.materials.get(&d.material.id) {
            Some(&m) => m,
            None => {
                assets.materials.get(d.material.id).map_err(in_draw)?;
                return Err(in_draw(Failure::new(
                    translucid_result::ErrorStaleHandle,
                    "its material's texture was destroyed",
                )));
            }
        };
        let transform = glam::Mat4::from_cols_array(&d.transform);
        if !transform.is_finite() {
            return Err(in_draw(Failure::argument("transform is not finite")));
        }
        let tint = match glam::Vec4::from_array(d.tint) {
            t if t == glam::Vec4::ZERO => glam::Vec4::ONE,
            t if t.is_finite() && t.min_element() >= 0.0 => t,
            t => {
                return Err(in_draw(Failure::argument(format!(
                    "tint {:?} must be finite and non-negative",
                    t.to_array()
                ))))
            }
        };
        let draw = Draw {
            mesh,
            material,
            transform,
            tint,
        };
        match d.layer {
            l if l == translucid_layer::Transparent as u32 => transparent.push(draw),
            l if l == translucid_layer::Opaque as u32 => opaque.push(draw),
            l => return Err(in_draw(Failure::enumeration("translucid_layer", l))),
        }
    }
    Ok((opaque, transparent))
}

/// `items` (handle, asset) with those `base` places first, in its order, then the others as
/// they come.
fn in_place<'a, T>(
    items: impl Iterator<Item = (u64, &'a T)>,
    base: Option<&HashMap<u64, usize>>,
) -> Vec<(u64, &'a T)> {
    let mut items: Vec<_> = items.collect();
    if let Some(base) = base {
        // A stable sort: the new ones keep their order after the placed ones.
        items.sort_by_key(|(handle, _)| base.get(handle).map_or((1, 0), |&i| (0, i)));
    }
    items
}
