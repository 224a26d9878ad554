//! `fault.abort`: the process running the case aborts mid-case, as a driver that aborts on heap
//! corruption kills it. The supervisor records the case as `crash` with the signal, starts a new
//! child and goes on.

use anyhow::Result;
use fragkit::harness::{Case, Ctx, Outcome};

pub const CASE: Case = Case {
    name: "fault.abort",
    summary: "the process running the case aborts (SIGABRT) mid-case (crashes on purpose)",
    requires: wgpu::Features::empty(),
    params: &[],
    sweep: &[],
    budget_s: 1,
    timed_verdict: false,
    shaders: &[],
    run,
};

fn run(_ctx: &mut Ctx) -> Result<Outcome> {
    eprintln!("fault.abort: aborting on purpose");
    std::process::abort()
}
