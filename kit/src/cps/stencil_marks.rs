//! The stencil marks, at the start of the lighting pass, marking (op Replace) each level's texels
//! some pixel of whose block uses that level (shaders/cps/stencil_mark.wgsl): from the LOD-present
//! mask pyramid, one draw a level (an even and an odd level's pipeline; none for a level the LOD
//! pass found absent), or where the levels come from the foveation, from each block's geometry in
//! one instanced draw over every level's spans (cps/level_spans.rs).

use super::config::LodPolicy;
use super::level_spans::SpanBatch;
use super::plan::Plan;
use super::renderer::{LevelDraws, STENCIL};
use super::targets::MipChain;
use crate::deferred::lighting::HDR;
use crate::fullscreen::{FullscreenPipeline, bind_group_at, uniform_buffer};
use crate::gpu::Gpu;
use crate::rects::{RectFragment, RectPipeline, stencil_replace};
use crate::shaders;

/// The marks' draws: one a level from the pyramid, or one instanced draw from the foveation.
pub(super) enum StencilMarks {
    /// The even and the odd levels' pipelines, and each level's bind group.
    Pyramid { pipelines: [wgpu::RenderPipeline; 2], level_groups: Vec<wgpu::BindGroup> },
    /// One pipeline and bind group for every level, and every level's spans (the level in each
    /// rect's colour).
    Foveated { pipeline: wgpu::RenderPipeline, group: wgpu::BindGroup, spans: SpanBatch },
}

/// The uniform a block's levels under the foveated policy follow from (common/foveation.wgsl's
/// `FoveatedBlocks`): the foveation, the screen, each level's origin in the atlas.
pub(super) fn foveated_blocks(gpu: &Gpu, plan: &Plan, policy: &LodPolicy) -> wgpu::Buffer {
    let (w, h) = plan.screen;
    let mut words = policy.foveation_words(plan.screen, plan.top_level).to_vec();
    words.extend([w, h, 0, 0]);
    let mut origins = [[0u32; 4]; 9];
    for (level, origin) in origins.iter_mut().enumerate().take(plan.levels() as usize) {
        let (x, y) = plan.atlas.origins[level];
        *origin = [x, y, 0, 0];
    }
    words.extend(origins.iter().flatten());
    uniform_buffer(gpu, "foveated blocks", bytemuck::cast_slice(&words))
}

/// Where the marks read which levels a block uses.
pub(super) enum MarkSource<'a> {
    /// The finished LOD-present mask pyramid.
    Pyramid(&'a MipChain),
    /// The foveation (`foveated_blocks`), over the levels' spans.
    Foveation(&'a wgpu::Buffer, &'a SpanBatch),
}

impl StencilMarks {
    /// The marks of each level (`level_uniforms`), read from `source`.
    pub(super) fn new(gpu: &Gpu, source: MarkSource<'_>, level_uniforms: &[wgpu::Buffer]) -> Self {
        let mask = match source {
            MarkSource::Pyramid(mask) => mask,
            MarkSource::Foveation(blocks, spans) => return Self::foveated(gpu, blocks, spans),
        };
        // In the lighting pass: its colour target, left unwritten.
        let unwritten =
            [Some(wgpu::ColorTargetState { format: HDR, blend: None, write_mask: wgpu::ColorWrites::empty() })];
        let pipelines = ["fs_stencil_mark_even", "fs_stencil_mark_odd"].map(|entry_point| {
            FullscreenPipeline {
                label: "stencil mark",
                fragment: shaders::CPS_STENCIL_MARK,
                entry_point,
                targets: &unwritten,
                depth_stencil: Some(stencil_replace(STENCIL)),
                samples: 1,
            }
            .create(gpu)
        });
        let level_groups = level_uniforms
            .iter()
            .enumerate()
            .map(|(level, uniform)| {
                let resources = [(0, wgpu::BindingResource::TextureView(&mask.all)), (1, uniform.as_entire_binding())];
                bind_group_at(gpu, "stencil mark", &pipelines[level % 2], 0, &resources)
            })
            .collect();
        Self::Pyramid { pipelines, level_groups }
    }

    /// Every level's marks from the foveation (`blocks`: `foveated_blocks`), in one draw.
    fn foveated(gpu: &Gpu, blocks: &wgpu::Buffer, spans: &SpanBatch) -> Self {
        let pipeline = RectPipeline {
            colour_format: Some(HDR),
            colour_writes: wgpu::ColorWrites::empty(),
            fragment: RectFragment::Shader { file: shaders::CPS_STENCIL_MARK, entry: "fs_stencil_mark_foveated" },
            depth_stencil: Some(stencil_replace(STENCIL)),
            ..RectPipeline::new("foveated stencil marks")
        }
        .create(gpu);
        let group = bind_group_at(gpu, "foveated stencil marks", &pipeline, 0, &[(2, blocks.as_entire_binding())]);
        // The lighting's own batch: a clone shares the one buffer.
        Self::Foveated { pipeline, group, spans: spans.clone() }
    }

    /// Every level's marks, into `pass` (stencil reference 1). From the pyramid, each level is
    /// drawn as its lighting draw is (`level_draws`): where the plan skips absent levels on the
    /// GPU, a level no pixel uses marks nothing, so its whole rect is not run through the mark
    /// shader only to be discarded.
    pub(super) fn record(&self, pass: &mut wgpu::RenderPass<'_>, plan: &Plan, level_draws: &LevelDraws) {
        pass.set_stencil_reference(1);
        match self {
            Self::Pyramid { pipelines, level_groups } => {
                for (level, group) in level_groups.iter().enumerate() {
                    pass.set_pipeline(&pipelines[level % 2]);
                    pass.set_bind_group(0, group, &[]);
                    plan.set_level_viewport(pass, level);
                    level_draws.draw(pass, level);
                }
            }
            Self::Foveated { pipeline, group, spans } => {
                let (w, h) = plan.atlas.size;
                pass.set_viewport(0.0, 0.0, w as f32, h as f32, 0.0, 1.0);
                pass.set_scissor_rect(0, 0, w, h);
                pass.set_pipeline(pipeline);
                pass.set_bind_group(0, group, &[]);
                spans.draw_all(pass);
            }
        }
    }
}
