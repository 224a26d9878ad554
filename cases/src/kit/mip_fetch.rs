//! `kit.fetch.per_pixel_level`: `textureLoad` from a mipmapped texture at a level that differs
//! between neighbouring pixels (what the CPS composite does: each pixel reads its own level)
//! returns every pixel's own level's texel. Level maps vary per pixel, per 2×2 quad, per 4×4 and
//! per 8×8 block (seeded), so a failure also says at what granularity the adapter may vary the
//! level; each is fetched with the level straight from the map and with the level as a loop
//! counter (uniform across lanes).

use anyhow::{Context, Result, ensure};
use fragkit::cps::targets::MipChain;
use fragkit::fullscreen::{FullscreenPipeline, bind_group};
use fragkit::gpu::Gpu;
use fragkit::harness::{Case, Ctx, Outcome, ParamKind, ParamSpec, Sweep, SweepRange};
use fragkit::image_compare::side_by_side;
use fragkit::readback::read_texture;
use fragkit::scene::hash::SeededRng;
use fragkit::shaders;
use image::{Rgba, RgbaImage};

pub const CASE: Case = Case {
    name: "kit.fetch.per_pixel_level",
    summary: "textureLoad at a mip level that varies between neighbouring pixels reads each pixel's own level",
    requires: wgpu::Features::empty(),
    params: &[
        ParamSpec {
            name: "size",
            kind: ParamKind::Sizes,
            default: "64x64",
            help: "target and base mip size (powers of two, at most 4096)",
        },
        ParamSpec { name: "seed", kind: ParamKind::Count, default: "1", help: "seed of the level maps" },
    ],
    sweep: &[Sweep { param: "seed", range: SweepRange::Count(0, 1 << 20) }],
    run,
};

const FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::R32Uint;
/// Side of the blocks that share one level, from per pixel to 8×8.
const BLOCKS: [u32; 4] = [1, 2, 4, 8];
const WAYS: [(&str, &str); 2] = [("varying", "fs_fetch_varying_level"), ("uniform", "fs_fetch_uniform_level")];

/// Set in every texel, so that 0 means "read no texel" (out-of-bounds reads return 0).
const PRESENT: u32 = 1 << 31;

/// What mip `level` holds at texel `t`: the level and the texel, so a wrong fetch says what it read.
fn texel_value(level: u32, t: (u32, u32)) -> u32 {
    PRESENT | (level << 24) | (t.1 << 12) | t.0
}

fn describe(value: u32) -> String {
    if value & PRESENT == 0 {
        format!("{value} (no texel: out of the level's bounds)")
    } else {
        format!("level {} texel ({}, {})", (value >> 24) & 0x7f, value & 0xfff, (value >> 12) & 0xfff)
    }
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
            color_attachments: &[fragkit::attachments::colour(&view, None, wgpu::Color::TRANSPARENT)],
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

/// A picture of fetched values: red = level, green and blue = texel coordinates.
fn picture(values: &[u32], size: (u32, u32), levels: u32) -> RgbaImage {
    RgbaImage::from_fn(size.0, size.1, |x, y| {
        let v = values[(y * size.0 + x) as usize];
        let level = ((v >> 24) & 0x7f).min(levels);
        Rgba([(255 * level / levels.max(1)) as u8, (((v >> 12) & 0xfff) * 37) as u8, ((v & 0xfff) * 53) as u8, 255])
    })
}

fn run(ctx: &mut Ctx) -> Result<Outcome> {
    // Setup: a labelled mip chain and seeded level maps.
    let size = *ctx.params.sizes("size")?.first().context("size")?;
    ensure!(
        size.0.is_power_of_two() && size.1.is_power_of_two() && size.0 <= 4096 && size.1 <= 4096,
        "size {}x{}: both sides must be powers of two up to 4096 (each pixel's texel is p >> level)",
        size.0,
        size.1
    );
    let seed = ctx.params.count("seed")? as u32;
    let levels = size.0.max(size.1).trailing_zeros() + 1;
    let source = labelled_mips(ctx.gpu, size, levels);
    let pipelines = WAYS.map(|(way, entry_point)| {
        let pipeline = FullscreenPipeline {
            label: "mip fetch",
            fragment: shaders::MIP_FETCH,
            entry_point,
            targets: &[Some(FORMAT.into())],
            depth_stencil: None,
            samples: 1,
        }
        .create(ctx.gpu);
        (way, pipeline)
    });
    ctx.metric("levels", levels);

    let mut problems = Vec::new();
    for block in BLOCKS {
        let mut rng = SeededRng::new(seed ^ block);
        let per_block: Vec<u32> =
            (0..size.0.div_ceil(block) * size.1.div_ceil(block)).map(|_| rng.range(0, levels)).collect();
        let level_map: Vec<u32> = (0..size.1)
            .flat_map(|y| (0..size.0).map(move |x| (y / block, x / block)))
            .map(|(by, bx)| per_block[(by * size.0.div_ceil(block) + bx) as usize])
            .collect();
        // Expected: each pixel reads its own level's texel p >> level.
        let expected: Vec<u32> = level_map
            .iter()
            .enumerate()
            .map(|(i, &l)| texel_value(l, ((i as u32 % size.0) >> l, (i as u32 / size.0) >> l)))
            .collect();
        for (way, pipeline) in &pipelines {
            // Render and measure.
            let fetched = fetch(ctx.gpu, pipeline, &source, &level_map, size)?;
            let wrong: Vec<usize> = (0..expected.len()).filter(|&i| fetched[i] != expected[i]).collect();
            let label = format!("{way}.{block}x{block}");
            ctx.metric(&format!("{label}.wrong_fetches"), wrong.len());
            if let Some(&first) = wrong.first() {
                let (x, y) = (first as u32 % size.0, first as u32 / size.0);
                problems.push(format!(
                    "level {way} per {block}x{block} block: {} of {} fetches read another texel (pixel ({x}, {y}) at level {} \
                     read {})",
                    wrong.len(),
                    expected.len(),
                    level_map[first],
                    describe(fetched[first])
                ));
                let mask = RgbaImage::from_fn(size.0, size.1, |x, y| {
                    let i = (y * size.0 + x) as usize;
                    if fetched[i] == expected[i] { Rgba([0, 0, 0, 255]) } else { Rgba([255, 0, 0, 255]) }
                });
                let evidence = side_by_side(&picture(&fetched, size, levels), &picture(&expected, size, levels), &mask);
                ctx.evidence_image(&label, &evidence)?;
            }
        }
    }
    Ok(if problems.is_empty() { Outcome::Pass } else { Outcome::Fail(problems.join("; ")) })
}
