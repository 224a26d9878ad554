//! Where an adapter puts the samples of an N-sample pixel, found by sweeping an edge across a
//! pixel in 1/256-pixel steps. One draw covers the whole sweep: pixel i of a 256-pixel strip holds
//! a rect whose left (or top) edge sits i/256 into that pixel, so sample k is covered in pixels
//! 0..c_k and its coordinate lies in [(c_k - 1)/256, c_k/256].
//!
//! Two independent routes read which samples are covered: a per-sample resolve (the pipeline's
//! sample mask lets only sample k write, the resolve averages it into a plain texel) and, where
//! occlusion queries count, a stencil pass plus one masked occlusion query per sample.

use anyhow::{Context, Result, bail};
use serde::Serialize;

use crate::attachments::colour;
use crate::gpu::Gpu;
use crate::query::OcclusionQueries;
use crate::readback::{read_rgba8, read_texture};
use crate::rects::{Rect, RectBatch, RectFragment, RectPipeline, stencil_equal, stencil_replace};

/// Sweep steps per pixel; rasterisers snap to at least 8 sub-pixel bits, so finer steps mean nothing.
pub const STEPS: u32 = 256;

/// An interval [lo, hi] (pixels from the pixel's top-left corner) holding one sample coordinate.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct Interval {
    pub lo: f32,
    pub hi: f32,
}

impl Interval {
    fn from_covered_count(count: u32) -> Option<Self> {
        (count > 0).then(|| Self {
            lo: (count - 1) as f32 / STEPS as f32,
            hi: count as f32 / STEPS as f32,
        })
    }

    pub fn contains(&self, value: f32) -> bool {
        self.lo <= value && value <= self.hi
    }

    pub fn mid(&self) -> f32 {
        0.5 * (self.lo + self.hi)
    }
}

/// One sample's measured position, or why it could not be located.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct SamplePosition {
    pub x: Option<Interval>,
    pub y: Option<Interval>,
}

impl SamplePosition {
    pub fn mid(&self) -> Option<[f32; 2]> {
        Some([self.x?.mid(), self.y?.mid()])
    }
}

/// The standard positions (Vulkan/D3D tables) in pixels from the top-left corner.
pub fn standard_positions(samples: u32) -> Option<&'static [[f32; 2]]> {
    match samples {
        1 => Some(&[[0.5, 0.5]]),
        2 => Some(&[[0.75, 0.75], [0.25, 0.25]]),
        4 => Some(&[
            [0.375, 0.125],
            [0.875, 0.375],
            [0.125, 0.625],
            [0.625, 0.875],
        ]),
        8 => Some(&[
            [0.5625, 0.3125],
            [0.4375, 0.6875],
            [0.8125, 0.5625],
            [0.3125, 0.1875],
            [0.1875, 0.8125],
            [0.0625, 0.4375],
            [0.6875, 0.9375],
            [0.9375, 0.0625],
        ]),
        _ => None,
    }
}

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Axis {
    X,
    Y,
}

impl Axis {
    fn strip(self) -> (u32, u32) {
        match self {
            Axis::X => (STEPS, 1),
            Axis::Y => (1, STEPS),
        }
    }

    /// Rect i covers pixel i from an edge i/256 into it to the pixel's far side.
    fn sweep_rects(self) -> Vec<(Rect, [f32; 4])> {
        (0..STEPS)
            .map(|i| {
                let edge = i as f32 + i as f32 / STEPS as f32;
                let far = (i + 1) as f32;
                let rect = match self {
                    Axis::X => Rect::new(edge, 0.0, far, 1.0),
                    Axis::Y => Rect::new(0.0, edge, 1.0, far),
                };
                (rect, [1.0; 4])
            })
            .collect()
    }
}

/// Number of leading covered pixels, or an error if coverage is not a prefix (an edge sweep
/// must uncover a sample once and for all).
fn covered_prefix(covered: &[bool], what: &str) -> Result<u32> {
    let count = covered.iter().take_while(|&&c| c).count();
    if covered[count..].iter().any(|&c| c) {
        bail!("{what}: coverage is not monotonic along the sweep ({covered:?})");
    }
    Ok(count as u32)
}

