//! `cbr.upscale.bilinear`: the half-resolution baseline checkerboarding is compared with
//! (`HalfResolutionUpscale`: the scene at quarter resolution, then `shaders/cbr/upscale.wgsl`) is
//! the bilinear filter of its quarter-resolution image — the claim "checkerboarding beats the
//! upscaled quarter resolution" is only as good as that baseline. The expectation filters the
//! read-back quarter image (the stage's own input, as `kit.deferred.lighting` reads its G-buffer)
//! on the CPU in f64: full-resolution pixel p samples quarter texel coordinate (p + 1/2) / 2 − 1/2
//! on each axis, clamped to the edge. Bound per channel: the four texels' contrast times 1/16 (a
//! filter weight may be rounded to 4 sub-texel bits, the coarsest Vulkan allows: 1/32 an axis)
//! plus one f16 ulp of the result (2^-10 relative: the store may truncate).

use anyhow::Result;
use fragkit::cbr::HalfResolutionUpscale;
use fragkit::cbr::measure::read_hdr;
use fragkit::cbr::sampling::quarter_size;
use fragkit::cbr::scene::{Motion, textured_corridor};
use fragkit::harness::{Case, Ctx, Outcome, ParamKind, ParamSpec, Sweep, SweepRange};
use fragkit::image_compare::{error_mask, side_by_side};
use fragkit::tonemap::to_display;
use fragkit::shaders::{CBR_SCENE, CBR_UPSCALE, FULLSCREEN};

pub const CASE: Case = Case {
    name: "cbr.upscale.bilinear",
    summary: "the half-resolution baseline is the bilinear upscale of its quarter-resolution image",
    requires: wgpu::Features::empty(),
    params: &[ParamSpec { name: "size", kind: ParamKind::SizeFrom(2), default: "96x64", help: "screen size" }],
    sweep: &[Sweep { param: "size", range: SweepRange::Size { min: (2, 2), max: (200, 150) } }],
    budget_s: 1,
    timed_verdict: false,
    shaders: &[FULLSCREEN, CBR_SCENE, CBR_UPSCALE],
    run,
};

/// Filter weights to 4 sub-texel bits: each axis's weight within 1/32, so the two axes together
/// within 1/16 of the texels' contrast.
const WEIGHT_ROUNDING: f64 = 1.0 / 16.0;
const F16_RELATIVE: f64 = 1.0 / 1024.0;

/// The two texels an axis blends at full-resolution coordinate `p`, and the second one's weight.
fn taps(p: u32, quarter: u32) -> (usize, usize, f64) {
    let t = (f64::from(p) + 0.5) * 0.5 - 0.5;
    let first = t.floor();
    let clamp = |i: f64| i.clamp(0.0, f64::from(quarter - 1)) as usize;
    (clamp(first), clamp(first + 1.0), t - first)
}

fn run(ctx: &mut Ctx) -> Result<Outcome> {
    let size = ctx.params.size("size")?;
    let scene = textured_corridor(5, 16, Motion::Static);
    let mut upscale = HalfResolutionUpscale::new(ctx.gpu, &scene, size)?;
    upscale.render(ctx.gpu, 0)?;
    let quarter_image = read_hdr(ctx.gpu, upscale.quarter_image())?;
    let result = read_hdr(ctx.gpu, &upscale.output)?;

    // Expected: the bilinear filter of the quarter image, with its bound.
    let quarter = quarter_size(size);
    let texel = |x: usize, y: usize, c: usize| f64::from(quarter_image[(y * quarter.0 as usize + x) * 4 + c]);
    let mut expected = Vec::with_capacity(result.len());
    let mut wrong = Vec::with_capacity((size.0 * size.1) as usize);
    let mut worst = 0.0f64;
    for y in 0..size.1 {
        let (y0, y1, fy) = taps(y, quarter.1);
        for x in 0..size.0 {
            let (x0, x1, fx) = taps(x, quarter.0);
            let mut beyond = false;
            for c in 0..4 {
                let corners = [texel(x0, y0, c), texel(x1, y0, c), texel(x0, y1, c), texel(x1, y1, c)];
                let top = corners[0] + (corners[1] - corners[0]) * fx;
                let bottom = corners[2] + (corners[3] - corners[2]) * fx;
                let value = top + (bottom - top) * fy;
                let contrast =
                    corners.iter().copied().fold(f64::MIN, f64::max) - corners.iter().copied().fold(f64::MAX, f64::min);
                let bound = WEIGHT_ROUNDING * contrast + F16_RELATIVE * value.abs() + f64::from(f32::EPSILON);
                let got = f64::from(result[((y * size.0 + x) * 4) as usize + c]);
                let error = (got - value).abs();
                worst = worst.max(error / bound);
                beyond |= error.is_nan() || error > bound;
                expected.push(value as f32);
            }
            wrong.push(beyond);
        }
    }
    let wrong_count = wrong.iter().filter(|&&w| w).count();
    ctx.metric("pixels_beyond_bound", wrong_count);
    ctx.metric("worst_error_in_bounds", worst);
    if wrong_count == 0 {
        return Ok(Outcome::Pass);
    }
    let reference = to_display(size.0, size.1, &expected)?;
    ctx.evidence_image(
        "upscale",
        &side_by_side(&to_display(size.0, size.1, &result)?, &reference, &error_mask(&reference, &wrong)),
    )?;
    Ok(Outcome::Fail(format!(
        "{wrong_count} of {} pixels differ from the bilinear filter of the quarter image beyond the bound (worst {worst:.1}x)",
        size.0 * size.1
    )))
}
