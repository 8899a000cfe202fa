//! The CPU exact renderer: the definition of the right answer that every GPU method is
//! measured against (ARCHITECTURE.md, on the fragment model).
//!
//! Per pixel: every transparent triangle covering the pixel centre under the rules of
//! [`crate::raster`] (back faces culled for single-sided materials), with depth-buffer value
//! below the opaque depth there, is shaded with [`crate::shading::shade_transparent`]; the
//! fragments are sorted by view depth, ties broken by (draw index, quad index, triangle index
//! within the quad), and composited front to back over the opaque colour.
//!
//! [`render_in_submission_order`] composites the same fragments in submission order instead,
//! as unsorted hardware blending does: the CPU model of the `blend` method.
//!
//! For speed: vertices are transformed once per draw, triangles are set up and binned to
//! 32×32 tiles in parallel, and tiles render in parallel, each with its own fragment list.

#![deny(unsafe_code)]

mod prepare;
mod shade;

pub use prepare::TILE;

#[cfg(test)]
mod tests;

use crate::image::{Image, OpaqueLayer};
use crate::raster::{order_depth, DepthOrder, PixelRect, MAX_VIEWPORT};
use crate::scene::Scene;
use crate::shading::{composite_front_to_back, composite_until, Fragment};
use glam::Vec3;
use prepare::{DrawData, PrimRef};
use rayon::prelude::*;
use shade::TriangleShader;
use std::cmp::Ordering;

/// Renders the scene's transparent layer over `opaque`, at the opaque layer's size.
pub fn render(scene: &Scene, opaque: &OpaqueLayer) -> crate::Result<Image> {
    render_pixels(scene, opaque, Record::order, &|_, _, fragments, opaque| {
        composite_front_to_back(fragments.iter().map(|f| f.fragment), opaque)
    })
}

/// [`render`] with the exact method's early stop: each pixel composites its fragments until
/// every channel of its transmittance is below `threshold`.
pub fn render_until(scene: &Scene, opaque: &OpaqueLayer, threshold: f32) -> crate::Result<Image> {
    render_pixels(scene, opaque, Record::order, &|_, _, fragments, opaque| {
        composite_until(fragments.iter().map(|f| f.fragment), opaque, threshold)
    })
}

/// The fragments of [`render`], composited the way unsorted hardware blending (the `blend`
/// method) composites them: in submission order, by draw index, then quad, then triangle
/// within the quad, each one blended over what is already there (`dst = L + T ⊙ dst`), with
/// no regard for depth. The last fragment submitted ends up in front. Where submission runs
/// back to front and nothing interpenetrates this equals [`render`]; elsewhere it shows the
/// error that sorting avoids.
///
/// Coverage, the opaque depth test, back-face culling and shading (texture level of detail
/// included) are the reference's, so it differs from a hardware rasterizer where those do.
pub fn render_in_submission_order(scene: &Scene, opaque: &OpaqueLayer) -> crate::Result<Image> {
    render_pixels(
        scene,
        opaque,
        Record::last_submitted_first,
        &|_, _, fragments, opaque| {
            composite_front_to_back(fragments.iter().map(|f| f.fragment), opaque)
        },
    )
}

/// One transparent fragment of a pixel, as the reference rasterizes and shades it.
#[derive(Clone, Copy, Debug)]
pub struct PixelFragment {
    /// The depth it is ordered by at the pixel centre (`raster::order_depth`: clip w, or
    /// device depth + 1 under an orthographic projection).
    pub view_depth: f32,
    /// Depth-buffer value (0 near, 1 far).
    pub device_depth: f32,
    pub fragment: Fragment,
}

/// Resolves one pixel `(x, y)` from its fragments and the opaque colour behind them.
pub type Resolve<'a> = dyn Fn(u32, u32, &[PixelFragment], Vec3) -> Vec3 + Sync + 'a;

/// The reference's rasterization and shading with another per-pixel resolve: CPU models of
/// the approximate methods. Fragments come in submission order (draw, quad, triangle), the
/// order in which the GPU's blending sees them.
pub fn render_with(
    scene: &Scene,
    opaque: &OpaqueLayer,
    resolve: &Resolve<'_>,
) -> crate::Result<Image> {
    render_pixels(scene, opaque, Record::submission, resolve)
}

