//! `kit.msaa.sample_mask`: the pipeline's multisample mask decides which samples a draw may
//! write: with mask m, a white full-pixel draw into a cleared N-sample target resolves to
//! popcount(m)/N white. Checked for the empty mask, every single-sample mask and the full mask.

use anyhow::Result;
use fragkit::caps::common_sample_counts;
use fragkit::harness::{Case, Ctx, Outcome, Verdict};
use fragkit::probe::multisample_render::render_problem;
use fragkit::probe::sample_mask::measure_sample_mask;
use fragkit::shaders::RECT;

pub const CASE: Case = Case {
    name: "kit.msaa.sample_mask",
    summary: "the pipeline sample mask limits which samples a draw writes",
    requires: wgpu::Features::empty(),
    params: &[],
    sweep: &[],
    budget_s: 1,
    timed_verdict: false,
    shaders: &[RECT],
    run,
};

fn run(ctx: &mut Ctx) -> Result<Outcome> {
    let multisampled: Vec<u32> = common_sample_counts(ctx.gpu).into_iter().filter(|&n| n > 1).collect();
    if multisampled.is_empty() {
        return Ok(Outcome::NotSupported("multisampling".into()));
    }
    let mut verdict = Verdict::new();
    for samples in multisampled {
        if let Some(problem) = render_problem(ctx.gpu, samples)? {
            verdict.fail(problem);
            continue;
        }
        let results = measure_sample_mask(ctx.gpu, samples)?;
        for r in results.iter().filter(|r| !r.honoured()) {
            verdict
                .fail(format!("{samples}x mask {:#b}: resolved {}, expected {} (±1)", r.mask, r.resolved, r.expected));
        }
        ctx.metric(&format!("{samples}x"), &results);
    }
    Ok(verdict.outcome())
}
