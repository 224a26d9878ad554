//! The scene deferred at full resolution: a G-buffer of every pixel, every pixel shaded by the
//! checkerboard's own lighting, transparents forward on top. The baseline deferred
//! checkerboarding is timed against — the same work but for the pixels checkerboarding leaves
//! out (forward full resolution also shades overdraw, which deferred shading removes, so it would
//! credit checkerboarding with a saving that is not its own). Rasterised upright, or turned a
//! quarter (`QUARTER_TURN`, every target H wide and W tall) as the offset passes draw their views.

use anyhow::Result;

use super::frame::{BACKGROUND, TARGET_USAGE, shading_uniform};
use super::sampling::Orientation;
use super::scene::CheckerboardScene;
use super::scene_pass::{
    ALBEDO, DEPTH, DrawSet, HDR, NORMAL, ScenePassKind, ScenePipelines, SceneResources, TextureLod,
};
use crate::attachments;
use crate::fullscreen::{FullscreenPipeline, bind_group};
use crate::gpu::Gpu;
use crate::query::GpuTimer;
use crate::shaders;

pub struct DeferredFullResolution {
    pipelines: ScenePipelines,
    resources: SceneResources,
    scene: CheckerboardScene,
    screen: (u32, u32),
    orientation: Orientation,
    /// Normal + shininess, albedo + specular weight (read by `cbr.deferred_full_resolution`).
    pub gbuffer: [wgpu::Texture; 2],
    pub depth: wgpu::Texture,
    pub colour: wgpu::Texture,
    shade: wgpu::RenderPipeline,
    pub timer: GpuTimer,
}

fn view(texture: &wgpu::Texture) -> wgpu::TextureView {
    texture.create_view(&Default::default())
}

impl DeferredFullResolution {
    pub fn new(gpu: &Gpu, scene: &CheckerboardScene, screen: (u32, u32), orientation: Orientation) -> Result<Self> {
        let pipelines = ScenePipelines::new(gpu, 1);
        let resources = SceneResources::new(gpu, &pipelines, scene, 1)?;
        let shade = FullscreenPipeline {
            label: "shade full resolution",
            fragment: shaders::CBR_SHADE_SAMPLES,
            entry_point: match orientation {
                Orientation::Upright => "fs_shade_full_resolution",
                Orientation::Turned => "fs_shade_full_resolution_turned",
            },
            targets: &[Some(HDR.into())],
            depth_stencil: None,
            samples: 1,
        }
        .create(gpu);
        let target = orientation.target_size(screen);
        Ok(Self {
            gbuffer: [
                gpu.texture("full-resolution gbuffer normal", target, NORMAL, 1, TARGET_USAGE),
                gpu.texture("full-resolution gbuffer albedo", target, ALBEDO, 1, TARGET_USAGE),
            ],
            depth: gpu.texture("full-resolution depth", target, DEPTH, 1, TARGET_USAGE),
            colour: gpu.texture("deferred full resolution", target, HDR, 1, TARGET_USAGE),
            pipelines,
            resources,
            scene: scene.clone(),
            screen,
            orientation,
            shade,
            timer: GpuTimer::new(gpu, 4),
        })
    }

    /// Records frame `index`: G-buffer, shading, transparents.
    pub fn record(&mut self, gpu: &Gpu, encoder: &mut wgpu::CommandEncoder, index: u32) {
        let frame = self.scene.frame_view(index, self.screen);
        let clip = self.orientation.clip_transform() * frame.full_from_world;
        self.resources.write_view(gpu, 0, clip, &frame, self.screen, TextureLod::Bias(0.0));
        self.resources.write_objects(gpu, &frame);
        let (gbuffer, depth) = (self.gbuffer.each_ref().map(view), view(&self.depth));
        let clear = wgpu::Color::TRANSPARENT;
        {
            let mut pass = encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
                label: Some("gbuffer"),
                color_attachments: &[
                    attachments::colour(&gbuffer[0], None, clear),
                    attachments::colour(&gbuffer[1], None, clear),
                ],
                depth_stencil_attachment: Some(wgpu::RenderPassDepthStencilAttachment {
                    view: &depth,
                    depth_ops: Some(wgpu::Operations { load: wgpu::LoadOp::Clear(1.0), store: wgpu::StoreOp::Store }),
                    stencil_ops: None,
                }),
                timestamp_writes: self.timer.pass("gbuffer"),
                ..Default::default()
            });
            self.resources.draw(&mut pass, &self.pipelines, ScenePassKind::Gbuffer, DrawSet::Opaque, 0);
        }
        let shading = shading_uniform(gpu, &frame, self.screen, 0, self.resources.light_count());
        let group = bind_group(
            gpu,
            "shade full resolution",
            &self.shade,
            0,
            &[
                shading.as_entire_binding(),
                wgpu::BindingResource::TextureView(&gbuffer[0]),
                wgpu::BindingResource::TextureView(&gbuffer[1]),
                wgpu::BindingResource::TextureView(&depth),
                wgpu::BindingResource::TextureView(self.resources.lights_view()),
            ],
        );
        let colour = view(&self.colour);
        {
            let mut pass = encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
                label: Some("shade"),
                color_attachments: &[attachments::colour(&colour, None, BACKGROUND)],
                timestamp_writes: self.timer.pass("shade"),
                ..Default::default()
            });
            pass.set_pipeline(&self.shade);
            pass.set_bind_group(0, &group, &[]);
            pass.draw(0..3, 0..1);
        }
        if self.resources.has(DrawSet::Transparent) {
            let mut pass = encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
                label: Some("transparents"),
                color_attachments: &[Some(wgpu::RenderPassColorAttachment {
                    view: &colour,
                    depth_slice: None,
                    resolve_target: None,
                    ops: wgpu::Operations { load: wgpu::LoadOp::Load, store: wgpu::StoreOp::Store },
                })],
                depth_stencil_attachment: Some(wgpu::RenderPassDepthStencilAttachment {
                    view: &depth,
                    depth_ops: None,
                    stencil_ops: None,
                }),
                timestamp_writes: self.timer.pass("transparents"),
                ..Default::default()
            });
            self.resources.draw(&mut pass, &self.pipelines, ScenePassKind::Forward, DrawSet::Transparent, 0);
        }
    }
}
