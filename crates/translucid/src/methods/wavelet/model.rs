//! The `wavelet` method on the CPU, pass for pass like its shaders, over the reference's
//! fragments: a test requires the GPU image to match it within 2/255. It keeps the GPU's
//! storage: with coefficient images, half-float coefficients and the RGBA16F frame colour are
//! rounded after every addition, in submission order, as blending into those targets rounds
//! them; in the bins, coefficients and colour stay in single precision until the one write,
//! and every addend is rounded to a multiple of 2^-16 first, as the bin raster rounds them.

#![deny(unsafe_code)]

use super::math;
use super::{Precision, Settings, Storage, ABSORBED_TRANSMITTANCE};
use crate::image::{Image, OpaqueLayer};
use crate::reference::{self, PixelFragment};
use crate::scene::Scene;
use glam::Vec3;

/// `v` stored in an RGBA16F target by a blend. Lavapipe rounds towards zero there (measured:
/// rounding to nearest leaves the model further from the GPU than not rounding at all).
fn half_floats(v: Vec3) -> Vec3 {
    v.to_array().map(half_towards_zero).into()
}

/// `v` stored in an RGBA16F image by a shader (rounded to nearest).
fn half_nearest(v: Vec3) -> Vec3 {
    v.to_array().map(|x| half::f16::from_f32(x).to_f32()).into()
}

fn half_towards_zero(x: f32) -> f32 {
    let h = half::f16::from_f32(x);
    if h.is_finite() && h.to_f32().abs() > x.abs() {
        // Sign and magnitude: one less in the bits is one step towards zero.
        half::f16::from_bits(h.to_bits() - 1).to_f32()
    } else {
        h.to_f32()
    }
}

/// The bin raster's rounding of what it sums (`waveletQuantize` in wavelet.glsl), which makes
/// its sums exact and so independent of the order of its lists.
const QUANTUM: f32 = 65536.0;

fn quantized(v: Vec3) -> Vec3 {
    Vec3::from((v * QUANTUM).to_array().map(f32::round_ties_even)) / QUANTUM
}

/// What the model needs besides the fragments: the settings and the camera's depth mapping.
#[derive(Clone, Copy, Debug)]
pub struct Model {
    pub settings: Settings,
    /// Device depth = `depth_a − depth_b / d + depth_c · d` at order depth `d`.
    pub depth_a: f32,
    pub depth_b: f32,
    pub depth_c: f32,
}

impl Model {
    /// The model of `settings` for `scene`'s camera at `width` x `height`.
    pub fn new(settings: Settings, scene: &Scene, width: u32, height: u32) -> Self {
        let (depth_a, depth_b, depth_c) = scene.camera.depth_mapping(width, height);
        Self {
            settings,
            depth_a,
            depth_b,
            depth_c,
        }
    }

    /// `sum + addend`, stored as the variant stores a coefficient.
    fn add_coefficient(&self, sum: Vec3, addend: Vec3) -> Vec3 {
        match (self.settings.storage, self.settings.precision) {
            (Storage::Images, Precision::Half) => half_floats(sum + addend),
            (Storage::Images, Precision::Single) => sum + addend,
            (Storage::Bins, _) => sum + quantized(addend),
        }
    }

    /// The final colour of pixel (x, y): `fragments` in submission order over `opaque`.
    pub fn resolve(&self, x: u32, y: u32, fragments: &[PixelFragment], opaque: Vec3) -> Vec3 {
        let Settings { rank, noise, .. } = self.settings;
        // Pass 1: bounds.
        let (nearest, farthest) = fragments.iter().fold((f32::MAX, -f32::MAX), |(n, f), p| {
            (n.min(p.view_depth), f.max(p.view_depth))
        });
        let pixel_noise = math::pixel_noise(x, y);
        let position = |f: &PixelFragment| {
            let v = math::normalized_depth(f.view_depth, nearest, farthest);
            math::noisy_cell_position(v, rank, noise, pixel_noise)
        };
        // Pass 2: coefficients, in the order the blend sees them.
        let mut coefficients = vec![Vec3::ZERO; math::coefficient_count(rank)];
        for f in fragments {
            let a = math::absorbance(f.fragment.transmittance);
            for (i, addend) in math::event_addends(position(f), rank, a) {
                coefficients[i] = self.add_coefficient(coefficients[i], addend);
            }
        }
        let cells = math::synthesize(&coefficients, rank);
        // Pass 3: the opaque layer dimmed, and the depth from which nothing is visible.
        // The frame colour is RGBA16F: every blend into it rounds.
        let behind = math::transmittance(math::absorbance_behind_all(&cells)) * opaque;
        let cut = math::opaque_position(&cells, -ABSORBED_TRANSMITTANCE.ln()).and_then(|p| {
            let last = (math::coefficient_count(rank) - 1) as f32;
            let slack = noise.clamp(0.0, 0.5 * last) * pixel_noise;
            let v = ((p + slack) / last).min(1.0);
            // A cut that maps back onto the nearest depth (a pixel of one depth) hides
            // nothing: every fragment is in cell 0, in front of it.
            let view = nearest + v * (farthest - nearest);
            (view > nearest).then(|| self.depth_a - self.depth_b / view + self.depth_c * view)
        });
        // Pass 4: shading.
        let lit = fragments
            .iter()
            .filter(|f| !cut.is_some_and(|c| f.device_depth >= c))
            .map(|f| {
                let own = math::absorbance(f.fragment.transmittance);
                let in_front = math::absorbance_in_front(&cells, position(f), own);
                f.fragment.radiance * math::transmittance(in_front)
            });
        match self.settings.storage {
            // Blended one by one into the dimmed opaque colour.
            Storage::Images => lit.fold(half_floats(behind), |c, l| half_floats(c + l)),
            // Summed apart, quantized, then added to it in one store.
            Storage::Bins => {
                half_nearest(behind + lit.fold(Vec3::ZERO, |sum, l| sum + quantized(l)))
            }
        }
    }

    /// The whole frame over `opaque`.
    pub fn render(&self, scene: &Scene, opaque: &OpaqueLayer) -> crate::Result<Image> {
        reference::render_with(scene, opaque, &|x, y, fragments, opaque| {
            self.resolve(x, y, fragments, opaque)
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::shading::Fragment;

    /// One fully opaque fragment (alpha 1: absorbance at its limit) is exact at every rank
    /// in both storages: its own share is removed, and nothing hides it. The depth cut once
    /// mapped back onto the fragment's own depth and culled it at random.
    #[test]
    fn a_lone_opaque_fragment_is_its_own_colour() {
        let colour = Vec3::new(0.9, 0.5, 0.1);
        let fragment = PixelFragment {
            view_depth: 3.0,
            device_depth: 0.75,
            fragment: Fragment {
                radiance: colour,
                transmittance: Vec3::ZERO,
            },
        };
        for storage in [Storage::Bins, Storage::Images] {
            for rank in 0..=math::MAX_RANK {
                let model = Model {
                    settings: Settings {
                        rank,
                        noise: 0.0,
                        precision: Precision::Single,
                        storage,
                    },
                    // Device depth 0.75 at view depth 3: a - b / 3 = 0.75.
                    depth_a: 1.0,
                    depth_b: 0.75,
                    depth_c: 0.0,
                };
                let got = model.resolve(0, 0, &[fragment], Vec3::ONE);
                assert!(
                    (got - colour).abs().max_element() < 2e-3,
                    "rank {rank}, {storage:?}: {got} instead of {colour}"
                );
            }
        }
    }
}
