//! The `wboit` method on the CPU, operation for operation like its shaders
//! (`shaders/wboit/`), over the reference's fragments: a test requires the GPU image to match
//! it within 2/255.

#![deny(unsafe_code)]

use crate::image::{Image, OpaqueLayer};
use crate::reference::{self, PixelFragment};
use crate::scene::Scene;
use glam::Vec3;

/// `shaders/common/wboit.glsl`: `max_c α_c · max(1e-2, 3e3·(1 − z)³)`.
pub fn weight(alpha: Vec3, device_depth: f32) -> f32 {
    let near = 1.0 - device_depth;
    alpha.max_element() * (3e3 * near * near * near).max(1e-2)
}

/// Below this summed weighted opacity a channel has no transparent contribution.
const MIN_OPACITY: f32 = 1e-5;

/// Transmittance clamp before the logarithm.
const MIN_TRANSMITTANCE: f32 = 1e-5;

/// One pixel: f32 sums in submission order, as the RGBA32F targets blend them.
pub fn resolve(fragments: &[PixelFragment], opaque: Vec3) -> Vec3 {
    let mut radiance = Vec3::ZERO;
    let mut opacity = Vec3::ZERO;
    let mut absorbance = Vec3::ZERO;
    for f in fragments {
        let t = f.fragment.transmittance;
        let alpha = Vec3::ONE - t;
        let w = weight(alpha, f.device_depth);
        radiance += w * f.fragment.radiance;
        opacity += w * alpha;
        absorbance += -t.max(Vec3::splat(MIN_TRANSMITTANCE)).ln();
    }
    let revealage = (-absorbance).exp();
    let average = radiance / opacity.max(Vec3::splat(MIN_OPACITY));
    average * (Vec3::ONE - revealage) + revealage * opaque
}

/// The whole frame over `opaque`.
pub fn render(scene: &Scene, opaque: &OpaqueLayer) -> crate::Result<Image> {
    reference::render_with(scene, opaque, &|_, _, fragments, opaque| {
        resolve(fragments, opaque)
    })
}
