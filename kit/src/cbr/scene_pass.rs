//! The scene pass of `shaders/cbr/scene.wgsl`: its pipelines (forward opaque, forward
//! transparent, G-buffer, object motion) at one sample count, and a scene's GPU resources (vertex
//! buffer, lights, albedo map, per-view and per-draw uniforms addressed by dynamic offsets).

use anyhow::Result;
use glam::{Mat4, Vec3};
use wgpu::util::DeviceExt;

use super::scene::{ALBEDO_MAP_SIZE, CheckerboardScene, CheckerboardVertex, FrameView, albedo_map_levels};
use crate::deferred::lights::LightTexture;
use crate::gpu::Gpu;
use crate::scene::corridor::Light;
use crate::shaders;

pub const HDR: wgpu::TextureFormat = wgpu::TextureFormat::Rgba16Float;
pub const NORMAL: wgpu::TextureFormat = wgpu::TextureFormat::Rgba16Float;
pub const ALBEDO: wgpu::TextureFormat = wgpu::TextureFormat::Rgba8Unorm;
/// Full-resolution pixels of motion, alpha 1 on moving objects.
pub const MOTION: wgpu::TextureFormat = wgpu::TextureFormat::Rgba16Float;
pub const DEPTH: wgpu::TextureFormat = wgpu::TextureFormat::Depth32Float;

/// How texture LOD is chosen in a pass.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum TextureLod {
    /// `textureSampleBias` by this many levels (0: the pass's own footprint; the whitepaper's
    /// checkerboard setting is −0.5).
    Bias(f32),
    /// `textureSampleGrad` with the derivatives scaled (0.5: exactly full resolution's LOD).
    Gradient(f32),
}

impl TextureLod {
    pub fn name(self) -> String {
        match self {
            Self::Bias(b) => format!("bias{b}"),
            Self::Gradient(g) => format!("grad{g}"),
        }
    }

    fn mode_and_value(self) -> (u32, f32) {
        match self {
            Self::Bias(b) => (0, b),
            Self::Gradient(g) => (1, g),
        }
    }
}

/// Which draws of the scene a pass draws.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum DrawSet {
    Opaque,
    Transparent,
    Moving,
}

/// Uniform blocks at 256-byte slots of one buffer, bound with dynamic offsets.
struct UniformSlots {
    buffer: wgpu::Buffer,
}

const SLOT: u64 = 256;

impl UniformSlots {
    fn new(gpu: &Gpu, label: &str, count: usize) -> Self {
        let buffer = gpu.device.create_buffer(&wgpu::BufferDescriptor {
            label: Some(label),
            size: SLOT * count.max(1) as u64,
            usage: wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST,
            mapped_at_creation: false,
        });
        Self { buffer }
    }

    fn write(&self, gpu: &Gpu, slot: usize, bytes: &[u8]) {
        gpu.queue.write_buffer(&self.buffer, SLOT * slot as u64, bytes);
    }

    fn binding(&self, size: u64) -> wgpu::BindingResource<'_> {
        wgpu::BindingResource::Buffer(wgpu::BufferBinding {
            buffer: &self.buffer,
            offset: 0,
            size: wgpu::BufferSize::new(size),
        })
    }
}

/// `View` in scene.wgsl: 3 matrices, screen, LOD mode/value, eye, light count.
const VIEW_BYTES: u64 = 224;
/// `Object`: model now and one frame earlier.
const OBJECT_BYTES: u64 = 128;

/// The scene pass's pipelines at one sample count.
pub struct ScenePipelines {
    layout: wgpu::BindGroupLayout,
    pub samples: u32,
    /// Forward opaque draws lay their depth first (no colour), so that the shading draw, depth
    /// Equal, shades each pixel's visible surface once rather than every surface drawn over it.
    forward_depth: wgpu::RenderPipeline,
    forward: wgpu::RenderPipeline,
    transparent: wgpu::RenderPipeline,
    gbuffer: wgpu::RenderPipeline,
    object_motion: wgpu::RenderPipeline,
}

fn uniform_entry(binding: u32) -> wgpu::BindGroupLayoutEntry {
    wgpu::BindGroupLayoutEntry {
        binding,
        visibility: wgpu::ShaderStages::VERTEX_FRAGMENT,
        ty: wgpu::BindingType::Buffer {
            ty: wgpu::BufferBindingType::Uniform,
            has_dynamic_offset: true,
            min_binding_size: None,
        },
        count: None,
    }
}

