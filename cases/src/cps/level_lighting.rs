//! `cps.level_lighting`: every level shades exactly as many texels as the LOD input needs, and
//! every texel a level shades holds the CPU Phong (`fragkit::deferred::phong`) of the G-buffer
//! sample at the centre pixel of its 2^l block (clamped to the screen), under the scene's own
//! lights, within the derived f32/f16 bound; and, where the plan skips absent levels
//! on the GPU, each level's indirect draw has zero instances exactly where the LOD input holds no
//! pixel of that level (elsewhere every level is drawn directly, once). The LOD is a seeded input
//! (random per pixel, and one with whole levels absent), so the expectation owes nothing to the
//! GPU's LOD pass.

use anyhow::Result;
use fragkit::cps::reference::expected_shaded_texels;
use fragkit::cps::{CompositeMode, CpsConfig, CpsRenderer, LodPolicy};
use fragkit::deferred::DeferredInputs;
use fragkit::deferred::phong::{read_surfaces, shade};
use fragkit::harness::{Case, Ctx, Outcome, ParamKind, ParamSpec, Sweep, SweepRange, Verdict};
use fragkit::scene::corridor::corridor;
use fragkit::shaders::{CPS_COMPOSITE, CPS_LIGHTING, CPS_LOD, CPS_MASK_REDUCE, CPS_STENCIL_MARK, FRAGMENT_STORAGE, FULLSCREEN, GBUFFER, INDIRECT_DRAW, RECT};

use super::{frame, random_lod};

pub const CASE: Case = Case {
    name: "cps.level_lighting",
    summary: "each lit coarse texel is the CPU Phong of its block's centre pixel; absent levels draw nothing",
    requires: wgpu::Features::empty(),
    params: &[
        ParamSpec { name: "sizes", kind: ParamKind::SizesFrom(1), default: "1x1,61x37", help: "screen sizes" },
        ParamSpec { name: "lights", kind: ParamKind::CountIn(1, 4096), default: "32", help: "point lights" },
        ParamSpec { name: "seed", kind: ParamKind::CountIn(0, 1 << 20), default: "5", help: "scene and LOD seed" },
    ],
    sweep: &[
        Sweep { param: "sizes", range: SweepRange::Size { min: (1, 1), max: (160, 120) } },
        Sweep { param: "lights", range: SweepRange::Count(1, 1024) },
        Sweep { param: "seed", range: SweepRange::Count(0, 1 << 20) },
    ],
    budget_s: 1,
    timed_verdict: false,
    shaders: &[RECT, FULLSCREEN, FRAGMENT_STORAGE, INDIRECT_DRAW, GBUFFER, CPS_LOD, CPS_MASK_REDUCE, CPS_LIGHTING, CPS_COMPOSITE, CPS_STENCIL_MARK],
    run,
};

fn run(ctx: &mut Ctx) -> Result<Outcome> {
    let seed = ctx.params.count_u32("seed")?;
    let scene = corridor(seed, ctx.params.count_u32("lights")?);
    let mut verdict = Verdict::new();
    for size in ctx.params.sizes("sizes")? {
        let inputs = DeferredInputs::new(ctx.gpu, &scene, size)?;
        let surfaces = read_surfaces(ctx.gpu, &inputs.gbuffer)?;
        // Random levels everywhere, and levels 1 and 3 only (0, 2 and 4.. absent).
        let sparse: Vec<u8> = random_lod(size, seed + 1).iter().map(|l| if l % 2 == 0 { 1 } else { 3 }).collect();
        for (name, lod) in [("random", random_lod(size, seed)), ("levels_1_3", sparse)] {
            let renderer = CpsRenderer::new(
                ctx.gpu,
                size,
                CpsConfig::new(8, LodPolicy::Explicit(lod.clone()), CompositeMode::Nearest),
            )?;
            renderer.render(ctx.gpu, &frame(&inputs))?;
            let top = renderer.plan.top_level;
            let key = format!("{}x{}.{name}", size.0, size.1);

            // Each shaded texel against the Phong of its block's centre pixel; and, per level, as
            // many shaded texels as the LOD input needs (a fresh renderer's atlas holds no older
            // shading), so that a frame whose draws shaded nothing cannot pass on no evidence.
            let needed = expected_shaded_texels(size, &lod, top);
            let (mut checked, mut wrong, mut worst) = (0usize, 0usize, 0.0f64);
            for level in 0..=top {
                let (w, _) = renderer.plan.level_extents[level as usize];
                let lit = renderer.read_lit_level(ctx.gpu, level)?;
                let shaded = lit.chunks_exact(4).filter(|t| t[3] == 1.0).count() as u64;
                if shaded != needed[level as usize] {
                    verdict.fail(format!(
                        "{key}: level {level} shaded {shaded} texels, the LOD input needs {}",
                        needed[level as usize]
                    ));
                }
                let block = 1u32 << level;
                for (i, texel) in lit.chunks_exact(4).enumerate().filter(|(_, t)| t[3] == 1.0) {
                    let (qx, qy) = (i as u32 % w, i as u32 / w);
                    let (x, y) = ((qx * block + block / 2).min(size.0 - 1), (qy * block + block / 2).min(size.1 - 1));
                    let expected = shade(&surfaces[(y * size.0 + x) as usize], scene.camera.eye, &scene.lights);
                    checked += 1;
                    worst = worst.max(expected.error_in_bounds(texel));
                    wrong += usize::from(!expected.admits(texel));
                }
            }
            ctx.metric(
                &format!("{key}.texels"),
                serde_json::json!({"checked": checked, "beyond_bound": wrong, "worst_error_in_bounds": worst}),
            );
            if wrong > 0 {
                verdict.fail(format!("{key}: {wrong} of {checked} lit texels differ from the Phong of their block's centre pixel (worst {worst:.1}x the bound)"));
            }

            // Where the GPU counts the levels, their draw arguments whole (the kit opens its
            // device without wgpu's indirect validation): one full-screen triangle, one instance,
            // zero instances exactly for the levels the input leaves absent. Elsewhere each level
            // is drawn directly, once.
            if let Some(draws) = renderer.read_level_draws(ctx.gpu)? {
                let expected_draws: Vec<[u32; 4]> =
                    needed.iter().map(|&texels| [3, u32::from(texels > 0), 0, 0]).collect();
                let instances: Vec<u32> = draws.iter().map(|d| d[1]).collect();
                ctx.metric(&format!("{key}.instances"), serde_json::json!({"measured": instances, "expected": expected_draws.iter().map(|d| d[1]).collect::<Vec<_>>(), "skips_absent_levels": true}));
                if draws != expected_draws {
                    verdict.fail(format!("{key}: level draw arguments {draws:?}, expected {expected_draws:?}"));
                }
            } else {
                ctx.metric(&format!("{key}.level_draws"), "direct (no counted indirect draws here: kit.draw.indirect)");
            }
        }
    }
    Ok(verdict.outcome())
}
