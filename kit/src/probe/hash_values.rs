//! The shared WGSL hash functions (`pcg_hash`, `hash_unit`, `fragment_random`) evaluated on the
//! GPU by `shaders/kit/hash_values.wgsl` — the very functions the OIT noise and random numbers
//! call — on inputs the CPU rebuilds from the pixel index alone.

use anyhow::Result;

use crate::fullscreen::{FullscreenPipeline, bind_group, render_to_readback, uniform_buffer};
use crate::gpu::Gpu;
use crate::shaders;

/// Row length of the evaluation grid.
pub const GRID_WIDTH: u32 = 256;

/// The inputs `fs_hash_values` hands `fragment_random` at index `k`: runs of four share noise, id
/// and stream and differ in depth.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RandomInputs {
    pub noise: u32,
    pub depth: f32,
    pub id: u32,
    pub stream: u32,
}

impl RandomInputs {
    pub fn at(k: u32) -> Self {
        let run = k >> 2;
        Self {
            noise: run.wrapping_mul(2654435761),
            depth: f32::from_bits(0x3f80_0000 - k.wrapping_mul(40503) % 0x3f80_0000),
            id: run / 3,
            stream: run % 4,
        }
    }
}

/// What the GPU computed at index `k`: `pcg_hash(k)`, `hash_unit(k)` and `fragment_random` of
/// [`RandomInputs::at`]`(k)`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct HashValues {
    pub hash: u32,
    pub unit: f32,
    pub random: f32,
}

/// Evaluates the functions at indices `0..rows·GRID_WIDTH`.
pub fn evaluate_hashes(gpu: &Gpu, rows: u32) -> Result<Vec<HashValues>> {
    gpu.scoped("hash values", || {
        let format = wgpu::TextureFormat::Rgba32Uint;
        let pipeline = FullscreenPipeline {
            label: "hash values",
            fragment: shaders::HASH_VALUES,
            entry_point: "fs_hash_values",
            targets: &[Some(format.into())],
            depth_stencil: None,
            samples: 1,
        }
        .create(gpu);
        let grid = uniform_buffer(gpu, "hash grid", bytemuck::cast_slice(&[GRID_WIDTH, 0, 0, 0]));
        let group = bind_group(gpu, "hash values", &pipeline, 0, &[grid.as_entire_binding()]);
        let texels = render_to_readback(gpu, "hash values", &pipeline, &group, format, (GRID_WIDTH, rows))?;
        let words: &[u32] = bytemuck::cast_slice(&texels.bytes);
        Ok(words
            .chunks_exact(4)
            .map(|w| HashValues { hash: w[0], unit: f32::from_bits(w[1]), random: f32::from_bits(w[2]) })
            .collect())
    })
}
