//! `soak.oit`: stochastic transparency (sample-mask variant where the adapter has it, else the
//! paper's) of the 16-layer scene, the noise advancing and the temporal filter accumulating every
//! frame.

use anyhow::Result;
use fragkit::gpu::Gpu;
use fragkit::harness::{Case, Ctx, Outcome};
use fragkit::oit::filter::PostFilter;
use fragkit::oit::scene::QuadScene;
use fragkit::probe::multisample_render::render_problem;
use fragkit::oit::stochastic::{
    COVERAGE_COLOUR, PingPongNoise, ResolvedTarget, Stochastic, available_variants, render_stochastic,
};
use fragkit::query::GpuTimer;
use fragkit::readback::read_texture;
use fragkit::shaders::{ALPHA_RAMP, FULLSCREEN, OIT_BILATERAL, OIT_NOISE_STEP, OIT_QUAD, OIT_SAMPLE_MASK, OIT_STOCHASTIC, OIT_TEMPORAL, RECT};

use super::{PARAMS, Soaked, soak};

pub const CASE: Case = Case {
    name: "soak.oit",
    summary: "stochastic transparency over many frames and resizes: no memory growth, last frame reproducible",
    requires: wgpu::Features::empty(),
    params: PARAMS,
    sweep: &[],
    budget_s: 76,
    timed_verdict: false,
    shaders: &[RECT, FULLSCREEN, ALPHA_RAMP, OIT_QUAD, OIT_NOISE_STEP, OIT_STOCHASTIC, OIT_SAMPLE_MASK, OIT_TEMPORAL, OIT_BILATERAL],
    run,
};

const SAMPLES: u32 = 4;

struct OitSoak {
    scene: QuadScene,
    variant: Stochastic,
    target: ResolvedTarget,
    noise: PingPongNoise,
    filter: PostFilter,
}

impl Soaked for OitSoak {
    /// The variant this adapter runs.
    type Setup = Stochastic;

    fn setup(gpu: &Gpu) -> Result<Stochastic> {
        let variants = available_variants(gpu, SAMPLES)?;
        Ok(variants.iter().find(|v| **v == Stochastic::SampleMask).unwrap_or(&variants[0]).clone())
    }

    fn new(gpu: &Gpu, variant: &Stochastic, size: (u32, u32)) -> Result<Self> {
        Ok(Self {
            scene: QuadScene::stiff(16, 3),
            variant: variant.clone(),
            target: ResolvedTarget::new(gpu, size, SAMPLES, COVERAGE_COLOUR),
            noise: PingPongNoise::new(gpu, size, 3),
            filter: PostFilter::new(gpu, size),
        })
    }

    fn render(&mut self, gpu: &Gpu, _frame: u32) -> Result<()> {
        let mut timer = GpuTimer::new(gpu, 4);
        self.noise.advance(gpu);
        render_stochastic(gpu, &self.scene, &self.target, &self.noise, &self.variant, &mut timer)?;
        self.filter.accumulate(gpu, &self.target.resolved, &mut timer);
        Ok(())
    }

    fn output(&self, gpu: &Gpu) -> Result<Vec<u8>> {
        Ok(read_texture(gpu, self.filter.accumulated(), wgpu::TextureAspect::All, 0)?.bytes)
    }
}

fn run(ctx: &mut Ctx) -> Result<Outcome> {
    // A 4x target that does not render (softpipe's GL, where wgpu-hal advertises 4x anyway) draws
    // nothing defined: its frames cannot be held to a replay.
    if let Some(problem) = render_problem(ctx.gpu, SAMPLES)? {
        return Ok(Outcome::Fail(problem));
    }
    soak::<OitSoak>(ctx)
}
