//! The shared machinery of the quad passes (instance buffer, pipelines, MSAA targets, the
//! ping-pong noise) and stochastic transparency itself.

use anyhow::{Context, Result, ensure};
use wgpu::util::DeviceExt;

use super::scene::QuadScene;
use crate::fullscreen::{FullscreenPipeline, bind_group, uniform_buffer};
use crate::gpu::Gpu;
use crate::query::GpuTimer;
use crate::readback::read_texture;
use crate::scene::hash::pcg_hash;
use crate::shaders::{self, ShaderFile};

/// Accumulations and the single-sampled methods' images.
pub const COLOUR: wgpu::TextureFormat = wgpu::TextureFormat::Rgba16Float;
/// The coverage methods' multisampled colour: 8 bits a channel, as MSAA colour buffers usually
/// are (on lavapipe a third faster than f16 at 4x); accumulation happens in f16 afterwards.
pub const COVERAGE_COLOUR: wgpu::TextureFormat = wgpu::TextureFormat::Rgba8Unorm;
pub const DEPTH: wgpu::TextureFormat = wgpu::TextureFormat::Depth32Float;

#[repr(C)]
#[derive(Clone, Copy, bytemuck::Pod, bytemuck::Zeroable)]
struct QuadInstance {
    rect: [f32; 4],
    depth_alpha: [f32; 3],
    colour: [f32; 3],
    key: u32,
}

/// A scene's quads, ready to draw in scene order.
pub struct QuadBatch {
    buffer: wgpu::Buffer,
    pub count: u32,
}

impl QuadBatch {
    pub fn new(gpu: &Gpu, scene: &QuadScene) -> Result<Self> {
        scene.validate()?;
        let instances: Vec<QuadInstance> = scene
            .quads
            .iter()
            .map(|q| QuadInstance {
                rect: q.rect,
                depth_alpha: [q.depth.0, q.depth.1, q.alpha],
                colour: q.colour,
                key: q.key,
            })
            .collect();
        let buffer = gpu.device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
            label: Some("quads"),
            contents: bytemuck::cast_slice(&instances),
            usage: wgpu::BufferUsages::VERTEX,
        });
        Ok(Self { buffer, count: scene.quads.len() as u32 })
    }

    /// Draws quads `range` in scene order (instance i = quad i).
    pub fn draw(&self, pass: &mut wgpu::RenderPass<'_>, range: std::ops::Range<u32>) {
        pass.set_vertex_buffer(0, self.buffer.slice(..));
        pass.draw(0..6, range);
    }
}

/// A quad pass's pipeline state.
pub struct QuadPipeline<'a> {
    pub label: &'a str,
    pub fragment: ShaderFile,
    pub entry_point: &'a str,
    pub targets: &'a [Option<wgpu::ColorTargetState>],
    pub depth_write: bool,
    pub depth_compare: wgpu::CompareFunction,
    pub samples: u32,
    pub alpha_to_coverage: bool,
}

impl QuadPipeline<'_> {
    pub fn create(&self, gpu: &Gpu) -> wgpu::RenderPipeline {
        let vertex = shaders::OIT_QUAD.module(gpu);
        let fragment = self.fragment.module(gpu);
        gpu.device.create_render_pipeline(&wgpu::RenderPipelineDescriptor {
            label: Some(self.label),
            layout: None,
            vertex: wgpu::VertexState {
                module: &vertex,
                entry_point: Some("vs_quad"),
                compilation_options: Default::default(),
                buffers: &[Some(wgpu::VertexBufferLayout {
                    array_stride: std::mem::size_of::<QuadInstance>() as u64,
                    step_mode: wgpu::VertexStepMode::Instance,
                    attributes: &wgpu::vertex_attr_array![0 => Float32x4, 1 => Float32x3, 2 => Float32x3, 3 => Uint32],
                })],
            },
            primitive: Default::default(),
            depth_stencil: Some(wgpu::DepthStencilState {
                format: DEPTH,
                depth_write_enabled: Some(self.depth_write),
                depth_compare: Some(self.depth_compare),
                stencil: Default::default(),
                bias: Default::default(),
            }),
            multisample: wgpu::MultisampleState {
                count: self.samples,
                mask: !0,
                alpha_to_coverage_enabled: self.alpha_to_coverage,
            },
            fragment: Some(wgpu::FragmentState {
                module: &fragment,
                entry_point: Some(self.entry_point),
                compilation_options: Default::default(),
                targets: self.targets,
            }),
            multiview_mask: None,
            cache: None,
        })
    }
}

