//! Per-frame preparation: vertices transformed once per draw, triangles set up, culled and
//! binned to screen tiles.

use crate::raster::{self, Facing, PixelRect, Triangle};
use crate::scene::{Draw, Mesh, Scene};
use glam::{Mat3, Mat4, Vec3, Vec4};
use rayon::prelude::*;

/// Tile edge in pixels: small enough to balance threads, big enough that most triangles
/// land in one tile.
pub const TILE: u32 = 32;

/// Quads set up per parallel job while binning.
const QUADS_PER_JOB: usize = 4096;

/// A transparent draw's vertices in the frame.
pub struct DrawData<'s> {
    pub draw: &'s Draw,
    pub mesh: &'s Mesh,
    pub clip: Vec<Vec4>,
    /// World positions, only for meshes without normals (for face normals).
    pub world: Option<Vec<Vec3>>,
    /// Transforms normals to world space: the cofactor matrix, i.e. the inverse-transpose
    /// scaled by the determinant. Shading normalises and is two-sided, so scale and sign do
    /// not matter, and unlike the inverse it exists for singular transforms.
    pub normal_matrix: Mat3,
}

impl<'s> DrawData<'s> {
    pub fn new(scene: &'s Scene, draw: &'s Draw, view_projection: &Mat4) -> Self {
        let mesh = &scene.meshes[draw.mesh];
        let mvp = raster::model_view_projection(view_projection, &draw.transform);
        let clip = mesh
            .positions
            .iter()
            .map(|&p| raster::clip_position(&mvp, p))
            .collect();
        let world = mesh.normals.is_none().then(|| {
            mesh.positions
                .iter()
                .map(|&p| draw.transform.transform_point3(p))
                .collect()
        });
        let normal_matrix = crate::shading::normal_matrix(&draw.transform);
        Self {
            draw,
            mesh,
            clip,
            world,
            normal_matrix,
        }
    }

    /// Vertex indices of triangle `sub` (0 or 1) of quad `quad`, if it exists.
    pub fn triangle(&self, quad: u32, sub: u8) -> Option<[u32; 3]> {
        Mesh::quad_triangles(self.mesh.quads[quad as usize])[sub as usize]
    }

    /// The triangle set up for the viewport, unless it covers nothing or is culled.
    pub fn setup(
        &self,
        scene: &Scene,
        vertices: [u32; 3],
        width: u32,
        height: u32,
    ) -> Option<Triangle> {
        let tri = Triangle::setup(vertices.map(|i| self.clip[i as usize]), width, height)?;
        let single_sided = !scene.materials[self.draw.material].double_sided;
        (!(single_sided && tri.facing() == Facing::Back)).then_some(tri)
    }
}

/// One triangle of the transparent layer. Its order key is `(draw, quad, sub)`.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord)]
pub struct PrimRef {
    pub draw: u32,
    pub quad: u32,
    pub sub: u8,
}

/// The screen cut into tiles, each with the triangles that may cover it, in order.
pub struct Bins {
    pub tiles: Vec<PixelRect>,
    pub prims: Vec<Vec<PrimRef>>,
}

pub fn tiles(width: u32, height: u32) -> Vec<PixelRect> {
    let mut out = Vec::new();
    for y in (0..height).step_by(TILE as usize) {
        for x in (0..width).step_by(TILE as usize) {
            out.push(PixelRect::new(
                x,
                y,
                (x + TILE).min(width),
                (y + TILE).min(height),
            ));
        }
    }
    out
}

/// Sets up every transparent triangle in parallel and lists it in each tile its bounds touch.
pub fn bin(scene: &Scene, draws: &[DrawData<'_>], width: u32, height: u32) -> Bins {
    let tiles_x = width.div_ceil(TILE);
    let tiles = tiles(width, height);
    let jobs: Vec<(u32, usize)> = draws
        .iter()
        .enumerate()
        .flat_map(|(d, data)| {
            (0..data.mesh.quads.len())
                .step_by(QUADS_PER_JOB)
                .map(move |start| (d as u32, start))
        })
        .collect();
    let pieces: Vec<Vec<(u32, PrimRef)>> = jobs
        .par_iter()
        .map(|&(draw, start)| {
            let data = &draws[draw as usize];
            let end = (start + QUADS_PER_JOB).min(data.mesh.quads.len());
            let mut out = Vec::new();
            for quad in start as u32..end as u32 {
                for sub in 0..2u8 {
                    let Some(vertices) = data.triangle(quad, sub) else {
                        continue;
                    };
                    let Some(tri) = data.setup(scene, vertices, width, height) else {
                        continue;
                    };
                    let b = tri.bounds();
                    let prim = PrimRef { draw, quad, sub };
                    for ty in b.y0 / TILE..b.y1.div_ceil(TILE) {
                        for tx in b.x0 / TILE..b.x1.div_ceil(TILE) {
                            out.push((ty * tiles_x + tx, prim));
                        }
                    }
                }
            }
            out
        })
        .collect();
    let mut prims = vec![Vec::new(); tiles.len()];
    for (tile, prim) in pieces.into_iter().flatten() {
        prims[tile as usize].push(prim);
    }
    Bins { tiles, prims }
}
