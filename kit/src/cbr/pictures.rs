//! `fragkit render cbr`: frames N−1 and N in the sample layout, the motion each pixel used, the
//! pixel-source (missing-shading) mask, the reconstruction, the full-resolution reference and
//! the error map, as PNGs.

use anyhow::Result;
use image::{Rgba, RgbaImage};

use super::frame::layout_size;
use super::measure::{measure_against, read_hdr, read_sources};
use super::reconstruct::PixelSource;
use super::renderer::{Checkerboard, CheckerboardConfig, FullResolutionScene};
use super::scene::CheckerboardScene;
use crate::gpu::Gpu;
use crate::tonemap::to_display;

/// A pixel source's colour in the mask: samples of the frames dark, fills bright.
fn source_colour(source: PixelSource) -> Rgba<u8> {
    Rgba(match source {
        PixelSource::Current => [40, 40, 40, 255],
        PixelSource::History => [90, 90, 120, 255],
        PixelSource::FirstFrame => [255, 255, 255, 255],
        PixelSource::JitterCancelled => [255, 200, 0, 255],
        PixelSource::Disoccluded => [255, 40, 40, 255],
        PixelSource::Assumed => [40, 200, 255, 255],
        PixelSource::OffScreen => [200, 0, 200, 255],
    })
}

/// Motion as colour: red right, green down, 4 pixels a frame at full intensity.
fn motion_image(screen: (u32, u32), motion: &[f32]) -> RgbaImage {
    let channel = |v: f32| (128.0 + 32.0 * v).clamp(0.0, 255.0) as u8;
    let bytes = motion.chunks_exact(4).flat_map(|m| [channel(m[0]), channel(m[1]), 128, 255]).collect();
    RgbaImage::from_raw(screen.0, screen.1, bytes).expect("sized by the screen")
}

/// Renders `frames` frames of `scene`; the pictures of the last one, named.
pub fn render_all(
    gpu: &Gpu,
    scene: &CheckerboardScene,
    config: CheckerboardConfig,
    frames: u32,
) -> Result<Vec<(String, RgbaImage)>> {
    let screen = config.screen;
    let mut checkerboard = Checkerboard::new(gpu, scene, config)?.showing_motion(gpu)?;
    for frame in 0..frames.max(1) {
        checkerboard.render(gpu, frame)?;
    }
    let mut fullres = FullResolutionScene::new(gpu, scene, screen)?;
    fullres.render(gpu, frames.max(1) - 1)?;

    let last = frames.max(1) - 1;
    let layout = layout_size(screen);
    let mut pictures = Vec::new();
    for (name, index) in [("frame_n", Some(last)), ("frame_n_minus_1", last.checked_sub(1))] {
        if let Some(index) = index {
            let samples = read_hdr(gpu, &checkerboard.frame(index).colour)?;
            pictures.push((name.to_owned(), to_display(layout.0, layout.1, &samples)?));
        }
    }
    if let Some(motion) = &checkerboard.reconstruction.motion {
        pictures.push(("motion".to_owned(), motion_image(screen, &read_hdr(gpu, motion)?)));
    }
    let sources = read_sources(gpu, &checkerboard.reconstruction)?;
    let mask = sources.iter().flat_map(|s| source_colour(*s).0).collect();
    pictures.push(("pixel_sources".to_owned(), RgbaImage::from_raw(screen.0, screen.1, mask).expect("sized")));
    let result = read_hdr(gpu, &checkerboard.reconstruction.colour)?;
    let reference = read_hdr(gpu, fullres.output())?;
    pictures.push(("reconstruction".to_owned(), to_display(screen.0, screen.1, &result)?));
    pictures.push(("full_resolution".to_owned(), to_display(screen.0, screen.1, &reference)?));
    let (_, evidence) = measure_against(screen, &result, &reference, 8)?;
    pictures.push(("error_map".to_owned(), evidence));
    Ok(pictures)
}
