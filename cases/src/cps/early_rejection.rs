//! `cps.early_rejection`: the stencil-Equal lighting costs in proportion to the texels it shades:
//! the lighting pass with level 0 needed at 1/64 of the pixels (the rest at the top level, a
//! handful of texels) must cost far less than with level 0 everywhere (early stencil rejection).
//! Reports the GPU time per shaded texel of a foveated frame's lighting pass (every level is one
//! draw of that pass). When the ratio is too high, the kit's own capability probe decides: if it shows
//! this adapter rejecting early, CPS lost a capability the adapter has (Fail); only if the probe
//! shows no early rejection either is it NotSupported.

use anyhow::Result;
use fragkit::cps::{CompositeMode, CpsConfig, CpsRenderer, LodPolicy};
use fragkit::harness::{Case, Ctx, Outcome, ParamKind, ParamSpec};
use fragkit::probe::stencil_gated_draw::{REJECTION_RATIO_LIMIT, adapter_rejects_early};
use fragkit::shaders::{CPS_COMPOSITE, CPS_LIGHTING, CPS_LOD, CPS_MASK_REDUCE, CPS_STENCIL_MARK, FRAGMENT_STORAGE, FULLSCREEN, GBUFFER, HEAVY_SHADING, INDIRECT_DRAW, RECT};
use fragkit_report::noise::median;

use super::{corridor_inputs, frame};

pub const CASE: Case = Case {
    name: "cps.early_rejection",
    summary: "a level's lighting time scales with the texels its stencil passes",
    requires: wgpu::Features::TIMESTAMP_QUERY,
    params: &[
        ParamSpec { name: "size", kind: ParamKind::Size, default: "128x128", help: "screen size" },
        ParamSpec { name: "lights", kind: ParamKind::CountIn(1, 4096), default: "64", help: "point lights" },
        ParamSpec { name: "repeats", kind: ParamKind::CountIn(1, 1000), default: "3", help: "timed repeats (median)" },
    ],
    sweep: &[],
    budget_s: 13,
    timed_verdict: true,
    shaders: &[RECT, FULLSCREEN, HEAVY_SHADING, FRAGMENT_STORAGE, INDIRECT_DRAW, GBUFFER, CPS_LOD, CPS_MASK_REDUCE, CPS_LIGHTING, CPS_COMPOSITE, CPS_STENCIL_MARK],
    run,
};

fn run(ctx: &mut Ctx) -> Result<Outcome> {
    let size = ctx.params.size("size")?;
    let repeats = ctx.params.count("repeats")?.max(1);
    let inputs = corridor_inputs(ctx.gpu, size, ctx.params.count_u32("lights")?, 4)?;
    let pixels = (size.0 * size.1) as usize;

    // Level 0 in the top-left 1/8 × 1/8 of the screen, the rest at the coarsest level: time of
    // the lighting pass, versus level 0 everywhere.
    let corner: Vec<u8> = (0..pixels)
        .map(|i| if (i as u32 % size.0) < size.0 / 8 && (i as u32 / size.0) < size.1 / 8 { 0 } else { 8 })
        .collect();
    let mut level0_ms = Vec::new();
    for lod in [corner, vec![0u8; pixels]] {
        let renderer =
            CpsRenderer::new(ctx.gpu, size, CpsConfig::new(8, LodPolicy::Explicit(lod), CompositeMode::Nearest))?;
        renderer.render(ctx.gpu, &frame(&inputs))?;
        let times: Vec<f64> = (0..repeats)
            .map(|_| Ok(renderer.render(ctx.gpu, &frame(&inputs))?.gpu_ms("light")))
            .collect::<Result<_>>()?;
        level0_ms.push(median(times));
    }
    let fraction = f64::from((size.0 / 8) * (size.1 / 8)) / pixels as f64;
    let ratio = level0_ms[0] / level0_ms[1];
    ctx.metric("level0_passing_fraction", fraction);
    ctx.metric("level0_ms", serde_json::json!({"passing_fraction": level0_ms[0], "all": level0_ms[1]}));
    ctx.metric("time_ratio", ratio);

    // Time per shaded texel of a foveated frame's lighting pass.
    let foveated = CpsRenderer::new(ctx.gpu, size, CpsConfig::new(5, LodPolicy::foveated(), CompositeMode::Nearest))?;
    foveated.render(ctx.gpu, &frame(&inputs))?;
    let output = foveated.render(ctx.gpu, &frame(&inputs))?;
    let shaded: u64 = output.shaded_texels.iter().sum();
    let ms = output.gpu_ms("light");
    ctx.metric(
        "foveated_lighting",
        serde_json::json!({"shaded_per_level": output.shaded_texels, "ms": ms, "ns_per_texel": ms * 1e6 / shaded.max(1) as f64}),
    );

    if ratio <= REJECTION_RATIO_LIMIT {
        return Ok(Outcome::Pass);
    }
    let cps_says = format!("level 0 with {:.1} % of the pixels cost {ratio:.2}x the full level", fraction * 100.0);
    let (adapter_rejects, probe_ratio) = adapter_rejects_early(ctx.gpu)?;
    ctx.metric("probe_time_ratio", probe_ratio);
    Ok(if adapter_rejects {
        Outcome::Fail(format!(
            "CPS loses early stencil rejection: {cps_says}, while the kit's probe shows this adapter rejecting early (ratio {probe_ratio:.2})"
        ))
    } else {
        Outcome::NotSupported(format!(
            "early stencil rejection: {cps_says}; the kit's probe agrees (ratio {probe_ratio:.2})"
        ))
    })
}