/// A multisampled colour + depth target resolved into a single-sampled image.
pub struct ResolvedTarget {
    pub size: (u32, u32),
    pub samples: u32,
    pub format: wgpu::TextureFormat,
    pub msaa: Option<(wgpu::TextureView, wgpu::TextureView)>,
    pub depth: wgpu::TextureView,
    pub resolved: wgpu::Texture,
    pub resolved_view: wgpu::TextureView,
}

impl ResolvedTarget {
    pub fn new(gpu: &Gpu, size: (u32, u32), samples: u32, format: wgpu::TextureFormat) -> Self {
        let resolved = gpu.texture(
            "oit image",
            size,
            format,
            1,
            wgpu::TextureUsages::RENDER_ATTACHMENT
                | wgpu::TextureUsages::TEXTURE_BINDING
                | wgpu::TextureUsages::COPY_SRC,
        );
        let msaa = (samples > 1).then(|| {
            let colour = gpu.texture("oit msaa", size, format, samples, wgpu::TextureUsages::RENDER_ATTACHMENT);
            colour.create_view(&Default::default())
        });
        let depth = gpu
            .texture("oit depth", size, DEPTH, samples, wgpu::TextureUsages::RENDER_ATTACHMENT)
            .create_view(&Default::default());
        Self {
            size,
            samples,
            format,
            msaa: msaa.map(|view| (view, resolved.create_view(&Default::default()))),
            depth,
            resolved_view: resolved.create_view(&Default::default()),
            resolved,
        }
    }

    /// Colour attachment cleared to transparent black (resolving where multisampled).
    pub fn colour_attachment(&self) -> Option<wgpu::RenderPassColorAttachment<'_>> {
        match &self.msaa {
            Some((msaa, resolve)) => crate::attachments::colour(msaa, Some(resolve), wgpu::Color::TRANSPARENT),
            None => crate::attachments::colour(&self.resolved_view, None, wgpu::Color::TRANSPARENT),
        }
    }

    pub fn depth_attachment(&self) -> Option<wgpu::RenderPassDepthStencilAttachment<'_>> {
        Some(wgpu::RenderPassDepthStencilAttachment {
            view: &self.depth,
            depth_ops: Some(wgpu::Operations { load: wgpu::LoadOp::Clear(1.0), store: wgpu::StoreOp::Discard }),
            stencil_ops: None,
        })
    }

    /// The resolved image, RGB per pixel.
    pub fn read_rgb(&self, gpu: &Gpu) -> Result<Vec<[f32; 3]>> {
        let texels = read_texture(gpu, &self.resolved, wgpu::TextureAspect::All, 0)?;
        let values: Vec<f32> = match self.format {
            wgpu::TextureFormat::Rgba8Unorm => texels.bytes.iter().map(|&b| f32::from(b) / 255.0).collect(),
            _ => texels.as_f16(),
        };
        Ok(values.chunks_exact(4).map(|t| [t[0], t[1], t[2]]).collect())
    }
}

/// Two screen-size noise textures: frame 0 uses the seeded one, each later frame hashes the
/// previous into the other (`shaders/oit/noise_step.wgsl`).
pub struct PingPongNoise {
    views: [wgpu::TextureView; 2],
    pipeline: wgpu::RenderPipeline,
    frame: u32,
}

