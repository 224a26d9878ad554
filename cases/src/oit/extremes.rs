//! `oit.extremes`: stiff opacities stay exact and finite. A full-screen layer of opacity 0 covers
//! no sample of any pixel and one of opacity 1 every sample, in every frame and stochastic
//! variant; 1e-6, 1e-3 and 0.999999 give finite images; 64 full-screen layers at one depth peel
//! into exactly 65 layers (with the background) and match the exact composite; opacities NaN,
//! negative or above 1 are refused with a message naming them.

use anyhow::Result;
use fragkit::harness::{Case, Ctx, Outcome, Verdict};
use fragkit::oit::reference::exact_image;
use fragkit::oit::run::{Accumulation, Method, run_method};
use fragkit::oit::scene::{Quad, QuadScene};
use fragkit::oit::stochastic::{
    COVERAGE_COLOUR, PingPongNoise, ResolvedTarget, Stochastic, available_variants, render_stochastic,
};
use fragkit::query::GpuTimer;
use fragkit::scene::hash::SeededRng;
use fragkit::shaders::{ALPHA_RAMP, FRAGMENT_STORAGE, FULLSCREEN, OIT_BILATERAL, OIT_NOISE_STEP, OIT_PEEL, OIT_PLAIN_COVERAGE, OIT_QUAD, OIT_SAMPLE_MASK, OIT_STOCHASTIC, OIT_TEMPORAL, OIT_UNDER, OIT_WEIGHTED_ACCUMULATE, OIT_WEIGHTED_COMPOSITE, RECT, SAMPLE_COVERAGE_RECORD};

use super::multisample_counts;

pub const CASE: Case = Case {
    name: "oit.extremes",
    summary: "opacity 0/1 exact per pixel, tiny and near-1 opacities finite, 64 equal-depth layers exact",
    requires: wgpu::Features::empty(),
    params: &[],
    sweep: &[],
    budget_s: 3,
    timed_verdict: false,
    shaders: &[RECT, FULLSCREEN, SAMPLE_COVERAGE_RECORD, ALPHA_RAMP, FRAGMENT_STORAGE, OIT_QUAD, OIT_NOISE_STEP, OIT_STOCHASTIC, OIT_SAMPLE_MASK, OIT_PLAIN_COVERAGE, OIT_WEIGHTED_ACCUMULATE, OIT_WEIGHTED_COMPOSITE, OIT_PEEL, OIT_UNDER, OIT_TEMPORAL, OIT_BILATERAL],
    run,
};

fn layer(alpha: f32) -> QuadScene {
    QuadScene::keyed(
        "layer",
        vec![Quad { rect: [-1.0, 1.0, 1.0, -1.0], depth: (0.5, 0.5), alpha, colour: [1.0; 3], key: 0 }],
    )
}

fn run(ctx: &mut Ctx) -> Result<Outcome> {
    let size = (32, 32);
    let samples = match multisample_counts(ctx.gpu)? {
        Ok(counts) => *counts.last().expect("a non-empty list"),
        Err(outcome) => return Ok(outcome),
    };
    let variants = available_variants(ctx.gpu, samples)?;
    let mut verdict = Verdict::new();
    let target = ResolvedTarget::new(ctx.gpu, size, samples, COVERAGE_COLOUR);
    for variant in &variants {
        let name = Method::Stochastic(variant.clone()).name();
        for alpha in [0.0, 1e-6, 1e-3, 0.999_999, 1.0] {
            let mut noise = PingPongNoise::new(ctx.gpu, size, 3);
            for frame in 0..4 {
                if frame > 0 {
                    noise.advance(ctx.gpu);
                }
                render_stochastic(ctx.gpu, &layer(alpha), &target, &noise, variant, &mut GpuTimer::new(ctx.gpu, 1))?;
                let image = target.read_rgb(ctx.gpu)?;
                let non_finite = image.iter().flatten().filter(|v| !v.is_finite()).count();
                let wrong = match alpha {
                    0.0 => image.iter().filter(|p| p[0] != 0.0).count(),
                    1.0 => image.iter().filter(|p| p[0] != 1.0).count(),
                    _ => 0,
                };
                if non_finite > 0 || wrong > 0 {
                    verdict.fail(format!("{name} α {alpha} frame {frame}: {non_finite} non-finite values, {wrong} pixels not exactly covered"));
                }
            }
        }
    }

    // 64 full-screen layers at one depth over the background: every pixel holds 65 layers.
    let mut rng = SeededRng::new(8);
    let mut quads =
        vec![Quad { rect: [-1.0, 1.0, 1.0, -1.0], depth: (0.999, 0.999), alpha: 1.0, colour: [0.5; 3], key: 0 }];
    quads.extend((0..64).map(|_| Quad {
        rect: [-1.0, 1.0, 1.0, -1.0],
        depth: (0.5, 0.5),
        alpha: 0.02 + 0.1 * rng.unit(),
        colour: [rng.unit(), rng.unit(), rng.unit()],
        key: 0,
    }));
    let stack = QuadScene::keyed("equal_depth_64", quads);
    let once = Accumulation { frames: 1, seed: 1, filtered: false };
    let peeled = run_method(ctx.gpu, &stack, size, 1, &Method::DepthPeeling, once)?;
    let exact = exact_image(&stack, size, &[[0.5, 0.5]]);
    // Each of the 65 blends rounds to f16: at most half an ulp, 2^-12 below 1, per blend.
    let tolerance = 65.0 / 4096.0;
    let worst = peeled
        .image
        .iter()
        .zip(&exact)
        .flat_map(|(a, b)| (0..3).map(move |c| (a[c] - b[c]).abs()))
        .fold(0.0f32, f32::max);
    ctx.metric("equal_depth_64", serde_json::json!({"layers_peeled": peeled.layers, "worst_difference": worst}));
    if peeled.layers != Some(65) {
        verdict.fail(format!("64 equal-depth layers: depth peeling found {:?} layers, expected 65", peeled.layers));
    }
    if worst > tolerance || peeled.image.iter().flatten().any(|v| !v.is_finite()) {
        verdict.fail(format!("64 equal-depth layers: depth peeling differs from the exact composite by {worst}"));
    }
    for method in [Method::Stochastic(Stochastic::Paper), Method::WeightedBlended, Method::PlainCoverage] {
        let method_samples = if method == Method::WeightedBlended { 1 } else { samples };
        let result = run_method(
            ctx.gpu,
            &stack,
            size,
            method_samples,
            &method,
            Accumulation { frames: 4, seed: 1, filtered: true },
        )?;
        let non_finite = result.image.iter().flatten().filter(|v| !v.is_finite()).count();
        if non_finite > 0 {
            verdict.fail(format!("64 equal-depth layers, {}: {non_finite} non-finite values", method.name()));
        }
    }

    // Opacities outside 0..=1 are refused, naming the value.
    for bad in [f32::NAN, -0.1, 1.5] {
        match run_method(ctx.gpu, &layer(bad), size, samples, &Method::Stochastic(Stochastic::Paper), once) {
            Err(e) if format!("{e:#}").contains(&format!("opacity {bad}")) => {}
            Err(e) => verdict.fail(format!("opacity {bad} refused without naming it: {e:#}")),
            Ok(_) => verdict.fail(format!("opacity {bad} was rendered instead of refused")),
        }
    }
    Ok(verdict.outcome())
}
