//! `kit.scissor.msaa`: a scissored draw under MSAA touches exactly the samples inside the
//! scissor rect: none of the pixels outside it may change. Read back through a resolve (every
//! backend) and, where occlusion queries count, through a stencil written under the scissor.

use anyhow::Result;
use fragkit::attachments;
use fragkit::caps::common_sample_counts;
use fragkit::harness::{Case, Ctx, Outcome, ParamKind, ParamSpec, Sweep, SweepRange, Verdict};
use fragkit::image_compare::{compare, side_by_side};
use fragkit::probe::multisample_render::render_problem;
use fragkit::probe::occlusion::{OcclusionPrecision, measure_occlusion_precision};
use fragkit::query::OcclusionQueries;
use fragkit::readback::read_rgba8;
use fragkit::rects::{Rect, RectBatch, RectFragment, RectPipeline, stencil_equal, stencil_replace};
use fragkit::shaders::RECT;

pub const CASE: Case = Case {
    name: "kit.scissor.msaa",
    summary: "a scissored draw under MSAA covers no sample outside the scissor rect",
    requires: wgpu::Features::empty(),
    params: &[
        ParamSpec { name: "size", kind: ParamKind::Size, default: "40x30", help: "target size" },
        ParamSpec { name: "scissor", kind: ParamKind::Counts, default: "8,8,20,10", help: "x,y,width,height" },
        ParamSpec { name: "sample_counts", kind: ParamKind::Counts, default: "1,4", help: "sample counts to test" },
    ],
    sweep: &[
        // At least the default scissor (8, 8, 20, 10) must fit.
        Sweep { param: "size", range: SweepRange::Size { min: (28, 18), max: (400, 300) } },
    ],
    budget_s: 1,
    timed_verdict: false,
    shaders: &[RECT],
    run,
};

struct Scissor {
    x: u32,
    y: u32,
    w: u32,
    h: u32,
}

/// Colour the resolve target holds before the pass, so that a pixel the resolve never wrote shows.
const UNRESOLVED: [u8; 4] = [255, 0, 255, 255];

/// Renders white under the scissor into a cleared MSAA target and resolves it (into a target
/// filled with `UNRESOLVED` first).
fn scissored_fill(ctx: &mut Ctx, size: (u32, u32), samples: u32, s: &Scissor) -> Result<image::RgbaImage> {
    let gpu = ctx.gpu;
    let format = wgpu::TextureFormat::Rgba8Unorm;
    let msaa = gpu.texture("scissor msaa", size, format, samples, wgpu::TextureUsages::RENDER_ATTACHMENT);
    let resolved = gpu.texture(
        "scissor resolved",
        size,
        format,
        1,
        wgpu::TextureUsages::RENDER_ATTACHMENT | wgpu::TextureUsages::COPY_SRC,
    );
    let (msaa_view, resolved_view) = (msaa.create_view(&Default::default()), resolved.create_view(&Default::default()));
    let fill = RectPipeline {
        colour_format: Some(format),
        fragment: RectFragment::InstanceColour,
        samples,
        ..RectPipeline::new("scissored fill")
    }
    .create(gpu);
    let full = RectBatch::new(gpu, size, &[(Rect::full(size.0, size.1), [1.0; 4])]);
    let mut encoder = gpu.encoder("scissored fill");
    if samples > 1 {
        let unresolved = wgpu::Color { r: 1.0, g: 0.0, b: 1.0, a: 1.0 };
        encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
            label: Some("resolve target filled"),
            color_attachments: &[attachments::colour(&resolved_view, None, unresolved)],
            ..Default::default()
        });
    }
    {
        let (view, resolve) = if samples > 1 { (&msaa_view, Some(&resolved_view)) } else { (&resolved_view, None) };
        let mut pass = encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
            label: Some("scissored fill"),
            color_attachments: &[attachments::colour(view, resolve, wgpu::Color::BLACK)],
            ..Default::default()
        });
        pass.set_pipeline(&fill);
        pass.set_scissor_rect(s.x, s.y, s.w, s.h);
        full.draw(&mut pass, ..);
    }
    gpu.submit(encoder);
    read_rgba8(gpu, &resolved)
}

