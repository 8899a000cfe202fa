//! Materials: how a surface maps to the fragment model's radiance `L` and transmittance `T`.
//! The mapping itself lives in [`crate::shading`].

use glam::{Vec3, Vec4};

#[derive(Clone, Debug, PartialEq)]
pub struct Material {
    pub name: String,
    /// Linear RGB and alpha (coverage). Multiplied by vertex colour and texture.
    pub base_colour: Vec4,
    /// Base-colour texture (index into `Scene::textures`), sampled with the mesh's UVs.
    pub texture: Option<usize>,
    /// Fraction of the covered light that passes through, tinted, instead of being scattered
    /// (glTF `KHR_materials_transmission`). 0 for ordinary alpha blending.
    pub transmission: f32,
    /// Per-channel filter on the transmitted light, e.g. volume attenuation
    /// `attenuationColour ^ (thickness / attenuationDistance)`. White when there is none.
    pub transmission_tint: Vec3,
    /// Specular reflectance at normal incidence of a transmissive surface (0.04 for ior 1.5).
    pub reflectance: f32,
    /// Lit by the scene light (ambient + two-sided Lambert), or shown at its base colour.
    pub lit: bool,
    /// When false, back faces are culled.
    pub double_sided: bool,
    /// Opaque layer only: fragments with alpha below this are discarded (glTF MASK).
    pub alpha_cutoff: Option<f32>,
}

impl Default for Material {
    fn default() -> Self {
        Self {
            name: String::new(),
            base_colour: Vec4::ONE,
            texture: None,
            transmission: 0.0,
            transmission_tint: Vec3::ONE,
            reflectance: 0.0,
            lit: false,
            double_sided: true,
            alpha_cutoff: None,
        }
    }
}

impl Material {
    /// An unlit, double-sided alpha material.
    pub fn alpha(rgb: Vec3, alpha: f32) -> Self {
        Self {
            base_colour: rgb.extend(alpha),
            ..Self::default()
        }
    }

    pub fn validate(&self) -> Result<(), String> {
        let in_unit = |v: f32| (0.0..=1.0).contains(&v);
        if !crate::shading::is_colour(self.base_colour) {
            return Err(format!(
                "base_colour {:?} must be non-negative and at most {}",
                self.base_colour.to_array(),
                crate::shading::MAX_COLOUR
            ));
        }
        if !in_unit(self.base_colour.w) {
            return Err(format!("alpha {} is not in [0, 1]", self.base_colour.w));
        }
        if !in_unit(self.transmission) || !in_unit(self.reflectance) {
            return Err("transmission and reflectance must be in [0, 1]".into());
        }
        if !self.transmission_tint.is_finite()
            || self.transmission_tint.cmplt(Vec3::ZERO).any()
            || self.transmission_tint.cmpgt(Vec3::ONE).any()
        {
            return Err(format!(
                "transmission_tint {:?} is not in [0, 1]",
                self.transmission_tint.to_array()
            ));
        }
        Ok(())
    }
}
