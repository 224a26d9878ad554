//! Coarse pixel shading against full-resolution deferred shading: the corridor with 200 lights
//! at 640×360, foveated LOD (top level 5), nearest composite; the default fovea (inner radius
//! 24 px) and two wider ones, whose ideal speed-ups are lower. GPU time from timestamp queries
//! around every pass (CPS: the LOD and pyramid passes where the policy has them, "build"; the
//! stencil marks and lighting, one pass; the composite; full resolution: its lighting pass), the
//! G-buffer excluded from both. Each CPS variant is set against the ideal speed-up its
//! shaded texel count implies, with where the rest goes (the fixed passes, the cost per shaded
//! texel). Where the adapter's occlusion queries only say whether a level shaded (GL), there is
//! no texel count and so no ideal to set a variant against.

use std::collections::BTreeMap;

use anyhow::Result;

use super::{Bench, Sample, VariantSummary, require_timestamps};
use crate::cps::renderer::CpsFrame;
use crate::cps::{CompositeMode, CpsConfig, CpsRenderer, LodPolicy};
use crate::deferred::DeferredInputs;
use crate::deferred::lighting::FullResolution;
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
    /// The occlusion queries count texels (kit.occlusion.exact), so the frame's shaded texels
    /// are known.
    counts_texels: bool,
}

impl CpsBench {
    pub fn new(gpu: &Gpu) -> Result<Self> {
        require_timestamps(gpu, "cps")?;
        let inputs = DeferredInputs::new(gpu, &corridor(1, LIGHTS), SIZE)?;
        let renderers = INNER_RADII
            .iter()
            .map(|&inner_radius| {
                let policy = LodPolicy::Foveated { focus: (0.5, 0.5), inner_radius };
                Ok((inner_radius, CpsRenderer::new(gpu, SIZE, CpsConfig::new(5, policy, CompositeMode::Nearest))?))
            })
            .collect::<Result<_>>()?;
        let counts_texels = measure_occlusion_precision(gpu)? == OcclusionPrecision::Exact;
        Ok(Self { full_resolution: FullResolution::new(gpu, SIZE), inputs, renderers, counts_texels })
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
        Ok(Sample {
            gpu_ms: out.gpu_ms(""),
            parts: vec![
                ("build_ms", out.gpu_ms("lod") + out.gpu_ms("pyramid")),
                ("lighting_ms", out.gpu_ms("light")),
                ("composite_ms", out.gpu_ms("composite")),
            ],
            counts: [("shaded_texels", out.shaded_texels.iter().sum()), ("render_passes", out.pass_times.len() as u64)]
                .into_iter()
                .filter(|&(count, _)| self.counts_texels || count != "shaded_texels")
                .collect(),
        })
    }

    fn explain(&self, variant: &VariantSummary, baseline: &VariantSummary) -> (BTreeMap<String, f64>, Option<String>) {
        // Only the CPS variants count their passes; full resolution has nothing to explain.
        let Some(&passes) = variant.counts.get("render_passes") else { return (BTreeMap::new(), None) };
        let Some(&shaded) = variant.counts.get("shaded_texels") else {
            let why = "no ideal: this adapter's occlusion queries say only whether a level shaded, not how many texels (kit.occlusion.exact)";
            return (BTreeMap::new(), Some(format!("{why}; {passes} render passes")));
        };
        let pixels = f64::from(SIZE.0 * SIZE.1);
        let ideal = pixels / shaded as f64;
        let lighting = variant.parts.get("lighting_ms").copied().unwrap_or(0.0);
        let full_ms = baseline.median_ms;
        // Lighting cost per shaded texel relative to full resolution's per pixel: 1 is the
        // ideal; the fixed passes are the rest of the gap.
        let texel_cost = (lighting / shaded as f64) / (full_ms / pixels);
        let derived = BTreeMap::from([
            ("ideal_speedup".to_owned(), ideal),
            ("fraction_of_ideal".to_owned(), variant.speedup / ideal),
            ("texel_cost_in_full_resolution_pixels".to_owned(), texel_cost),
        ]);
        let percent = |speedup: f64| 100.0 * speedup / ideal;
        let interval = variant.speedup_interval;
        let sentence = format!(
            "ideal {ideal:.2}x from {shaded} shaded texels: {:.0} % of ideal ({:.0}–{:.0} %); a shaded texel costs {texel_cost:.2} full-resolution pixels; {passes} render passes",
            percent(variant.speedup),
            percent(interval.low),
            percent(interval.high)
        );
        (derived, Some(sentence))
    }
}
