//! `cps.extremes`: stiff inputs stay finite and exact. 200 lights on a 1×1 screen; every pixel at
//! level 8 on a 300×200 screen (fragments larger than the screen); lights placed exactly on
//! surface points the G-buffer holds (distance 0). No NaN or Inf may reach any lit level or
//! composite, and each level's occlusion count is what the policy's definition (its CPU model,
//! not the GPU's LOD buffer) says it must shade: exact where queries count, else the Boolean
//! answer a conservative query must give.

use anyhow::Result;
use fragkit::cps::lod_model::model;
use fragkit::cps::reference::expected_shaded_texels;
use fragkit::cps::{CompositeMode, CpsConfig, CpsRenderer, LodPolicy, MAX_LEVEL};
use fragkit::deferred::DeferredInputs;
use fragkit::deferred::lights::LightTexture;
use fragkit::deferred::phong::read_surfaces;
use fragkit::harness::{Case, Ctx, Outcome, Verdict};
use fragkit::probe::occlusion::{OcclusionPrecision, measure_occlusion_precision};
use fragkit::readback::read_texture;
use fragkit::scene::corridor::{Light, corridor};
use fragkit::shaders::{CPS_COMPOSITE, CPS_LIGHTING, CPS_LOD, CPS_MASK_REDUCE, CPS_STENCIL_MARK, FRAGMENT_STORAGE, FULLSCREEN, GBUFFER, INDIRECT_DRAW, RECT};

use super::{corridor_inputs, frame};

pub const CASE: Case = Case {
    name: "cps.extremes",
    summary: "1x1 with 200 lights, level 8 past the screen, lights on surfaces: finite and exact",
    requires: wgpu::Features::empty(),
    params: &[],
    sweep: &[],
    budget_s: 3,
    timed_verdict: false,
    shaders: &[RECT, FULLSCREEN, FRAGMENT_STORAGE, INDIRECT_DRAW, GBUFFER, CPS_LOD, CPS_MASK_REDUCE, CPS_LIGHTING, CPS_COMPOSITE, CPS_STENCIL_MARK],
    run,
};

/// Renders every composite mode, recording in `verdict` what is wrong (non-finite values,
/// wrong counts).
fn check_all_modes(
    ctx: &mut Ctx,
    verdict: &mut Verdict,
    name: &str,
    inputs: &DeferredInputs,
    policy: LodPolicy,
    precision: OcclusionPrecision,
) -> Result<()> {
    let size = inputs.gbuffer.size;
    let surfaces = read_surfaces(ctx.gpu, &inputs.gbuffer)?;
    for composite in CompositeMode::ALL {
        let renderer = CpsRenderer::new(ctx.gpu, size, CpsConfig::new(MAX_LEVEL, policy.clone(), composite))?;
        let output = renderer.render(ctx.gpu, &frame(inputs))?;
        let mut values = renderer.read_image(ctx.gpu)?;
        for level in 0..renderer.plan.levels() {
            values.extend(renderer.read_lit_level(ctx.gpu, level)?);
        }
        let non_finite = values.iter().filter(|v| !v.is_finite()).count();
        // Expected: the policy's definition, evaluated on the CPU.
        let lod = model(&policy, size, &surfaces, inputs.eye, renderer.plan.top_level);
        anyhow::ensure!(
            !lod.ambiguous.contains(&true),
            "{name}: the scene puts pixels on a level boundary f32 cannot decide; it must not"
        );
        let expected = expected_shaded_texels(size, &lod.levels, renderer.plan.top_level);
        ctx.metric(
            &format!("{name}.{}", composite.name()),
            serde_json::json!({"non_finite": non_finite, "shaded": output.shaded_texels, "expected": expected}),
        );
        if non_finite > 0 {
            verdict.fail(format!("{name} {}: {non_finite} non-finite values", composite.name()));
        }
        let counts_hold = output.shaded_texels.len() == expected.len()
            && output.shaded_texels.iter().zip(&expected).all(|(&m, &e)| precision.allows(m, e));
        if !counts_hold {
            verdict.fail(format!(
                "{name} {}: occlusion queries answered {:?} per level, where {expected:?} texels must be shaded \
                 ({precision:?} queries)",
                composite.name(),
                output.shaded_texels
            ));
        }
    }
    Ok(())
}