impl PingPongNoise {
    pub fn new(gpu: &Gpu, size: (u32, u32), seed: u32) -> Self {
        let usage = wgpu::TextureUsages::RENDER_ATTACHMENT
            | wgpu::TextureUsages::TEXTURE_BINDING
            | wgpu::TextureUsages::COPY_DST;
        let textures = [0, 1].map(|_| gpu.texture("noise", size, wgpu::TextureFormat::R32Uint, 1, usage));
        let seeded: Vec<u32> = (0..size.0 * size.1).map(|i| pcg_hash(i ^ pcg_hash(seed))).collect();
        gpu.queue.write_texture(
            textures[0].as_image_copy(),
            bytemuck::cast_slice(&seeded),
            wgpu::TexelCopyBufferLayout { offset: 0, bytes_per_row: Some(size.0 * 4), rows_per_image: None },
            textures[0].size(),
        );
        let views = [&textures[0], &textures[1]].map(|t| t.create_view(&Default::default()));
        let pipeline = FullscreenPipeline {
            label: "noise step",
            fragment: shaders::OIT_NOISE_STEP,
            entry_point: "fs_noise_step",
            targets: &[Some(wgpu::TextureFormat::R32Uint.into())],
            depth_stencil: None,
            samples: 1,
        }
        .create(gpu);
        Self { views, pipeline, frame: 0 }
    }

    /// This frame's noise.
    pub fn current(&self) -> &wgpu::TextureView {
        &self.views[(self.frame % 2) as usize]
    }

    /// Advances to the next frame's noise (one render pass, no upload).
    pub fn advance(&mut self, gpu: &Gpu) {
        let (from, to) = ((self.frame % 2) as usize, ((self.frame + 1) % 2) as usize);
        self.frame += 1;
        let step = uniform_buffer(gpu, "noise frame", bytemuck::cast_slice(&[self.frame, 0, 0, 0]));
        let group = bind_group(
            gpu,
            "noise step",
            &self.pipeline,
            0,
            &[step.as_entire_binding(), wgpu::BindingResource::TextureView(&self.views[from])],
        );
        let mut encoder = gpu.encoder("noise step");
        {
            let mut pass = encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
                label: Some("noise step"),
                color_attachments: &[crate::attachments::colour(&self.views[to], None, wgpu::Color::TRANSPARENT)],
                ..Default::default()
            });
            pass.set_pipeline(&self.pipeline);
            pass.set_bind_group(0, &group, &[]);
            pass.draw(0..3, 0..1);
        }
        gpu.submit(encoder);
    }
}

/// Which stochastic variant a frame uses.
#[derive(Clone, Debug, PartialEq)]
pub enum Stochastic {
    /// The paper: alpha f^γ straight into alpha-to-coverage.
    Paper,
    /// f^γ, then k = floor(N f^γ + u) samples through the alpha this adapter maps to exactly k
    /// (`exact_alpha[k]`, from the measured transfer function).
    Corrected { exact_alpha: Vec<f32> },
    /// A run of floor(N α + u) samples written through `@builtin(sample_mask)`.
    SampleMask,
}

/// Renders one stochastic frame of `scene` with this frame's noise; returns the resolved image.
pub fn render_stochastic(
    gpu: &Gpu,
    scene: &QuadScene,
    target: &ResolvedTarget,
    noise: &PingPongNoise,
    variant: &Stochastic,
    timer: &mut GpuTimer,
) -> Result<()> {
    let quads = QuadBatch::new(gpu, scene)?;
    let (fragment, entry, a2c) = match variant {
        Stochastic::SampleMask => (shaders::OIT_SAMPLE_MASK, "fs_sample_mask", false),
        _ => (shaders::OIT_STOCHASTIC, "fs_stochastic", true),
    };
    let pipeline = QuadPipeline {
        label: "stochastic transparency",
        fragment,
        entry_point: entry,
        targets: &[Some(target.format.into())],
        depth_write: true,
        depth_compare: wgpu::CompareFunction::LessEqual,
        samples: target.samples,
        alpha_to_coverage: a2c,
    }
    .create(gpu);
    let mut words: Vec<u32> = match variant {
        Stochastic::Corrected { exact_alpha } => {
            let mut words = vec![1, target.samples, 0, 0];
            let mut table = exact_alpha.iter().map(|a| a.to_bits()).collect::<Vec<_>>();
            table.resize(12, 1.0f32.to_bits());
            words.extend(table);
            words
        }
        Stochastic::Paper => vec![0, target.samples, 0, 0],
        // `MaskParams` holds only the sample count.
        Stochastic::SampleMask => vec![target.samples, 0, 0, 0],
    };
    words.resize(16, 0);
    let params = uniform_buffer(gpu, "stochastic", bytemuck::cast_slice(&words));
    let group = bind_group(
        gpu,
        "stochastic",
        &pipeline,
        0,
        &[params.as_entire_binding(), wgpu::BindingResource::TextureView(noise.current())],
    );
    let mut encoder = gpu.encoder("stochastic transparency");
    {
        let mut pass = encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
            label: Some("stochastic transparency"),
            color_attachments: &[target.colour_attachment()],
            depth_stencil_attachment: target.depth_attachment(),
            timestamp_writes: timer.pass("stochastic transparency"),
            ..Default::default()
        });
        pass.set_pipeline(&pipeline);
        pass.set_bind_group(0, &group, &[]);
        quads.draw(&mut pass, 0..quads.count);
    }
    timer.resolve(&mut encoder);
    gpu.submit(encoder);
    Ok(())
}

