//! `cps.composite.matches_reference`: the GPU composites (nearest, the original 4-neighbour
//! interpolation, our seam-free one) equal a CPU implementation of the same equations, fed with
//! the GPU's own LOD buffer and lit levels, within 1/1024 (relative above 1: the f16 targets keep
//! 11 significant bits). Also records each mode's seam error: how far the colour step between
//! neighbouring pixels of different levels departs from full resolution's; ours must score below
//! the original 4-neighbour interpolation.

use anyhow::Result;
use fragkit::cps::reference::{CompositeInputs, Level, seam_error};
use fragkit::cps::{CompositeMode, CpsConfig, CpsRenderer, LodPolicy};
use fragkit::deferred::lighting::light_full_resolution;
use fragkit::harness::{Case, Ctx, Outcome, ParamKind, ParamSpec};
use fragkit::readback::read_texture;

use super::{corridor_inputs, frame, random_lod};

pub const CASE: Case = Case {
    name: "cps.composite.matches_reference",
    summary: "the three GPU composites equal their CPU equations within 1/1024",
    requires: wgpu::Features::empty(),
    params: &[
        ParamSpec { name: "size", kind: ParamKind::Sizes, default: "64x48", help: "screen size" },
        ParamSpec { name: "lights", kind: ParamKind::CountIn(1, 4096), default: "24", help: "point lights" },
        ParamSpec { name: "max_level", kind: ParamKind::CountIn(0, 8), default: "4", help: "coarsest level" },
    ],
    sweep: &[],
    run,
};

/// Allowed difference: 1/1024 absolute, relative above 1.
fn within_tolerance(gpu: f32, cpu: f32) -> bool {
    (gpu - cpu).abs() <= cpu.abs().max(1.0) / 1024.0
}

fn as_texels(values: &[f32]) -> Vec<[f32; 4]> {
    values.chunks_exact(4).map(|c| [c[0], c[1], c[2], c[3]]).collect()
}

fn run(ctx: &mut Ctx) -> Result<Outcome> {
    let size = ctx.params.sizes("size")?[0];
    let max_level = u32::try_from(ctx.params.count("max_level")?)?;
    let inputs = corridor_inputs(ctx.gpu, size, u32::try_from(ctx.params.count("lights")?)?, 2)?;
    let fullres = light_full_resolution(ctx.gpu, &inputs)?;
    let reference = as_texels(&read_texture(ctx.gpu, &fullres, wgpu::TextureAspect::All, 0)?.as_f16());

    let mut problems = Vec::new();
    let mut seams = std::collections::BTreeMap::new();
    let policies = [
        ("foveated", LodPolicy::Foveated { focus: (0.4, 0.5), inner_radius: 5.0 }),
        ("random", LodPolicy::Explicit(random_lod(size, 9))),
    ];
    for (name, policy) in policies {
        for composite in CompositeMode::ALL {
            let renderer = CpsRenderer::new(ctx.gpu, size, CpsConfig::new(max_level, policy.clone(), composite))?;
            renderer.render(ctx.gpu, &frame(&inputs))?;
            let gpu_image = as_texels(&renderer.read_image(ctx.gpu)?);

            // Expected: the CPU composite of the GPU's own inputs.
            let lod = renderer.read_lod(ctx.gpu)?;
            let lit: Vec<Level> = (0..renderer.plan.levels())
                .map(|l| {
                    Ok(Level {
                        extent: renderer.plan.level_extents[l as usize],
                        texels: as_texels(&renderer.read_lit_level(ctx.gpu, l)?),
                    })
                })
                .collect::<Result<_>>()?;
            let cpu_image = CompositeInputs { screen: size, lod: &lod, lit: &lit }.composite(composite);

            let worst = gpu_image
                .iter()
                .zip(&cpu_image)
                .flat_map(|(g, c)| (0..3).map(move |i| (g[i] - c[i]).abs() / c[i].abs().max(1.0)))
                .fold(0.0f32, f32::max);
            let wrong =
                gpu_image.iter().zip(&cpu_image).filter(|(g, c)| (0..3).any(|i| !within_tolerance(g[i], c[i]))).count();
            let seam = seam_error(size, &lod, &gpu_image, &reference);
            ctx.metric(&format!("{name}.{}", composite.name()), serde_json::json!({"worst_relative_difference": worst, "pixels_out_of_tolerance": wrong, "seam_error": seam}));
            if wrong > 0 {
                problems.push(format!(
                    "{name} {}: {wrong} pixels differ from the CPU equations (worst {worst:.2e})",
                    composite.name()
                ));
            }
            seams.insert((name, composite.name()), seam);
        }
        // Ours must keep level changes smoother than the original interpolation does.
        let (ours, original) = (seams[&(name, "seam_free")], seams[&(name, "four_neighbour")]);
        if ours >= original {
            problems.push(format!(
                "{name}: seam-free composite's seam error {ours:.5} is not below the 4-neighbour one's {original:.5}"
            ));
        }
    }
    Ok(if problems.is_empty() { Outcome::Pass } else { Outcome::Fail(problems.join("; ")) })
}
