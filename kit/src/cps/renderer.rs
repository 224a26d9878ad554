//! The CPS frame: LOD buffer and level 0 of the LOD-present mask (one pass) → the mask's even
//! coarser levels (one pass each) — neither under the foveated policy, whose passes compute a
//! pixel's level where they need it → one pass that marks every level's stencil, side by side in
//! one atlas (one draw a level; under the foveated policy one instanced draw for all), then lights
//! every level behind stencil Equal (one draw a level, its viewport the level's rect; under the
//! foveated policy the rects of its spans, cps/level_spans.rs) → composite.
//! Targets and pipelines are made once per renderer; `render` records one frame in one encoder
//! with a timestamp pair around every pass and an occlusion query around every level's lighting
//! draw.

use anyhow::{Context, Result};
use glam::Vec3;

use super::config::{CpsConfig, LodPolicy};
use super::level_spans::{LevelSpans, SpanBatch};
use super::plan::Plan;
use super::reference::Level;
use super::stencil_marks::{MarkSource, StencilMarks, foveated_blocks};
use super::targets::OrPyramid;
use crate::deferred::gbuffer::Gbuffer;
use crate::deferred::lighting::{HDR, shading_uniform};
use crate::deferred::lights::LightTexture;
use crate::fullscreen::{FullscreenPipeline, bind_group, bind_group_at, uniform_buffer};
use crate::gpu::Gpu;
use crate::query::{GpuTimer, OcclusionQueries, PassTime};
use crate::rects::{RectFragment, RectPipeline, stencil_state};
use crate::shaders;

const LOD: wgpu::TextureFormat = wgpu::TextureFormat::R8Uint;
const MASK: wgpu::TextureFormat = OrPyramid::FORMAT;
pub(super) const STENCIL: wgpu::TextureFormat = wgpu::TextureFormat::Stencil8;

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
        self.pass_times.iter().filter(|t| t.label.starts_with(prefix)).fold(0.0, |sum, t| sum + t.ms)
    }
}

fn target_usage() -> wgpu::TextureUsages {
    wgpu::TextureUsages::RENDER_ATTACHMENT | wgpu::TextureUsages::TEXTURE_BINDING | wgpu::TextureUsages::COPY_SRC
}

/// Colour and stencil attachments of one pass; `viewport` limits drawing to the texels in use.
struct PassTargets<'a> {
    colours: &'a [&'a wgpu::TextureView],
    /// Keep the colours' contents instead of clearing them (only what the pass writes is read).
    keep_colours: bool,
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
    let load = if targets.keep_colours { wgpu::LoadOp::Load } else { wgpu::LoadOp::Clear(wgpu::Color::TRANSPARENT) };
    let colours: Vec<_> = targets
        .colours
        .iter()
        .map(|view| {
            Some(wgpu::RenderPassColorAttachment {
                view,
                depth_slice: None,
                resolve_target: None,
                ops: wgpu::Operations { load, store: wgpu::StoreOp::Store },
            })
        })
        .collect();
    let mut pass = encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
        label: Some(label),
        color_attachments: &colours,
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

/// How each level's full-screen triangle is drawn; a level's marks and its lighting share it.
pub(crate) enum LevelDraws {
    /// Directly, one instance a level: every level is drawn and its stencil rejects what it need
    /// not shade. Coarse pixel shading needs nothing more (an adapter without indirect draws —
    /// GLES 3.0, WebGL2 — runs the technique this way).
    Direct,
    /// From arguments (four `u32` words a level) that the LOD pass counts into this buffer
    /// (`Plan::skip_absent_levels_on_gpu`): zero instances for a level no pixel uses.
    Counted(wgpu::Buffer),
}

impl LevelDraws {
    pub(super) fn draw(&self, pass: &mut wgpu::RenderPass<'_>, level: usize) {
        match self {
            Self::Direct => pass.draw(0..3, 0..1),
            Self::Counted(arguments) => pass.draw_indirect(arguments, 16 * level as u64),
        }
    }
}

