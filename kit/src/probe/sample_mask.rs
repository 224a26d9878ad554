//! Whether the pipeline's multisample mask is honoured: a full-pixel draw with mask m into a
//! cleared N-sample target must resolve to popcount(m)/N of its colour.

use anyhow::Result;
use serde::Serialize;

use super::multisample_render::resolved_fill;
use crate::gpu::Gpu;

#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct MaskResult {
    pub mask: u32,
    /// Resolved 8-bit value of a white draw.
    pub resolved: u8,
    /// round(255 · popcount(mask) / N).
    pub expected: u8,
}

impl MaskResult {
    /// Within one 8-bit step: resolves may round either way.
    pub fn honoured(&self) -> bool {
        self.resolved.abs_diff(self.expected) <= 1
    }
}

/// Every mask with zero or one sample set, and the full mask.
pub fn measure_sample_mask(gpu: &Gpu, samples: u32) -> Result<Vec<MaskResult>> {
    super::scoped(gpu, &format!("{samples}x sample mask probe"), || {
        let masks = std::iter::once(0).chain((0..samples).map(|s| 1 << s)).chain(std::iter::once((1 << samples) - 1));
        masks
            .map(|mask: u32| {
                let value = resolved_fill(gpu, samples, (1, 1), mask)?.get_pixel(0, 0)[0];
                let expected = (255.0 * mask.count_ones() as f32 / samples as f32).round() as u8;
                Ok(MaskResult { mask, resolved: value, expected })
            })
            .collect()
    })
}
