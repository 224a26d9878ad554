//! One checkerboard frame: its targets in the sample layout (each sample's turned view in its
//! half, sample s of quarter pixel q at (q.y + s·Hq, Wq − 1 − q.x); see
//! `shaders/common/checkerboard.wgsl`) and the passes that fill them, on either path (offset
//! passes or a real 2x target) with forward or deferred shading, as the plan says.

use anyhow::Result;

use super::plan::{CheckerboardPlan, Shading};
use super::sampling::{CheckerboardPath, offset_for_sample, quarter_projection, quarter_size, sample_positions};
use super::scene::FrameView;
use super::scene_pass::{
    ALBEDO, DEPTH, DrawSet, HDR, MOTION, NORMAL, ScenePassKind, ScenePipelines, SceneResources, TextureLod,
};
use crate::attachments;
use crate::fullscreen::{FullscreenPipeline, bind_group};
use crate::gpu::Gpu;
use crate::query::GpuTimer;
use crate::shaders;

/// The colour the scene pass clears to: shaders/common/lighting.wgsl's BACKGROUND.
pub const BACKGROUND: wgpu::Color = wgpu::Color { r: 0.02, g: 0.025, b: 0.035, a: 1.0 };

/// A frame's samples as the reconstruction reads them, all in the sample layout.
pub struct CheckerboardFrame {
    /// Shaded samples (forward: everything; deferred: the shade resolve target).
    pub colour: wgpu::Texture,
    pub depth: wgpu::Texture,
    /// Per-object motion, where objects move.
    pub motion: Option<wgpu::Texture>,
    /// The deferred path's forward buffer (premultiplied colour, accumulated alpha), where
    /// there are transparent draws.
    pub forward: Option<wgpu::Texture>,
}

/// The texture usage of every target the kit renders, samples and reads back.
pub(crate) const TARGET_USAGE: wgpu::TextureUsages = wgpu::TextureUsages::RENDER_ATTACHMENT
    .union(wgpu::TextureUsages::TEXTURE_BINDING)
    .union(wgpu::TextureUsages::COPY_SRC);

/// Size of the sample layout for a full-resolution screen: two turned quarter-resolution views
/// side by side.
pub fn layout_size(screen: (u32, u32)) -> (u32, u32) {
    let (qw, qh) = quarter_size(screen);
    (2 * qh, qw)
}

impl CheckerboardFrame {
    fn new(gpu: &Gpu, screen: (u32, u32), plan: &CheckerboardPlan) -> Self {
        let size = layout_size(screen);
        let target = |label, format| gpu.texture(label, size, format, 1, TARGET_USAGE);
        Self {
            colour: target("checkerboard colour", HDR),
            depth: target("checkerboard depth", DEPTH),
            motion: plan.object_motion.then(|| target("checkerboard motion", MOTION)),
            forward: plan.forward_buffer.then(|| target("checkerboard forward buffer", HDR)),
        }
    }
}

/// Targets a frame's passes render into before the sample layout: the offset path's
/// G-buffer (already in the layout), or the 2x path's multisampled targets.
struct Scratch {
    /// Normal + shininess, albedo + specular (deferred only).
    gbuffer: Option<[wgpu::Texture; 2]>,
    /// 2x path: colour (forward), depth, motion and forward buffer at quarter size.
    msaa_colour: Option<wgpu::Texture>,
    msaa_depth: Option<wgpu::Texture>,
    msaa_motion: Option<wgpu::Texture>,
    msaa_forward: Option<wgpu::Texture>,
}

impl Scratch {
    fn new(gpu: &Gpu, screen: (u32, u32), plan: &CheckerboardPlan) -> Self {
        let msaa = plan.path == CheckerboardPath::Msaa2x;
        let (size, samples) = if msaa { (quarter_size(screen), 2) } else { (layout_size(screen), 1) };
        let target = |label, format| gpu.texture(label, size, format, samples, TARGET_USAGE);
        Self {
            gbuffer: (plan.shading == Shading::Deferred).then(|| {
                [target("checkerboard gbuffer normal", NORMAL), target("checkerboard gbuffer albedo", ALBEDO)]
            }),
            msaa_colour: (msaa && plan.shading == Shading::Forward).then(|| target("2x colour", HDR)),
            msaa_depth: msaa.then(|| target("2x depth", DEPTH)),
            msaa_motion: (msaa && plan.object_motion).then(|| target("2x motion", MOTION)),
            msaa_forward: (msaa && plan.forward_buffer).then(|| target("2x forward buffer", HDR)),
        }
    }
}

