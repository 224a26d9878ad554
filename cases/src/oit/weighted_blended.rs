//! `oit.weighted_blended`: the weighted-blended baseline (`render_weighted`, the renderer's own
//! passes: `shaders/oit/weighted_accumulate.wgsl` and `weighted_composite.wgsl`) on known layers
//! equals a CPU model of McGuire and Bavoil's equations: weight w = clamp(α·max(10⁻², 3·10³·(1−z)³),
//! 10⁻², 3·10³), accumulation Σ w·(α·c, α), revealage Π(1−α), result (Σ wαc / Σ wα)·(1 − Π(1−α)).
//! Seeded full-screen layers (colour, opacity, depth), so every pixel holds the same sums.
//! Bound: each of the n accumulation and revealage stores into `Rgba16Float` loses up to one f16
//! ulp (2^-10 relative; Vulkan lets it truncate), a ratio of two such sums twice that, and the
//! final store one more: (3n + 1)·2^-10 relative to the larger of the average and the result.

use anyhow::Result;
use fragkit::harness::{Case, Ctx, Outcome, ParamKind, ParamSpec, Sweep, SweepRange};
use fragkit::oit::methods::render_weighted;
use fragkit::oit::scene::{Quad, QuadScene};
use fragkit::oit::stochastic::{COLOUR, ResolvedTarget};
use fragkit::query::GpuTimer;
use fragkit::scene::hash::SeededRng;
use fragkit::shaders::{FULLSCREEN, OIT_PLAIN_COVERAGE, OIT_QUAD, OIT_WEIGHTED_ACCUMULATE, OIT_WEIGHTED_COMPOSITE};

pub const CASE: Case = Case {
    name: "oit.weighted_blended",
    summary: "the weighted-blended baseline equals its equations on known layers",
    requires: wgpu::Features::empty(),
    params: &[
        ParamSpec { name: "layers", kind: ParamKind::CountIn(1, 16), default: "4", help: "full-screen layers" },
        ParamSpec { name: "seed", kind: ParamKind::CountIn(0, 1 << 20), default: "6", help: "layer seed" },
    ],
    sweep: &[
        Sweep { param: "layers", range: SweepRange::Count(1, 16) },
        Sweep { param: "seed", range: SweepRange::Count(0, 1 << 20) },
    ],
    budget_s: 1,
    timed_verdict: false,
    shaders: &[FULLSCREEN, OIT_QUAD, OIT_PLAIN_COVERAGE, OIT_WEIGHTED_ACCUMULATE, OIT_WEIGHTED_COMPOSITE],
    run,
};

const SIZE: (u32, u32) = (8, 8);

fn layers(count: u32, seed: u32) -> QuadScene {
    let mut rng = SeededRng::new(seed);
    let mut unit = || rng.unit();
    let quads = (0..count)
        .map(|_| {
            let depth = 0.05 + 0.9 * unit();
            Quad {
                rect: [-1.0, 1.0, 1.0, -1.0],
                depth: (depth, depth),
                alpha: 0.05 + 0.9 * unit(),
                colour: [unit(), unit(), unit()],
                key: 0,
            }
        })
        .collect();
    QuadScene::keyed("weighted known layers", quads)
}

/// The equations, in f64.
fn expected(scene: &QuadScene) -> ([f64; 3], [f64; 3]) {
    let (mut sum, mut weight_sum, mut revealed) = ([0.0f64; 3], 0.0f64, 1.0f64);
    for quad in &scene.quads {
        let (alpha, z) = (f64::from(quad.alpha), f64::from(quad.depth.0));
        let weight = (alpha * (3e3 * (1.0 - z).powi(3)).max(1e-2)).clamp(1e-2, 3e3);
        (0..3).for_each(|c| sum[c] += weight * alpha * f64::from(quad.colour[c]));
        weight_sum += weight * alpha;
        revealed *= 1.0 - alpha;
    }
    let average = sum.map(|s| s / weight_sum.max(1e-5));
    (average.map(|a| a * (1.0 - revealed)), average)
}

fn run(ctx: &mut Ctx) -> Result<Outcome> {
    let count = ctx.params.count_u32("layers")?;
    let scene = layers(count, ctx.params.count_u32("seed")?);

    let target = ResolvedTarget::new(ctx.gpu, SIZE, 1, COLOUR);
    render_weighted(ctx.gpu, &scene, &target, &mut GpuTimer::new(ctx.gpu, 3))?;
    let image = target.read_rgb(ctx.gpu)?;

    let (colour, average) = expected(&scene);
    let bound: [f64; 3] =
        std::array::from_fn(|c| f64::from(3 * count + 1) / 1024.0 * colour[c].max(average[c]).max(1.0 / 1024.0));
    let worst = image
        .iter()
        .flat_map(|p| (0..3).map(move |c| (f64::from(p[c]) - colour[c]).abs() / bound[c]))
        .fold(0.0, f64::max);
    ctx.metric("expected", colour);
    ctx.metric("measured_first_pixel", image[0]);
    ctx.metric("worst_error_in_bounds", worst);
    Ok(if worst <= 1.0 {
        Outcome::Pass
    } else {
        Outcome::Fail(format!(
            "weighted blended {:?} at pixel 0, the equations give {colour:.4?} (worst {worst:.1}x the bound)",
            image[0]
        ))
    })
}
