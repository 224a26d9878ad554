//! Depth read-back where the adapter cannot copy depth into a buffer (GLES, some GL): a
//! full-screen fragment pass writes each depth value's bits into an `R32Uint` target.

use anyhow::{Result, bail};

use crate::fullscreen::{FullscreenPipeline, bind_group, render_to_readback};
use crate::gpu::Gpu;
use crate::readback::read_texture;
use crate::shaders;

/// Reads a single-sampled `Depth32Float` texture's values: by copy where the adapter can copy
/// depth to a buffer, else through a fragment pass writing each value's bits
/// (`shaders/kit/depth_bits.wgsl`). The texture needs `TEXTURE_BINDING` for the second.
pub fn read_depth(gpu: &Gpu, texture: &wgpu::Texture) -> Result<Vec<f32>> {
    if texture.format() != wgpu::TextureFormat::Depth32Float {
        bail!("read_depth needs Depth32Float, got {:?}", texture.format());
    }
    let copies = gpu.adapter.get_downlevel_capabilities().flags;
    if copies.contains(wgpu::DownlevelFlags::DEPTH_TEXTURE_AND_BUFFER_COPIES) {
        return Ok(read_texture(gpu, texture, wgpu::TextureAspect::All, 0)?.as_f32());
    }
    let format = wgpu::TextureFormat::R32Uint;
    let pipeline = FullscreenPipeline {
        label: "depth bits",
        fragment: shaders::DEPTH_BITS,
        entry_point: "fs_depth_bits",
        targets: &[Some(format.into())],
        depth_stencil: None,
        samples: 1,
    }
    .create(gpu);
    let depth_view = texture
        .create_view(&wgpu::TextureViewDescriptor { aspect: wgpu::TextureAspect::DepthOnly, ..Default::default() });
    let group = bind_group(gpu, "depth bits", &pipeline, 0, &[wgpu::BindingResource::TextureView(&depth_view)]);
    let size = (texture.width(), texture.height());
    Ok(render_to_readback(gpu, "depth bits", &pipeline, &group, format, size)?.as_f32())
}
