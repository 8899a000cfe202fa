//! The scene model: what every method and the CPU reference render.
//!
//! A [`Scene`] holds meshes (quads, as the bin rasterizer wants them), materials, textures,
//! an opaque layer of draws, the transparent draws in submission order, a camera and a light.
//! Scenes come from glTF files ([`gltf`]) or are generated ([`generated`]).

#![deny(unsafe_code)]

mod camera;
pub mod generated;
pub mod gltf;
mod material;
mod mesh;
pub mod motion;
mod texture;

pub use camera::{look_at_view, Camera, Projection};
pub use material::Material;
pub use mesh::{pair_triangles, Mesh};
#[cfg(test)]
pub(crate) use texture::hand_cases as texture_hand;
pub use texture::{
    srgb_lut, Filter, MipFilter, Sampler, Texture, Wrap, MAX_SCENE_TEXELS, MAX_TEXTURE_SIZE,
};

use glam::{Mat4, Vec3};

/// One instance of a mesh with a material, a model-to-world transform and a tint.
#[derive(Clone, Debug, PartialEq)]
pub struct Draw {
    pub mesh: usize,
    pub material: usize,
    pub transform: Mat4,
    /// Linear RGBA multiplied into the instance's colour, as a vertex colour is (alpha into
    /// coverage); `Vec4::ONE` for none. Finite and non-negative.
    pub tint: glam::Vec4,
}

/// Ambient light plus one directional light, used by lit materials.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Light {
    /// Direction the light travels *towards* the surface is `-direction`; i.e. this points at
    /// the light. Normalised when the scene is validated.
    pub direction: Vec3,
    pub colour: Vec3,
    pub ambient: Vec3,
}

impl Default for Light {
    fn default() -> Self {
        Self {
            direction: Vec3::new(0.3, 0.8, 0.5).normalize(),
            colour: Vec3::splat(0.8),
            ambient: Vec3::splat(0.35),
        }
    }
}

/// Everything needed to render one frame.
#[derive(Clone, Debug, Default)]
pub struct Scene {
    pub name: String,
    pub meshes: Vec<Mesh>,
    pub materials: Vec<Material>,
    pub textures: Vec<Texture>,
    /// Depth-tested, depth-writing draws rendered first into colour and depth.
    pub opaque: Vec<Draw>,
    /// Transparent draws in submission order (the order unsorted blending uses).
    pub transparent: Vec<Draw>,
    pub camera: Camera,
    pub light: Light,
    /// Linear-light colour behind everything.
    pub background: Vec3,
}

/// What may change from one frame to the next: the camera, the light, and which of a scene's
/// meshes are drawn with which materials, where. The assets (meshes, materials, textures) stay
/// the scene's.
#[derive(Clone, Copy, Debug)]
pub struct FrameInput<'a> {
    pub camera: Camera,
    pub light: Light,
    /// Linear-light colour behind everything.
    pub background: Vec3,
    /// Depth-tested, depth-writing draws rendered first into colour and depth.
    pub opaque: &'a [Draw],
    /// Transparent draws in submission order.
    pub transparent: &'a [Draw],
}

impl Scene {
    /// The scene with its opaque draws made transparent at coverage `alpha` (0 < alpha <= 1),
    /// drawn first, then its own transparent draws: each opaque material gets a copy with base
    /// alpha `alpha` (times its texture's alpha) and no alpha cutoff. Turns any glTF into a
    /// load for the transparent methods (`--blend-alpha`), e.g. a million opaque triangles.
    pub fn opaque_as_transparent(&self, alpha: f32) -> crate::Result<Scene> {
        if !(alpha > 0.0 && alpha <= 1.0) {
            return Err(crate::Error::InvalidScene(format!(
                "blend alpha {alpha} is not in (0, 1]"
            )));
        }
        let mut scene = self.clone();
        let mut copies = std::collections::HashMap::new();
        let mut made = Vec::new();
        for draw in &mut scene.opaque {
            let first = self.materials.len();
            let material = *copies.entry(draw.material).or_insert_with(|| {
                let mut copy = self.materials[draw.material].clone();
                copy.base_colour.w = alpha;
                copy.alpha_cutoff = None;
                copy.name = format!("{} at alpha {alpha}", copy.name);
                made.push(copy);
                first + made.len() - 1
            });
            draw.material = material;
        }
        scene.materials.extend(made);
        scene.transparent = std::mem::take(&mut scene.opaque);
        scene.transparent.extend_from_slice(&self.transparent);
        Ok(scene)
    }

