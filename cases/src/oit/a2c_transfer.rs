//! `oit.a2c.transfer`: per sample count, the alpha → covered-samples table over 257 alphas and
//! several pixels: which counts occur, whether coverage is monotonic in alpha, whether the adapter
//! dithers, which masks it uses. Expected of any adapter: alpha 0 covers nothing, alpha 1 covers
//! every sample, coverage never falls as alpha grows, every count 0..=N is reachable.

use anyhow::Result;
use fragkit::harness::{Case, Ctx, Outcome};
use fragkit::probe::alpha_to_coverage::{ALPHA_STEPS, measure_alpha_to_coverage};
use fragkit::probe::sample_mask::measure_sample_mask;

use super::multisample_counts;

pub const CASE: Case = Case {
    name: "oit.a2c.transfer",
    summary: "alpha-to-coverage: monotonic, 0 → none, 1 → all, every count reachable; levels, masks, dithering",
    requires: wgpu::Features::empty(),
    params: &[],
    sweep: &[],
    run,
};

fn run(ctx: &mut Ctx) -> Result<Outcome> {
    let counts = multisample_counts(ctx.gpu);
    if counts.is_empty() {
        return Ok(Outcome::NotSupported("multisampling".into()));
    }
    let mut problems = Vec::new();
    for samples in counts {
        let mask_honoured = measure_sample_mask(ctx.gpu, samples)?.iter().all(|m| m.honoured());
        let transfer = measure_alpha_to_coverage(ctx.gpu, samples, mask_honoured)?;
        ctx.metric(&format!("{samples}x"), &transfer);
        let at = |step: u32| transfer.mean_covered[step as usize];
        if at(0) != 0.0 {
            problems.push(format!("{samples}x: alpha 0 covers {} samples", at(0)));
        }
        if at(ALPHA_STEPS) != samples as f32 {
            problems.push(format!("{samples}x: alpha 1 covers {} of {samples} samples", at(ALPHA_STEPS)));
        }
        if !transfer.monotonic {
            problems.push(format!("{samples}x: coverage falls somewhere as alpha grows"));
        }
        let missing: Vec<u32> = (0..=samples).filter(|k| !transfer.levels.contains(k)).collect();
        if !missing.is_empty() {
            problems.push(format!("{samples}x: no alpha covers exactly {missing:?} samples"));
        }
    }
    Ok(if problems.is_empty() { Outcome::Pass } else { Outcome::Fail(problems.join("; ")) })
}
