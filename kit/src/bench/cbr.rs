//! Checkerboard rendering against full resolution where pixel shading dominates: the static
//! textured corridor with 200 lights at 320×180, CSO, forward and deferred shading, on the exact
//! offset-pass path and, where the kit measured a real one, the 2x MSAA path. Each is timed
//! against full resolution shaded the same way — forward against forward, deferred against
//! deferred — so that the speed-up is what checkerboarding saves, not what deferred shading saves
//! (overdraw) — and rasterised as the checkerboard's views are: turned a quarter for the offset
//! passes (then turned back upright by one more pass), upright for the 2x path. Every baseline's
//! time is printed. GPU time of a whole frame from timestamp queries around every pass.

use anyhow::Result;

use super::{Bench, Sample, require_timestamps};
use crate::cbr::sampling::CheckerboardPath;
use crate::cbr::scene::{Motion, textured_corridor};
use crate::cbr::{Checkerboard, CheckerboardConfig, FullResolutionScene, Orientation, Shading};
use crate::gpu::Gpu;

pub const SIZE: (u32, u32) = (320, 180);
pub const LIGHTS: u32 = 200;

pub struct CbrBench {
    /// Full resolution in each of `BASELINES`.
    full_resolution: Vec<FullResolutionScene>,
    /// Each path this adapter has × `Shading::ALL`.
    renderers: Vec<Checkerboard>,
    /// Each renderer's last frame index: its own sequence, so that every frame has the one
    /// before it as history and the phases alternate.
    frames: Vec<u32>,
}

/// The full-resolution baselines, in variant order.
const BASELINES: [(Shading, Orientation); 4] = [
    (Shading::Forward, Orientation::Upright),
    (Shading::Deferred, Orientation::Upright),
    (Shading::Forward, Orientation::Turned),
    (Shading::Deferred, Orientation::Turned),
];

impl CbrBench {
    pub fn new(gpu: &Gpu) -> Result<Self> {
        require_timestamps(gpu, "cbr")?;
        let scene = textured_corridor(5, LIGHTS, Motion::Static);
        let mut paths = vec![CheckerboardPath::OffsetPasses];
        if CheckerboardPath::for_adapter(gpu) == CheckerboardPath::Msaa2x {
            paths.push(CheckerboardPath::Msaa2x);
        }
        let full_resolution = BASELINES
            .iter()
            .map(|&(shading, orientation)| FullResolutionScene::shaded(gpu, &scene, SIZE, shading, orientation))
            .collect::<Result<_>>()?;
        let renderers: Vec<Checkerboard> = paths
            .iter()
            .flat_map(|&path| Shading::ALL.map(|shading| (path, shading)))
            .map(|(path, shading)| Checkerboard::new(gpu, &scene, CheckerboardConfig::new(SIZE, path, shading)))
            .collect::<Result<_>>()?;
        let frames = vec![0; renderers.len()];
        Ok(Self { full_resolution, renderers, frames })
    }
}

impl Bench for CbrBench {
    fn name(&self) -> String {
        format!("{}x{}_{LIGHTS}_lights", SIZE.0, SIZE.1)
    }

    fn variants(&self) -> Vec<String> {
        // Upright baselines keep the names they had before the offset passes turned.
        let baseline_name = |(shading, orientation): &(Shading, Orientation)| match orientation {
            Orientation::Upright => format!("full_resolution_{}", shading.name()),
            Orientation::Turned => format!("full_resolution_{}_turned", shading.name()),
        };
        let renderer_name = |r: &Checkerboard| format!("{}_{}", r.plan().path.name(), r.plan().shading.name());
        BASELINES.iter().map(baseline_name).chain(self.renderers.iter().map(renderer_name)).collect()
    }

    fn baseline(&self, variant: usize) -> usize {
        let Some(renderer) = variant.checked_sub(BASELINES.len()).map(|r| &self.renderers[r]) else {
            return variant;
        };
        let plan = renderer.plan();
        let baseline = (plan.shading, plan.path.orientation());
        BASELINES.iter().position(|&b| b == baseline).expect("every baseline is listed")
    }

    fn run(&mut self, gpu: &Gpu, variant: usize) -> Result<Sample> {
        let baselines = BASELINES.len();
        if variant < baselines {
            return Ok(Sample::gpu_ms(self.full_resolution[variant].render(gpu, 0)?));
        }
        // Successive frames of a renderer alternate the checkerboard's phase and reconstruct
        // from the one before, as in a real sequence.
        let index = variant - baselines;
        self.frames[index] += 1;
        let frame = self.renderers[index].render(gpu, self.frames[index])?;
        // Where the time goes: scene passes (shading) and the reconstruction.
        let reconstruct: f64 = frame
            .passes
            .iter()
            .zip(&frame.pass_ms)
            .filter(|(p, _)| p.starts_with("reconstruct"))
            .map(|(_, ms)| ms)
            .sum();
        Ok(Sample {
            gpu_ms: frame.gpu_ms,
            parts: vec![("scene_ms", frame.gpu_ms - reconstruct), ("reconstruct_ms", reconstruct)],
            counts: Vec::new(),
        })
    }
}