/// Per-sample covered counts along one axis, through per-sample resolves.
fn covered_counts_by_resolve(gpu: &Gpu, samples: u32, axis: Axis) -> Result<Vec<u32>> {
    let size = axis.strip();
    let format = wgpu::TextureFormat::Rgba8Unorm;
    // RENDER_ATTACHMENT only: on GL a multisampled texture that is also TEXTURE_BINDING gets no storage.
    let msaa = gpu.texture(
        "sweep msaa",
        size,
        format,
        samples,
        wgpu::TextureUsages::RENDER_ATTACHMENT,
    );
    let resolved = gpu.texture(
        "sweep resolved",
        size,
        format,
        1,
        wgpu::TextureUsages::RENDER_ATTACHMENT | wgpu::TextureUsages::COPY_SRC,
    );
    let (msaa_view, resolved_view) = (
        msaa.create_view(&Default::default()),
        resolved.create_view(&Default::default()),
    );
    let rects = RectBatch::new(gpu, size, &axis.sweep_rects());
    let mut counts = Vec::new();
    for sample in 0..samples {
        let pipeline = RectPipeline {
            colour_format: Some(format),
            fragment: RectFragment::InstanceColour,
            samples,
            sample_mask: 1 << sample,
            ..RectPipeline::new("sweep, one sample")
        }
        .create(gpu);
        let mut encoder = gpu.encoder("sample sweep");
        {
            let mut pass = encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
                label: Some("sample sweep"),
                color_attachments: &[colour(
                    if samples > 1 {
                        &msaa_view
                    } else {
                        &resolved_view
                    },
                    (samples > 1).then_some(&resolved_view),
                    wgpu::Color::TRANSPARENT,
                )],
                ..Default::default()
            });
            pass.set_pipeline(&pipeline);
            rects.draw(&mut pass, ..);
        }
        gpu.queue.submit([encoder.finish()]);
        let image = read_rgba8(gpu, &resolved)?;
        let covered: Vec<bool> = image.pixels().map(|p| p[0] > 0).collect();
        counts.push(covered_prefix(
            &covered,
            &format!("{samples}x sample {sample} along {axis:?}"),
        )?);
    }
    Ok(counts)
}

/// Per-sample covered counts along one axis, through a stencil pass and masked occlusion queries.
/// Meaningful only where occlusion queries count samples.
fn covered_counts_by_occlusion(gpu: &Gpu, samples: u32, axis: Axis) -> Result<Vec<u32>> {
    let size = axis.strip();
    let format = wgpu::TextureFormat::Depth24PlusStencil8;
    let stencil = gpu.texture(
        "sweep stencil",
        size,
        format,
        samples,
        wgpu::TextureUsages::RENDER_ATTACHMENT,
    );
    let view = stencil.create_view(&Default::default());
    let rects = RectBatch::new(gpu, size, &axis.sweep_rects());
    let full = RectBatch::new(gpu, size, &[(Rect::full(size.0, size.1), [1.0; 4])]);
    let mark = RectPipeline {
        depth_stencil: Some(stencil_replace(format)),
        samples,
        ..RectPipeline::new("mark sweep")
    }
    .create(gpu);
    let count_pipelines: Vec<_> = (0..samples)
        .map(|sample| {
            RectPipeline {
                depth_stencil: Some(stencil_equal(format)),
                samples,
                sample_mask: 1 << sample,
                ..RectPipeline::new("count one sample")
            }
            .create(gpu)
        })
        .collect();
    let queries = OcclusionQueries::new(gpu, samples);
    let mut encoder = gpu.encoder("sample sweep by occlusion");
    {
        let mut pass = encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
            label: Some("sample sweep by occlusion"),
            depth_stencil_attachment: Some(wgpu::RenderPassDepthStencilAttachment {
                view: &view,
                depth_ops: Some(wgpu::Operations {
                    load: wgpu::LoadOp::Clear(1.0),
                    store: wgpu::StoreOp::Discard,
                }),
                stencil_ops: Some(wgpu::Operations {
                    load: wgpu::LoadOp::Clear(0),
                    store: wgpu::StoreOp::Discard,
                }),
            }),
            occlusion_query_set: Some(queries.set()),
            ..Default::default()
        });
        pass.set_stencil_reference(1);
        pass.set_pipeline(&mark);
        rects.draw(&mut pass, ..);
        for (sample, pipeline) in count_pipelines.iter().enumerate() {
            pass.set_pipeline(pipeline);
            pass.begin_occlusion_query(sample as u32);
            full.draw(&mut pass, ..);
            pass.end_occlusion_query();
        }
    }
    queries.resolve(&mut encoder);
    gpu.queue.submit([encoder.finish()]);
    Ok(queries.read(gpu)?.into_iter().map(|c| c as u32).collect())
}

