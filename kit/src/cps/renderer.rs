//! The CPS frame: LOD buffer → LOD-present mask pyramid (one pass a level) → the stencil of
//! every level, side by side in one atlas (one pass, one draw a level) → every level lit in one
//! pass behind stencil Equal (one draw a level, its viewport the level's rect) → composite. Targets and pipelines are made once per renderer; `render` records one frame in
//! one encoder with a timestamp pair around every pass and an occlusion query around every
//! level's lighting draw.

use anyhow::{Context, Result};
use glam::Vec3;

use super::config::{CpsConfig, LodPolicy};
use super::plan::Plan;
use super::reference::Level;
use super::targets::MipChain;
use crate::deferred::gbuffer::Gbuffer;
use crate::deferred::lighting::{HDR, shading_uniform};
use crate::deferred::lights::LightTexture;
use crate::fullscreen::{FullscreenPipeline, bind_group, uniform_buffer};
use crate::gpu::Gpu;
use crate::query::{GpuTimer, OcclusionQueries, PassTime};
use crate::rects::stencil_state;
use crate::shaders;

const LOD: wgpu::TextureFormat = wgpu::TextureFormat::R8Uint;
const MASK: wgpu::TextureFormat = wgpu::TextureFormat::R32Uint;
const STENCIL: wgpu::TextureFormat = wgpu::TextureFormat::Stencil8;

/// One frame's inputs.
pub struct CpsFrame<'a> {
    pub gbuffer: &'a Gbuffer,
    pub lights: &'a LightTexture,
    pub eye: Vec3,
}

/// One frame's results; the textures stay owned by the renderer.
pub struct CpsOutput {
    /// Coarse texels shaded per level (occlusion counts; booleans on GL).
    pub shaded_texels: Vec<u64>,
    /// Every pass, in order, with its GPU time (empty without timestamps).
    pub pass_times: Vec<PassTime>,
}

impl CpsOutput {
    /// GPU time of the passes whose label starts with `prefix` ("" for all).
    pub fn gpu_ms(&self, prefix: &str) -> f64 {
        self.pass_times.iter().filter(|t| t.label.starts_with(prefix)).map(|t| t.ms).sum()
    }
}

fn target_usage() -> wgpu::TextureUsages {
    wgpu::TextureUsages::RENDER_ATTACHMENT | wgpu::TextureUsages::TEXTURE_BINDING | wgpu::TextureUsages::COPY_SRC
}

/// Colour and stencil attachments of one pass; `viewport` limits drawing to the texels in use.
struct PassTargets<'a> {
    colour: Option<&'a wgpu::TextureView>,
    stencil: Option<(&'a wgpu::TextureView, wgpu::LoadOp<u32>)>,
    viewport: (u32, u32),
}

fn begin<'e>(
    encoder: &'e mut wgpu::CommandEncoder,
    label: &str,
    targets: PassTargets<'_>,
    timer: &mut GpuTimer,
    queries: Option<&wgpu::QuerySet>,
) -> wgpu::RenderPass<'e> {
    let colour =
        targets.colour.map(|view| crate::attachments::colour(view, None, wgpu::Color::TRANSPARENT)).unwrap_or(None);
    let mut pass = encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
        label: Some(label),
        color_attachments: &[colour],
        depth_stencil_attachment: targets.stencil.map(|(view, load)| wgpu::RenderPassDepthStencilAttachment {
            view,
            depth_ops: None,
            stencil_ops: Some(wgpu::Operations { load, store: wgpu::StoreOp::Store }),
        }),
        timestamp_writes: timer.pass(label),
        occlusion_query_set: queries,
        multiview_mask: None,
    });
    pass.set_viewport(0.0, 0.0, targets.viewport.0 as f32, targets.viewport.1 as f32, 0.0, 1.0);
    pass
}

/// Limits drawing to one level's rect of an atlas: x, y, width, height.
fn set_level_viewport(pass: &mut wgpu::RenderPass<'_>, (x, y, width, height): (u32, u32, u32, u32)) {
    pass.set_viewport(x as f32, y as f32, width as f32, height as f32, 0.0, 1.0);
    pass.set_scissor_rect(x, y, width, height);
}

