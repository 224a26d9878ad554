//! Checkerboard rendering of a scene's frames, and the two images it is measured against: the
//! full-resolution render of the same frame and a half-resolution render upscaled bilinearly.

use anyhow::{Result, ensure};
use serde::Serialize;

use super::deferred_full_resolution::DeferredFullResolution;
use super::frame::{BACKGROUND, CheckerboardFrame, FramePasses, TARGET_USAGE, layout_size};
use super::plan::{CheckerboardPlan, Shading};
use super::reconstruct::{Detection, Reconstruction, ReconstructionInputs};
use super::sampling::{CheckerboardPath, Orientation, check_screen, quarter_projection, quarter_size};
use super::scene::CheckerboardScene;
use super::scene_pass::{DEPTH, DrawSet, HDR, ScenePassKind, ScenePipelines, SceneResources, TextureLod};
use crate::attachments;
use crate::fullscreen::{FullscreenPipeline, bind_group, uniform_buffer};
use crate::gpu::Gpu;
use crate::query::GpuTimer;
use crate::shaders;

#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct CheckerboardConfig {
    pub screen: (u32, u32),
    pub path: CheckerboardPath,
    pub shading: Shading,
    pub detection: Detection,
    /// Texture LOD in the quarter-resolution passes.
    #[serde(skip)]
    pub lod: TextureLod,
}

impl CheckerboardConfig {
    /// Exact full-resolution LOD by gradients, CSO at its default tolerance.
    pub fn new(screen: (u32, u32), path: CheckerboardPath, shading: Shading) -> Self {
        Self { screen, path, shading, detection: Detection::DEFAULT_CSO, lod: TextureLod::Gradient(0.5) }
    }
}

/// Checks a screen for checkerboarding on this adapter: at least 2×2, and its sample layout
/// (twice the quarter height by the quarter width) within the texture limit.
pub fn check_checkerboard_screen(gpu: &Gpu, screen: (u32, u32)) -> Result<()> {
    check_screen(screen)?;
    let max = gpu.device.limits().max_texture_dimension_2d;
    let layout = layout_size(screen);
    ensure!(
        screen.0 <= max && screen.1 <= max && layout.0 <= max && layout.1 <= max,
        "checkerboard screen {}x{} needs {}x{} full-resolution and {}x{} sample-layout targets; this adapter allows {max}x{max}",
        screen.0,
        screen.1,
        screen.0,
        screen.1,
        layout.0,
        layout.1
    );
    Ok(())
}

/// One rendered frame: its GPU time, the passes it recorded and each one's time (where the
/// adapter has timestamps).
#[derive(Clone, Debug)]
pub struct RenderedFrame {
    pub gpu_ms: f64,
    pub passes: Vec<String>,
    pub pass_ms: Vec<f64>,
}

/// A checkerboard renderer for one scene: frames N and N−1 ping-pong between two targets.
pub struct Checkerboard {
    pub config: CheckerboardConfig,
    scene: CheckerboardScene,
    passes: FramePasses,
    frames: [CheckerboardFrame; 2],
    pub reconstruction: Reconstruction,
    timer: GpuTimer,
    /// The last frame rendered: the next one has history only if it follows it.
    last: Option<u32>,
}

impl Checkerboard {
    pub fn new(gpu: &Gpu, scene: &CheckerboardScene, config: CheckerboardConfig) -> Result<Self> {
        check_checkerboard_screen(gpu, config.screen)?;
        let plan = CheckerboardPlan::new(scene, config.path, config.shading);
        let passes = FramePasses::new(gpu, scene, config.screen, plan, config.lod)?;
        let frames = [passes.frame_targets(gpu), passes.frame_targets(gpu)];
        let reconstruction = Reconstruction::new(gpu, config.screen, &passes.plan, config.detection)?;
        Ok(Self {
            config,
            scene: scene.clone(),
            passes,
            frames,
            reconstruction,
            timer: GpuTimer::new(gpu, 16),
            last: None,
        })
    }

    /// The same renderer, its reconstruction also writing the motion each pixel used.
    pub fn showing_motion(mut self, gpu: &Gpu) -> Result<Self> {
        self.reconstruction =
            Reconstruction::showing_motion(gpu, self.config.screen, &self.passes.plan, self.config.detection)?;
        Ok(self)
    }

