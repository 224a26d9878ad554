//! `fault.validation_error`: creates a texture wgpu must reject (zero width) in the middle of a
//! case. The runner's error scope turns the case into `fail` with wgpu's message; the next case
//! runs as if nothing happened.

use anyhow::Result;
use fragkit::harness::{Case, Ctx, Outcome};

pub const CASE: Case = Case {
    name: "fault.validation_error",
    summary: "a wgpu validation error mid-case fails that case with its message (fails on purpose)",
    requires: wgpu::Features::empty(),
    params: &[],
    sweep: &[],
    budget_s: 1,
    timed_verdict: false,
    shaders: &[],
    run,
};

fn run(ctx: &mut Ctx) -> Result<Outcome> {
    ctx.gpu.texture("zero-width texture", (0, 4), wgpu::TextureFormat::Rgba8Unorm, 1, wgpu::TextureUsages::COPY_SRC);
    // Reaching here is expected: the error surfaces when the runner pops its error scope.
    Ok(Outcome::Pass)
}
