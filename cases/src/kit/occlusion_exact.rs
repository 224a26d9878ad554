//! `kit.occlusion.exact`: an occlusion query around a stencil-Equal full-screen draw counts
//! exactly the samples whose stencil holds the reference, for seeded stencil patterns drawn as
//! geometry with sub-pixel edges, on 1×1, odd and larger targets, at 1x and 4x.

use anyhow::{Context, Result};
use fragkit::attachments;
use fragkit::caps::{common_sample_counts, matches_standard};
use fragkit::harness::{Case, Ctx, Outcome, ParamKind, ParamSpec, Sweep, SweepRange};
use fragkit::probe::multisample_render::render_problem;
use fragkit::probe::occlusion::{OcclusionPrecision, measure_occlusion_precision};
use fragkit::probe::sample_positions::{measure, standard_positions};
use fragkit::probe::sample_projections::measure_projections;
use fragkit::query::OcclusionQueries;
use fragkit::rects::{Rect, RectBatch, RectPipeline, stencil_equal, stencil_replace};
use fragkit::scene::hash::SeededRng;
use fragkit::shaders::{FRAGMENT_STORAGE, FULLSCREEN, RECT, SAMPLE_COVERAGE_RECORD};

pub const CASE: Case = Case {
    name: "kit.occlusion.exact",
    summary: "occlusion queries count exactly the pixels (1x) and samples (4x) that pass a stencil-Equal test",
    requires: wgpu::Features::empty(),
    params: &[
        ParamSpec { name: "sizes", kind: ParamKind::Sizes, default: "1x1,7x5,64x64,257x131", help: "target sizes" },
        ParamSpec { name: "sample_counts", kind: ParamKind::Counts, default: "1,4", help: "sample counts to test" },
        ParamSpec { name: "rects", kind: ParamKind::Count, default: "24", help: "stencil rects per pattern" },
        ParamSpec { name: "seed", kind: ParamKind::CountIn(0, u32::MAX as u64), default: "1", help: "pattern seed" },
    ],
    sweep: &[
        Sweep { param: "sizes", range: SweepRange::Size { min: (1, 1), max: (400, 300) } },
        Sweep { param: "rects", range: SweepRange::Count(1, 256) },
        Sweep { param: "seed", range: SweepRange::Count(0, 1 << 20) },
    ],
    budget_s: 1,
    timed_verdict: false,
    shaders: &[RECT, FULLSCREEN, SAMPLE_COVERAGE_RECORD, FRAGMENT_STORAGE],
    run,
};

/// Stencil values the pattern writes; every value, 0 included, gets its own counted draw.
const VALUES: u32 = 4;

/// Seeded rects with edges at k/2 + 1/16 px, reaching past the target so clipping is exercised.
/// An edge on the 1/16-px grid is where the coarsest sub-pixel precision Vulkan and GL permit
/// (4 bits) keeps it, so snapping cannot move it; and the 1x, 2x and 4x standard sample positions
/// are multiples of 1/8 px, so no edge passes through a sample and the fill convention's tie rule
/// never decides a count.
fn pattern(size: (u32, u32), count: u64, seed: u32) -> Vec<(Rect, u32)> {
    let mut rng = SeededRng::new(seed ^ (size.0 << 16) ^ size.1);
    let coordinate = |rng: &mut SeededRng, extent: u32| rng.range(0, 2 * extent + 8) as f32 * 0.5 - 2.0 + 1.0 / 16.0;
    (0..count)
        .map(|_| {
            let (xa, xb) = (coordinate(&mut rng, size.0), coordinate(&mut rng, size.0));
            let (ya, yb) = (coordinate(&mut rng, size.1), coordinate(&mut rng, size.1));
            (Rect::new(xa.min(xb), ya.min(yb), xa.max(xb), ya.max(yb)), rng.range(1, VALUES))
        })
        .collect()
}

/// CPU expectation: per stencil value, the samples whose last covering rect wrote it.
fn expected_counts(size: (u32, u32), positions: &[[f32; 2]], pattern: &[(Rect, u32)]) -> Vec<u64> {
    let mut counts = vec![0u64; VALUES as usize];
    for y in 0..size.1 {
        for x in 0..size.0 {
            for [sx, sy] in positions {
                let (px, py) = (x as f32 + sx, y as f32 + sy);
                let value = pattern.iter().rev().find(|(r, _)| r.covers(px, py)).map_or(0, |&(_, v)| v);
                counts[value as usize] += 1;
            }
        }
    }
    counts
}