    pub fn plan(&self) -> &CheckerboardPlan {
        &self.passes.plan
    }

    /// Frame `index`'s samples (N when it was the last rendered, N−1 the one before).
    pub fn frame(&self, index: u32) -> &CheckerboardFrame {
        &self.frames[(index % 2) as usize]
    }

    /// Renders and reconstructs frame `index` (jitter phase index mod 2); frame index − 1 is its
    /// history when it was the frame rendered last.
    pub fn render(&mut self, gpu: &Gpu, index: u32) -> Result<RenderedFrame> {
        let view = self.scene.frame_view(index, self.config.screen);
        let phase = index % 2;
        let has_history = index > 0 && self.last == Some(index - 1);
        let (current, previous) = {
            let [a, b] = &self.frames;
            if phase == 0 { (a, b) } else { (b, a) }
        };
        gpu.scoped("checkerboard frame", || {
            let mut encoder = gpu.encoder("checkerboard frame");
            self.passes.record(gpu, &mut encoder, &mut self.timer, &view, phase, current);
            let inputs = ReconstructionInputs {
                current,
                previous: has_history.then_some(previous),
                view: &view,
                phase,
                near_far: (self.scene.camera.near, self.scene.camera.far),
            };
            self.reconstruction.record(gpu, &mut encoder, &mut self.timer, &inputs);
            self.timer.resolve(&mut encoder);
            gpu.submit(encoder);
            Ok(())
        })?;
        self.last = Some(index);
        // The passes the frame recorded: without timestamps they go untimed (`pass_ms` empty),
        // not unlisted.
        let passes = self.timer.recorded().to_vec();
        let times = self.timer.read(gpu)?;
        Ok(RenderedFrame {
            gpu_ms: times.iter().map(|t| t.ms).sum(),
            pass_ms: times.iter().map(|t| t.ms).collect(),
            passes,
        })
    }
}

/// The scene rendered in one pass at some resolution and projection (forward, single-sampled).
struct ForwardImage {
    pipelines: ScenePipelines,
    resources: SceneResources,
    scene: CheckerboardScene,
    colour: wgpu::Texture,
    depth: wgpu::Texture,
    timer: GpuTimer,
}

impl ForwardImage {
    /// Targets of `size` (width, height as the target holds them).
    fn new(gpu: &Gpu, scene: &CheckerboardScene, size: (u32, u32)) -> Result<Self> {
        let pipelines = ScenePipelines::new(gpu, 1);
        let resources = SceneResources::new(gpu, &pipelines, scene, 1)?;
        Ok(Self {
            resources,
            pipelines,
            scene: scene.clone(),
            colour: gpu.texture("forward image", size, HDR, 1, TARGET_USAGE),
            depth: gpu.texture("forward image depth", size, DEPTH, 1, TARGET_USAGE),
            timer: GpuTimer::new(gpu, 2),
        })
    }

    /// Records frame `index` through `to_target` (applied after the full-resolution
    /// view-projection of `screen`).
    fn record(
        &mut self,
        gpu: &Gpu,
        encoder: &mut wgpu::CommandEncoder,
        index: u32,
        screen: (u32, u32),
        to_target: glam::Mat4,
        lod: TextureLod,
    ) {
        let view = self.scene.frame_view(index, screen);
        self.resources.write_view(gpu, 0, to_target * view.full_from_world, &view, screen, lod);
        self.resources.write_objects(gpu, &view);
        let (colour, depth) =
            (self.colour.create_view(&Default::default()), self.depth.create_view(&Default::default()));
        let mut pass = encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
            label: Some("scene"),
            color_attachments: &[attachments::colour(&colour, None, BACKGROUND)],
            depth_stencil_attachment: Some(wgpu::RenderPassDepthStencilAttachment {
                view: &depth,
                depth_ops: Some(wgpu::Operations { load: wgpu::LoadOp::Clear(1.0), store: wgpu::StoreOp::Store }),
                stencil_ops: None,
            }),
            timestamp_writes: self.timer.pass("scene"),
            ..Default::default()
        });
        self.resources.draw(&mut pass, &self.pipelines, ScenePassKind::Forward, DrawSet::Opaque, 0);
        if self.resources.has(DrawSet::Transparent) {
            self.resources.draw(&mut pass, &self.pipelines, ScenePassKind::Forward, DrawSet::Transparent, 0);
        }
    }
}

