//! `cbr.jitter.coverage`: the samples of the two jitter phases, as the GPU placed them, hit
//! every full-resolution pixel centre exactly once, except the documented edge (odd rows of the
//! first column, which the right-jittered phase never reaches). Counted per pixel, odd sizes
//! included.

use anyhow::Result;
use fragkit::cbr::probe::measure_landing;
use fragkit::cbr::sampling::{CheckerboardPath, check_screen, documented_gaps};
use fragkit::harness::{Case, Ctx, Outcome, ParamKind, ParamSpec, Sweep, SweepRange, Verdict};
use fragkit::shaders::{CBR_SAMPLE_ID_RECORD, FRAGMENT_STORAGE, FULLSCREEN, RECT, SAMPLE_COVERAGE_RECORD};

pub const CASE: Case = Case {
    name: "cbr.jitter.coverage",
    summary: "two jittered frames sample every full-resolution pixel once, bar the documented column",
    requires: wgpu::Features::empty(),
    params: &[ParamSpec {
        name: "sizes",
        kind: ParamKind::SizesFrom(2),
        default: "2x2,7x5,33x17,64x48",
        help: "full-resolution sizes",
    }],
    sweep: &[Sweep { param: "sizes", range: SweepRange::Size { min: (2, 2), max: (400, 300) } }],
    budget_s: 1,
    timed_verdict: false,
    shaders: &[RECT, FULLSCREEN, SAMPLE_COVERAGE_RECORD, FRAGMENT_STORAGE, CBR_SAMPLE_ID_RECORD],
    run,
};

fn run(ctx: &mut Ctx) -> Result<Outcome> {
    let path = CheckerboardPath::for_adapter(ctx.gpu);
    ctx.metric("path", path.name());
    let mut verdict = Verdict::new();
    for screen in ctx.params.sizes("sizes")? {
        check_screen(screen)?;
        let mut hits = vec![0u32; (screen.0 * screen.1) as usize];
        for phase in 0..2 {
            for (x, y) in measure_landing(ctx.gpu, screen, path, phase)?.into_iter().flatten().flatten() {
                hits[(y * screen.0 + x) as usize] += 1;
            }
        }
        let gaps = documented_gaps(screen);
        let (mut twice, mut missed, mut gap_hits) = (0, 0, 0);
        for y in 0..screen.1 {
            for x in 0..screen.0 {
                let count = hits[(y * screen.0 + x) as usize];
                match (gaps.contains(&(x, y)), count) {
                    (true, 0) | (false, 1) => {}
                    (true, _) => gap_hits += 1,
                    (false, 0) => missed += 1,
                    (false, _) => twice += 1,
                }
            }
        }
        let key = format!("{}x{}", screen.0, screen.1);
        ctx.metric(&key, serde_json::json!({"missed": missed, "hit_more_than_once": twice, "documented_gaps": gaps.len(), "gaps_hit": gap_hits}));
        if missed + twice + gap_hits > 0 {
            verdict.fail(format!("{key}: {missed} pixels never sampled, {twice} sampled more than once, {gap_hits} documented gaps sampled"));
        }
    }
    Ok(verdict.outcome())
}
