//! `oit.order_independence`: the same stochastic frame (same seed) of the paper's quads drawn in
//! every one of the 24 orders of its four transparent quads reads back bit-identical, for each
//! stochastic variant: a fragment's random number depends on its quad's key and depth, never on
//! when it is drawn, and the depth test resolves the rest.

use anyhow::Result;
use fragkit::harness::{Case, Ctx, Outcome, ParamKind, ParamSpec, Sweep, SweepRange, Verdict};
use fragkit::oit::scene::QuadScene;
use fragkit::oit::stochastic::{COVERAGE_COLOUR, PingPongNoise, ResolvedTarget, available_variants, render_stochastic};
use fragkit::query::GpuTimer;
use fragkit::readback::read_texture;
use fragkit::shaders::{ALPHA_RAMP, FRAGMENT_STORAGE, FULLSCREEN, OIT_NOISE_STEP, OIT_QUAD, OIT_SAMPLE_MASK, OIT_STOCHASTIC, RECT, SAMPLE_COVERAGE_RECORD};

use super::multisample_counts;

pub const CASE: Case = Case {
    name: "oit.order_independence",
    summary: "every draw order of the paper's quads gives a bit-identical stochastic frame",
    requires: wgpu::Features::empty(),
    params: &[ParamSpec { name: "size", kind: ParamKind::Size, default: "48x48", help: "target size" }],
    sweep: &[Sweep { param: "size", range: SweepRange::Size { min: (4, 4), max: (128, 128) } }],
    budget_s: 3,
    timed_verdict: false,
    shaders: &[RECT, FULLSCREEN, SAMPLE_COVERAGE_RECORD, ALPHA_RAMP, FRAGMENT_STORAGE, OIT_QUAD, OIT_NOISE_STEP, OIT_STOCHASTIC, OIT_SAMPLE_MASK],
    run,
};

/// All orders of `items`.
fn permutations(items: &[usize]) -> Vec<Vec<usize>> {
    if items.len() <= 1 {
        return vec![items.to_vec()];
    }
    (0..items.len())
        .flat_map(|i| {
            let mut rest = items.to_vec();
            let first = rest.remove(i);
            permutations(&rest).into_iter().map(move |mut tail| {
                tail.insert(0, first);
                tail
            })
        })
        .collect()
}

fn run(ctx: &mut Ctx) -> Result<Outcome> {
    let size = ctx.params.size("size")?;
    let samples = match multisample_counts(ctx.gpu)? {
        Ok(counts) => *counts.last().expect("a non-empty list"),
        Err(outcome) => return Ok(outcome),
    };
    let variants = available_variants(ctx.gpu, samples)?;
    let scene = QuadScene::paper();
    let orders = permutations(&[1, 2, 3, 4]);
    let target = ResolvedTarget::new(ctx.gpu, size, samples, COVERAGE_COLOUR);
    let noise = PingPongNoise::new(ctx.gpu, size, 5);
    let mut verdict = Verdict::new();
    for variant in &variants {
        let mut first: Option<Vec<u8>> = None;
        let mut differing_orders = 0;
        for order in &orders {
            // The background stays first; the transparent quads (keys kept) in this order.
            let mut permuted = scene.clone();
            permuted.quads = std::iter::once(0).chain(order.iter().copied()).map(|i| scene.quads[i]).collect();
            render_stochastic(ctx.gpu, &permuted, &target, &noise, variant, &mut GpuTimer::new(ctx.gpu, 1))?;
            let bytes = read_texture(ctx.gpu, &target.resolved, wgpu::TextureAspect::All, 0)?.bytes;
            match &first {
                None => first = Some(bytes),
                Some(reference) if *reference != bytes => differing_orders += 1,
                Some(_) => {}
            }
        }
        let name = fragkit::oit::run::Method::Stochastic(variant.clone()).name();
        ctx.metric(name, serde_json::json!({"orders": orders.len(), "differing_from_first": differing_orders}));
        if differing_orders > 0 {
            verdict.fail(format!("{name}: {differing_orders} of {} draw orders differ from the first", orders.len()));
        }
    }
    Ok(verdict.outcome())
}