/// Everything that renders checkerboard frames for one scene, screen and plan.
pub struct FramePasses {
    pub plan: CheckerboardPlan,
    screen: (u32, u32),
    lod: TextureLod,
    pipelines: ScenePipelines,
    resources: SceneResources,
    scratch: Scratch,
    shade: Option<wgpu::RenderPipeline>,
    /// The 2x path's copies into the sample layout.
    unpack: Option<Unpack>,
}

/// The unpack passes' pipelines (colour-like targets, depth) and their layout uniform.
struct Unpack {
    colour: wgpu::RenderPipeline,
    depth: wgpu::RenderPipeline,
    layout: wgpu::Buffer,
}

fn view(texture: &wgpu::Texture) -> wgpu::TextureView {
    texture.create_view(&Default::default())
}

fn depth_attachment(view: &wgpu::TextureView, clear: bool) -> Option<wgpu::RenderPassDepthStencilAttachment<'_>> {
    Some(wgpu::RenderPassDepthStencilAttachment {
        view,
        // Passes that only test depth leave it read-only.
        depth_ops: clear.then_some(wgpu::Operations { load: wgpu::LoadOp::Clear(1.0), store: wgpu::StoreOp::Store }),
        stencil_ops: None,
    })
}

impl FramePasses {
    pub fn new(
        gpu: &Gpu,
        scene: &super::scene::CheckerboardScene,
        screen: (u32, u32),
        plan: CheckerboardPlan,
        lod: TextureLod,
    ) -> Result<Self> {
        let msaa = plan.path == CheckerboardPath::Msaa2x;
        let pipelines = ScenePipelines::new(gpu, if msaa { 2 } else { 1 });
        let resources = SceneResources::new(gpu, &pipelines, scene, 2)?;
        let fullscreen = |label, fragment, entry_point, targets: &[Option<wgpu::ColorTargetState>], depth| {
            FullscreenPipeline { label, fragment, entry_point, targets, depth_stencil: depth, samples: 1 }.create(gpu)
        };
        let shade = (plan.shading == Shading::Deferred).then(|| {
            let (file, entry) = if msaa {
                (shaders::CBR_SHADE_MSAA_SAMPLES, "fs_shade_msaa_samples")
            } else {
                (shaders::CBR_SHADE_SAMPLES, "fs_shade_samples")
            };
            fullscreen("shade samples", file, entry, &[Some(HDR.into())], None)
        });
        let unpack = msaa.then(|| {
            let depth = wgpu::DepthStencilState {
                format: DEPTH,
                depth_write_enabled: Some(true),
                depth_compare: Some(wgpu::CompareFunction::Always),
                stencil: Default::default(),
                bias: Default::default(),
            };
            let (qw, _) = quarter_size(screen);
            Unpack {
                colour: fullscreen(
                    "unpack colour",
                    shaders::CBR_UNPACK_SAMPLES,
                    "fs_unpack_colour",
                    &[Some(HDR.into())],
                    None,
                ),
                depth: fullscreen("unpack depth", shaders::CBR_UNPACK_SAMPLES, "fs_unpack_depth", &[], Some(depth)),
                layout: crate::fullscreen::uniform_buffer(gpu, "sample layout", bytemuck::cast_slice(&[qw, 0, 0, 0])),
            }
        });
        Ok(Self { scratch: Scratch::new(gpu, screen, &plan), plan, screen, lod, pipelines, resources, shade, unpack })
    }

    /// Targets for one frame of this plan.
    pub fn frame_targets(&self, gpu: &Gpu) -> CheckerboardFrame {
        CheckerboardFrame::new(gpu, self.screen, &self.plan)
    }

