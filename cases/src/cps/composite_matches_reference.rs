//! `cps.composite.matches_reference`: the GPU composites (nearest, the original 4-neighbour
//! interpolation, our seam-free one) equal a CPU implementation of the same equations, fed with
//! the composite stage's inputs (the LOD buffer and lit levels, each checked against its own
//! definition by cps.lod_policy and cps.level_lighting), within a bound derived per pixel and
//! channel from the f16 stores on its way and the magnitudes entering it
//! (`fragkit::cps::reference::Composited`). Also records each mode's seam error: how far the
//! colour step between neighbouring pixels of different levels departs from full resolution's
//! (the ranking is checked over the report's sweep by `cps.composite.seam_free_sweep`, the
//! seam-free guarantee by `cps.composite.linear_precision`).

use anyhow::Result;
use fragkit::cps::reference::{CompositeInputs, Level, seam_error};
use fragkit::cps::{CompositeMode, CpsConfig, CpsRenderer, LodPolicy};
use fragkit::deferred::lighting::light_full_resolution;
use fragkit::harness::{Case, Ctx, Outcome, ParamKind, ParamSpec, Sweep, SweepRange, Verdict};
use fragkit::readback::read_texture;
use fragkit::shaders::{CPS_COMPOSITE, CPS_LIGHTING, CPS_LOD, CPS_MASK_REDUCE, CPS_STENCIL_MARK, DEFERRED_LIGHTING, FRAGMENT_STORAGE, FULLSCREEN, GBUFFER, INDIRECT_DRAW, RECT};

use super::{corridor_inputs, frame, random_lod};

pub const CASE: Case = Case {
    name: "cps.composite.matches_reference",
    summary: "the three GPU composites equal their CPU equations within their derived f16 bounds",
    requires: wgpu::Features::empty(),
    params: &[
        ParamSpec { name: "size", kind: ParamKind::Size, default: "64x48", help: "screen size" },
        ParamSpec { name: "lights", kind: ParamKind::CountIn(1, 4096), default: "24", help: "point lights" },
        ParamSpec { name: "max_level", kind: ParamKind::CountIn(0, 8), default: "4", help: "coarsest level" },
    ],
    sweep: &[
        Sweep { param: "size", range: SweepRange::Size { min: (1, 1), max: (200, 150) } },
        Sweep { param: "lights", range: SweepRange::Count(1, 4096) },
        Sweep { param: "max_level", range: SweepRange::Count(0, 8) },
    ],
    budget_s: 1,
    timed_verdict: false,
    shaders: &[RECT, FULLSCREEN, FRAGMENT_STORAGE, INDIRECT_DRAW, GBUFFER, DEFERRED_LIGHTING, CPS_LOD, CPS_MASK_REDUCE, CPS_LIGHTING, CPS_COMPOSITE, CPS_STENCIL_MARK],
    run,
};

fn as_texels(values: &[f32]) -> Vec<[f32; 4]> {
    values.chunks_exact(4).map(|c| [c[0], c[1], c[2], c[3]]).collect()
}

fn run(ctx: &mut Ctx) -> Result<Outcome> {
    let size = ctx.params.size("size")?;
    let max_level = ctx.params.count_u32("max_level")?;
    let inputs = corridor_inputs(ctx.gpu, size, ctx.params.count_u32("lights")?, 2)?;
    let fullres = light_full_resolution(ctx.gpu, &inputs)?;
    let reference = as_texels(&read_texture(ctx.gpu, &fullres, wgpu::TextureAspect::All, 0)?.as_f16());

    let mut verdict = Verdict::new();
    let policies = [
        ("foveated", LodPolicy::Foveated { focus: (0.4, 0.5), inner_radius: 5.0 }),
        ("random", LodPolicy::Explicit(random_lod(size, 9))),
    ];
    for (name, policy) in policies {
        for composite in CompositeMode::ALL {
            let renderer = CpsRenderer::new(ctx.gpu, size, CpsConfig::new(max_level, policy.clone(), composite))?;
            renderer.render(ctx.gpu, &frame(&inputs))?;
            let gpu_image = as_texels(&renderer.read_image(ctx.gpu)?);

            // Expected: the CPU composite of the GPU's own inputs.
            let lod = renderer.read_lod(ctx.gpu)?;
            let lit: Vec<Level> = (0..renderer.plan.levels())
                .map(|l| {
                    Ok(Level {
                        extent: renderer.plan.level_extents[l as usize],
                        texels: as_texels(&renderer.read_lit_level(ctx.gpu, l)?),
                    })
                })
                .collect::<Result<_>>()?;
            let expected = CompositeInputs { screen: size, lod: &lod, lit: &lit }.composite_with_bounds(composite);

            // The worst difference as a fraction of its bound (above 1: out of bounds).
            let worst = gpu_image
                .iter()
                .zip(&expected)
                .flat_map(|(g, e)| (0..3).map(move |i| (g[i] - e.colour[i]).abs() / e.bound[i]))
                .fold(0.0f32, f32::max);
            let wrong = gpu_image.iter().zip(&expected).filter(|(g, e)| !e.within(**g)).count();
            let seam = seam_error(size, &lod, &gpu_image, &reference);
            ctx.metric(&format!("{name}.{}", composite.name()), serde_json::json!({"worst_difference_over_bound": worst, "pixels_out_of_tolerance": wrong, "seam_error": seam}));
            if wrong > 0 {
                verdict.fail(format!(
                    "{name} {}: {wrong} pixels differ from the CPU equations beyond their bounds (worst {worst:.2}x its bound)",
                    composite.name()
                ));
            }
        }
    }
    Ok(verdict.outcome())
}
