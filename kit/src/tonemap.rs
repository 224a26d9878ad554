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
