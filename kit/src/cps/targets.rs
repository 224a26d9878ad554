//! Mip chains: one texture whose mip l holds level l, with a view of each mip (to render into
//! or read alone) and one of the whole chain (for the composite).

use crate::gpu::Gpu;

pub struct MipChain {
    pub texture: wgpu::Texture,
    /// A view of mip l alone, for l in 0..levels.
    pub level_views: Vec<wgpu::TextureView>,
    /// All mips, for shaders that pick the level per pixel.
    pub all: wgpu::TextureView,
}

impl MipChain {
    pub fn new(
        gpu: &Gpu,
        label: &str,
        (width, height): (u32, u32),
        levels: u32,
        format: wgpu::TextureFormat,
        usage: wgpu::TextureUsages,
    ) -> Self {
        let texture = gpu.device.create_texture(&wgpu::TextureDescriptor {
            label: Some(label),
            size: wgpu::Extent3d { width, height, depth_or_array_layers: 1 },
            mip_level_count: levels,
            sample_count: 1,
            dimension: wgpu::TextureDimension::D2,
            format,
            usage,
            view_formats: &[],
        });
        let level_views = (0..levels)
            .map(|level| {
                texture.create_view(&wgpu::TextureViewDescriptor {
                    label: Some(label),
                    base_mip_level: level,
                    mip_level_count: Some(1),
                    ..Default::default()
                })
            })
            .collect();
        let all = texture.create_view(&Default::default());
        Self { texture, level_views, all }
    }
}