fn render_pixels(
    scene: &Scene,
    opaque: &OpaqueLayer,
    order: fn(&Record, &Record) -> Ordering,
    resolve: &Resolve<'_>,
) -> crate::Result<Image> {
    scene.validate()?;
    let (width, height) = (opaque.width, opaque.height);
    check_viewport(width, height)?;
    let n = width as usize * height as usize;
    if opaque.colour.len() != n || opaque.depth.len() != n {
        return Err(crate::Error::InvalidViewport {
            width,
            height,
            reason: "opaque layer colour or depth has the wrong number of pixels".into(),
        });
    }
    check_order_keys(scene)?;

    let view_projection = scene.camera.view_projection(width, height);
    let draws: Vec<DrawData<'_>> = scene
        .transparent
        .par_iter()
        .map(|d| DrawData::new(scene, d, &view_projection))
        .collect();
    let bins = prepare::bin(scene, &draws, width, height);
    let ctx = TileContext {
        scene,
        draws: &draws,
        opaque,
        order,
        resolve,
        depth_order: scene.camera.depth_order(),
    };
    let tiles: Vec<Vec<Vec3>> = bins
        .tiles
        .par_iter()
        .zip(&bins.prims)
        .map_init(Scratch::default, |scratch, (rect, prims)| {
            ctx.render_tile(*rect, prims, scratch)
        })
        .collect::<crate::Result<_>>()?;

    let mut image = Image::filled(width, height, glam::Vec4::ONE);
    for (rect, colours) in bins.tiles.iter().zip(tiles) {
        let mut c = colours.into_iter();
        for y in rect.y0..rect.y1 {
            for x in rect.x0..rect.x1 {
                let colour = c.next().unwrap_or(Vec3::ZERO);
                image.set(x, y, colour.extend(1.0));
            }
        }
    }
    Ok(image)
}

fn check_viewport(width: u32, height: u32) -> crate::Result<()> {
    let reason = if width == 0 || height == 0 {
        "zero size"
    } else if width > MAX_VIEWPORT || height > MAX_VIEWPORT {
        "larger than the rasterizer supports"
    } else {
        return Ok(());
    };
    Err(crate::Error::InvalidViewport {
        width,
        height,
        reason: reason.into(),
    })
}

/// Order keys are `(draw: u32, quad: u32, sub)`; say so rather than wrap.
fn check_order_keys(scene: &Scene) -> crate::Result<()> {
    let too_many = u32::try_from(scene.transparent.len()).is_err()
        || scene
            .meshes
            .iter()
            .any(|m| u32::try_from(m.quads.len()).is_err());
    if too_many {
        return Err(crate::Error::TooLarge(
            "more than 2^32 transparent draws or quads in one mesh".into(),
        ));
    }
    Ok(())
}

/// A fragment waiting to be sorted into its pixel's list.
#[derive(Clone, Copy)]
struct Record {
    /// Pixel index within the tile.
    pixel: u32,
    view_depth: f32,
    device_depth: f32,
    prim: PrimRef,
    fragment: Fragment,
}

impl Record {
    /// Front to back; equal depths in submission order.
    fn order(&self, other: &Self) -> Ordering {
        self.view_depth
            .total_cmp(&other.view_depth)
            .then(self.prim.cmp(&other.prim))
    }

    /// Submission order: draw, quad, triangle.
    fn submission(&self, other: &Self) -> Ordering {
        self.prim.cmp(&other.prim)
    }

    /// Reverse submission order: the front-to-back order that blending each fragment over
    /// the ones submitted before it produces.
    fn last_submitted_first(&self, other: &Self) -> Ordering {
        other.prim.cmp(&self.prim)
    }
}

/// Per-thread buffers, reused from tile to tile.
/// The most fragments the reference holds for one tile of [`prepare::TILE`]² pixels: 16 M
/// (16,384 a pixel on average, about 800 MB with their sorted copy), past which a frame is
/// refused rather than run the process out of memory (a fuzzed file drawing one window
/// 100,000 times asked for gigabytes).
pub const MAX_TILE_FRAGMENTS: usize = 1 << 24;

#[derive(Default)]
struct Scratch {
    /// Fragments in rasterization order.
    frags: Vec<Record>,
    /// The same, grouped by pixel (a counting sort), then sorted within each pixel.
    by_pixel: Vec<Record>,
    /// Start of each pixel's group in `by_pixel`, plus the end.
    starts: Vec<usize>,
}

