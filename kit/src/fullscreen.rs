//! Full-screen passes: `shaders/kit/fullscreen.wgsl`'s triangle with a fragment stage from any
//! pass file, and the bind groups and uniforms such passes take.

use wgpu::util::DeviceExt;

use crate::gpu::Gpu;
use crate::shaders::{self, ShaderFile};

/// A full-screen pipeline's fixed-function state; `layout: None` lets wgpu derive the layout.
#[derive(Clone, Debug)]
pub struct FullscreenPipeline<'a> {
    pub label: &'a str,
    pub fragment: ShaderFile,
    pub entry_point: &'a str,
    pub targets: &'a [Option<wgpu::ColorTargetState>],
    pub depth_stencil: Option<wgpu::DepthStencilState>,
    pub samples: u32,
}

impl FullscreenPipeline<'_> {
    pub fn create(&self, gpu: &Gpu) -> wgpu::RenderPipeline {
        self.create_specialised(gpu, &[])
    }

    /// The pipeline with the fragment stage's `override` constants set (name, value).
    pub fn create_specialised(&self, gpu: &Gpu, constants: &[(&str, f64)]) -> wgpu::RenderPipeline {
        self.create_from_module(gpu, &self.fragment.module(gpu), constants)
    }

    /// [`Self::create_specialised`] with the fragment stage compiled from `fragment`, a module
    /// made from `self.fragment`'s source with a declaration changed for the device.
    pub fn create_from_module(
        &self,
        gpu: &Gpu,
        fragment: &wgpu::ShaderModule,
        constants: &[(&str, f64)],
    ) -> wgpu::RenderPipeline {
        let vertex = shaders::FULLSCREEN.module(gpu);
        gpu.device.create_render_pipeline(&wgpu::RenderPipelineDescriptor {
            label: Some(self.label),
            layout: None,
            vertex: wgpu::VertexState {
                module: &vertex,
                entry_point: Some("vs_fullscreen"),
                compilation_options: Default::default(),
                buffers: &[],
            },
            primitive: Default::default(),
            depth_stencil: self.depth_stencil.clone(),
            multisample: wgpu::MultisampleState { count: self.samples, ..Default::default() },
            fragment: Some(wgpu::FragmentState {
                module: fragment,
                entry_point: Some(self.entry_point),
                compilation_options: wgpu::PipelineCompilationOptions { constants, ..Default::default() },
                targets: self.targets,
            }),
            multiview_mask: None,
            cache: None,
        })
    }
}

/// Binds `resources` at bindings 0, 1, ... of group `group` of a pipeline with a derived layout.
pub fn bind_group(
    gpu: &Gpu,
    label: &str,
    pipeline: &wgpu::RenderPipeline,
    group: u32,
    resources: &[wgpu::BindingResource<'_>],
) -> wgpu::BindGroup {
    let numbered: Vec<(u32, wgpu::BindingResource)> =
        resources.iter().enumerate().map(|(i, resource)| (i as u32, resource.clone())).collect();
    bind_group_at(gpu, label, pipeline, group, &numbered)
}

/// Binds each `(binding, resource)` of group `group` of a pipeline with a derived layout (for
/// entry points that leave some of a module's bindings unused).
pub fn bind_group_at(
    gpu: &Gpu,
    label: &str,
    pipeline: &wgpu::RenderPipeline,
    group: u32,
    resources: &[(u32, wgpu::BindingResource<'_>)],
) -> wgpu::BindGroup {
    let entries: Vec<wgpu::BindGroupEntry> = resources
        .iter()
        .map(|(binding, resource)| wgpu::BindGroupEntry { binding: *binding, resource: resource.clone() })
        .collect();
    gpu.device.create_bind_group(&wgpu::BindGroupDescriptor {
        label: Some(label),
        layout: &pipeline.get_bind_group_layout(group),
        entries: &entries,
    })
}

/// A uniform buffer holding `contents` (padded by the caller to WGSL's layout).
pub fn uniform_buffer(gpu: &Gpu, label: &str, contents: &[u8]) -> wgpu::Buffer {
    gpu.device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
        label: Some(label),
        contents,
        usage: wgpu::BufferUsages::UNIFORM,
    })
}

/// Runs `pipeline` (one colour target of `format`, bind group 0 = `group`) over a fresh `size`
/// target and reads the target back: the shape of every probe that evaluates a function per pixel.
pub fn render_to_readback(
    gpu: &Gpu,
    label: &str,
    pipeline: &wgpu::RenderPipeline,
    group: &wgpu::BindGroup,
    format: wgpu::TextureFormat,
    size: (u32, u32),
) -> anyhow::Result<crate::readback::Texels> {
    let target =
        gpu.texture(label, size, format, 1, wgpu::TextureUsages::RENDER_ATTACHMENT | wgpu::TextureUsages::COPY_SRC);
    let view = target.create_view(&Default::default());
    let mut encoder = gpu.encoder(label);
    {
        let mut pass = encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
            label: Some(label),
            color_attachments: &[crate::attachments::colour(&view, None, wgpu::Color::TRANSPARENT)],
            ..Default::default()
        });
        pass.set_pipeline(pipeline);
        pass.set_bind_group(0, group, &[]);
        pass.draw(0..3, 0..1);
    }
    gpu.submit(encoder);
    crate::readback::read_texture(gpu, &target, wgpu::TextureAspect::All, 0)
}
