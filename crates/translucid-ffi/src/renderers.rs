//! The context's renderers. Each is made for one method, size and settings over every asset
//! the context holds (meshes, materials, textures: uploaded once for all the renderers of a
//! generation, `ResidentAssets`), and draws any frame with
//! those settings: a frame only names which assets it draws, where, and from which camera
//! (`Renderer::set_frame`: nothing rebuilt, no shader compiled). Creating or destroying an
//! asset makes the renderers stale: each frame after it gets a new renderer (made before the
//! stale one is freed, so that it takes its compute pipelines), while a stale one lives on
//! until no frame in flight uses it (so that destroying an asset a frame in flight draws is
//! safe). A context keeps a few renderers, so that views of different sizes
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
#[derive(Default)]
struct AssetIndex {
    meshes: HashMap<u64, usize>,
    materials: HashMap<u64, usize>,
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
    /// Meshes moved (`translucid_mesh_update`) since the assets were uploaded: a renderer
    /// made later copies their vertices in with its first frame.
    moved: HashSet<u64>,
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
                let (scene, index) = asset_scene(assets, request)?;
                let options = self
                    .kept
                    .iter()
                    .filter(|k| k.key == request.key)
                    .max_by_key(|k| k.last_used)
                    .map_or_else(
                        || request.options.clone(),
                        |k| k.renderer.learned_options(&request.options),
                    );
                // The renderers it replaces are freed only after it is made: it takes the
                // compute pipelines they hold instead of compiling its own.
                let shape = FrameShape {
                    width: request.width,
                    height: request.height,
                    frames_in_flight: self.frames_in_flight,
                };
                let renderer = match self
                    .resident
                    .as_ref()
                    .filter(|r| r.generation == assets.generation)
                {
                    Some(resident) => {
                        let assets = resident.assets.clone();
                        let mut renderer = Renderer::sharing(
                            gpu,
                            assets,
                            &scene,
                            request.method,
                            shape,
                            &options,
                        )?;
                        for mesh in &resident.moved {
                            if let Some(&i) = index.meshes.get(mesh) {
                                renderer.update_mesh(i, &scene.meshes[i].positions)?;
                            }
                        }
                        renderer
                    }
                    None => {
                        let renderer = Renderer::with_frames_in_flight(
                            gpu,
                            &scene,
                            request.method,
                            request.width,
                            request.height,
                            &options,
                            self.frames_in_flight,
                        )?;
                        self.resident = Some(Resident {
                            generation: assets.generation,
                            assets: renderer.resident().clone(),
                            moved: HashSet::new(),
                        });
                        renderer
                    }
                };
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
fn asset_scene(assets: &Assets<'_>, request: &FrameRequest<'_>) -> FfiResult<(Scene, AssetIndex)> {
    let mut index = AssetIndex::default();
    let mut scene = Scene {
        name: "C API assets".into(),
        camera: request.camera,
        light: request.light,
        background: request.background,
        ..Scene::default()
    };
    for (handle, mesh) in assets.meshes.iter() {
        index.meshes.insert(handle, scene.meshes.len());
        scene.meshes.push(mesh.clone());
    }
    let mut textures = HashMap::new();
    for (handle, texture) in assets.textures.iter() {
        textures.insert(handle, scene.textures.len());
        scene.textures.push(texture.clone());
    }
    for (handle, record) in assets.materials.iter() {
        let texture = match record.texture {
            None => None,
            Some(t) => match textures.get(&t) {
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
