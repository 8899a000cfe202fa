//! The camera: a view matrix, a projection and a sub-pixel jitter, in Vulkan conventions
//! (framebuffer Y down, clip z in [0, w]).
//!
//! Engines hand over their own projection matrix ([`Projection::Matrix`]): reversed-Z,
//! infinite far planes and off-centre frusta are taken as they are. [`Projection::Perspective`]
//! is the helper for scenes that name a field of view, its aspect following the render size.
//!
//! Inside translucid depth always grows away from the eye: a reversed-Z matrix is turned
//! around (clip z becomes w − z, device depth 1 − d) before anything uses it, so the opaque
//! pass, every method and the CPU reference depth-test with one convention. Fragments are
//! ordered by clip w under a perspective projection and by device depth under an
//! orthographic one ([`Camera::depth_order`]); oblique near planes are refused.

use crate::raster::DepthOrder;
use glam::{Mat4, Vec2, Vec3, Vec4};

/// How view space maps to clip space.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Projection {
    /// A symmetric perspective whose aspect ratio is the render size's: vertical field of view
    /// in radians, near and far distances (`far` may be infinite). Depth 0 at near, 1 at far.
    Perspective { fov_y: f32, near: f32, far: f32 },
    /// An orthographic projection whose aspect ratio is the render size's: half the view's
    /// height (in view-space units), near and far distances (finite). Depth 0 at near, 1 at
    /// far.
    Orthographic {
        half_height: f32,
        near: f32,
        far: f32,
    },
    /// The engine's clip-from-view matrix, column-major, in Vulkan clip space (y down, z in
    /// [0, w]), used as given: perspective (`w = k · z_view`, k ≠ 0; the far plane may be at
    /// infinity) or orthographic (w a positive constant). Depth may grow or shrink with
    /// distance (reversed-Z). An orthographic matrix must look down view −z, as the view
    /// matrices of right-handed engines do: its depth direction is read from that.
    Matrix(Mat4),
}

#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Camera {
    /// World to view transform.
    pub view: Mat4,
    pub projection: Projection,
    /// Sub-pixel offset of the whole image, in pixels (x right, y down), applied after the
    /// projection as temporal anti-aliasing jitters it; zero for none.
    pub jitter: Vec2,
}

impl Default for Camera {
    fn default() -> Self {
        Self::look_at(Vec3::new(0.0, 0.0, 5.0), Vec3::ZERO, 0.8, 0.1, 100.0)
    }
}

impl Camera {
    /// A perspective camera at `eye` looking at `target`.
    pub fn look_at(eye: Vec3, target: Vec3, fov_y: f32, near: f32, far: f32) -> Self {
        Self {
            view: look_at_view(eye, target),
            projection: Projection::Perspective { fov_y, near, far },
            jitter: Vec2::ZERO,
        }
    }

    /// The clip-from-view matrix for a `width` x `height` render, jitter included, as the
    /// engine gave it (depth direction unchanged).
    pub fn projection_matrix(&self, width: u32, height: u32) -> Mat4 {
        let mut p = match self.projection {
            Projection::Perspective { fov_y, near, far } => {
                let aspect = width as f32 / height as f32;
                let mut p = if far.is_infinite() {
                    Mat4::perspective_infinite_rh(fov_y, aspect, near)
                } else {
                    Mat4::perspective_rh(fov_y, aspect, near, far)
                };
                // Vulkan's framebuffer Y points down.
                p.y_axis.y = -p.y_axis.y;
                p
            }
            Projection::Orthographic {
                half_height,
                near,
                far,
            } => {
                let half_width = half_height * width as f32 / height as f32;
                let mut p = Mat4::orthographic_rh(
                    -half_width,
                    half_width,
                    -half_height,
                    half_height,
                    near,
                    far,
                );
                p.y_axis.y = -p.y_axis.y;
                p
            }
            Projection::Matrix(m) => m,
        };
        if self.jitter != Vec2::ZERO {
            // Clip x and y move by the jitter's share of the viewport's NDC span, times w.
            let shift = Vec2::new(
                2.0 * self.jitter.x / width as f32,
                2.0 * self.jitter.y / height as f32,
            );
            let w = p.row(3);
            p = Mat4::from_cols(
                add_rows(p.x_axis, shift, w.x),
                add_rows(p.y_axis, shift, w.y),
                add_rows(p.z_axis, shift, w.z),
                add_rows(p.w_axis, shift, w.w),
            );
        }
        p
    }

