//! `fault.out_of_memory`: the case asks for more memory than the machine has, as a driver that
//! allocates without bound would. The allocator refuses and the process aborts ("memory allocation
//! of … bytes failed"); the supervising `check` records the case as `crash` with that message and
//! goes on. One request of 4 TiB, refused at once: growing until the kernel's OOM killer steps in
//! would take the machine's other processes with it.

use anyhow::Result;
use fragkit::harness::{Case, Ctx, Outcome};

pub const CASE: Case = Case {
    name: "fault.out_of_memory",
    summary: "the case allocates 4 TiB and the process aborts (runs out of memory on purpose)",
    requires: wgpu::Features::empty(),
    params: &[],
    sweep: &[],
    budget_s: 1,
    timed_verdict: false,
    shaders: &[],
    run,
};

fn run(_ctx: &mut Ctx) -> Result<Outcome> {
    eprintln!("fault.out_of_memory: allocating 4 TiB on purpose");
    let huge: Vec<u8> = vec![1; 1 << 42];
    // Reading it back keeps the allocation from being optimised away.
    Ok(Outcome::Fail(format!("4 TiB were allocated ({} bytes): the fault did not happen", huge.len())))
}