    /// Records frame `view` in jitter phase `phase` into `frame`.
    pub fn record(
        &self,
        gpu: &Gpu,
        encoder: &mut wgpu::CommandEncoder,
        timer: &mut GpuTimer,
        view: &FrameView,
        phase: u32,
        frame: &CheckerboardFrame,
    ) {
        for (slot, offset) in self.view_offsets().into_iter().enumerate() {
            let quarter = quarter_projection(self.screen, phase, offset);
            let clip = self.plan.path.orientation().clip_transform() * quarter * view.full_from_world;
            self.resources.write_view(gpu, slot, clip, view, self.screen, self.lod);
        }
        self.resources.write_objects(gpu, view);

        let depth_view = view_of_depth(self, frame);
        match self.plan.shading {
            Shading::Forward => {
                let colour = self.scratch.msaa_colour.as_ref().map_or_else(|| self::view(&frame.colour), self::view);
                let sets: &[DrawSet] =
                    if self.plan.transparents { &[DrawSet::Opaque, DrawSet::Transparent] } else { &[DrawSet::Opaque] };
                self.scene_pass(
                    encoder,
                    timer,
                    "scene forward",
                    &[attachments::colour(&colour, None, BACKGROUND)],
                    (&depth_view, true),
                    ScenePassKind::Forward,
                    sets,
                );
            }
            Shading::Deferred => {
                let gbuffer =
                    self.scratch.gbuffer.as_ref().expect("deferred plans have a G-buffer").each_ref().map(self::view);
                let clear = wgpu::Color::TRANSPARENT;
                self.scene_pass(
                    encoder,
                    timer,
                    "gbuffer",
                    &[attachments::colour(&gbuffer[0], None, clear), attachments::colour(&gbuffer[1], None, clear)],
                    (&depth_view, true),
                    ScenePassKind::Gbuffer,
                    &[DrawSet::Opaque],
                );
                if let Some(forward) = &frame.forward {
                    let target = self.scratch.msaa_forward.as_ref().map_or_else(|| self::view(forward), self::view);
                    self.scene_pass(
                        encoder,
                        timer,
                        "forward buffer",
                        &[attachments::colour(&target, None, clear)],
                        (&depth_view, false),
                        ScenePassKind::Forward,
                        &[DrawSet::Transparent],
                    );
                }
                if let (Some(forward), Some(samples)) = (&frame.forward, &self.scratch.msaa_forward) {
                    self.unpack(gpu, encoder, timer, "unpack forward buffer", samples, forward);
                }
                let depth_samples = self.scratch.msaa_depth.as_ref().unwrap_or(&frame.depth);
                let shading = shading_uniform(gpu, view, self.screen, phase, self.resources.light_count());
                let group = bind_group(
                    gpu,
                    "shade samples",
                    self.shade.as_ref().expect("deferred plans shade"),
                    0,
                    &[
                        shading.as_entire_binding(),
                        wgpu::BindingResource::TextureView(&gbuffer[0]),
                        wgpu::BindingResource::TextureView(&gbuffer[1]),
                        wgpu::BindingResource::TextureView(&self::view(depth_samples)),
                        wgpu::BindingResource::TextureView(self.resources.lights_view()),
                    ],
                );
                let target = self::view(&frame.colour);
                let mut pass = encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
                    label: Some("shade samples"),
                    color_attachments: &[attachments::colour(&target, None, wgpu::Color::TRANSPARENT)],
                    timestamp_writes: timer.pass("shade samples"),
                    ..Default::default()
                });
                pass.set_pipeline(self.shade.as_ref().expect("deferred plans shade"));
                pass.set_bind_group(0, &group, &[]);
                pass.draw(0..3, 0..1);
            }
        }
        if let (Some(colour), Shading::Forward) = (&self.scratch.msaa_colour, self.plan.shading) {
            self.unpack(gpu, encoder, timer, "unpack colour", colour, &frame.colour);
        }
        if let Some(motion) = &frame.motion {
            let target = self.scratch.msaa_motion.as_ref().map_or_else(|| self::view(motion), self::view);
            self.scene_pass(
                encoder,
                timer,
                "object motion",
                &[attachments::colour(&target, None, wgpu::Color::TRANSPARENT)],
                (&depth_view, false),
                ScenePassKind::Forward,
                &[DrawSet::Moving],
            );
            if let Some(samples) = &self.scratch.msaa_motion {
                self.unpack(gpu, encoder, timer, "unpack motion", samples, motion);
            }
        }
        if let Some(samples) = &self.scratch.msaa_depth {
            self.unpack(gpu, encoder, timer, "unpack depth", samples, &frame.depth);
        }
    }

    /// The projection offset of each view of a frame: the 2x target's one, or each offset pass's.
    fn view_offsets(&self) -> Vec<[f32; 2]> {
        match self.plan.path {
            CheckerboardPath::Msaa2x => vec![[0.0, 0.0]],
            CheckerboardPath::OffsetPasses => (0..2).map(|s| offset_for_sample(s, &sample_positions())).collect(),
        }
    }

    /// One pass of the scene through every view of the frame, drawing `sets` in order: the 2x
    /// target's one view, or each offset pass turned into its half of the sample layout. `depth` is
    /// cleared and written, or (`false`) only tested.
    #[allow(clippy::too_many_arguments)]
    fn scene_pass(
        &self,
        encoder: &mut wgpu::CommandEncoder,
        timer: &mut GpuTimer,
        label: &str,
        colours: &[Option<wgpu::RenderPassColorAttachment<'_>>],
        depth: (&wgpu::TextureView, bool),
        kind: ScenePassKind,
        sets: &[DrawSet],
    ) {
        let mut pass = encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
            label: Some(label),
            color_attachments: colours,
            depth_stencil_attachment: depth_attachment(depth.0, depth.1),
            timestamp_writes: timer.pass(label),
            ..Default::default()
        });
        let views = self.view_offsets().len();
        let (qw, qh) = quarter_size(self.screen);
        for view in 0..views {
            if views > 1 {
                let x = view as u32 * qh;
                pass.set_viewport(x as f32, 0.0, qh as f32, qw as f32, 0.0, 1.0);
                pass.set_scissor_rect(x, 0, qh, qw);
            }
            for set in sets {
                self.resources.draw(&mut pass, &self.pipelines, kind, *set, view);
            }
        }
    }

    /// Copies each sample of a 2x target into the sample layout (`target`).
    fn unpack(
        &self,
        gpu: &Gpu,
        encoder: &mut wgpu::CommandEncoder,
        timer: &mut GpuTimer,
        label: &'static str,
        samples: &wgpu::Texture,
        target: &wgpu::Texture,
    ) {
        let unpack = self.unpack.as_ref().expect("2x plans unpack");
        let depth = samples.format() == DEPTH;
        let pipeline = if depth { &unpack.depth } else { &unpack.colour };
        let source = self::view(samples);
        let binding = if depth { 2 } else { 1 };
        let group = crate::fullscreen::bind_group_at(
            gpu,
            label,
            pipeline,
            0,
            &[(0, unpack.layout.as_entire_binding()), (binding, wgpu::BindingResource::TextureView(&source))],
        );
        let target_view = self::view(target);
        let colour = [attachments::colour(&target_view, None, wgpu::Color::TRANSPARENT)];
        let mut pass = encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
            label: Some(label),
            color_attachments: if depth { &[] } else { &colour },
            depth_stencil_attachment: depth.then_some(wgpu::RenderPassDepthStencilAttachment {
                view: &target_view,
                depth_ops: Some(wgpu::Operations { load: wgpu::LoadOp::Clear(1.0), store: wgpu::StoreOp::Store }),
                stencil_ops: None,
            }),
            timestamp_writes: timer.pass(label),
            ..Default::default()
        });
        pass.set_pipeline(pipeline);
        pass.set_bind_group(0, &group, &[]);
        pass.draw(0..3, 0..1);
    }
}

