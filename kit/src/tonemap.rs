//! HDR to display: Reinhard (x / (1 + x)) then the sRGB transfer curve, to 8 bits. Images shown
//! to people and the perceptual metrics (PSNR, FLIP) use this display-referred form.

use anyhow::{Result, ensure};
use image::RgbaImage;

fn srgb_encode(linear: f32) -> f32 {
    if linear <= 0.003_130_8 { 12.92 * linear } else { 1.055 * linear.powf(1.0 / 2.4) - 0.055 }
}

/// One HDR channel to an 8-bit display value; NaN shows as 0 (and is caught by finiteness checks).
pub fn display_channel(value: f32) -> u8 {
    let mapped = if value.is_finite() { value.max(0.0) / (1.0 + value.max(0.0)) } else { 0.0 };
    (srgb_encode(mapped) * 255.0).round() as u8
}

/// RGBA f32 texels (row-major, `width * height * 4` values) to a display image.
pub fn to_display(width: u32, height: u32, rgba: &[f32]) -> Result<RgbaImage> {
    ensure!(rgba.len() == (width * height * 4) as usize, "{} channels for a {width}x{height} image", rgba.len());
    let bytes = rgba
        .chunks_exact(4)
        .flat_map(|t| [display_channel(t[0]), display_channel(t[1]), display_channel(t[2]), 255])
        .collect();
    Ok(RgbaImage::from_raw(width, height, bytes).expect("size checked"))
}

/// Linear RGB already in 0..1 (no tone curve, clamped) to sRGB display pixels.
pub fn ldr_to_display(width: u32, height: u32, rgb: &[[f32; 3]]) -> Result<RgbaImage> {
    ensure!(rgb.len() == (width * height) as usize, "{} pixels for a {width}x{height} image", rgb.len());
    let encode = |v: f32| (srgb_encode(if v.is_finite() { v.clamp(0.0, 1.0) } else { 0.0 }) * 255.0).round() as u8;
    let bytes = rgb.iter().flat_map(|p| [encode(p[0]), encode(p[1]), encode(p[2]), 255]).collect();
    Ok(RgbaImage::from_raw(width, height, bytes).expect("size checked"))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The sRGB transfer function (IEC 61966-2-1), in f64.
    fn srgb(linear: f64) -> f64 {
        if linear <= 0.003_130_8 { 12.92 * linear } else { 1.055 * linear.powf(1.0 / 2.4) - 0.055 }
    }

    #[test]
    fn a_channel_is_reinhard_then_srgb_to_8_bits() {
        for value in [0.0f32, 0.001, 0.002, 0.05, 0.25, 1.0, 3.0, 40.0, 1e6] {
            let mapped = f64::from(value) / (1.0 + f64::from(value));
            let expected = (srgb(mapped) * 255.0).round() as u8;
            assert_eq!(display_channel(value), expected, "{value}");
        }
        // Below the linear segment's end, and at its end, the straight line.
        assert!((srgb_encode(0.002) - 12.92 * 0.002).abs() < 1e-7);
        assert!((srgb_encode(0.003_130_8) - 12.92 * 0.003_130_8).abs() < 1e-7);
        assert!((srgb_encode(0.5) - srgb(0.5) as f32).abs() < 1e-6 && (srgb_encode(1.0) - 1.0).abs() < 1e-6);
        for nothing in [-1.0, f32::NAN, f32::INFINITY, f32::NEG_INFINITY] {
            assert_eq!(display_channel(nothing), 0, "{nothing}");
        }
    }

    #[test]
    fn images_keep_their_size_order_and_opaque_alpha_and_refuse_a_wrong_length() {
        let image = to_display(2, 1, &[1.0, 0.0, 3.0, 0.2, 0.0, 0.25, 0.0, 0.9]).unwrap();
        assert_eq!(image.dimensions(), (2, 1));
        assert_eq!(image.get_pixel(0, 0).0, [display_channel(1.0), 0, display_channel(3.0), 255]);
        assert_eq!(image.get_pixel(1, 0).0, [0, display_channel(0.25), 0, 255]);
        assert!(to_display(2, 2, &[0.0; 8]).is_err());
        // Display-referred input: clamped to 0..1, no tone curve.
        let ldr = ldr_to_display(3, 1, &[[0.5, 1.5, -1.0], [f32::NAN, 0.002, 1.0], [0.0, 0.0, 0.0]]).unwrap();
        let encode = |v: f64| (srgb(v) * 255.0).round() as u8;
        assert_eq!(ldr.get_pixel(0, 0).0, [encode(0.5), 255, 0, 255]);
        assert_eq!(ldr.get_pixel(1, 0).0, [0, encode(0.002), 255, 255]);
        assert!(ldr_to_display(2, 1, &[[0.0; 3]]).is_err());
    }
}
