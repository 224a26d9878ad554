//! Full-resolution deferred lighting (`shaders/deferred/lighting.wgsl`): every pixel shaded from
//! its own G-buffer sample into an `Rgba16Float` target.

use anyhow::{Result, ensure};
use glam::Vec3;

use super::DeferredInputs;
use crate::attachments;
use crate::fullscreen::{FullscreenPipeline, bind_group, uniform_buffer};
use crate::gpu::Gpu;
use crate::query::GpuTimer;
use crate::shaders;

pub const HDR: wgpu::TextureFormat = wgpu::TextureFormat::Rgba16Float;

/// `Shading` in the lighting shaders: eye position and light count.
pub fn shading_uniform(gpu: &Gpu, eye: Vec3, light_count: u32) -> wgpu::Buffer {
    let words: [u32; 4] = [eye.x.to_bits(), eye.y.to_bits(), eye.z.to_bits(), light_count];
    uniform_buffer(gpu, "shading", bytemuck::cast_slice(&words))
}

/// Full-resolution deferred lighting at one size: its pipeline and target, made once.
pub struct FullResolution {
    pub target: wgpu::Texture,
    view: wgpu::TextureView,
    pipeline: wgpu::RenderPipeline,
}

impl FullResolution {
    pub fn new(gpu: &Gpu, size: (u32, u32)) -> Self {
        let target = gpu.texture(
            "full-resolution lighting",
            size,
            HDR,
            1,
            wgpu::TextureUsages::RENDER_ATTACHMENT
                | wgpu::TextureUsages::TEXTURE_BINDING
                | wgpu::TextureUsages::COPY_SRC,
        );
        let pipeline = FullscreenPipeline {
            label: "full-resolution lighting",
            fragment: shaders::DEFERRED_LIGHTING,
            entry_point: "fs_deferred",
            targets: &[Some(HDR.into())],
            depth_stencil: None,
            samples: 1,
        }
        .create(gpu);
        Self { view: target.create_view(&Default::default()), target, pipeline }
    }

    /// Lights every pixel of `inputs` into [`Self::target`], timing the pass.
    pub fn render(&self, gpu: &Gpu, inputs: &DeferredInputs, timer: &mut GpuTimer) -> Result<()> {
        ensure!(
            inputs.gbuffer.size == (self.target.width(), self.target.height()),
            "G-buffer size differs from the target's"
        );
        let shading = shading_uniform(gpu, inputs.eye, inputs.lights.count);
        let [position, normal, albedo] = &inputs.gbuffer.views;
        let group = bind_group(
            gpu,
            "full-resolution lighting",
            &self.pipeline,
            0,
            &[
                shading.as_entire_binding(),
                wgpu::BindingResource::TextureView(position),
                wgpu::BindingResource::TextureView(normal),
                wgpu::BindingResource::TextureView(albedo),
                wgpu::BindingResource::TextureView(&inputs.lights.view),
            ],
        );
        let mut encoder = gpu.encoder("full-resolution lighting");
        {
            let mut pass = encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
                label: Some("full-resolution lighting"),
                color_attachments: &[attachments::colour(&self.view, None, wgpu::Color::TRANSPARENT)],
                timestamp_writes: timer.pass("full-resolution lighting"),
                ..Default::default()
            });
            pass.set_pipeline(&self.pipeline);
            pass.set_bind_group(0, &group, &[]);
            pass.draw(0..3, 0..1);
        }
        timer.resolve(&mut encoder);
        gpu.submit(encoder);
        Ok(())
    }
}

/// Lights every pixel once; returns the `Rgba16Float` image.
pub fn light_full_resolution(gpu: &Gpu, inputs: &DeferredInputs) -> Result<wgpu::Texture> {
    let lighting = FullResolution::new(gpu, inputs.gbuffer.size);
    lighting.render(gpu, inputs, &mut GpuTimer::new(gpu, 1))?;
    Ok(lighting.target)
}
