//! Order-independent transparency on the 16-layer stiff scene at 256×256: one stochastic frame
//! (4x, the paper's variant) and weighted blended OIT against exact depth peeling. GPU time from
//! timestamp queries around every pass.

use anyhow::Result;

use super::{Bench, Sample, require_timestamps};
use crate::gpu::Gpu;
use crate::oit::run::{Accumulation, Method, run_method};
use crate::oit::scene::QuadScene;
use crate::oit::stochastic::Stochastic;

pub const SIZE: (u32, u32) = (256, 256);
pub const LAYERS: u32 = 16;

pub struct OitBench {
    scene: QuadScene,
    methods: [(&'static str, Method, u32); 3],
}

impl OitBench {
    pub fn new(gpu: &Gpu) -> Result<Self> {
        require_timestamps(gpu, "oit")?;
        Ok(Self {
            scene: QuadScene::stiff(LAYERS, 1),
            methods: [
                ("depth_peeling", Method::DepthPeeling, 1),
                ("stochastic_4x", Method::Stochastic(Stochastic::Paper), 4),
                ("weighted_blended", Method::WeightedBlended, 1),
            ],
        })
    }
}

impl Bench for OitBench {
    fn name(&self) -> String {
        format!("{LAYERS}_layers_{}x{}", SIZE.0, SIZE.1)
    }

    fn variants(&self) -> Vec<String> {
        self.methods.iter().map(|(name, ..)| (*name).to_owned()).collect()
    }

    fn baseline(&self, _variant: usize) -> usize {
        0
    }

    fn run(&mut self, gpu: &Gpu, variant: usize) -> Result<Sample> {
        let (_, method, samples) = &self.methods[variant];
        let once = Accumulation { frames: 1, seed: 1, filtered: false };
        Ok(Sample::gpu_ms(run_method(gpu, &self.scene, SIZE, *samples, method, once)?.gpu_ms))
    }
}
