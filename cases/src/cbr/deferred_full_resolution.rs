//! `cbr.deferred_full_resolution`: the baseline deferred checkerboarding is timed against
//! (`DeferredFullResolution`: a full-resolution G-buffer, then `fs_shade_full_resolution` in
//! `shaders/cbr/shade_samples.wgsl` at every pixel; and rasterised turned a quarter as the bench
//! times it, `fs_shade_full_resolution_turned`, then `shaders/cbr/turn_back.wgsl`) shades each
//! pixel of its upright output as its definition says: the
//! Phong of its G-buffer sample at the world point its depth puts under the pixel centre. A
//! baseline that shaded the wrong point would make every deferred speed-up and error figure
//! quote a different frame. The expectation is the CPU Phong (`fragkit::deferred::phong`, f64,
//! the scene's own light list) of the read-back normal and albedo at the world point unprojected
//! in f64 from the read-back depth and the frame's view-projection. Bound: the Phong model's
//! derived bound, plus what the GPU's f32 unprojection may move the point by — each homogeneous
//! component off by the f32 inverse's own error (computed here against the f64 inverse) and 2^-21
//! of the sum of its terms' magnitudes (seven roundings), then divided by w, whose terms cancel
//! far from the eye — taken as the largest change of the CPU shading over a step of that size
//! along each axis, summed over the axes. Unlit surfaces must give their albedo and
//! empty pixels the background, within one f16 ulp. The scene is the bench's textured corridor
//! without its glass panes (transparents are drawn forward on top, by the forward path's own
//! pipeline, which the reconstruction cases check).

use anyhow::Result;
use fragkit::cbr::scene::{Motion, textured_corridor};
use fragkit::cbr::{FullResolutionScene, Orientation, Shading};
use fragkit::deferred::phong::{PhongComparison, ShadedSample, Surface, shade};
use fragkit::harness::{Case, Ctx, Outcome, ParamKind, ParamSpec, Sweep, SweepRange, Verdict};
use fragkit::depth_readback::read_depth;
use fragkit::readback::read_texture;
use fragkit::shaders::{CBR_SCENE, CBR_SHADE_SAMPLES, CBR_TURN_BACK, DEPTH_BITS, FULLSCREEN};
use glam::{DMat4, DVec3, DVec4};

pub const CASE: Case = Case {
    name: "cbr.deferred_full_resolution",
    summary: "the deferred full-resolution baseline shades each pixel's G-buffer sample at its own centre",
    requires: wgpu::Features::empty(),
    params: &[
        ParamSpec { name: "size", kind: ParamKind::SizeFrom(1), default: "96x64", help: "screen size" },
        ParamSpec { name: "lights", kind: ParamKind::CountIn(1, 4096), default: "32", help: "point lights" },
    ],
    sweep: &[
        Sweep { param: "size", range: SweepRange::Size { min: (1, 1), max: (160, 120) } },
        Sweep { param: "lights", range: SweepRange::Count(1, 4096) },
    ],
    budget_s: 1,
    timed_verdict: false,
    shaders: &[FULLSCREEN, DEPTH_BITS, CBR_SCENE, CBR_SHADE_SAMPLES, CBR_TURN_BACK],
    run,
};

/// Rounding of one row of the f32 unprojection (four products, three sums: seven roundings of
/// half an ulp) against the sum of its terms' magnitudes.
const PRODUCT_ROUNDING: f64 = 1.0 / (1u64 << 21) as f64;

/// The exact world point of `ndc`, and how far, per axis, the GPU's f32 unprojection may land
/// from it: each homogeneous component off by the f32 inverse's own error (`gpu` against
/// `exact`, known here) and the product's rounding, then divided by w (whose terms cancel far
/// from the eye, where the depth nears 1).
fn unproject(gpu: &DMat4, exact: &DMat4, ndc: DVec4) -> (DVec3, DVec3) {
    let row_error = |r: usize| {
        (0..4)
            .map(|c| {
                let (g, e) = (gpu.col(c)[r], exact.col(c)[r]);
                ((g - e) * ndc[c]).abs() + PRODUCT_ROUNDING * (g * ndc[c]).abs()
            })
            .sum::<f64>()
    };
    let clip = *exact * ndc;
    let point = clip.truncate() / clip.w;
    let w_error = row_error(3);
    let axis = |r: usize| (row_error(r) + point[r].abs() * w_error) / (clip.w.abs() - w_error);
    (point, DVec3::new(axis(0), axis(1), axis(2)))
}

fn f32x4(v: DVec3, w: f32) -> [f32; 4] {
    [v.x as f32, v.y as f32, v.z as f32, w]
}

