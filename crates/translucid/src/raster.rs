//! The rasterization rules shared by the CPU reference and the GPU exact method.
//!
//! Everything here is written so that a GLSL compute shader can reproduce it bit for bit: plain
//! integer arithmetic for coverage, and float formulas evaluated in the order written (GLSL
//! must mark them `precise` so that no multiply-add is fused; `x * 0.5 + 0.5` is safe either
//! way because the product is exact).
//!
//! # Viewport transform
//!
//! A clip-space vertex `(x, y, z, w)` maps, in f32, to
//! `x_fb = (x / w * 0.5 + 0.5) * width`, `y_fb = (y / w * 0.5 + 0.5) * height`,
//! `z_ndc = z / w`. [`clip_position`] fixes the order of the model-view-projection product.
//!
//! # Fixed-point path (the common case)
//!
//! Used when every vertex has `w > 0`, `z >= 0` and `|x_fb|, |y_fb| <= GUARD_BAND`.
//!
//! - Snap: `X = i64(floor(x_fb * 256 + 0.5))`, same for `Y` (8 sub-pixel bits, round to nearest).
//! - Signed double area `A2 = Σ (X_i Y_{i+1} − X_{i+1} Y_i)` in i64. `A2 == 0` covers nothing.
//!   Vulkan's `a = −A2 / 2`; with `frontFace = COUNTER_CLOCKWISE`, `A2 < 0` is front-facing.
//! - Edge `k` is the edge opposite vertex `k`, from `V_j = V_{k+1}` to `V_l = V_{k+2}`:
//!   `a = s (Y_j − Y_l)`, `b = s (X_l − X_j)`, `c = s (X_j Y_l − Y_j X_l)`, with `s = sign(A2)`,
//!   so that `E_k(P) = a P_x + b P_y + c` is positive inside whatever the winding.
//! - Pixel `(x, y)` is sampled at its centre `P = (256 x + 128, 256 y + 128)`.
//! - Top-left rule: the sample is inside edge `k` when `E_k > 0`, or `E_k == 0` and the
//!   inward normal `(a, b)` has `a > 0`, or `a == 0 && b > 0` (a left edge, or a top edge with
//!   framebuffer y pointing down). Two triangles sharing an edge compute exactly negated
//!   integers for it, so exactly one of them owns every sample on it.
//! - Interpolation (f32): `λ_k = f32(E_k) * (1 / f32(|A2|))`; `z_ndc = λ0 z0 + λ1 z1 + λ2 z2`
//!   (linear in screen space, as depth buffers are); `q_k = λ_k * (1 / w_k)`;
//!   `view_depth = 1 / (q0 + q1 + q2)` (the clip `w`); perspective-correct barycentrics
//!   `b_k = q_k * view_depth`.
//!
//! # Homogeneous path (near plane, behind the eye, outside the guard band)
//!
//! After Olano & Greer, "Triangle scan conversion using 2D homogeneous coordinates" (1997): no
//! clipping, nothing dropped. In f32, like everything the GPU does per pixel: the clip
//! coordinates are first scaled by `2^-e`, where `2^e <= m < 2^(e+1)` for the largest
//! magnitude `m` among them, so that the products below cannot overflow whatever the scene's
//! scale (an exact scaling, which rounding commutes with: two triangles sharing an edge still
//! compute exactly proportional lines for it). Each scaled vertex becomes
//! `V = ((x/2 + w/2) W, (y/2 + w/2) H, w)` and edge `k` the line `V_j × V_l`, normalised by
//! `s = sign(det[V0 V1 V2])` (front-facing when `det < 0`, like `A2`). At pixel centre
//! `p = (x + 0.5, y + 0.5, 1)` the normalised values `e_k = (line_k · p) / |det|` are the
//! perspective barycentrics up to one common positive factor; a sample is covered when all
//! three are inside by the same tie rule as above, which also rejects the mirrored "external"
//! triangle behind the eye. Then `d = 1 / Σ e_k`, `b_k = e_k * d`, `z_ndc = Σ e_k z_k` (scaled
//! clip z) and `view_depth = d * 2^e`.
//! An edge whose two ends have `w > 0` and lie inside the guard band is tested with the
//! fixed-point edge function of its snapped ends instead, so it stays watertight against
//! fixed-point neighbours.
//!
//! # Order depth
//!
//! Fragments are ordered by [`order_depth`]: `view_depth` (clip `w`) under a perspective
//! projection; `z_ndc + 1` under an orthographic one, where `w` is the same everywhere and
//! `z_ndc` is linear in view depth (`+ 1` keeps it positive, so that its bits order like
//! its values, and above 0, which the compute raster keeps for "nothing yet").
//!
//! # Depth clip
//!
//! Samples with `z_ndc < 0`, `z_ndc > 1` (or NaN) are discarded, as hardware near/far clipping
//! would. That is what clips a triangle crossing the near plane.

#![deny(unsafe_code)]

use glam::{Mat4, Vec3, Vec4};

pub use crate::interface::raster::{GUARD_BAND, SUBPIXEL_BITS};
const SUBPIXEL_SCALE: f32 = (1 << SUBPIXEL_BITS) as f32;
const HALF_PIXEL: i64 = crate::interface::raster::HALF_PIXEL as i64;
/// Largest viewport width or height the rules support.
pub const MAX_VIEWPORT: u32 = 1 << 16;

