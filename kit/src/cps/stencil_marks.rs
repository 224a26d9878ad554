//! The stencil marks: one draw a level at the start of the lighting pass (none for a level the LOD
//! pass found absent), each marking (op Replace) the level's texels some pixel of whose block uses
//! that level (shaders/cps/stencil_mark.wgsl) — from the LOD-present mask pyramid (an even and an
//! odd level's pipeline), or where the levels come from the foveation from each block's geometry.

use super::config::LodPolicy;
use super::plan::Plan;
use super::renderer::{STENCIL, level_draw_offset};
use super::targets::MipChain;
use crate::deferred::lighting::HDR;
use crate::fullscreen::{FullscreenPipeline, bind_group_at, uniform_buffer};
use crate::gpu::Gpu;
use crate::rects::stencil_state;
use crate::shaders;

pub(super) struct StencilMarks {
    pipelines: Vec<wgpu::RenderPipeline>,
    /// Each level's bind group, made once.
    level_groups: Vec<wgpu::BindGroup>,
}

impl StencilMarks {
    /// The marks of a plan's levels, read from `mask` (its finished pyramid) or, without one,
    /// from the foveation.
    pub(super) fn new(
        gpu: &Gpu,
        plan: &Plan,
        policy: &LodPolicy,
        mask: Option<&MipChain>,
        level_uniforms: &[wgpu::Buffer],
    ) -> Self {
        let entry_points: &[&str] = if mask.is_none() {
            &["fs_stencil_mark_foveated"]
        } else {
            &["fs_stencil_mark_even", "fs_stencil_mark_odd"]
        };
        // In the lighting pass: its colour target, left unwritten.
        let unwritten =
            [Some(wgpu::ColorTargetState { format: HDR, blend: None, write_mask: wgpu::ColorWrites::empty() })];
        let pipelines: Vec<wgpu::RenderPipeline> = entry_points
            .iter()
            .map(|entry_point| {
                FullscreenPipeline {
                    label: "stencil mark",
                    fragment: shaders::CPS_STENCIL_MARK,
                    entry_point,
                    targets: &unwritten,
                    depth_stencil: Some(stencil_state(
                        STENCIL,
                        wgpu::CompareFunction::Always,
                        wgpu::StencilOperation::Replace,
                    )),
                    samples: 1,
                }
                .create(gpu)
            })
            .collect();
        // What the marks read: the pyramid, or the foveation with the screen.
        let (mask, foveation) = match mask {
            Some(mask) => (Some(&mask.all), None),
            None => {
                let (w, h) = plan.screen;
                let mut words = policy.foveation_words(plan.screen, plan.top_level).to_vec();
                words.extend([w, h, 0, 0]);
                (None, Some(uniform_buffer(gpu, "foveation", bytemuck::cast_slice(&words))))
            }
        };
        let level_groups = level_uniforms
            .iter()
            .enumerate()
            .map(|(level, uniform)| {
                let pipeline = &pipelines[level % pipelines.len()];
                let mut resources = vec![(1, uniform.as_entire_binding())];
                if let Some(mask) = mask {
                    resources.push((0, wgpu::BindingResource::TextureView(mask)));
                }
                if let Some(foveation) = &foveation {
                    resources.push((2, foveation.as_entire_binding()));
                }
                bind_group_at(gpu, "stencil mark", pipeline, 0, &resources)
            })
            .collect();
        Self { pipelines, level_groups }
    }

    /// Every level's marks, into `pass` (stencil reference 1), each level drawn with its
    /// lighting draw's indirect arguments (`level_draws`): where the plan skips absent levels on
    /// the GPU, a level no pixel uses marks nothing, so its whole rect is not run through the
    /// mark shader only to be discarded.
    pub(super) fn record(&self, pass: &mut wgpu::RenderPass<'_>, plan: &Plan, level_draws: &wgpu::Buffer) {
        pass.set_stencil_reference(1);
        for (level, group) in self.level_groups.iter().enumerate() {
            pass.set_pipeline(&self.pipelines[level % self.pipelines.len()]);
            pass.set_bind_group(0, group, &[]);
            plan.set_level_viewport(pass, level);
            pass.draw_indirect(level_draws, level_draw_offset(level));
        }
    }
}
