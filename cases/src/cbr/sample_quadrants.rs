//! `cbr.sample_quadrants`: on the checkerboard path this adapter uses (a real 2x target where
//! the kit measured one, the offset passes otherwise), every sample of every quarter-resolution
//! pixel lands on the expected full-resolution pixel centre — measured by rasterising one rect
//! per full-resolution pixel through the frame's projection — in both jitter phases.

use anyhow::Result;
use fragkit::cbr::probe::measure_landing;
use fragkit::cbr::sampling::{CheckerboardPath, check_screen, quarter_size, sample_pixel, sample_positions};
use fragkit::harness::{Case, Ctx, Outcome, ParamKind, ParamSpec, Sweep, SweepRange, Verdict};
use fragkit::shaders::{CBR_SAMPLE_ID_RECORD, FRAGMENT_STORAGE, FULLSCREEN, RECT, SAMPLE_COVERAGE_RECORD};

pub const CASE: Case = Case {
    name: "cbr.sample_quadrants",
    summary: "every checkerboard sample lands on its full-resolution pixel centre, both phases",
    requires: wgpu::Features::empty(),
    params: &[ParamSpec {
        name: "sizes",
        kind: ParamKind::SizesFrom(2),
        default: "2x2,7x5,64x48",
        help: "full-resolution sizes",
    }],
    sweep: &[Sweep { param: "sizes", range: SweepRange::Size { min: (2, 2), max: (300, 200) } }],
    budget_s: 1,
    timed_verdict: false,
    shaders: &[RECT, FULLSCREEN, SAMPLE_COVERAGE_RECORD, FRAGMENT_STORAGE, CBR_SAMPLE_ID_RECORD],
    run,
};

fn run(ctx: &mut Ctx) -> Result<Outcome> {
    let path = CheckerboardPath::for_adapter(ctx.gpu);
    ctx.metric("path", path.name());
    let positions = sample_positions();
    let mut verdict = Verdict::new();
    for screen in ctx.params.sizes("sizes")? {
        check_screen(screen)?;
        let quarter = quarter_size(screen);
        for phase in 0..2 {
            let landed = measure_landing(ctx.gpu, screen, path, phase)?;
            // Expected: the pixel the mapping names, or nothing where that pixel is off screen.
            let mut wrong = Vec::new();
            for (i, slots) in landed.iter().enumerate() {
                let q = (i as u32 % quarter.0, i as u32 / quarter.0);
                for (sample, got) in slots.iter().enumerate() {
                    let (x, y) = sample_pixel(q, sample, phase, &positions);
                    let on_screen = (0..i64::from(screen.0)).contains(&x) && (0..i64::from(screen.1)).contains(&y);
                    let expected = on_screen.then_some((x as u32, y as u32));
                    if *got != expected {
                        wrong.push(format!("q{q:?} s{sample}: {got:?} not {expected:?}"));
                    }
                }
            }
            ctx.metric(&format!("{}x{}.phase{phase}.wrong_samples", screen.0, screen.1), wrong.len());
            if !wrong.is_empty() {
                verdict.fail(format!(
                    "{}x{} phase {phase}: {} samples misplaced, e.g. {}",
                    screen.0,
                    screen.1,
                    wrong.len(),
                    wrong[..wrong.len().min(3)].join(", ")
                ));
            }
        }
    }
    Ok(verdict.outcome())
}
