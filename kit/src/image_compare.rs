//! Image comparison: per-channel differences, PSNR and an error mask to show where they differ.

use anyhow::{Result, ensure};
use image::{Rgba, RgbaImage};
use serde::Serialize;

#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct ImageDifference {
    /// Pixels where any channel differs by more than the tolerance.
    pub differing_pixels: u64,
    /// Largest per-channel difference, in 8-bit steps.
    pub max_channel_difference: u8,
    /// PSNR over RGB in dB; infinite for identical images.
    pub psnr_db: f64,
}

/// Compares two equally sized images; `tolerance` is in 8-bit steps per channel.
pub fn compare(result: &RgbaImage, reference: &RgbaImage, tolerance: u8) -> Result<(ImageDifference, RgbaImage)> {
    ensure!(
        result.dimensions() == reference.dimensions(),
        "cannot compare a {:?} result with a {:?} reference",
        result.dimensions(),
        reference.dimensions()
    );
    let mut mask = RgbaImage::new(result.width(), result.height());
    let (mut differing, mut max, mut squared) = (0u64, 0u8, 0f64);
    for ((a, b), m) in result.pixels().zip(reference.pixels()).zip(mask.pixels_mut()) {
        let worst = (0..4).map(|c| a[c].abs_diff(b[c])).max().unwrap_or(0);
        squared += (0..3).map(|c| f64::from(a[c].abs_diff(b[c])).powi(2)).sum::<f64>();
        max = max.max(worst);
        *m = if worst > tolerance {
            differing += 1;
            Rgba([255, 0, 0, 255])
        } else {
            Rgba([b[0] / 4, b[1] / 4, b[2] / 4, 255])
        };
    }
    let mse = squared / (3.0 * f64::from(result.width() * result.height()).max(1.0));
    let psnr_db = if mse == 0.0 { f64::INFINITY } else { 10.0 * (255.0f64.powi(2) / mse).log10() };
    Ok((ImageDifference { differing_pixels: differing, max_channel_difference: max, psnr_db }, mask))
}

/// Result, reference and error mask side by side, as VK-GL-CTS writes them.
pub fn side_by_side(result: &RgbaImage, reference: &RgbaImage, mask: &RgbaImage) -> RgbaImage {
    let (w, h) = result.dimensions();
    let mut out = RgbaImage::new(w * 3, h);
    for (i, img) in [result, reference, mask].into_iter().enumerate() {
        image::imageops::replace(&mut out, img, i64::from(w) * i as i64, 0);
    }
    out
}

/// Mean FLIP error (NVIDIA's perceptual metric, 0 = identical, 1 = maximal) of `result` against
/// `reference`, both display-referred sRGB, at FLIP's default viewing conditions.
pub fn flip_mean(result: &RgbaImage, reference: &RgbaImage) -> Result<f32> {
    ensure!(
        result.dimensions() == reference.dimensions(),
        "FLIP needs equal sizes: {:?} vs {:?}",
        result.dimensions(),
        reference.dimensions()
    );
    let rgb = |image: &RgbaImage| image.pixels().flat_map(|p| [p[0], p[1], p[2]]).collect::<Vec<u8>>();
    let (w, h) = result.dimensions();
    let reference = nv_flip::FlipImageRgb8::with_data(w, h, &rgb(reference));
    let test = nv_flip::FlipImageRgb8::with_data(w, h, &rgb(result));
    let error = nv_flip::flip(reference, test, nv_flip::DEFAULT_PIXELS_PER_DEGREE);
    Ok(nv_flip::FlipPool::from_image(&error).mean())
}

