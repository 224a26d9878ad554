//! `kit.draw.indirect`: an indirect full-target draw renders every pixel, first on its own and
//! then after a draw whose vertex buffer was freed (`fragkit::probe::indirect_draw`, which the
//! CPS plan asks before drawing its levels indirectly). The expectation is the draw's definition:
//! arguments (3 vertices, 1 instance) cover the target, whatever vertex state came before.

use anyhow::Result;
use fragkit::harness::{Case, Ctx, Outcome};
use fragkit::probe::indirect_draw::indirect_draw_problem;
use fragkit::shaders::{FULLSCREEN, INDIRECT_DRAW, RECT};

pub const CASE: Case = Case {
    name: "kit.draw.indirect",
    summary: "an indirect draw renders, also after an earlier draw's vertex buffer was freed",
    requires: wgpu::Features::empty(),
    params: &[],
    sweep: &[],
    budget_s: 1,
    timed_verdict: false,
    shaders: &[RECT, FULLSCREEN, INDIRECT_DRAW],
    run,
};

fn run(ctx: &mut Ctx) -> Result<Outcome> {
    if !ctx.gpu.adapter.get_downlevel_capabilities().flags.contains(wgpu::DownlevelFlags::INDIRECT_EXECUTION) {
        return Ok(Outcome::NotSupported("INDIRECT_EXECUTION (the adapter's API has no indirect draws)".into()));
    }
    Ok(match indirect_draw_problem(ctx.gpu)? {
        None => Outcome::Pass,
        Some(problem) => Outcome::Fail(problem),
    })
}