pub struct CpsRenderer {
    pub config: CpsConfig,
    pub plan: Plan,
    /// LOD per pixel (`R8Uint`, screen-sized).
    pub lod: wgpu::Texture,
    lod_view: wgpu::TextureView,
    /// OR-reduced edge flags (content policy only).
    pub edges: Option<MipChain>,
    /// OR-reduced LOD-present bits: bit l of mip l texel q = some pixel of q's block has LOD l.
    pub mask: MipChain,
    /// Every level's stencil, side by side (absent for the naive comparison).
    pub stencil: Option<wgpu::Texture>,
    /// Every lit level, side by side; alpha 1 marks a shaded texel.
    pub lit: wgpu::Texture,
    /// The composite (`Rgba16Float`, screen-sized).
    pub image: wgpu::Texture,
    /// Indirect draw arguments of each level's lighting draw.
    pub(crate) level_draws: wgpu::Buffer,
    level_uniforms: Vec<wgpu::Buffer>,
    lod_pipeline: Option<wgpu::RenderPipeline>,
    /// Edge detection and the edge pyramid's reduction (content policy only).
    edge_pipelines: Option<(wgpu::RenderPipeline, wgpu::RenderPipeline)>,
    present_pipeline: wgpu::RenderPipeline,
    mask_reduce_pipeline: wgpu::RenderPipeline,
    /// Stencil marks of every level, from the finished mask pyramid.
    mark_pipeline: Option<wgpu::RenderPipeline>,
    light_pipeline: wgpu::RenderPipeline,
    composite_pipeline: wgpu::RenderPipeline,
}

