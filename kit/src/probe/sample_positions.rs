//! Where an adapter puts the samples of an N-sample pixel, found by sweeping an edge across a
//! pixel in 1/256-pixel steps. One draw covers the whole sweep: pixel i of a 256-pixel strip holds
//! a rect whose left (or top) edge sits i/256 into that pixel, so sample k is covered in pixels
//! 0..c_k and the edge crossed it between (c_k - 1)/256 and c_k/256. The rasteriser snaps that
//! edge to its sub-pixel grid first (`probe::subpixel_precision`: 1/16 px may be all there is), so
//! the interval is where the *edge* was, and the sample lies within one grid step of it.
//!
//! Three independent routes read which samples are covered: a per-sample resolve (the pipeline's
//! sample mask lets only sample k write, the resolve averages it into a plain texel); where
//! occlusion queries count, a stencil pass plus one masked occlusion query per sample; and, where
//! fragment shaders may write storage, per-sample invocations recording their `sample_index`.
//! The first two need an honoured pipeline sample mask, the third real per-sample shading.

use anyhow::{Context, Result, bail};
use serde::Serialize;

use crate::attachments::colour;
use crate::fullscreen::{bind_group, uniform_buffer};
use crate::gpu::Gpu;
use crate::query::OcclusionQueries;
use crate::readback::{map_buffer, read_rgba8};
use crate::rects::{Rect, RectBatch, RectFragment, RectPipeline, stencil_equal, stencil_replace};
use crate::shaders;

/// Sweep steps per pixel: the sub-pixel precision probe's resolution (8 bits, the finest grid
/// seen on real rasterisers; the specifications promise only 4).
pub const STEPS: u32 = 256;

/// An interval [lo, hi] (pixels from the pixel's top-left corner) holding one sample coordinate.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct Interval {
    pub lo: f32,
    pub hi: f32,
}

impl Interval {
    fn from_covered_count(count: u32) -> Option<Self> {
        (count > 0).then(|| Self { lo: (count - 1) as f32 / STEPS as f32, hi: count as f32 / STEPS as f32 })
    }

