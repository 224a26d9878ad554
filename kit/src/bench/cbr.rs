//! Checkerboard rendering against full resolution where pixel shading dominates: the static
//! textured corridor with 200 lights at 320×180, CSO, forward and deferred shading, on the exact
//! offset-pass path and, where the kit measured a real one, the 2x MSAA path. GPU time of a whole
//! frame from timestamp queries around every pass (checkerboarding: scene passes and
//! reconstruction; full resolution: its scene pass).

use anyhow::Result;

use super::{Bench, Sample, require_timestamps};
use crate::cbr::sampling::CheckerboardPath;
use crate::cbr::scene::{Motion, textured_corridor};
use crate::cbr::{Checkerboard, CheckerboardConfig, FullResolutionScene, Shading};
use crate::gpu::Gpu;

pub const SIZE: (u32, u32) = (320, 180);
pub const LIGHTS: u32 = 200;

pub struct CbrBench {
    full_resolution: FullResolutionScene,
    renderers: Vec<(String, Checkerboard)>,
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
        let renderers = paths
            .iter()
            .flat_map(|&path| Shading::ALL.map(|shading| (path, shading)))
            .map(|(path, shading)| {
                let renderer = Checkerboard::new(gpu, &scene, CheckerboardConfig::new(SIZE, path, shading))?;
                Ok((format!("{}_{}", path.name(), shading.name()), renderer))
            })
            .collect::<Result<_>>()?;
        Ok(Self { full_resolution: FullResolutionScene::new(gpu, &scene, SIZE)?, renderers, frame: 0 })
    }
}

impl Bench for CbrBench {
    fn name(&self) -> String {
        format!("{}x{}_{LIGHTS}_lights", SIZE.0, SIZE.1)
    }

    fn variants(&self) -> Vec<String> {
        std::iter::once("full_resolution".to_owned()).chain(self.renderers.iter().map(|(n, _)| n.clone())).collect()
    }

    fn baseline(&self) -> usize {
        0
    }

    fn run(&mut self, gpu: &Gpu, variant: usize) -> Result<Sample> {
        if variant == 0 {
            return Ok(Sample::gpu_ms(self.full_resolution.render(gpu, 0)?));
        }
        // Successive frames alternate the checkerboard's phase, as in a real sequence.
        self.frame += 1;
        Ok(Sample::gpu_ms(self.renderers[variant - 1].1.render(gpu, self.frame)?.gpu_ms))
    }
}
