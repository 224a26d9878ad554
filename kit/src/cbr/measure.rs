//! Measuring a reconstruction: its error against the full-resolution render of the same frame
//! (bitwise and display-referred: PSNR, FLIP, an error mask), the documented gap column left
//! out, and how many pixels came from each source.

use std::collections::BTreeMap;

use anyhow::{Result, bail};
use image::RgbaImage;
use serde::Serialize;

use super::reconstruct::{PixelSource, Reconstruction};
use super::renderer::{Checkerboard, CheckerboardConfig, FullResolutionScene, HalfResolutionUpscale};
use super::sampling::documented_gaps;
use super::scene::CheckerboardScene;
use crate::gpu::Gpu;
use crate::image_compare::{compare, flip_mean, side_by_side};
use crate::readback::read_texture;
use crate::tonemap::to_display;

/// An HDR target's texels as f32 RGBA.
pub fn read_hdr(gpu: &Gpu, texture: &wgpu::Texture) -> Result<Vec<f32>> {
    Ok(read_texture(gpu, texture, wgpu::TextureAspect::All, 0)?.as_f16())
}

/// The last of a run of frames, checkerboarded and at full resolution, read back.
pub struct ComparedFrame {
    /// HDR RGBA of the reconstruction and of the full-resolution render.
    pub result: Vec<f32>,
    pub reference: Vec<f32>,
    pub sources: Vec<PixelSource>,
    /// The passes the last frame ran, and the ones its plan lists.
    pub passes: Vec<String>,
    pub planned: Vec<&'static str>,
}

/// Renders frames 0..`frames` of `scene` checkerboarded, and the last one at full resolution.
pub fn render_with_reference(
    gpu: &Gpu,
    scene: &CheckerboardScene,
    config: CheckerboardConfig,
    frames: u32,
) -> Result<ComparedFrame> {
    let mut checkerboard = Checkerboard::new(gpu, scene, config)?;
    let mut passes = Vec::new();
    for frame in 0..frames.max(1) {
        passes = checkerboard.render(gpu, frame)?.passes;
    }
    let mut fullres = FullResolutionScene::new(gpu, scene, config.screen)?;
    fullres.render(gpu, frames.max(1) - 1)?;
    Ok(ComparedFrame {
        result: read_hdr(gpu, &checkerboard.reconstruction.colour)?,
        reference: read_hdr(gpu, fullres.output())?,
        sources: read_sources(gpu, &checkerboard.reconstruction)?,
        passes,
        planned: checkerboard.plan().passes(),
    })
}

/// What a reconstruction of frame `frame` is held to where it cannot match full resolution
/// exactly: references measured in the same run from the same frame, each as PSNR against the
/// full-resolution render — the quarter-resolution render upscaled bilinearly (it shades half the
/// samples checkerboarding does) and the checkerboarded frame reconstructed without history.
#[derive(Clone, Copy, Debug)]
pub struct SameFrameReferences {
    pub upscale_psnr_db: f64,
    pub without_history_psnr_db: f64,
}

impl SameFrameReferences {
    pub fn measure(
        gpu: &Gpu,
        scene: &CheckerboardScene,
        config: CheckerboardConfig,
        frame: u32,
        reference: &[f32],
    ) -> Result<Self> {
        let mut upscale = HalfResolutionUpscale::new(gpu, scene, config.screen)?;
        upscale.render(gpu, frame)?;
        let mut alone = Checkerboard::new(gpu, scene, config)?;
        alone.render(gpu, frame)?;
        let psnr_of =
            |image: &[f32]| -> Result<f64> { Ok(measure_against(config.screen, image, reference, 0)?.0.psnr_db) };
        Ok(Self {
            upscale_psnr_db: psnr_of(&read_hdr(gpu, &upscale.output)?)?,
            without_history_psnr_db: psnr_of(&read_hdr(gpu, &alone.reconstruction.colour)?)?,
        })
    }

    /// Whether a reconstruction at `psnr_db` beats a reference at `other` (a perfect one, of
    /// infinite PSNR, beats what it ties with).
    pub fn beats(psnr_db: f64, other: f64) -> bool {
        psnr_db > other || psnr_db == f64::INFINITY
    }
}

