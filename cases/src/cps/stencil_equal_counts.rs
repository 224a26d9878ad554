//! `cps.stencil_equal.counts`: every level's stencil marks exactly the coarse texels some pixel of
//! that level falls in, checked texel by texel through what the level's lighting wrote (and the
//! stencil itself where the adapter copies stencil), and the occlusion query around each level's
//! stencil-Equal lighting draw counts exactly those texels. For the foveated policy (inner radii
//! either side of one pixel, where the marks switch from the geometry to the mask pyramid), the
//! content policy,
//! a seeded random LOD per pixel and all pixels at level 8 (past the screen), on 1×1, odd and
//! even sizes. The levels come from the policies' CPU models (`cps::lod_model`), not the GPU's LOD
//! buffer; a texel whose block holds a pixel the model calls ambiguous may go either way and is
//! left out of the texel comparison (and widens the count's range by one), counted in the metric.

use anyhow::Result;
use fragkit::cps::lod_model::model;
use fragkit::cps::reference::{blocks_holding, needed_texels};
use fragkit::cps::{CompositeMode, CpsConfig, CpsRenderer, LodPolicy, MAX_LEVEL};
use fragkit::deferred::phong::read_surfaces;
use fragkit::harness::{Case, Ctx, Outcome, ParamKind, ParamSpec, Sweep, SweepRange, Verdict};
use fragkit::probe::occlusion::{OcclusionPrecision, measure_occlusion_precision};
use fragkit::shaders::{CPS_COMPOSITE, CPS_EDGE_MASK, CPS_LIGHTING, CPS_LOD, CPS_MASK_REDUCE, CPS_STENCIL_MARK, FRAGMENT_STORAGE, FULLSCREEN, GBUFFER, INDIRECT_DRAW, RECT};

use super::{corridor_inputs, frame, random_lod};

pub const CASE: Case = Case {
    name: "cps.stencil_equal.counts",
    summary: "each level's stencil and occlusion count hold exactly the coarse texels its pixels need",
    requires: wgpu::Features::empty(),
    params: &[
        ParamSpec { name: "sizes", kind: ParamKind::Sizes, default: "1x1,64x48,257x131", help: "screen sizes" },
        ParamSpec { name: "seed", kind: ParamKind::CountIn(0, u32::MAX as u64), default: "3", help: "scene and random-LOD seed" },
    ],
    sweep: &[
        Sweep { param: "sizes", range: SweepRange::Size { min: (1, 1), max: (300, 200) } },
        Sweep { param: "seed", range: SweepRange::Count(0, 1 << 20) },
    ],
    budget_s: 3,
    timed_verdict: false,
    shaders: &[RECT, FULLSCREEN, FRAGMENT_STORAGE, INDIRECT_DRAW, GBUFFER, CPS_EDGE_MASK, CPS_LOD, CPS_MASK_REDUCE, CPS_LIGHTING, CPS_COMPOSITE, CPS_STENCIL_MARK],
    run,
};

fn policies(size: (u32, u32), seed: u32) -> Vec<(&'static str, LodPolicy)> {
    vec![
        ("foveated", LodPolicy::Foveated { focus: (0.3, 0.6), inner_radius: 6.0 }),
        // The narrowest rings the marks compute from the geometry, and narrower ones, which go
        // through the mask pyramid (`Plan::levels_from_foveation`): at 0.3 px no pixel of 64x48
        // lies in level 1's ring around a focus on a pixel centre, though the block around it
        // holds levels 0 and 2.
        ("foveated_r1", LodPolicy::Foveated { focus: (32.5 / 64.0, 24.5 / 48.0), inner_radius: 1.0 }),
        ("foveated_r0.3", LodPolicy::Foveated { focus: (32.5 / 64.0, 24.5 / 48.0), inner_radius: 0.3 }),
        ("content", LodPolicy::content()),
        ("random", LodPolicy::Explicit(random_lod(size, seed))),
        ("all_level_8", LodPolicy::Explicit(vec![MAX_LEVEL as u8; (size.0 * size.1) as usize])),
    ]
}

