//! The sample layout's WGSL functions (`checkerboard_texel`, `layout_pixel_centre` in
//! `shaders/common/checkerboard.wgsl`) evaluated on the GPU by `shaders/cbr/layout_values.wgsl`:
//! for every full-resolution pixel the layout texel a phase keeps it in, and for every layout
//! texel the pixel centre its sample sees.

use anyhow::Result;

use super::frame::layout_size;
use super::sampling::quarter_size;
use crate::fullscreen::{FullscreenPipeline, bind_group, render_to_readback, uniform_buffer};
use crate::gpu::Gpu;
use crate::shaders;

/// What the layout functions return for one screen and phase.
pub struct LayoutValues {
    /// Per full-resolution pixel (row-major): its layout texel, or None where the phase has none.
    pub texel_of_pixel: Vec<Option<(u32, u32)>>,
    /// Per layout texel (row-major): the full-resolution pixel centre its sample sees.
    pub centre_of_texel: Vec<[f32; 2]>,
}

pub fn evaluate_layout(gpu: &Gpu, screen: (u32, u32), phase: u32) -> Result<LayoutValues> {
    let quarter = quarter_size(screen);
    gpu.scoped("checkerboard layout values", || {
        let words = [quarter.0 as i32, quarter.1 as i32, phase as i32, 0];
        let uniform = uniform_buffer(gpu, "layout", bytemuck::cast_slice(&words));
        let evaluate = |entry_point: &str, format: wgpu::TextureFormat, size: (u32, u32)| {
            let pipeline = FullscreenPipeline {
                label: entry_point,
                fragment: shaders::CBR_LAYOUT_VALUES,
                entry_point,
                targets: &[Some(format.into())],
                depth_stencil: None,
                samples: 1,
            }
            .create(gpu);
            let group = bind_group(gpu, entry_point, &pipeline, 0, &[uniform.as_entire_binding()]);
            render_to_readback(gpu, entry_point, &pipeline, &group, format, size)
        };
        let texels = evaluate("fs_texel_of_pixel", wgpu::TextureFormat::Rgba32Sint, screen)?;
        let centres = evaluate("fs_centre_of_texel", wgpu::TextureFormat::Rgba32Sint, layout_size(screen))?;
        let texel_words: &[i32] = bytemuck::cast_slice(&texels.bytes);
        let centre_words: &[u32] = bytemuck::cast_slice(&centres.bytes);
        Ok(LayoutValues {
            texel_of_pixel: texel_words
                .chunks_exact(4)
                .map(|t| (t[0] >= 0 && t[1] >= 0).then_some((t[0] as u32, t[1] as u32)))
                .collect(),
            centre_of_texel: centre_words
                .chunks_exact(4)
                .map(|c| [f32::from_bits(c[0]), f32::from_bits(c[1])])
                .collect(),
        })
    })
}
