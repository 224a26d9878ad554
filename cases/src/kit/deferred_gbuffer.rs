//! `kit.deferred.gbuffer`: the G-buffer pass (`render_gbuffer`, `shaders/deferred/gbuffer.wgsl`)
//! — the input of full-resolution lighting, every CPS level and so of every CPS comparison, none
//! of which could see a G-buffer bug since both sides read the same G-buffer — equals a CPU ray
//! cast of the scene's own triangles and camera (`fragkit::deferred::surface_model`), pixel by
//! pixel. Bounds, from the formats and the rasteriser:
//! - which surface: pixels within 1/16 px of an edge (4 sub-pixel bits, the coarsest Vulkan
//!   allows) or at depths a `Depth32Float` test cannot order are left out and counted;
//! - position (`Rgba32Uint` f32 bits): on the hit triangle's plane within 16 f32 ulps of the
//!   largest coordinate involved (perspective-correct interpolation: a weighted sum over a sum of
//!   weights, each step within half an ulp), and projecting onto the pixel centre within 1/16 px
//!   (snapped vertices move the triangle by at most half a grid step);
//! - normal and shininess (`Rgba16Float`): the vertex's normal, normalised, and shininess within
//!   one f16 ulp (2^-10 relative: Vulkan lets the store truncate) plus 2^-20 for f32's normalise;
//! - albedo and specular weight (`Rgba8Unorm`): within one 8-bit step;
//! - background: the cleared G-buffer (w = 0) where the ray meets nothing.

use anyhow::Result;
use fragkit::deferred::DeferredInputs;
use fragkit::deferred::phong::{Surface, read_surfaces};
use fragkit::deferred::surface_model::{ExpectedPixel, SurfaceModel};
use fragkit::harness::{Case, Ctx, Outcome, ParamKind, ParamSpec, Sweep, SweepRange};
use fragkit::image_compare::{error_mask, side_by_side};
use fragkit::scene::corridor::corridor;
use fragkit::tonemap::ldr_to_display;
use fragkit::shaders::GBUFFER;
use glam::DVec3;

pub const CASE: Case = Case {
    name: "kit.deferred.gbuffer",
    summary: "the G-buffer equals a CPU ray cast of the scene: surface, position, normal, material",
    requires: wgpu::Features::empty(),
    params: &[
        ParamSpec { name: "size", kind: ParamKind::SizeFrom(1), default: "96x64", help: "screen size" },
        ParamSpec { name: "seed", kind: ParamKind::CountIn(0, 1 << 20), default: "2", help: "scene seed" },
    ],
    sweep: &[
        Sweep { param: "size", range: SweepRange::Size { min: (1, 1), max: (160, 120) } },
        Sweep { param: "seed", range: SweepRange::Count(0, 1 << 20) },
    ],
    budget_s: 1,
    timed_verdict: false,
    shaders: &[GBUFFER],
    run,
};

/// The rasteriser's sub-pixel grid at its coarsest (Vulkan: at least 4 bits), in pixels.
const SUBPIXEL: f64 = 1.0 / 16.0;
const F32_ULP: f64 = 1.0 / (1u64 << 23) as f64;
const F16_RELATIVE: f64 = 1.0 / 1024.0;
/// f32's normalise of an interpolated unit normal, absolute.
const NORMALISE: f64 = 1.0 / (1u64 << 20) as f64;

/// What is wrong with one pixel's G-buffer sample, if anything.
fn check(model: &SurfaceModel, expected: ExpectedPixel, gpu: &Surface) -> Option<&'static str> {
    match expected {
        ExpectedPixel::Ambiguous => None,
        ExpectedPixel::Background => (gpu.position[3] != 0.0).then_some("surface where the ray meets nothing"),
        ExpectedPixel::Surface { triangle, position } => {
            if gpu.position[3] != 1.0 {
                return Some("no surface where the ray meets one");
            }
            let at = DVec3::new(f64::from(gpu.position[0]), f64::from(gpu.position[1]), f64::from(gpu.position[2]));
            let (normal, on_plane) = model.plane(triangle);
            let largest = [at, on_plane, position].iter().map(|p| p.abs().max_element()).fold(1.0, f64::max);
            if normal.dot(at - on_plane).abs() > 16.0 * F32_ULP * largest {
                return Some("position off its surface's plane");
            }
            let (px, py) = model.project(at);
            let (cx, cy) = model.project(position);
            if (px - cx).abs() > SUBPIXEL || (py - cy).abs() > SUBPIXEL {
                return Some("position away from the pixel centre");
            }
            let vertex = model.vertex(triangle);
            let unit = DVec3::from(vertex.normal.map(f64::from)).normalize();
            let stored = [unit.x, unit.y, unit.z, f64::from(vertex.shininess)];
            let normal_ok = (0..4)
                .all(|c| (f64::from(gpu.normal[c]) - stored[c]).abs() <= F16_RELATIVE * stored[c].abs() + NORMALISE);
            if !normal_ok {
                return Some("normal or shininess");
            }
            let albedo_ok =
                (0..4).all(|c| (f64::from(gpu.albedo[c]) - f64::from(vertex.albedo[c])).abs() * 255.0 <= 1.0);
            (!albedo_ok).then_some("albedo or specular weight")
        }
    }
}

fn run(ctx: &mut Ctx) -> Result<Outcome> {
    let size = ctx.params.size("size")?;
    let scene = corridor(ctx.params.count_u32("seed")?, 1);
    let inputs = DeferredInputs::new(ctx.gpu, &scene, size)?;
    let surfaces = read_surfaces(ctx.gpu, &inputs.gbuffer)?;

    let model = SurfaceModel::new(&scene, size);
    let expected = model.expected(SUBPIXEL);
    let problems: Vec<Option<&str>> = expected.iter().zip(&surfaces).map(|(e, g)| check(&model, *e, g)).collect();

    let count = |f: &dyn Fn(&ExpectedPixel) -> bool| expected.iter().filter(|e| f(e)).count();
    ctx.metric("surface_pixels", count(&|e| matches!(e, ExpectedPixel::Surface { .. })));
    ctx.metric("background_pixels", count(&|e| *e == ExpectedPixel::Background));
    ctx.metric("ambiguous_pixels_left_out", count(&|e| *e == ExpectedPixel::Ambiguous));
    let mut kinds: Vec<&str> = problems.iter().flatten().copied().collect();
    let wrong_count = kinds.len();
    ctx.metric("wrong_pixels", wrong_count);
    if wrong_count == 0 {
        return Ok(Outcome::Pass);
    }
    kinds.sort_unstable();
    kinds.dedup();
    let albedo_of = |s: &Surface| [s.albedo[0], s.albedo[1], s.albedo[2]];
    let result: Vec<[f32; 3]> = surfaces.iter().map(albedo_of).collect();
    let reference: Vec<[f32; 3]> = expected
        .iter()
        .map(|e| match e {
            ExpectedPixel::Surface { triangle, .. } => {
                let a = model.vertex(*triangle).albedo;
                [a[0], a[1], a[2]]
            }
            _ => [0.0; 3],
        })
        .collect();
    let wrong: Vec<bool> = problems.iter().map(Option::is_some).collect();
    let reference = ldr_to_display(size.0, size.1, &reference)?;
    ctx.evidence_image(
        "albedo",
        &side_by_side(&ldr_to_display(size.0, size.1, &result)?, &reference, &error_mask(&reference, &wrong)),
    )?;
    Ok(Outcome::Fail(format!(
        "{wrong_count} of {} pixels differ from the ray cast ({})",
        size.0 * size.1,
        kinds.join(", ")
    )))
}
