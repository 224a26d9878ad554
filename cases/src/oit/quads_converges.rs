//! `oit.quads.converges`: the temporally accumulated stochastic image of the paper's quads
//! approaches the exact composite (at this adapter's sample positions) as frames accumulate.
//! Monte Carlo error falls like 1/√frames, so the fitted slope of log RMSE against log frames
//! (1, 4, 16, 64) must lie in [−0.65, −0.35] (−0.5 ± 0.15: the RMSE of a few frames is itself
//! noisy) for the sample-mask variant, which is unbiased. The alpha-to-coverage variants flatten
//! at a floor (their slope over 1..16 is reported too): a fixed coverage
//! pattern per count correlates the layers' samples (lavapipe does not dither); their slopes and
//! floors are reported.

use anyhow::{Context, Result};
use fragkit::harness::{Case, Ctx, Outcome, ParamKind, ParamSpec, Sweep, SweepRange, Verdict};
use fragkit::oit::filter::{PostFilter, read_rgb};
use fragkit::oit::reference::{exact_image, rmse};
use fragkit::oit::scene::QuadScene;
use fragkit::oit::stochastic::{
    COVERAGE_COLOUR, PingPongNoise, ResolvedTarget, Stochastic, available_variants, render_stochastic,
    sample_mask_output,
};
use fragkit::probe::sample_positions::{measure, standard_positions};
use fragkit::probe::sample_projections::measure_projections;
use fragkit::query::GpuTimer;
use fragkit::shaders::{ALPHA_RAMP, FRAGMENT_STORAGE, FULLSCREEN, OIT_BILATERAL, OIT_NOISE_STEP, OIT_QUAD, OIT_SAMPLE_MASK, OIT_STOCHASTIC, OIT_TEMPORAL, RECT, SAMPLE_COVERAGE_RECORD};

use super::multisample_counts;

pub const CASE: Case = Case {
    name: "oit.quads.converges",
    summary: "accumulated stochastic transparency converges to the exact composite like 1/sqrt(frames)",
    requires: wgpu::Features::empty(),
    params: &[ParamSpec { name: "size", kind: ParamKind::Size, default: "64x64", help: "target size" }],
    sweep: &[Sweep { param: "size", range: SweepRange::Size { min: (8, 8), max: (128, 128) } }],
    budget_s: 4,
    timed_verdict: false,
    shaders: &[RECT, FULLSCREEN, SAMPLE_COVERAGE_RECORD, ALPHA_RAMP, FRAGMENT_STORAGE, OIT_QUAD, OIT_NOISE_STEP, OIT_STOCHASTIC, OIT_SAMPLE_MASK, OIT_TEMPORAL, OIT_BILATERAL],
    run,
};

const CHECKPOINTS: [u32; 4] = [1, 4, 16, 64];

/// Least-squares slope of log(error) against log(frames).
fn log_slope(points: &[(u32, f64)]) -> f64 {
    let xs: Vec<f64> = points.iter().map(|&(f, _)| f64::from(f).ln()).collect();
    let ys: Vec<f64> = points.iter().map(|&(_, e)| e.max(1e-12).ln()).collect();
    let (mx, my) = (xs.iter().sum::<f64>() / xs.len() as f64, ys.iter().sum::<f64>() / ys.len() as f64);
    let covariance: f64 = xs.iter().zip(&ys).map(|(x, y)| (x - mx) * (y - my)).sum();
    let variance: f64 = xs.iter().map(|x| (x - mx).powi(2)).sum();
    covariance / variance
}

fn run(ctx: &mut Ctx) -> Result<Outcome> {
    let size = ctx.params.size("size")?;
    let frames = *CHECKPOINTS.last().expect("checkpoints");
    let samples = match multisample_counts(ctx.gpu)? {
        Ok(counts) => *counts.last().expect("a non-empty list"),
        Err(outcome) => return Ok(outcome),
    };
    // Expected: the exact composite at the positions this adapter samples: measured where a
    // route reads single samples; where none can (GLES), the standard table once the unmasked
    // sweep has confirmed each axis's coordinates (which sample sits where is then the table's).
    let measured = measure(ctx.gpu, samples)?;
    let positions: Vec<[f32; 2]> = if measured.read_single_samples() {
        let Some(agreed) = measured.agreed() else {
            return Ok(Outcome::NotSupported(format!(
                "measured {samples}x sample positions: the routes disagree (see kit.msaa.sample_positions)"
            )));
        };
        agreed.iter().filter_map(|s| s.mid()).collect()
    } else if measure_projections(ctx.gpu, samples)?.matches_standard(samples) {
        ctx.metric("positions", "the standard table, each axis confirmed by an unmasked sweep");
        standard_positions(samples).context("no standard table for this count")?.to_vec()
    } else {
        return Ok(Outcome::NotSupported(format!(
            "{samples}x sample positions: no route reads single samples here, and the unmasked sweep's coordinates are not the standard table's"
        )));
    };
    let scene = QuadScene::paper();
    let exact = exact_image(&scene, size, &positions);

    let variants = available_variants(ctx.gpu, samples)?;
    // The unbiased variant writes the sample mask, which every backend offers; a pipeline that
    // does not build is the translator's bug (a failure), not a missing capability.
    let sample_mask = sample_mask_output(ctx.gpu, samples);
    let target = ResolvedTarget::new(ctx.gpu, size, samples, COVERAGE_COLOUR);
    let mut verdict = Verdict::new();
    for variant in &variants {
        let mut noise = PingPongNoise::new(ctx.gpu, size, 11);
        let mut filter = PostFilter::new(ctx.gpu, size);
        let mut timer = GpuTimer::new(ctx.gpu, 2 * frames + 2);
        let mut errors = Vec::new();
        for frame in 1..=frames {
            if frame > 1 {
                noise.advance(ctx.gpu);
            }
            render_stochastic(ctx.gpu, &scene, &target, &noise, variant, &mut timer)?;
            filter.accumulate(ctx.gpu, &target.resolved, &mut timer);
            if CHECKPOINTS.contains(&frame) {
                errors.push((frame, rmse(&read_rgb(ctx.gpu, filter.accumulated())?, &exact)));
            }
        }
        let early: Vec<(u32, f64)> = errors.iter().copied().filter(|&(f, _)| f <= 16).collect();
        let (slope_early, slope_all) = (log_slope(&early), log_slope(&errors));
        let name = fragkit::oit::run::Method::Stochastic(variant.clone()).name();
        ctx.metric(name, serde_json::json!({"rmse": errors, "slope_1_to_16": slope_early, "slope": slope_all}));
        if *variant == Stochastic::SampleMask && !(-0.65..=-0.35).contains(&slope_all) {
            verdict
                .fail(format!("{name}: error slope {slope_all:.3} over {CHECKPOINTS:?} frames, expected -0.5 ± 0.15"));
        }
    }
    if let Err(e) = sample_mask {
        verdict.fail(format!(
            "the @builtin(sample_mask) output pipeline, needed for the unbiased variant, does not build: {e} \
             (the alpha-to-coverage slopes are reported)"
        ));
    }
    Ok(verdict.outcome())
}
