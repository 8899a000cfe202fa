//! A linear-light RGBA float image, the currency between methods, the reference and metrics.

#![deny(unsafe_code)]

use glam::{Vec3, Vec4};

/// Linear-light RGBA, row-major, top row first.
#[derive(Clone, Debug, PartialEq)]
pub struct Image {
    pub width: u32,
    pub height: u32,
    pub pixels: Vec<Vec4>,
}

impl Image {
    /// An image filled with one colour.
    pub fn filled(width: u32, height: u32, colour: Vec4) -> Self {
        Self {
            width,
            height,
            pixels: vec![colour; width as usize * height as usize],
        }
    }

    pub fn get(&self, x: u32, y: u32) -> Vec4 {
        self.pixels[(y * self.width + x) as usize]
    }

    pub fn set(&mut self, x: u32, y: u32, value: Vec4) {
        self.pixels[(y * self.width + x) as usize] = value;
    }

    /// The display-encoded (sRGB) value of one pixel's RGB, in 0..=1, not quantised.
    pub fn srgb(&self, x: u32, y: u32) -> Vec3 {
        let p = self.get(x, y);
        Vec3::new(
            linear_to_srgb(p.x),
            linear_to_srgb(p.y),
            linear_to_srgb(p.z),
        )
    }

    /// 8-bit sRGB RGBA bytes (alpha forced opaque), for PNG output.
    pub fn to_srgb8(&self) -> Vec<u8> {
        let mut out = Vec::with_capacity(self.pixels.len() * 4);
        for p in &self.pixels {
            for c in [p.x, p.y, p.z] {
                out.push(quantize(linear_to_srgb(c)));
            }
            out.push(255);
        }
        out
    }

    /// Writes the image as an 8-bit sRGB PNG.
    pub fn save_png(&self, path: &std::path::Path) -> crate::Result<()> {
        if let Some(dir) = path.parent().filter(|d| !d.as_os_str().is_empty()) {
            std::fs::create_dir_all(dir)?;
        }
        ::image::save_buffer(
            path,
            &self.to_srgb8(),
            self.width,
            self.height,
            ::image::ExtendedColorType::Rgba8,
        )?;
        Ok(())
    }
}

/// Rounds a 0..=1 value to a byte, clamping out-of-range values.
pub fn quantize(v: f32) -> u8 {
    (v.clamp(0.0, 1.0) * 255.0 + 0.5) as u8
}

/// The sRGB transfer function (IEC 61966-2-1), linear light to display encoding.
pub fn linear_to_srgb(v: f32) -> f32 {
    let v = v.clamp(0.0, 1.0);
    if v <= 0.003_130_8 {
        v * 12.92
    } else {
        1.055 * v.powf(1.0 / 2.4) - 0.055
    }
}

/// The inverse sRGB transfer function, display encoding to linear light.
pub fn srgb_to_linear(v: f32) -> f32 {
    if v <= 0.040_45 {
        v / 12.92
    } else {
        ((v + 0.055) / 1.055).powf(2.4)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn srgb_round_trips() {
        for i in 0..=255u8 {
            let e = i as f32 / 255.0;
            assert_eq!(quantize(linear_to_srgb(srgb_to_linear(e))), i);
        }
    }
}

/// The engine's opaque layer: what every transparency method composites onto and depth-tests
/// against. Depth is the Vulkan depth-buffer value in translucid's convention, 0 near and 1
/// far (a transparent fragment is visible where its depth is *less* than this), whatever
/// the camera's projection: an engine with a reversed-Z projection hands over `1 − d`.
#[derive(Clone, Debug, PartialEq)]
pub struct OpaqueLayer {
    pub width: u32,
    pub height: u32,
    /// Linear-light RGB per pixel, row-major, top row first.
    pub colour: Vec<Vec3>,
    pub depth: Vec<f32>,
}

impl OpaqueLayer {
    /// A layer of one colour at the far plane (nothing opaque in the way).
    pub fn clear(width: u32, height: u32, colour: Vec3) -> Self {
        let n = width as usize * height as usize;
        Self {
            width,
            height,
            colour: vec![colour; n],
            depth: vec![1.0; n],
        }
    }

    /// The colour alone, as an image.
    pub fn to_image(&self) -> Image {
        Image {
            width: self.width,
            height: self.height,
            pixels: self.colour.iter().map(|c| c.extend(1.0)).collect(),
        }
    }
}
