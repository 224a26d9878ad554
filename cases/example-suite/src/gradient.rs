//! `example.gradient`: the suite's own render pass (`shaders/gradient.wgsl`: each pixel's colour
//! its centre's place on the target) against a CPU model of what the pass defines. The pixel
//! centre is exact in f32 and the division is within 2.5 ulps, so the only rounding that can
//! reach the 8-bit target is the float-to-unorm conversion: one step either way.

use anyhow::Result;
use fragkit::attachments;
use fragkit::fullscreen::uniform_buffer;
use fragkit::harness::{Case, Ctx, Outcome, ParamKind, ParamSpec, Verdict};
use fragkit::readback::read_rgba8;

pub const CASE: Case = Case {
    name: "example.gradient",
    summary: "a full-screen gradient pass equals its CPU definition within one 8-bit step",
    requires: wgpu::Features::empty(),
    params: &[ParamSpec {
        name: "size",
        kind: ParamKind::Size,
        default: "64x48",
        help: "target size",
    }],
    sweep: &[],
    budget_s: 1,
    timed_verdict: false,
    shaders: &[],
    run,
};

const SHADER: &str = include_str!("../shaders/gradient.wgsl");

/// The one 8-bit step the float-to-unorm conversion may round either way.
const TOLERANCE: u8 = 1;

fn run(ctx: &mut Ctx) -> Result<Outcome> {
    // Setup: an 8-bit target and the pass's pipeline.
    let (width, height) = ctx.params.size("size")?;
    let gpu = ctx.gpu;
    let target = gpu.texture(
        "gradient target",
        (width, height),
        wgpu::TextureFormat::Rgba8Unorm,
        1,
        wgpu::TextureUsages::RENDER_ATTACHMENT | wgpu::TextureUsages::COPY_SRC,
    );
    let module = gpu.device.create_shader_module(wgpu::ShaderModuleDescriptor {
        label: Some("gradient.wgsl"),
        source: wgpu::ShaderSource::Wgsl(SHADER.into()),
    });
    let pipeline = gpu.device.create_render_pipeline(&wgpu::RenderPipelineDescriptor {
        label: Some("gradient"),
        layout: None,
        vertex: wgpu::VertexState {
            module: &module,
            entry_point: Some("vs"),
            compilation_options: Default::default(),
            buffers: &[],
        },
        fragment: Some(wgpu::FragmentState {
            module: &module,
            entry_point: Some("fs"),
            compilation_options: Default::default(),
            targets: &[Some(wgpu::TextureFormat::Rgba8Unorm.into())],
        }),
        primitive: Default::default(),
        depth_stencil: None,
        multisample: Default::default(),
        multiview_mask: None,
        cache: None,
    });
    let size: Vec<u8> = [width as f32, height as f32, 0.0, 0.0].iter().flat_map(|v| v.to_le_bytes()).collect();
    let size = uniform_buffer(gpu, "gradient target size", &size);
    let bindings = gpu.device.create_bind_group(&wgpu::BindGroupDescriptor {
        label: Some("gradient"),
        layout: &pipeline.get_bind_group_layout(0),
        entries: &[wgpu::BindGroupEntry { binding: 0, resource: size.as_entire_binding() }],
    });

    // Render.
    let view = target.create_view(&Default::default());
    let mut encoder = gpu.encoder("gradient");
    {
        let mut pass = encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
            label: Some("gradient"),
            color_attachments: &[attachments::colour(&view, None, wgpu::Color::BLACK)],
            ..Default::default()
        });
        pass.set_pipeline(&pipeline);
        pass.set_bind_group(0, &bindings, &[]);
        pass.draw(0..3, 0..1);
    }
    gpu.submit(encoder);

    // Measure.
    let image = read_rgba8(gpu, &target)?;

    // Expectation: the pass's definition at each pixel centre, rounded to 8 bits.
    let unorm8 = |value: f64| (value.clamp(0.0, 1.0) * 255.0).round() as u8;
    let mut worst = 0u8;
    let mut wrong = 0usize;
    let mut first = None;
    for (x, y, pixel) in image.enumerate_pixels() {
        let expected = [
            unorm8((f64::from(x) + 0.5) / f64::from(width)),
            unorm8((f64::from(y) + 0.5) / f64::from(height)),
            unorm8(0.25),
            255,
        ];
        let off = pixel.0.iter().zip(expected).map(|(&got, want)| got.abs_diff(want)).max().unwrap_or(0);
        worst = worst.max(off);
        if off > TOLERANCE {
            wrong += 1;
            first.get_or_insert(format!("({x}, {y}) is {:?}, defined {expected:?}", pixel.0));
        }
    }

    // Compare.
    ctx.metric("worst_step", worst);
    ctx.metric("pixels_off", wrong);
    let mut verdict = Verdict::new();
    if let Some(first) = first {
        ctx.evidence_image("result", &image)?;
        verdict.fail(format!(
            "{wrong} of {} pixels more than {TOLERANCE} step from the definition; first: {first}",
            width * height
        ));
    }
    Ok(verdict.outcome())
}