    /// The frame the scene itself describes.
    pub fn frame_input(&self) -> FrameInput<'_> {
        FrameInput {
            camera: self.camera,
            light: self.light,
            background: self.background,
            opaque: &self.opaque,
            transparent: &self.transparent,
        }
    }

    /// A copy without the textures' texels (each level keeps its size): what a renderer
    /// keeps once the textures are uploaded, for the frames to come.
    pub fn without_texels(&self) -> Scene {
        Scene {
            name: self.name.clone(),
            meshes: self.meshes.clone(),
            materials: self.materials.clone(),
            textures: self.textures.iter().map(Texture::without_texels).collect(),
            opaque: self.opaque.clone(),
            transparent: self.transparent.clone(),
            camera: self.camera,
            light: self.light,
            background: self.background,
        }
    }

    /// Makes `input` the scene's frame, after checking it against the scene's assets (the
    /// draw vectors keep their allocations).
    pub fn set_frame(&mut self, input: &FrameInput<'_>) -> crate::Result<()> {
        self.check_frame(input)?;
        self.camera = input.camera;
        self.light = Light {
            direction: input.light.direction.normalize(),
            ..input.light
        };
        self.background = input.background;
        self.opaque.clear();
        self.opaque.extend_from_slice(input.opaque);
        self.transparent.clear();
        self.transparent.extend_from_slice(input.transparent);
        Ok(())
    }

    /// Checks every cross-reference and value a renderer relies on, so that no method has to:
    /// indices in range, finite positions and transforms, textures present.
    pub fn validate(&self) -> crate::Result<()> {
        let bad = |msg: String| Err(crate::Error::InvalidScene(msg));
        for (i, mesh) in self.meshes.iter().enumerate() {
            mesh.validate().map_err(|e| {
                crate::Error::InvalidScene(format!("mesh {i} ({}): {e}", mesh.name))
            })?;
        }
        for (i, m) in self.materials.iter().enumerate() {
            if let Some(t) = m.texture {
                if t >= self.textures.len() {
                    return bad(format!(
                        "material {i} uses texture {t}, scene has {}",
                        self.textures.len()
                    ));
                }
            }
            m.validate()
                .map_err(|e| crate::Error::InvalidScene(format!("material {i}: {e}")))?;
        }
        for (i, t) in self.textures.iter().enumerate() {
            t.validate()
                .map_err(|e| crate::Error::InvalidScene(format!("texture {i}: {e}")))?;
        }
        self.check_frame(&self.frame_input())
    }

    /// Checks a frame's draws, camera and light against this scene's assets.
    pub fn check_frame(&self, input: &FrameInput<'_>) -> crate::Result<()> {
        let bad = |msg: String| Err(crate::Error::InvalidScene(msg));
        let drawn_quads = input
            .opaque
            .iter()
            .chain(input.transparent)
            .filter_map(|d| self.meshes.get(d.mesh))
            .map(|m| m.quads.len() as u64)
            .fold(0u64, u64::saturating_add);
        if drawn_quads > MAX_FRAME_QUADS {
            return bad(format!(
                "the frame draws {drawn_quads} quads (each draw's mesh counted again); \
                 translucid draws at most {MAX_FRAME_QUADS} a frame"
            ));
        }
        for (layer, draws) in [("opaque", input.opaque), ("transparent", input.transparent)] {
            for (i, d) in draws.iter().enumerate() {
                if d.mesh >= self.meshes.len() {
                    return bad(format!(
                        "{layer} draw {i} uses mesh {}, scene has {}",
                        d.mesh,
                        self.meshes.len()
                    ));
                }
                if d.material >= self.materials.len() {
                    return bad(format!(
                        "{layer} draw {i} uses material {}, scene has {}",
                        d.material,
                        self.materials.len()
                    ));
                }
                if !d.transform.is_finite() {
                    return bad(format!("{layer} draw {i} has a non-finite transform"));
                }
                // Projective model matrices are not transforms an engine or glTF makes (glTF
                // requires affine nodes), and one with a w of 1.8e19 put exact off the
                // reference.
                if d.transform.row(3) != glam::Vec4::W {
                    return bad(format!(
                        "{layer} draw {i}: transform's last row is {:?}; a model matrix must \
                         be affine (0, 0, 0, 1)",
                        d.transform.row(3).to_array()
                    ));
                }
                if !crate::shading::is_colour(d.tint) {
                    return bad(format!(
                        "{layer} draw {i}: tint {:?} must be non-negative and at most {}",
                        d.tint.to_array(),
                        crate::shading::MAX_COLOUR
                    ));
                }
            }
        }
        input
            .camera
            .validate()
            .map_err(|e| crate::Error::InvalidScene(format!("camera: {e}")))?;
        let light = &input.light;
        if !light.direction.is_finite() || light.direction.length_squared() == 0.0 {
            return bad("light direction must be finite and non-zero".into());
        }
        for (what, colour) in [
            ("light colour", light.colour),
            ("ambient light", light.ambient),
            ("background", input.background),
        ] {
            if !crate::shading::is_colour(colour.extend(0.0)) {
                return bad(format!(
                    "{what} {:?} must be non-negative and at most {}",
                    colour.to_array(),
                    crate::shading::MAX_COLOUR
                ));
            }
        }
        Ok(())
    }

    /// Number of quads drawn in the transparent layer.
    pub fn transparent_quads(&self) -> usize {
        self.transparent
            .iter()
            .map(|d| self.meshes[d.mesh].quads.len())
            .sum()
    }
}

