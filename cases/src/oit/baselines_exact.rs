//! `oit.baselines.exact`: the two exact baselines every OIT method is measured against — depth
//! peeling (`render_depth_peeling`: `shaders/oit/peel.wgsl` and `under.wgsl`) and sorted blending
//! (`render_sorted_blend`: `shaders/oit/sorted_blend.wgsl`) — equal the CPU's exact composite
//! (`oit::reference::exact_image`: per pixel, the covering quads sorted by depth then key,
//! blended front to back) on seeded overlapping quads. Quad edges lie on pixel boundaries, so
//! coverage is the same whatever the rasteriser's sub-pixel precision. Two scenes: distinct depths
//! (both methods) and pairs at equal depths (depth peeling only: sorting cannot order them; ties go
//! by key). Bound per pixel: each covering layer costs at most two stores into `Rgba16Float` (the
//! peeled layer and the blend), each within one f16 ulp of a value at most 1 (2^-10; Vulkan lets
//! it truncate), and the last blend one more: (2n + 1)·2^-10 for n covering quads. Depth peeling
//! also peels exactly as many layers as the most quads any pixel holds. A third scene adds a
//! half-transparent slab tilted in depth through the others (depth peeling only), leaving out
//! the pixels where its depth and another quad's are closer than the rasteriser's snapping of
//! the slab's plane (1/16 px, Vulkan's coarsest sub-pixel grid, times its slope).

use anyhow::Result;
use fragkit::harness::{Case, Ctx, Outcome, ParamKind, ParamSpec, Sweep, SweepRange, Verdict};
use fragkit::image_compare::{error_mask, side_by_side};
use fragkit::oit::methods::sortable;
use fragkit::oit::reference::exact_image;
use fragkit::oit::run::{Accumulation, Method, run_method};
use fragkit::oit::scene::{Quad, QuadScene};
use fragkit::scene::hash::SeededRng;
use fragkit::tonemap::ldr_to_display;
use fragkit::shaders::{FULLSCREEN, OIT_PEEL, OIT_PLAIN_COVERAGE, OIT_QUAD, OIT_SORTED_BLEND, OIT_UNDER};

pub const CASE: Case = Case {
    name: "oit.baselines.exact",
    summary: "depth peeling and sorted blending equal the CPU's exact composite within f16 rounding",
    requires: wgpu::Features::empty(),
    params: &[
        ParamSpec { name: "size", kind: ParamKind::SizeFrom(1), default: "64x48", help: "target size" },
        ParamSpec { name: "layers", kind: ParamKind::CountIn(1, 24), default: "10", help: "transparent quads" },
        ParamSpec { name: "seed", kind: ParamKind::CountIn(0, 1 << 20), default: "4", help: "quad seed" },
    ],
    sweep: &[
        Sweep { param: "size", range: SweepRange::Size { min: (1, 1), max: (128, 128) } },
        Sweep { param: "layers", range: SweepRange::Count(1, 24) },
        Sweep { param: "seed", range: SweepRange::Count(0, 1 << 20) },
    ],
    budget_s: 1,
    timed_verdict: false,
    shaders: &[FULLSCREEN, OIT_QUAD, OIT_PLAIN_COVERAGE, OIT_SORTED_BLEND, OIT_PEEL, OIT_UNDER],
    run,
};

/// A quad's rect in whole pixels: x0, y0 (top), x1, y1 (exclusive).
type PixelRect = [u32; 4];

fn covers([x0, y0, x1, y1]: &PixelRect, x: u32, y: u32) -> bool {
    (*x0..*x1).contains(&x) && (*y0..*y1).contains(&y)
}

/// The opaque background, then `layers` seeded quads over whole pixels: opacities from nearly
/// transparent to nearly opaque; with `ties`, every second quad at the depth of the one before.
fn scene(size: (u32, u32), layers: u32, seed: u32, ties: bool) -> (QuadScene, Vec<PixelRect>) {
    let mut rng = SeededRng::new(seed);
    let (w, h) = size;
    let mut pixel_rects = vec![[0, 0, w, h]];
    let mut quads =
        vec![Quad { rect: [-1.0, 1.0, 1.0, -1.0], depth: (0.999, 0.999), alpha: 1.0, colour: [0.5; 3], key: 0 }];
    let mut depth = 0.5;
    let span = |extent: u32, rng: &mut SeededRng| {
        let a = (rng.unit() * extent as f32) as u32 % extent;
        let b = (rng.unit() * extent as f32) as u32 % extent;
        (a.min(b), a.max(b) + 1)
    };
    for i in 0..layers {
        let (x0, x1) = span(w, &mut rng);
        let (y0, y1) = span(h, &mut rng);
        if !(ties && i % 2 == 1) {
            // Distinct by construction: a fresh depth in its own slot of (0.05, 0.95).
            depth = 0.05 + 0.9 * (i as f32 + 0.1 + 0.8 * rng.unit()) / layers as f32;
        }
        let alpha = match i % 4 {
            0 => 0.97 + 0.029 * rng.unit(),
            1 => 0.001 + 0.02 * rng.unit(),
            _ => 0.1 + 0.8 * rng.unit(),
        };
        let ndc_x = |x: u32| 2.0 * x as f32 / w as f32 - 1.0;
        let ndc_y = |y: u32| 1.0 - 2.0 * y as f32 / h as f32;
        quads.push(Quad {
            rect: [ndc_x(x0), ndc_y(y0), ndc_x(x1), ndc_y(y1)],
            depth: (depth, depth),
            alpha,
            colour: [rng.unit(), rng.unit(), rng.unit()],
            key: 0,
        });
        pixel_rects.push([x0, y0, x1, y1]);
    }
    let name = if ties { "equal_depth_pairs" } else { "distinct_depths" };
    (QuadScene::keyed(name, quads), pixel_rects)
}