/// `view_projection * model`, each column `((v0 * m.x + v1 * m.y) + v2 * m.z) + v3 * m.w` without
/// fused multiply-adds: the order the GPU must use to get the same matrix (the mesh pipelines
/// compute it per vertex, `modelViewProjection` in raster_rules.glsl).
pub fn model_view_projection(view_projection: &Mat4, model: &Mat4) -> Mat4 {
    let v = view_projection;
    let column = |m: Vec4| ((v.x_axis * m.x + v.y_axis * m.y) + v.z_axis * m.z) + v.w_axis * m.w;
    Mat4::from_cols(
        column(model.x_axis),
        column(model.y_axis),
        column(model.z_axis),
        column(model.w_axis),
    )
}

/// `mvp * (p, 1)` as `((c0 * x + c1 * y) + c2 * z) + c3`, per component, without fused
/// multiply-adds: the order the GPU must use to get the same clip coordinates.
pub fn clip_position(mvp: &Mat4, p: Vec3) -> Vec4 {
    ((mvp.x_axis * p.x + mvp.y_axis * p.y) + mvp.z_axis * p.z) + mvp.w_axis
}

/// The viewport transform: `(x_fb, y_fb, z_ndc)` of a clip-space vertex.
pub fn viewport_transform(clip: Vec4, width: u32, height: u32) -> Vec3 {
    Vec3::new(
        (clip.x / clip.w * 0.5 + 0.5) * width as f32,
        (clip.y / clip.w * 0.5 + 0.5) * height as f32,
        clip.z / clip.w,
    )
}

/// Snaps a framebuffer coordinate to fixed point (1/256 pixel), rounding to nearest.
pub fn snap(v: f32) -> i64 {
    (v * SUBPIXEL_SCALE + 0.5).floor() as i64
}

/// A half-open rectangle of pixels `[x0, x1) × [y0, y1)`.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct PixelRect {
    pub x0: u32,
    pub y0: u32,
    pub x1: u32,
    pub y1: u32,
}

impl PixelRect {
    pub fn new(x0: u32, y0: u32, x1: u32, y1: u32) -> Self {
        Self { x0, y0, x1, y1 }
    }

    /// The whole viewport.
    pub fn full(width: u32, height: u32) -> Self {
        Self::new(0, 0, width, height)
    }

    pub fn is_empty(&self) -> bool {
        self.x0 >= self.x1 || self.y0 >= self.y1
    }

    pub fn intersect(&self, other: &Self) -> Self {
        Self::new(
            self.x0.max(other.x0),
            self.y0.max(other.y0),
            self.x1.min(other.x1),
            self.y1.min(other.y1),
        )
    }
}

/// How fragments are ordered along the view axis: see the module's "Order depth".
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum DepthOrder {
    /// By clip w: perspective projections.
    ClipW,
    /// By z_ndc: orthographic projections, whose clip w is constant.
    DeviceZ,
}

/// The depth sample `s` is ordered by under `order`.
pub fn order_depth(s: &Sample, order: DepthOrder) -> f32 {
    match order {
        DepthOrder::ClipW => s.view_depth,
        DepthOrder::DeviceZ => s.z_ndc + 1.0,
    }
}

/// What a covered sample yields.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Sample {
    /// Perspective-correct barycentric weights of the three vertices.
    pub barycentric: Vec3,
    /// Depth-buffer value, interpolated linearly in screen space; in [0, 1].
    pub z_ndc: f32,
    /// Clip `w` (view-space distance along the view axis), perspective-correct.
    pub view_depth: f32,
}

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Facing {
    Front,
    Back,
}

/// A triangle set up for rasterization in one viewport.
#[derive(Clone, Debug)]
pub struct Triangle {
    facing: Facing,
    bounds: PixelRect,
    kind: Kind,
}

#[derive(Clone, Debug)]
enum Kind {
    Fixed(FixedSetup),
    Homogeneous(Box<HomogeneousSetup>),
}

/// An integer edge function, normalised positive inside, with its tie bias
/// (1 when samples exactly on the edge belong to this triangle, else 0).
#[derive(Clone, Copy, Debug)]
struct FixedEdge {
    a: i64,
    b: i64,
    c: i64,
    bias: i64,
}

impl FixedEdge {
    /// The edge from `p` to `q`, multiplied by `sign`.
    fn new(p: (i64, i64), q: (i64, i64), sign: i64) -> Self {
        let a = sign * (p.1 - q.1);
        let b = sign * (q.0 - p.0);
        let c = sign * (p.0 * q.1 - p.1 * q.0);
        let owns_ties = a > 0 || (a == 0 && b > 0);
        Self {
            a,
            b,
            c,
            bias: i64::from(owns_ties),
        }
    }

    /// Edge value at the centre of pixel `(x, y)`.
    fn at(&self, x: u32, y: u32) -> i64 {
        let px = ((x as i64) << SUBPIXEL_BITS) + HALF_PIXEL;
        let py = ((y as i64) << SUBPIXEL_BITS) + HALF_PIXEL;
        self.a * px + self.b * py + self.c
    }

