//! `fault.hang`: the case never returns, as a driver wait that never ends would. (A shader
//! cannot stand in for it here: llvmpipe bounds every shader loop, and an endless loop — nested
//! three deep — came back in 36 ms.) The supervising `check` kills the process once the case's
//! timeout passes without a record (30 s, the shortest, from its 1 s budget; or `--timeout`) and
//! records the case as `timeout`.

use anyhow::Result;
use fragkit::harness::{Case, Ctx, Outcome};

pub const CASE: Case = Case {
    name: "fault.hang",
    summary: "the case never returns (times out on purpose)",
    requires: wgpu::Features::empty(),
    params: &[],
    sweep: &[],
    budget_s: 1,
    timed_verdict: false,
    shaders: &[],
    run,
};

fn run(_ctx: &mut Ctx) -> Result<Outcome> {
    eprintln!("fault.hang: waiting for ever on purpose");
    loop {
        std::thread::sleep(std::time::Duration::from_secs(3600));
    }
}
