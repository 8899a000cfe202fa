//! The frame loop translucid is measured and tested on: the camera circles the scene and
//! every third transparent draw moves, a little each frame, as in an engine.

#![deny(unsafe_code)]

use super::{Camera, Draw, Scene};
use glam::{Mat4, Vec3};

/// Radians the camera turns per frame: a full circle in about 160 frames.
const TURN_PER_FRAME: f32 = 0.04;

/// A scene's orbit: where the camera circles and how far its draws move.
#[derive(Clone, Copy, Debug)]
pub struct Orbit {
    /// The centre of the transparent draws' bounds: the camera turns about the vertical
    /// axis through it.
    centre: Vec3,
    /// Radius of the circle a moving draw travels: 2 % of the bounds' diagonal.
    sway: f32,
}

impl Orbit {
    pub fn new(scene: &Scene) -> Self {
        let mut min = Vec3::splat(f32::MAX);
        let mut max = Vec3::splat(f32::MIN);
        for draw in &scene.transparent {
            for &p in &scene.meshes[draw.mesh].positions {
                let world = draw.transform.transform_point3(p);
                min = min.min(world);
                max = max.max(world);
            }
        }
        if min.x > max.x {
            // No transparent vertex: circle the origin, move nothing far.
            (min, max) = (Vec3::ZERO, Vec3::ZERO);
        }
        Self {
            centre: (min + max) * 0.5,
            sway: (max - min).length() * 0.02,
        }
    }

    /// The camera of frame `index`: the scene's, turned `index` steps about the centre.
    pub fn camera(&self, scene: &Scene, index: u32) -> Camera {
        let turn = Mat4::from_translation(self.centre)
            * Mat4::from_rotation_y(index as f32 * TURN_PER_FRAME)
            * Mat4::from_translation(-self.centre);
        Camera {
            view: scene.camera.view * turn,
            ..scene.camera
        }
    }

    /// Frame `index`'s transparent draws into `draws`: the scene's, every third one moved
    /// along a small circle of its own phase.
    pub fn transparent(&self, scene: &Scene, index: u32, draws: &mut Vec<Draw>) {
        draws.clear();
        draws.extend(scene.transparent.iter().enumerate().map(|(k, d)| {
            if k % 3 != 0 {
                return d.clone();
            }
            let phase = index as f32 * TURN_PER_FRAME * 3.0 + k as f32;
            let offset = Vec3::new(
                phase.cos() - (k as f32).cos(),
                phase.sin() - (k as f32).sin(),
                0.0,
            );
            Draw {
                transform: Mat4::from_translation(offset * self.sway) * d.transform,
                ..d.clone()
            }
        }));
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn frame_zero_is_the_scene_and_later_frames_move() {
        let scene = super::super::load("spheres").expect("spheres");
        let orbit = Orbit::new(&scene);
        let mut draws = Vec::new();
        orbit.transparent(&scene, 0, &mut draws);
        assert_eq!(orbit.camera(&scene, 0), scene.camera);
        for (a, b) in draws.iter().zip(&scene.transparent) {
            assert!(a.transform.abs_diff_eq(b.transform, 1e-5));
        }
        orbit.transparent(&scene, 5, &mut draws);
        assert_ne!(orbit.camera(&scene, 5).view, scene.camera.view);
        assert_ne!(draws[0].transform, scene.transparent[0].transform);
        assert_eq!(draws[1].transform, scene.transparent[1].transform);
    }
}