fn texture_entry(binding: u32, filterable: bool) -> wgpu::BindGroupLayoutEntry {
    wgpu::BindGroupLayoutEntry {
        binding,
        visibility: wgpu::ShaderStages::FRAGMENT,
        ty: wgpu::BindingType::Texture {
            sample_type: wgpu::TextureSampleType::Float { filterable },
            view_dimension: wgpu::TextureViewDimension::D2,
            multisampled: false,
        },
        count: None,
    }
}

impl ScenePipelines {
    pub fn new(gpu: &Gpu, samples: u32) -> Self {
        let layout = gpu.device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("checkerboard scene"),
            entries: &[
                uniform_entry(0),
                uniform_entry(1),
                texture_entry(2, false),
                texture_entry(3, true),
                wgpu::BindGroupLayoutEntry {
                    binding: 4,
                    visibility: wgpu::ShaderStages::FRAGMENT,
                    ty: wgpu::BindingType::Sampler(wgpu::SamplerBindingType::Filtering),
                    count: None,
                },
            ],
        });
        let pipeline_layout = gpu.device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
            label: Some("checkerboard scene"),
            bind_group_layouts: &[Some(&layout)],
            immediate_size: 0,
        });
        let module = shaders::CBR_SCENE.module_for_samples(gpu, samples);
        let premultiplied = wgpu::BlendState {
            color: wgpu::BlendComponent {
                src_factor: wgpu::BlendFactor::One,
                dst_factor: wgpu::BlendFactor::OneMinusSrcAlpha,
                operation: wgpu::BlendOperation::Add,
            },
            alpha: wgpu::BlendComponent {
                src_factor: wgpu::BlendFactor::One,
                dst_factor: wgpu::BlendFactor::OneMinusSrcAlpha,
                operation: wgpu::BlendOperation::Add,
            },
        };
        let create = |label: &str,
                      entry: &str,
                      targets: &[Option<wgpu::ColorTargetState>],
                      depth: (bool, wgpu::CompareFunction),
                      cull: Option<wgpu::Face>| {
            gpu.device.create_render_pipeline(&wgpu::RenderPipelineDescriptor {
                label: Some(label),
                layout: Some(&pipeline_layout),
                vertex: wgpu::VertexState {
                    module: &module,
                    entry_point: Some("vs_scene"),
                    compilation_options: Default::default(),
                    buffers: &[Some(wgpu::VertexBufferLayout {
                        array_stride: std::mem::size_of::<CheckerboardVertex>() as u64,
                        step_mode: wgpu::VertexStepMode::Vertex,
                        attributes: &wgpu::vertex_attr_array![
                            0 => Float32x3, 1 => Float32x3, 2 => Float32x4, 3 => Float32, 4 => Float32
                        ],
                    })],
                },
                primitive: wgpu::PrimitiveState { cull_mode: cull, ..Default::default() },
                depth_stencil: Some(wgpu::DepthStencilState {
                    format: DEPTH,
                    depth_write_enabled: Some(depth.0),
                    depth_compare: Some(depth.1),
                    stencil: Default::default(),
                    bias: Default::default(),
                }),
                multisample: wgpu::MultisampleState { count: samples, ..Default::default() },
                fragment: Some(wgpu::FragmentState {
                    module: &module,
                    entry_point: Some(entry),
                    compilation_options: Default::default(),
                    targets,
                }),
                multiview_mask: None,
                cache: None,
            })
        };
        let back = Some(wgpu::Face::Back);
        let less = wgpu::CompareFunction::Less;
        let depth_only =
            [Some(wgpu::ColorTargetState { format: HDR, blend: None, write_mask: wgpu::ColorWrites::empty() })];
        Self {
            forward_depth: create("scene forward depth", "fs_depth_only", &depth_only, (true, less), back),
            forward: create(
                "scene forward",
                "fs_forward",
                &[Some(HDR.into())],
                (false, wgpu::CompareFunction::Equal),
                back,
            ),
            transparent: create(
                "scene transparent",
                "fs_transparent",
                &[Some(wgpu::ColorTargetState {
                    format: HDR,
                    blend: Some(premultiplied),
                    write_mask: wgpu::ColorWrites::ALL,
                })],
                (false, less),
                None,
            ),
            gbuffer: create(
                "scene gbuffer",
                "fs_gbuffer",
                &[Some(NORMAL.into()), Some(ALBEDO.into())],
                (true, less),
                back,
            ),
            object_motion: create(
                "scene object motion",
                "fs_object_motion",
                &[Some(MOTION.into())],
                (false, wgpu::CompareFunction::Equal),
                back,
            ),
            layout,
            samples,
        }
    }

    /// The pipeline drawing `set` for a pass of `kind`.
    fn pipeline(&self, kind: ScenePassKind, set: DrawSet) -> &wgpu::RenderPipeline {
        match (kind, set) {
            (_, DrawSet::Transparent) => &self.transparent,
            (_, DrawSet::Moving) => &self.object_motion,
            (ScenePassKind::Forward, DrawSet::Opaque) => &self.forward,
            (ScenePassKind::Gbuffer, DrawSet::Opaque) => &self.gbuffer,
        }
    }
}