/// The rasteriser's sub-pixel grid at its coarsest (Vulkan: at least 4 bits), in pixels: snapped
/// vertices move a tilted quad's depth plane by up to its slope times this.
const SUBPIXEL: f32 = 1.0 / 16.0;

/// Adds a half-transparent slab across the middle third, tilted in depth from near (left) to far
/// (right) through the other quads, and marks the pixels where its depth and another covering
/// quad's are too close for the order to be certain: within the slab's slope times the sub-pixel
/// grid, plus 2^-20 for the f32 interpolation.
fn with_tilted_slab(scene: QuadScene, rects: &mut Vec<PixelRect>, size: (u32, u32)) -> (QuadScene, Vec<bool>) {
    let (w, h) = size;
    let (top, bottom) = (h / 3, (2 * h / 3).max(h / 3 + 1));
    let depth = (0.05f32, 0.95f32);
    let slab = Quad {
        rect: [-1.0, 1.0 - 2.0 * top as f32 / h as f32, 1.0, 1.0 - 2.0 * bottom as f32 / h as f32],
        depth,
        alpha: 0.5,
        colour: [0.9, 0.6, 0.1],
        key: 0,
    };
    let mut quads = scene.quads;
    quads.push(slab);
    rects.push([0, top, w, bottom]);
    let slope = (depth.1 - depth.0) / w as f32;
    let mut uncertain = vec![false; (w * h) as usize];
    for y in top..bottom {
        for x in 0..w {
            let at = depth.0 + slope * (x as f32 + 0.5);
            uncertain[(y * w + x) as usize] = rects[..rects.len() - 1].iter().zip(&quads).any(|(rect, q)| {
                covers(rect, x, y) && (at - q.depth.0).abs() <= slope * SUBPIXEL + 1.0 / (1 << 20) as f32
            });
        }
    }
    (QuadScene::keyed("tilted_slab", quads), uncertain)
}

/// How many quads cover each pixel.
fn coverage(size: (u32, u32), rects: &[PixelRect]) -> Vec<u32> {
    let mut counts = Vec::with_capacity((size.0 * size.1) as usize);
    for y in 0..size.1 {
        for x in 0..size.0 {
            counts.push(rects.iter().filter(|rect| covers(rect, x, y)).count() as u32);
        }
    }
    counts
}

fn run(ctx: &mut Ctx) -> Result<Outcome> {
    let size = ctx.params.size("size")?;
    let layers = ctx.params.count_u32("layers")?;
    let seed = ctx.params.count_u32("seed")?;
    let once = Accumulation { frames: 1, seed: 1, filtered: false };
    let mut verdict = Verdict::new();
    for kind in ["distinct", "ties", "tilted"] {
        let (scene, mut rects) = scene(size, layers, seed, kind == "ties");
        let (scene, uncertain) = if kind == "tilted" {
            with_tilted_slab(scene, &mut rects, size)
        } else {
            (scene, vec![false; (size.0 * size.1) as usize])
        };
        let covering = coverage(size, &rects);
        let exact = exact_image(&scene, size, &[[0.5, 0.5]]);
        let bounds: Vec<f32> = covering.iter().map(|&n| (2 * n + 1) as f32 / 1024.0).collect();
        let methods =
            if sortable(&scene) { vec![Method::DepthPeeling, Method::SortedBlend] } else { vec![Method::DepthPeeling] };
        for method in methods {
            let result = run_method(ctx.gpu, &scene, size, 1, &method, once)?;
            let label = format!("{}.{}", scene.name, method.name());
            let errors: Vec<f32> = result
                .image
                .iter()
                .zip(&exact)
                // The largest channel error; a NaN stays NaN (f32::max would drop it).
                .map(|(a, b)| {
                    (0..3).map(|c| (a[c] - b[c]).abs()).fold(0.0, |m, e| if e.is_nan() || e > m { e } else { m })
                })
                .collect();
            let wrong: Vec<bool> = errors
                .iter()
                .zip(&bounds)
                .zip(&uncertain)
                .map(|((e, b), &left_out)| !left_out && (e.is_nan() || e > b))
                .collect();
            let wrong_count = wrong.iter().filter(|&&w| w).count();
            let worst = errors
                .iter()
                .zip(&bounds)
                .zip(&uncertain)
                .filter(|(_, u)| !**u)
                .map(|((e, b), _)| e / b)
                .fold(0.0, f32::max);
            let deepest = covering.iter().copied().max().unwrap_or(0);
            ctx.metric(
                &label,
                serde_json::json!({"pixels_beyond_bound": wrong_count, "worst_error_in_bounds": worst,
                    "order_uncertain_pixels_left_out": uncertain.iter().filter(|&&u| u).count(),
                    "layers_peeled": result.layers, "most_quads_on_a_pixel": deepest}),
            );
            if method == Method::DepthPeeling && result.layers != Some(deepest) {
                verdict.fail(format!(
                    "{label}: peeled {:?} layers, the deepest pixel holds {deepest} quads",
                    result.layers
                ));
            }
            if wrong_count > 0 {
                verdict.fail(format!(
                    "{label}: {wrong_count} of {} pixels differ from the exact composite beyond (2n+1)·2^-10 (worst {worst:.1}x the bound)",
                    exact.len()
                ));
                let reference = ldr_to_display(size.0, size.1, &exact)?;
                let shown = ldr_to_display(size.0, size.1, &result.image)?;
                ctx.evidence_image(&label, &side_by_side(&shown, &reference, &error_mask(&reference, &wrong)))?;
            }
        }
    }
    Ok(verdict.outcome())
}
