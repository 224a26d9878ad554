//! `kit.deferred.lighting`: full-resolution deferred lighting equals a CPU Phong of the read-back
//! G-buffer under the scene's own light list (not the light texture the GPU reads), pixel by
//! pixel, within a bound derived per pixel from f32 arithmetic and the f16 target
//! (`fragkit::deferred::phong`). The GPU pass runs `shade_gbuffer_pixel`, the function every CPS
//! level and the full-resolution reference share, so a light skipped, shifted or misread there is
//! caught here rather than moving both sides of a comparison.

use anyhow::Result;
use fragkit::deferred::DeferredInputs;
use fragkit::deferred::lighting::light_full_resolution;
use fragkit::deferred::phong::{PhongComparison, read_surfaces, shade};
use fragkit::harness::{Case, Ctx, Outcome, ParamKind, ParamSpec, Sweep, SweepRange};
use fragkit::readback::read_texture;
use fragkit::scene::corridor::corridor;
use fragkit::shaders::{DEFERRED_LIGHTING, FULLSCREEN, GBUFFER};

pub const CASE: Case = Case {
    name: "kit.deferred.lighting",
    summary: "full-resolution lighting equals a CPU Phong of the G-buffer within derived f32/f16 bounds",
    requires: wgpu::Features::empty(),
    params: &[
        ParamSpec { name: "size", kind: ParamKind::SizeFrom(1), default: "96x64", help: "screen size" },
        ParamSpec { name: "lights", kind: ParamKind::CountIn(1, 4096), default: "64", help: "point lights" },
        ParamSpec { name: "seed", kind: ParamKind::CountIn(0, 1 << 20), default: "2", help: "scene seed" },
    ],
    sweep: &[
        Sweep { param: "size", range: SweepRange::Size { min: (1, 1), max: (160, 120) } },
        Sweep { param: "lights", range: SweepRange::Count(1, 4096) },
        Sweep { param: "seed", range: SweepRange::Count(0, 1 << 20) },
    ],
    budget_s: 1,
    timed_verdict: false,
    shaders: &[FULLSCREEN, GBUFFER, DEFERRED_LIGHTING],
    run,
};

fn run(ctx: &mut Ctx) -> Result<Outcome> {
    let size = ctx.params.size("size")?;
    let scene = corridor(ctx.params.count_u32("seed")?, ctx.params.count_u32("lights")?);
    let inputs = DeferredInputs::new(ctx.gpu, &scene, size)?;
    let lit = read_texture(ctx.gpu, &light_full_resolution(ctx.gpu, &inputs)?, wgpu::TextureAspect::All, 0)?.as_f16();

    // Expected: Phong of each read-back sample under the scene's lights, with its error bound.
    let surfaces = read_surfaces(ctx.gpu, &inputs.gbuffer)?;
    let expected: Vec<_> = surfaces.iter().map(|s| shade(s, scene.camera.eye, &scene.lights)).collect();
    let comparison = PhongComparison::new(&expected, &lit);
    let surface_pixels = surfaces.iter().filter(|s| s.position[3] != 0.0).count();
    ctx.metric("surface_pixels", surface_pixels);
    ctx.metric("pixels_beyond_bound", comparison.wrong_count);
    ctx.metric("worst_error_in_bounds", comparison.worst);

    if comparison.wrong_count == 0 {
        return Ok(Outcome::Pass);
    }
    ctx.evidence_image("comparison", &comparison.evidence(size, &expected, &lit)?)?;
    Ok(Outcome::Fail(format!(
        "{} of {} pixels differ from the CPU Phong beyond their derived bound (worst {:.1}x the bound)",
        comparison.wrong_count,
        size.0 * size.1,
        comparison.worst
    )))
}
