//! `cps.lod_policy`: the LOD buffer the GPU writes equals the CPU model of each policy's
//! definition (`fragkit::cps::lod_model`), fed with the scene's inputs: the foveated formula at
//! several foci and radii (a foveated frame computes each level where it needs it, with the
//! function `read_lod` renders the buffer with), and the content rule from the read-back G-buffer
//! at two threshold pairs. Pixels whose level hangs on a comparison closer than f32 can decide are skipped and
//! counted (`ambiguous_pixels`), never guessed.

use anyhow::Result;
use fragkit::cps::lod_model::model;
use fragkit::cps::{CompositeMode, CpsConfig, CpsRenderer, LodPolicy};
use fragkit::deferred::phong::read_surfaces;
use fragkit::harness::{Case, Ctx, Outcome, ParamKind, ParamSpec, Sweep, SweepRange, Verdict};
use fragkit::shaders::{CPS_COMPOSITE, CPS_EDGE_MASK, CPS_LIGHTING, CPS_LOD, CPS_MASK_REDUCE, CPS_STENCIL_MARK, FRAGMENT_STORAGE, FULLSCREEN, GBUFFER, INDIRECT_DRAW, RECT};

use super::{corridor_inputs, frame};

pub const CASE: Case = Case {
    name: "cps.lod_policy",
    summary: "the GPU's LOD buffer equals the CPU model of the foveated and content policies",
    requires: wgpu::Features::empty(),
    params: &[
        ParamSpec { name: "sizes", kind: ParamKind::SizesFrom(1), default: "64x48,131x77,300x6", help: "screen sizes" },
        ParamSpec { name: "radius", kind: ParamKind::CountIn(1, 512), default: "6", help: "foveation radius (pixels)" },
        ParamSpec { name: "max_level", kind: ParamKind::CountIn(0, 8), default: "8", help: "coarsest level" },
        ParamSpec { name: "seed", kind: ParamKind::CountIn(0, 1 << 20), default: "3", help: "scene seed" },
    ],
    sweep: &[
        Sweep { param: "sizes", range: SweepRange::Size { min: (1, 1), max: (300, 200) } },
        Sweep { param: "radius", range: SweepRange::Count(1, 512) },
        Sweep { param: "max_level", range: SweepRange::Count(0, 8) },
        Sweep { param: "seed", range: SweepRange::Count(0, 1 << 20) },
    ],
    budget_s: 2,
    timed_verdict: false,
    shaders: &[RECT, FULLSCREEN, FRAGMENT_STORAGE, INDIRECT_DRAW, GBUFFER, CPS_EDGE_MASK, CPS_LOD, CPS_MASK_REDUCE, CPS_LIGHTING, CPS_COMPOSITE, CPS_STENCIL_MARK],
    run,
};

/// The coarsest level a screen can use: one fragment covering its longer side.
fn top_level(screen: (u32, u32), max_level: u32) -> u32 {
    max_level.min(screen.0.max(screen.1).next_power_of_two().trailing_zeros())
}

fn run(ctx: &mut Ctx) -> Result<Outcome> {
    let radius = ctx.params.count("radius")? as f32;
    let max_level = ctx.params.count_u32("max_level")?;
    let seed = ctx.params.count_u32("seed")?;
    let policies = [
        ("foveated_centre", LodPolicy::Foveated { focus: (0.5, 0.5), inner_radius: radius }),
        ("foveated_corner", LodPolicy::Foveated { focus: (0.1, 0.85), inner_radius: radius * 1.5 }),
        ("content", LodPolicy::content()),
        ("content_strict", LodPolicy::Content { normal_cos: 0.99, depth_ratio: 0.01 }),
    ];
    let mut verdict = Verdict::new();
    for size in ctx.params.sizes("sizes")? {
        let inputs = corridor_inputs(ctx.gpu, size, 1, seed)?;
        let surfaces = read_surfaces(ctx.gpu, &inputs.gbuffer)?;
        let top = top_level(size, max_level);
        for (name, policy) in &policies {
            let renderer =
                CpsRenderer::new(ctx.gpu, size, CpsConfig::new(max_level, policy.clone(), CompositeMode::Nearest))?;
            renderer.render(ctx.gpu, &frame(&inputs))?;
            let measured = renderer.read_lod(ctx.gpu)?;

            // Expected: the policy's definition, evaluated on the CPU.
            let expected = model(policy, size, &surfaces, inputs.eye, top);
            let ambiguous = expected.ambiguous.iter().filter(|&&a| a).count();
            let wrong: Vec<(usize, u8, u8)> = (0..measured.len())
                .filter(|&i| !expected.ambiguous[i] && measured[i] != expected.levels[i])
                .map(|i| (i, measured[i], expected.levels[i]))
                .collect();
            let key = format!("{}x{}.{name}", size.0, size.1);
            let levels_used = (0..=top).filter(|&l| expected.levels.contains(&(l as u8))).count();
            ctx.metric(&key, serde_json::json!({"wrong_pixels": wrong.len(), "ambiguous_pixels": ambiguous, "levels_used": levels_used}));
            if let Some(&(i, got, want)) = wrong.first() {
                let (x, y) = (i as u32 % size.0, i as u32 / size.0);
                verdict.fail(format!(
                    "{key}: {} pixels at the wrong level, first ({x}, {y}): {got}, the policy says {want}",
                    wrong.len()
                ));
            }
        }
    }
    Ok(verdict.outcome())
}
