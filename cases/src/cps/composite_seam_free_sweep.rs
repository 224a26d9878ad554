//! `cps.composite.seam_free_sweep`: over `fragkit report cps`'s own sweep (foveated and content
//! LOD × top levels 2, 4, 6 × 1, 16, 64, 200 lights, the corridor at 320×180), the seam-free
//! composite's seam error and FLIP against full resolution are at or below the original
//! 4-neighbour interpolation's on every row. Both are measured in the same run on the same LOD
//! and lit levels, so the reference is the rival, not a constant. Nearest is recorded beside
//! them. Parameter-free: the sweep is the report's.

use anyhow::Result;
use fragkit::cps::CompositeMode;
use fragkit::cps::report::{CpsSweep, composite_quality};
use fragkit::harness::{Case, Ctx, Outcome, Verdict};
use fragkit::shaders::{CPS_COMPOSITE, CPS_EDGE_MASK, CPS_LIGHTING, CPS_LOD, CPS_MASK_REDUCE, CPS_STENCIL_MARK, DEFERRED_LIGHTING, FRAGMENT_STORAGE, FULLSCREEN, GBUFFER, INDIRECT_DRAW, RECT};

pub const CASE: Case = Case {
    name: "cps.composite.seam_free_sweep",
    summary: "over the CPS report's sweep, seam-free is at or below 4-neighbour in seam error and FLIP on every row",
    requires: wgpu::Features::empty(),
    params: &[],
    sweep: &[],
    budget_s: 97,
    timed_verdict: false,
    shaders: &[RECT, FULLSCREEN, FRAGMENT_STORAGE, INDIRECT_DRAW, GBUFFER, DEFERRED_LIGHTING, CPS_EDGE_MASK, CPS_LOD, CPS_MASK_REDUCE, CPS_LIGHTING, CPS_COMPOSITE, CPS_STENCIL_MARK],
    run,
};

fn run(ctx: &mut Ctx) -> Result<Outcome> {
    // Setup, render and measure: every composite on every configuration of the report's sweep.
    let sweep = CpsSweep::default();
    let rows = composite_quality(ctx.gpu, &sweep, &CompositeMode::ALL)?;

    // Compare each seam-free row with the 4-neighbour row of the same configuration.
    let mut verdict = Verdict::new();
    for ours in rows.iter().filter(|r| r.composite == CompositeMode::SeamFree) {
        let configuration = format!("{}.top{}.lights{}", ours.policy, ours.max_level, ours.lights);
        let of = |mode| {
            rows.iter().find(|r| {
                r.composite == mode && (&r.policy, r.max_level, r.lights) == (&ours.policy, ours.max_level, ours.lights)
            })
        };
        let (Some(original), Some(nearest)) = (of(CompositeMode::FourNeighbour), of(CompositeMode::Nearest)) else {
            anyhow::bail!("{configuration}: the sweep lacks a 4-neighbour or nearest row");
        };
        ctx.metric(
            &configuration,
            serde_json::json!({
                "seam_error": {"seam_free": ours.quality.seam_error, "four_neighbour": original.quality.seam_error, "nearest": nearest.quality.seam_error},
                "flip": {"seam_free": ours.quality.flip, "four_neighbour": original.quality.flip, "nearest": nearest.quality.flip},
            }),
        );
        if ours.quality.seam_error > original.quality.seam_error {
            verdict.fail(format!(
                "{configuration}: seam error {:.5} above 4-neighbour's {:.5}",
                ours.quality.seam_error, original.quality.seam_error
            ));
        }
        if ours.quality.flip > original.quality.flip {
            verdict.fail(format!(
                "{configuration}: FLIP {:.5} above 4-neighbour's {:.5}",
                ours.quality.flip, original.quality.flip
            ));
        }
    }
    ctx.metric("rows", rows.len() / CompositeMode::ALL.len());
    Ok(verdict.outcome())
}
