//! Coarse pixel shading against full-resolution deferred shading: the corridor with 200 lights
//! at 640×360, foveated LOD (top level 5), nearest composite; the default fovea (inner radius
//! 24 px) and two wider ones, whose ideal speed-ups are lower. GPU time from timestamp queries
//! around every pass (CPS: the LOD and pyramid passes where the policy has them, "build"; the
//! stencil marks and lighting, one pass; the composite; full resolution: its lighting pass), the
//! G-buffer excluded from both. Each CPS variant is set against the ideal speed-up its
//! shaded texel count implies, with where the rest goes (the fixed passes, the cost per shaded
//! texel). Where the adapter's occlusion queries only say whether a level shaded (GL), there is
//! no texel count and so no ideal to set a variant against.
//!
//! The ideal assumes a shaded texel costs what a full-resolution pixel does. Each round also
//! times the variant's own samples — the G-buffer samples its texels light, per the CPU model of
//! the foveated LOD, gathered into a small G-buffer — lit by the full-resolution pass itself: what
//! shading exactly those samples costs on this adapter with nothing of CPS around them: a
//! reference for the speed-up with CPS's own passes, marks and composite taken away. Not a bound:
//! the gathered samples lie in another order, and on lavapipe a small pass costs more per pixel
//! than a large one.

use std::collections::BTreeMap;

use anyhow::Result;

use super::{Bench, Sample, VariantSummary, require_timestamps};
use crate::cps::lod_model::foveated;
use crate::cps::reference::shaded_samples;
use crate::cps::renderer::CpsFrame;
use crate::cps::{CompositeMode, CpsConfig, CpsRenderer, LodPolicy};
use crate::deferred::DeferredInputs;
use crate::deferred::gbuffer::gather;
use crate::deferred::lighting::FullResolution;
use crate::deferred::lights::LightTexture;
use crate::gpu::Gpu;
use crate::probe::occlusion::{OcclusionPrecision, measure_occlusion_precision};
use crate::query::GpuTimer;
use crate::scene::corridor::corridor;

pub const SIZE: (u32, u32) = (640, 360);
pub const LIGHTS: u32 = 200;
/// Foveation inner radii in pixels; the first is the policy's default.
pub const INNER_RADII: [f32; 3] = [24.0, 48.0, 96.0];

pub struct CpsBench {
    inputs: DeferredInputs,
    full_resolution: FullResolution,
    renderers: Vec<(f32, CpsRenderer)>,
    /// Per renderer, its samples gathered, the full-resolution pass at their size, and how many
    /// samples the model gives.
    samples: Vec<(DeferredInputs, FullResolution, u64)>,
    /// The occlusion queries count texels (kit.occlusion.exact), so the frame's shaded texels
    /// are known.
    counts_texels: bool,
}

impl CpsBench {
    pub fn new(gpu: &Gpu) -> Result<Self> {
        require_timestamps(gpu, "cps")?;
        let scene = corridor(1, LIGHTS);
        let inputs = DeferredInputs::new(gpu, &scene, SIZE)?;
        let focus = (0.5, 0.5);
        let renderers: Vec<(f32, CpsRenderer)> = INNER_RADII
            .iter()
            .map(|&inner_radius| {
                let policy = LodPolicy::Foveated { focus, inner_radius };
                Ok((inner_radius, CpsRenderer::new(gpu, SIZE, CpsConfig::new(5, policy, CompositeMode::Nearest))?))
            })
            .collect::<Result<_>>()?;
        let samples = renderers
            .iter()
            .map(|(inner_radius, renderer)| {
                let top = renderer.plan.top_level;
                let lod = foveated(SIZE, focus, *inner_radius, top).levels;
                let pixels = shaded_samples(SIZE, &lod, top);
                let gbuffer = gather(gpu, &inputs.gbuffer, &pixels)?;
                let lighting = FullResolution::new(gpu, gbuffer.size);
                let lights = LightTexture::new(gpu, &scene.lights)?;
                Ok((DeferredInputs { gbuffer, lights, eye: inputs.eye }, lighting, pixels.len() as u64))
            })
            .collect::<Result<_>>()?;
        let counts_texels = measure_occlusion_precision(gpu)? == OcclusionPrecision::Exact;
        Ok(Self { full_resolution: FullResolution::new(gpu, SIZE), inputs, renderers, samples, counts_texels })
    }
}

impl Bench for CpsBench {
    fn name(&self) -> String {
        format!("{}x{}_{LIGHTS}_lights", SIZE.0, SIZE.1)
    }