    fn covers(&self, value: i64) -> bool {
        value + self.bias > 0
    }
}

#[derive(Clone, Debug)]
struct FixedSetup {
    edges: [FixedEdge; 3],
    inv_area: f32,
    z_ndc: [f32; 3],
    inv_w: [f32; 3],
}

#[derive(Clone, Debug)]
struct HomogeneousSetup {
    /// `(a, b, c)` of each edge line, normalised positive inside.
    lines: [[f32; 3]; 3],
    /// Fixed-point replacement for the coverage test of an edge, where both ends allow it.
    fixed: [Option<FixedEdge>; 3],
    inv_abs_det: f32,
    /// Clip-space z of each vertex, scaled.
    z: [f32; 3],
    /// The vertices were scaled by `2^-exponent`.
    exponent: i32,
}

impl HomogeneousSetup {
    fn line_at(&self, k: usize, x: u32, y: u32) -> f32 {
        let [a, b, c] = self.lines[k];
        (a * (x as f32 + 0.5) + b * (y as f32 + 0.5)) + c
    }

    fn covers(&self, x: u32, y: u32) -> bool {
        (0..3).all(|k| match &self.fixed[k] {
            Some(edge) => edge.covers(edge.at(x, y)),
            None => {
                let v = self.line_at(k, x, y);
                let [a, b, _] = self.lines[k];
                v > 0.0 || (v == 0.0 && (a > 0.0 || (a == 0.0 && b > 0.0)))
            }
        })
    }

    /// The unnormalised perspective barycentrics `e_k` at a pixel centre.
    fn weights(&self, x: u32, y: u32) -> [f32; 3] {
        [0, 1, 2].map(|k| self.line_at(k, x, y) * self.inv_abs_det)
    }
}

/// A vertex after the viewport transform, with its snapped position when it has one.
#[derive(Clone, Copy)]
struct Projected {
    fb: Vec3,
    w: f32,
    snapped: Option<(i64, i64)>,
}

fn project(clip: Vec4, width: u32, height: u32) -> Projected {
    let fb = viewport_transform(clip, width, height);
    let in_band = |v: f32| v.abs() <= GUARD_BAND; // false for NaN
    let snapped =
        (clip.w > 0.0 && in_band(fb.x) && in_band(fb.y)).then(|| (snap(fb.x), snap(fb.y)));
    Projected {
        fb,
        w: clip.w,
        snapped,
    }
}

impl Triangle {
    /// Sets up the triangle with clip-space vertices `clip` for a `width × height` viewport.
    /// `None` when it can cover no sample: zero area (after snapping, on the fixed path),
    /// non-finite coordinates, nothing inside the depth range, or outside the viewport.
    pub fn setup(clip: [Vec4; 3], width: u32, height: u32) -> Option<Self> {
        if width == 0 || height == 0 || width > MAX_VIEWPORT || height > MAX_VIEWPORT {
            return None;
        }
        if !clip.iter().all(|v| v.is_finite()) {
            return None;
        }
        let projected = clip.map(|v| project(v, width, height));
        let snapped = [0, 1, 2].map(|i| projected[i].snapped.filter(|_| clip[i].z >= 0.0));
        let triangle = match snapped {
            [Some(a), Some(b), Some(c)] => Self::setup_fixed(&projected, [a, b, c], width, height),
            _ => Self::setup_homogeneous(clip, &projected, width, height),
        }?;
        (!triangle.bounds.is_empty()).then_some(triangle)
    }

    fn setup_fixed(
        v: &[Projected; 3],
        p: [(i64, i64); 3],
        width: u32,
        height: u32,
    ) -> Option<Self> {
        let area2: i64 = (0..3)
            .map(|i| {
                let j = (i + 1) % 3;
                p[i].0 * p[j].1 - p[j].0 * p[i].1
            })
            .sum();
        if area2 == 0 {
            return None;
        }
        let sign = area2.signum();
        let edges = [0, 1, 2].map(|k| FixedEdge::new(p[(k + 1) % 3], p[(k + 2) % 3], sign));
        // Pixels whose centre lies in the snapped bounding box.
        let lo = |c: i64| (c - HALF_PIXEL + 255).div_euclid(256);
        let hi = |c: i64| (c - HALF_PIXEL).div_euclid(256) + 1;
        let xs = p.map(|q| q.0);
        let ys = p.map(|q| q.1);
        let clamp = |v: i64, max: u32| v.clamp(0, max as i64) as u32;
        let bounds = PixelRect::new(
            clamp(lo(min3(xs)), width),
            clamp(lo(min3(ys)), height),
            clamp(hi(max3(xs)), width),
            clamp(hi(max3(ys)), height),
        );
        Some(Self {
            facing: if area2 < 0 {
                Facing::Front
            } else {
                Facing::Back
            },
            bounds,
            kind: Kind::Fixed(FixedSetup {
                edges,
                inv_area: 1.0 / (area2.abs() as f32),
                z_ndc: v.map(|p| p.fb.z),
                inv_w: v.map(|p| 1.0 / p.w),
            }),
        })
    }