fn run(ctx: &mut Ctx) -> Result<Outcome> {
    let seed = ctx.params.count_u32("seed")?;
    let precision = measure_occlusion_precision(ctx.gpu)?;
    let stencil_copies = ctx
        .gpu
        .adapter
        .get_downlevel_capabilities()
        .flags
        .contains(wgpu::DownlevelFlags::DEPTH_TEXTURE_AND_BUFFER_COPIES);
    ctx.metric("stencil_read_back", stencil_copies);
    let mut verdict = Verdict::new();
    for size in ctx.params.sizes("sizes")? {
        let inputs = corridor_inputs(ctx.gpu, size, 2, seed)?;
        let surfaces = read_surfaces(ctx.gpu, &inputs.gbuffer)?;
        for (name, policy) in policies(size, seed) {
            let config = CpsConfig::new(MAX_LEVEL, policy.clone(), CompositeMode::Nearest);
            let renderer = CpsRenderer::new(ctx.gpu, size, config)?;
            let output = renderer.render(ctx.gpu, &frame(&inputs))?;

            // Expected, from the policy's model: texels whose block holds a pixel of the level;
            // texels beside an ambiguous pixel may go either way.
            let top = renderer.plan.top_level;
            let modelled = model(&policy, size, &surfaces, inputs.eye, top);
            let key = format!("{}x{}.{name}", size.0, size.1);
            let mut expected = Vec::new();
            let mut undecided = Vec::new();

            // Route 1: the texels each level's lighting wrote (alpha 1), read back texel by texel;
            // route 2, where depth/stencil copies exist: each stencil level itself.
            for level in 0..=top {
                let needed = needed_texels(size, &modelled.levels, top, level);
                let uncertain = blocks_holding(size, &modelled.ambiguous, level);
                let sure = |i: usize| !uncertain[i];
                expected.push(needed.iter().enumerate().filter(|&(i, &n)| n && sure(i)).count() as u64);
                undecided.push(uncertain.iter().filter(|&&u| u).count() as u64);
                let lit = renderer.read_lit_level(ctx.gpu, level)?;
                let wrong = lit
                    .chunks_exact(4)
                    .zip(&needed)
                    .enumerate()
                    .filter(|&(i, (t, &n))| sure(i) && (t[3] == 1.0) != n)
                    .count();
                if wrong > 0 {
                    verdict
                        .fail(format!("{key}: level {level} lit {wrong} texels it should not have, or missed them"));
                }
                if stencil_copies {
                    let stencil = renderer.read_stencil_level(ctx.gpu, level)?;
                    let wrong = stencil
                        .iter()
                        .zip(&needed)
                        .enumerate()
                        .filter(|&(i, (&s, &n))| sure(i) && (s != 0) != n)
                        .count();
                    if wrong > 0 {
                        verdict.fail(format!("{key}: level {level} stencil wrong at {wrong} texels"));
                    }
                }
            }
            ctx.metric(
                &key,
                serde_json::json!({"top_level": top, "expected": expected, "undecided": undecided, "measured": output.shaded_texels}),
            );
            // Route 2: the occlusion counts of the stencil-Equal lighting draws, within the
            // undecided texels of each level.
            let in_range = |m: u64, e: u64, u: u64| (e..=e + u).contains(&m);
            let counts_agree = output.shaded_texels.len() == expected.len()
                && (0..expected.len()).all(|l| {
                    let (m, e, u) = (output.shaded_texels[l], expected[l], undecided[l]);
                    match precision {
                        OcclusionPrecision::Exact => in_range(m, e, u),
                        _ => precision.allows(m, e) || u > 0,
                    }
                });
            if !counts_agree {
                verdict.fail(format!(
                    "{key}: occlusion counts {:?}, expected {expected:?} (plus up to {undecided:?} undecided)",
                    output.shaded_texels
                ));
            }
        }
    }
    Ok(if !verdict.is_clean() {
        verdict.outcome()
    } else if precision != OcclusionPrecision::Exact {
        Outcome::NotSupported(format!(
            "exact occlusion counts ({precision:?}); the per-texel read-back matched exactly"
        ))
    } else {
        Outcome::Pass
    })
}
