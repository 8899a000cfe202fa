//! Image error measures, on display-encoded values: what a viewer sees, and what the
//! "within 2/255 per channel" promise of the exact method is stated in.
//!
//! Every measure works on [`Image::srgb`] (sRGB encoding, 0–1 scale, not quantised), RGB
//! only; alpha is ignored.

#![deny(unsafe_code)]

use crate::image::{srgb_to_linear, Image};
use glam::{Vec3, Vec4};

/// A per-channel difference above this counts a pixel as "over" (the exact method's bound).
pub const TOLERANCE: f32 = 2.0 / 255.0;
/// Differences at or above this show as white in [`heat_map`].
pub const HEAT_SATURATION: f32 = 8.0 / 255.0;

/// How far two images are apart.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Metrics {
    /// Largest absolute difference of any channel of any pixel.
    pub max_error: f32,
    /// Root mean square of the per-channel differences.
    pub rmse: f32,
    /// Peak signal-to-noise ratio in dB for a peak of 1: `10 log10(1 / mse)`.
    /// `f32::INFINITY` when the images are identical (mse = 0).
    pub psnr: f32,
    /// Pixels with any channel off by more than [`TOLERANCE`].
    pub pixels_over: u64,
    /// `pixels_over` as a share of all pixels (0 for an empty image).
    pub share_over: f64,
    /// Pixels with a NaN or infinite colour channel in either image. Each counts as over;
    /// any makes `max_error` and `rmse` infinite and `psnr` minus infinity, so that no bound
    /// passes them and no score reads perfect.
    pub non_finite: u64,
}

impl Metrics {
    /// Whether every pixel is finite and within `bound` in every channel.
    pub fn within(&self, bound: f32) -> bool {
        self.non_finite == 0 && self.max_error <= bound
    }
}

fn check_sizes(a: &Image, b: &Image) -> crate::Result<()> {
    if (a.width, a.height) != (b.width, b.height) {
        return Err(crate::Error::InvalidViewport {
            width: b.width,
            height: b.height,
            reason: format!("cannot compare with an image of {}x{}", a.width, a.height),
        });
    }
    Ok(())
}

/// Absolute per-channel difference of the display-encoded colours of every pixel, row-major.
fn differences<'a>(a: &'a Image, b: &'a Image) -> impl Iterator<Item = Vec3> + 'a {
    (0..a.height).flat_map(move |y| (0..a.width).map(move |x| (a.srgb(x, y) - b.srgb(x, y)).abs()))
}

/// Compares two images of the same size. A pixel that is not finite in either image is
/// never a match (see [`Metrics::non_finite`]).
pub fn compare(a: &Image, b: &Image) -> crate::Result<Metrics> {
    check_sizes(a, b)?;
    let mut max_error = 0.0f32;
    let mut sum_sq = 0.0f64;
    let mut pixels_over = 0u64;
    let mut non_finite = 0u64;
    let finite = |p: &Vec4| p.truncate().is_finite();
    for ((d, pa), pb) in differences(a, b).zip(&a.pixels).zip(&b.pixels) {
        if !(finite(pa) && finite(pb)) {
            non_finite += 1;
            continue;
        }
        max_error = max_error.max(d.max_element());
        sum_sq += d.as_dvec3().length_squared();
        pixels_over += u64::from(d.max_element() > TOLERANCE);
    }
    if non_finite > 0 {
        max_error = f32::INFINITY;
        pixels_over += non_finite;
    }
    let pixels = a.pixels.len() as u64;
    let finite_pixels = pixels - non_finite;
    let mse = if finite_pixels == 0 {
        0.0
    } else {
        sum_sq / (3 * finite_pixels) as f64
    };
    let (rmse, psnr) = if non_finite > 0 {
        (f32::INFINITY, f32::NEG_INFINITY)
    } else if mse == 0.0 {
        (0.0, f32::INFINITY)
    } else {
        (mse.sqrt() as f32, (10.0 * (1.0 / mse).log10()) as f32)
    };
    Ok(Metrics {
        max_error,
        rmse,
        psnr,
        pixels_over,
        share_over: if pixels == 0 {
            0.0
        } else {
            pixels_over as f64 / pixels as f64
        },
        non_finite,
    })
}

/// The heat-map colour (display-encoded) of a largest per-channel difference `d`: black at
/// 0, ramping through red and yellow to white at [`HEAT_SATURATION`], so that a difference of
/// [`TOLERANCE`] already shows as a clear dark red.
pub fn heat_colour(d: f32) -> Vec3 {
    let t = (d / HEAT_SATURATION).clamp(0.0, 1.0) * 3.0;
    Vec3::new(
        t.min(1.0),
        (t - 1.0).clamp(0.0, 1.0),
        (t - 2.0).clamp(0.0, 1.0),
    )
}

/// Per-pixel picture of where two images differ (see [`heat_colour`]); a size mismatch is an
/// error.
pub fn heat_map(a: &Image, b: &Image) -> crate::Result<Image> {
    check_sizes(a, b)?;
    let pixels = differences(a, b)
        .map(|d| {
            let c = heat_colour(d.max_element());
            // The image is linear; decode so the PNG shows the ramp as designed.
            Vec4::new(
                srgb_to_linear(c.x),
                srgb_to_linear(c.y),
                srgb_to_linear(c.z),
                1.0,
            )
        })
        .collect();
    Ok(Image {
        width: a.width,
        height: a.height,
        pixels,
    })
}

