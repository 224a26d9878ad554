//! Whether the pipeline's multisample mask is honoured: a full-pixel draw with mask m into a
//! cleared N-sample target must resolve to popcount(m)/N of its colour.

use anyhow::Result;
use serde::Serialize;

use crate::attachments::colour;
use crate::gpu::Gpu;
use crate::readback::read_rgba8;
use crate::rects::{Rect, RectBatch, RectFragment, RectPipeline};

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
    gpu.scoped(&format!("{samples}x sample mask probe"), || {
        let format = wgpu::TextureFormat::Rgba8Unorm;
        let msaa = gpu.texture("mask msaa", (1, 1), format, samples, wgpu::TextureUsages::RENDER_ATTACHMENT);
        let resolved = gpu.texture(
            "mask resolved",
            (1, 1),
            format,
            1,
            wgpu::TextureUsages::RENDER_ATTACHMENT | wgpu::TextureUsages::COPY_SRC,
        );
        let (msaa_view, resolved_view) =
            (msaa.create_view(&Default::default()), resolved.create_view(&Default::default()));
        let full = RectBatch::new(gpu, (1, 1), &[(Rect::full(1, 1), [1.0; 4])]);
        let masks = std::iter::once(0).chain((0..samples).map(|s| 1 << s)).chain(std::iter::once((1 << samples) - 1));
        masks
            .map(|mask: u32| {
                let pipeline = RectPipeline {
                    colour_format: Some(format),
                    fragment: RectFragment::InstanceColour,
                    samples,
                    sample_mask: u64::from(mask),
                    ..RectPipeline::new("masked fill")
                }
                .create(gpu);
                let mut encoder = gpu.encoder("masked fill");
                {
                    let mut pass = encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
                        label: Some("masked fill"),
                        color_attachments: &[colour(&msaa_view, Some(&resolved_view), wgpu::Color::TRANSPARENT)],
                        ..Default::default()
                    });
                    pass.set_pipeline(&pipeline);
                    full.draw(&mut pass, ..);
                }
                gpu.submit(encoder);
                let value = read_rgba8(gpu, &resolved)?.get_pixel(0, 0)[0];
                let expected = (255.0 * mask.count_ones() as f32 / samples as f32).round() as u8;
                Ok(MaskResult { mask, resolved: value, expected })
            })
            .collect()
    })
}
