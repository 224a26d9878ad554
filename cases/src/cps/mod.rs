//! `cps.*`: coarse pixel shading through a stencil pyramid.

pub mod all_fine_equals_fullres;
pub mod composite_linear_precision;
pub mod composite_matches_reference;
pub mod composite_seam_free_sweep;
pub mod early_rejection;
pub mod extremes;
pub mod level_lighting;
pub mod lod_policy;
pub mod stencil_equal_counts;

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