/// GPU result: the pattern drawn into the stencil, then one counted Equal draw per value.
fn measured_counts(ctx: &mut Ctx, size: (u32, u32), samples: u32, pattern: &[(Rect, u32)]) -> Result<Vec<u64>> {
    let gpu = ctx.gpu;
    let format = wgpu::TextureFormat::Depth24PlusStencil8;
    let stencil = gpu.texture("occlusion stencil", size, format, samples, wgpu::TextureUsages::RENDER_ATTACHMENT);
    let view = stencil.create_view(&Default::default());
    let rects: Vec<(Rect, [f32; 4])> = pattern.iter().map(|&(r, _)| (r, [1.0; 4])).collect();
    let rects = RectBatch::new(gpu, size, &rects);
    let full = RectBatch::new(gpu, size, &[(Rect::full(size.0, size.1), [1.0; 4])]);
    let mark =
        RectPipeline { depth_stencil: Some(stencil_replace(format)), samples, ..RectPipeline::new("stencil pattern") }
            .create(gpu);
    let count =
        RectPipeline { depth_stencil: Some(stencil_equal(format)), samples, ..RectPipeline::new("counted Equal draw") }
            .create(gpu);
    let queries = OcclusionQueries::new(gpu, VALUES);
    let mut encoder = gpu.encoder("occlusion exactness");
    {
        let mut pass = encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
            label: Some("stencil pattern and counts"),
            depth_stencil_attachment: attachments::stencil(&view, Some(0)),
            occlusion_query_set: Some(queries.set()),
            ..Default::default()
        });
        pass.set_pipeline(&mark);
        for (i, &(_, value)) in pattern.iter().enumerate() {
            pass.set_stencil_reference(value);
            rects.draw(&mut pass, i as u32..i as u32 + 1);
        }
        pass.set_pipeline(&count);
        for value in 0..VALUES {
            pass.set_stencil_reference(value);
            pass.begin_occlusion_query(value);
            full.draw(&mut pass, ..);
            pass.end_occlusion_query();
        }
    }
    queries.resolve(&mut encoder);
    gpu.submit(encoder);
    let counts = queries.read(gpu)?;
    Ok(counts)
}

fn run(ctx: &mut Ctx) -> Result<Outcome> {
    let sizes = ctx.params.sizes("sizes")?;
    let rect_count = ctx.params.count("rects")?;
    let seed = ctx.params.count_u32("seed")?;
    let advertised = common_sample_counts(ctx.gpu);
    let precision = measure_occlusion_precision(ctx.gpu)?;
    ctx.metric("precision", precision);

    let mut mismatches = Vec::new();
    for samples in ctx.params.counts("sample_counts")? {
        let samples = u32::try_from(samples).context("sample count")?;
        if !advertised.contains(&samples) {
            ctx.metric(&format!("{samples}x"), "not supported");
            continue;
        }
        if samples > 1
            && let Some(problem) = render_problem(ctx.gpu, samples)? {
                mismatches.push(problem);
                continue;
            }
        // Expectations use the standard positions, which the edge sweep must confirm
        // (kit.msaa.sample_positions judges them); the pattern's edges avoid only those. Where
        // no route reads single samples, the unmasked sweep confirms each axis's coordinates.
        let measured = measure(ctx.gpu, samples)?;
        let standard = if !measured.read_single_samples() {
            let projections = measure_projections(ctx.gpu, samples)?;
            ctx.metric(&format!("{samples}x.positions_from"), "projections (no route reads single samples)");
            projections.matches_standard(samples)
        } else {
            let positions = measured
                .agreed()
                .context("the sample positions could not be measured consistently; see kit.msaa.sample_positions")?;
            matches_standard(samples, positions)
        };
        anyhow::ensure!(
            samples <= 4 && standard,
            "{samples}x samples are not at the standard positions (or not on the 1/8-px grid the pattern avoids); see kit.msaa.sample_positions"
        );
        let positions = standard_positions(samples).context("no standard table for this count")?;
        for &size in &sizes {
            let pattern = pattern(size, rect_count, seed);
            let expected = expected_counts(size, positions, &pattern);
            let measured = measured_counts(ctx, size, samples, &pattern)?;
            ctx.metric(
                &format!("{samples}x.{}x{}", size.0, size.1),
                serde_json::json!({"expected": expected, "measured": measured}),
            );
            let agree = match precision {
                OcclusionPrecision::Exact => measured == expected,
                // Boolean queries can only say whether anything passed.
                _ => measured.iter().zip(&expected).all(|(&m, &e)| (m > 0) == (e > 0)),
            };
            if !agree {
                mismatches
                    .push(format!("{samples}x {}x{}: expected {expected:?}, measured {measured:?}", size.0, size.1));
            }
        }
    }
    Ok(match precision {
        _ if !mismatches.is_empty() => Outcome::Fail(mismatches.join("; ")),
        OcclusionPrecision::Exact => Outcome::Pass,
        OcclusionPrecision::Boolean => Outcome::NotSupported(
            "exact occlusion counts: queries return 0/1 (booleans agreed with the expected counts)".into(),
        ),
        wrong => Outcome::Fail(format!("occlusion probe returned {wrong:?}")),
    })
}
