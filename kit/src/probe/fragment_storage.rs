//! Whether fragment shaders can write storage buffers, by a render that does it, not by the flag:
//! wgpu's GL backend sets `FRAGMENT_WRITABLE_STORAGE` on softpipe's GL 3.3, whose storage-buffer
//! extension it sees, while naga writes storage buffers only for GLSL 4.00 and later and refuses
//! every such pipeline ("The selected version doesn't support Features(BUFFER_STORAGE)").

use anyhow::Result;
use wgpu::util::DeviceExt;

use crate::attachments::colour;
use crate::fullscreen::{FullscreenPipeline, bind_group};
use crate::gpu::Gpu;
use crate::readback::read_buffer_words;
use crate::shaders;

/// None when a fragment shader's storage writes land; else what the probe saw, in a sentence.
/// Measured once per device.
pub fn fragment_storage_problem(gpu: &Gpu) -> Result<Option<String>> {
    gpu.probed_once("fragment_storage", measure)
}

fn measure(gpu: &Gpu) -> Result<Option<String>> {
    let limits = gpu.device.limits();
    let flags = gpu.adapter.get_downlevel_capabilities().flags;
    if !flags.contains(wgpu::DownlevelFlags::FRAGMENT_WRITABLE_STORAGE)
        || limits.max_storage_buffers_per_shader_stage == 0
    {
        return Ok(Some("fragment storage writes: the adapter does not offer them".into()));
    }
    let written = gpu.scoped("fragment storage probe", || {
        let format = wgpu::TextureFormat::Rgba8Unorm;
        let target = gpu.texture("fragment storage probe", (4, 1), format, 1, wgpu::TextureUsages::RENDER_ATTACHMENT);
        let view = target.create_view(&Default::default());
        let storage = gpu.device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
            label: Some("fragment storage probe"),
            contents: bytemuck::cast_slice(&[0u32; 4]),
            usage: wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_SRC,
        });
        let pipeline = FullscreenPipeline {
            label: "fragment storage probe",
            fragment: shaders::FRAGMENT_STORAGE,
            entry_point: "fs_fragment_storage",
            targets: &[Some(format.into())],
            depth_stencil: None,
            samples: 1,
        }
        .create(gpu);
        let group = bind_group(gpu, "fragment storage probe", &pipeline, 0, &[storage.as_entire_binding()]);
        let mut encoder = gpu.encoder("fragment storage probe");
        {
            let mut pass = encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
                label: Some("fragment storage probe"),
                color_attachments: &[colour(&view, None, wgpu::Color::BLACK)],
                ..Default::default()
            });
            pass.set_pipeline(&pipeline);
            pass.set_bind_group(0, &group, &[]);
            pass.draw(0..3, 0..1);
        }
        gpu.submit(encoder);
        read_buffer_words(gpu, &storage)
    });
    Ok(match written {
        Ok(words) if words == [1, 2, 3, 4] => None,
        Ok(words) => Some(format!("fragment storage writes: a 4-pixel draw left {words:?}, expected [1, 2, 3, 4]")),
        Err(error) => Some(format!("fragment storage writes: the adapter offers them, but {error:#}")),
    })
}