pub struct CpsRenderer {
    pub config: CpsConfig,
    pub plan: Plan,
    /// LOD per pixel (`R8Uint`; the screen's pixels of a texture as large as the mask pyramid's
    /// base, which the LOD pass writes beside it). Where the levels come from the foveation, no
    /// frame writes it: `read_lod` renders it on request.
    pub lod: wgpu::Texture,
    lod_view: wgpu::TextureView,
    /// OR-reduced edge flags (content policy only).
    pub edges: Option<OrPyramid>,
    /// OR-reduced LOD-present bits: bit l of mip l texel q = some pixel of q's block has LOD l;
    /// only the even mips are built (an odd level's marks OR four texels of the mip below).
    /// Absent where the levels come from the foveation.
    pub mask: Option<OrPyramid>,
    /// Every level's stencil, side by side (absent for the naive comparison).
    pub stencil: Option<wgpu::Texture>,
    /// Every lit level, side by side; alpha 1 marks a shaded texel. Not cleared between frames:
    /// a texel holds the last shading it got (the frame's stencil says which it shaded).
    pub lit: wgpu::Texture,
    /// The composite (`Rgba16Float`, screen-sized).
    pub image: wgpu::Texture,
    /// How each level's marks and lighting are drawn.
    pub(crate) level_draws: LevelDraws,
    /// The LOD buffer and mask level 0 from the policy, or (the caller's own LOD) mask level 0
    /// from the LOD buffer, or (levels from the foveation) the LOD buffer alone.
    lod_pipeline: wgpu::RenderPipeline,
    /// Edge detection (content policy only).
    edge_pipeline: Option<wgpu::RenderPipeline>,
    /// Stencil marks, drawn at the start of the lighting pass.
    marks: Option<StencilMarks>,
    /// Where the levels come from the foveation (with a stencil pyramid), each level's lighting
    /// draws its spans, not its whole bounds (cps/level_spans.rs).
    light_spans: Option<SpanBatch>,
    /// Each level's group 1 of the lighting.
    light_level_groups: Vec<wgpu::BindGroup>,
    /// A full-screen triangle a level, or a rect a span.
    light_pipeline: wgpu::RenderPipeline,
    composite_pipeline: wgpu::RenderPipeline,
}