/// The pass that turns a turned frame upright.
struct TurnBack {
    pipeline: wgpu::RenderPipeline,
    upright: wgpu::Texture,
}

impl TurnBack {
    fn new(gpu: &Gpu, screen: (u32, u32)) -> Self {
        let pipeline = FullscreenPipeline {
            label: "turn back",
            fragment: shaders::CBR_TURN_BACK,
            entry_point: "fs_turn_back",
            targets: &[Some(HDR.into())],
            depth_stencil: None,
            samples: 1,
        }
        .create(gpu);
        Self { pipeline, upright: gpu.texture("full resolution turned back", screen, HDR, 1, TARGET_USAGE) }
    }

    fn record(&self, gpu: &Gpu, encoder: &mut wgpu::CommandEncoder, timer: &mut GpuTimer, turned: &wgpu::Texture) {
        let source = turned.create_view(&Default::default());
        let group = bind_group(gpu, "turn back", &self.pipeline, 0, &[wgpu::BindingResource::TextureView(&source)]);
        let target = self.upright.create_view(&Default::default());
        let mut pass = encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
            label: Some("turn back"),
            color_attachments: &[attachments::colour(&target, None, wgpu::Color::TRANSPARENT)],
            timestamp_writes: timer.pass("turn back"),
            ..Default::default()
        });
        pass.set_pipeline(&self.pipeline);
        pass.set_bind_group(0, &group, &[]);
        pass.draw(0..3, 0..1);
    }
}

/// The reference: every pixel of the frame shaded at full resolution — forward (the image the
/// cases measure against), or deferred (the timing baseline of deferred checkerboarding).
pub struct FullResolutionScene {
    image: FullResolutionImage,
    screen: (u32, u32),
    orientation: Orientation,
    /// Where the frame is rasterised turned.
    turn_back: Option<TurnBack>,
}

enum FullResolutionImage {
    Forward(Box<ForwardImage>),
    Deferred(Box<DeferredFullResolution>),
}

impl FullResolutionScene {
    /// Forward full resolution, upright.
    pub fn new(gpu: &Gpu, scene: &CheckerboardScene, screen: (u32, u32)) -> Result<Self> {
        Self::shaded(gpu, scene, screen, Shading::Forward, Orientation::Upright)
    }

    /// Full resolution shaded the way `shading` says, rasterised in `orientation`.
    pub fn shaded(
        gpu: &Gpu,
        scene: &CheckerboardScene,
        screen: (u32, u32),
        shading: Shading,
        orientation: Orientation,
    ) -> Result<Self> {
        crate::deferred::gbuffer::check_size(gpu, screen)?;
        let image = match shading {
            Shading::Forward => {
                FullResolutionImage::Forward(Box::new(ForwardImage::new(gpu, scene, orientation.target_size(screen))?))
            }
            Shading::Deferred => {
                FullResolutionImage::Deferred(Box::new(DeferredFullResolution::new(gpu, scene, screen, orientation)?))
            }
        };
        let turn_back = (orientation == Orientation::Turned).then(|| TurnBack::new(gpu, screen));
        Ok(Self { image, screen, orientation, turn_back })
    }

    /// The deferred image's targets as rasterised (turned where the frame is).
    pub fn deferred(&self) -> Option<&DeferredFullResolution> {
        match &self.image {
            FullResolutionImage::Deferred(image) => Some(image),
            FullResolutionImage::Forward(_) => None,
        }
    }

    /// The upright frame.
    pub fn output(&self) -> &wgpu::Texture {
        match (&self.turn_back, &self.image) {
            (Some(turn_back), _) => &turn_back.upright,
            (None, FullResolutionImage::Forward(image)) => &image.colour,
            (None, FullResolutionImage::Deferred(image)) => &image.colour,
        }
    }

