//! Checkerboard rendering against full resolution where pixel shading dominates: the static
//! textured corridor with 200 lights at 320×180, CSO, forward and deferred shading, on the exact
//! offset-pass path and, where the kit measured a real one, the 2x MSAA path. Each is timed
//! against full resolution shaded the same way — forward against forward, deferred against
//! deferred — so that the speed-up is what checkerboarding saves, not what deferred shading saves
//! (overdraw); both baselines' times are printed beside them. GPU time of a whole frame from
//! timestamp queries around every pass.

use anyhow::Result;

use super::{Bench, Sample, require_timestamps};
use crate::cbr::sampling::CheckerboardPath;
use crate::cbr::scene::{Motion, textured_corridor};
use crate::cbr::{Checkerboard, CheckerboardConfig, FullResolutionScene, Shading};
use crate::gpu::Gpu;

pub const SIZE: (u32, u32) = (320, 180);
pub const LIGHTS: u32 = 200;

pub struct CbrBench {
    /// Forward, then deferred (`Shading::ALL`'s order).
    full_resolution: Vec<FullResolutionScene>,
    renderers: Vec<(String, Shading, Checkerboard)>,
    frame: u32,
}

impl CbrBench {
    pub fn new(gpu: &Gpu) -> Result<Self> {
        require_timestamps(gpu, "cbr")?;
        let scene = textured_corridor(5, LIGHTS, Motion::Static);
        let mut paths = vec![CheckerboardPath::OffsetPasses];
        if CheckerboardPath::for_adapter(gpu) == CheckerboardPath::Msaa2x {
            paths.push(CheckerboardPath::Msaa2x);
        }
        let full_resolution = Shading::ALL
            .iter()
            .map(|&shading| FullResolutionScene::shaded(gpu, &scene, SIZE, shading))
            .collect::<Result<_>>()?;
        let renderers = paths
            .iter()
            .flat_map(|&path| Shading::ALL.map(|shading| (path, shading)))
            .map(|(path, shading)| {
                let renderer = Checkerboard::new(gpu, &scene, CheckerboardConfig::new(SIZE, path, shading))?;
                Ok((format!("{}_{}", path.name(), shading.name()), shading, renderer))
            })
            .collect::<Result<_>>()?;
        Ok(Self { full_resolution, renderers, frame: 0 })
    }
}

fn shading_index(shading: Shading) -> usize {
    Shading::ALL.iter().position(|&s| s == shading).expect("in ALL")
}

impl Bench for CbrBench {
    fn name(&self) -> String {
        format!("{}x{}_{LIGHTS}_lights", SIZE.0, SIZE.1)
    }

    fn variants(&self) -> Vec<String> {
        Shading::ALL
            .iter()
            .map(|s| format!("full_resolution_{}", s.name()))
            .chain(self.renderers.iter().map(|(n, ..)| n.clone()))
            .collect()
    }

    fn baseline(&self, variant: usize) -> usize {
        let baselines = Shading::ALL.len();
        if variant < baselines { variant } else { shading_index(self.renderers[variant - baselines].1) }
    }

    fn run(&mut self, gpu: &Gpu, variant: usize) -> Result<Sample> {
        let baselines = Shading::ALL.len();
        if variant < baselines {
            return Ok(Sample::gpu_ms(self.full_resolution[variant].render(gpu, 0)?));
        }
        // Successive frames alternate the checkerboard's phase, as in a real sequence.
        self.frame += 1;
        let frame = self.renderers[variant - baselines].2.render(gpu, self.frame)?;
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