    /// Whether device depth shrinks with distance (reversed-Z).
    pub fn reversed_depth(&self) -> bool {
        match self.projection {
            Projection::Perspective { .. } | Projection::Orthographic { .. } => false,
            // Orthographic, d = (m22 z + m32) / m33: depth falls with distance (z more
            // negative) when m22 > 0.
            Projection::Matrix(m) if is_orthographic(&m) => m.z_axis.z > 0.0,
            // d = m22 / m23 + m32 / w: depth falls as w grows when m32 > 0.
            Projection::Matrix(m) => m.w_axis.z > 0.0,
        }
    }

    /// How fragments are ordered along the view axis: by clip w, or, under an orthographic
    /// projection (constant w), by device depth.
    pub fn depth_order(&self) -> DepthOrder {
        match self.projection {
            Projection::Orthographic { .. } => DepthOrder::DeviceZ,
            Projection::Matrix(m) if is_orthographic(&m) => DepthOrder::DeviceZ,
            _ => DepthOrder::ClipW,
        }
    }

    /// The projection as translucid uses it: jittered, with depth growing away from the eye
    /// (a reversed-Z projection turned around).
    pub fn clip_from_view(&self, width: u32, height: u32) -> Mat4 {
        let mut p = self.projection_matrix(width, height);
        if self.reversed_depth() {
            for column in [&mut p.x_axis, &mut p.y_axis, &mut p.z_axis, &mut p.w_axis] {
                column.z = column.w - column.z;
            }
        }
        p
    }

    /// The camera's position in the world (zero when the view matrix cannot be inverted).
    pub fn eye(&self) -> Vec3 {
        let eye = self.view.inverse().w_axis.truncate();
        if eye.is_finite() {
            eye
        } else {
            Vec3::ZERO
        }
    }

    /// [`Self::clip_from_view`] × view.
    pub fn view_projection(&self, width: u32, height: u32) -> Mat4 {
        self.clip_from_view(width, height) * self.view
    }

    /// `(a, b, c)` with device depth `a − b / d + c · d` for a point at order depth `d`
    /// ([`crate::raster::order_depth`]), in translucid's depth convention (see
    /// [`Self::clip_from_view`]).
    pub fn depth_mapping(&self, width: u32, height: u32) -> (f32, f32, f32) {
        match self.depth_order() {
            // The order depth is device depth + 1.
            DepthOrder::DeviceZ => (-1.0, 0.0, 1.0),
            DepthOrder::ClipW => {
                let p = self.clip_from_view(width, height);
                // z_clip = m22 z + m32 and w = m23 z, so d = m22 / m23 + m32 / w.
                (p.z_axis.z / p.z_axis.w, -p.w_axis.z, 0.0)
            }
        }
    }

    pub fn validate(&self) -> Result<(), String> {
        if !self.view.is_finite() {
            return Err("view matrix is not finite".into());
        }
        if !self.jitter.is_finite() {
            return Err(format!("jitter {} is not finite", self.jitter));
        }
        match self.projection {
            Projection::Perspective { fov_y, near, far } => {
                if !(fov_y > 0.0 && fov_y < std::f32::consts::PI) {
                    return Err(format!("vertical field of view {fov_y} is not in (0, pi)"));
                }
                if !(near > 0.0 && near.is_finite() && far > near) {
                    return Err(format!(
                        "near {near} and far {far} must satisfy 0 < near < far (far may be \
                         infinite)"
                    ));
                }
                Ok(())
            }
            Projection::Orthographic {
                half_height,
                near,
                far,
            } => {
                if !(half_height > 0.0 && half_height.is_finite()) {
                    return Err(format!(
                        "orthographic half height {half_height} must be positive and finite"
                    ));
                }
                if !(near.is_finite() && far.is_finite() && far > near) {
                    return Err(format!(
                        "orthographic near {near} and far {far} must be finite, near < far"
                    ));
                }
                Ok(())
            }
            Projection::Matrix(m) => check_projection_matrix(&m),
        }
    }

    /// A camera that frames a bounding box from a pleasant angle, used when a glTF file has no
    /// camera of its own.
    pub fn framing(min: Vec3, max: Vec3, fov_y: f32) -> Self {
        let centre = (min + max) * 0.5;
        let radius = ((max - min).length() * 0.5).max(1e-3);
        let distance = radius / (fov_y * 0.5).sin() * 1.05;
        let dir = Vec3::new(0.35, 0.3, 1.0).normalize();
        let eye = centre + dir * distance;
        // Half the gap to the bounding sphere: a near plane tangent to it is reached by the
        // bounding box's corners as the scene turns or moves, and then every triangle of the
        // mesh may cross it as far as the host can tell.
        let near = ((distance - radius) * 0.5).max(distance * 1e-3);
        let far = distance + radius * 2.0;
        Self::look_at(eye, centre, fov_y, near, far)
    }
}

