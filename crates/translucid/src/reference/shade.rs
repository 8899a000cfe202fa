//! Turning a covered sample into a fragment: attribute interpolation and texture level of
//! detail, then the shared [`shading::shade_transparent`].

use super::prepare::DrawData;
use crate::raster::{Sample, Triangle};
use crate::scene::{Material, Scene, Texture};
use crate::shading::{self, Fragment};
use glam::{Vec2, Vec3, Vec4};

/// A triangle's vertex attributes, ready for interpolation.
pub struct TriangleShader<'s> {
    scene: &'s Scene,
    material: &'s Material,
    texture: Option<&'s Texture>,
    colours: Option<[Vec4; 3]>,
    /// World-space vertex normals, or the face normal three times.
    normals: [Vec3; 3],
    uvs: Option<[Vec2; 3]>,
}

impl<'s> TriangleShader<'s> {
    pub fn new(scene: &'s Scene, data: &DrawData<'s>, vertices: [u32; 3]) -> Self {
        let mesh = data.mesh;
        let material = &scene.materials[data.draw.material];
        let normals = match (&mesh.normals, &data.world) {
            (Some(n), _) => pick(n, vertices).map(|n| data.normal_matrix * n),
            (None, Some(w)) => {
                let p = pick(w, vertices);
                [shading::face_normal(p[1] - p[0], p[2] - p[0]); 3]
            }
            (None, None) => [Vec3::ZERO; 3],
        };
        Self {
            scene,
            material,
            texture: material.texture.map(|t| &scene.textures[t]),
            colours: tinted_colours(mesh.colours.as_deref(), data.draw.tint, vertices),
            normals,
            uvs: mesh.uvs.as_deref().map(|u| pick(u, vertices)),
        }
    }

    /// The fragment of the sample at pixel `(x, y)` of `tri`.
    pub fn shade(&self, tri: &Triangle, x: u32, y: u32, s: &Sample) -> Fragment {
        let b = s.barycentric;
        let mix3 = |v: [Vec3; 3]| v[0] * b.x + v[1] * b.y + v[2] * b.z;
        let colour = self
            .colours
            .map_or(Vec4::ONE, |c| c[0] * b.x + c[1] * b.y + c[2] * b.z);
        let texel = self
            .texture
            .map_or(Vec4::ONE, |t| self.texel(t, tri, x, y, b));
        shading::shade_transparent(
            self.material,
            &self.scene.light,
            colour,
            texel,
            mix3(self.normals),
        )
    }

    /// Samples the texture with a level of detail from analytic derivatives: Vulkan's
    /// isotropic `ρ = max(|∂uv/∂x|, |∂uv/∂y|)` in level-0 texels, `lod = log2 ρ`, from the
    /// exact screen-space derivative of the perspective-correct UV at the pixel centre (not
    /// from 2×2 finite differences, which a compute rasterizer does not have). A mesh without
    /// UVs samples (0, 0), like an attribute that reads zero.
    fn texel(&self, t: &Texture, tri: &Triangle, x: u32, y: u32, b: Vec3) -> Vec4 {
        let Some(uv) = self.uvs else {
            return t.sample(Vec2::ZERO, 0.0);
        };
        let mix = |w: Vec3| uv[0] * w.x + uv[1] * w.y + uv[2] * w.z;
        let [dbx, dby] = tri.barycentric_gradients(x, y);
        let size = Vec2::new(t.width() as f32, t.height() as f32);
        let rho = (mix(dbx) * size).length().max((mix(dby) * size).length());
        t.sample(mix(b), rho.log2())
    }
}

/// A triangle's vertex colours times the draw's tint, as setup writes them (a mesh without
/// colours has white ones); `None` when there are neither colours nor a tint.
fn tinted_colours(colours: Option<&[Vec4]>, tint: Vec4, vertices: [u32; 3]) -> Option<[Vec4; 3]> {
    match colours {
        Some(c) => Some(pick(c, vertices).map(|c| c * tint)),
        None if tint != Vec4::ONE => Some([tint; 3]),
        None => None,
    }
}

/// The attributes of a triangle's three vertices.
fn pick<T: Copy>(values: &[T], vertices: [u32; 3]) -> [T; 3] {
    vertices.map(|i| values[i as usize])
}
