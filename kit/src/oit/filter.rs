//! The post-filter of stochastic transparency: temporal accumulation (`shaders/oit/temporal.wgsl`)
//! then a bilateral filter weighted by colour difference (`shaders/oit/bilateral.wgsl`).

use anyhow::Result;

use super::stochastic::COLOUR;
use crate::attachments;
use crate::fullscreen::{FullscreenPipeline, bind_group, uniform_buffer};
use crate::gpu::Gpu;
use crate::query::GpuTimer;
use crate::readback::read_texture;
use crate::shaders;

/// Running accumulation of frames (ping-pong history) and the bilateral pass over it.
pub struct PostFilter {
    size: (u32, u32),
    history: [wgpu::Texture; 2],
    filtered: wgpu::Texture,
    temporal: wgpu::RenderPipeline,
    bilateral: wgpu::RenderPipeline,
    frames: u32,
    /// Colour difference beyond which the history restarts.
    pub tolerance: f32,
    pub range_sigma: f32,
}

impl PostFilter {
    pub fn new(gpu: &Gpu, size: (u32, u32)) -> Self {
        let usage = wgpu::TextureUsages::RENDER_ATTACHMENT
            | wgpu::TextureUsages::TEXTURE_BINDING
            | wgpu::TextureUsages::COPY_SRC;
        let pipeline = |label, fragment, entry_point| {
            FullscreenPipeline {
                label,
                fragment,
                entry_point,
                targets: &[Some(COLOUR.into())],
                depth_stencil: None,
                samples: 1,
            }
            .create(gpu)
        };
        Self {
            size,
            history: [0, 1].map(|_| gpu.texture("temporal history", size, COLOUR, 1, usage)),
            filtered: gpu.texture("bilateral", size, COLOUR, 1, usage),
            temporal: pipeline("temporal", shaders::OIT_TEMPORAL, "fs_temporal"),
            bilateral: pipeline("bilateral", shaders::OIT_BILATERAL, "fs_bilateral"),
            frames: 0,
            tolerance: 1.0,
            range_sigma: 0.1,
        }
    }

    fn pass(
        &self,
        gpu: &Gpu,
        label: &str,
        pipeline: &wgpu::RenderPipeline,
        group: &wgpu::BindGroup,
        target: &wgpu::Texture,
        timer: &mut GpuTimer,
    ) {
        let view = target.create_view(&Default::default());
        let mut encoder = gpu.encoder(label);
        {
            let mut pass = encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
                label: Some(label),
                color_attachments: &[attachments::colour(&view, None, wgpu::Color::TRANSPARENT)],
                timestamp_writes: timer.pass(label),
                ..Default::default()
            });
            pass.set_pipeline(pipeline);
            pass.set_bind_group(0, group, &[]);
            pass.draw(0..3, 0..1);
        }
        timer.resolve(&mut encoder);
        gpu.submit(encoder);
    }

    /// Folds a new frame into the history.
    pub fn accumulate(&mut self, gpu: &Gpu, frame: &wgpu::Texture, timer: &mut GpuTimer) {
        let (read, write) = ((self.frames % 2) as usize, ((self.frames + 1) % 2) as usize);
        let words = [self.frames, self.tolerance.to_bits(), 0, 0];
        let uniform = uniform_buffer(gpu, "temporal", bytemuck::cast_slice(&words));
        let (current, history) =
            (frame.create_view(&Default::default()), self.history[read].create_view(&Default::default()));
        let group = bind_group(
            gpu,
            "temporal",
            &self.temporal,
            0,
            &[
                uniform.as_entire_binding(),
                wgpu::BindingResource::TextureView(&current),
                wgpu::BindingResource::TextureView(&history),
            ],
        );
        self.pass(gpu, "temporal", &self.temporal, &group, &self.history[write], timer);
        self.frames += 1;
    }

    /// The accumulation so far.
    pub fn accumulated(&self) -> &wgpu::Texture {
        &self.history[(self.frames % 2) as usize]
    }

    /// The bilateral-filtered accumulation.
    pub fn filter(&self, gpu: &Gpu, timer: &mut GpuTimer) -> &wgpu::Texture {
        let uniform = uniform_buffer(gpu, "bilateral", bytemuck::cast_slice(&[self.range_sigma, 0.0, 0.0, 0.0]));
        let source = self.accumulated().create_view(&Default::default());
        let group = bind_group(
            gpu,
            "bilateral",
            &self.bilateral,
            0,
            &[uniform.as_entire_binding(), wgpu::BindingResource::TextureView(&source)],
        );
        self.pass(gpu, "bilateral", &self.bilateral, &group, &self.filtered, timer);
        &self.filtered
    }

    pub fn size(&self) -> (u32, u32) {
        self.size
    }
}

/// RGB per pixel of an `Rgba16Float` texture.
pub fn read_rgb(gpu: &Gpu, texture: &wgpu::Texture) -> Result<Vec<[f32; 3]>> {
    Ok(read_texture(gpu, texture, wgpu::TextureAspect::All, 0)?
        .as_f16()
        .chunks_exact(4)
        .map(|t| [t[0], t[1], t[2]])
        .collect())
}