/// An error mask from a per-pixel verdict: red where `wrong`, the reference dimmed elsewhere.
pub fn error_mask(reference: &RgbaImage, wrong: &[bool]) -> RgbaImage {
    let mut mask = reference.clone();
    for (pixel, &bad) in mask.pixels_mut().zip(wrong) {
        *pixel = if bad { Rgba([255, 0, 0, 255]) } else { Rgba([pixel[0] / 4, pixel[1] / 4, pixel[2] / 4, 255]) };
    }
    mask
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A 5×3 image whose every channel differs from pixel to pixel.
    fn picture() -> RgbaImage {
        RgbaImage::from_fn(5, 3, |x, y| Rgba([(40 * x + 7) as u8, (50 * y + 3) as u8, (x * y + 90) as u8, 200]))
    }

    #[test]
    fn one_channel_of_one_pixel_past_the_tolerance_is_one_differing_pixel() {
        let reference = picture();
        for channel in 0..4 {
            for (step, tolerance, differing) in [(3u8, 3u8, 0u64), (4, 3, 1), (1, 0, 1), (0, 0, 0)] {
                let mut result = reference.clone();
                result.get_pixel_mut(4, 2)[channel] += step;
                let (difference, mask) = compare(&result, &reference, tolerance).unwrap();
                assert_eq!(
                    (difference.differing_pixels, difference.max_channel_difference),
                    (differing, step),
                    "channel {channel}, step {step}, tolerance {tolerance}"
                );
                let red = Rgba([255, 0, 0, 255]);
                assert_eq!(*mask.get_pixel(4, 2) == red, differing == 1);
                // Elsewhere the mask is the reference dimmed.
                let p = reference.get_pixel(1, 2);
                assert_eq!(*mask.get_pixel(1, 2), Rgba([p[0] / 4, p[1] / 4, p[2] / 4, 255]));
            }
        }
    }

    #[test]
    fn psnr_is_over_the_colour_channels_of_every_pixel() {
        let reference = picture();
        assert_eq!(compare(&reference, &reference, 0).unwrap().0.psnr_db, f64::INFINITY);
        // One channel off by 15 in one pixel of 15: MSE = 225 / 45 = 5.
        let mut result = reference.clone();
        result.get_pixel_mut(0, 0)[1] -= 3;
        result.get_pixel_mut(0, 0)[1] += 18;
        let psnr = compare(&result, &reference, 255).unwrap().0.psnr_db;
        assert!((psnr - 10.0 * (255.0f64 * 255.0 / 5.0).log10()).abs() < 1e-12, "{psnr}");
        // Alpha takes no part in PSNR.
        let mut alpha = reference.clone();
        alpha.get_pixel_mut(2, 1)[3] = 0;
        assert_eq!(compare(&alpha, &reference, 0).unwrap().0.psnr_db, f64::INFINITY);
        assert!(compare(&RgbaImage::new(5, 2), &reference, 0).is_err());
    }

    #[test]
    fn an_error_mask_and_the_strip_keep_each_picture_in_its_place() {
        let reference = picture();
        let mut wrong = vec![false; 15];
        wrong[7] = true;
        let mask = error_mask(&reference, &wrong);
        assert_eq!(*mask.get_pixel(2, 1), Rgba([255, 0, 0, 255]));
        let p = reference.get_pixel(3, 1);
        assert_eq!(*mask.get_pixel(3, 1), Rgba([p[0] / 4, p[1] / 4, p[2] / 4, 255]));
        let result = RgbaImage::from_pixel(5, 3, Rgba([1, 2, 3, 4]));
        let strip = side_by_side(&result, &reference, &mask);
        assert_eq!(strip.dimensions(), (15, 3));
        assert_eq!(
            (strip.get_pixel(4, 2), strip.get_pixel(9, 2), strip.get_pixel(12, 1)),
            (&Rgba([1, 2, 3, 4]), reference.get_pixel(4, 2), mask.get_pixel(2, 1))
        );
    }

    #[test]
    fn flip_sees_one_wrong_pixel_and_not_an_identical_image() {
        let reference = picture();
        assert_eq!(flip_mean(&reference, &reference).unwrap(), 0.0);
        let mut result = reference.clone();
        result.get_pixel_mut(2, 1)[0] = 255;
        assert!(flip_mean(&result, &reference).unwrap() > 0.0);
        assert!(flip_mean(&RgbaImage::new(4, 3), &reference).is_err());
    }
}