    fn setup_homogeneous(
        clip: [Vec4; 3],
        projected: &[Projected; 3],
        width: u32,
        height: u32,
    ) -> Option<Self> {
        let (wf, hf) = (width as f32, height as f32);
        let largest = clip
            .iter()
            .fold(0.0f32, |m, c| m.max(c.abs().max_element()));
        let exponent = exponent_of(largest);
        let scaled = clip.map(|c| c.to_array().map(|v| scale_by_power_of_two(v, -exponent)));
        let v = scaled.map(|[x, y, _, w]| [(x * 0.5 + w * 0.5) * wf, (y * 0.5 + w * 0.5) * hf, w]);
        let raw = [0, 1, 2].map(|k| cross(v[(k + 1) % 3], v[(k + 2) % 3]));
        let det = dot(raw[0], v[0]);
        if det == 0.0 || !det.is_finite() {
            return None;
        }
        let sign = det.signum();
        let bounds = visible_bounds(clip, width, height)?;
        let fixed = [0, 1, 2].map(|k| {
            let (j, l) = ((k + 1) % 3, (k + 2) % 3);
            match (projected[j].snapped, projected[l].snapped) {
                (Some(p), Some(q)) if p != q => Some(FixedEdge::new(p, q, sign as i64)),
                _ => None,
            }
        });
        Some(Self {
            facing: if det < 0.0 {
                Facing::Front
            } else {
                Facing::Back
            },
            bounds,
            kind: Kind::Homogeneous(Box::new(HomogeneousSetup {
                lines: raw.map(|l| l.map(|c| c * sign)),
                fixed,
                inv_abs_det: 1.0 / det.abs(),
                z: scaled.map(|c| c[2]),
                exponent,
            })),
        })
    }

    pub fn facing(&self) -> Facing {
        self.facing
    }

    /// Whether this triangle was set up on the homogeneous path.
    pub fn is_homogeneous(&self) -> bool {
        matches!(self.kind, Kind::Homogeneous(_))
    }

    /// A rectangle, inside the viewport, outside which no sample is covered.
    pub fn bounds(&self) -> PixelRect {
        self.bounds
    }

    /// The sample at pixel `(x, y)`, if the triangle covers its centre and it survives the
    /// depth clip.
    pub fn sample_at(&self, x: u32, y: u32) -> Option<Sample> {
        match &self.kind {
            Kind::Fixed(f) => {
                let e = f.edges.map(|edge| edge.at(x, y));
                (0..3)
                    .all(|k| f.edges[k].covers(e[k]))
                    .then(|| fixed_sample(f, e))
                    .flatten()
            }
            Kind::Homogeneous(h) => h
                .covers(x, y)
                .then(|| homogeneous_sample(h, x, y))
                .flatten(),
        }
    }

    /// Calls `visit(x, y, sample)` for every covered sample inside `rect`, row by row.
    pub fn rasterize(&self, rect: PixelRect, mut visit: impl FnMut(u32, u32, Sample)) {
        let r = self.bounds.intersect(&rect);
        if r.is_empty() {
            return;
        }
        match &self.kind {
            Kind::Fixed(f) => {
                // Step the edge functions exactly along each row: same integers as `at`.
                let step = f.edges.map(|e| e.a << SUBPIXEL_BITS);
                for y in r.y0..r.y1 {
                    let mut e = f.edges.map(|edge| edge.at(r.x0, y));
                    for x in r.x0..r.x1 {
                        if (0..3).all(|k| f.edges[k].covers(e[k])) {
                            if let Some(s) = fixed_sample(f, e) {
                                visit(x, y, s);
                            }
                        }
                        for k in 0..3 {
                            e[k] += step[k];
                        }
                    }
                }
            }
            Kind::Homogeneous(h) => {
                for y in r.y0..r.y1 {
                    for x in r.x0..r.x1 {
                        if let Some(s) = h
                            .covers(x, y)
                            .then(|| homogeneous_sample(h, x, y))
                            .flatten()
                        {
                            visit(x, y, s);
                        }
                    }
                }
            }
        }
    }

    /// Screen-space derivatives `[∂b/∂x, ∂b/∂y]` of the perspective-correct barycentrics at
    /// the centre of pixel `(x, y)`, computed analytically (for texture level of detail).
    pub fn barycentric_gradients(&self, x: u32, y: u32) -> [Vec3; 2] {
        // Both paths interpolate b_k = q_k / Σq with q_k affine in screen position, so
        // ∂b_k = (∂q_k − b_k ∂Σq) / Σq.
        let (q, dqx, dqy) = match &self.kind {
            Kind::Fixed(f) => {
                let e = f.edges.map(|edge| edge.at(x, y));
                let lambda = |k: usize| e[k] as f32 * f.inv_area;
                let d =
                    |coef: i64, k: usize| coef as f32 * SUBPIXEL_SCALE * f.inv_area * f.inv_w[k];
                (
                    [0, 1, 2].map(|k| lambda(k) * f.inv_w[k]),
                    [0, 1, 2].map(|k| d(f.edges[k].a, k)),
                    [0, 1, 2].map(|k| d(f.edges[k].b, k)),
                )
            }
            Kind::Homogeneous(h) => (
                h.weights(x, y),
                [0, 1, 2].map(|k| h.lines[k][0] * h.inv_abs_det),
                [0, 1, 2].map(|k| h.lines[k][1] * h.inv_abs_det),
            ),
        };
        let sum = (q[0] + q[1]) + q[2];
        if sum == 0.0 {
            return [Vec3::ZERO; 2];
        }
        let b = q.map(|v| v / sum);
        let grad = |dq: [f32; 3]| {
            let ds = (dq[0] + dq[1]) + dq[2];
            Vec3::from_array([0, 1, 2].map(|k| (dq[k] - b[k] * ds) / sum))
        };
        [grad(dqx), grad(dqy)]
    }
}

