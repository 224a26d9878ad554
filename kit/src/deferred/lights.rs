//! Lights in a 2D `Rgba32Float` texture used as a 1D array: light i is elements 2i (position,
//! range) and 2i + 1 (colour, intensity); element k sits at (k mod width, k div width).

use anyhow::{Result, ensure};

use crate::gpu::Gpu;
use crate::scene::corridor::Light;

/// Texels a row; a power of two keeps every addressing variant exact at small indices.
pub const LIGHT_TEXTURE_WIDTH: u32 = 64;

pub struct LightTexture {
    pub texture: wgpu::Texture,
    pub view: wgpu::TextureView,
    pub count: u32,
}

impl LightTexture {
    pub fn new(gpu: &Gpu, lights: &[Light]) -> Result<Self> {
        ensure!(!lights.is_empty(), "light count 0: the lighting passes need at least one light");
        let elements = 2 * lights.len().max(1) as u64;
        let height = elements.div_ceil(u64::from(LIGHT_TEXTURE_WIDTH));
        let max = u64::from(gpu.device.limits().max_texture_dimension_2d);
        ensure!(
            height <= max,
            "{} lights need a {LIGHT_TEXTURE_WIDTH}x{height} light texture; this adapter allows {max} rows ({} lights at most)",
            lights.len(),
            max * u64::from(LIGHT_TEXTURE_WIDTH) / 2
        );
        let height = height as u32;
        let mut texels = vec![[0.0f32; 4]; (LIGHT_TEXTURE_WIDTH * height) as usize];
        for (i, light) in lights.iter().enumerate() {
            texels[2 * i] = [light.position.x, light.position.y, light.position.z, light.range];
            texels[2 * i + 1] = [light.colour.x, light.colour.y, light.colour.z, light.intensity];
        }
        let texture = gpu.texture(
            "lights",
            (LIGHT_TEXTURE_WIDTH, height),
            wgpu::TextureFormat::Rgba32Float,
            1,
            wgpu::TextureUsages::TEXTURE_BINDING | wgpu::TextureUsages::COPY_DST,
        );
        gpu.queue.write_texture(
            texture.as_image_copy(),
            bytemuck::cast_slice(&texels),
            wgpu::TexelCopyBufferLayout {
                offset: 0,
                bytes_per_row: Some(LIGHT_TEXTURE_WIDTH * 16),
                rows_per_image: None,
            },
            texture.size(),
        );
        let view = texture.create_view(&Default::default());
        Ok(Self { texture, view, count: lights.len() as u32 })
    }
}
