//! `kit.determinism`: the same seeded scene rendered twice, each time with fresh resources,
//! reads back bit-identical; and the render is checked against the CPU's coverage of the scene
//! so that two identical blank images cannot pass.

use anyhow::Result;
use fragkit::attachments;
use fragkit::fullscreen::{bind_group, uniform_buffer};
use fragkit::gpu::Gpu;
use fragkit::harness::{Case, Ctx, Outcome, ParamKind, ParamSpec, Sweep, SweepRange};
use fragkit::image_compare::{compare, side_by_side};
use fragkit::probe::subpixel_precision::COARSEST_SNAP;
use fragkit::readback::read_rgba8;
use fragkit::scene::hash::SeededRng;
use fragkit::shaders;
use fragkit::shaders::NOISE_TRIANGLES;
use wgpu::util::DeviceExt;

pub const CASE: Case = Case {
    name: "kit.determinism",
    summary: "a seeded scene rendered twice from scratch reads back bit-identical",
    requires: wgpu::Features::empty(),
    params: &[
        ParamSpec { name: "size", kind: ParamKind::Size, default: "96x64", help: "target size" },
        ParamSpec {
            name: "triangles",
            kind: ParamKind::CountIn(1, 1000000),
            default: "48",
            help: "triangles in the scene",
        },
        ParamSpec { name: "seed", kind: ParamKind::CountIn(0, u32::MAX as u64), default: "7", help: "scene and noise seed" },
    ],
    sweep: &[
        Sweep { param: "size", range: SweepRange::Size { min: (1, 1), max: (256, 256) } },
        Sweep { param: "triangles", range: SweepRange::Count(1, 2000) },
        Sweep { param: "seed", range: SweepRange::Count(0, 1 << 20) },
    ],
    budget_s: 1,
    timed_verdict: false,
    shaders: &[NOISE_TRIANGLES],
    run,
};

/// Background colour; no triangle shade reaches it (shades are at least 0.25 in green).
const BACKGROUND: [u8; 4] = [0, 0, 0, 255];

#[repr(C)]
#[derive(Clone, Copy, bytemuck::Pod, bytemuck::Zeroable)]
struct Vertex {
    position: [f32; 3],
    shade: [f32; 3],
}

/// Seeded triangles in clip space, some reaching past the edges, at random depths.
fn scene(triangles: u64, seed: u32) -> Vec<Vertex> {
    let mut rng = SeededRng::new(seed);
    (0..triangles)
        .flat_map(|_| {
            let depth = rng.unit();
            let shade = [rng.unit(), 0.25 + 0.75 * rng.unit(), rng.unit()];
            let centre = [rng.unit() * 2.4 - 1.2, rng.unit() * 2.4 - 1.2];
            let corner = move |rng: &mut SeededRng| Vertex {
                position: [centre[0] + rng.unit() * 0.8 - 0.4, centre[1] + rng.unit() * 0.8 - 0.4, depth],
                shade,
            };
            [corner(&mut rng), corner(&mut rng), corner(&mut rng)]
        })
        .collect()
}

/// Renders the scene with resources created from nothing.
fn render(ctx: &mut Ctx, size: (u32, u32), vertices: &[Vertex], seed: u32) -> Result<image::RgbaImage> {
    let gpu: &Gpu = ctx.gpu;
    let format = wgpu::TextureFormat::Rgba8Unorm;
    let colour = gpu.texture(
        "determinism colour",
        size,
        format,
        1,
        wgpu::TextureUsages::RENDER_ATTACHMENT | wgpu::TextureUsages::COPY_SRC,
    );
    let depth = gpu.texture(
        "determinism depth",
        size,
        wgpu::TextureFormat::Depth24PlusStencil8,
        1,
        wgpu::TextureUsages::RENDER_ATTACHMENT,
    );
    let (colour_view, depth_view) = (colour.create_view(&Default::default()), depth.create_view(&Default::default()));
    let module = shaders::NOISE_TRIANGLES.module(gpu);
    let pipeline = gpu.device.create_render_pipeline(&wgpu::RenderPipelineDescriptor {
        label: Some("noise triangles"),
        layout: None,
        vertex: wgpu::VertexState {
            module: &module,
            entry_point: Some("vs_triangle"),
            compilation_options: Default::default(),
            buffers: &[Some(wgpu::VertexBufferLayout {
                array_stride: std::mem::size_of::<Vertex>() as u64,
                step_mode: wgpu::VertexStepMode::Vertex,
                attributes: &wgpu::vertex_attr_array![0 => Float32x3, 1 => Float32x3],
            })],
        },
        primitive: Default::default(),
        depth_stencil: Some(wgpu::DepthStencilState {
            format: wgpu::TextureFormat::Depth24PlusStencil8,
            depth_write_enabled: Some(true),
            depth_compare: Some(wgpu::CompareFunction::LessEqual),
            stencil: Default::default(),
            bias: Default::default(),
        }),
        multisample: Default::default(),
        fragment: Some(wgpu::FragmentState {
            module: &module,
            entry_point: Some("fs_noise"),
            compilation_options: Default::default(),
            targets: &[Some(format.into())],
        }),
        multiview_mask: None,
        cache: None,
    });
    let vertex_buffer = gpu.device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
        label: Some("scene vertices"),
        contents: bytemuck::cast_slice(vertices),
        usage: wgpu::BufferUsages::VERTEX,
    });
    let seed_buffer = uniform_buffer(gpu, "noise seed", bytemuck::cast_slice(&[seed, 0, 0, 0]));
    let bind_group = bind_group(gpu, "noise seed", &pipeline, 0, &[seed_buffer.as_entire_binding()]);
    let mut encoder = gpu.encoder("determinism");
    {
        let mut pass = encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
            label: Some("noise triangles"),
            color_attachments: &[attachments::colour(&colour_view, None, wgpu::Color::BLACK)],
            depth_stencil_attachment: attachments::stencil(&depth_view, Some(0)),
            ..Default::default()
        });
        pass.set_pipeline(&pipeline);
        pass.set_bind_group(0, &bind_group, &[]);
        pass.set_vertex_buffer(0, vertex_buffer.slice(..));
        pass.draw(0..vertices.len() as u32, 0..1);
    }
    gpu.submit(encoder);
    read_rgba8(gpu, &colour)
}