fn min3f(v: [f32; 3]) -> f32 {
    v[0].min(v[1]).min(v[2])
}

fn max3f(v: [f32; 3]) -> f32 {
    v[0].max(v[1]).max(v[2])
}

fn min3(v: [i64; 3]) -> i64 {
    v[0].min(v[1]).min(v[2])
}

fn max3(v: [i64; 3]) -> i64 {
    v[0].max(v[1]).max(v[2])
}

fn cross(p: [f32; 3], q: [f32; 3]) -> [f32; 3] {
    [
        p[1] * q[2] - p[2] * q[1],
        p[2] * q[0] - p[0] * q[2],
        p[0] * q[1] - p[1] * q[0],
    ]
}

fn dot(p: [f32; 3], q: [f32; 3]) -> f32 {
    (p[0] * q[0] + p[1] * q[1]) + p[2] * q[2]
}

/// Interpolation on the fixed-point path, from the (non-negative) edge values.
fn fixed_sample(f: &FixedSetup, e: [i64; 3]) -> Option<Sample> {
    let lambda = e.map(|v| v as f32 * f.inv_area);
    let z_ndc = (lambda[0] * f.z_ndc[0] + lambda[1] * f.z_ndc[1]) + lambda[2] * f.z_ndc[2];
    let q = [0, 1, 2].map(|k| lambda[k] * f.inv_w[k]);
    // Back within the vertices' range, which rounding may leave: 1 / w before the division,
    // and z (raster_rules.glsl).
    let within = |v: f32, lo: f32, hi: f32| v.max(lo).min(hi);
    let inverse = within((q[0] + q[1]) + q[2], min3f(f.inv_w), max3f(f.inv_w));
    let view_depth = 1.0 / inverse;
    let z_ndc = within(z_ndc, min3f(f.z_ndc), max3f(f.z_ndc));
    finish(q.map(|v| v * view_depth), z_ndc, view_depth)
}

/// Interpolation on the homogeneous path.
fn homogeneous_sample(h: &HomogeneousSetup, x: u32, y: u32) -> Option<Sample> {
    let e = h.weights(x, y);
    let sum = (e[0] + e[1]) + e[2];
    if sum <= 0.0 || sum.is_nan() {
        return None; // on the plane through the eye, or behind it
    }
    let d = 1.0 / sum;
    let z_ndc = (e[0] * h.z[0] + e[1] * h.z[1]) + e[2] * h.z[2];
    finish(
        e.map(|v| v * d),
        z_ndc,
        scale_by_power_of_two(d, h.exponent),
    )
}

/// The exponent `e` of a finite `m >= 0`: `2^e <= m < 2^(e+1)`, or -127 when `m` is 0 or
/// subnormal (which scaling by `2^127` keeps finite).
fn exponent_of(m: f32) -> i32 {
    ((m.to_bits() >> 23) & 0xFF) as i32 - 127
}

/// `v * 2^k` for `k` in [-127, 127], exact when the result is normal: two multiplications by
/// powers of two that are themselves normal floats.
fn scale_by_power_of_two(v: f32, k: i32) -> f32 {
    let power = |k: i32| f32::from_bits(((k + 127) as u32) << 23);
    v * power(k / 2) * power(k - k / 2)
}

/// The depth clip.
fn finish(b: [f32; 3], z_ndc: f32, view_depth: f32) -> Option<Sample> {
    (0.0..=1.0).contains(&z_ndc).then_some(Sample {
        barycentric: Vec3::from_array(b),
        z_ndc,
        view_depth,
    })
}

/// Pixels that can hold a sample with `0 <= z_ndc <= 1`: the bounding box of the triangle
/// clipped (in clip space) to `0 <= z <= w`, projected, padded by a pixel against rounding.
/// `None` when nothing of the triangle lies in the depth range.
fn visible_bounds(clip: [Vec4; 3], width: u32, height: u32) -> Option<PixelRect> {
    let mut poly: Vec<[f64; 4]> = clip
        .iter()
        .map(|c| [c.x as f64, c.y as f64, c.z as f64, c.w as f64])
        .collect();
    for plane in [|v: &[f64; 4]| v[2], |v: &[f64; 4]| v[3] - v[2]] {
        poly = clip_polygon(&poly, plane);
        if poly.is_empty() {
            return None;
        }
    }
    let (wf, hf) = (width as f64, height as f64);
    let mut lo = [f64::INFINITY; 2];
    let mut hi = [f64::NEG_INFINITY; 2];
    for v in &poly {
        if v[3] <= 0.0 || v[3].is_nan() {
            return Some(PixelRect::full(width, height));
        }
        let p = [
            (v[0] / v[3] * 0.5 + 0.5) * wf,
            (v[1] / v[3] * 0.5 + 0.5) * hf,
        ];
        for i in 0..2 {
            lo[i] = lo[i].min(p[i]);
            hi[i] = hi[i].max(p[i]);
        }
    }
    let first = |v: f64, max: u32| ((v - 0.5).ceil() - 1.0).clamp(0.0, max as f64) as u32;
    let end = |v: f64, max: u32| ((v - 0.5).floor() + 2.0).clamp(0.0, max as f64) as u32;
    Some(PixelRect::new(
        first(lo[0], width),
        first(lo[1], height),
        end(hi[0], width),
        end(hi[1], height),
    ))
}