    fn variants(&self) -> Vec<String> {
        std::iter::once("full_resolution".to_owned())
            .chain(self.renderers.iter().map(|(radius, _)| format!("foveated_r{radius}")))
            .collect()
    }

    fn baseline(&self, _variant: usize) -> usize {
        0
    }

    fn run(&mut self, gpu: &Gpu, variant: usize) -> Result<Sample> {
        if variant == 0 {
            let mut timer = GpuTimer::new(gpu, 1);
            self.full_resolution.render(gpu, &self.inputs, &mut timer)?;
            return Ok(Sample::gpu_ms(timer.read(gpu)?.iter().map(|t| t.ms).sum()));
        }
        let frame = CpsFrame { gbuffer: &self.inputs.gbuffer, lights: &self.inputs.lights, eye: self.inputs.eye };
        let out = self.renderers[variant - 1].1.render(gpu, &frame)?;
        let (samples, lighting, modelled) = &self.samples[variant - 1];
        let mut timer = GpuTimer::new(gpu, 1);
        lighting.render(gpu, samples, &mut timer)?;
        let samples_ms = timer.read(gpu)?.iter().map(|t| t.ms).sum();
        Ok(Sample {
            gpu_ms: out.gpu_ms(""),
            parts: vec![
                ("build_ms", out.gpu_ms("lod") + out.gpu_ms("pyramid")),
                ("lighting_ms", out.gpu_ms("light")),
                ("composite_ms", out.gpu_ms("composite")),
                // Not part of the frame: its samples alone, lit at full resolution.
                ("samples_alone_ms", samples_ms),
            ],
            counts: [
                ("shaded_texels", out.shaded_texels.iter().sum()),
                ("modelled_samples", *modelled),
                ("render_passes", out.pass_times.len() as u64),
            ]
            .into_iter()
            .filter(|&(count, _)| self.counts_texels || count != "shaded_texels")
            .collect(),
        })
    }

    fn explain(&self, variant: &VariantSummary, baseline: &VariantSummary) -> (BTreeMap<String, f64>, Option<String>) {
        // Only the CPS variants count their passes; full resolution has nothing to explain.
        let Some(&passes) = variant.counts.get("render_passes") else { return (BTreeMap::new(), None) };
        let pixels = f64::from(SIZE.0 * SIZE.1);
        let full_ms = baseline.median_ms;
        let mut derived = BTreeMap::new();
        let mut said = Vec::new();
        match variant.counts.get("shaded_texels") {
            Some(&shaded) => {
                let ideal = pixels / shaded as f64;
                let lighting = variant.parts.get("lighting_ms").copied().unwrap_or(0.0);
                // Lighting cost per shaded texel relative to full resolution's per pixel: 1 is the
                // ideal; the fixed passes are the rest of the gap.
                let texel_cost = (lighting / shaded as f64) / (full_ms / pixels);
                derived.insert("ideal_speedup".to_owned(), ideal);
                derived.insert("fraction_of_ideal".to_owned(), variant.speedup / ideal);
                derived.insert("texel_cost_in_full_resolution_pixels".to_owned(), texel_cost);
                let percent = |speedup: f64| 100.0 * speedup / ideal;
                let interval = variant.speedup_interval;
                said.push(format!(
                    "ideal {ideal:.2}x from {shaded} shaded texels: {:.0} % of ideal ({:.0}–{:.0} %); a shaded texel costs {texel_cost:.2} full-resolution pixels",
                    percent(variant.speedup),
                    percent(interval.low),
                    percent(interval.high)
                ));
            }
            None => said.push(
                "no ideal from texel counts: this adapter's occlusion queries say only whether a level shaded (kit.occlusion.exact)"
                    .to_owned(),
            ),
        }
        if let (Some(&samples), Some(&alone_ms)) =
            (variant.counts.get("modelled_samples"), variant.parts.get("samples_alone_ms"))
        {
            let sample_cost = (alone_ms / samples as f64) / (full_ms / pixels);
            let reachable = full_ms / alone_ms;
            derived.insert("sample_alone_cost_in_full_resolution_pixels".to_owned(), sample_cost);
            derived.insert("reachable_speedup".to_owned(), reachable);
            derived.insert("fraction_of_reachable".to_owned(), variant.speedup / reachable);
            said.push(format!(
                "its {samples} samples lit alone by the full-resolution pass cost {sample_cost:.2} pixels each: {reachable:.2}x reachable, {:.0} % of it",
                100.0 * variant.speedup / reachable
            ));
        }
        said.push(format!("{passes} render passes"));
        (derived, Some(said.join("; ")))
    }
}
