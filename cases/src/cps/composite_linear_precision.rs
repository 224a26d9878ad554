//! `cps.composite.linear_precision`: the seam-free composite's guarantee, on the GPU. Fed with
//! lit levels holding shading linear in screen position (each texel the function at the pixel
//! its level samples: `fragkit::cps::reference::sampled_levels`), it returns the function at
//! every pixel between the outermost samples whatever the levels, so a level boundary adds no
//! step the shading does not have. The expectation is the function itself; the bound is the f16
//! rounding of the inputs (scaled by the weights' magnitudes) and of the store. Levels: the
//! corridor's content and foveated LODs and a seeded LOD of whole blocks. The original
//! 4-neighbour interpolation gets the same input and its worst departure is recorded: it is exact
//! only between fragments of one size.

use anyhow::Result;
use fragkit::cps::lod_model::nested_random;
use fragkit::cps::reference::{CompositeInputs, sampled_levels};
use fragkit::cps::{CompositeMode, CpsConfig, CpsRenderer, LodPolicy};
use fragkit::harness::{Case, Ctx, Outcome, ParamKind, ParamSpec, Sweep, SweepRange, Verdict};
use fragkit::image_compare::{error_mask, side_by_side};
use fragkit::tonemap::to_display;
use fragkit::shaders::{CPS_COMPOSITE, CPS_EDGE_MASK, CPS_LIGHTING, CPS_LOD, CPS_MASK_REDUCE, CPS_STENCIL_MARK, FRAGMENT_STORAGE, FULLSCREEN, GBUFFER, INDIRECT_DRAW, RECT};

use super::{corridor_inputs, frame};

pub const CASE: Case = Case {
    name: "cps.composite.linear_precision",
    summary: "the seam-free composite reproduces shading linear in screen position at every pixel between samples",
    requires: wgpu::Features::empty(),
    params: &[
        ParamSpec { name: "size", kind: ParamKind::Size, default: "96x64", help: "screen size" },
        ParamSpec { name: "max_level", kind: ParamKind::CountIn(1, 8), default: "4", help: "coarsest level" },
        ParamSpec { name: "seed", kind: ParamKind::CountIn(0, u32::MAX as u64), default: "1", help: "seed of the LOD of whole blocks" },
    ],
    sweep: &[
        Sweep { param: "size", range: SweepRange::Size { min: (1, 1), max: (200, 150) } },
        Sweep { param: "max_level", range: SweepRange::Count(1, 8) },
        Sweep { param: "seed", range: SweepRange::Count(0, 1 << 20) },
    ],
    budget_s: 2,
    timed_verdict: false,
    shaders: &[RECT, FULLSCREEN, FRAGMENT_STORAGE, INDIRECT_DRAW, GBUFFER, CPS_EDGE_MASK, CPS_LOD, CPS_MASK_REDUCE, CPS_LIGHTING, CPS_COMPOSITE, CPS_STENCIL_MARK],
    run,
};

/// f16's spacing on [1, 2), where the shading lies: what one store may move a value there.
const F16_SPACING: f32 = 1.0 / 1024.0;

/// RGB linear in the pixel's position, in [1, 2) on any screen.
fn shading(screen: (u32, u32), p: [i64; 2]) -> [f32; 4] {
    let (x, y) = (p[0] as f32 / screen.0 as f32, p[1] as f32 / screen.1 as f32);
    [1.0 + 0.9 * x, 1.0 + 0.9 * y, 1.0 + 0.45 * (x + y), 1.0]
}

fn run(ctx: &mut Ctx) -> Result<Outcome> {
    let size = ctx.params.size("size")?;
    let max_level = ctx.params.count_u32("max_level")?;
    let seed = ctx.params.count_u32("seed")?;
    let inputs = corridor_inputs(ctx.gpu, size, 16, 2)?;
    let width = i64::from(size.0);
    let pixel_at = |i: usize| [i as i64 % width, i as i64 / width];

    let policies = [
        ("content", LodPolicy::content()),
        ("foveated", LodPolicy::Foveated { focus: (0.4, 0.5), inner_radius: 5.0 }),
        ("whole_blocks", LodPolicy::Explicit(nested_random(size, max_level, seed))),
    ];
    let mut verdict = Verdict::new();
    for (name, policy) in policies {
        for composite in [CompositeMode::SeamFree, CompositeMode::FourNeighbour] {
            // Setup and render: the policy's LOD, then the composite of linear shading over it.
            let renderer = CpsRenderer::new(ctx.gpu, size, CpsConfig::new(max_level, policy.clone(), composite))?;
            renderer.render(ctx.gpu, &frame(&inputs))?;
            let levels = sampled_levels(size, renderer.plan.top_level, |p| shading(size, p));
            renderer.composite_levels(ctx.gpu, &levels)?;
            let image = renderer.read_image(ctx.gpu)?;

            // Expected: the shading itself at each pixel.
            let departures: Vec<f32> = image
                .chunks_exact(4)
                .enumerate()
                .map(|(i, got)| {
                    let want = shading(size, pixel_at(i));
                    (0..3).map(|c| (got[c] - want[c]).abs()).fold(0.0, f32::max)
                })
                .collect();
            let label = format!("{name}.{}", composite.name());
            if composite == CompositeMode::FourNeighbour {
                ctx.metric(&format!("{label}.worst_departure"), departures.iter().copied().fold(0.0, f32::max));
                continue;
            }

            // Compare where the guarantee holds: P between samples (no flat corner), within the
            // inputs' f16 rounding times the weights' magnitudes plus the store's.
            let lod = renderer.read_lod(ctx.gpu)?;
            let model = CompositeInputs { screen: size, lod: &lod, lit: &levels };
            let mut beyond_samples = 0;
            let mut worst = 0.0f32;
            let wrong: Vec<bool> = departures
                .iter()
                .enumerate()
                .map(|(i, &departure)| match model.seam_free_triangle(pixel_at(i)) {
                    Some(triangle) if !triangle.has_flat_corner() => {
                        let (beta, delta) = triangle.weights();
                        let weights = (1.0 - beta - delta).abs() + beta.abs() + delta.abs();
                        worst = worst.max(departure);
                        departure > (weights + 1.0) * F16_SPACING
                    }
                    _ => {
                        beyond_samples += 1;
                        false
                    }
                })
                .collect();
            let wrong_count = wrong.iter().filter(|&&w| w).count();
            ctx.metric(
                &label,
                serde_json::json!({"worst_departure_between_samples": worst, "pixels_beyond_samples": beyond_samples, "pixels_out_of_bound": wrong_count}),
            );
            if wrong_count > 0 {
                let expected: Vec<f32> = (0..departures.len()).flat_map(|i| shading(size, pixel_at(i))).collect();
                let expected = to_display(size.0, size.1, &expected)?;
                let result = to_display(size.0, size.1, &image)?;
                ctx.evidence_image(&label, &side_by_side(&result, &expected, &error_mask(&expected, &wrong)))?;
                verdict.fail(format!(
                    "{name}: {wrong_count} pixels between samples depart from the linear shading beyond their bound (worst {worst:.5})"
                ));
            }
        }
    }
    Ok(verdict.outcome())
}