/// The depth the scene passes test against: the 2x target's, or the frame's own.
fn view_of_depth(passes: &FramePasses, frame: &CheckerboardFrame) -> wgpu::TextureView {
    view(passes.scratch.msaa_depth.as_ref().unwrap_or(&frame.depth))
}

/// `SampleShading` in the shade passes: inverse view-projection, screen, quarter size, eye,
/// light count, phase.
pub(crate) fn shading_uniform(
    gpu: &Gpu,
    view: &FrameView,
    screen: (u32, u32),
    phase: u32,
    light_count: u32,
) -> wgpu::Buffer {
    let (qw, qh) = quarter_size(screen);
    let mut words: Vec<u32> = view.full_from_world.inverse().to_cols_array().map(f32::to_bits).to_vec();
    words.extend([(screen.0 as f32).to_bits(), (screen.1 as f32).to_bits(), qw, qh]);
    words.extend([view.eye.x.to_bits(), view.eye.y.to_bits(), view.eye.z.to_bits(), light_count]);
    words.extend([phase, 0, 0, 0]);
    crate::fullscreen::uniform_buffer(gpu, "sample shading", bytemuck::cast_slice(&words))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Two turned quarter-resolution views side by side: width two quarter heights, height one
    /// quarter width (odd sides rounded up).
    #[test]
    fn the_layout_holds_two_turned_quarter_views() {
        assert_eq!(layout_size((64, 48)), (48, 32));
        assert_eq!(layout_size((17, 9)), (10, 9));
        assert_eq!(layout_size((1, 1)), (2, 1));
    }
}