impl Scratch {
    /// Groups `frags` by pixel and sorts each group: far cheaper than one big sort.
    fn sort(&mut self, pixels: usize, order: fn(&Record, &Record) -> Ordering) {
        self.starts.clear();
        self.starts.resize(pixels + 1, 0);
        for r in &self.frags {
            self.starts[r.pixel as usize + 1] += 1;
        }
        for i in 0..pixels {
            self.starts[i + 1] += self.starts[i];
        }
        let mut next = self.starts.clone();
        self.by_pixel.clear();
        // Reserved when the fragments were: see `TileContext::render_tile`.
        self.by_pixel.extend_from_slice(&self.frags);
        for r in &self.frags {
            let slot = &mut next[r.pixel as usize];
            self.by_pixel[*slot] = *r;
            *slot += 1;
        }
        for i in 0..pixels {
            self.by_pixel[self.starts[i]..self.starts[i + 1]].sort_unstable_by(order);
        }
    }

    fn pixel(&self, i: usize) -> impl Iterator<Item = PixelFragment> + '_ {
        self.by_pixel[self.starts[i]..self.starts[i + 1]]
            .iter()
            .map(|r| PixelFragment {
                view_depth: r.view_depth,
                device_depth: r.device_depth,
                fragment: r.fragment,
            })
    }
}

/// Whether room for `len` records cannot be had in `v` (memory is short).
fn cannot_reserve(v: &mut Vec<Record>, len: usize) -> bool {
    v.try_reserve(len.saturating_sub(v.len())).is_err()
}

struct TileContext<'a, 's> {
    scene: &'s Scene,
    draws: &'a [DrawData<'s>],
    opaque: &'a OpaqueLayer,
    order: fn(&Record, &Record) -> Ordering,
    resolve: &'a Resolve<'a>,
    depth_order: DepthOrder,
}

impl TileContext<'_, '_> {
    /// Final colours of the tile's pixels, row by row; an error past [`MAX_TILE_FRAGMENTS`]
    /// or when memory for the fragments cannot be had.
    fn render_tile(
        &self,
        rect: PixelRect,
        prims: &[PrimRef],
        scratch: &mut Scratch,
    ) -> crate::Result<Vec<Vec3>> {
        let (width, height) = (self.opaque.width, self.opaque.height);
        let tile_width = rect.x1 - rect.x0;
        let frags = &mut scratch.frags;
        frags.clear();
        let mut full = false;
        for &prim in prims {
            if full {
                break;
            }
            let data = &self.draws[prim.draw as usize];
            let Some(vertices) = data.triangle(prim.quad, prim.sub) else {
                continue;
            };
            let Some(tri) = data.setup(self.scene, vertices, width, height) else {
                continue;
            };
            let shader = TriangleShader::new(self.scene, data, vertices);
            tri.rasterize(rect, |x, y, s| {
                let i = y as usize * width as usize + x as usize;
                if s.z_ndc < self.opaque.depth[i] && !full {
                    // Grown fallibly, with room for the sorted copy too.
                    if frags.len() == frags.capacity() {
                        let more = frags.len().max(1024);
                        full = frags.len() >= MAX_TILE_FRAGMENTS
                            || frags.try_reserve(more).is_err()
                            || cannot_reserve(&mut scratch.by_pixel, frags.len() + more);
                        if full {
                            return;
                        }
                    }
                    frags.push(Record {
                        pixel: (y - rect.y0) * tile_width + (x - rect.x0),
                        view_depth: order_depth(&s, self.depth_order),
                        device_depth: s.z_ndc,
                        prim,
                        fragment: shader.shade(&tri, x, y, &s),
                    });
                }
            });
        }
        if full {
            return Err(crate::Error::TooLarge(format!(
                "the CPU reference holds at most {MAX_TILE_FRAGMENTS} fragments in a tile of \
                 {0}x{0} pixels (or what memory allows); the tile at ({1}, {2}) has more",
                prepare::TILE,
                rect.x0,
                rect.y0
            )));
        }
        let pixels = (tile_width * (rect.y1 - rect.y0)) as usize;
        scratch.sort(pixels, self.order);

        let mut out = Vec::with_capacity(pixels);
        let mut fragments = Vec::new();
        for y in rect.y0..rect.y1 {
            for x in rect.x0..rect.x1 {
                let pixel = ((y - rect.y0) * tile_width + (x - rect.x0)) as usize;
                let opaque = self.opaque.colour[y as usize * width as usize + x as usize];
                fragments.clear();
                fragments.extend(scratch.pixel(pixel));
                out.push((self.resolve)(x, y, &fragments, opaque));
            }
        }
        Ok(out)
    }
}
