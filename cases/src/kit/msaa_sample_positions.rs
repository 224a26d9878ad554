//! `kit.msaa.sample_positions.Nx`: where an N-sample target really puts its samples, found by
//! an edge sweep in 1/256-pixel steps, against the standard tables give or take what 4-bit vertex
//! snapping (the coarsest Vulkan and GL allow) may move the swept edge; and what
//! `@builtin(position)` reports under per-sample shading.

use anyhow::{Context, Result};
use fragkit::caps::{common_sample_counts, matches_standard};
use fragkit::harness::capability::missing_capability;
use fragkit::harness::{Case, Ctx, Outcome, Verdict};
use fragkit::probe::multisample_render::render_problem;
use fragkit::probe::sample_positions::{
    Route, STEPS, SamplePosition, measure, measure_per_sample_shading, standard_positions,
};
use fragkit::probe::sample_projections::measure_projections;
use fragkit::probe::subpixel_precision::COARSEST_SNAP;
use fragkit::shaders::{FRAGMENT_STORAGE, FULLSCREEN, RECT, SAMPLE_COVERAGE_RECORD, SAMPLE_POSITION};

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
            sweep: &[],
            budget_s: 1,
            timed_verdict: false,
            shaders: &[RECT, FULLSCREEN, SAMPLE_POSITION, SAMPLE_COVERAGE_RECORD, FRAGMENT_STORAGE],
            run: |ctx| sample_positions(ctx, $samples),
        };
    };
}

sample_positions_case!(CASE_1X, 1, "kit.msaa.sample_positions.1x");
sample_positions_case!(CASE_2X, 2, "kit.msaa.sample_positions.2x");
sample_positions_case!(CASE_4X, 4, "kit.msaa.sample_positions.4x");
sample_positions_case!(CASE_8X, 8, "kit.msaa.sample_positions.8x");

/// Names what `@builtin(position)` gave for one sample: its location, the pixel centre, or else.
/// The builtin is not snapped, so where the sweep found the standard table it must give the
/// standard position itself (within the sweep's 1/256 px); elsewhere, the sample as far as the
/// snapped sweep locates it.
fn position_builtin_meaning(reported: [f32; 2], sample: &SamplePosition, standard: Option<[f32; 2]>) -> String {
    let step = 1.0 / STEPS as f32;
    let near = |a: [f32; 2], b: [f32; 2]| (a[0] - b[0]).abs() <= step && (a[1] - b[1]).abs() <= step;
    let at_sample = match (standard, sample.x, sample.y) {
        (Some(position), _, _) => near(reported, position),
        (None, Some(x), Some(y)) => x.within(COARSEST_SNAP, reported[0]) && y.within(COARSEST_SNAP, reported[1]),
        _ => false,
    };
    match () {
        _ if at_sample => "sample".into(),
        _ if near(reported, [0.5, 0.5]) => "centre".into(),
        _ => format!("other ({:.4}, {:.4})", reported[0], reported[1]),
    }
}

/// Where no route reads single samples (GLES: no sample mask, no fragment storage or per-sample
/// shading), what an unmasked sweep still shows: how many samples the target renders and each
/// axis's sorted coordinates, against the standard table's. Which sample sits where stays
/// unmeasured, and the metrics say so.
fn projections_only(ctx: &mut Ctx, samples: u32, skipped: &[(Route, String)]) -> Result<Outcome> {
    let why: Vec<String> = skipped.iter().map(|(route, why)| format!("{route:?}: {why}")).collect();
    ctx.metric("positions_from", format!("projections only: no route reads single samples ({})", why.join("; ")));
    let projections = measure_projections(ctx.gpu, samples)?;
    ctx.metric("projections", &projections);
    Ok(match () {
        _ if projections.rendered_samples != samples => Outcome::Fail(format!(
            "{samples}x: an unmasked edge sweep shows the target renders {} samples",
            projections.rendered_samples
        )),
        _ if !projections.matches_standard(samples) => Outcome::Fail(format!(
            "{samples}x: each axis's sample coordinates (x {:?}, y {:?}) differ from the standard table's by more than 4-bit snapping allows",
            projections.x, projections.y
        )),
        _ => Outcome::Pass,
    })
}