#[derive(Clone, Debug, Serialize)]
pub struct ReconstructionError {
    /// Pixels compared (the documented gap column excluded).
    pub compared_pixels: u64,
    /// Pixels whose HDR value differs in any bit.
    pub inexact_pixels: u64,
    /// Pixels whose display value differs by more than the tolerance.
    pub differing_pixels: u64,
    pub max_display_difference: u8,
    pub psnr_db: f64,
    pub flip: f64,
    /// Pixels with a NaN or infinite channel.
    pub non_finite_pixels: u64,
}

/// Compares `result` with `reference` (HDR RGBA texels of `screen`), the gap column taken from
/// the reference; also returns result | reference | error mask for evidence.
pub fn measure_against(
    screen: (u32, u32),
    result: &[f32],
    reference: &[f32],
    display_tolerance: u8,
) -> Result<(ReconstructionError, RgbaImage)> {
    if result.len() != reference.len() || result.len() != (screen.0 * screen.1 * 4) as usize {
        bail!("comparing {} with {} channels for a {}x{} screen", result.len(), reference.len(), screen.0, screen.1);
    }
    let mut result = result.to_vec();
    let gaps = documented_gaps(screen);
    for &(x, y) in &gaps {
        let i = ((y * screen.0 + x) * 4) as usize;
        result[i..i + 4].copy_from_slice(&reference[i..i + 4]);
    }
    let texels =
        |v: &[f32]| v.chunks_exact(4).map(|c| c.iter().map(|x| x.to_bits()).collect::<Vec<_>>()).collect::<Vec<_>>();
    let inexact = texels(&result).iter().zip(texels(reference)).filter(|(a, b)| **a != *b).count() as u64;
    let non_finite = result.chunks_exact(4).filter(|c| c.iter().any(|x| !x.is_finite())).count() as u64;
    let (shown, expected) = (to_display(screen.0, screen.1, &result)?, to_display(screen.0, screen.1, reference)?);
    let (difference, mask) = compare(&shown, &expected, display_tolerance)?;
    let error = ReconstructionError {
        compared_pixels: u64::from(screen.0 * screen.1) - gaps.len() as u64,
        inexact_pixels: inexact,
        differing_pixels: difference.differing_pixels,
        max_display_difference: difference.max_channel_difference,
        psnr_db: difference.psnr_db,
        flip: f64::from(flip_mean(&shown, &expected)?),
        non_finite_pixels: non_finite,
    };
    Ok((error, side_by_side(&shown, &expected, &mask)))
}

/// Each pixel's source, row-major.
pub fn read_sources(gpu: &Gpu, reconstruction: &Reconstruction) -> Result<Vec<PixelSource>> {
    let texels = read_texture(gpu, &reconstruction.source, wgpu::TextureAspect::All, 0)?;
    texels
        .bytes
        .iter()
        .map(|&b| {
            PixelSource::from_byte(b).ok_or_else(|| anyhow::anyhow!("reconstruction wrote unknown pixel source {b}"))
        })
        .collect()
}

/// How many pixels came from each source (every source listed, zeros included).
pub fn source_counts(sources: &[PixelSource]) -> BTreeMap<&'static str, u64> {
    let mut counts: BTreeMap<&'static str, u64> = PixelSource::ALL.iter().map(|s| (s.name(), 0)).collect();
    for source in sources {
        *counts.get_mut(source.name()).expect("every source listed") += 1;
    }
    counts
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_reconstruction_beats_a_reference_above_it_and_a_perfect_one_beats_its_tie() {
        assert!(SameFrameReferences::beats(30.0, 29.9));
        assert!(!SameFrameReferences::beats(30.0, 30.0));
        assert!(!SameFrameReferences::beats(29.0, 30.0));
        assert!(SameFrameReferences::beats(f64::INFINITY, f64::INFINITY));
        assert!(!SameFrameReferences::beats(40.0, f64::INFINITY));
    }

    #[test]
    fn source_counts_list_every_source_with_its_pixels() {
        let counts = source_counts(&[PixelSource::History, PixelSource::Current, PixelSource::History]);
        assert_eq!(counts.len(), PixelSource::ALL.len());
        assert_eq!((counts["history"], counts["current"], counts["assumed"]), (2, 1, 0));
        assert_eq!(counts.values().sum::<u64>(), 3);
    }
}
