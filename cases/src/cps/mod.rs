//! `cps.*`: coarse pixel shading through a stencil pyramid.

fragkit::cases! {
    lod_policy: CASE;
    stencil_equal_counts: CASE;
    level_lighting: CASE;
    all_fine_equals_fullres: CASE;
    composite_matches_reference: CASE;
    composite_linear_precision: CASE;
    composite_seam_free_sweep: CASE;
    early_rejection: CASE;
    extremes: CASE;
}

use anyhow::Result;
use fragkit::Gpu;
use fragkit::cps::renderer::CpsFrame;
use fragkit::deferred::DeferredInputs;
use fragkit::scene::corridor::corridor;
use fragkit::scene::hash::SeededRng;

/// The corridor's G-buffer and lights at `size`.
pub fn corridor_inputs(gpu: &Gpu, size: (u32, u32), lights: u32, seed: u32) -> Result<DeferredInputs> {
    DeferredInputs::new(gpu, &corridor(seed, lights), size)
}

pub fn frame(inputs: &DeferredInputs) -> CpsFrame<'_> {
    CpsFrame { gbuffer: &inputs.gbuffer, lights: &inputs.lights, eye: inputs.eye }
}

/// A seeded LOD per pixel, uniform over 0..=8: every block mixes levels, the pyramid's worst case.
pub fn random_lod(size: (u32, u32), seed: u32) -> Vec<u8> {
    let mut rng = SeededRng::new(seed);
    (0..size.0 * size.1).map(|_| rng.range(0, 9) as u8).collect()
}
