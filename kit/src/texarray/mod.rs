//! A 2D texture used as a 1D array: element k at (k mod w, k div w). The four classic ways to
//! fetch element k (`shaders/texarray/fetch.wgsl`), and a measurement of which indices each
//! gets right on an adapter, held to what each may return by definition (`model`).

use anyhow::{Context, Result, ensure};
use serde::Serialize;

use crate::fullscreen::{FullscreenPipeline, bind_group, render_to_readback, uniform_buffer};
use crate::gpu::Gpu;
use crate::shaders;

pub mod model;

#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum FetchVariant {
    /// `array_texel` (the renderer's fetch): `textureLoad(k mod w, k div w)`, exact while k fits a u32.
    Integer,
    /// Float divide: y = floor(k / w), x = k − y·w, sampled at the texel centre.
    Divide,
    /// Float reciprocal: t = k·(1/w), x from fract(t), y from floor(t).
    Reciprocal,
    /// One multiply, uv = (1/w, 1/(w·h))·(k + 0.5), with repeat addressing and nearest filtering.
    SingleMultiply,
}

impl FetchVariant {
    pub const ALL: [Self; 4] = [Self::Integer, Self::Divide, Self::Reciprocal, Self::SingleMultiply];
}

/// Row length of the index list and result targets.
const LIST_WIDTH: u32 = 256;

/// Which of `indices` each variant fetched correctly from a `size` texture of elements.
#[derive(Clone, Debug, Serialize)]
pub struct VariantResult {
    pub variant: FetchVariant,
    pub wrong: usize,
    /// The smallest index (of those tried) fetched wrong, with what came back.
    pub first_wrong: Option<(u32, u32)>,
    /// What came back for each index, in order.
    #[serde(skip)]
    pub fetched: Vec<u32>,
}

/// Test indices: densely around every power of two up to the element count, the last 64
/// elements, and a stride through the whole array.
pub fn sweep_indices(elements: u32) -> Vec<u32> {
    let mut indices: Vec<u32> = (0..32)
        .map(|bit| 1u64 << bit)
        .take_while(|&p| p <= u64::from(elements))
        .flat_map(|p| (p.saturating_sub(8)..p + 8).map(|k| k as u32))
        .chain(elements.saturating_sub(64)..elements)
        .chain((0..elements).step_by(4099))
        .filter(|&k| k < elements)
        .collect();
    indices.sort_unstable();
    indices.dedup();
    indices
}

pub fn measure_index_exactness(gpu: &Gpu, size: (u32, u32), indices: &[u32]) -> Result<Vec<VariantResult>> {
    let elements = u64::from(size.0) * u64::from(size.1);
    ensure!(elements <= u64::from(u32::MAX), "{size:?} holds more elements than a u32 index reaches");
    ensure!(indices.iter().all(|&k| u64::from(k) < elements), "an index lies beyond the {elements} elements");
    gpu.scoped("texture-array fetch", || {
        // Element k stores k's four bytes.
        let data: Vec<u8> = (0..elements as u32).flat_map(u32::to_le_bytes).collect();
        let texture = gpu.texture(
            "array elements",
            size,
            wgpu::TextureFormat::Rgba8Unorm,
            1,
            wgpu::TextureUsages::TEXTURE_BINDING | wgpu::TextureUsages::COPY_DST,
        );
        gpu.queue.write_texture(
            texture.as_image_copy(),
            &data,
            wgpu::TexelCopyBufferLayout { offset: 0, bytes_per_row: Some(size.0 * 4), rows_per_image: None },
            texture.size(),
        );
        let rows = (indices.len() as u32).div_ceil(LIST_WIDTH).max(1);
        let mut list = indices.to_vec();
        list.resize((LIST_WIDTH * rows) as usize, 0);
        let index_texture = gpu.texture(
            "index list",
            (LIST_WIDTH, rows),
            wgpu::TextureFormat::R32Uint,
            1,
            wgpu::TextureUsages::TEXTURE_BINDING | wgpu::TextureUsages::COPY_DST,
        );
        gpu.queue.write_texture(
            index_texture.as_image_copy(),
            bytemuck::cast_slice(&list),
            wgpu::TexelCopyBufferLayout { offset: 0, bytes_per_row: Some(LIST_WIDTH * 4), rows_per_image: None },
            index_texture.size(),
        );
        let sampler = gpu.device.create_sampler(&wgpu::SamplerDescriptor {
            label: Some("nearest repeat"),
            address_mode_u: wgpu::AddressMode::Repeat,
            address_mode_v: wgpu::AddressMode::Repeat,
            ..Default::default()
        });
        let pipeline = FullscreenPipeline {
            label: "texture-array fetch",
            fragment: shaders::TEXARRAY_FETCH,
            entry_point: "fs_fetch",
            targets: &[Some(wgpu::TextureFormat::R32Uint.into())],
            depth_stencil: None,
            samples: 1,
        }
        .create(gpu);
        let (element_view, index_view) =
            (texture.create_view(&Default::default()), index_texture.create_view(&Default::default()));
        FetchVariant::ALL
            .into_iter()
            .enumerate()
            .map(|(v, variant)| {
                let uniform = uniform_buffer(
                    gpu,
                    "fetch",
                    bytemuck::cast_slice(&[v as u32, indices.len() as u32, LIST_WIDTH, 0]),
                );
                let group = bind_group(
                    gpu,
                    "texture-array fetch",
                    &pipeline,
                    0,
                    &[
                        uniform.as_entire_binding(),
                        wgpu::BindingResource::TextureView(&element_view),
                        wgpu::BindingResource::Sampler(&sampler),
                        wgpu::BindingResource::TextureView(&index_view),
                    ],
                );
                let result = render_to_readback(
                    gpu,
                    "texture-array fetch",
                    &pipeline,
                    &group,
                    wgpu::TextureFormat::R32Uint,
                    (LIST_WIDTH, rows),
                )?;
                let fetched: Vec<u32> = bytemuck::cast_slice(&result.bytes)[..indices.len()].to_vec();
                let wrong: Vec<(u32, u32)> =
                    indices.iter().zip(&fetched).filter(|(k, f)| k != f).map(|(&k, &f)| (k, f)).collect();
                Ok(VariantResult { variant, wrong: wrong.len(), first_wrong: wrong.first().copied(), fetched })
            })
            .collect::<Result<Vec<_>>>()
            .context("fetching through each variant")
    })
}
