//! `oit.a2c.transfer`: per sample count, the alpha → covered-samples table over 257 alphas and
//! several pixels: which counts occur, whether coverage is monotonic in alpha, whether the adapter
//! dithers, which masks it uses. Expected of any adapter: alpha 0 covers nothing, alpha 1 covers
//! every sample, coverage never falls as alpha grows, every count 0..=N is reachable; and the
//! kit's plain A2C method (`render_plain_coverage`, `shaders/oit/plain_coverage.wgsl`) covers, at
//! each of those alphas, what the transfer measured in the same run does (undithered adapters).

use anyhow::Result;
use fragkit::Gpu;
use fragkit::harness::{Case, Ctx, Outcome, Verdict};
use fragkit::oit::run::{Accumulation, Method, run_method};
use fragkit::oit::scene::{Quad, QuadScene};
use fragkit::probe::alpha_to_coverage::{ALPHA_STEPS, measure_alpha_to_coverage};
use fragkit::probe::sample_mask::measure_sample_mask;
use fragkit::shaders::{ALPHA_RAMP, FRAGMENT_STORAGE, FULLSCREEN, OIT_PLAIN_COVERAGE, OIT_QUAD, RECT, SAMPLE_COVERAGE_RECORD};

use super::multisample_counts;

pub const CASE: Case = Case {
    name: "oit.a2c.transfer",
    summary: "alpha-to-coverage: monotonic, 0 → none, 1 → all, every count reachable; levels, masks, dithering",
    requires: wgpu::Features::empty(),
    params: &[],
    sweep: &[],
    budget_s: 1,
    timed_verdict: false,
    shaders: &[RECT, FULLSCREEN, SAMPLE_COVERAGE_RECORD, ALPHA_RAMP, FRAGMENT_STORAGE, OIT_QUAD, OIT_PLAIN_COVERAGE],
    run,
};

/// Covered samples per column of a white layer over black drawn by the plain A2C method, column
/// k at alpha k / ALPHA_STEPS (the transfer probe's alphas, bit for bit), read from the resolve.
fn plain_coverage_columns(gpu: &Gpu, samples: u32) -> Result<Vec<f32>> {
    let columns = ALPHA_STEPS + 1;
    let ndc_x = |k: u32| 2.0 * k as f32 / columns as f32 - 1.0;
    let mut quads =
        vec![Quad { rect: [-1.0, 1.0, 1.0, -1.0], depth: (0.999, 0.999), alpha: 1.0, colour: [0.0; 3], key: 0 }];
    quads.extend((0..columns).map(|k| Quad {
        rect: [ndc_x(k), 1.0, ndc_x(k + 1), -1.0],
        depth: (0.5, 0.5),
        alpha: k as f32 / ALPHA_STEPS as f32,
        colour: [1.0; 3],
        key: 0,
    }));
    let scene = QuadScene::keyed("alpha columns", quads);
    let once = Accumulation { frames: 1, seed: 1, filtered: false };
    let image = run_method(gpu, &scene, (columns, 1), samples, &Method::PlainCoverage, once)?.image;
    // The resolve averages white and black samples: the covered fraction, to 8 bits.
    Ok(image.iter().map(|rgb| (rgb[0] * samples as f32).round()).collect())
}

fn run(ctx: &mut Ctx) -> Result<Outcome> {
    let counts = match multisample_counts(ctx.gpu)? {
        Ok(counts) => counts,
        Err(outcome) => return Ok(outcome),
    };
    let mut verdict = Verdict::new();
    for samples in counts {
        let mask_honoured = measure_sample_mask(ctx.gpu, samples)?.iter().all(|m| m.honoured());
        let transfer = measure_alpha_to_coverage(ctx.gpu, samples, mask_honoured)?;
        ctx.metric(&format!("{samples}x"), &transfer);
        let at = |step: u32| transfer.mean_covered[step as usize];
        if at(0) != 0.0 {
            verdict.fail(format!("{samples}x: alpha 0 covers {} samples", at(0)));
        }
        if at(ALPHA_STEPS) != samples as f32 {
            verdict.fail(format!("{samples}x: alpha 1 covers {} of {samples} samples", at(ALPHA_STEPS)));
        }
        if !transfer.monotonic {
            verdict.fail(format!("{samples}x: coverage falls somewhere as alpha grows"));
        }
        let missing: Vec<u32> = (0..=samples).filter(|k| !transfer.levels.contains(k)).collect();
        if !missing.is_empty() {
            verdict.fail(format!("{samples}x: no alpha covers exactly {missing:?} samples"));
        }
        // The kit's plain A2C method (the comparison baseline) must cover what the adapter's
        // transfer does at its quads' own alphas; where the adapter dithers, a pixel's count
        // depends on where it lies, so only the undithered transfer is a per-pixel reference.
        if transfer.dithered {
            ctx.metric(&format!("{samples}x.plain_coverage"), "not compared: the adapter dithers");
            continue;
        }
        let columns = plain_coverage_columns(ctx.gpu, samples)?;
        let differing: Vec<u32> = (0..=ALPHA_STEPS).filter(|&k| columns[k as usize] != at(k)).collect();
        ctx.metric(&format!("{samples}x.plain_coverage_differing_alphas"), differing.len());
        if let Some(&k) = differing.first() {
            verdict.fail(format!(
                "{samples}x: plain alpha-to-coverage at {} of {} alphas covers other than the measured transfer (alpha {k}/{ALPHA_STEPS}: {} samples, transfer {})",
                differing.len(),
                ALPHA_STEPS + 1,
                columns[k as usize],
                at(k)
            ));
        }
    }
    Ok(verdict.outcome())
}