    /// True when `value` lies within `margin` of the interval.
    pub fn within(&self, margin: f32, value: f32) -> bool {
        self.lo - margin <= value && value <= self.hi + margin
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
        4 => Some(&[[0.375, 0.125], [0.875, 0.375], [0.125, 0.625], [0.625, 0.875]]),
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
pub(crate) enum Axis {
    X,
    Y,
}

impl Axis {
    pub(crate) fn strip(self) -> (u32, u32) {
        match self {
            Axis::X => (STEPS, 1),
            Axis::Y => (1, STEPS),
        }
    }

    /// Rect i covers pixel i from an edge i/256 into it to the pixel's far side.
    pub(crate) fn sweep_rects(self) -> Vec<(Rect, [f32; 4])> {
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

/// An edge sweep along `axis` drawn into a `samples`-sample target with pipeline mask
/// `sample_mask`, resolved: each strip pixel's red channel, the share of its samples covered.
pub(crate) fn resolved_sweep(gpu: &Gpu, samples: u32, axis: Axis, sample_mask: u64) -> Result<Vec<u8>> {
    let size = axis.strip();
    let format = wgpu::TextureFormat::Rgba8Unorm;
    // RENDER_ATTACHMENT only: on GL a multisampled texture that is also TEXTURE_BINDING gets no storage.
    let msaa = gpu.texture("sweep msaa", size, format, samples, wgpu::TextureUsages::RENDER_ATTACHMENT);
    let resolved = gpu.texture(
        "sweep resolved",
        size,
        format,
        1,
        wgpu::TextureUsages::RENDER_ATTACHMENT | wgpu::TextureUsages::COPY_SRC,
    );
    let (msaa_view, resolved_view) = (msaa.create_view(&Default::default()), resolved.create_view(&Default::default()));
    let rects = RectBatch::new(gpu, size, &axis.sweep_rects());
    let pipeline = RectPipeline {
        colour_format: Some(format),
        fragment: RectFragment::InstanceColour,
        samples,
        sample_mask,
        ..RectPipeline::new("sample sweep")
    }
    .create(gpu);
    let mut encoder = gpu.encoder("sample sweep");
    {
        let mut pass = encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
            label: Some("sample sweep"),
            color_attachments: &[colour(
                if samples > 1 { &msaa_view } else { &resolved_view },
                (samples > 1).then_some(&resolved_view),
                wgpu::Color::TRANSPARENT,
            )],
            ..Default::default()
        });
        pass.set_pipeline(&pipeline);
        rects.draw(&mut pass, ..);
    }
    gpu.submit(encoder);
    Ok(read_rgba8(gpu, &resolved)?.pixels().map(|p| p[0]).collect())
}

/// Per-sample covered counts along one axis, through per-sample resolves.
fn covered_counts_by_resolve(gpu: &Gpu, samples: u32, axis: Axis) -> Result<Vec<u32>> {
    (0..samples)
        .map(|sample| {
            let covered: Vec<bool> = resolved_sweep(gpu, samples, axis, 1 << sample)?.iter().map(|&v| v > 0).collect();
            covered_prefix(&covered, &format!("{samples}x sample {sample} along {axis:?}"))
        })
        .collect()
}

/// Per-sample covered counts along one axis, through a stencil pass and masked occlusion queries.
/// Meaningful only where occlusion queries count samples.
fn covered_counts_by_occlusion(gpu: &Gpu, samples: u32, axis: Axis) -> Result<Vec<u32>> {
    let size = axis.strip();
    let format = wgpu::TextureFormat::Depth24PlusStencil8;
    let stencil = gpu.texture("sweep stencil", size, format, samples, wgpu::TextureUsages::RENDER_ATTACHMENT);
    let view = stencil.create_view(&Default::default());
    let rects = RectBatch::new(gpu, size, &axis.sweep_rects());
    let full = RectBatch::new(gpu, size, &[(Rect::full(size.0, size.1), [1.0; 4])]);
    let mark =
        RectPipeline { depth_stencil: Some(stencil_replace(format)), samples, ..RectPipeline::new("mark sweep") }
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
                depth_ops: Some(wgpu::Operations { load: wgpu::LoadOp::Clear(1.0), store: wgpu::StoreOp::Discard }),
                stencil_ops: Some(wgpu::Operations { load: wgpu::LoadOp::Clear(0), store: wgpu::StoreOp::Discard }),
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
    gpu.submit(encoder);
    Ok(queries.read(gpu)?.into_iter().map(|c| c as u32).collect())
}

fn positions_from_counts(x: &[u32], y: &[u32]) -> Vec<SamplePosition> {
    x.iter()
        .zip(y)
        .map(|(&cx, &cy)| SamplePosition { x: Interval::from_covered_count(cx), y: Interval::from_covered_count(cy) })
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

/// What each per-sample invocation saw: its `sample_index` and `fract(@builtin(position))`.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct PerSampleShading {
    /// Invocations that ran for one fully covered pixel (N when shading is per sample).
    pub invocations: u32,
    /// `sample_index` of each invocation, ordered by index.
    pub sample_index: Vec<u32>,
    /// `fract(position.xy)` each invocation saw, in the same order.
    pub position: Vec<[f32; 2]>,
}

/// A storage buffer for fragment records plus its read-back twin.
pub(crate) fn storage_pair(gpu: &Gpu, label: &str, size: u64) -> (wgpu::Buffer, wgpu::Buffer) {
    let storage = gpu.device.create_buffer(&wgpu::BufferDescriptor {
        label: Some(label),
        size,
        usage: wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_SRC | wgpu::BufferUsages::COPY_DST,
        mapped_at_creation: false,
    });
    let readback = gpu.device.create_buffer(&wgpu::BufferDescriptor {
        label: Some(label),
        size,
        usage: wgpu::BufferUsages::COPY_DST | wgpu::BufferUsages::MAP_READ,
        mapped_at_creation: false,
    });
    (storage, readback)
}

/// Draws `rects` on an N-sample depth-stencil-only target with a recording fragment shader
/// bound at group 0 and returns the storage buffer's bytes.
/// Where a recording draw writes: a storage buffer (every word first set to `fill`) and its
/// read-back twin.
pub(crate) struct RecordStorage<'a> {
    pub buffer: &'a wgpu::Buffer,
    pub readback: &'a wgpu::Buffer,
    pub fill: u32,
}

pub(crate) fn record_fragments(
    gpu: &Gpu,
    size: (u32, u32),
    samples: u32,
    fragment: RectFragment,
    rects: &[(Rect, [f32; 4])],
    bindings: &[wgpu::BindingResource<'_>],
    storage: RecordStorage<'_>,
) -> Result<Vec<u8>> {
    let format = wgpu::TextureFormat::Depth24PlusStencil8;
    let depth = gpu.texture("recording target", size, format, samples, wgpu::TextureUsages::RENDER_ATTACHMENT);
    let view = depth.create_view(&Default::default());
    let pipeline = RectPipeline {
        depth_stencil: Some(crate::rects::stencil_state(
            format,
            wgpu::CompareFunction::Always,
            wgpu::StencilOperation::Keep,
        )),
        fragment,
        samples,
        ..RectPipeline::new("recording draw")
    }
    .create(gpu);
    let bind_group = bind_group(gpu, "recording bindings", &pipeline, 0, bindings);
    let batch = RectBatch::new(gpu, size, rects);
    // Every word starts as `fill`, so untouched slots are told apart from written ones.
    let words = (storage.buffer.size() / 4) as usize;
    gpu.queue.write_buffer(storage.buffer, 0, bytemuck::cast_slice(&vec![storage.fill; words]));
    let mut encoder = gpu.encoder("recording draw");
    {
        let mut pass = encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
            label: Some("recording draw"),
            depth_stencil_attachment: crate::attachments::stencil(&view, Some(0)),
            ..Default::default()
        });
        pass.set_pipeline(&pipeline);
        pass.set_bind_group(0, &bind_group, &[]);
        batch.draw(&mut pass, ..);
    }
    encoder.copy_buffer_to_buffer(storage.buffer, 0, storage.readback, 0, None);
    gpu.submit(encoder);
    map_buffer(gpu, storage.readback)
}

