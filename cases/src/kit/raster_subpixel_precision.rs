//! `kit.raster.subpixel_precision`: how finely the rasteriser snaps vertices, measured by
//! `shaders/kit/sloped_edge.wgsl` (the snapped offset of 256 vertex positions to 1/256 px), held
//! to what Vulkan and GL require: a grid of at least 4 bits, no vertex moved a whole step of it.

use anyhow::Result;
use fragkit::harness::{Case, Ctx, Outcome};
use fragkit::probe::subpixel_precision::{COARSEST_BITS, measure};
use fragkit::shaders::SLOPED_EDGE;

pub const CASE: Case = Case {
    name: "kit.raster.subpixel_precision",
    summary: "vertices snap to a sub-pixel grid of at least 4 bits and move less than one step of it",
    requires: wgpu::Features::empty(),
    params: &[],
    sweep: &[],
    budget_s: 1,
    timed_verdict: false,
    shaders: &[SLOPED_EDGE],
    run,
};

fn run(ctx: &mut Ctx) -> Result<Outcome> {
    let precision = measure(ctx.gpu)?;
    ctx.metric("bits", precision.bits);
    ctx.metric("largest_move", precision.largest_move);
    if !precision.unreadable.is_empty() {
        return Ok(Outcome::Fail(format!(
            "the snapped vertex lay outside its pixel for offsets {:?} (1/256 px)",
            precision.unreadable
        )));
    }
    Ok(if precision.within_specification() {
        Outcome::Pass
    } else {
        Outcome::Fail(format!(
            "snapped to {} bits (at least {COARSEST_BITS} required), moving a vertex up to {} px",
            precision.bits, precision.largest_move
        ))
    })
}