/// One Sutherland–Hodgman step: the part of a polygon where `dist >= 0`.
pub(crate) fn clip_polygon(poly: &[[f64; 4]], dist: impl Fn(&[f64; 4]) -> f64) -> Vec<[f64; 4]> {
    let mut out = Vec::with_capacity(poly.len() + 1);
    for (i, cur) in poly.iter().enumerate() {
        let next = &poly[(i + 1) % poly.len()];
        let (dc, dn) = (dist(cur), dist(next));
        if dc >= 0.0 {
            out.push(*cur);
        }
        if (dc >= 0.0) != (dn >= 0.0) {
            let t = dc / (dc - dn);
            out.push([0, 1, 2, 3].map(|k| cur[k] + (next[k] - cur[k]) * t));
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    const W: u32 = 8;
    const H: u32 = 8;

    /// A clip-space vertex (w = 1, z = 0.5) landing at framebuffer `(x, y)` in an 8×8 viewport;
    /// exact in f32 for coordinates in multiples of 1/16.
    fn at(x: f32, y: f32) -> Vec4 {
        Vec4::new(x / W as f32 * 2.0 - 1.0, y / H as f32 * 2.0 - 1.0, 0.5, 1.0)
    }

    /// Per-pixel count of covering triangles.
    fn coverage(tris: &[[Vec4; 3]], w: u32, h: u32) -> Vec<u32> {
        let mut count = vec![0; (w * h) as usize];
        for &t in tris {
            if let Some(tri) = Triangle::setup(t, w, h) {
                tri.rasterize(PixelRect::full(w, h), |x, y, _| {
                    count[(y * w + x) as usize] += 1
                });
            }
        }
        count
    }

    fn centre_in(x: u32, y: u32, x0: f32, y0: f32, x1: f32, y1: f32) -> bool {
        let (cx, cy) = (x as f32 + 0.5, y as f32 + 0.5);
        cx >= x0 && cx < x1 && cy >= y0 && cy < y1
    }

    #[test]
    fn square_with_edges_on_pixel_centres_follows_top_left_rule() {
        // Edges at 1.5 (left, top: included) and 4.5 (right, bottom: excluded); the
        // diagonal passes through the centres (1.5, 1.5), (2.5, 2.5), (3.5, 3.5).
        let (a, b, c, d) = (at(1.5, 1.5), at(4.5, 1.5), at(4.5, 4.5), at(1.5, 4.5));
        let count = coverage(&[[a, b, c], [a, c, d]], W, H);
        for y in 0..H {
            for x in 0..W {
                let want = u32::from((1..4).contains(&x) && (1..4).contains(&y));
                assert_eq!(count[(y * W + x) as usize], want, "pixel ({x}, {y})");
            }
        }
    }

    #[test]
    fn fan_sharing_edges_covers_every_pixel_exactly_once() {
        // Triangles fanned around an interior point to points along a rectangle's boundary,
        // some on pixel centres, some not, some triangles wound the other way round.
        let (x0, y0, x1, y1) = (0.5, 1.5, 7.25, 6.5);
        let boundary = [
            (x0, y0),
            (2.5, y0),
            (3.1875, y0),
            (x1, y0),
            (x1, 3.5),
            (x1, 4.0625),
            (x1, y1),
            (5.5, y1),
            (1.8125, y1),
            (x0, y1),
            (x0, 4.5),
        ];
        for centre in [(3.5, 4.5), (2.9375, 3.0625), (x0, y0)] {
            let c = at(centre.0, centre.1);
            let tris: Vec<[Vec4; 3]> = (0..boundary.len())
                .map(|i| {
                    let p = boundary[i];
                    let q = boundary[(i + 1) % boundary.len()];
                    let (p, q) = (at(p.0, p.1), at(q.0, q.1));
                    if i % 3 == 0 {
                        [c, q, p]
                    } else {
                        [c, p, q]
                    }
                })
                .collect();
            let count = coverage(&tris, W, H);
            for y in 0..H {
                for x in 0..W {
                    let want = u32::from(centre_in(x, y, x0, y0, x1, y1));
                    assert_eq!(
                        count[(y * W + x) as usize],
                        want,
                        "pixel ({x}, {y}), centre {centre:?}"
                    );
                }
            }
        }
    }

    #[test]
    fn shared_edges_stay_watertight_on_the_homogeneous_path() {
        // The same mesh with varying positive w and one vertex in front of the near plane
        // (z < 0, but z_ndc interpolates back into range) goes the homogeneous way and must
        // still cover each pixel once.
        let scale = |v: Vec4, w: f32, z: f32| Vec4::new(v.x * w, v.y * w, z * w, w);
        let (a, b, c, d, e) = (
            scale(at(0.5, 0.5), 1.0, 0.5),
            scale(at(7.5, 0.5), 2.0, 0.5),
            scale(at(7.5, 7.5), 0.5, 0.5),
            scale(at(0.5, 7.5), 3.0, 0.5),
            scale(at(3.5, 4.5), 1.5, -0.01),
        );
        let tris = [[e, a, b], [e, b, c], [e, c, d], [e, d, a]];
        assert!(tris
            .iter()
            .all(|&t| Triangle::setup(t, W, H).is_some_and(|t| t.is_homogeneous())));
        let count = coverage(&tris, W, H);
        for y in 0..H {
            for x in 0..W {
                let inside = (0..7).contains(&x) && (0..7).contains(&y);
                let want = u32::from(inside && !(x == 3 && y == 4));
                // The centre pixel (3, 4) has z_ndc < 0 and is depth-clipped.
                assert_eq!(count[(y * W + x) as usize], want, "pixel ({x}, {y})");
            }
        }
    }

    #[test]
    fn the_homogeneous_path_is_the_same_at_any_scale() {
        // Clip coordinates scaled by 2^60 (a scene in light years, say) describe the same
        // triangle: same coverage and barycentrics, a view depth 2^60 times as large. In f32
        // the products of unscaled vertices would overflow.
        let t = [
            Vec4::new(-0.9, -0.8, -0.2, 1.0),
            Vec4::new(1.5, -0.7, 0.6, 2.0),
            Vec4::new(0.2, 1.1, 0.3, 1.5),
        ];
        let factor = 2.0f32.powi(60);
        let far = t.map(|v| v * factor);
        let (near, far) = (Triangle::setup(t, W, H), Triangle::setup(far, W, H));
        let (near, far) = (near.expect("visible"), far.expect("visible at scale"));
        assert!(near.is_homogeneous() && far.is_homogeneous());
        let mut n = 0;
        for y in 0..H {
            for x in 0..W {
                let (a, b) = (near.sample_at(x, y), far.sample_at(x, y));
                assert_eq!(a.is_some(), b.is_some(), "pixel ({x}, {y})");
                if let (Some(a), Some(b)) = (a, b) {
                    assert_eq!(a.barycentric, b.barycentric);
                    assert_eq!(a.z_ndc, b.z_ndc);
                    assert_eq!(a.view_depth * factor, b.view_depth);
                    n += 1;
                }
            }
        }
        assert!(n > 10, "{n} samples");
    }

    #[test]
    fn huge_quad_outside_the_guard_band_covers_every_pixel_once() {
        // Corners 2^21 px away; the diagonal y = x runs through pixel centres.
        let far = (1 << 21) as f32;
        let (lo, hi) = (4.0 - far, 4.0 + far);
        let (a, b, c, d) = (at(lo, lo), at(hi, lo), at(hi, hi), at(lo, hi));
        let tris = [[a, b, c], [a, c, d]];
        assert!(tris
            .iter()
            .all(|&t| Triangle::setup(t, W, H).is_some_and(|t| t.is_homogeneous())));
        assert_eq!(coverage(&tris, W, H), vec![1; (W * H) as usize]);
    }

    #[test]
    fn facing_follows_vulkan_counter_clockwise_rule() {
        // In framebuffer coordinates (y down): (0,0) → (0,4) → (4,0) has a = 8 > 0.
        let front = [at(0.0, 0.0), at(0.0, 4.0), at(4.0, 0.0)];
        let back = [front[0], front[2], front[1]];
        let setup = |t| Triangle::setup(t, W, H).expect("covers pixels");
        assert_eq!(setup(front).facing(), Facing::Front);
        assert_eq!(setup(back).facing(), Facing::Back);
        // Same answer on the homogeneous path (one vertex in front of the near plane).
        let near = |mut t: [Vec4; 3]| {
            t[0].z = -0.1;
            t
        };
        assert!(setup(near(front)).is_homogeneous());
        assert_eq!(setup(near(front)).facing(), Facing::Front);
        assert_eq!(setup(near(back)).facing(), Facing::Back);
        // Both windings cover the same pixels.
        assert_eq!(coverage(&[front], W, H), coverage(&[back], W, H));
    }

    #[test]
    fn degenerate_triangles_cover_nothing() {
        let collinear = [at(0.0, 0.0), at(2.0, 2.0), at(6.0, 6.0)];
        let repeated = [at(1.0, 1.0), at(5.0, 2.0), at(5.0, 2.0)];
        // Smaller than the snapping grid: all three vertices snap to the same point.
        let tiny = [
            at(2.5, 2.5),
            at(2.5 + 1.0 / 1024.0, 2.5),
            at(2.5, 2.5 + 1.0 / 1024.0),
        ];
        for t in [collinear, repeated, tiny] {
            assert!(Triangle::setup(t, W, H).is_none(), "{t:?}");
        }
        // Homogeneously degenerate: the triangle's plane contains the eye.
        let edge_on = [
            Vec4::new(0.0, 0.0, 0.5, 1.0),
            Vec4::new(0.0, 0.0, -2.0, -1.0),
            Vec4::new(0.0, 0.0, 1.0, 2.0),
        ];
        assert!(Triangle::setup(edge_on, W, H).is_none());
    }

    /// Clip-space vertex for an 8x8 viewport with a perspective camera: view-space point
    /// `(x, y, -d)` with near 1, far 100, 90° field of view.
    fn perspective(x: f32, y: f32, d: f32) -> Vec4 {
        let (n, f) = (1.0f32, 100.0f32);
        Vec4::new(x, -y, (f / (f - n)) * d - f * n / (f - n), d)
    }

    fn clip_against_near(t: [Vec4; 3]) -> Vec<[Vec4; 3]> {
        let mut poly = Vec::new();
        for i in 0..3 {
            let (p, q) = (t[i], t[(i + 1) % 3]);
            if p.z >= 0.0 {
                poly.push(p);
            }
            if (p.z >= 0.0) != (q.z >= 0.0) {
                let s = p.z / (p.z - q.z);
                let mut v = p + (q - p) * s;
                v.z = 0.0;
                poly.push(v);
            }
        }
        (1..poly.len().saturating_sub(1))
            .map(|i| [poly[0], poly[i], poly[i + 1]])
            .collect()
    }

    #[test]
    fn triangle_crossing_the_near_plane_matches_the_hand_clipped_one() {
        // A floor-like triangle from well inside the frustum to behind the eye (w < 0).
        let t = [
            perspective(-3.1, -1.3, 4.0),
            perspective(2.7, -1.1, 5.0),
            perspective(0.3, -0.9, -2.0),
        ];
        let tri = Triangle::setup(t, W, H).expect("visible");
        assert!(tri.is_homogeneous());
        let clipped = clip_against_near(t);
        assert_eq!(clipped.len(), 2);
        let whole = coverage(&[t], W, H);
        let by_hand = coverage(&clipped, W, H);
        assert!(whole.iter().sum::<u32>() > 3, "{whole:?}");
        assert_eq!(whole, by_hand);
        // Interpolated values agree with the hand-clipped triangles' where both cover, up to
        // the effect of snapping the clipped vertices (1/512 px times a steep gradient).
        for piece in &clipped {
            let p = Triangle::setup(*piece, W, H).expect("visible");
            p.rasterize(PixelRect::full(W, H), |x, y, s| {
                let w = tri.sample_at(x, y).expect("covered");
                assert!((w.z_ndc - s.z_ndc).abs() < 1e-3, "{w:?} vs {s:?}");
                assert!((w.view_depth - s.view_depth).abs() < 2e-3 * s.view_depth);
            });
        }
    }

    #[test]
    fn fixed_and_homogeneous_paths_interpolate_alike() {
        let t = [
            perspective(-3.0, -2.0, 2.0),
            perspective(3.0, -1.0, 6.0),
            perspective(0.5, 3.0, 3.0),
        ];
        let fixed = Triangle::setup(t, W, H).expect("visible");
        assert!(!fixed.is_homogeneous());
        let homogeneous =
            Triangle::setup_homogeneous(t, &t.map(|v| project(v, W, H)), W, H).expect("visible");
        let mut n = 0;
        fixed.rasterize(PixelRect::full(W, H), |x, y, s| {
            let h = homogeneous.sample_at(x, y).expect("same coverage");
            assert!((s.barycentric - h.barycentric).abs().max_element() < 1e-3);
            assert!((s.view_depth - h.view_depth).abs() < 1e-3);
            let [gx, gy] = fixed.barycentric_gradients(x, y);
            let [hx, hy] = homogeneous.barycentric_gradients(x, y);
            assert!((gx - hx).abs().max_element() < 1e-3 && (gy - hy).abs().max_element() < 1e-3);
            n += 1;
        });
        assert!(n > 10);
    }

    #[test]
    fn view_depth_is_perspective_correct_and_z_ndc_linear() {
        // Two vertices at w = 1, one at w = 3; halfway in screen space between w = 1 and w = 3
        // the depth is the harmonic mean 1.5.
        let n = |x: f32, y: f32, w: f32| Vec4::new(x * w, y * w, 0.25 * w, w);
        let t = [n(-1.0, -1.0, 1.0), n(1.0, -1.0, 3.0), n(-1.0, 1.0, 1.0)];
        let tri = Triangle::setup(t, W, H).expect("visible");
        let s = tri.sample_at(3, 0).expect("covered"); // x_fb = 3.5, y_fb = 0.5
        let lambda1 = 3.5 / 8.0; // screen-space weight of vertex 1 (at x_fb = 8)
        let want = 1.0 / ((1.0 - lambda1) + lambda1 / 3.0);
        assert!((s.view_depth - want).abs() < 1e-5, "{s:?} vs {want}");
        assert!((s.z_ndc - 0.25).abs() < 1e-6);
        assert!((s.barycentric.y - lambda1 / 3.0 * want).abs() < 1e-5);
    }
}