/// Sample-index slots per pixel in the storage route; the last one also catches larger indices.
const SLOTS_PER_PIXEL: u32 = 32;

/// Per-sample covered counts along one axis, through fragment storage writes indexed by
/// `sample_index` (needs per-sample shading and fragment storage writes). An invocation with a
/// `sample_index` the target should not have is an error naming the indices seen.
fn covered_counts_by_storage(gpu: &Gpu, samples: u32, axis: Axis) -> Result<Vec<u32>> {
    let size = axis.strip();
    let strip = uniform_buffer(gpu, "strip layout", bytemuck::cast_slice(&[size.0, SLOTS_PER_PIXEL, 0, 0]));
    let (storage, readback) = storage_pair(gpu, "covered samples", u64::from(STEPS * SLOTS_PER_PIXEL) * 4);
    let bytes = record_fragments(
        gpu,
        size,
        samples,
        RectFragment::Shader { file: shaders::SAMPLE_COVERAGE_RECORD, entry: "fs_record_sample" },
        &axis.sweep_rects(),
        &[strip.as_entire_binding(), storage.as_entire_binding()],
        RecordStorage { buffer: &storage, readback: &readback, fill: 0 },
    )?;
    let covered: &[u32] = bytemuck::cast_slice(&bytes);
    let pixels = || covered.chunks_exact(SLOTS_PER_PIXEL as usize);
    let seen: Vec<u32> = (0..SLOTS_PER_PIXEL).filter(|&s| pixels().any(|p| p[s as usize] != 0)).collect();
    if seen.iter().any(|&s| s >= samples) {
        bail!("a {samples}x target ran per-sample invocations with sample_index {seen:?}");
    }
    (0..samples as usize)
        .map(|sample| {
            let column: Vec<bool> = pixels().map(|pixel| pixel[sample] != 0).collect();
            covered_prefix(&column, &format!("{samples}x sample {sample} along {axis:?} (storage)"))
        })
        .collect()
}

/// Sample positions read through fragment storage writes indexed by `sample_index`.
pub fn measure_by_storage(gpu: &Gpu, samples: u32) -> Result<Vec<SamplePosition>> {
    gpu.scoped(&format!("{samples}x sample sweep (storage)"), || {
        let x = covered_counts_by_storage(gpu, samples, Axis::X)?;
        let y = covered_counts_by_storage(gpu, samples, Axis::Y)?;
        Ok(positions_from_counts(&x, &y))
    })
}

/// Runs a per-sample shader over one fully covered pixel and lists its invocations.
pub fn measure_per_sample_shading(gpu: &Gpu, samples: u32) -> Result<PerSampleShading> {
    gpu.scoped(&format!("{samples}x per-sample shading probe"), || {
        // Layout of `Invocations` in shaders/kit/sample_position.wgsl: count + 3 pad, 64 × 4 words.
        let (storage, readback) = storage_pair(gpu, "per-sample invocations", (4 + 64 * 4) * 4);
        let bytes = record_fragments(
            gpu,
            (1, 1),
            samples,
            RectFragment::Shader { file: shaders::SAMPLE_POSITION, entry: "fs_sample_position" },
            &[(Rect::full(1, 1), [1.0; 4])],
            &[storage.as_entire_binding()],
            RecordStorage { buffer: &storage, readback: &readback, fill: 0 },
        )?;
        let words: &[u32] = bytemuck::cast_slice(&bytes);
        let invocations = words[0];
        let mut records: Vec<(u32, [f32; 2])> = words[4..]
            .chunks_exact(4)
            .take(invocations.min(64) as usize)
            .map(|r| (r[2], [f32::from_bits(r[0]), f32::from_bits(r[1])]))
            .collect();
        records.sort_by_key(|r| r.0);
        Ok(PerSampleShading {
            invocations,
            sample_index: records.iter().map(|r| r.0).collect(),
            position: records.iter().map(|r| r.1).collect(),
        })
    })
    .context("per-sample shading")
}

