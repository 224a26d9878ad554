//! `fault.abort`: the process running the case aborts, as a driver bug can make it: the runner
//! must record a crash for this case alone and go on with the next in a new process. Opt-in.

use anyhow::Result;
use fragkit::harness::{Case, Ctx, Outcome};

pub const CASE: Case = Case {
    name: "fault.abort",
    summary: "aborts its process (opt-in): the runner records a crash and goes on",
    requires: wgpu::Features::empty(),
    params: &[],
    sweep: &[],
    budget_s: 1,
    timed_verdict: false,
    shaders: &[],
    run,
};

fn run(_ctx: &mut Ctx) -> Result<Outcome> {
    std::process::abort()
}
