//! What a person looks at: the LOD buffer, each level's stencil mask and lit mip, and the
//! composite, read back from a rendered frame as display images.

use anyhow::{Context, Result};
use image::{Rgba, RgbaImage};

use super::renderer::{CpsRenderer, LevelDraws};
use crate::gpu::Gpu;
use crate::readback::{read_buffer_words, read_stencil, read_texture};
use crate::tonemap::to_display;

/// A distinct colour per level, fine (blue) to coarse (red).
fn level_colour(level: u8) -> Rgba<u8> {
    const COLOURS: [[u8; 3]; 9] = [
        [30, 60, 200],
        [40, 140, 230],
        [40, 200, 200],
        [60, 200, 90],
        [170, 220, 50],
        [250, 210, 40],
        [250, 140, 30],
        [230, 70, 40],
        [170, 20, 60],
    ];
    let [r, g, b] = COLOURS[usize::from(level.min(8))];
    Rgba([r, g, b, 255])
}

impl CpsRenderer {
    /// The LOD per pixel as read back; where the frame computes the foveated levels itself and
    /// writes no LOD buffer, as the LOD pass renders it now.
    pub fn read_lod(&self, gpu: &Gpu) -> Result<Vec<u8>> {
        if self.plan.levels_from_foveation {
            self.render_foveated_lod(gpu).context("rendering the foveated LOD")?;
        }
        let (width, height) = self.plan.screen;
        Ok(read_texture(gpu, &self.lod, wgpu::TextureAspect::All, 0)?.region(0, 0, width, height).bytes)
    }

    /// Level `level` of the lit pyramid (data region only), RGBA f32 per texel.
    pub fn read_lit_level(&self, gpu: &Gpu, level: u32) -> Result<Vec<f32>> {
        let (x, y, w, h) = self.plan.atlas.rect(level as usize);
        Ok(read_texture(gpu, &self.lit, wgpu::TextureAspect::All, 0)?.region(x, y, w, h).as_f16())
    }

    /// The composite, RGBA f32 per pixel.
    pub fn read_image(&self, gpu: &Gpu) -> Result<Vec<f32>> {
        Ok(read_texture(gpu, &self.image, wgpu::TextureAspect::All, 0)?.as_f16())
    }

    /// Each level's lighting draw arguments as the GPU counted them (levels 0..=top: vertex
    /// count, instance count, first vertex, first instance): instance count 0 for a level the
    /// GPU found absent. None where the levels are drawn directly, one instance each.
    pub fn read_level_draws(&self, gpu: &Gpu) -> Result<Option<Vec<[u32; 4]>>> {
        let LevelDraws::Counted(arguments) = &self.level_draws else {
            return Ok(None);
        };
        let words = read_buffer_words(gpu, arguments)?;
        Ok(Some(words.chunks_exact(4).take(self.plan.levels() as usize).map(|d| [d[0], d[1], d[2], d[3]]).collect()))
    }

    /// Level `level`'s stencil (data region only): 1 where the level shades.
    pub fn read_stencil_level(&self, gpu: &Gpu, level: u32) -> Result<Vec<u8>> {
        let (x, y, w, h) = self.plan.atlas.rect(level as usize);
        let stencil = self.stencil.as_ref().context("the naive configuration builds no stencil pyramid")?;
        Ok(read_stencil(gpu, stencil, 0)?.region(x, y, w, h).bytes)
    }