/// A way of reading per-sample coverage.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Route {
    Resolve,
    Occlusion,
    Storage,
}

/// The sweep read by every route this adapter allows, and whether the routes agree.
#[derive(Clone, Debug, Serialize)]
pub struct PositionsMeasurement {
    pub sample_mask_honoured: bool,
    pub routes: Vec<(Route, Result<Vec<SamplePosition>, String>)>,
    /// Routes that could not run here, and why.
    pub skipped: Vec<(Route, String)>,
}

impl PositionsMeasurement {
    /// True when some route read single samples here; false when none could run or every one
    /// that ran failed (the kit cannot see single samples on this adapter).
    pub fn read_single_samples(&self) -> bool {
        self.routes.iter().any(|(_, r)| r.is_ok())
    }

    /// The positions all successful routes agree on; None when none succeeded or they disagree.
    pub fn agreed(&self) -> Option<&Vec<SamplePosition>> {
        let mut results = self.routes.iter().filter_map(|(_, r)| r.as_ref().ok());
        let first = results.next()?;
        results.all(|other| other == first).then_some(first)
    }
}

/// Runs the sweep through every route the adapter allows: the mask-based routes only where
/// the mask is honoured, occlusion only where counts are exact, storage only where fragment
/// shaders may write storage.
pub fn measure(gpu: &Gpu, samples: u32) -> Result<PositionsMeasurement> {
    // The routes' results say what each found; the GL errors of a refused target are theirs.
    crate::diagnostics::probing(|| measure_routes(gpu, samples)).0
}

fn measure_routes(gpu: &Gpu, samples: u32) -> Result<PositionsMeasurement> {
    use crate::probe::occlusion::{OcclusionPrecision, measure_occlusion_precision};
    use crate::probe::sample_mask::measure_sample_mask;
    let sample_mask_honoured = samples == 1 || measure_sample_mask(gpu, samples)?.iter().all(|m| m.honoured());
    let exact_occlusion = measure_occlusion_precision(gpu)? == OcclusionPrecision::Exact;
    let fragment_storage = crate::probe::fragment_storage::fragment_storage_problem(gpu)?.is_none();
    let mut routes = Vec::new();
    let mut skipped = Vec::new();
    let text = |r: Result<Vec<SamplePosition>>| r.map_err(|e| format!("{e:#}"));
    if sample_mask_honoured {
        routes.push((Route::Resolve, text(measure_by_resolve(gpu, samples))));
        if exact_occlusion {
            routes.push((Route::Occlusion, text(measure_by_occlusion(gpu, samples))));
        } else {
            skipped.push((Route::Occlusion, "occlusion queries do not count samples".into()));
        }
    } else {
        let why = "the pipeline sample mask is ignored";
        skipped.push((Route::Resolve, why.into()));
        skipped.push((Route::Occlusion, why.into()));
    }
    if fragment_storage {
        // The route also needs per-sample shading, which GLES 3.1 lacks: a refused shader means
        // the route cannot run here, not that it measured wrong.
        let measured = text(measure_by_storage(gpu, samples));
        match measured.as_ref().err().and_then(|error| crate::harness::capability::missing_capability(error)) {
            Some(missing) => skipped.push((Route::Storage, format!("per-sample shading: {missing}"))),
            None => routes.push((Route::Storage, measured)),
        }
    } else {
        skipped.push((Route::Storage, "fragment shaders cannot write storage".into()));
    }
    Ok(PositionsMeasurement { sample_mask_honoured, routes, skipped })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_value_is_within_an_interval_up_to_its_margin_on_either_side_and_no_further() {
        let interval = Interval::from_covered_count(65).expect("a covered count");
        assert_eq!(interval, Interval { lo: 0.25, hi: 65.0 / 256.0 });
        assert_eq!(Interval::from_covered_count(0), None);
        let margin = 1.0 / 16.0;
        for (value, within) in [
            (0.25 - margin, true),
            (65.0 / 256.0 + margin, true),
            (0.25 - margin - 1e-4, false),
            (65.0 / 256.0 + margin + 1e-4, false),
            (0.25, true),
        ] {
            assert_eq!(interval.within(margin, value), within, "{value}");
        }
        assert_eq!(interval.mid(), (0.25 + 65.0 / 256.0) / 2.0);
        let located = SamplePosition { x: Some(interval), y: Interval::from_covered_count(128) };
        assert_eq!(located.mid(), Some([interval.mid(), 127.5 / 256.0]));
        assert_eq!(SamplePosition { y: None, ..located }.mid(), None);
    }
}
