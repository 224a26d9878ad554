//! One method, start to finish: render (over `frames` frames with temporal accumulation for the
//! stochastic variants, optionally bilateral-filtered), read back, with the GPU time spent.

use anyhow::Result;

use super::filter::{PostFilter, read_rgb};
use super::methods::{render_depth_peeling, render_plain_coverage, render_sorted_blend, render_weighted};
use super::scene::QuadScene;
use super::stochastic::{COLOUR, COVERAGE_COLOUR, PingPongNoise, ResolvedTarget, Stochastic, render_stochastic};
use crate::gpu::Gpu;
use crate::query::GpuTimer;

#[derive(Clone, Debug, PartialEq)]
pub enum Method {
    Stochastic(Stochastic),
    PlainCoverage,
    SortedBlend,
    WeightedBlended,
    DepthPeeling,
}

impl Method {
    pub fn name(&self) -> &'static str {
        match self {
            Self::Stochastic(Stochastic::Paper) => "stochastic",
            Self::Stochastic(Stochastic::Corrected { .. }) => "stochastic_corrected",
            Self::Stochastic(Stochastic::SampleMask) => "stochastic_sample_mask",
            Self::PlainCoverage => "alpha_to_coverage",
            Self::SortedBlend => "sorted_blend",
            Self::WeightedBlended => "weighted_blended",
            Self::DepthPeeling => "depth_peeling",
        }
    }

    /// Methods that draw the scene once per frame and accumulate.
    pub fn is_stochastic(&self) -> bool {
        matches!(self, Self::Stochastic(_))
    }
}

/// A method's image and cost.
pub struct MethodResult {
    pub image: Vec<[f32; 3]>,
    /// GPU time of all its passes, all frames together.
    pub gpu_ms: f64,
    /// Layers peeled (depth peeling only).
    pub layers: Option<u32>,
}

/// How the stochastic variants are run: frames accumulated, noise seed, bilateral filter.
#[derive(Clone, Copy, Debug)]
pub struct Accumulation {
    pub frames: u32,
    pub seed: u32,
    pub filtered: bool,
}

/// Renders `scene` with `method` at `samples` per pixel (1 for the single-sampled methods).
pub fn run_method(
    gpu: &Gpu,
    scene: &QuadScene,
    size: (u32, u32),
    samples: u32,
    method: &Method,
    accumulation: Accumulation,
) -> Result<MethodResult> {
    let Accumulation { frames, seed, filtered } = accumulation;
    let format = if method.is_stochastic() || *method == Method::PlainCoverage { COVERAGE_COLOUR } else { COLOUR };
    let target = ResolvedTarget::new(gpu, size, samples, format);
    let mut timer = GpuTimer::new(gpu, 2 * frames.max(1) + 2 * scene.quads.len() as u32 + 8);
    let mut layers = None;
    let image = match method {
        Method::Stochastic(variant) => {
            let mut noise = PingPongNoise::new(gpu, size, seed);
            let mut filter = PostFilter::new(gpu, size);
            for frame in 0..frames.max(1) {
                if frame > 0 {
                    noise.advance(gpu);
                }
                render_stochastic(gpu, scene, &target, &noise, variant, &mut timer)?;
                filter.accumulate(gpu, &target.resolved, &mut timer);
            }
            let result = if filtered { filter.filter(gpu, &mut timer) } else { filter.accumulated() };
            read_rgb(gpu, result)?
        }
        Method::PlainCoverage => {
            render_plain_coverage(gpu, scene, &target, &mut timer)?;
            target.read_rgb(gpu)?
        }
        Method::SortedBlend => {
            render_sorted_blend(gpu, scene, &target, &mut timer)?;
            target.read_rgb(gpu)?
        }
        Method::WeightedBlended => {
            render_weighted(gpu, scene, &target, &mut timer)?;
            target.read_rgb(gpu)?
        }
        Method::DepthPeeling => {
            layers = Some(render_depth_peeling(gpu, scene, &target, &mut timer, scene.quads.len() as u32 + 1)?);
            target.read_rgb(gpu)?
        }
    };
    let gpu_ms = timer.read(gpu)?.iter().map(|t| t.ms).sum();
    Ok(MethodResult { image, gpu_ms, layers })
}
