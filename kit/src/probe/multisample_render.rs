//! Whether an advertised N-sample target renders at all: a white draw over a cleared N-sample
//! colour target (`resolved_fill`, shared with the sample-mask probe), resolved and read back, must come back white everywhere. wgpu's GL backend
//! advertises 2x and 4x whatever the driver's GL_MAX_SAMPLES says, and where GL refuses the
//! renderbuffer (softpipe) the framebuffer is incomplete and nothing is drawn, without an error
//! wgpu reports: this probe turns that into words the cases can give.

use anyhow::Result;

use crate::attachments::colour;
use crate::diagnostics::{probing, with_raised};
use crate::gpu::Gpu;
use crate::readback::read_rgba8;
use crate::rects::{Rect, RectBatch, RectFragment, RectPipeline};

const SIZE: (u32, u32) = (8, 8);

/// A white full-target draw with pipeline sample mask `sample_mask` into a cleared `samples`-sample
/// target of `size`, resolved and read back (the sample-mask probe's draw too).
pub fn resolved_fill(gpu: &Gpu, samples: u32, size: (u32, u32), sample_mask: u32) -> Result<image::RgbaImage> {
    let format = wgpu::TextureFormat::Rgba8Unorm;
    let msaa = gpu.texture("multisample fill", size, format, samples, wgpu::TextureUsages::RENDER_ATTACHMENT);
    let usage = wgpu::TextureUsages::RENDER_ATTACHMENT | wgpu::TextureUsages::COPY_SRC;
    let resolved = gpu.texture("multisample fill resolve", size, format, 1, usage);
    let (msaa_view, resolved_view) = (msaa.create_view(&Default::default()), resolved.create_view(&Default::default()));
    let pipeline = RectPipeline {
        colour_format: Some(format),
        fragment: RectFragment::InstanceColour,
        samples,
        sample_mask: u64::from(sample_mask),
        ..RectPipeline::new("multisample fill")
    }
    .create(gpu);
    let full = RectBatch::new(gpu, size, &[(Rect::full(size.0, size.1), [1.0; 4])]);
    let mut encoder = gpu.encoder("multisample fill");
    {
        let mut pass = encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
            label: Some("multisample fill"),
            color_attachments: &[colour(&msaa_view, Some(&resolved_view), wgpu::Color::TRANSPARENT)],
            ..Default::default()
        });
        pass.set_pipeline(&pipeline);
        full.draw(&mut pass, ..);
    }
    gpu.submit(encoder);
    read_rgba8(gpu, &resolved)
}

/// None when an N-sample target renders; else what the probe saw, in a sentence.
pub fn render_problem(gpu: &Gpu, samples: u32) -> Result<Option<String>> {
    let all_samples = (1u32 << samples) - 1;
    let (image, raised) =
        probing(|| gpu.scoped(&format!("{samples}x render probe"), || resolved_fill(gpu, samples, SIZE, all_samples)));
    let white = image?.pixels().filter(|p| p.0 == [255; 4]).count();
    let total = (SIZE.0 * SIZE.1) as usize;
    Ok((white < total).then(|| {
        with_raised(
            format!(
                "{samples}x is advertised but a {samples}x target does not render: a white draw over it resolved \
                 white in {white} of {total} pixels"
            ),
            &raised,
        )
    }))
}
