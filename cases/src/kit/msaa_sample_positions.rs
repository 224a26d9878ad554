//! `kit.msaa.sample_positions.Nx`: where an N-sample target really puts its samples, found by
//! an edge sweep in 1/256-pixel steps, against the standard tables; and what
//! `@builtin(position)` reports under per-sample shading.

use anyhow::{Context, Result};
use fragkit::caps::{common_sample_counts, matches_standard};
use fragkit::harness::{Case, Ctx, Outcome};
use fragkit::probe::occlusion::{OcclusionPrecision, measure_occlusion_precision};
use fragkit::probe::sample_positions::{
    STEPS, SamplePosition, measure_by_occlusion, measure_by_resolve, measure_per_sample_shading,
    standard_positions,
};

macro_rules! sample_positions_case {
    ($const:ident, $samples:literal, $name:literal) => {
        pub const $const: Case = Case {
            name: $name,
            summary: concat!(
                "every sample of a ",
                $samples,
                "x pixel sits at its standard position (edge sweep, 1/256 px)"
            ),
            requires: wgpu::Features::empty(),
            params: &[],
            run: |ctx| sample_positions(ctx, $samples),
        };
    };
}

sample_positions_case!(CASE_1X, 1, "kit.msaa.sample_positions.1x");
sample_positions_case!(CASE_2X, 2, "kit.msaa.sample_positions.2x");
sample_positions_case!(CASE_4X, 4, "kit.msaa.sample_positions.4x");
sample_positions_case!(CASE_8X, 8, "kit.msaa.sample_positions.8x");

/// Names what `@builtin(position)` gave for one sample: its location, the pixel centre, or else.
fn position_builtin_meaning(reported: [f32; 2], sample: &SamplePosition) -> String {
    let step = 1.0 / STEPS as f32;
    let near =
        |a: [f32; 2], b: [f32; 2]| (a[0] - b[0]).abs() <= step && (a[1] - b[1]).abs() <= step;
    match sample.mid() {
        Some(mid) if near(reported, mid) => "sample".into(),
        _ if near(reported, [0.5, 0.5]) => "centre".into(),
        _ => format!("other ({:.4}, {:.4})", reported[0], reported[1]),
    }
}

fn sample_positions(ctx: &mut Ctx, samples: u32) -> Result<Outcome> {
    // Requirements: the adapter must claim the count for colour and depth formats alike.
    let advertised = common_sample_counts(ctx.gpu);
    ctx.metric("advertised_sample_counts", &advertised);
    if !advertised.contains(&samples) {
        return Ok(Outcome::NotSupported(format!(
            "{samples}x multisampling (adapter offers {advertised:?})"
        )));
    }
    let standard = standard_positions(samples).context("no standard table for this count")?;

    // Measure: the sweep read back through per-sample resolves, and through occlusion counts
    // where those are exact, as an independent second route.
    let by_resolve = measure_by_resolve(ctx.gpu, samples)?;
    ctx.metric(
        "positions",
        by_resolve
            .iter()
            .map(SamplePosition::mid)
            .collect::<Vec<_>>(),
    );
    let mut problems = Vec::new();
    if by_resolve.iter().any(|p| p.x.is_none() || p.y.is_none()) {
        problems.push("some samples were never covered: the target rendered nothing there (an unexplained zero)".to_owned());
    }
    let occlusion = measure_occlusion_precision(ctx.gpu)?;
    ctx.metric("occlusion", occlusion);
    if occlusion == OcclusionPrecision::Exact {
        let by_occlusion = measure_by_occlusion(ctx.gpu, samples)?;
        ctx.metric("routes_agree", by_occlusion == by_resolve);
        if by_occlusion != by_resolve {
            let mids: Vec<_> = by_occlusion.iter().map(SamplePosition::mid).collect();
            problems.push(format!(
                "resolve and occlusion routes disagree: occlusion says {mids:?}"
            ));
        }
    }

    // Expect: each sample's measured interval holds its standard position.
    ctx.metric("standard", standard);
    if !matches_standard(samples, &by_resolve) {
        let mids: Vec<_> = by_resolve.iter().map(SamplePosition::mid).collect();
        problems.push(format!(
            "positions {mids:?} differ from the standard {standard:?} by more than 1/{STEPS} px"
        ));
    }

    // Per-sample shading: each sample's invocation must see its own sample_index.
    let shading = measure_per_sample_shading(ctx.gpu, samples)?;
    let meanings: Vec<String> = shading
        .position
        .iter()
        .zip(&by_resolve)
        .map(|(&p, s)| position_builtin_meaning(p, s))
        .collect();
    ctx.metric("position_builtin", &meanings);
    ctx.metric("sample_index", &shading.sample_index);
    let expected_indices: Vec<Option<u32>> = (0..samples).map(Some).collect();
    if shading.sample_index != expected_indices {
        problems.push(format!(
            "per-sample invocations saw sample_index {:?}, expected {expected_indices:?}",
            shading.sample_index
        ));
    }

    Ok(if problems.is_empty() {
        Outcome::Pass
    } else {
        Outcome::Fail(problems.join("; "))
    })
}
