//! `kit.hash.values`: the WGSL hash functions every seeded GPU pass calls (`pcg_hash`,
//! `hash_unit` in shaders/common/hash.wgsl; the OIT per-fragment number `fragment_random` in
//! shaders/common/opacity.wgsl) give, bit for bit, what their definitions give on the CPU — the
//! CPU hash anchored to the published PCG values — over 16384 inputs, including runs that differ
//! only in depth. Integer arithmetic is exact and WGSL rounds f32 addition and multiplication
//! correctly, so no tolerance applies.

use anyhow::Result;
use fragkit::harness::{Case, Ctx, Outcome};
use fragkit::oit::fragment_random::fragment_random;
use fragkit::probe::hash_values::{GRID_WIDTH, RandomInputs, evaluate_hashes};
use fragkit::scene::hash::{hash_unit, pcg_hash};
use fragkit::shaders::{FULLSCREEN, HASH_VALUES};

pub const CASE: Case = Case {
    name: "kit.hash.values",
    summary: "the WGSL hash and per-fragment random number equal their CPU definitions bit for bit",
    requires: wgpu::Features::empty(),
    params: &[],
    sweep: &[],
    budget_s: 1,
    timed_verdict: false,
    shaders: &[FULLSCREEN, HASH_VALUES],
    run,
};

const ROWS: u32 = 64;

const FUNCTIONS: [&str; 3] = ["pcg_hash", "hash_unit", "fragment_random"];

fn run(ctx: &mut Ctx) -> Result<Outcome> {
    let got = evaluate_hashes(ctx.gpu, ROWS)?;
    let mut wrong = [0usize; 3];
    let mut examples = Vec::new();
    for (k, values) in (0..GRID_WIDTH * ROWS).zip(&got) {
        // Expected: each function's definition on the same inputs.
        let inputs = RandomInputs::at(k);
        let expected = [
            pcg_hash(k),
            hash_unit(k).to_bits(),
            fragment_random(inputs.noise, inputs.depth, inputs.id, inputs.stream).to_bits(),
        ];
        let measured = [values.hash, values.unit.to_bits(), values.random.to_bits()];
        for (f, (m, e)) in measured.into_iter().zip(expected).enumerate() {
            if m != e {
                wrong[f] += 1;
                if wrong[f] == 1 {
                    examples.push(format!("{}(k={k}) = {m:#010x}, defined {e:#010x}", FUNCTIONS[f]));
                }
            }
        }
    }
    ctx.metric("inputs", GRID_WIDTH * ROWS);
    for (name, count) in FUNCTIONS.iter().zip(wrong) {
        ctx.metric(&format!("{name}.wrong"), count);
    }
    Ok(if examples.is_empty() {
        Outcome::Pass
    } else {
        Outcome::Fail(format!(
            "{} of {} inputs differ: {}",
            wrong.iter().max().unwrap_or(&0),
            GRID_WIDTH * ROWS,
            examples.join("; ")
        ))
    })
}
