//! `fault.segfault`: the process running the case writes through a null pointer mid-case, as a
//! driver that dereferences a wild pointer kills it. The supervisor records the case as `crash`
//! with the signal, starts a new child and goes on.

use anyhow::Result;
use fragkit::harness::{Case, Ctx, Outcome};

pub const CASE: Case = Case {
    name: "fault.segfault",
    summary: "the process running the case writes through a null pointer (SIGSEGV) (crashes on purpose)",
    requires: wgpu::Features::empty(),
    params: &[],
    sweep: &[],
    budget_s: 1,
    timed_verdict: false,
    shaders: &[],
    run,
};

fn run(_ctx: &mut Ctx) -> Result<Outcome> {
    eprintln!("fault.segfault: writing through a null pointer on purpose");
    let null = std::hint::black_box(std::ptr::null_mut::<u64>());
    // SAFETY: not safe at all, on purpose: the fault this case injects is this write.
    unsafe { null.write_volatile(1) };
    Ok(Outcome::Pass)
}