impl CpsRenderer {
    pub fn new(gpu: &Gpu, screen: (u32, u32), config: CpsConfig) -> Result<Self> {
        let plan = Plan::new(gpu, screen, &config)?;
        let levels = plan.levels();
        let atlas = &plan.atlas;
        let lod = gpu.texture("lod", plan.padded, LOD, 1, target_usage() | wgpu::TextureUsages::COPY_DST);
        let fullscreen =
            |label: &'static str, fragment, entry_point: &str, format: Option<wgpu::TextureFormat>, depth_stencil| {
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
        let counted = if plan.skip_absent_levels_on_gpu { "_counted" } else { "" };
        let lod_and_mask = |label, policy: &str| {
            FullscreenPipeline {
                label,
                fragment: shaders::CPS_LOD,
                entry_point: &format!("fs_lod_{policy}{counted}"),
                targets: &[Some(LOD.into()), Some(MASK.into())],
                depth_stencil: None,
                samples: 1,
            }
            .create(gpu)
        };
        let (lod_pipeline, edge_pipeline) = match &config.policy {
            LodPolicy::Foveated { .. } if plan.levels_from_foveation => {
                (fullscreen("foveated lod", shaders::CPS_LOD, "fs_lod_foveated_alone", Some(LOD), None), None)
            }
            LodPolicy::Foveated { .. } => (lod_and_mask("foveated lod", "foveated"), None),
            LodPolicy::Content { .. } => (
                lod_and_mask("content lod", "content"),
                Some(fullscreen("edge mask", shaders::CPS_EDGE_MASK, "fs_edge_mask", Some(MASK), None)),
            ),
            LodPolicy::Explicit(_) => (
                fullscreen("lod present", shaders::CPS_LOD, &format!("fs_lod_present{counted}"), Some(MASK), None),
                None,
            ),
        };
        let pyramid = |label, step| OrPyramid::new(gpu, label, plan.padded, levels, step, target_usage());
        let mask = (!plan.levels_from_foveation).then(|| pyramid("lod-present pyramid", 2));
        let level_uniforms: Vec<wgpu::Buffer> = (0..levels as usize)
            .map(|level| {
                let (x, y) = atlas.origins[level];
                uniform_buffer(gpu, "level", bytemuck::cast_slice(&[level as u32, x, y, 0]))
            })
            .collect();
        let foveated = (plan.stencil_pyramid && plan.levels_from_foveation).then(|| {
            (
                foveated_blocks(gpu, &plan, &config.policy),
                LevelSpans::foveated(&plan, &config.policy).batch(gpu, atlas.size),
            )
        });
        let marks = plan.stencil_pyramid.then(|| {
            let source = match (&mask, &foveated) {
                (Some(mask), _) => MarkSource::Pyramid(&mask.chain),
                (None, Some((blocks, spans))) => MarkSource::Foveation(blocks, spans),
                (None, None) => {
                    unreachable!("a stencil pyramid without a mask pyramid has its levels from the foveation")
                }
            };
            StencilMarks::new(gpu, source, &level_uniforms)
        });
        let lit_where_marked = plan
            .stencil_pyramid
            .then(|| stencil_state(STENCIL, wgpu::CompareFunction::Equal, wgpu::StencilOperation::Keep));
        let light_pipeline = match &foveated {
            Some(_) => RectPipeline {
                colour_format: Some(HDR),
                fragment: RectFragment::Shader { file: shaders::CPS_LIGHTING, entry: "fs_light_level_foveated" },
                depth_stencil: lit_where_marked,
                ..RectPipeline::new("light level spans")
            }
            .create(gpu),
            None => fullscreen("light level", shaders::CPS_LIGHTING, "fs_light_level", Some(HDR), lit_where_marked),
        };
        // Under the foveated policy each level's group also holds the blocks' uniform.
        let light_level_groups = level_uniforms
            .iter()
            .map(|uniform| {
                let mut resources = vec![(0, uniform.as_entire_binding())];
                resources.extend(foveated.as_ref().map(|(blocks, _)| (1, blocks.as_entire_binding())));
                bind_group_at(gpu, "light level", &light_pipeline, 1, &resources)
            })
            .collect();
        let light_spans = foveated.map(|(_, spans)| spans);
        // An indirect buffer only where the GPU counts the levels: wgpu refuses one without
        // indirect execution.
        let level_draws = match plan.skip_absent_levels_on_gpu {
            true => LevelDraws::Counted(gpu.device.create_buffer(&wgpu::BufferDescriptor {
                label: Some("level draws"),
                size: 16 * 9,
                usage: wgpu::BufferUsages::STORAGE
                    | wgpu::BufferUsages::INDIRECT
                    | wgpu::BufferUsages::COPY_DST
                    | wgpu::BufferUsages::COPY_SRC,
                mapped_at_creation: false,
            })),
            false => LevelDraws::Direct,
        };
        Ok(Self {
            lod_view: lod.create_view(&Default::default()),
            lod,
            edges: plan.edge_pyramid.then(|| pyramid("edge pyramid", 1)),
            mask,
            stencil: plan.stencil_pyramid.then(|| gpu.texture("stencil atlas", atlas.size, STENCIL, 1, target_usage())),
            // Written by copies too: a case composites known shading (`composite_levels`).
            lit: gpu.texture("lit atlas", atlas.size, HDR, 1, target_usage() | wgpu::TextureUsages::COPY_DST),
            image: gpu.texture("cps composite", screen, HDR, 1, target_usage()),
            level_draws,
            lod_pipeline,
            edge_pipeline,
            marks,
            light_spans,
            light_level_groups,
            light_pipeline,
            composite_pipeline: FullscreenPipeline {
                label: "composite",
                fragment: shaders::CPS_COMPOSITE,
                entry_point: config.composite.entry_point(),
                targets: &[Some(HDR.into())],
                depth_stencil: None,
                samples: 1,
            }
            .create_specialised(gpu, &[("foveated", f64::from(u8::from(plan.levels_from_foveation)))]),
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
        // Counted from zero instances where a level is a full-screen triangle (the LOD pass adds
        // one where a pixel uses the level).
        if let (None, LevelDraws::Counted(arguments)) = (&self.light_spans, &self.level_draws) {
            let draws: Vec<[u32; 4]> = (0..9).map(|_| [3, 0, 0, 0]).collect();
            gpu.queue.write_buffer(arguments, 0, bytemuck::cast_slice(&draws));
        }
        if let LodPolicy::Explicit(values) = &self.config.policy {
            gpu.queue.write_texture(
                self.lod.as_image_copy(),
                values,
                wgpu::TexelCopyBufferLayout {
                    offset: 0,
                    bytes_per_row: Some(self.plan.screen.0),
                    rows_per_image: None,
                },
                wgpu::Extent3d { width: self.plan.screen.0, height: self.plan.screen.1, depth_or_array_layers: 1 },
            );
        }
        let mut encoder = gpu.encoder("cps frame");
        if !self.plan.levels_from_foveation {
            self.record_lod(gpu, &mut encoder, frame, &mut timer);
        }
        self.record_mask_pyramid(gpu, &mut encoder, &mut timer);
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

    /// Reduces `pyramid` upwards, one pass (labelled `label` and the mip) a reduced mip: texel q
    /// ORs its children in the mip `step` below.
    fn record_or_reduce(
        &self,
        gpu: &Gpu,
        encoder: &mut wgpu::CommandEncoder,
        pyramid: &OrPyramid,
        label: &str,
        timer: &mut GpuTimer,
    ) {
        let (chain, pipeline, step) = (&pyramid.chain, &pyramid.reduce, pyramid.step);
        for level in (step..self.plan.levels() as usize).step_by(step) {
            let finer = wgpu::BindingResource::TextureView(&chain.level_views[level - step]);
            let group = bind_group(gpu, label, pipeline, 0, &[finer]);
            let targets = PassTargets {
                colours: &[&chain.level_views[level]],
                keep_colours: false,
                stencil: None,
                viewport: self.plan.level_extents[level],
            };
            let mut pass = begin(encoder, &format!("{label} {level}"), targets, timer, None);
            pass.set_pipeline(pipeline);
            pass.set_bind_group(0, &group, &[]);
            pass.draw(0..3, 0..1);
        }
    }

    /// The LOD buffer and mask level 0 in one pass (the content policy's edge pyramid first), or
    /// for the caller's own LOD, uploaded before the encoder, mask level 0 from it.
    fn record_lod(&self, gpu: &Gpu, encoder: &mut wgpu::CommandEncoder, frame: &CpsFrame, timer: &mut GpuTimer) {
        let edges = match (&self.config.policy, &self.edges) {
            (LodPolicy::Content { normal_cos, depth_ratio }, Some(edges)) => {
                self.record_edges(gpu, encoder, frame, edges, (*normal_cos, *depth_ratio), timer);
                Some(edges)
            }
            _ => None,
        };
        self.record_lod_pass(gpu, encoder, edges, timer);
    }

    /// The LOD buffer alone where the frame computes the foveated levels itself: for a reader
    /// of the LOD (`read_lod`), outside the frame.
    pub(crate) fn render_foveated_lod(&self, gpu: &Gpu) -> Result<()> {
        let mut timer = GpuTimer::new(gpu, 1);
        let mut encoder = gpu.encoder("cps lod");
        self.record_lod_pass(gpu, &mut encoder, None, &mut timer);
        timer.resolve(&mut encoder);
        gpu.submit(encoder);
        timer.read(gpu).map(drop)
    }

    /// The LOD pass itself, reading the content policy's `edges` where given.
    fn record_lod_pass(
        &self,
        gpu: &Gpu,
        encoder: &mut wgpu::CommandEncoder,
        edges: Option<&OrPyramid>,
        timer: &mut GpuTimer,
    ) {
        let screen = self.plan.screen;
        let mut words = self.config.policy.foveation_words(screen, self.plan.top_level).to_vec();
        words.extend([self.plan.top_level, 0, 0, 0]);
        let parameters = uniform_buffer(gpu, "lod parameters", bytemuck::cast_slice(&words));
        let mut resources = vec![(0, parameters.as_entire_binding())];
        if let Some(edges) = edges {
            resources.push((1, wgpu::BindingResource::TextureView(&edges.chain.all)));
        }
        if let LodPolicy::Explicit(_) = self.config.policy {
            resources.push((2, wgpu::BindingResource::TextureView(&self.lod_view)));
        }
        let group = bind_group_at(gpu, "lod", &self.lod_pipeline, 0, &resources);
        let counts = match &self.level_draws {
            LevelDraws::Counted(arguments) => {
                Some(bind_group(gpu, "level draws", &self.lod_pipeline, 1, &[arguments.as_entire_binding()]))
            }
            LevelDraws::Direct => None,
        };
        let written: Vec<&wgpu::TextureView> = match (&self.mask, &self.config.policy) {
            (None, _) => vec![&self.lod_view],
            (Some(mask), LodPolicy::Explicit(_)) => vec![&mask.chain.level_views[0]],
            (Some(mask), _) => vec![&self.lod_view, &mask.chain.level_views[0]],
        };
        let mut pass = begin(
            encoder,
            "lod",
            PassTargets { keep_colours: false, colours: &written, stencil: None, viewport: screen },
            timer,
            None,
        );
        pass.set_pipeline(&self.lod_pipeline);
        pass.set_bind_group(0, &group, &[]);
        if let Some(counts) = &counts {
            pass.set_bind_group(1, counts, &[]);
        }
        pass.draw(0..3, 0..1);
    }

    /// The content policy's edge flags and their OR-reduced pyramid.
    fn record_edges(
        &self,
        gpu: &Gpu,
        encoder: &mut wgpu::CommandEncoder,
        frame: &CpsFrame,
        edges: &OrPyramid,
        (normal_cos, depth_ratio): (f32, f32),
        timer: &mut GpuTimer,
    ) {
        let edge_pipeline = self.edge_pipeline.as_ref().expect("planned with the edge pyramid");
        let words = [frame.eye.x, frame.eye.y, frame.eye.z, normal_cos, depth_ratio, 0.0, 0.0, 0.0];
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
            let targets = PassTargets {
                keep_colours: false,
                colours: &[&edges.chain.level_views[0]],
                stencil: None,
                viewport: self.plan.screen,
            };
            let mut pass = begin(encoder, "edges 0", targets, timer, None);
            pass.set_pipeline(edge_pipeline);
            pass.set_bind_group(0, &group, &[]);
            pass.draw(0..3, 0..1);
        }
        self.record_or_reduce(gpu, encoder, edges, "edges", timer);
    }

    /// The LOD-present mask's even coarser levels, one pass each (ORing the even one below), where
    /// the stencil marks read them.
    fn record_mask_pyramid(&self, gpu: &Gpu, encoder: &mut wgpu::CommandEncoder, timer: &mut GpuTimer) {
        if let (true, Some(mask)) = (self.plan.stencil_pyramid, &self.mask) {
            self.record_or_reduce(gpu, encoder, mask, "pyramid", timer);
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
        // The lit atlas is not cleared: a texel keeps its last shading until shaded again, and
        // the composite reads only texels the frame's stencil let the lighting shade.
        let targets = PassTargets {
            colours: &[&lit],
            keep_colours: true,
            stencil: stencil.as_ref().map(|view| (view, wgpu::LoadOp::Clear(0))),
            viewport: self.plan.atlas.size,
        };
        let mut pass = begin(encoder, "light", targets, timer, Some(queries.set()));
        // The marks first: draws of one pass see the stencil earlier draws wrote.
        if let Some(marks) = &self.marks {
            marks.record(&mut pass, &self.plan, &self.level_draws);
            // Lit where marked: stencil Equal 1.
            pass.set_stencil_reference(1);
        }
        pass.set_pipeline(&self.light_pipeline);
        pass.set_bind_group(0, &inputs, &[]);
        for level in 0..self.plan.levels() as usize {
            pass.set_bind_group(1, &self.light_level_groups[level], &[]);
            pass.begin_occlusion_query(level as u32);
            match &self.light_spans {
                Some(spans) => {
                    self.plan.set_atlas_viewport(&mut pass, level);
                    spans.draw_level(&mut pass, level);
                }
                None => {
                    self.plan.set_level_viewport(&mut pass, level);
                    self.level_draws.draw(&mut pass, level);
                }
            }
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
        words.extend(self.config.policy.foveation_words(self.plan.screen, self.plan.top_level));
        let uniform = uniform_buffer(gpu, "composite", bytemuck::cast_slice(&words));
        let lit = self.lit.create_view(&Default::default());
        let resources = [
            uniform.as_entire_binding(),
            wgpu::BindingResource::TextureView(&self.lod_view),
            wgpu::BindingResource::TextureView(&lit),
        ];
        let group = bind_group(gpu, "composite", &self.composite_pipeline, 0, &resources);
        let view = self.image.create_view(&Default::default());
        // Every pixel is written: nothing to clear.
        let targets = PassTargets { keep_colours: true, colours: &[&view], stencil: None, viewport: self.plan.screen };
        let mut pass = begin(encoder, "composite", targets, timer, None);
        pass.set_pipeline(&self.composite_pipeline);
        pass.set_bind_group(0, &group, &[]);
        pass.draw(0..3, 0..1);
    }
}
