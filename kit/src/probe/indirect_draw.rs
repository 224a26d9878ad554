//! Whether an indirect draw renders, and still renders once an earlier pipeline's vertex buffer
//! is gone, as it is in any renderer that frees a mesh. wgpu-hal 30's GL backend, where GL has
//! separate vertex formats (GL 4.3, GLES 3.1), enables a pipeline's vertex attributes and never
//! disables them for a later pipeline with fewer (command.rs, `set_render_pipeline`); deleting
//! the buffer behind one leaves an enabled attribute with no buffer, and GLES 3.1 refuses every
//! DrawArraysIndirect then ("INVALID_OPERATION ... if zero is bound to any enabled vertex
//! array", section 10.5), a rule desktop GL does not have. The CPS renderer draws its levels
//! indirectly only where this probe renders; `kit.draw.indirect` reports it.

use anyhow::Result;
use wgpu::util::DeviceExt;

use crate::attachments::colour;
use crate::fullscreen::FullscreenPipeline;
use crate::gpu::Gpu;
use crate::readback::read_rgba8;
use crate::rects::{Rect, RectBatch, RectFragment, RectPipeline};
use crate::shaders;

const SIZE: (u32, u32) = (4, 4);
const DRAWN: [u8; 4] = [0, 255, 0, 255];

/// None when indirect draws render here, also after a freed vertex buffer; else what the probe
/// saw, in a sentence. Measured once per device.
pub fn indirect_draw_problem(gpu: &Gpu) -> Result<Option<String>> {
    gpu.probed_once("indirect_draw", measure)
}

fn measure(gpu: &Gpu) -> Result<Option<String>> {
    if !gpu.adapter.get_downlevel_capabilities().flags.contains(wgpu::DownlevelFlags::INDIRECT_EXECUTION) {
        return Ok(Some("indirect draws: the adapter does not offer them".into()));
    }
    let format = wgpu::TextureFormat::Rgba8Unorm;
    let usage = wgpu::TextureUsages::RENDER_ATTACHMENT | wgpu::TextureUsages::COPY_SRC;
    let target = gpu.texture("indirect draw probe", SIZE, format, 1, usage);
    let view = target.create_view(&Default::default());
    let pipeline = FullscreenPipeline {
        label: "indirect draw probe",
        fragment: shaders::INDIRECT_DRAW,
        entry_point: "fs_indirect_draw",
        targets: &[Some(format.into())],
        depth_stencil: None,
        samples: 1,
    }
    .create(gpu);
    let arguments = gpu.device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
        label: Some("indirect draw probe arguments"),
        contents: bytemuck::cast_slice(&[3u32, 1, 0, 0]),
        usage: wgpu::BufferUsages::INDIRECT,
    });
    // One pass into the probe's target, submitted.
    let render = |label: &str, draw: &dyn Fn(&mut wgpu::RenderPass<'_>)| {
        let mut encoder = gpu.encoder(label);
        {
            let mut pass = encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
                label: Some(label),
                color_attachments: &[colour(&view, None, wgpu::Color::TRANSPARENT)],
                ..Default::default()
            });
            draw(&mut pass);
        }
        gpu.submit(encoder);
    };
    // The pixels an indirect full-target draw left undrawn.
    let draw_indirect = || -> Result<u32> {
        gpu.scoped("indirect draw probe", || {
            render("indirect draw probe", &|pass| {
                pass.set_pipeline(&pipeline);
                pass.draw_indirect(&arguments, 0);
            });
            Ok(read_rgba8(gpu, &target)?.pixels().filter(|p| p.0 != DRAWN).count() as u32)
        })
    };
    let pixels = SIZE.0 * SIZE.1;
    let missed = draw_indirect()?;
    if missed > 0 {
        return Ok(Some(format!(
            "indirect draws: a full-target indirect draw left {missed} of {pixels} pixels undrawn"
        )));
    }
    // A draw through a vertex buffer, which is then freed (the wait lets wgpu destroy it).
    {
        let batch = RectBatch::new(gpu, SIZE, &[(Rect::full(SIZE.0, SIZE.1), [1.0; 4])]);
        let rects = RectPipeline {
            colour_format: Some(format),
            fragment: RectFragment::InstanceColour,
            ..RectPipeline::new("indirect draw probe, vertex buffer")
        }
        .create(gpu);
        render("indirect draw probe, vertex buffer", &|pass| {
            pass.set_pipeline(&rects);
            batch.draw(pass, ..);
        });
    }
    gpu.wait()?;
    let missed = draw_indirect()?;
    Ok((missed > 0).then(|| {
        format!(
            "indirect draws: after a draw whose vertex buffer was then freed, a full-target indirect draw left {missed} of {pixels} pixels undrawn"
        )
    }))
}