/// Whether opaque draws shade (forward) or write the G-buffer.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ScenePassKind {
    Forward,
    Gbuffer,
}

/// A scene on the GPU: vertices, lights, albedo map and the uniforms of up to `views` views.
pub struct SceneResources {
    vertices: wgpu::Buffer,
    views: UniformSlots,
    objects: UniformSlots,
    group: wgpu::BindGroup,
    lights: LightTexture,
    light_count: u32,
    draws: Vec<(std::ops::Range<u32>, DrawSet)>,
}

/// Uploads the albedo map's mip chain.
fn albedo_map(gpu: &Gpu) -> wgpu::TextureView {
    let levels = albedo_map_levels();
    let texture = gpu.device.create_texture_with_data(
        &gpu.queue,
        &wgpu::TextureDescriptor {
            label: Some("albedo map"),
            size: wgpu::Extent3d { width: ALBEDO_MAP_SIZE, height: ALBEDO_MAP_SIZE, depth_or_array_layers: 1 },
            mip_level_count: levels.len() as u32,
            sample_count: 1,
            dimension: wgpu::TextureDimension::D2,
            format: wgpu::TextureFormat::Rgba8Unorm,
            usage: wgpu::TextureUsages::TEXTURE_BINDING,
            view_formats: &[],
        },
        wgpu::util::TextureDataOrder::MipMajor,
        bytemuck::cast_slice(&levels.concat()),
    );
    texture.create_view(&Default::default())
}

