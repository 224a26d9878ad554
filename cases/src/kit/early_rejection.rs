//! `kit.early_rejection`: a heavy fragment shader behind a stencil-Equal test that passes ≤ 2 %
//! of the pixels must cost far less GPU time than the same draw with stencil Always. Counts are
//! checked exactly (occlusion query; atomic counter under `@early_depth_test(force)` where the
//! feature exists); the time ratio is a capability result, since a driver may legally shade late.

use anyhow::Result;
use fragkit::harness::{Case, Ctx, Outcome, ParamKind, ParamSpec};
use fragkit::probe::occlusion::{OcclusionPrecision, measure_occlusion_precision};
use fragkit::probe::stencil_gated_draw::{Gate, GatedDraw, StencilGatedDraw};
use fragkit::query::median;

pub const CASE: Case = Case {
    name: "kit.early_rejection",
    summary: "a stencil-Equal test that passes few pixels skips the fragment shader for the rest",
    requires: wgpu::Features::empty(),
    params: &[
        ParamSpec { name: "size", kind: ParamKind::Sizes, default: "256x256", help: "target size" },
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
    run,
};

/// Above this Equal/Always time ratio the adapter is judged to shade rejected fragments anyway:
/// halfway between perfect rejection (the passing fraction, ≤ 0.02) and none (1.0).
const REJECTION_RATIO_LIMIT: f64 = 0.5;

/// GPU time where the adapter has timestamps, else the wall time of a submit-and-wait.
fn time_ms(draw: &GatedDraw) -> f64 {
    draw.gpu_ms.unwrap_or(draw.wall_ms)
}

fn run(ctx: &mut Ctx) -> Result<Outcome> {
    let size = ctx.params.sizes("size")?[0];
    let passing = ctx.params.sizes("passing")?[0];
    let iterations = u32::try_from(ctx.params.count("iterations")?)?;
    let repeats = ctx.params.count("repeats")?.max(1);
    let gpu = ctx.gpu;
    let precision = measure_occlusion_precision(gpu)?;
    let can_count = gpu.has(wgpu::Features::SHADER_EARLY_DEPTH_TEST)
        && gpu.adapter.get_downlevel_capabilities().flags.contains(wgpu::DownlevelFlags::FRAGMENT_WRITABLE_STORAGE);
    ctx.metric("timer", if gpu.has(wgpu::Features::TIMESTAMP_QUERY) { "gpu timestamps" } else { "wall clock" });

    // Render: one untimed round pays for shader compilation, then timed repeats of both gates.
    let draw = StencilGatedDraw::new(gpu, size, passing, iterations)?;
    let warm_up = draw.draw(gpu, Gate::Equal)?;
    draw.draw(gpu, Gate::Always)?;
    let mut equal = Vec::new();
    let mut always = Vec::new();
    for _ in 0..repeats {
        equal.push(time_ms(&draw.draw(gpu, Gate::Equal)?));
        always.push(time_ms(&draw.draw(gpu, Gate::Always)?));
    }
    let counted_fragments = if can_count { Some(draw.count_fragments_with_atomic(gpu)?) } else { None };

    // Expected: exactly the marked square passes.
    let expected = u64::from(passing.0 * passing.1);
    let fraction = expected as f64 / f64::from(size.0 * size.1);
    let (equal_ms, always_ms) = (median(equal), median(always));
    let ratio = equal_ms / always_ms;
    ctx.metric("passing_fraction", fraction);
    ctx.metric("equal_ms", equal_ms);
    ctx.metric("always_ms", always_ms);
    ctx.metric("time_ratio", ratio);
    ctx.metric("occlusion_count", serde_json::json!({"expected": expected, "measured": warm_up.passing_samples}));
    ctx.metric("atomic_count", serde_json::json!({"expected": expected, "measured": counted_fragments}));

    let mut problems = Vec::new();
    if precision == OcclusionPrecision::Exact && warm_up.passing_samples != expected {
        problems
            .push(format!("occlusion query counted {} passing pixels, expected {expected}", warm_up.passing_samples));
    }
    if let Some(counted) = counted_fragments
        && u64::from(counted) != expected
    {
        problems
            .push(format!("atomic counter under early_depth_test(force) saw {counted} fragments, expected {expected}"));
    }
    Ok(if !problems.is_empty() {
        Outcome::Fail(problems.join("; "))
    } else if ratio > REJECTION_RATIO_LIMIT {
        Outcome::NotSupported(format!(
            "early stencil rejection: the Equal draw ({:.2} % passing) cost {ratio:.2}x the Always draw",
            fraction * 100.0
        ))
    } else {
        Outcome::Pass
    })
}
