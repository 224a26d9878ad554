//! `oit.a2c.coverage_stats`: over many pixels and frames, the mean covered fraction of a layer
//! of opacity α matches its expectation within a bound derived from the variance: a fraction
//! c ∈ [0, 1] with mean μ has Var c ≤ μ(1 − μ), so the mean of n independent values lies within
//! 5·sqrt(μ(1 − μ)/n) of μ except with probability < 1e-6. Expectations:
//! - the corrected variant and the sample-mask variant: μ = α;
//! - the paper's variant: the quantised expectation E[Q(f^γ)]/N from this adapter's measured
//!   transfer function (each step edge known to 1/256, so μ is an interval), its bias against α
//!   reported;
//! - α = 0 and α = 1: exactly no and full coverage.

use anyhow::Result;
use fragkit::harness::{Case, Ctx, Outcome, ParamKind, ParamSpec, Sweep, SweepRange, Verdict};
use fragkit::oit::scene::{Quad, QuadScene};
use fragkit::oit::stochastic::{
    COVERAGE_COLOUR, PingPongNoise, ResolvedTarget, Stochastic, exact_alpha_table, render_stochastic,
    sample_mask_output,
};
use fragkit::probe::alpha_to_coverage::{ALPHA_STEPS, AlphaToCoverage, measure_alpha_to_coverage};
use fragkit::query::GpuTimer;
use fragkit::shaders::{ALPHA_RAMP, FRAGMENT_STORAGE, FULLSCREEN, OIT_NOISE_STEP, OIT_QUAD, OIT_SAMPLE_MASK, OIT_STOCHASTIC, RECT, SAMPLE_COVERAGE_RECORD};

use super::multisample_counts;

pub const CASE: Case = Case {
    name: "oit.a2c.coverage_stats",
    summary: "mean coverage of f^γ (corrected, sample-mask, paper) matches its expectation within 5 sigma",
    requires: wgpu::Features::empty(),
    params: &[
        ParamSpec { name: "size", kind: ParamKind::Size, default: "64x64", help: "pixels per frame" },
        ParamSpec {
            name: "frames",
            kind: ParamKind::CountIn(1, 100000),
            default: "8",
            help: "frames (seeds) averaged",
        },
    ],
    sweep: &[
        Sweep { param: "size", range: SweepRange::Size { min: (8, 8), max: (128, 128) } },
        Sweep { param: "frames", range: SweepRange::Count(1, 32) },
    ],
    budget_s: 8,
    timed_verdict: false,
    shaders: &[RECT, FULLSCREEN, SAMPLE_COVERAGE_RECORD, ALPHA_RAMP, FRAGMENT_STORAGE, OIT_QUAD, OIT_NOISE_STEP, OIT_STOCHASTIC, OIT_SAMPLE_MASK],
    run,
};

const ALPHAS: [f32; 10] = [0.0, 1e-6, 1e-3, 0.1, 0.2, 0.5, 0.6, 0.9, 0.999_999, 1.0];

/// E[covered samples] / N of the paper's variant, as an interval from the 1/256-wide step edges:
/// P(count ≥ k) = P(f^γ ≥ b_k) = 1 − b_k^(α/(1−α)) with b_k the alpha where count k begins.
fn quantised_expectation(transfer: &AlphaToCoverage, alpha: f64) -> (f64, f64) {
    let n = f64::from(transfer.samples);
    let exceed = |b: f64| if b <= 0.0 { 1.0 } else { 1.0 - b.powf(alpha / (1.0 - alpha)) };
    let (mut lo, mut hi) = (0.0, 0.0);
    for k in 1..=transfer.samples {
        let Some(&(_, step)) = transfer.thresholds.iter().filter(|&&(count, _)| count >= k).min_by_key(|&&(_, s)| s)
        else {
            continue;
        };
        lo += exceed(f64::from(step) / f64::from(ALPHA_STEPS));
        hi += exceed(f64::from(step.saturating_sub(1)) / f64::from(ALPHA_STEPS));
    }
    (lo / n, hi / n)
}

fn run(ctx: &mut Ctx) -> Result<Outcome> {
    let size = ctx.params.size("size")?;
    let frames = ctx.params.count_u32("frames")?.max(1);
    let counts = match multisample_counts(ctx.gpu)? {
        Ok(counts) => counts,
        Err(outcome) => return Ok(outcome),
    };
    let mut verdict = Verdict::new();
    for samples in counts {
        let transfer = measure_alpha_to_coverage(ctx.gpu, samples, false)?;
        let mut variants = vec![("paper", Stochastic::Paper)];
        match exact_alpha_table(&transfer) {
            Ok(exact_alpha) => variants.push(("corrected", Stochastic::Corrected { exact_alpha })),
            Err(e) => ctx.metric(&format!("{samples}x.corrected"), format!("not available: {e:#}")),
        }
        // GL supports writing the sample mask; a pipeline that does not build is the
        // translator's bug, not a missing capability.
        match sample_mask_output(ctx.gpu, samples) {
            Ok(()) => variants.push(("sample_mask", Stochastic::SampleMask)),
            Err(e) => {
                verdict.fail(format!("{samples}x: the @builtin(sample_mask) output pipeline does not build: {e}"))
            }
        }
        let target = ResolvedTarget::new(ctx.gpu, size, samples, COVERAGE_COLOUR);
        for (name, variant) in &variants {
            let mut rows = Vec::new();
            for alpha in ALPHAS {
                // One full-screen white layer of opacity α over transparent black: each pixel's
                // resolved red is its covered fraction.
                let scene = QuadScene::keyed(
                    "coverage",
                    vec![Quad { rect: [-1.0, 1.0, 1.0, -1.0], depth: (0.5, 0.5), alpha, colour: [1.0; 3], key: 0 }],
                );
                let mut noise = PingPongNoise::new(ctx.gpu, size, 17);
                let mut sum = 0.0f64;
                for frame in 0..frames {
                    if frame > 0 {
                        noise.advance(ctx.gpu);
                    }
                    render_stochastic(ctx.gpu, &scene, &target, &noise, variant, &mut GpuTimer::new(ctx.gpu, 1))?;
                    // The 8-bit resolve of k white samples out of N is round(255 k / N) / 255.
                    let n = f64::from(samples);
                    sum += target.read_rgb(ctx.gpu)?.iter().map(|p| (f64::from(p[0]) * n).round() / n).sum::<f64>();
                }
                let n = f64::from(size.0 * size.1 * frames);
                let mean = sum / n;
                let (lo, hi) = match variant {
                    Stochastic::Paper if alpha > 0.0 && alpha < 1.0 => {
                        quantised_expectation(&transfer, f64::from(alpha))
                    }
                    _ => (f64::from(alpha), f64::from(alpha)),
                };
                let spread = |mu: f64| 5.0 * (mu * (1.0 - mu) / n).sqrt();
                let ok = mean >= lo - spread(lo) && mean <= hi + spread(hi);
                rows.push(serde_json::json!({"alpha": alpha, "mean": mean, "expected": [lo, hi], "bound": spread(hi.max(lo)), "bias": mean - f64::from(alpha)}));
                if !ok {
                    verdict.fail(format!(
                        "{samples}x {name}: α {alpha}: mean coverage {mean:.5}, expected {lo:.5}..{hi:.5} ± {:.5}",
                        spread(hi)
                    ));
                }
            }
            ctx.metric(&format!("{samples}x.{name}"), rows);
        }
    }
    Ok(verdict.outcome())
}
