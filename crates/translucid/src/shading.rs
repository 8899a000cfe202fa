//! The shading function shared by every method and the CPU reference.
//!
//! `shaders/common/shading.glsl` implements the same mapping on the GPU; a test runs both on
//! the same inputs and requires them to agree. Change one, change the other.
//!
//! A fragment's base colour is `material.base_colour × vertex colour × texel`; its alpha is
//! coverage `a`. Lit materials see `ambient + light × |n·l|` (two-sided Lambert: thin
//! transparent surfaces are lit from either side). Then, with transmission `t`, reflectance `r`
//! and tint `k`:
//!
//! ```text
//! L = a · ((1 − t) · rgb · lighting + t · r · lighting)
//! T = (1 − a) + a · t · (1 − r) · k · rgb          (per channel)
//! ```
//!
//! Plain alpha (`t = 0`) gives the classic `L = a·c`, `T = 1 − a` on every channel.

#![deny(unsafe_code)]

use crate::scene::{Light, Material};
use glam::{DMat3, Mat3, Mat4, Vec3, Vec4};

/// The largest colour value translucid takes and gives: the largest finite half float, what
/// the colour targets hold. Colour inputs (base colours, vertex colours, tints, the light,
/// the background, the opaque layer) above it are refused; a fragment's radiance and every
/// method's output are clamped to it, so that no output is infinite.
pub const MAX_COLOUR: f32 = 65504.0;

/// A transparent fragment in the fragment model: premultiplied radiance and per-channel
/// transmittance.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Fragment {
    pub radiance: Vec3,
    pub transmittance: Vec3,
}

/// Whether every channel of `colour` is in [0, [`MAX_COLOUR`]] (NaN is not).
pub fn is_colour(colour: impl Into<glam::Vec4>) -> bool {
    let c: Vec4 = colour.into();
    c.cmpge(Vec4::ZERO).all() && c.cmple(Vec4::splat(MAX_COLOUR)).all()
}

/// Light arriving at a surface with normal `normal` (any length, however small or large;
/// zero or not finite means unlit by the directional light).
pub fn lighting(material: &Material, light: &Light, normal: Vec3) -> Vec3 {
    if !material.lit {
        return Vec3::ONE;
    }
    let n = unit_or_zero(normal);
    let l = light.direction.normalize_or_zero();
    light.ambient + light.colour * n.dot(l).abs()
}

/// `v` divided by its largest component (each component then in [-1, 1]), or zero when it
/// has no direction (zero or not finite): a vector at any scale brought to one where squares
/// and cross products neither underflow (a scene at scale 1e-12) nor overflow (1e19).
fn to_unit_scale(v: Vec3) -> Vec3 {
    let largest = v.abs().max_element();
    if largest > 0.0 && largest.is_finite() {
        v / largest
    } else {
        Vec3::ZERO
    }
}

/// `v` at unit length, or zero when it has no direction (zero or not finite), at any scale.
pub fn unit_or_zero(v: Vec3) -> Vec3 {
    to_unit_scale(v).normalize_or_zero()
}

/// The matrix that takes a draw's vertex normals to world space, for the reference and the
/// GPU alike: the cofactor matrix of the model's upper 3x3 (its inverse transpose times its
/// determinant, so it is defined for a singular model, one that flattens the mesh, where the
/// inverse is not; the sign a mirroring model gives it does not matter to two-sided
/// lighting, and normals are made unit after it). Computed in f64 and scaled so that its
/// largest entry is 1, so that no scale of the model overflows or underflows it; zero when
/// every entry is.
pub fn normal_matrix(model: &Mat4) -> Mat3 {
    let m = Mat3::from_mat4(*model).as_dmat3();
    let cofactors = DMat3::from_cols(
        m.y_axis.cross(m.z_axis),
        m.z_axis.cross(m.x_axis),
        m.x_axis.cross(m.y_axis),
    );
    let largest = cofactors
        .to_cols_array()
        .iter()
        .fold(0.0f64, |most, v| most.max(v.abs()));
    if largest > 0.0 && largest.is_finite() {
        (cofactors * (1.0 / largest)).as_mat3()
    } else {
        Mat3::ZERO
    }
}

/// The face normal of a triangle with edges `e1` and `e2` from one corner (unnormalised, its
/// sign unimportant: lighting is two-sided), at any scale; zero for a degenerate or
/// non-finite triangle.
pub fn face_normal(e1: Vec3, e2: Vec3) -> Vec3 {
    to_unit_scale(e1).cross(to_unit_scale(e2))
}

/// Base colour and alpha of a fragment before lighting.
pub fn base_colour(material: &Material, vertex_colour: Vec4, texel: Vec4) -> Vec4 {
    material.base_colour * vertex_colour * texel
}

/// Maps a transparent fragment to (L, T).
pub fn shade_transparent(
    material: &Material,
    light: &Light,
    vertex_colour: Vec4,
    texel: Vec4,
    normal: Vec3,
) -> Fragment {
    let base = base_colour(material, vertex_colour, texel);
    let a = base.w.clamp(0.0, 1.0);
    let rgb = base.truncate();
    let lit = lighting(material, light, normal);
    let t = material.transmission;
    let r = material.reflectance;
    // Clamped before the coverage multiplies it: rgb · lit may pass f32's range.
    let radiance = a * ((1.0 - t) * rgb * lit + t * r * lit).min(Vec3::splat(MAX_COLOUR));
    let transmittance = Vec3::splat(1.0 - a) + a * t * (1.0 - r) * material.transmission_tint * rgb;
    Fragment {
        radiance,
        transmittance: transmittance.clamp(Vec3::ZERO, Vec3::ONE),
    }
}

