//! The G-buffer pass (`shaders/deferred/gbuffer.wgsl`): world position, normal + shininess,
//! albedo + specular weight and `Depth32Float` depth (copyable, so read back without compute).

use anyhow::{Result, ensure};
use wgpu::util::DeviceExt;

use crate::attachments;
use crate::fullscreen::{bind_group, uniform_buffer};
use crate::gpu::Gpu;
use crate::query::GpuTimer;
use crate::scene::corridor::{Scene, SceneVertex};
use crate::shaders;

/// f32 bits of the world position (exact, and renderable on every backend, unlike Rgba32Float).
pub const POSITION: wgpu::TextureFormat = wgpu::TextureFormat::Rgba32Uint;
pub const NORMAL: wgpu::TextureFormat = wgpu::TextureFormat::Rgba16Float;
pub const ALBEDO: wgpu::TextureFormat = wgpu::TextureFormat::Rgba8Unorm;
pub const DEPTH: wgpu::TextureFormat = wgpu::TextureFormat::Depth32Float;

pub struct Gbuffer {
    pub size: (u32, u32),
    pub position: wgpu::Texture,
    pub normal: wgpu::Texture,
    pub albedo: wgpu::Texture,
    pub depth: wgpu::Texture,
    pub views: [wgpu::TextureView; 3],
}

/// Checks a render size against the adapter before anything is created.
pub fn check_size(gpu: &Gpu, (width, height): (u32, u32)) -> Result<()> {
    let max = gpu.device.limits().max_texture_dimension_2d;
    ensure!(width >= 1 && height >= 1, "render size {width}x{height} is empty; both sides must be at least 1");
    ensure!(
        width <= max && height <= max,
        "render size {width}x{height} exceeds this adapter's {max}x{max} texture limit"
    );
    Ok(())
}

/// The G-buffer pass at one size: its pipeline and targets, made once, rendered per frame.
pub struct GbufferPass {
    pub gbuffer: Gbuffer,
    pipeline: wgpu::RenderPipeline,
}

impl GbufferPass {
    pub fn new(gpu: &Gpu, size: (u32, u32)) -> Result<Self> {
        check_size(gpu, size)?;
        let usage = wgpu::TextureUsages::RENDER_ATTACHMENT
            | wgpu::TextureUsages::TEXTURE_BINDING
            | wgpu::TextureUsages::COPY_SRC;
        let position = gpu.texture("gbuffer position", size, POSITION, 1, usage);
        let normal = gpu.texture("gbuffer normal", size, NORMAL, 1, usage);
        let albedo = gpu.texture("gbuffer albedo", size, ALBEDO, 1, usage);
        let depth = gpu.texture("gbuffer depth", size, DEPTH, 1, usage);
        let views = [&position, &normal, &albedo].map(|t| t.create_view(&Default::default()));

        let module = shaders::GBUFFER.module(gpu);
        let pipeline = gpu.device.create_render_pipeline(&wgpu::RenderPipelineDescriptor {
            label: Some("gbuffer"),
            layout: None,
            vertex: wgpu::VertexState {
                module: &module,
                entry_point: Some("vs_scene"),
                compilation_options: Default::default(),
                buffers: &[Some(wgpu::VertexBufferLayout {
                    array_stride: std::mem::size_of::<SceneVertex>() as u64,
                    step_mode: wgpu::VertexStepMode::Vertex,
                    attributes: &wgpu::vertex_attr_array![0 => Float32x3, 1 => Float32x3, 2 => Float32x4, 3 => Float32],
                })],
            },
            primitive: wgpu::PrimitiveState { cull_mode: Some(wgpu::Face::Back), ..Default::default() },
            depth_stencil: Some(wgpu::DepthStencilState {
                format: DEPTH,
                depth_write_enabled: Some(true),
                depth_compare: Some(wgpu::CompareFunction::Less),
                stencil: Default::default(),
                bias: Default::default(),
            }),
            multisample: Default::default(),
            fragment: Some(wgpu::FragmentState {
                module: &module,
                entry_point: Some("fs_gbuffer"),
                compilation_options: Default::default(),
                targets: &[Some(POSITION.into()), Some(NORMAL.into()), Some(ALBEDO.into())],
            }),
            multiview_mask: None,
            cache: None,
        });
        Ok(Self { gbuffer: Gbuffer { size, position, normal, albedo, depth, views }, pipeline })
    }