fn run(ctx: &mut Ctx) -> Result<Outcome> {
    let size = ctx.params.size("size")?;
    let lights = ctx.params.count_u32("lights")?;
    let mut scene = textured_corridor(5, lights, Motion::Static);
    scene.draws.retain(|draw| !draw.transparent);

    let mut verdict = Verdict::new();
    // Upright, and turned a quarter as the offset passes draw (the bench's baseline): there
    // upright pixel (x, y) sits at texel (y, W − 1 − x) of an H-wide target.
    for orientation in [Orientation::Upright, Orientation::Turned] {
        let turned = orientation == Orientation::Turned;
        // The upright pixel of a rasterised texel.
        let pixel_of = |i: u32| if turned { (size.0 - 1 - i / size.1, i % size.1) } else { (i % size.0, i / size.0) };
        let mut frame = FullResolutionScene::shaded(ctx.gpu, &scene, size, Shading::Deferred, orientation)?;
        frame.render(ctx.gpu, 0)?;
        let baseline = frame.deferred().expect("a deferred frame");
        let all = wgpu::TextureAspect::All;
        let colour = read_texture(ctx.gpu, frame.output(), all, 0)?.as_f16();
        let normal = read_texture(ctx.gpu, &baseline.gbuffer[0], all, 0)?.as_f16();
        let albedo = read_texture(ctx.gpu, &baseline.gbuffer[1], all, 0)?.bytes;
        let depth = read_depth(ctx.gpu, &baseline.depth)?;

        // Expected: the Phong of each sample at the point under its pixel centre.
        let view = scene.frame_view(0, size);
        let world_from_clip = view.full_from_world.as_dmat4().inverse();
        // What the shade pass multiplies by: the f32 inverse (`shading_uniform`).
        let gpu_world_from_clip = view.full_from_world.inverse().as_dmat4();
        let (w, h) = (f64::from(size.0), f64::from(size.1));
        // In upright order, as the output is.
        let mut expected = vec![None; depth.len()];
        for (i, &d) in depth.iter().enumerate() {
            let (px, py) = pixel_of(i as u32);
            let slot = &mut expected[(py * size.0 + px) as usize];
            let n = &normal[4 * i..4 * i + 4];
            let a: [f32; 4] = std::array::from_fn(|c| f32::from(albedo[4 * i + c]) / 255.0);
            let surface = |p: DVec3, drawn: bool| Surface {
                position: f32x4(p, if drawn { 1.0 } else { 0.0 }),
                normal: [n[0], n[1], n[2], n[3]],
                albedo: a,
            };
            if n[..3].iter().all(|&v| v == 0.0) {
                *slot = Some(shade(&surface(DVec3::ZERO, false), view.eye, &scene.lights));
                continue;
            }
            if n[3] < 0.0 {
                let colour = [0, 1, 2].map(|c| f64::from(a[c]));
                *slot = Some(ShadedSample { colour, bound: colour.map(|v| v.abs() / 1024.0 + 1e-7) });
                continue;
            }
            let (x, y) = (f64::from(px) + 0.5, f64::from(py) + 0.5);
            let ndc = DVec4::new(2.0 * x / w - 1.0, 1.0 - 2.0 * y / h, f64::from(d), 1.0);
            let (point, step) = unproject(&gpu_world_from_clip, &world_from_clip, ndc);
            let at = |p: DVec3| shade(&surface(p, true), view.eye, &scene.lights);
            let centre = at(point);
            let mut bound = centre.bound;
            for (axis, step) in [(DVec3::X, step.x), (DVec3::Y, step.y), (DVec3::Z, step.z)] {
                let moved = [at(point + axis * step), at(point - axis * step)];
                for (c, channel) in bound.iter_mut().enumerate() {
                    let change =
                        moved.iter().map(|m| (m.colour[c] - centre.colour[c]).abs() + m.bound[c] - centre.bound[c]);
                    *channel += change.fold(0.0, f64::max);
                }
            }
            *slot = Some(ShadedSample { colour: centre.colour, bound });
        }
        let expected: Vec<ShadedSample> = expected.into_iter().map(|e| e.expect("every texel is a pixel")).collect();

        let comparison = PhongComparison::new(&expected, &colour);
        let name = orientation.name();
        let metric = |what: &str| if turned { format!("{name}.{what}") } else { what.to_owned() };
        ctx.metric(&metric("pixels_beyond_bound"), comparison.wrong_count);
        ctx.metric(&metric("worst_error_in_bounds"), comparison.worst);
        if comparison.wrong_count > 0 {
            ctx.evidence_image(&format!("comparison_{name}"), &comparison.evidence(size, &expected, &colour)?)?;
            verdict.fail(format!(
                "{name}: {} of {} pixels differ from the CPU Phong at their own centre beyond the bound (worst {:.1}x)",
                comparison.wrong_count,
                size.0 * size.1,
                comparison.worst
            ));
        }
    }
    Ok(verdict.outcome())
}