/// The most quads (of every draw, a mesh drawn twice counted twice) one frame may draw:
/// 32 M, six times the largest scene the tests draw (hairball:5m), where a frame takes
/// minutes on a CPU driver. A 1.6 KB glTF file listing a node 100,000 times drew a
/// 10,000-quad mesh as often: a billion quads, hours of work, before this bound.
pub const MAX_FRAME_QUADS: u64 = 1 << 25;

/// A scene by name: one of the [`generated::NAMES`], a sized one (`hairball:100k`,
/// [`generated::SIZED`]), else a path to a `.gltf`/`.glb` file.
///
/// A spec that names an existing file, or ends in `.gltf`/`.glb`, is loaded as glTF (so a
/// mistyped path reports the missing file); anything else gives
/// [`crate::Error::UnknownScene`] listing the generated names.
pub fn load(spec: &str) -> crate::Result<Scene> {
    load_with(spec, &gltf::ImportOptions::default())
}

/// [`load`], importing a glTF file with `options` (the folders its URIs may reach, the
/// amounts it may take).
pub fn load_with(spec: &str, options: &gltf::ImportOptions) -> crate::Result<Scene> {
    if let Some(scene) = generated::generate(spec) {
        return Ok(scene);
    }
    if let Some(sized) = generated::generate_sized(spec) {
        return sized.map_err(crate::Error::InvalidScene);
    }
    let path = std::path::Path::new(spec);
    let gltf_extension = path
        .extension()
        .is_some_and(|e| e.eq_ignore_ascii_case("gltf") || e.eq_ignore_ascii_case("glb"));
    if path.exists() || gltf_extension {
        return gltf::load_with(path, options);
    }
    Err(crate::Error::UnknownScene(
        spec.to_string(),
        format!(
            "{}, draws<N> for N of 1 to {}, {}",
            generated::NAMES.join(", "),
            generated::MAX_DRAWS,
            generated::SIZED
                .iter()
                .map(|(name, counts)| format!("{name}:N for N {counts}"))
                .collect::<Vec<_>>()
                .join(", ")
        ),
    ))
}