impl CpsRenderer {
    pub fn new(gpu: &Gpu, screen: (u32, u32), config: CpsConfig) -> Result<Self> {
        let plan = Plan::new(gpu, screen, &config)?;
        let levels = plan.levels();
        let atlas = &plan.atlas;
        let lod = gpu.texture("lod", screen, LOD, 1, target_usage() | wgpu::TextureUsages::COPY_DST);
        let chain = |label, format| MipChain::new(gpu, label, plan.padded, levels, format, target_usage());
        let fullscreen = |label: &'static str,
                          fragment,
                          entry_point: &'static str,
                          format: Option<wgpu::TextureFormat>,
                          depth_stencil| {
            FullscreenPipeline {
                label,
                fragment,
                entry_point,
                targets: &[format.map(Into::into)],
                depth_stencil,
                samples: 1,
            }
            .create(gpu)
        };
        let (lod_pipeline, edge_pipelines) = match &config.policy {
            LodPolicy::Foveated { .. } => {
                (Some(fullscreen("foveated lod", shaders::CPS_LOD_FOVEATED, "fs_lod_foveated", Some(LOD), None)), None)
            }
            LodPolicy::Content { .. } => (
                Some(fullscreen("content lod", shaders::CPS_LOD_CONTENT, "fs_lod_content", Some(LOD), None)),
                Some((
                    fullscreen("edge mask", shaders::CPS_EDGE_MASK, "fs_edge_mask", Some(MASK), None),
                    fullscreen("edge reduce", shaders::CPS_MASK_REDUCE, "fs_mask_reduce", Some(MASK), None),
                )),
            ),
            LodPolicy::Explicit(_) => (None, None),
        };
        let present_entry = if plan.skip_absent_levels_on_gpu { "fs_lod_present_and_count" } else { "fs_lod_present" };
        let mark_pipeline = plan.stencil_pyramid.then(|| {
            FullscreenPipeline {
                label: "stencil mark",
                fragment: shaders::CPS_STENCIL_MARK,
                entry_point: "fs_stencil_mark",
                // Stencil only: the pass's one colour slot is empty.
                targets: &[None],
                depth_stencil: Some(stencil_state(
                    STENCIL,
                    wgpu::CompareFunction::Always,
                    wgpu::StencilOperation::Replace,
                )),
                samples: 1,
            }
            .create(gpu)
        });
        let level_draws = gpu.device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("level draws"),
            size: 16 * 9,
            usage: wgpu::BufferUsages::STORAGE
                | wgpu::BufferUsages::INDIRECT
                | wgpu::BufferUsages::COPY_DST
                | wgpu::BufferUsages::COPY_SRC,
            mapped_at_creation: false,
        });
        Ok(Self {
            lod_view: lod.create_view(&Default::default()),
            lod,
            edges: plan.edge_pyramid.then(|| chain("edge pyramid", MASK)),
            mask: chain("lod-present pyramid", MASK),
            stencil: plan.stencil_pyramid.then(|| gpu.texture("stencil atlas", atlas.size, STENCIL, 1, target_usage())),
            // Written by copies too: a case composites known shading (`composite_levels`).
            lit: gpu.texture("lit atlas", atlas.size, HDR, 1, target_usage() | wgpu::TextureUsages::COPY_DST),
            image: gpu.texture("cps composite", screen, HDR, 1, target_usage()),
            level_draws,
            level_uniforms: (0..levels as usize)
                .map(|level| {
                    let (x, y) = atlas.origins[level];
                    uniform_buffer(gpu, "level", bytemuck::cast_slice(&[level as u32, x, y, 0]))
                })
                .collect(),
            lod_pipeline,
            edge_pipelines,
            present_pipeline: fullscreen("lod present", shaders::CPS_LOD_PRESENT, present_entry, Some(MASK), None),
            mask_reduce_pipeline: fullscreen(
                "mask reduce",
                shaders::CPS_MASK_REDUCE,
                "fs_mask_reduce",
                Some(MASK),
                None,
            ),
            mark_pipeline,
            light_pipeline: fullscreen(
                "light level",
                shaders::CPS_LIGHTING,
                "fs_light_level",
                Some(HDR),
                plan.stencil_pyramid
                    .then(|| stencil_state(STENCIL, wgpu::CompareFunction::Equal, wgpu::StencilOperation::Keep)),
            ),
            composite_pipeline: FullscreenPipeline {
                label: "composite",
                fragment: shaders::CPS_COMPOSITE,
                entry_point: config.composite.entry_point(),
                targets: &[Some(HDR.into())],
                depth_stencil: None,
                samples: 1,
            }
            .create(gpu),
            config,
            plan,
        })
    }

    /// Records and runs one frame; waits for its queries.
    pub fn render(&self, gpu: &Gpu, frame: &CpsFrame) -> Result<CpsOutput> {
        anyhow::ensure!(
            frame.gbuffer.size == self.plan.screen,
            "G-buffer is {:?}, the renderer was planned for {:?}",
            frame.gbuffer.size,
            self.plan.screen
        );
        let levels = self.plan.levels();
        let mut timer = GpuTimer::new(gpu, 6 * levels + 8);
        let queries = OcclusionQueries::new(gpu, levels);
        let draws: Vec<[u32; 4]> = (0..9).map(|_| [3, u32::from(!self.plan.skip_absent_levels_on_gpu), 0, 0]).collect();
        gpu.queue.write_buffer(&self.level_draws, 0, bytemuck::cast_slice(&draws));
        if let LodPolicy::Explicit(values) = &self.config.policy {
            gpu.queue.write_texture(
                self.lod.as_image_copy(),
                values,
                wgpu::TexelCopyBufferLayout {
                    offset: 0,
                    bytes_per_row: Some(self.plan.screen.0),
                    rows_per_image: None,
                },
                self.lod.size(),
            );
        }
        let mut encoder = gpu.encoder("cps frame");
        self.record_lod(gpu, &mut encoder, frame, &mut timer);
        self.record_stencil_pyramid(gpu, &mut encoder, &mut timer);
        self.record_lighting(gpu, &mut encoder, frame, &mut timer, &queries);
        self.record_composite(gpu, &mut encoder, &mut timer);
        queries.resolve(&mut encoder);
        timer.resolve(&mut encoder);
        gpu.submit(encoder);
        let shaded_texels = queries.read(gpu).context("reading per-level shaded counts")?;
        Ok(CpsOutput { shaded_texels, pass_times: timer.read(gpu)? })
    }

    /// Composites `levels` (0..=top, each holding its level's extent) in place of what `render`
    /// lit, over the LOD buffer the last `render` left: the composite alone, fed with shading
    /// whose exact reconstruction a case knows (`cps.composite.linear_precision`).
    pub fn composite_levels(&self, gpu: &Gpu, levels: &[Level]) -> Result<()> {
        anyhow::ensure!(
            levels.len() == self.plan.levels() as usize,
            "{} levels given, the plan has {}",
            levels.len(),
            self.plan.levels()
        );
        for (level, given) in levels.iter().enumerate() {
            let (x, y, width, height) = self.plan.atlas.rect(level);
            anyhow::ensure!(
                given.extent == (width, height) && given.texels.len() == (width * height) as usize,
                "level {level} is {:?} with {} texels; the plan's is {width}x{height}",
                given.extent,
                given.texels.len()
            );
            let halves: Vec<u16> =
                given.texels.iter().flatten().map(|&value| half::f16::from_f32(value).to_bits()).collect();
            gpu.queue.write_texture(
                wgpu::TexelCopyTextureInfo {
                    texture: &self.lit,
                    mip_level: 0,
                    origin: wgpu::Origin3d { x, y, z: 0 },
                    aspect: wgpu::TextureAspect::All,
                },
                bytemuck::cast_slice(&halves),
                wgpu::TexelCopyBufferLayout { offset: 0, bytes_per_row: Some(width * 8), rows_per_image: None },
                wgpu::Extent3d { width, height, depth_or_array_layers: 1 },
            );
        }
        let mut timer = GpuTimer::new(gpu, 1);
        let mut encoder = gpu.encoder("cps composite");
        self.record_composite(gpu, &mut encoder, &mut timer);
        timer.resolve(&mut encoder);
        gpu.submit(encoder);
        timer.read(gpu).map(drop)
    }

    /// Reduces the edge pyramid from mip 1 to the top: texel q ORs its 2×2 children.
    fn record_edge_reduce(
        &self,
        gpu: &Gpu,
        encoder: &mut wgpu::CommandEncoder,
        edges: &MipChain,
        reduce: &wgpu::RenderPipeline,
        timer: &mut GpuTimer,
    ) {
        for level in 1..self.plan.levels() as usize {
            let group = bind_group(
                gpu,
                "edges",
                reduce,
                0,
                &[wgpu::BindingResource::TextureView(&edges.level_views[level - 1])],
            );
            let targets = PassTargets {
                colour: Some(&edges.level_views[level]),
                stencil: None,
                viewport: self.plan.level_extents[level],
            };
            let mut pass = begin(encoder, &format!("edges {level}"), targets, timer, None);
            pass.set_pipeline(reduce);
            pass.set_bind_group(0, &group, &[]);
            pass.draw(0..3, 0..1);
        }
    }

    fn record_lod(&self, gpu: &Gpu, encoder: &mut wgpu::CommandEncoder, frame: &CpsFrame, timer: &mut GpuTimer) {
        let screen = self.plan.screen;
        let top = self.plan.top_level;
        let lod_targets = || PassTargets { colour: Some(&self.lod_view), stencil: None, viewport: screen };
        match (&self.config.policy, &self.lod_pipeline) {
            (LodPolicy::Foveated { focus, inner_radius }, Some(pipeline)) => {
                let words = [
                    (focus.0 * screen.0 as f32).to_bits(),
                    (focus.1 * screen.1 as f32).to_bits(),
                    inner_radius.to_bits(),
                    top,
                ];
                let uniform = uniform_buffer(gpu, "foveation", bytemuck::cast_slice(&words));
                let group = bind_group(gpu, "foveation", pipeline, 0, &[uniform.as_entire_binding()]);
                let mut pass = begin(encoder, "lod", lod_targets(), timer, None);
                pass.set_pipeline(pipeline);
                pass.set_bind_group(0, &group, &[]);
                pass.draw(0..3, 0..1);
            }
            (LodPolicy::Content { normal_cos, depth_ratio }, Some(pipeline)) => {
                let (edges, (edge_pipeline, edge_reduce)) =
                    (self.edges.as_ref().expect("planned"), self.edge_pipelines.as_ref().expect("planned"));
                let words = [frame.eye.x, frame.eye.y, frame.eye.z, *normal_cos, *depth_ratio, 0.0, 0.0, 0.0];
                let thresholds = uniform_buffer(gpu, "edge thresholds", bytemuck::cast_slice(&words));
                let [position, normal, _] = &frame.gbuffer.views;
                let group = bind_group(
                    gpu,
                    "edge mask",
                    edge_pipeline,
                    0,
                    &[
                        thresholds.as_entire_binding(),
                        wgpu::BindingResource::TextureView(position),
                        wgpu::BindingResource::TextureView(normal),
                    ],
                );
                {
                    let targets = PassTargets { colour: Some(&edges.level_views[0]), stencil: None, viewport: screen };
                    let mut pass = begin(encoder, "edges 0", targets, timer, None);
                    pass.set_pipeline(edge_pipeline);
                    pass.set_bind_group(0, &group, &[]);
                    pass.draw(0..3, 0..1);
                }
                self.record_edge_reduce(gpu, encoder, edges, edge_reduce, timer);
                let uniform = uniform_buffer(gpu, "content lod", bytemuck::cast_slice(&[top, 0, 0, 0]));
                let group = bind_group(
                    gpu,
                    "content lod",
                    pipeline,
                    0,
                    &[uniform.as_entire_binding(), wgpu::BindingResource::TextureView(&edges.all)],
                );
                let mut pass = begin(encoder, "lod", lod_targets(), timer, None);
                pass.set_pipeline(pipeline);
                pass.set_bind_group(0, &group, &[]);
                pass.draw(0..3, 0..1);
            }
            // Explicit LOD was uploaded before the encoder.
            _ => {}
        }
    }

    /// The LOD-present mask pyramid, one pass a level (level 0 from the LOD, coarser ones ORing
    /// the finer mask); then every level's stencil in its atlas, one pass, one draw a level.
    fn record_stencil_pyramid(&self, gpu: &Gpu, encoder: &mut wgpu::CommandEncoder, timer: &mut GpuTimer) {
        let range = uniform_buffer(gpu, "lod range", bytemuck::cast_slice(&[self.plan.top_level, 0, 0, 0]));
        let from_lod = [range.as_entire_binding(), wgpu::BindingResource::TextureView(&self.lod_view)];
        let counts = self.plan.skip_absent_levels_on_gpu.then(|| {
            bind_group(gpu, "level draws", &self.present_pipeline, 1, &[self.level_draws.as_entire_binding()])
        });
        for level in 0..self.plan.levels() as usize {
            let targets = PassTargets {
                colour: Some(&self.mask.level_views[level]),
                stencil: None,
                viewport: self.plan.level_extents[level],
            };
            let mut pass = begin(encoder, &format!("pyramid {level}"), targets, timer, None);
            if level == 0 {
                pass.set_pipeline(&self.present_pipeline);
                pass.set_bind_group(0, &bind_group(gpu, "lod present", &self.present_pipeline, 0, &from_lod), &[]);
                if let Some(counts) = &counts {
                    pass.set_bind_group(1, counts, &[]);
                }
            } else {
                let finer = wgpu::BindingResource::TextureView(&self.mask.level_views[level - 1]);
                let group = bind_group(gpu, "mask reduce", &self.mask_reduce_pipeline, 0, &[finer]);
                pass.set_pipeline(&self.mask_reduce_pipeline);
                pass.set_bind_group(0, &group, &[]);
            }
            pass.draw(0..3, 0..1);
        }
        let (Some(mark), Some(stencil)) = (&self.mark_pipeline, &self.stencil) else { return };
        let stencil_view = stencil.create_view(&Default::default());
        let targets = PassTargets {
            colour: None,
            stencil: Some((&stencil_view, wgpu::LoadOp::Clear(0))),
            viewport: self.plan.atlas.size,
        };
        let mut pass = begin(encoder, "pyramid marks", targets, timer, None);
        pass.set_pipeline(mark);
        pass.set_stencil_reference(1);
        for level in 0..self.plan.levels() as usize {
            let resources =
                [wgpu::BindingResource::TextureView(&self.mask.all), self.level_uniforms[level].as_entire_binding()];
            pass.set_bind_group(0, &bind_group(gpu, "stencil mark", mark, 0, &resources), &[]);
            set_level_viewport(&mut pass, self.plan.atlas.rect(level));
            pass.draw(0..3, 0..1);
        }
    }

    fn record_lighting(
        &self,
        gpu: &Gpu,
        encoder: &mut wgpu::CommandEncoder,
        frame: &CpsFrame,
        timer: &mut GpuTimer,
        queries: &OcclusionQueries,
    ) {
        let shading = shading_uniform(gpu, frame.eye, frame.lights.count);
        let [position, normal, albedo] = &frame.gbuffer.views;
        let inputs = bind_group(
            gpu,
            "light inputs",
            &self.light_pipeline,
            0,
            &[
                shading.as_entire_binding(),
                wgpu::BindingResource::TextureView(position),
                wgpu::BindingResource::TextureView(normal),
                wgpu::BindingResource::TextureView(albedo),
                wgpu::BindingResource::TextureView(&frame.lights.view),
            ],
        );
        let lit = self.lit.create_view(&Default::default());
        let stencil = self.stencil.as_ref().map(|stencil| stencil.create_view(&Default::default()));
        let targets = PassTargets {
            colour: Some(&lit),
            stencil: stencil.as_ref().map(|view| (view, wgpu::LoadOp::Load)),
            viewport: self.plan.atlas.size,
        };
        let mut pass = begin(encoder, "light", targets, timer, Some(queries.set()));
        pass.set_pipeline(&self.light_pipeline);
        if self.stencil.is_some() {
            pass.set_stencil_reference(1);
        }
        pass.set_bind_group(0, &inputs, &[]);
        for level in 0..self.plan.levels() as usize {
            let group = bind_group(
                gpu,
                "light level",
                &self.light_pipeline,
                1,
                &[self.level_uniforms[level].as_entire_binding()],
            );
            pass.set_bind_group(1, &group, &[]);
            set_level_viewport(&mut pass, self.plan.atlas.rect(level));
            pass.begin_occlusion_query(level as u32);
            pass.draw_indirect(&self.level_draws, 16 * level as u64);
            pass.end_occlusion_query();
        }
    }

    fn record_composite(&self, gpu: &Gpu, encoder: &mut wgpu::CommandEncoder, timer: &mut GpuTimer) {
        let (w, h) = self.plan.screen;
        let mut words = vec![self.plan.top_level, 0, w, h];
        for level in 0..9 {
            let (x, y) = self.plan.atlas.origins.get(level).copied().unwrap_or_default();
            words.extend([x, y, 0, 0]);
        }
        let uniform = uniform_buffer(gpu, "composite", bytemuck::cast_slice(&words));
        let lit = self.lit.create_view(&Default::default());
        let resources = [
            uniform.as_entire_binding(),
            wgpu::BindingResource::TextureView(&self.lod_view),
            wgpu::BindingResource::TextureView(&lit),
        ];
        let group = bind_group(gpu, "composite", &self.composite_pipeline, 0, &resources);
        let view = self.image.create_view(&Default::default());
        let targets = PassTargets { colour: Some(&view), stencil: None, viewport: self.plan.screen };
        let mut pass = begin(encoder, "composite", targets, timer, None);
        pass.set_pipeline(&self.composite_pipeline);
        pass.set_bind_group(0, &group, &[]);
        pass.draw(0..3, 0..1);
    }
}
