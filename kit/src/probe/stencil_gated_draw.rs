//! A heavy full-screen fragment shader (`shaders/kit/heavy_shading.wgsl`) behind a stencil test:
//! a square in the top-left corner is marked in the stencil, then the heavy draw runs with
//! stencil Equal (only the square passes) or Always (every pixel passes). Comparing the two GPU
//! times shows whether the adapter rejects fragments before shading them.

use std::time::Instant;

use anyhow::{Result, ensure};
use wgpu::util::DeviceExt;

use crate::attachments;
use crate::fullscreen::{FullscreenPipeline, bind_group, uniform_buffer};
use crate::gpu::Gpu;
use crate::query::{GpuTimer, OcclusionQueries};
use crate::readback::read_buffer_words;
use crate::rects::{Rect, RectBatch, RectPipeline, stencil_replace, stencil_state};
use crate::shaders;
use fragkit_report::noise::median;

const STENCIL: wgpu::TextureFormat = wgpu::TextureFormat::Depth24PlusStencil8;

/// Above this Equal/Always time ratio the adapter shades rejected fragments anyway: halfway
/// between perfect rejection (the passing fraction, ≤ 0.02 at the probe's defaults) and none (1).
pub const REJECTION_RATIO_LIMIT: f64 = 0.5;

/// Equal and Always GPU times (medians) and their ratio.
#[derive(Clone, Copy, Debug)]
pub struct GateTimes {
    pub equal_ms: f64,
    pub always_ms: f64,
    /// The first Equal draw's measurements (its occlusion count).
    pub first_equal: GatedDraw,
}

impl GateTimes {
    pub fn ratio(&self) -> f64 {
        self.equal_ms / self.always_ms
    }
}

/// The kit's capability probe at `kit.early_rejection`'s defaults (256×256, a 36×36 square,
/// 96 iterations, 3 repeats): whether this adapter skips stencil-rejected fragments, and the ratio.
pub fn adapter_rejects_early(gpu: &Gpu) -> Result<(bool, f64)> {
    let ratio = StencilGatedDraw::new(gpu, (256, 256), (36, 36), 96)?.time(gpu, 3)?.ratio();
    Ok((ratio <= REJECTION_RATIO_LIMIT, ratio))
}
const COLOUR: wgpu::TextureFormat = wgpu::TextureFormat::Rgba8Unorm;

/// Which stencil test gates the heavy draw.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Gate {
    /// Only the marked square passes.
    Equal,
    /// Every pixel passes.
    Always,
}

/// One gated draw's measurements.
#[derive(Clone, Copy, Debug)]
pub struct GatedDraw {
    /// Begin-to-end timestamps of the heavy pass; None without timestamps.
    pub gpu_ms: Option<f64>,
    /// Submit-and-wait of the heavy pass alone.
    pub wall_ms: f64,
    /// Occlusion count of samples that passed the gate.
    pub passing_samples: u64,
}

pub struct StencilGatedDraw {
    stencil_view: wgpu::TextureView,
    colour_view: wgpu::TextureView,
    mark: wgpu::RenderPipeline,
    square: RectBatch,
    equal: (wgpu::RenderPipeline, wgpu::BindGroup),
    always: (wgpu::RenderPipeline, wgpu::BindGroup),
}

fn heavy_pipeline(
    gpu: &Gpu,
    compare: wgpu::CompareFunction,
    workload: &wgpu::Buffer,
) -> (wgpu::RenderPipeline, wgpu::BindGroup) {
    let pipeline = FullscreenPipeline {
        label: "heavy shading",
        fragment: shaders::HEAVY_SHADING,
        entry_point: "fs_heavy",
        targets: &[Some(COLOUR.into())],
        depth_stencil: Some(stencil_state(STENCIL, compare, wgpu::StencilOperation::Keep)),
        samples: 1,
    }
    .create(gpu);
    let bind_group = bind_group(gpu, "workload", &pipeline, 0, &[workload.as_entire_binding()]);
    (pipeline, bind_group)
}

impl StencilGatedDraw {
    /// A `size` target whose top-left `passing` square is marked; the shader loops `iterations` times.
    pub fn new(gpu: &Gpu, size: (u32, u32), passing: (u32, u32), iterations: u32) -> Result<Self> {
        ensure!(passing.0 <= size.0 && passing.1 <= size.1, "passing square {passing:?} exceeds the target {size:?}");
        let stencil = gpu.texture("gate stencil", size, STENCIL, 1, wgpu::TextureUsages::RENDER_ATTACHMENT);
        let colour = gpu.texture("heavy colour", size, COLOUR, 1, wgpu::TextureUsages::RENDER_ATTACHMENT);
        let workload = uniform_buffer(gpu, "workload", bytemuck::cast_slice(&[iterations, 0, 0, 0]));
        Ok(Self {
            stencil_view: stencil.create_view(&Default::default()),
            colour_view: colour.create_view(&Default::default()),
            mark: RectPipeline {
                depth_stencil: Some(stencil_replace(STENCIL)),
                ..RectPipeline::new("mark passing square")
            }
            .create(gpu),
            square: RectBatch::new(gpu, size, &[(Rect::new(0.0, 0.0, passing.0 as f32, passing.1 as f32), [1.0; 4])]),
            equal: heavy_pipeline(gpu, wgpu::CompareFunction::Equal, &workload),
            always: heavy_pipeline(gpu, wgpu::CompareFunction::Always, &workload),
        })
    }