/// Colour of an opaque fragment, or `None` when an alpha cutoff discards it.
pub fn shade_opaque(
    material: &Material,
    light: &Light,
    vertex_colour: Vec4,
    texel: Vec4,
    normal: Vec3,
) -> Option<Vec3> {
    let base = base_colour(material, vertex_colour, texel);
    if material.alpha_cutoff.is_some_and(|cut| base.w < cut) {
        return None;
    }
    Some(base.truncate() * lighting(material, light, normal))
}

/// Composites fragments sorted front to back over an opaque colour:
/// `L_acc += T_acc · L_i; T_acc *= T_i; final = L_acc + T_acc · opaque`.
pub fn composite_front_to_back(
    fragments: impl IntoIterator<Item = Fragment>,
    opaque: Vec3,
) -> Vec3 {
    composite_until(fragments, opaque, 0.0)
}

/// [`composite_front_to_back`] that stops once every channel of the transmittance is below
/// `threshold` (the exact method's early stop; 0 never stops), the opaque colour still
/// dimmed by what is left. The result is clamped to [`MAX_COLOUR`].
pub fn composite_until(
    fragments: impl IntoIterator<Item = Fragment>,
    opaque: Vec3,
    threshold: f32,
) -> Vec3 {
    let mut radiance = Vec3::ZERO;
    let mut transmittance = Vec3::ONE;
    for f in fragments {
        if threshold > 0.0 && transmittance.cmplt(Vec3::splat(threshold)).all() {
            break;
        }
        radiance += transmittance * f.radiance;
        transmittance *= f.transmittance;
    }
    (radiance + transmittance * opaque).min(Vec3::splat(MAX_COLOUR))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn plain_alpha_is_premultiplied_over() {
        let m = Material::alpha(Vec3::new(1.0, 0.5, 0.0), 0.25);
        let f = shade_transparent(&m, &Light::default(), Vec4::ONE, Vec4::ONE, Vec3::Z);
        assert_eq!(f.radiance, Vec3::new(0.25, 0.125, 0.0));
        assert_eq!(f.transmittance, Vec3::splat(0.75));
    }

    #[test]
    fn full_transmission_filters_per_channel() {
        let m = Material {
            base_colour: Vec4::new(1.0, 1.0, 1.0, 1.0),
            transmission: 1.0,
            transmission_tint: Vec3::new(1.0, 0.5, 0.25),
            ..Material::default()
        };
        let f = shade_transparent(&m, &Light::default(), Vec4::ONE, Vec4::ONE, Vec3::Z);
        assert_eq!(f.radiance, Vec3::ZERO);
        assert_eq!(f.transmittance, Vec3::new(1.0, 0.5, 0.25));
    }

    /// A lit surface shades the same at every scale: face normals of scenes at 1e-12 or
    /// 1e19 once lost the diffuse term (their squared lengths under- or overflowed).
    #[test]
    fn face_normals_and_lighting_hold_at_every_scale() {
        let lit = Material {
            lit: true,
            ..Material::alpha(Vec3::ONE, 0.5)
        };
        let light = Light::default();
        let at_one = lighting(&lit, &light, face_normal(Vec3::X, Vec3::new(0.3, 1.0, 0.2)));
        for scale in [1e-30f32, 1e-12, 1e-9, 1e10, 1e12, 1e19, 1e30] {
            let e1 = Vec3::X * scale;
            let e2 = Vec3::new(0.3, 1.0, 0.2) * scale;
            let n = face_normal(e1, e2);
            let shaded = lighting(&lit, &light, n);
            assert!(
                (shaded - at_one).abs().max_element() < 1e-5,
                "{scale}: {shaded} against {at_one}"
            );
        }
        for bad in [
            Vec3::ZERO,
            Vec3::splat(f32::NAN),
            Vec3::new(f32::INFINITY, 0.0, 0.0),
        ] {
            assert_eq!(unit_or_zero(bad), Vec3::ZERO, "{bad}");
            assert_eq!(face_normal(bad, Vec3::Y), Vec3::ZERO, "{bad}");
        }
    }

    #[test]
    fn two_layers_composite_by_hand() {
        // Red at alpha 0.5 in front of blue at alpha 0.5 over white:
        // L = 0.5*red + 0.5*(0.5*blue); T = 0.25; final = (0.5, 0, 0.25) + 0.25.
        let red = Fragment {
            radiance: Vec3::new(0.5, 0.0, 0.0),
            transmittance: Vec3::splat(0.5),
        };
        let blue = Fragment {
            radiance: Vec3::new(0.0, 0.0, 0.5),
            transmittance: Vec3::splat(0.5),
        };
        let c = composite_front_to_back([red, blue], Vec3::ONE);
        assert_eq!(c, Vec3::new(0.75, 0.25, 0.5));
    }
}