    /// Renders `scene` into [`Self::gbuffer`].
    pub fn render(&self, gpu: &Gpu, scene: &Scene, timer: &mut GpuTimer) {
        let size = self.gbuffer.size;
        let view_projection = scene.camera.view_projection(size.0 as f32 / size.1 as f32);
        let camera = uniform_buffer(gpu, "camera", bytemuck::cast_slice(&view_projection.to_cols_array()));
        let camera_group = bind_group(gpu, "camera", &self.pipeline, 0, &[camera.as_entire_binding()]);
        let vertices = gpu.device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
            label: Some("scene vertices"),
            contents: bytemuck::cast_slice(&scene.vertices),
            usage: wgpu::BufferUsages::VERTEX,
        });
        let depth_view = self.gbuffer.depth.create_view(&Default::default());
        let views = &self.gbuffer.views;
        let mut encoder = gpu.encoder("gbuffer");
        {
            let clear = wgpu::Color::TRANSPARENT;
            let mut pass = encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
                label: Some("gbuffer"),
                color_attachments: &[
                    attachments::colour(&views[0], None, clear),
                    attachments::colour(&views[1], None, clear),
                    attachments::colour(&views[2], None, clear),
                ],
                depth_stencil_attachment: Some(wgpu::RenderPassDepthStencilAttachment {
                    view: &depth_view,
                    depth_ops: Some(wgpu::Operations { load: wgpu::LoadOp::Clear(1.0), store: wgpu::StoreOp::Store }),
                    stencil_ops: None,
                }),
                timestamp_writes: timer.pass("gbuffer"),
                ..Default::default()
            });
            pass.set_pipeline(&self.pipeline);
            pass.set_bind_group(0, &camera_group, &[]);
            pass.set_vertex_buffer(0, vertices.slice(..));
            pass.draw(0..scene.vertices.len() as u32, 0..1);
        }
        timer.resolve(&mut encoder);
        gpu.submit(encoder);
    }
}

/// A G-buffer holding `source`'s samples at `pixels` (row-major indices), in that order, row by
/// row in a texture about as wide as tall; the texels after the last hold no surface
/// (background). For timing a pass over exactly those samples (the CPS bench's reference).
pub fn gather(gpu: &Gpu, source: &Gbuffer, pixels: &[u32]) -> Result<Gbuffer> {
    let count = pixels.len().max(1) as u32;
    let width = count.isqrt().max(1);
    let size = (width, count.div_ceil(width));
    check_size(gpu, size)?;
    let usage = wgpu::TextureUsages::TEXTURE_BINDING | wgpu::TextureUsages::COPY_DST | wgpu::TextureUsages::COPY_SRC;
    let gathered = |texture: &wgpu::Texture, label: &str, format: wgpu::TextureFormat| -> Result<wgpu::Texture> {
        let texels = crate::readback::read_texture(gpu, texture, wgpu::TextureAspect::All, 0)?;
        let bytes = texels.bytes_per_texel as usize;
        let mut data = vec![0u8; (size.0 * size.1) as usize * bytes];
        for (at, &pixel) in data.chunks_exact_mut(bytes).zip(pixels) {
            let from = pixel as usize * bytes;
            at.copy_from_slice(&texels.bytes[from..from + bytes]);
        }
        let target = gpu.texture(label, size, format, 1, usage);
        gpu.queue.write_texture(
            target.as_image_copy(),
            &data,
            wgpu::TexelCopyBufferLayout { offset: 0, bytes_per_row: Some(size.0 * bytes as u32), rows_per_image: None },
            wgpu::Extent3d { width: size.0, height: size.1, depth_or_array_layers: 1 },
        );
        Ok(target)
    };
    let position = gathered(&source.position, "gathered position", POSITION)?;
    let normal = gathered(&source.normal, "gathered normal", NORMAL)?;
    let albedo = gathered(&source.albedo, "gathered albedo", ALBEDO)?;
    // No pass reads a gathered sample's depth.
    let depth = gpu.texture("gathered depth", size, DEPTH, 1, wgpu::TextureUsages::RENDER_ATTACHMENT);
    let views = [&position, &normal, &albedo].map(|t| t.create_view(&Default::default()));
    Ok(Gbuffer { size, position, normal, albedo, depth, views })
}

/// Renders the scene's G-buffer at `size` once.
pub fn render_gbuffer(gpu: &Gpu, scene: &Scene, size: (u32, u32), timer: &mut GpuTimer) -> Result<Gbuffer> {
    let pass = GbufferPass::new(gpu, size)?;
    pass.render(gpu, scene, timer);
    Ok(pass.gbuffer)
}