/// The images left to right, top-aligned, on black where one is shorter than the tallest.
pub fn side_by_side(images: &[&Image]) -> Image {
    let width = images.iter().map(|i| i.width).sum();
    let height = images.iter().map(|i| i.height).max().unwrap_or(0);
    let mut out = Image::filled(width, height, Vec4::new(0.0, 0.0, 0.0, 1.0));
    let mut left = 0;
    for image in images {
        for y in 0..image.height {
            for x in 0..image.width {
                out.set(left + x, y, image.get(x, y));
            }
        }
        left += image.width;
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A one-row image from display-encoded grey levels in 1/255 steps.
    fn greys(levels: &[u8]) -> Image {
        let pixels = levels
            .iter()
            .map(|&l| Vec3::splat(srgb_to_linear(l as f32 / 255.0)).extend(1.0))
            .collect();
        Image {
            width: levels.len() as u32,
            height: 1,
            pixels,
        }
    }

    #[test]
    fn identical_images_have_infinite_psnr() {
        let a = greys(&[0, 100, 255]);
        let m = compare(&a, &a).expect("same size");
        assert_eq!(m.max_error, 0.0);
        assert_eq!(m.rmse, 0.0);
        assert_eq!(m.psnr, f32::INFINITY);
        assert_eq!((m.pixels_over, m.share_over), (0, 0.0));
    }

    #[test]
    fn hand_computed_differences() {
        // Differences of 0, 1 and 4 levels on all three channels of 4 pixels.
        let a = greys(&[10, 10, 10, 200]);
        let b = greys(&[10, 11, 14, 200]);
        let m = compare(&a, &b).expect("same size");
        let step = 1.0 / 255.0;
        assert!((m.max_error - 4.0 * step).abs() < 1e-5);
        // mse = (0 + 1 + 16 + 0) step² · 3 / 12 = 4.25 step²
        let mse = 4.25 * step * step;
        assert!((m.rmse - mse.sqrt()).abs() < 1e-5);
        assert!((m.psnr - 10.0 * (1.0 / mse).log10()).abs() < 0.01);
        // 1/255 is within the tolerance, 4/255 is not.
        assert_eq!(m.pixels_over, 1);
        assert_eq!(m.share_over, 0.25);
    }

    #[test]
    fn one_channel_over_counts_the_pixel() {
        let a = Image::filled(2, 1, Vec4::new(0.0, 0.0, 0.0, 1.0));
        let mut b = a.clone();
        b.set(1, 0, Vec4::new(0.0, 0.0, 1.0, 1.0));
        let m = compare(&a, &b).expect("same size");
        assert!((m.max_error - 1.0).abs() < 1e-6);
        assert_eq!(m.pixels_over, 1);
        // mse = 1 / 6 -> psnr = 10 log10(6)
        assert!((m.psnr - 10.0 * 6f32.log10()).abs() < 1e-4);
    }

    /// NaN and infinite pixels (vertices at 1e30 give them) never count as a match: they
    /// once left `max_error` at 0 (NaN loses every `max`) and the frame looked perfect.
    #[test]
    fn non_finite_pixels_fail_every_bound() {
        let a = greys(&[10, 10, 10, 10]);
        for bad in [f32::NAN, f32::INFINITY] {
            let mut b = a.clone();
            b.set(2, 0, Vec4::new(bad, 0.0, 0.0, 1.0));
            for (x, y) in [(&a, &b), (&b, &a)] {
                let m = compare(x, y).expect("same size");
                assert_eq!(m.non_finite, 1, "{bad}");
                assert_eq!(m.max_error, f32::INFINITY, "{bad}");
                assert_eq!(m.pixels_over, 1, "{bad}");
                assert!(!m.within(1.0), "{bad}");
                // The finite pixels match, and still the scores say the worst: an all-NaN
                // frame once read "psnr inf, rmse 0".
                assert_eq!(m.rmse, f32::INFINITY, "{bad}");
                assert_eq!(m.psnr, f32::NEG_INFINITY, "{bad}");
            }
        }
        assert!(compare(&a, &a).expect("same size").within(0.0));
    }

    #[test]
    fn size_mismatch_is_an_error() {
        let a = Image::filled(2, 2, Vec4::ONE);
        let b = Image::filled(2, 3, Vec4::ONE);
        assert!(compare(&a, &b).is_err());
        assert!(heat_map(&a, &b).is_err());
    }

    #[test]
    fn heat_map_ramps_from_black_through_red_to_white() {
        assert_eq!(heat_colour(0.0), Vec3::ZERO);
        let two = heat_colour(2.0 / 255.0);
        assert!((two - Vec3::new(0.75, 0.0, 0.0)).abs().max_element() < 1e-5);
        assert!(
            (heat_colour(16.0 / 3.0 / 255.0) - Vec3::new(1.0, 1.0, 0.0))
                .abs()
                .max_element()
                < 1e-5
        );
        assert_eq!(heat_colour(8.0 / 255.0), Vec3::ONE);
        assert_eq!(heat_colour(1.0), Vec3::ONE);
        let map = heat_map(&greys(&[10, 10]), &greys(&[10, 12])).expect("same size");
        assert_eq!(map.srgb(0, 0), Vec3::ZERO);
        assert!((map.srgb(1, 0) - two).abs().max_element() < 1e-3);
    }

    #[test]
    fn side_by_side_places_images_left_to_right() {
        let red = Image::filled(2, 1, Vec4::new(1.0, 0.0, 0.0, 1.0));
        let green = Image::filled(1, 2, Vec4::new(0.0, 1.0, 0.0, 1.0));
        let out = side_by_side(&[&red, &green]);
        assert_eq!((out.width, out.height), (3, 2));
        assert_eq!(out.get(1, 0), red.get(0, 0));
        assert_eq!(out.get(2, 1), green.get(0, 1));
        assert_eq!(out.get(0, 1), Vec4::new(0.0, 0.0, 0.0, 1.0));
        assert_eq!(side_by_side(&[]).pixels.len(), 0);
    }
}