fn sample_positions(ctx: &mut Ctx, samples: u32) -> Result<Outcome> {
    // Requirements: the adapter must claim the count for colour and depth formats alike.
    let advertised = common_sample_counts(ctx.gpu);
    ctx.metric("advertised_sample_counts", &advertised);
    if !advertised.contains(&samples) {
        return Ok(Outcome::NotSupported(format!("{samples}x multisampling (adapter offers {advertised:?})")));
    }
    if samples > 1
        && let Some(problem) = render_problem(ctx.gpu, samples)? {
            return Ok(Outcome::Fail(problem));
        }
    let standard = standard_positions(samples).context("no standard table for this count")?;

    // Measure: the sweep through every independent route this adapter allows.
    let measurement = measure(ctx.gpu, samples)?;
    ctx.metric("sample_mask_honoured", measurement.sample_mask_honoured);
    ctx.metric("skipped_routes", &measurement.skipped);
    let mut verdict = Verdict::new();
    for (route, result) in &measurement.routes {
        match result {
            Ok(positions) => {
                let mids: Vec<_> = positions.iter().map(SamplePosition::mid).collect();
                ctx.metric(&format!("positions.{route:?}").to_lowercase(), &mids);
                if positions.iter().any(|p| p.x.is_none() || p.y.is_none()) {
                    verdict.fail(format!("{route:?} route: some samples were never covered (an unexplained zero)"));
                }
            }
            Err(error) => verdict.fail(format!("{route:?} route failed: {error}")),
        }
    }
    let Some(positions) = measurement.agreed().cloned() else {
        if measurement.routes.is_empty() {
            return projections_only(ctx, samples, &measurement.skipped);
        }
        if measurement.routes.iter().filter(|(_, r)| r.is_ok()).count() > 1 {
            verdict.fail("the routes disagree on the positions");
        }
        return Ok(verdict.outcome());
    };
    ctx.metric("positions", positions.iter().map(SamplePosition::mid).collect::<Vec<_>>());

    // Expect: each sample's standard position within one 4-bit grid step of where the swept
    // edge crossed it (the adapter's own precision is reported, not relied on).
    ctx.metric("standard", standard);
    if !matches_standard(samples, &positions) {
        let mids: Vec<_> = positions.iter().map(SamplePosition::mid).collect();
        verdict.fail(format!(
            "positions {mids:?} differ from the standard {standard:?} by more than 4-bit snapping allows (1/16 px + 1/{STEPS} px)"
        ));
    }

    // Per-sample shading: one invocation per sample, each seeing its own sample_index — where
    // the adapter has it at all (a downlevel GL 3.3 has no sample_index; the positions stand).
    let shading = match measure_per_sample_shading(ctx.gpu, samples) {
        Ok(shading) => shading,
        Err(error) => match missing_capability(&format!("{error:#}")) {
            Some(capability) => {
                ctx.metric("per_sample_shading", format!("not offered: {capability}"));
                return Ok(verdict.outcome());
            }
            None => return Err(error),
        },
    };
    let expected_indices: Vec<u32> = (0..samples).collect();
    ctx.metric("invocations", shading.invocations);
    ctx.metric("sample_index", &shading.sample_index);
    if shading.sample_index == expected_indices {
        let standard_found = matches_standard(samples, &positions);
        let meanings: Vec<String> = shading
            .position
            .iter()
            .zip(&positions)
            .zip(standard)
            .map(|((&p, s), &table)| position_builtin_meaning(p, s, standard_found.then_some(table)))
            .collect();
        ctx.metric("position_builtin", &meanings);
        // The sample's own position (Vulkan, Metal) or the pixel centre (D3D) are both fine; any
        // other point is not where this fragment was shaded.
        if meanings.iter().any(|m| m.starts_with("other")) {
            verdict.fail(format!("under per-sample shading @builtin(position) reported {meanings:?}"));
        }
    } else {
        verdict.fail(format!(
            "per-sample shading ran {} invocations with sample_index {:?}, expected {expected_indices:?}",
            shading.invocations, shading.sample_index
        ));
    }

    Ok(verdict.outcome())
}
