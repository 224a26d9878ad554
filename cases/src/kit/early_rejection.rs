//! `kit.early_rejection`: a heavy fragment shader behind a stencil-Equal test that passes ≤ 2 %
//! of the pixels must cost far less GPU time than the same draw with stencil Always. Counts are
//! checked exactly (occlusion query; atomic counter under `@early_depth_test(force)` where the
//! feature exists); the time ratio is a capability result, since a driver may legally shade late.

use anyhow::Result;
use fragkit::attachments;
use fragkit::gpu::Gpu;
use fragkit::harness::{Case, Ctx, Outcome, ParamKind, ParamSpec};
use fragkit::probe::occlusion::{OcclusionPrecision, measure_occlusion_precision};
use fragkit::query::{GpuTimer, OcclusionQueries};
use fragkit::readback::map_buffer;
use fragkit::rects::{Rect, RectBatch, RectPipeline, stencil_replace, stencil_state};
use fragkit::shaders;
use wgpu::util::DeviceExt;

pub const CASE: Case = Case {
    name: "kit.early_rejection",
    summary: "a stencil-Equal test that passes few pixels skips the fragment shader for the rest",
    requires: wgpu::Features::empty(),
    params: &[
        ParamSpec {
            name: "size",
            kind: ParamKind::Sizes,
            default: "256x256",
            help: "target size",
        },
        ParamSpec {
            name: "passing",
            kind: ParamKind::Sizes,
            default: "36x36",
            help: "stencil-marked square (1.98 % of 256x256)",
        },
        ParamSpec {
            name: "iterations",
            kind: ParamKind::Count,
            default: "96",
            help: "shader loop length",
        },
        ParamSpec {
            name: "repeats",
            kind: ParamKind::Count,
            default: "3",
            help: "timed repeats (median taken)",
        },
    ],
    run,
};

/// Above this Equal/Always time ratio the adapter is judged to shade rejected fragments anyway:
/// halfway between perfect rejection (the passing fraction, ≤ 0.02) and none (1.0).
const REJECTION_RATIO_LIMIT: f64 = 0.5;

const STENCIL: wgpu::TextureFormat = wgpu::TextureFormat::Depth24PlusStencil8;
const COLOUR: wgpu::TextureFormat = wgpu::TextureFormat::Rgba8Unorm;

fn heavy_pipeline(gpu: &Gpu, compare: wgpu::CompareFunction) -> wgpu::RenderPipeline {
    let module = shaders::HEAVY_SHADING.module(gpu);
    gpu.device
        .create_render_pipeline(&wgpu::RenderPipelineDescriptor {
            label: Some("heavy shading"),
            layout: None,
            vertex: wgpu::VertexState {
                module: &module,
                entry_point: Some("vs_fullscreen"),
                compilation_options: Default::default(),
                buffers: &[],
            },
            primitive: Default::default(),
            depth_stencil: Some(stencil_state(
                STENCIL,
                compare,
                wgpu::StencilOperation::Keep,
            )),
            multisample: Default::default(),
            fragment: Some(wgpu::FragmentState {
                module: &module,
                entry_point: Some("fs_heavy"),
                compilation_options: Default::default(),
                targets: &[Some(COLOUR.into())],
            }),
            multiview_mask: None,
            cache: None,
        })
}

fn counter_pipeline(gpu: &Gpu) -> wgpu::RenderPipeline {
    let module = shaders::FRAGMENT_COUNTER.module(gpu);
    gpu.device
        .create_render_pipeline(&wgpu::RenderPipelineDescriptor {
            label: Some("fragment counter"),
            layout: None,
            vertex: wgpu::VertexState {
                module: &module,
                entry_point: Some("vs_fullscreen"),
                compilation_options: Default::default(),
                buffers: &[],
            },
            primitive: Default::default(),
            depth_stencil: Some(stencil_state(
                STENCIL,
                wgpu::CompareFunction::Equal,
                wgpu::StencilOperation::Keep,
            )),
            multisample: Default::default(),
            fragment: Some(wgpu::FragmentState {
                module: &module,
                entry_point: Some("fs_count"),
                compilation_options: Default::default(),
                targets: &[],
            }),
            multiview_mask: None,
            cache: None,
        })
}

/// Results of one stencil-marked frame: the Equal and Always heavy draws timed separately.
struct Frame {
    equal_ms: f64,
    always_ms: f64,
    equal_samples: u64,
    counted_fragments: Option<u32>,
}

