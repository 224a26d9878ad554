//! Mip chains: one texture whose mip l holds level l, with a view of each mip (to render into
//! or read alone) and one of the whole chain (for the composite); and the bitmask pyramids built
//! on them.

use crate::fullscreen::FullscreenPipeline;
use crate::gpu::Gpu;
use crate::shaders;

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

/// A bitmask pyramid (`R32Uint`) and the pipeline that OR-reduces it upwards `step` mips a pass
/// (`shaders/cps/mask_reduce.wgsl`): every mip (step 1: the edge pyramid, whose every mip the
/// content policy reads), or only the even ones (step 2: the LOD-present pyramid, whose odd
/// levels the stencil marks OR from the even mip below).
pub struct OrPyramid {
    pub chain: MipChain,
    pub reduce: wgpu::RenderPipeline,
    pub step: usize,
}

impl OrPyramid {
    pub const FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::R32Uint;

    pub fn new(gpu: &Gpu, label: &str, size: (u32, u32), levels: u32, step: usize, usage: wgpu::TextureUsages) -> Self {
        let entry_point = if step == 1 { "fs_mask_reduce" } else { "fs_mask_reduce_two_levels" };
        let reduce = FullscreenPipeline {
            label: "mask reduce",
            fragment: shaders::CPS_MASK_REDUCE,
            entry_point,
            targets: &[Some(Self::FORMAT.into())],
            depth_stencil: None,
            samples: 1,
        }
        .create(gpu);
        Self { chain: MipChain::new(gpu, label, size, levels, Self::FORMAT, usage), reduce, step }
    }
}
