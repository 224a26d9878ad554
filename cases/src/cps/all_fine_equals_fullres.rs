//! `cps.all_fine_equals_fullres`: with LOD 0 everywhere, every composite of CPS is bit-identical
//! to full-resolution deferred shading: level 0 shades each pixel from its own G-buffer sample with
//! the same shader code, and every composite weight is then 0 or 1.

use anyhow::Result;
use fragkit::cps::{CompositeMode, CpsConfig, CpsRenderer, LodPolicy, MAX_LEVEL};
use fragkit::deferred::lighting::light_full_resolution;
use fragkit::harness::{Case, Ctx, Outcome, ParamKind, ParamSpec, Sweep, SweepRange, Verdict};
use fragkit::image_compare::{compare, side_by_side};
use fragkit::readback::read_texture;
use fragkit::tonemap::to_display;
use fragkit::shaders::{CPS_COMPOSITE, CPS_LIGHTING, CPS_LOD, CPS_MASK_REDUCE, CPS_STENCIL_MARK, DEFERRED_LIGHTING, FRAGMENT_STORAGE, FULLSCREEN, GBUFFER, INDIRECT_DRAW, RECT};

use super::{corridor_inputs, frame};

pub const CASE: Case = Case {
    name: "cps.all_fine_equals_fullres",
    summary: "LOD 0 everywhere reproduces full-resolution deferred shading bit for bit",
    requires: wgpu::Features::empty(),
    params: &[
        ParamSpec { name: "size", kind: ParamKind::Size, default: "96x64", help: "screen size" },
        ParamSpec { name: "lights", kind: ParamKind::CountIn(1, 4096), default: "32", help: "point lights" },
    ],
    sweep: &[
        Sweep { param: "size", range: SweepRange::Size { min: (1, 1), max: (200, 150) } },
        Sweep { param: "lights", range: SweepRange::Count(1, 4096) },
    ],
    budget_s: 1,
    timed_verdict: false,
    shaders: &[RECT, FULLSCREEN, FRAGMENT_STORAGE, INDIRECT_DRAW, GBUFFER, DEFERRED_LIGHTING, CPS_LOD, CPS_MASK_REDUCE, CPS_LIGHTING, CPS_COMPOSITE, CPS_STENCIL_MARK],
    run,
};

fn run(ctx: &mut Ctx) -> Result<Outcome> {
    let size = ctx.params.size("size")?;
    let inputs = corridor_inputs(ctx.gpu, size, ctx.params.count_u32("lights")?, 1)?;

    // Reference: full-resolution deferred lighting, raw f16 bits.
    let fullres = light_full_resolution(ctx.gpu, &inputs)?;
    let reference = read_texture(ctx.gpu, &fullres, wgpu::TextureAspect::All, 0)?;

    let mut verdict = Verdict::new();
    for composite in CompositeMode::ALL {
        // LOD 0 everywhere, with the whole pyramid still planned (max level 8).
        let config = CpsConfig::new(MAX_LEVEL, LodPolicy::Explicit(vec![0; (size.0 * size.1) as usize]), composite);
        let renderer = CpsRenderer::new(ctx.gpu, size, config)?;
        let output = renderer.render(ctx.gpu, &frame(&inputs))?;
        let result = read_texture(ctx.gpu, &renderer.image, wgpu::TextureAspect::All, 0)?;
        let differing =
            result.bytes.chunks_exact(8).zip(reference.bytes.chunks_exact(8)).filter(|(a, b)| a != b).count();
        ctx.metric(
            composite.name(),
            serde_json::json!({"differing_pixels": differing, "shaded_texels": output.shaded_texels}),
        );
        if differing > 0 {
            let (shown, expected) =
                (to_display(size.0, size.1, &result.as_f16())?, to_display(size.0, size.1, &reference.as_f16())?);
            let (_, mask) = compare(&shown, &expected, 0)?;
            ctx.evidence_image(composite.name(), &side_by_side(&shown, &expected, &mask))?;
            verdict.fail(format!("{}: {differing} pixels differ from full resolution", composite.name()));
        }
        let coarser: u64 = output.shaded_texels.iter().skip(1).sum();
        if coarser != 0 {
            verdict.fail(format!("{}: levels above 0 shaded {coarser} texels with every LOD at 0", composite.name()));
        }
    }
    Ok(verdict.outcome())
}