impl SceneResources {
    pub fn new(gpu: &Gpu, pipelines: &ScenePipelines, scene: &CheckerboardScene, views: usize) -> Result<Self> {
        // WGSL bindings are static: an unlit scene binds one unused light and counts none.
        let placeholder = [Light { position: Vec3::ZERO, range: 0.0, colour: Vec3::ZERO, intensity: 0.0 }];
        let lights = LightTexture::new(gpu, if scene.lights.is_empty() { &placeholder } else { &scene.lights })?;
        let vertices = gpu.device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
            label: Some("checkerboard scene vertices"),
            contents: bytemuck::cast_slice(&scene.vertices),
            usage: wgpu::BufferUsages::VERTEX,
        });
        let view_slots = UniformSlots::new(gpu, "checkerboard views", views);
        let object_slots = UniformSlots::new(gpu, "checkerboard objects", scene.draws.len());
        let sampler = gpu.device.create_sampler(&wgpu::SamplerDescriptor {
            label: Some("albedo map"),
            address_mode_u: wgpu::AddressMode::Repeat,
            address_mode_v: wgpu::AddressMode::Repeat,
            mag_filter: wgpu::FilterMode::Linear,
            min_filter: wgpu::FilterMode::Linear,
            mipmap_filter: wgpu::MipmapFilterMode::Linear,
            ..Default::default()
        });
        let map = albedo_map(gpu);
        let group = gpu.device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("checkerboard scene"),
            layout: &pipelines.layout,
            entries: &[
                wgpu::BindGroupEntry { binding: 0, resource: view_slots.binding(VIEW_BYTES) },
                wgpu::BindGroupEntry { binding: 1, resource: object_slots.binding(OBJECT_BYTES) },
                wgpu::BindGroupEntry { binding: 2, resource: wgpu::BindingResource::TextureView(&lights.view) },
                wgpu::BindGroupEntry { binding: 3, resource: wgpu::BindingResource::TextureView(&map) },
                wgpu::BindGroupEntry { binding: 4, resource: wgpu::BindingResource::Sampler(&sampler) },
            ],
        });
        let draws = scene
            .draws
            .iter()
            .map(|d| {
                let set = match (d.transparent, d.velocity != Vec3::ZERO) {
                    (true, _) => DrawSet::Transparent,
                    (false, true) => DrawSet::Moving,
                    (false, false) => DrawSet::Opaque,
                };
                (d.vertices.clone(), set)
            })
            .collect();
        Ok(Self {
            vertices,
            views: view_slots,
            objects: object_slots,
            group,
            lights,
            light_count: scene.lights.len() as u32,
            draws,
        })
    }

    /// Writes view slot `slot`: rasterising through `clip_from_world`, motion and shading from
    /// `frame`, textures at `lod`.
    pub fn write_view(
        &self,
        gpu: &Gpu,
        slot: usize,
        clip_from_world: Mat4,
        frame: &FrameView,
        screen: (u32, u32),
        lod: TextureLod,
    ) {
        let (mode, value) = lod.mode_and_value();
        let mut words: Vec<u32> = Vec::with_capacity(VIEW_BYTES as usize / 4);
        for matrix in [clip_from_world, frame.full_from_world, frame.previous_full_from_world] {
            words.extend(matrix.to_cols_array().map(f32::to_bits));
        }
        words.extend([(screen.0 as f32).to_bits(), (screen.1 as f32).to_bits(), mode, value.to_bits()]);
        words.extend([frame.eye.x.to_bits(), frame.eye.y.to_bits(), frame.eye.z.to_bits(), self.light_count]);
        self.views.write(gpu, slot, bytemuck::cast_slice(&words));
    }

    /// Writes every draw's model matrices for `frame`.
    pub fn write_objects(&self, gpu: &Gpu, frame: &FrameView) {
        for (slot, (now, before)) in frame.models.iter().enumerate() {
            let mut floats = now.to_cols_array().to_vec();
            floats.extend(before.to_cols_array());
            self.objects.write(gpu, slot, bytemuck::cast_slice(&floats));
        }
    }

    /// Lights the shading passes read (an unlit scene's holds one unused light).
    pub fn lights_view(&self) -> &wgpu::TextureView {
        &self.lights.view
    }

    /// Lights shaded: 0 for an unlit scene.
    pub fn light_count(&self) -> u32 {
        self.light_count
    }

    /// Whether the scene has draws of `set` (moving draws are opaque too).
    pub fn has(&self, set: DrawSet) -> bool {
        self.draws.iter().any(|(_, s)| *s == set)
    }

    /// Draws `set` through view slot `view`: opaque includes moving draws, whose motion pass is
    /// `DrawSet::Moving`.
    pub fn draw(
        &self,
        pass: &mut wgpu::RenderPass<'_>,
        pipelines: &ScenePipelines,
        kind: ScenePassKind,
        set: DrawSet,
        view: usize,
    ) {
        if (kind, set) == (ScenePassKind::Forward, DrawSet::Opaque) {
            self.draw_with(pass, &pipelines.forward_depth, set, view);
        }
        self.draw_with(pass, pipelines.pipeline(kind, set), set, view);
    }

    fn draw_with(&self, pass: &mut wgpu::RenderPass<'_>, pipeline: &wgpu::RenderPipeline, set: DrawSet, view: usize) {
        pass.set_pipeline(pipeline);
        pass.set_vertex_buffer(0, self.vertices.slice(..));
        for (slot, (range, draw_set)) in self.draws.iter().enumerate() {
            let drawn = match set {
                DrawSet::Opaque => *draw_set != DrawSet::Transparent,
                other => *draw_set == other,
            };
            if drawn {
                pass.set_bind_group(0, &self.group, &[(SLOT * view as u64) as u32, (SLOT * slot as u64) as u32]);
                pass.draw(range.clone(), 0..1);
            }
        }
    }
}