fn positions_from_counts(x: &[u32], y: &[u32]) -> Vec<SamplePosition> {
    x.iter()
        .zip(y)
        .map(|(&cx, &cy)| SamplePosition {
            x: Interval::from_covered_count(cx),
            y: Interval::from_covered_count(cy),
        })
        .collect()
}

/// Sample positions read through per-sample resolves (works on every backend).
pub fn measure_by_resolve(gpu: &Gpu, samples: u32) -> Result<Vec<SamplePosition>> {
    gpu.scoped(&format!("{samples}x sample sweep (resolve)"), || {
        let x = covered_counts_by_resolve(gpu, samples, Axis::X)?;
        let y = covered_counts_by_resolve(gpu, samples, Axis::Y)?;
        Ok(positions_from_counts(&x, &y))
    })
}

/// Sample positions read through occlusion counts (needs exact occlusion queries).
pub fn measure_by_occlusion(gpu: &Gpu, samples: u32) -> Result<Vec<SamplePosition>> {
    gpu.scoped(&format!("{samples}x sample sweep (occlusion)"), || {
        let x = covered_counts_by_occlusion(gpu, samples, Axis::X)?;
        let y = covered_counts_by_occlusion(gpu, samples, Axis::Y)?;
        Ok(positions_from_counts(&x, &y))
    })
}

/// What `@builtin(position)` and `sample_index` report under per-sample shading, per sample.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct PerSampleShading {
    /// `sample_index` each sample's invocation saw (None where nothing was written).
    pub sample_index: Vec<Option<u32>>,
    /// `fract(position.xy)` each sample's invocation saw.
    pub position: Vec<[f32; 2]>,
}

/// Runs a per-sample shader on a 1×1 target and reads each sample's output through a masked resolve.
pub fn measure_per_sample_shading(gpu: &Gpu, samples: u32) -> Result<PerSampleShading> {
    gpu.scoped(&format!("{samples}x per-sample shading probe"), || {
        let format = wgpu::TextureFormat::Rgba16Float;
        let msaa = gpu.texture(
            "per-sample msaa",
            (1, 1),
            format,
            samples,
            wgpu::TextureUsages::RENDER_ATTACHMENT,
        );
        let resolved = gpu.texture(
            "per-sample resolved",
            (1, 1),
            format,
            1,
            wgpu::TextureUsages::RENDER_ATTACHMENT | wgpu::TextureUsages::COPY_SRC,
        );
        let (msaa_view, resolved_view) = (
            msaa.create_view(&Default::default()),
            resolved.create_view(&Default::default()),
        );
        let full = RectBatch::new(gpu, (1, 1), &[(Rect::full(1, 1), [1.0; 4])]);
        let mut result = PerSampleShading {
            sample_index: Vec::new(),
            position: Vec::new(),
        };
        for sample in 0..samples {
            let pipeline = RectPipeline {
                colour_format: Some(format),
                fragment: RectFragment::SamplePosition,
                samples,
                sample_mask: 1 << sample,
                ..RectPipeline::new("per-sample probe")
            }
            .create(gpu);
            let mut encoder = gpu.encoder("per-sample probe");
            {
                let mut pass = encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
                    label: Some("per-sample probe"),
                    color_attachments: &[colour(
                        if samples > 1 {
                            &msaa_view
                        } else {
                            &resolved_view
                        },
                        (samples > 1).then_some(&resolved_view),
                        wgpu::Color::TRANSPARENT,
                    )],
                    ..Default::default()
                });
                pass.set_pipeline(&pipeline);
                full.draw(&mut pass, ..);
            }
            gpu.queue.submit([encoder.finish()]);
            // Only sample `sample` was written; the resolve averaged it with zeros.
            let texel = read_texture(gpu, &resolved, wgpu::TextureAspect::All, 0)?.as_f16();
            let n = samples as f32;
            let index_code = (texel[2] * n * 16.0).round() as i64 - 1;
            result.sample_index.push(u32::try_from(index_code).ok());
            result.position.push([texel[0] * n, texel[1] * n]);
        }
        Ok(result)
    })
    .context("per-sample shading")
}