/// A right-handed view matrix at `eye` looking at `target`, up as near +Y as it can be.
pub fn look_at_view(eye: Vec3, target: Vec3) -> Mat4 {
    // Made unit without squaring the distance, which overflows past 1.8e19.
    let forward = crate::shading::unit_or_zero(target - eye);
    let forward = if forward == Vec3::ZERO {
        Vec3::NEG_Z
    } else {
        forward
    };
    // Pick an up vector that is not parallel to the view direction.
    let up = if forward.cross(Vec3::Y).length_squared() < 1e-6 {
        Vec3::Z
    } else {
        Vec3::Y
    };
    Mat4::look_to_rh(eye, forward, up)
}

/// `column` with `shift · w` added to its x and y (a row operation on the matrix).
fn add_rows(column: Vec4, shift: Vec2, w: f32) -> Vec4 {
    Vec4::new(
        column.x + shift.x * w,
        column.y + shift.y * w,
        column.z,
        column.w,
    )
}

/// Whether `m`'s clip w is the same for every point (an orthographic projection).
fn is_orthographic(m: &Mat4) -> bool {
    let w = m.row(3);
    w.x == 0.0 && w.y == 0.0 && w.z == 0.0
}

/// What translucid needs of an engine's projection matrix: finite; clip w proportional to the
/// view depth (perspective) or a positive constant (orthographic); clip z and w free of view
/// x and y (no oblique near plane); depth that changes with distance.
fn check_projection_matrix(m: &Mat4) -> Result<(), String> {
    if !m.is_finite() {
        return Err("projection matrix is not finite".into());
    }
    let (z, w) = (m.row(2), m.row(3));
    if w.x != 0.0 || w.y != 0.0 || z.x != 0.0 || z.y != 0.0 {
        return Err(format!(
            "projection matrix rows 2 and 3 ({z}, {w}) depend on view x or y (an oblique \
             near plane), which translucid does not support"
        ));
    }
    let constant_depth = if is_orthographic(m) {
        if w.w <= 0.0 {
            return Err(format!(
                "projection matrix row 3 is {w}: an orthographic projection's clip w must be \
                 a positive constant"
            ));
        }
        z.z == 0.0
    } else {
        if w.w != 0.0 {
            return Err(format!(
                "projection matrix row 3 is {w}: clip w must be k * view z with k != 0 (a \
                 perspective projection) or a positive constant (an orthographic one)"
            ));
        }
        z.w == 0.0
    };
    if constant_depth {
        return Err(format!(
            "projection matrix row 2 is {z}: depth does not change with distance"
        ));
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    const SIZE: (u32, u32) = (160, 90);

    /// Device depth of the view-space point at distance `d` straight ahead.
    fn depth(c: &Camera, d: f32) -> f32 {
        let clip = c.clip_from_view(SIZE.0, SIZE.1) * Vec4::new(0.0, 0.0, -d, 1.0);
        clip.z / clip.w
    }

    fn with_matrix(m: Mat4) -> Camera {
        Camera {
            projection: Projection::Matrix(m),
            ..Camera::default()
        }
    }

    fn vulkan(mut p: Mat4) -> Mat4 {
        p.y_axis.y = -p.y_axis.y;
        p
    }

    #[test]
    fn reversed_projections_are_turned_around() {
        let aspect = SIZE.0 as f32 / SIZE.1 as f32;
        let forward = Camera::look_at(Vec3::Z * 5.0, Vec3::ZERO, 0.8, 0.5, 50.0);
        // Reversed-Z: near and far swapped.
        let reversed = with_matrix(vulkan(Mat4::perspective_rh(0.8, aspect, 50.0, 0.5)));
        assert!(reversed.reversed_depth() && !forward.reversed_depth());
        for d in [0.5, 1.0, 7.0, 50.0] {
            let (f, r) = (depth(&forward, d), depth(&reversed, d));
            assert!((f - r).abs() < 1e-6, "at {d}: {f} forward, {r} reversed");
        }
        assert!(depth(&forward, 0.5).abs() < 1e-6 && (depth(&forward, 50.0) - 1.0).abs() < 1e-6);
    }

    #[test]
    fn infinite_far_planes_keep_depth_below_one() {
        let aspect = SIZE.0 as f32 / SIZE.1 as f32;
        for m in [
            Mat4::perspective_infinite_rh(0.8, aspect, 0.5),
            Mat4::perspective_infinite_reverse_rh(0.8, aspect, 0.5),
        ] {
            let c = with_matrix(vulkan(m));
            let near = depth(&c, 0.5);
            let far = depth(&c, 1e6);
            assert!(
                near.abs() < 1e-6 && far < 1.0 && far > 0.99,
                "{near}, {far}"
            );
        }
    }

    #[test]
    fn depth_mapping_follows_the_matrix() {
        let aspect = SIZE.0 as f32 / SIZE.1 as f32;
        for c in [
            Camera::look_at(Vec3::Z * 5.0, Vec3::ZERO, 0.8, 0.5, 50.0),
            with_matrix(vulkan(Mat4::perspective_infinite_reverse_rh(
                0.8, aspect, 0.5,
            ))),
        ] {
            let (a, b, c0) = c.depth_mapping(SIZE.0, SIZE.1);
            for d in [0.7f32, 3.0, 40.0] {
                assert!((a - b / d + c0 * d - depth(&c, d)).abs() < 1e-6);
            }
        }
        // Orthographic: order depth is device depth + 1.
        let ortho = with_matrix(vulkan(Mat4::orthographic_rh(
            -1.0, 1.0, -1.0, 1.0, 0.5, 20.0,
        )));
        let (a, b, c0) = ortho.depth_mapping(SIZE.0, SIZE.1);
        for d in [0.5f32, 3.0, 20.0] {
            let device = depth(&ortho, d);
            let order = device + 1.0;
            assert!((a - b / order + c0 * order - device).abs() < 1e-6);
        }
    }

    #[test]
    fn jitter_moves_the_image_by_that_many_pixels() {
        let mut c = Camera::look_at(Vec3::Z * 5.0, Vec3::ZERO, 0.8, 0.5, 50.0);
        let pixel = |c: &Camera| {
            let clip = c.view_projection(SIZE.0, SIZE.1) * Vec4::new(0.3, 0.2, -1.0, 1.0);
            Vec2::new(
                (clip.x / clip.w + 1.0) * 0.5 * SIZE.0 as f32,
                (clip.y / clip.w + 1.0) * 0.5 * SIZE.1 as f32,
            )
        };
        let still = pixel(&c);
        c.jitter = Vec2::new(0.25, -0.5);
        let moved = pixel(&c) - still;
        assert!((moved - c.jitter).length() < 1e-4, "{moved}");
    }

    #[test]
    fn oblique_and_degenerate_matrices_are_refused_with_the_reason() {
        let mut oblique = vulkan(Mat4::perspective_rh(0.8, 1.0, 0.1, 10.0));
        oblique.x_axis.z = 0.2;
        assert!(with_matrix(oblique)
            .validate()
            .expect_err("refused")
            .contains("oblique"));
        let nan = with_matrix(Mat4::NAN);
        assert!(nan.validate().expect_err("refused").contains("not finite"));
        let mut mixed = vulkan(Mat4::perspective_rh(0.8, 1.0, 0.1, 10.0));
        mixed.w_axis.w = 1.0;
        assert!(with_matrix(mixed)
            .validate()
            .expect_err("refused")
            .contains("row 3"));
        let mut flat = vulkan(Mat4::orthographic_rh(-1.0, 1.0, -1.0, 1.0, 0.1, 10.0));
        flat.z_axis.z = 0.0;
        assert!(with_matrix(flat)
            .validate()
            .expect_err("refused")
            .contains("does not change"));
    }

    #[test]
    fn orthographic_matrices_order_by_device_depth_either_way_round() {
        let ortho = vulkan(Mat4::orthographic_rh(-2.0, 2.0, -1.0, 1.0, 0.5, 20.0));
        let c = with_matrix(ortho);
        assert_eq!(c.validate(), Ok(()));
        assert_eq!(c.depth_order(), DepthOrder::DeviceZ);
        assert!(!c.reversed_depth());
        // Reversed: near at 1, far at 0, turned around inside translucid.
        let mut reversed = ortho;
        for column in [&mut reversed.z_axis, &mut reversed.w_axis] {
            column.z = column.w - column.z;
        }
        let r = with_matrix(reversed);
        assert!(r.reversed_depth());
        for d in [0.5, 3.0, 20.0] {
            assert!((depth(&c, d) - depth(&r, d)).abs() < 1e-6, "{d}");
        }
        assert!(depth(&c, 0.5).abs() < 1e-6 && (depth(&c, 20.0) - 1.0).abs() < 1e-6);
        assert_eq!(Camera::default().depth_order(), DepthOrder::ClipW);
    }
}
