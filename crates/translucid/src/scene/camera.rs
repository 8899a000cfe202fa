//! Perspective camera with Vulkan conventions: right-handed view space looking down -Z,
//! framebuffer Y down, depth 0 at the near plane and 1 at the far plane.

use glam::{Mat4, Vec3};

#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Camera {
    /// World to view transform.
    pub view: Mat4,
    /// Vertical field of view, radians.
    pub fov_y: f32,
    pub near: f32,
    pub far: f32,
}

impl Default for Camera {
    fn default() -> Self {
        Self::look_at(Vec3::new(0.0, 0.0, 5.0), Vec3::ZERO, 0.8, 0.1, 100.0)
    }
}

impl Camera {
    pub fn look_at(eye: Vec3, target: Vec3, fov_y: f32, near: f32, far: f32) -> Self {
        let forward = (target - eye).normalize_or(Vec3::NEG_Z);
        // Pick an up vector that is not parallel to the view direction.
        let up = if forward.cross(Vec3::Y).length_squared() < 1e-6 {
            Vec3::Z
        } else {
            Vec3::Y
        };
        Self {
            view: Mat4::look_at_rh(eye, target, up),
            fov_y,
            near,
            far,
        }
    }

    /// The projection for a viewport of the given aspect ratio (width / height).
    /// Maps view space to Vulkan clip space: y flipped so +Y is up on screen, z in [0, w].
    pub fn projection(&self, aspect: f32) -> Mat4 {
        let mut p = Mat4::perspective_rh(self.fov_y, aspect, self.near, self.far);
        p.y_axis.y = -p.y_axis.y;
        p
    }

    /// Projection × view.
    pub fn view_projection(&self, aspect: f32) -> Mat4 {
        self.projection(aspect) * self.view
    }

    pub fn validate(&self) -> Result<(), String> {
        if !self.view.is_finite() {
            return Err("view matrix is not finite".into());
        }
        if !(self.fov_y > 0.0 && self.fov_y < std::f32::consts::PI) {
            return Err(format!(
                "vertical field of view {} is not in (0, pi)",
                self.fov_y
            ));
        }
        if !(self.near > 0.0 && self.far > self.near && self.far.is_finite()) {
            return Err(format!(
                "near {} and far {} must satisfy 0 < near < far < infinity",
                self.near, self.far
            ));
        }
        Ok(())
    }

    /// A camera that frames a bounding box from a pleasant angle, used when a glTF file has no
    /// camera of its own.
    pub fn framing(min: Vec3, max: Vec3, fov_y: f32) -> Self {
        let centre = (min + max) * 0.5;
        let radius = ((max - min).length() * 0.5).max(1e-3);
        let distance = radius / (fov_y * 0.5).sin() * 1.05;
        let dir = Vec3::new(0.35, 0.3, 1.0).normalize();
        let eye = centre + dir * distance;
        let near = (distance - radius).max(distance * 1e-3);
        let far = distance + radius * 2.0;
        Self::look_at(eye, centre, fov_y, near, far)
    }
}