/// For k = 0..=N, an alpha this adapter maps to exactly k covered samples: the middle of the
/// measured alpha step for k. Errors when some count never occurs or coverage is not monotonic
/// (then no alpha gives a chosen count everywhere).
pub fn exact_alpha_table(transfer: &crate::probe::alpha_to_coverage::AlphaToCoverage) -> Result<Vec<f32>> {
    use crate::probe::alpha_to_coverage::ALPHA_STEPS;
    ensure!(
        transfer.monotonic && !transfer.dithered,
        "the alpha-to-coverage transfer is not a plain staircase here (monotonic {}, dithered {})",
        transfer.monotonic,
        transfer.dithered
    );
    let first_step = |k: u32| transfer.thresholds.iter().find(|&&(count, _)| count == k).map(|&(_, step)| step);
    (0..=transfer.samples)
        .map(|k| {
            let start = first_step(k)
                .with_context(|| format!("no alpha covers exactly {k} of {} samples", transfer.samples))?;
            let end = (k + 1..=transfer.samples).find_map(first_step).unwrap_or(ALPHA_STEPS + 1);
            Ok((start + end - 1) as f32 * 0.5 / ALPHA_STEPS as f32)
        })
        .collect()
}

/// Builds the `@builtin(sample_mask)` output pipeline: Ok where this adapter builds it, else the
/// error it gave (wgpu's GL backend mistranslates the builtin: naga writes a `uint` into GLSL's
/// `int gl_SampleMask[]`, wgpu#6085, #4335). A capability shown by creating the pipeline, not
/// read from a flag.
pub fn sample_mask_output(gpu: &Gpu, samples: u32) -> Result<(), String> {
    gpu.scoped("sample_mask output pipeline", || {
        QuadPipeline {
            label: "sample mask probe",
            fragment: shaders::OIT_SAMPLE_MASK,
            entry_point: "fs_sample_mask",
            targets: &[Some(COLOUR.into())],
            depth_write: true,
            depth_compare: wgpu::CompareFunction::LessEqual,
            samples,
            alpha_to_coverage: false,
        }
        .create(gpu);
        Ok(())
    })
    // wgpu's error spans lines (scope, call, cause); the cause is the last.
    .map_err(|e| {
        let text = format!("{e:#}");
        text.lines().map(str::trim).rfind(|l| !l.is_empty()).unwrap_or_default().to_owned()
    })
}

/// The stochastic variants this adapter can run at `samples` per pixel: always the paper's; the
/// corrected one where the measured transfer is a plain staircase; the sample-mask one where the
/// `sample_mask` output pipeline builds.
pub fn available_variants(gpu: &Gpu, samples: u32) -> Result<Vec<Stochastic>> {
    let mut variants = vec![Stochastic::Paper];
    if let Ok(exact_alpha) =
        exact_alpha_table(&crate::probe::alpha_to_coverage::measure_alpha_to_coverage(gpu, samples, false)?)
    {
        variants.push(Stochastic::Corrected { exact_alpha });
    }
    if sample_mask_output(gpu, samples).is_ok() {
        variants.push(Stochastic::SampleMask);
    }
    Ok(variants)
}