fn render_frame(
    ctx: &mut Ctx,
    size: (u32, u32),
    passing: (u32, u32),
    iterations: u32,
    count_fragments: bool,
) -> Result<Frame> {
    let gpu = ctx.gpu;
    let stencil = gpu.texture(
        "stencil",
        size,
        STENCIL,
        1,
        wgpu::TextureUsages::RENDER_ATTACHMENT,
    );
    let colour = gpu.texture(
        "heavy colour",
        size,
        COLOUR,
        1,
        wgpu::TextureUsages::RENDER_ATTACHMENT,
    );
    let (stencil_view, colour_view) = (
        stencil.create_view(&Default::default()),
        colour.create_view(&Default::default()),
    );
    let mark = RectPipeline {
        depth_stencil: Some(stencil_replace(STENCIL)),
        ..RectPipeline::new("mark passing square")
    }
    .create(gpu);
    let square = RectBatch::new(
        gpu,
        size,
        &[(
            Rect::new(0.0, 0.0, passing.0 as f32, passing.1 as f32),
            [1.0; 4],
        )],
    );
    let workload = gpu
        .device
        .create_buffer_init(&wgpu::util::BufferInitDescriptor {
            label: Some("workload"),
            contents: bytemuck::cast_slice(&[iterations, 0, 0, 0]),
            usage: wgpu::BufferUsages::UNIFORM,
        });
    let queries = OcclusionQueries::new(gpu, 1);
    let mut timer = GpuTimer::new(gpu, 2);
    let mut wall = Vec::new();
    for compare in [wgpu::CompareFunction::Equal, wgpu::CompareFunction::Always] {
        let pipeline = heavy_pipeline(gpu, compare);
        let bind_group = gpu.device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("workload"),
            layout: &pipeline.get_bind_group_layout(0),
            entries: &[wgpu::BindGroupEntry {
                binding: 0,
                resource: workload.as_entire_binding(),
            }],
        });
        // Marking runs in its own pass so the timed pass holds the heavy draw alone.
        let mut encoder = gpu.encoder("early rejection");
        {
            let mut pass = encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
                label: Some("mark"),
                depth_stencil_attachment: attachments::stencil(&stencil_view, Some(0)),
                ..Default::default()
            });
            pass.set_stencil_reference(1);
            pass.set_pipeline(&mark);
            square.draw(&mut pass, ..);
        }
        gpu.queue.submit([encoder.finish()]);
        gpu.wait()?;
        let mut encoder = gpu.encoder("heavy draw");
        {
            let equal = compare == wgpu::CompareFunction::Equal;
            let mut pass = encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
                label: Some("heavy draw"),
                color_attachments: &[attachments::colour(&colour_view, None, wgpu::Color::BLACK)],
                depth_stencil_attachment: attachments::stencil(&stencil_view, None),
                occlusion_query_set: equal.then_some(queries.set()),
                timestamp_writes: timer.pass(if equal {
                    "heavy, stencil Equal"
                } else {
                    "heavy, stencil Always"
                }),
                ..Default::default()
            });
            pass.set_stencil_reference(1);
            pass.set_pipeline(&pipeline);
            pass.set_bind_group(0, &bind_group, &[]);
            if equal {
                pass.begin_occlusion_query(0);
            }
            pass.draw(0..3, 0..1);
            if equal {
                pass.end_occlusion_query();
                drop(pass);
                queries.resolve(&mut encoder);
            }
        }
        let started = std::time::Instant::now();
        gpu.queue.submit([encoder.finish()]);
        gpu.wait()?;
        wall.push(started.elapsed().as_secs_f64() * 1e3);
    }
    let mut encoder = gpu.encoder("timestamps");
    timer.resolve(&mut encoder);
    gpu.queue.submit([encoder.finish()]);
    let times = timer.read(gpu)?;
    ctx.gpu_time(&times);
    // Without timestamps, wall time of a submit-and-wait per draw stands in (stated in metrics).
    let (equal_ms, always_ms) = match times.as_slice() {
        [equal, always] => (equal.ms, always.ms),
        _ => (wall[0], wall[1]),
    };
    let equal_samples = queries.read(gpu)?[0];
    let counted_fragments = if count_fragments {
        Some(count_with_atomic(gpu, &stencil_view)?)
    } else {
        None
    };
    Ok(Frame {
        equal_ms,
        always_ms,
        equal_samples,
        counted_fragments,
    })
}

