//! `kit.early_rejection`: a heavy fragment shader behind a stencil-Equal test that passes ≤ 2 %
//! of the pixels must cost far less GPU time than the same draw with stencil Always. Counts are
//! checked exactly (occlusion query; atomic counter under `@early_depth_test(force)` where the
//! feature exists); the time ratio is a capability result, since a driver may legally shade late.

use anyhow::Result;
use fragkit::harness::{Case, Ctx, Outcome, ParamKind, ParamSpec, Verdict};
use fragkit::probe::occlusion::{OcclusionPrecision, measure_occlusion_precision};
use fragkit::probe::stencil_gated_draw::{REJECTION_RATIO_LIMIT, StencilGatedDraw};
use fragkit::shaders::{FRAGMENT_COUNTER, FRAGMENT_STORAGE, FULLSCREEN, HEAVY_SHADING, RECT};

pub const CASE: Case = Case {
    name: "kit.early_rejection",
    summary: "a stencil-Equal test that passes few pixels skips the fragment shader for the rest",
    requires: wgpu::Features::empty(),
    params: &[
        ParamSpec { name: "size", kind: ParamKind::Size, default: "256x256", help: "target size" },
        ParamSpec {
            name: "passing",
            kind: ParamKind::Sizes,
            default: "36x36",
            help: "stencil-marked square (1.98 % of 256x256)",
        },
        ParamSpec {
            name: "iterations",
            kind: ParamKind::CountIn(1, 100000),
            default: "96",
            help: "shader loop length",
        },
        ParamSpec {
            name: "repeats",
            kind: ParamKind::CountIn(1, 1000),
            default: "3",
            help: "timed repeats (median taken)",
        },
    ],
    sweep: &[],
    budget_s: 8,
    timed_verdict: true,
    shaders: &[RECT, FULLSCREEN, HEAVY_SHADING, FRAGMENT_COUNTER, FRAGMENT_STORAGE],
    run,
};

fn run(ctx: &mut Ctx) -> Result<Outcome> {
    let size = ctx.params.size("size")?;
    let passing = ctx.params.sizes("passing")?[0];
    let iterations = ctx.params.count_u32("iterations")?;
    let repeats = ctx.params.count("repeats")?;
    let gpu = ctx.gpu;
    let precision = measure_occlusion_precision(gpu)?;
    let can_count = gpu.has(wgpu::Features::SHADER_EARLY_DEPTH_TEST)
        && fragkit::probe::fragment_storage::fragment_storage_problem(gpu)?.is_none();
    ctx.metric("timer", if gpu.has(wgpu::Features::TIMESTAMP_QUERY) { "gpu timestamps" } else { "wall clock" });

    // Render: one untimed round pays for shader compilation, then timed repeats of both gates.
    let draw = StencilGatedDraw::new(gpu, size, passing, iterations)?;
    let times = draw.time(gpu, repeats)?;
    let warm_up = times.first_equal;
    let counted_fragments = if can_count { Some(draw.count_fragments_with_atomic(gpu)?) } else { None };

    // Expected: exactly the marked square passes.
    let expected = u64::from(passing.0 * passing.1);
    let fraction = expected as f64 / f64::from(size.0 * size.1);
    let (equal_ms, always_ms, ratio) = (times.equal_ms, times.always_ms, times.ratio());
    ctx.metric("passing_fraction", fraction);
    ctx.metric("equal_ms", equal_ms);
    ctx.metric("always_ms", always_ms);
    ctx.metric("time_ratio", ratio);
    ctx.metric("occlusion_count", serde_json::json!({"expected": expected, "measured": warm_up.passing_samples}));
    ctx.metric("atomic_count", serde_json::json!({"expected": expected, "measured": counted_fragments}));

    let mut verdict = Verdict::new();
    if precision == OcclusionPrecision::Exact && warm_up.passing_samples != expected {
        verdict
            .fail(format!("occlusion query counted {} passing pixels, expected {expected}", warm_up.passing_samples));
    }
    if let Some(counted) = counted_fragments
        && u64::from(counted) != expected
    {
        verdict
            .fail(format!("atomic counter under early_depth_test(force) saw {counted} fragments, expected {expected}"));
    }
    Ok(if !verdict.is_clean() {
        verdict.outcome()
    } else if ratio > REJECTION_RATIO_LIMIT {
        Outcome::NotSupported(format!(
            "early stencil rejection: the Equal draw ({:.2} % passing) cost {ratio:.2}x the Always draw",
            fraction * 100.0
        ))
    } else {
        Outcome::Pass
    })
}
