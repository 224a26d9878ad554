//! Whether an advertised N-sample target renders at all: a white draw over a cleared N-sample
//! colour target, resolved and read back, must come back white everywhere. wgpu's GL backend
//! advertises 2x and 4x whatever the driver's GL_MAX_SAMPLES says, and where GL refuses the
//! renderbuffer (softpipe) the framebuffer is incomplete and nothing is drawn, without an error
//! wgpu reports: this probe turns that into words the cases can give.

use anyhow::Result;

use crate::attachments::colour;
use crate::gpu::Gpu;
use crate::readback::read_rgba8;
use crate::rects::{Rect, RectBatch, RectFragment, RectPipeline};

const SIZE: (u32, u32) = (8, 8);

/// None when an N-sample target renders; else what the probe saw, in a sentence.
pub fn render_problem(gpu: &Gpu, samples: u32) -> Result<Option<String>> {
    let format = wgpu::TextureFormat::Rgba8Unorm;
    let image = gpu.scoped(&format!("{samples}x render probe"), || {
        let msaa =
            gpu.texture("multisample render probe", SIZE, format, samples, wgpu::TextureUsages::RENDER_ATTACHMENT);
        let usage = wgpu::TextureUsages::RENDER_ATTACHMENT | wgpu::TextureUsages::COPY_SRC;
        let resolved = gpu.texture("multisample render probe resolve", SIZE, format, 1, usage);
        let (msaa_view, resolved_view) =
            (msaa.create_view(&Default::default()), resolved.create_view(&Default::default()));
        let pipeline = RectPipeline {
            colour_format: Some(format),
            fragment: RectFragment::InstanceColour,
            samples,
            ..RectPipeline::new("multisample render probe")
        }
        .create(gpu);
        let full = RectBatch::new(gpu, SIZE, &[(Rect::full(SIZE.0, SIZE.1), [1.0; 4])]);
        let mut encoder = gpu.encoder("multisample render probe");
        {
            let mut pass = encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
                label: Some("multisample render probe"),
                color_attachments: &[colour(&msaa_view, Some(&resolved_view), wgpu::Color::BLACK)],
                ..Default::default()
            });
            pass.set_pipeline(&pipeline);
            full.draw(&mut pass, ..);
        }
        gpu.submit(encoder);
        read_rgba8(gpu, &resolved)
    })?;
    let white = image.pixels().filter(|p| p.0 == [255; 4]).count();
    let total = (SIZE.0 * SIZE.1) as usize;
    Ok((white < total).then(|| {
        format!(
            "{samples}x is advertised but a {samples}x target does not render: a white draw over it resolved \
             white in {white} of {total} pixels"
        )
    }))
}
