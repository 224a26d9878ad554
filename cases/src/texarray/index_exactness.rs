//! `texarray.index_exactness`: for each way of fetching element k of a 2D texture used as a 1D
//! array, every index of a sweep up to and past 2^24 (dense near powers of two and the end) is
//! fetched on the GPU and held to what that variant may return by its definition
//! (`fragkit::texarray::model`: its f32 arithmetic and the sampler as the specifications bound
//! them): exactly k where the formats make it exact, one of the few neighbours the bounds allow
//! where they do not — any other element is a wrong address. Reported per variant: where the
//! model's exactness ends, and where this adapter's does. The integer variant — `array_texel` of
//! shaders/common/lighting.wgsl, the very function the lighting fetches lights with — is exact
//! everywhere.

use anyhow::Result;
use fragkit::harness::{Case, Ctx, Outcome, ParamKind, ParamSpec, Sweep, SweepRange, Verdict};
use fragkit::texarray::model::possible_elements;
use fragkit::texarray::{measure_index_exactness, sweep_indices};
use fragkit::shaders::{FULLSCREEN, TEXARRAY_FETCH};

pub const CASE: Case = Case {
    name: "texarray.index_exactness",
    summary: "element k of a texture used as a 1D array: which fetch variants stay exact past 2^24",
    requires: wgpu::Features::empty(),
    params: &[ParamSpec {
        name: "size",
        kind: ParamKind::Size,
        default: "4096x4097",
        help: "array texture size (4096x4097 holds 2^24 + 4096 elements)",
    }],
    sweep: &[Sweep { param: "size", range: SweepRange::Size { min: (1, 1), max: (4096, 4097) } }],
    budget_s: 2,
    timed_verdict: false,
    shaders: &[FULLSCREEN, TEXARRAY_FETCH],
    run,
};

fn run(ctx: &mut Ctx) -> Result<Outcome> {
    let size = ctx.params.size("size")?;
    let elements = size.0 * size.1;
    let indices = sweep_indices(elements);
    ctx.metric("elements", elements);
    ctx.metric("indices_tried", indices.len());

    let results = measure_index_exactness(ctx.gpu, size, &indices)?;
    let mut verdict = Verdict::new();
    for result in &results {
        let name = format!("{:?}", result.variant).to_lowercase();
        ctx.metric(&name, result);
        // Expected, per index, from the variant's definition: the elements it may fetch.
        let allowed: Vec<Vec<u64>> = indices.iter().map(|&k| possible_elements(result.variant, k, size)).collect();
        let model_exact_until = indices.iter().zip(&allowed).find(|(k, a)| a.as_slice() != [u64::from(**k)]);
        ctx.metric(&format!("{name}.model_first_inexact_index"), model_exact_until.map(|(k, _)| *k));
        let outside: Vec<(u32, u32, &Vec<u64>)> = indices
            .iter()
            .zip(&result.fetched)
            .zip(&allowed)
            .filter(|((_, got), a)| !a.contains(&u64::from(**got)))
            .map(|((&k, &got), a)| (k, got, a))
            .collect();
        ctx.metric(&format!("{name}.outside_the_model"), outside.len());
        if let Some((k, got, a)) = outside.first() {
            let shown: Vec<u64> = a.iter().copied().take(8).collect();
            verdict.fail(format!(
                "{name}: index {k} fetched element {got}, which its definition cannot give (it may give {shown:?}); {} of {} indices so",
                outside.len(),
                indices.len()
            ));
        }
    }
    Ok(verdict.outcome())
}
