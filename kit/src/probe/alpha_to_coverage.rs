//! The alpha-to-coverage transfer function: for each alpha on a fine grid, which samples a
//! fragment covers. One draw sweeps alpha along x (`shaders/kit/alpha_ramp.wgsl`); several rows
//! show whether the adapter dithers (different masks for the same alpha at different pixels).

use std::collections::BTreeSet;

use anyhow::Result;
use serde::Serialize;

use crate::attachments::colour;
use crate::fullscreen::{bind_group, uniform_buffer};
use crate::gpu::Gpu;
use crate::readback::read_rgba8;
use crate::rects::{Rect, RectBatch, RectFragment, RectPipeline};
use crate::shaders;

/// Alpha steps of the sweep: alpha = column / ALPHA_STEPS.
pub const ALPHA_STEPS: u32 = 256;
/// Rows (pixels with the same alpha) inspected for dithering.
pub const ROWS: u32 = 4;

#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct AlphaToCoverage {
    pub samples: u32,
    /// Covered-sample count per alpha step, averaged over the rows.
    pub mean_covered: Vec<f32>,
    /// Distinct covered counts seen over the sweep.
    pub levels: Vec<u32>,
    /// Coverage never decreases as alpha grows (per pixel).
    pub monotonic: bool,
    /// Pixels with the same alpha got different masks.
    pub dithered: bool,
    /// Distinct sample masks seen, in order of first appearance as alpha grows; empty where the
    /// sample mask cannot isolate samples.
    pub masks: Vec<u32>,
    /// For each covered count, the smallest alpha step that reached it.
    pub thresholds: Vec<(u32, u32)>,
}

/// Counts come from one resolve; per-sample masks only where `sample_mask_honoured` (each
/// sample is then isolated by the pipeline mask).
pub fn measure_alpha_to_coverage(gpu: &Gpu, samples: u32, sample_mask_honoured: bool) -> Result<AlphaToCoverage> {
    super::scoped(gpu, &format!("{samples}x alpha-to-coverage probe"), || {
        let size = (ALPHA_STEPS + 1, ROWS);
        let format = wgpu::TextureFormat::Rgba8Unorm;
        let msaa = gpu.texture("a2c msaa", size, format, samples, wgpu::TextureUsages::RENDER_ATTACHMENT);
        let resolved = gpu.texture(
            "a2c resolved",
            size,
            format,
            1,
            wgpu::TextureUsages::RENDER_ATTACHMENT | wgpu::TextureUsages::COPY_SRC,
        );
        let (msaa_view, resolved_view) =
            (msaa.create_view(&Default::default()), resolved.create_view(&Default::default()));
        let full = RectBatch::new(gpu, size, &[(Rect::full(size.0, size.1), [1.0; 4])]);
        let steps = uniform_buffer(gpu, "alpha ramp steps", bytemuck::cast_slice(&[ALPHA_STEPS as f32, 0.0, 0.0, 0.0]));
        let ramp = |sample_mask: u64| -> Result<image::RgbaImage> {
            let pipeline = RectPipeline {
                colour_format: Some(format),
                fragment: RectFragment::Shader { file: shaders::ALPHA_RAMP, entry: "fs_alpha_ramp" },
                samples,
                sample_mask,
                alpha_to_coverage: true,
                ..RectPipeline::new("alpha ramp")
            }
            .create(gpu);
            let bind_group = bind_group(gpu, "alpha ramp", &pipeline, 0, &[steps.as_entire_binding()]);
            let mut encoder = gpu.encoder("alpha ramp");
            {
                let mut pass = encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
                    label: Some("alpha ramp"),
                    color_attachments: &[colour(&msaa_view, Some(&resolved_view), wgpu::Color::TRANSPARENT)],
                    ..Default::default()
                });
                pass.set_pipeline(&pipeline);
                pass.set_bind_group(0, &bind_group, &[]);
                full.draw(&mut pass, ..);
            }
            gpu.submit(encoder);
            read_rgba8(gpu, &resolved)
        };
        // Counts from one resolve: white over N samples resolves to 255 · covered / N.
        let counts: Vec<u32> =
            ramp(!0)?.pixels().map(|p| (f32::from(p[0]) * samples as f32 / 255.0).round() as u32).collect();
        // Masks from one resolve per sample, where the sample mask isolates samples.
        let masks = if sample_mask_honoured {
            let mut masks = vec![0u32; counts.len()];
            for sample in 0..samples {
                for (mask, pixel) in masks.iter_mut().zip(ramp(1 << sample)?.pixels()) {
                    if pixel[0] > 0 {
                        *mask |= 1 << sample;
                    }
                }
            }
            Some(masks)
        } else {
            None
        };
        Ok(summarise(samples, size, &counts, masks.as_deref()))
    })
}

fn summarise(samples: u32, (width, rows): (u32, u32), counts: &[u32], masks: Option<&[u32]>) -> AlphaToCoverage {
    let at = |step: u32, row: u32| (row * width + step) as usize;
    let mut mean_covered = Vec::new();
    let mut levels = BTreeSet::new();
    let mut seen_masks = Vec::new();
    let mut thresholds: Vec<(u32, u32)> = Vec::new();
    let mut dithered = false;
    let mut monotonic = true;
    for step in 0..width {
        let mut total = 0;
        for row in 0..rows {
            let covered = counts[at(step, row)];
            total += covered;
            levels.insert(covered);
            if let Some(masks) = masks {
                let mask = masks[at(step, row)];
                if !seen_masks.contains(&mask) {
                    seen_masks.push(mask);
                }
                dithered |= mask != masks[at(step, 0)];
            }
            if !thresholds.iter().any(|&(c, _)| c == covered) {
                thresholds.push((covered, step));
            }
            dithered |= covered != counts[at(step, 0)];
            if step > 0 && covered < counts[at(step - 1, row)] {
                monotonic = false;
            }
        }
        mean_covered.push(total as f32 / rows as f32);
    }
    AlphaToCoverage {
        samples,
        mean_covered,
        levels: levels.into_iter().collect(),
        monotonic,
        dithered,
        masks: seen_masks,
        thresholds,
    }
}