/// Counts the fragments behind the stencil-Equal test with an atomic under forced early tests.
fn count_with_atomic(gpu: &Gpu, stencil_view: &wgpu::TextureView) -> Result<u32> {
    let pipeline = counter_pipeline(gpu);
    let counter = gpu
        .device
        .create_buffer_init(&wgpu::util::BufferInitDescriptor {
            label: Some("fragment counter"),
            contents: bytemuck::cast_slice(&[0u32]),
            usage: wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_SRC,
        });
    let readback = gpu.device.create_buffer(&wgpu::BufferDescriptor {
        label: Some("fragment counter read-back"),
        size: 4,
        usage: wgpu::BufferUsages::COPY_DST | wgpu::BufferUsages::MAP_READ,
        mapped_at_creation: false,
    });
    let bind_group = gpu.device.create_bind_group(&wgpu::BindGroupDescriptor {
        label: Some("fragment counter"),
        layout: &pipeline.get_bind_group_layout(0),
        entries: &[wgpu::BindGroupEntry {
            binding: 0,
            resource: counter.as_entire_binding(),
        }],
    });
    let mut encoder = gpu.encoder("fragment counter");
    {
        let mut pass = encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
            label: Some("fragment counter"),
            depth_stencil_attachment: attachments::stencil(stencil_view, None),
            ..Default::default()
        });
        pass.set_stencil_reference(1);
        pass.set_pipeline(&pipeline);
        pass.set_bind_group(0, &bind_group, &[]);
        pass.draw(0..3, 0..1);
    }
    encoder.copy_buffer_to_buffer(&counter, 0, &readback, 0, 4);
    gpu.queue.submit([encoder.finish()]);
    let bytes = map_buffer(gpu, &readback)?;
    Ok(u32::from_le_bytes([bytes[0], bytes[1], bytes[2], bytes[3]]))
}

fn median(mut values: Vec<f64>) -> f64 {
    values.sort_by(f64::total_cmp);
    values[values.len() / 2]
}

fn run(ctx: &mut Ctx) -> Result<Outcome> {
    let size = ctx.params.sizes("size")?[0];
    let passing = ctx.params.sizes("passing")?[0];
    let iterations = ctx.params.count("iterations")? as u32;
    let repeats = ctx.params.count("repeats")?.max(1);
    anyhow::ensure!(
        passing.0 <= size.0 && passing.1 <= size.1,
        "passing square {passing:?} exceeds the target {size:?}"
    );
    let precision = measure_occlusion_precision(ctx.gpu)?;
    let can_count = ctx.gpu.has(wgpu::Features::SHADER_EARLY_DEPTH_TEST)
        && ctx
            .gpu
            .adapter
            .get_downlevel_capabilities()
            .flags
            .contains(wgpu::DownlevelFlags::FRAGMENT_WRITABLE_STORAGE);
    ctx.metric(
        "timer",
        if ctx.gpu.has(wgpu::Features::TIMESTAMP_QUERY) {
            "gpu timestamps"
        } else {
            "wall clock"
        },
    );

    // Render: the first frame pays for shader compilation, so it is not timed.
    let warm_up = render_frame(ctx, size, passing, iterations, can_count)?;
    let frames: Vec<Frame> = (0..repeats)
        .map(|_| render_frame(ctx, size, passing, iterations, false))
        .collect::<Result<_>>()?;

    // Expected counts: the marked square, every pixel of it.
    let expected = u64::from(passing.0 * passing.1);
    let fraction = expected as f64 / f64::from(size.0 * size.1);
    let equal_ms = median(frames.iter().map(|f| f.equal_ms).collect());
    let always_ms = median(frames.iter().map(|f| f.always_ms).collect());
    let ratio = equal_ms / always_ms;
    ctx.metric("passing_fraction", fraction);
    ctx.metric("equal_ms", equal_ms);
    ctx.metric("always_ms", always_ms);
    ctx.metric("time_ratio", ratio);
    ctx.metric(
        "occlusion_count",
        serde_json::json!({"expected": expected, "measured": warm_up.equal_samples}),
    );
    ctx.metric(
        "atomic_count",
        serde_json::json!({"expected": expected, "measured": warm_up.counted_fragments}),
    );

    let mut problems = Vec::new();
    if precision == OcclusionPrecision::Exact && warm_up.equal_samples != expected {
        problems.push(format!(
            "occlusion query counted {} passing pixels, expected {expected}",
            warm_up.equal_samples
        ));
    }
    if let Some(counted) = warm_up.counted_fragments
        && u64::from(counted) != expected
    {
        problems.push(format!("atomic counter under early_depth_test(force) saw {counted} fragments, expected {expected}"));
    }
    Ok(if !problems.is_empty() {
        Outcome::Fail(problems.join("; "))
    } else if ratio > REJECTION_RATIO_LIMIT {
        Outcome::NotSupported(format!(
            "early stencil rejection: the Equal draw ({:.2} % passing) cost {ratio:.2}x the Always draw",
            fraction * 100.0
        ))
    } else {
        Outcome::Pass
    })
}