    /// Marks the square, then times the heavy draw under `gate` in a pass of its own.
    pub fn draw(&self, gpu: &Gpu, gate: Gate) -> Result<GatedDraw> {
        let mut encoder = gpu.encoder("mark");
        {
            let mut pass = encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
                label: Some("mark"),
                depth_stencil_attachment: attachments::stencil(&self.stencil_view, Some(0)),
                ..Default::default()
            });
            pass.set_stencil_reference(1);
            pass.set_pipeline(&self.mark);
            self.square.draw(&mut pass, ..);
        }
        gpu.submit(encoder);
        gpu.wait()?;

        let (pipeline, bind_group) = match gate {
            Gate::Equal => &self.equal,
            Gate::Always => &self.always,
        };
        let queries = OcclusionQueries::new(gpu, 1);
        let mut timer = GpuTimer::new(gpu, 1);
        let mut encoder = gpu.encoder("heavy draw");
        {
            let mut pass = encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
                label: Some("heavy draw"),
                color_attachments: &[attachments::colour(&self.colour_view, None, wgpu::Color::BLACK)],
                depth_stencil_attachment: attachments::stencil(&self.stencil_view, None),
                occlusion_query_set: Some(queries.set()),
                timestamp_writes: timer.pass("heavy draw"),
                ..Default::default()
            });
            pass.set_stencil_reference(1);
            pass.set_pipeline(pipeline);
            pass.set_bind_group(0, bind_group, &[]);
            pass.begin_occlusion_query(0);
            pass.draw(0..3, 0..1);
            pass.end_occlusion_query();
        }
        queries.resolve(&mut encoder);
        timer.resolve(&mut encoder);
        let started = Instant::now();
        gpu.submit(encoder);
        gpu.wait()?;
        let wall_ms = started.elapsed().as_secs_f64() * 1e3;
        let gpu_ms = timer.read(gpu)?.first().map(|t| t.ms);
        Ok(GatedDraw { gpu_ms, wall_ms, passing_samples: queries.read(gpu)?[0] })
    }

    /// One untimed round of both gates (shader compilation), then `repeats` timed rounds; GPU
    /// time where the adapter has timestamps, else the wall time of a submit-and-wait.
    pub fn time(&self, gpu: &Gpu, repeats: u64) -> Result<GateTimes> {
        let first_equal = self.draw(gpu, Gate::Equal)?;
        self.draw(gpu, Gate::Always)?;
        let time_ms = |draw: GatedDraw| draw.gpu_ms.unwrap_or(draw.wall_ms);
        let (mut equal, mut always) = (Vec::new(), Vec::new());
        for _ in 0..repeats.max(1) {
            equal.push(time_ms(self.draw(gpu, Gate::Equal)?));
            always.push(time_ms(self.draw(gpu, Gate::Always)?));
        }
        Ok(GateTimes { equal_ms: median(equal), always_ms: median(always), first_equal })
    }

    /// Counts the fragments behind the Equal gate with an atomic under forced early tests
    /// (needs `SHADER_EARLY_DEPTH_TEST` and fragment storage writes). Marks the square first.
    pub fn count_fragments_with_atomic(&self, gpu: &Gpu) -> Result<u32> {
        self.draw(gpu, Gate::Equal)?;
        let pipeline = FullscreenPipeline {
            label: "fragment counter",
            fragment: shaders::FRAGMENT_COUNTER,
            entry_point: "fs_count",
            targets: &[],
            depth_stencil: Some(stencil_state(STENCIL, wgpu::CompareFunction::Equal, wgpu::StencilOperation::Keep)),
            samples: 1,
        }
        .create(gpu);
        let counter = gpu.device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
            label: Some("fragment counter"),
            contents: bytemuck::cast_slice(&[0u32]),
            usage: wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_SRC,
        });
        let bind_group = bind_group(gpu, "fragment counter", &pipeline, 0, &[counter.as_entire_binding()]);
        let mut encoder = gpu.encoder("fragment counter");
        {
            let mut pass = encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
                label: Some("fragment counter"),
                depth_stencil_attachment: attachments::stencil(&self.stencil_view, None),
                ..Default::default()
            });
            pass.set_stencil_reference(1);
            pass.set_pipeline(&pipeline);
            pass.set_bind_group(0, &bind_group, &[]);
            pass.draw(0..3, 0..1);
        }
        gpu.submit(encoder);
        Ok(read_buffer_words(gpu, &counter)?[0])
    }
}
