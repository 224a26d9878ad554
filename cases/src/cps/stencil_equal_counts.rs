//! `cps.stencil_equal.counts`: every level's stencil marks exactly the coarse texels some pixel of
//! that level falls in, checked texel by texel through what the level's lighting wrote (and the
//! stencil itself where the adapter copies stencil), and the occlusion query around each level's
//! stencil-Equal lighting draw counts exactly those texels. For the foveated and content policies,
//! a seeded random LOD per pixel and all pixels at level 8 (past the screen), on 1×1, odd and
//! even sizes.

use anyhow::Result;
use fragkit::cps::reference::{expected_shaded_texels, needed_texels};
use fragkit::cps::{CompositeMode, CpsConfig, CpsRenderer, LodPolicy, MAX_LEVEL};
use fragkit::harness::{Case, Ctx, Outcome, ParamKind, ParamSpec, Sweep, SweepRange};
use fragkit::probe::occlusion::{OcclusionPrecision, measure_occlusion_precision};

use super::{corridor_inputs, frame, random_lod};

pub const CASE: Case = Case {
    name: "cps.stencil_equal.counts",
    summary: "each level's stencil and occlusion count hold exactly the coarse texels its pixels need",
    requires: wgpu::Features::empty(),
    params: &[
        ParamSpec { name: "sizes", kind: ParamKind::Sizes, default: "1x1,64x48,257x131", help: "screen sizes" },
        ParamSpec { name: "seed", kind: ParamKind::Count, default: "3", help: "scene and random-LOD seed" },
    ],
    sweep: &[
        Sweep { param: "sizes", range: SweepRange::Size { min: (1, 1), max: (300, 200) } },
        Sweep { param: "seed", range: SweepRange::Count(0, 1 << 20) },
    ],
    run,
};

fn policies(size: (u32, u32), seed: u32) -> Vec<(&'static str, LodPolicy)> {
    vec![
        ("foveated", LodPolicy::Foveated { focus: (0.3, 0.6), inner_radius: 6.0 }),
        ("content", LodPolicy::content()),
        ("random", LodPolicy::Explicit(random_lod(size, seed))),
        ("all_level_8", LodPolicy::Explicit(vec![MAX_LEVEL as u8; (size.0 * size.1) as usize])),
    ]
}

fn run(ctx: &mut Ctx) -> Result<Outcome> {
    let seed = ctx.params.count("seed")? as u32;
    let precision = measure_occlusion_precision(ctx.gpu)?;
    let stencil_copies = ctx
        .gpu
        .adapter
        .get_downlevel_capabilities()
        .flags
        .contains(wgpu::DownlevelFlags::DEPTH_TEXTURE_AND_BUFFER_COPIES);
    ctx.metric("stencil_read_back", stencil_copies);
    let mut problems = Vec::new();
    for size in ctx.params.sizes("sizes")? {
        let inputs = corridor_inputs(ctx.gpu, size, 2, seed)?;
        for (name, policy) in policies(size, seed) {
            let config = CpsConfig::new(MAX_LEVEL, policy, CompositeMode::Nearest);
            let renderer = CpsRenderer::new(ctx.gpu, size, config)?;
            let output = renderer.render(ctx.gpu, &frame(&inputs))?;

            // Expected, from the LOD buffer the GPU used: texels whose block holds a pixel of the level.
            let lod = renderer.read_lod(ctx.gpu)?;
            let top = renderer.plan.top_level;
            let expected = expected_shaded_texels(size, &lod, top);
            let key = format!("{}x{}.{name}", size.0, size.1);
            ctx.metric(
                &key,
                serde_json::json!({"top_level": top, "expected": expected, "measured": output.shaded_texels}),
            );

            // Route 1: the texels each level's lighting wrote (alpha 1), read back texel by texel;
            // route 2, where depth/stencil copies exist: each stencil level itself.
            for level in 0..=top {
                let needed = needed_texels(size, &lod, top, level);
                let lit = renderer.read_lit_level(ctx.gpu, level)?;
                let wrong = lit.chunks_exact(4).zip(&needed).filter(|&(t, &n)| (t[3] == 1.0) != n).count();
                if wrong > 0 {
                    problems
                        .push(format!("{key}: level {level} lit {wrong} texels it should not have, or missed them"));
                }
                if stencil_copies {
                    let stencil = renderer.read_stencil_level(ctx.gpu, level)?;
                    let wrong = stencil.iter().zip(&needed).filter(|&(&s, &n)| (s != 0) != n).count();
                    if wrong > 0 {
                        problems.push(format!("{key}: level {level} stencil wrong at {wrong} texels"));
                    }
                }
            }
            // Route 2: the occlusion counts of the stencil-Equal lighting draws.
            let counts_agree = match precision {
                OcclusionPrecision::Exact => output.shaded_texels == expected,
                _ => output.shaded_texels.iter().zip(&expected).all(|(&m, &e)| (m > 0) == (e > 0)),
            };
            if !counts_agree {
                problems.push(format!("{key}: occlusion counts {:?}, expected {expected:?}", output.shaded_texels));
            }
        }
    }
    Ok(if !problems.is_empty() {
        Outcome::Fail(problems.join("; "))
    } else if precision != OcclusionPrecision::Exact {
        Outcome::NotSupported(format!(
            "exact occlusion counts ({precision:?}); the per-texel read-back matched exactly"
        ))
    } else {
        Outcome::Pass
    })
}
