//! `fragkit render oit`: every method's image of a scene and its error map against the exact
//! composite, as display images.

use anyhow::Result;
use image::RgbaImage;

use super::reference::exact_image;
use super::run::{Accumulation, Method, run_method};
use super::scene::QuadScene;
use super::stochastic::{Stochastic, exact_alpha_table};
use crate::gpu::Gpu;
use crate::image_compare::compare;
use crate::probe::alpha_to_coverage::measure_alpha_to_coverage;
use crate::probe::sample_positions::measure;
use crate::tonemap::ldr_to_display;

/// The methods available on this adapter at `samples` per pixel, and why others are not.
pub fn available_methods(gpu: &Gpu, scene: &QuadScene, samples: u32) -> (Vec<Method>, Vec<(String, String)>) {
    let mut methods = vec![Method::Stochastic(Stochastic::Paper)];
    let mut missing = Vec::new();
    match measure_alpha_to_coverage(gpu, samples, true).and_then(|t| exact_alpha_table(&t)) {
        Ok(exact_alpha) => methods.push(Method::Stochastic(Stochastic::Corrected { exact_alpha })),
        Err(e) => missing.push(("stochastic_corrected".into(), format!("{e:#}"))),
    }
    methods.push(Method::Stochastic(Stochastic::SampleMask));
    methods.push(Method::PlainCoverage);
    if super::methods::sortable(scene) {
        methods.push(Method::SortedBlend);
    } else {
        missing.push(("sorted_blend".into(), "the scene has equal depths or tilted quads".into()));
    }
    methods.extend([Method::WeightedBlended, Method::DepthPeeling]);
    (methods, missing)
}

pub fn render_all(
    gpu: &Gpu,
    scene: &QuadScene,
    size: (u32, u32),
    samples: u32,
    frames: u32,
    seed: u32,
) -> Result<Vec<(String, RgbaImage)>> {
    let positions: Vec<[f32; 2]> = measure(gpu, samples)?
        .agreed()
        .map(|p| p.iter().filter_map(|s| s.mid()).collect())
        .unwrap_or_else(|| vec![[0.5, 0.5]]);
    let exact_msaa = ldr_to_display(size.0, size.1, &exact_image(scene, size, &positions))?;
    let exact_centre = ldr_to_display(size.0, size.1, &exact_image(scene, size, &[[0.5, 0.5]]))?;
    let mut pictures = vec![("exact".to_owned(), exact_msaa.clone())];
    let (methods, _) = available_methods(gpu, scene, samples);
    for method in methods {
        let method_samples = if method.is_stochastic() || method == Method::PlainCoverage { samples } else { 1 };
        let result =
            run_method(gpu, scene, size, method_samples, &method, Accumulation { frames, seed, filtered: true })?;
        let shown = ldr_to_display(size.0, size.1, &result.image)?;
        let reference = if method_samples > 1 { &exact_msaa } else { &exact_centre };
        let (_, mask) = compare(&shown, reference, 2)?;
        pictures.push((method.name().to_owned(), shown));
        pictures.push((format!("error_{}", method.name()), mask));
    }
    Ok(pictures)
}