fn run(ctx: &mut Ctx) -> Result<Outcome> {
    let precision = measure_occlusion_precision(ctx.gpu)?;
    let mut verdict = Verdict::new();

    let tiny = corridor_inputs(ctx.gpu, (1, 1), 200, 5)?;
    check_all_modes(ctx, &mut verdict, "1x1_200_lights", &tiny, LodPolicy::foveated(), precision)?;

    let wide = corridor_inputs(ctx.gpu, (300, 200), 8, 5)?;
    check_all_modes(
        ctx,
        &mut verdict,
        "300x200_all_level_8",
        &wide,
        LodPolicy::Explicit(vec![8; 300 * 200]),
        precision,
    )?;

    // Lights moved onto surface points the G-buffer holds, bit for bit: distance exactly 0 there.
    // Shading must be finite and continuous: as if each light sat 1 mm above its point along the
    // surface normal (the limit the shader's distance-0 rule stands for).
    let size = (48, 32);
    let mut scene = corridor(6, 16);
    let mut inputs = corridor_inputs(ctx.gpu, size, 16, 6)?;
    let positions = read_texture(ctx.gpu, &inputs.gbuffer.position, wgpu::TextureAspect::All, 0)?.as_f32();
    let normals = read_texture(ctx.gpu, &inputs.gbuffer.normal, wgpu::TextureAspect::All, 0)?.as_f16();
    let pixels: Vec<usize> = (0..scene.lights.len()).map(|i| (i * 97) % (size.0 * size.1) as usize).collect();
    let mut lifted = scene.clone();
    for ((light, lifted), &pixel) in scene.lights.iter_mut().zip(lifted.lights.iter_mut()).zip(&pixels) {
        let at = |v: &[f32]| glam::Vec3::new(v[pixel * 4], v[pixel * 4 + 1], v[pixel * 4 + 2]);
        // A 5 cm range keeps each light off the other lights' pixels, where a light in the same
        // plane would graze the surface and Phong's specular gate jumps for other reasons.
        light.position = at(&positions);
        light.range = 0.05;
        *lifted = Light { position: at(&positions) + 1e-3 * at(&normals).normalize(), ..*light };
    }
    let all_fine = LodPolicy::Explicit(vec![0; 48 * 32]);
    inputs.lights = LightTexture::new(ctx.gpu, &lifted.lights)?;
    let renderer = CpsRenderer::new(ctx.gpu, size, CpsConfig::new(0, all_fine.clone(), CompositeMode::Nearest))?;
    renderer.render(ctx.gpu, &frame(&inputs))?;
    let limit = renderer.read_image(ctx.gpu)?;
    inputs.lights = LightTexture::new(ctx.gpu, &scene.lights)?;
    check_all_modes(ctx, &mut verdict, "lights_on_surfaces", &inputs, all_fine, precision)?;
    renderer.render(ctx.gpu, &frame(&inputs))?;
    let on_surface = renderer.read_image(ctx.gpu)?;
    // 1 % of the value: the 1 mm lift changes attenuation by 1e-6, the direction by f16 rounding.
    let jumps: Vec<usize> = pixels
        .iter()
        .copied()
        .filter(|&p| {
            (0..3).any(|c| (on_surface[p * 4 + c] - limit[p * 4 + c]).abs() > 0.01 * limit[p * 4 + c].abs().max(1e-3))
        })
        .collect();
    ctx.metric("lights_on_surfaces.discontinuous_pixels", jumps.len());
    if !jumps.is_empty() {
        verdict.fail(format!(
            "lights on surfaces: shading jumps at {} of {} light pixels against lights 1 mm above",
            jumps.len(),
            pixels.len()
        ));
    }

    Ok(verdict.outcome())
}