/// Writes stencil 1 under the scissor, then counts samples equal to 1 without a scissor.
fn scissored_stencil_count(ctx: &mut Ctx, size: (u32, u32), samples: u32, s: &Scissor) -> Result<u64> {
    let gpu = ctx.gpu;
    let format = wgpu::TextureFormat::Depth24PlusStencil8;
    let stencil = gpu.texture("scissor stencil", size, format, samples, wgpu::TextureUsages::RENDER_ATTACHMENT);
    let view = stencil.create_view(&Default::default());
    let mark = RectPipeline {
        depth_stencil: Some(stencil_replace(format)),
        samples,
        ..RectPipeline::new("scissored stencil")
    }
    .create(gpu);
    let count =
        RectPipeline { depth_stencil: Some(stencil_equal(format)), samples, ..RectPipeline::new("count") }.create(gpu);
    let full = RectBatch::new(gpu, size, &[(Rect::full(size.0, size.1), [1.0; 4])]);
    let queries = OcclusionQueries::new(gpu, 1);
    let mut encoder = gpu.encoder("scissored stencil");
    {
        let mut pass = encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
            label: Some("scissored stencil and count"),
            depth_stencil_attachment: attachments::stencil(&view, Some(0)),
            occlusion_query_set: Some(queries.set()),
            ..Default::default()
        });
        pass.set_stencil_reference(1);
        pass.set_pipeline(&mark);
        pass.set_scissor_rect(s.x, s.y, s.w, s.h);
        full.draw(&mut pass, ..);
        pass.set_scissor_rect(0, 0, size.0, size.1);
        pass.set_pipeline(&count);
        pass.begin_occlusion_query(0);
        full.draw(&mut pass, ..);
        pass.end_occlusion_query();
    }
    queries.resolve(&mut encoder);
    gpu.submit(encoder);
    Ok(queries.read(gpu)?[0])
}

fn run(ctx: &mut Ctx) -> Result<Outcome> {
    let size = ctx.params.size("size")?;
    let rect = ctx.params.counts("scissor")?;
    let [x, y, w, h] = <[u64; 4]>::try_from(rect.clone())
        .map_err(|_| anyhow::anyhow!("scissor needs x,y,width,height, got {rect:?}"))?;
    let s = Scissor { x: x as u32, y: y as u32, w: w as u32, h: h as u32 };
    anyhow::ensure!(
        s.x + s.w <= size.0 && s.y + s.h <= size.1,
        "scissor {rect:?} leaves the {}x{} target",
        size.0,
        size.1
    );
    let advertised = common_sample_counts(ctx.gpu);
    let precision = measure_occlusion_precision(ctx.gpu)?;

    // Expected: white exactly inside the rect, black elsewhere, every sample (pixel-aligned rect).
    let expected = image::RgbaImage::from_fn(size.0, size.1, |px, py| {
        let inside = (s.x..s.x + s.w).contains(&px) && (s.y..s.y + s.h).contains(&py);
        if inside { image::Rgba([255; 4]) } else { image::Rgba([0, 0, 0, 255]) }
    });
    let mut verdict = Verdict::new();
    for samples in ctx.params.counts("sample_counts")? {
        let samples = samples as u32;
        if !advertised.contains(&samples) {
            ctx.metric(&format!("{samples}x"), "not supported");
            continue;
        }
        if samples > 1
            && let Some(problem) = render_problem(ctx.gpu, samples)? {
                verdict.fail(problem);
                continue;
            }
        let result = scissored_fill(ctx, size, samples, &s)?;
        let (difference, mask) = compare(&result, &expected, 0)?;
        ctx.metric(&format!("{samples}x.pixels_differing"), difference.differing_pixels);
        if difference.differing_pixels > 0 {
            ctx.evidence_image(&format!("{samples}x"), &side_by_side(&result, &expected, &mask))?;
            // Which way they differ says where: samples drawn outside the rect (the rasteriser),
            // or pixels the resolve never wrote (the resolve).
            let unresolved = result.pixels().filter(|p| p.0 == UNRESOLVED).count() as u64;
            verdict.fail(if unresolved == difference.differing_pixels {
                format!("{samples}x: {unresolved} pixels outside the scissor rect never resolved (they kept what the target held)")
            } else {
                format!("{samples}x: {} pixels differ from the scissor rect", difference.differing_pixels)
            });
        }
        if precision == OcclusionPrecision::Exact {
            let measured = scissored_stencil_count(ctx, size, samples, &s)?;
            let expected_samples = u64::from(s.w * s.h * samples);
            ctx.metric(
                &format!("{samples}x.stencil_samples"),
                serde_json::json!({"expected": expected_samples, "measured": measured}),
            );
            if measured != expected_samples {
                verdict.fail(format!("{samples}x: stencil written under the scissor covers {measured} samples, expected {expected_samples}"));
            }
        }
    }
    Ok(verdict.outcome())
}