    /// Named images of the last frame: `lod`, `stencil_<l>`, `lit_<l>` and `composite_<mode>`.
    pub fn pictures(&self, gpu: &Gpu) -> Result<Vec<(String, RgbaImage)>> {
        let (w, h) = self.plan.screen;
        let lod = self.read_lod(gpu)?;
        let mut pictures =
            vec![("lod".to_owned(), RgbaImage::from_fn(w, h, |x, y| level_colour(lod[(y * w + x) as usize])))];
        let stencil_copies = gpu
            .adapter
            .get_downlevel_capabilities()
            .flags
            .contains(wgpu::DownlevelFlags::DEPTH_TEXTURE_AND_BUFFER_COPIES);
        for level in 0..self.plan.levels() {
            let (lw, lh) = self.plan.level_extents[level as usize];
            let lit = self.read_lit_level(gpu, level)?;
            // The stencil itself where it can be copied, else what it let through (lit alpha).
            let marked: Vec<bool> = match (&self.stencil, stencil_copies) {
                (Some(_), true) => self.read_stencil_level(gpu, level)?.iter().map(|&s| s != 0).collect(),
                (Some(_), false) => lit.chunks_exact(4).map(|t| t[3] == 1.0).collect(),
                (None, _) => Vec::new(),
            };
            if !marked.is_empty() {
                let mask =
                    |x: u32, y: u32| if marked[(y * lw + x) as usize] { Rgba([255; 4]) } else { Rgba([0, 0, 0, 255]) };
                pictures.push((format!("stencil_{level}"), RgbaImage::from_fn(lw, lh, mask)));
            }
            pictures.push((format!("lit_{level}"), to_display(lw, lh, &lit)?));
        }
        pictures
            .push((format!("composite_{}", self.config.composite.name()), to_display(w, h, &self.read_image(gpu)?)?));
        Ok(pictures)
    }
}

/// Renders the corridor with CPS in every composite mode and at full resolution, and returns
/// every picture: the shared intermediates once, each composite, the full-resolution reference
/// and each composite's error map against it.
pub fn render_all(
    gpu: &Gpu,
    size: (u32, u32),
    policy: super::LodPolicy,
    max_level: u32,
    light_count: u32,
    seed: u32,
) -> Result<Vec<(String, RgbaImage)>> {
    use super::{CompositeMode, CpsConfig};
    use crate::deferred::DeferredInputs;
    use crate::deferred::lighting::light_full_resolution;

    let scene = crate::scene::corridor::corridor(seed, light_count);
    let inputs = DeferredInputs::new(gpu, &scene, size)?;
    let frame = super::renderer::CpsFrame { gbuffer: &inputs.gbuffer, lights: &inputs.lights, eye: inputs.eye };
    let fullres = light_full_resolution(gpu, &inputs)?;
    let reference = to_display(size.0, size.1, &read_texture(gpu, &fullres, wgpu::TextureAspect::All, 0)?.as_f16())?;
    let mut pictures = Vec::new();
    for (i, composite) in CompositeMode::ALL.into_iter().enumerate() {
        let renderer = CpsRenderer::new(gpu, size, CpsConfig::new(max_level, policy.clone(), composite))?;
        renderer.render(gpu, &frame)?;
        let mut frame_pictures = renderer.pictures(gpu)?;
        let composite_image = frame_pictures.pop().expect("composite is last");
        if i == 0 {
            pictures.extend(frame_pictures);
        }
        let (_, mask) = crate::image_compare::compare(&composite_image.1, &reference, 2)?;
        pictures.push((format!("error_{}", composite.name()), mask));
        pictures.push(composite_image);
    }
    pictures.push(("fullres".to_owned(), reference));
    Ok(pictures)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Nine levels, nine distinct opaque colours, fine blue to coarse red; deeper levels share the
    /// last one.
    #[test]
    fn each_level_has_its_own_colour() {
        let colours: Vec<Rgba<u8>> = (0..9).map(level_colour).collect();
        for (i, a) in colours.iter().enumerate() {
            assert_eq!(a[3], 255);
            assert!(colours[..i].iter().all(|b| b != a), "level {i} repeats a colour");
        }
        assert_eq!(level_colour(0), Rgba([30, 60, 200, 255]));
        assert_eq!(level_colour(8), Rgba([170, 20, 60, 255]));
        assert_eq!(level_colour(200), level_colour(8));
    }
}