/// CPU coverage of pixel centres: Some(covered), or None where the rasteriser's snapping of the
/// vertices may decide either way. At the coarsest sub-pixel precision Vulkan and GL permit
/// (4 bits) a vertex moves by less than δ = 1/16 px per axis, which changes the edge function
/// E(p) = (b − a) × (p − a) by at most δ (2 |p − a|₁ + |b − a|₁) + 4δ² (the cross products of
/// the moves, |u|∞, |v|∞ ≤ δ): a centre whose |E| exceeds that for every edge is decided.
fn cpu_coverage(size: (u32, u32), vertices: &[Vertex], x: u32, y: u32) -> Option<bool> {
    let delta = f64::from(COARSEST_SNAP);
    let p = [f64::from(x) + 0.5, f64::from(y) + 0.5];
    let to_pixels = |v: &Vertex| {
        [
            (f64::from(v.position[0]) + 1.0) * 0.5 * f64::from(size.0),
            (1.0 - f64::from(v.position[1])) * 0.5 * f64::from(size.1),
        ]
    };
    let mut undecidable = false;
    for triangle in vertices.chunks_exact(3) {
        let [a, b, c] = [to_pixels(&triangle[0]), to_pixels(&triangle[1]), to_pixels(&triangle[2])];
        // (edge function, the most snapping can change it)
        let edge = |u: [f64; 2], v: [f64; 2]| {
            let value = (v[0] - u[0]) * (p[1] - u[1]) - (v[1] - u[1]) * (p[0] - u[0]);
            let reach = delta
                * (2.0 * ((p[0] - u[0]).abs() + (p[1] - u[1]).abs()) + (v[0] - u[0]).abs() + (v[1] - u[1]).abs())
                + 4.0 * delta * delta;
            (value, reach)
        };
        let edges = [edge(a, b), edge(b, c), edge(c, a)];
        // Either winding: within reach of this triangle's boundary counts as undecidable.
        let inside_with_margin = |sign: f64| edges.iter().all(|&(e, reach)| e * sign > -reach);
        let surely_inside = |sign: f64| edges.iter().all(|&(e, reach)| e * sign > reach);
        if surely_inside(1.0) || surely_inside(-1.0) {
            return Some(true);
        }
        undecidable |= inside_with_margin(1.0) || inside_with_margin(-1.0);
    }
    if undecidable { None } else { Some(false) }
}

fn run(ctx: &mut Ctx) -> Result<Outcome> {
    let size = ctx.params.size("size")?;
    let seed = ctx.params.count_u32("seed")?;
    let vertices = scene(ctx.params.count("triangles")?, seed);

    let first = render(ctx, size, &vertices, seed)?;
    let second = render(ctx, size, &vertices, seed)?;

    let (difference, mask) = compare(&second, &first, 0)?;
    ctx.metric("differing_pixels", difference.differing_pixels);
    if difference.differing_pixels > 0 {
        ctx.evidence_image("repeat", &side_by_side(&second, &first, &mask))?;
        return Ok(Outcome::Fail(format!(
            "{} pixels differ between two renders of the same seed",
            difference.differing_pixels
        )));
    }
    // The render must show the scene: covered pixel centres shaded, uncovered ones background
    // (a blank render fails wherever the CPU finds a centre surely covered).
    let mut wrong = 0u64;
    let mut covered = 0u64;
    let coverage_mask = image::RgbaImage::from_fn(size.0, size.1, |x, y| {
        let shaded = first.get_pixel(x, y).0 != BACKGROUND;
        match cpu_coverage(size, &vertices, x, y) {
            Some(expected) if expected != shaded => {
                wrong += 1;
                image::Rgba([255, 0, 0, 255])
            }
            Some(expected) => {
                covered += u64::from(expected);
                image::Rgba([0, 0, 0, 255])
            }
            None => image::Rgba([64, 64, 64, 255]),
        }
    });
    ctx.metric("covered_pixels", covered);
    ctx.metric("coverage_mismatches", wrong);
    if wrong > 0 {
        ctx.evidence_image("coverage", &side_by_side(&first, &first, &coverage_mask))?;
        return Ok(Outcome::Fail(format!(
            "{wrong} pixels disagree with the CPU's coverage of the scene ({covered} covered)"
        )));
    }
    Ok(Outcome::Pass)
}
