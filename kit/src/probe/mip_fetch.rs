//! Whether `textureLoad` at a mip level that differs between neighbouring pixels reads each
//! pixel's own level — what the CPS composite does. A labelled mip chain (mip l texel t holds
//! its level and coordinates) is fetched with seeded level maps that vary per pixel, per 2×2
//! quad, per 4×4 and per 8×8 block, each with the level straight from the map ("varying") and
//! with the level as a loop counter ("uniform" across lanes). `kit.fetch.per_pixel_level` reports
//! the measurement; the CPS composite does not depend on it (its levels are one atlas, read at a
//! per-pixel offset).

use anyhow::Result;

use crate::cps::targets::MipChain;
use crate::fullscreen::{FullscreenPipeline, bind_group};
use crate::gpu::Gpu;
use crate::readback::read_texture;
use crate::scene::hash::SeededRng;
use crate::shaders;

pub const FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::R32Uint;
/// Side of the blocks that share one level, from per pixel to 8×8.
pub const BLOCKS: [u32; 4] = [1, 2, 4, 8];
/// The two ways to fetch: (name, entry point).
pub const WAYS: [(&str, &str); 2] = [("varying", "fs_fetch_varying_level"), ("uniform", "fs_fetch_uniform_level")];
/// Set in every texel, so that 0 means "read no texel" (out-of-bounds reads return 0).
pub const PRESENT: u32 = 1 << 31;

/// What mip `level` holds at texel `t`: the level and the texel, so a wrong fetch says what it read.
pub fn texel_value(level: u32, t: (u32, u32)) -> u32 {
    PRESENT | (level << 24) | (t.1 << 12) | t.0
}

/// One level map fetched one way.
pub struct FetchMeasurement {
    pub way: &'static str,
    pub block: u32,
    /// Row-major levels.
    pub level_map: Vec<u32>,
    pub fetched: Vec<u32>,
    /// Each pixel's own level's texel p >> level.
    pub expected: Vec<u32>,
}

impl FetchMeasurement {
    /// Indices of the pixels that read another texel.
    pub fn wrong(&self) -> Vec<usize> {
        (0..self.expected.len()).filter(|&i| self.fetched[i] != self.expected[i]).collect()
    }
}

/// Levels of a `size` mip chain (both sides powers of two).
pub fn levels(size: (u32, u32)) -> u32 {
    size.0.max(size.1).trailing_zeros() + 1
}

/// Fetches seeded level maps of every block size both ways from a labelled `size` chain.
pub fn measure(gpu: &Gpu, size: (u32, u32), seed: u32) -> Result<Vec<FetchMeasurement>> {
    anyhow::ensure!(
        size.0.is_power_of_two() && size.1.is_power_of_two() && size.0 <= 4096 && size.1 <= 4096,
        "size {}x{}: both sides must be powers of two up to 4096 (each pixel's texel is p >> level)",
        size.0,
        size.1
    );
    let levels = levels(size);
    let source = labelled_mips(gpu, size, levels);
    let pipelines = WAYS.map(|(way, entry_point)| {
        let pipeline = FullscreenPipeline {
            label: "mip fetch",
            fragment: shaders::MIP_FETCH,
            entry_point,
            targets: &[Some(FORMAT.into())],
            depth_stencil: None,
            samples: 1,
        }
        .create(gpu);
        (way, pipeline)
    });
    let mut measurements = Vec::new();
    for block in BLOCKS {
        let mut rng = SeededRng::new(seed ^ block);
        let per_block: Vec<u32> =
            (0..size.0.div_ceil(block) * size.1.div_ceil(block)).map(|_| rng.range(0, levels)).collect();
        let level_map: Vec<u32> = (0..size.1)
            .flat_map(|y| (0..size.0).map(move |x| (y / block, x / block)))
            .map(|(by, bx)| per_block[(by * size.0.div_ceil(block) + bx) as usize])
            .collect();
        let expected: Vec<u32> = level_map
            .iter()
            .enumerate()
            .map(|(i, &l)| texel_value(l, ((i as u32 % size.0) >> l, (i as u32 / size.0) >> l)))
            .collect();
        for (way, pipeline) in &pipelines {
            let fetched = fetch(gpu, pipeline, &source, &level_map, size)?;
            measurements.push(FetchMeasurement {
                way,
                block,
                level_map: level_map.clone(),
                fetched,
                expected: expected.clone(),
            });
        }
    }
    Ok(measurements)
}

/// A mip chain whose mip l holds `texel_value(l, t)` at every texel t.
fn labelled_mips(gpu: &Gpu, size: (u32, u32), levels: u32) -> MipChain {
    let usage = wgpu::TextureUsages::TEXTURE_BINDING | wgpu::TextureUsages::COPY_DST;
    let chain = MipChain::new(gpu, "labelled mips", size, levels, FORMAT, usage);
    for level in 0..levels {
        let (w, h) = ((size.0 >> level).max(1), (size.1 >> level).max(1));
        let values: Vec<u32> = (0..h).flat_map(|y| (0..w).map(move |x| texel_value(level, (x, y)))).collect();
        gpu.queue.write_texture(
            wgpu::TexelCopyTextureInfo {
                texture: &chain.texture,
                mip_level: level,
                origin: wgpu::Origin3d::ZERO,
                aspect: wgpu::TextureAspect::All,
            },
            bytemuck::cast_slice(&values),
            wgpu::TexelCopyBufferLayout { offset: 0, bytes_per_row: Some(4 * w), rows_per_image: None },
            wgpu::Extent3d { width: w, height: h, depth_or_array_layers: 1 },
        );
    }
    chain
}

/// One fetch pass at the levels of `level_map` (row-major), read back.
fn fetch(
    gpu: &Gpu,
    pipeline: &wgpu::RenderPipeline,
    source: &MipChain,
    level_map: &[u32],
    size: (u32, u32),
) -> Result<Vec<u32>> {
    let map =
        gpu.texture("level map", size, FORMAT, 1, wgpu::TextureUsages::TEXTURE_BINDING | wgpu::TextureUsages::COPY_DST);
    gpu.queue.write_texture(
        map.as_image_copy(),
        bytemuck::cast_slice(level_map),
        wgpu::TexelCopyBufferLayout { offset: 0, bytes_per_row: Some(4 * size.0), rows_per_image: None },
        map.size(),
    );
    let target =
        gpu.texture("fetched", size, FORMAT, 1, wgpu::TextureUsages::RENDER_ATTACHMENT | wgpu::TextureUsages::COPY_SRC);
    let map_view = map.create_view(&Default::default());
    let resources = [wgpu::BindingResource::TextureView(&map_view), wgpu::BindingResource::TextureView(&source.all)];
    let group = bind_group(gpu, "mip fetch", pipeline, 0, &resources);
    let view = target.create_view(&Default::default());
    let mut encoder = gpu.encoder("mip fetch");
    {
        let mut pass = encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
            label: Some("mip fetch"),
            color_attachments: &[crate::attachments::colour(&view, None, wgpu::Color::TRANSPARENT)],
            ..Default::default()
        });
        pass.set_pipeline(pipeline);
        pass.set_bind_group(0, &group, &[]);
        pass.draw(0..3, 0..1);
    }
    gpu.submit(encoder);
    let texels = read_texture(gpu, &target, wgpu::TextureAspect::All, 0)?;
    Ok(bytemuck::pod_collect_to_vec(&texels.bytes))
}
