//! What early stencil rejection buys on this adapter: a heavy fragment shader at 512×512 behind a
//! stencil-Equal gate passing 1.98 % of the pixels, against the same draw behind stencil Always.
//! GPU time from timestamp queries around the heavy pass; wall time of a submit-and-wait where
//! the adapter has no timestamps.

use anyhow::Result;

use super::{Bench, Sample};
use crate::gpu::Gpu;
use crate::probe::stencil_gated_draw::{Gate, StencilGatedDraw};

pub const SIZE: (u32, u32) = (512, 512);
const PASSING: (u32, u32) = (72, 72);
const ITERATIONS: u32 = 96;

pub struct EarlyRejectionBench {
    draw: StencilGatedDraw,
}

impl EarlyRejectionBench {
    pub fn new(gpu: &Gpu) -> Result<Self> {
        Ok(Self { draw: StencilGatedDraw::new(gpu, SIZE, PASSING, ITERATIONS)? })
    }
}

impl Bench for EarlyRejectionBench {
    fn name(&self) -> String {
        format!("heavy_{}x{}", SIZE.0, SIZE.1)
    }

    fn variants(&self) -> Vec<String> {
        vec!["stencil_always".to_owned(), "stencil_equal_1.98pct".to_owned()]
    }

    fn baseline(&self, _variant: usize) -> usize {
        0
    }

    fn run(&mut self, gpu: &Gpu, variant: usize) -> Result<Sample> {
        let gate = if variant == 0 { Gate::Always } else { Gate::Equal };
        let result = self.draw.draw(gpu, gate)?;
        Ok(Sample::gpu_ms(result.gpu_ms.unwrap_or(result.wall_ms)))
    }
}