    /// Renders frame `index`; its GPU time.
    pub fn render(&mut self, gpu: &Gpu, index: u32) -> Result<f64> {
        let screen = self.screen;
        let to_target = self.orientation.clip_transform();
        let turn_back = &self.turn_back;
        let timer = gpu.scoped("full-resolution frame", || {
            let mut encoder = gpu.encoder("full-resolution frame");
            let (timer, rasterised) = match &mut self.image {
                FullResolutionImage::Forward(image) => {
                    image.record(gpu, &mut encoder, index, screen, to_target, TextureLod::Bias(0.0));
                    (&mut image.timer, &image.colour)
                }
                FullResolutionImage::Deferred(image) => {
                    image.record(gpu, &mut encoder, index);
                    (&mut image.timer, &image.colour)
                }
            };
            if let Some(turn_back) = turn_back {
                turn_back.record(gpu, &mut encoder, timer, rasterised);
            }
            timer.resolve(&mut encoder);
            gpu.submit(encoder);
            Ok(timer)
        })?;
        Ok(timer.read(gpu)?.iter().map(|t| t.ms).sum())
    }
}

/// The baseline: one sample per 2×2 pixels (quarter resolution), upscaled bilinearly.
pub struct HalfResolutionUpscale {
    image: ForwardImage,
    screen: (u32, u32),
    pipeline: wgpu::RenderPipeline,
    sampler: wgpu::Sampler,
    pub output: wgpu::Texture,
}

impl HalfResolutionUpscale {
    pub fn new(gpu: &Gpu, scene: &CheckerboardScene, screen: (u32, u32)) -> Result<Self> {
        check_checkerboard_screen(gpu, screen)?;
        let pipeline = FullscreenPipeline {
            label: "bilinear upscale",
            fragment: shaders::CBR_UPSCALE,
            entry_point: "fs_upscale",
            targets: &[Some(HDR.into())],
            depth_stencil: None,
            samples: 1,
        }
        .create(gpu);
        let sampler = gpu.device.create_sampler(&wgpu::SamplerDescriptor {
            label: Some("bilinear"),
            mag_filter: wgpu::FilterMode::Linear,
            min_filter: wgpu::FilterMode::Linear,
            ..Default::default()
        });
        Ok(Self {
            image: ForwardImage::new(gpu, scene, quarter_size(screen))?,
            screen,
            pipeline,
            sampler,
            output: gpu.texture("upscaled", screen, HDR, 1, TARGET_USAGE),
        })
    }

    /// The quarter-resolution image the upscale reads (`cbr.upscale.bilinear`).
    pub fn quarter_image(&self) -> &wgpu::Texture {
        &self.image.colour
    }

    /// Renders frame `index` at quarter resolution and upscales it; the GPU time of both.
    pub fn render(&mut self, gpu: &Gpu, index: u32) -> Result<f64> {
        let quarter = quarter_size(self.screen);
        let uniform = uniform_buffer(
            gpu,
            "upscale",
            bytemuck::cast_slice(&[self.screen.0 as f32, self.screen.1 as f32, quarter.0 as f32, quarter.1 as f32]),
        );
        gpu.scoped("half-resolution frame", || {
            let mut encoder = gpu.encoder("half-resolution frame");
            let to_quarter = quarter_projection(self.screen, 0, [0.0, 0.0]);
            self.image.record(gpu, &mut encoder, index, self.screen, to_quarter, TextureLod::Bias(0.0));
            let source = self.image.colour.create_view(&Default::default());
            let group = bind_group(
                gpu,
                "upscale",
                &self.pipeline,
                0,
                &[
                    uniform.as_entire_binding(),
                    wgpu::BindingResource::TextureView(&source),
                    wgpu::BindingResource::Sampler(&self.sampler),
                ],
            );
            let target = self.output.create_view(&Default::default());
            {
                let mut pass = encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
                    label: Some("bilinear upscale"),
                    color_attachments: &[attachments::colour(&target, None, wgpu::Color::TRANSPARENT)],
                    timestamp_writes: self.image.timer.pass("upscale"),
                    ..Default::default()
                });
                pass.set_pipeline(&self.pipeline);
                pass.set_bind_group(0, &group, &[]);
                pass.draw(0..3, 0..1);
            }
            self.image.timer.resolve(&mut encoder);
            gpu.submit(encoder);
            Ok(())
        })?;
        Ok(self.image.timer.read(gpu)?.iter().map(|t| t.ms).sum())
    }
}
