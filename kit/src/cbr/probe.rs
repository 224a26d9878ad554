//! Measures where a checkerboard frame's samples land: a grid of rects, one per
//! full-resolution pixel with its coordinates as colour, drawn through the quarter-resolution
//! projection of a jitter phase as the scene passes build it (`quarter_projection`); each sample
//! reads back the pixel whose rect covered it. The rasteriser and the renderer's projection
//! decide, not the kit's mapping.

use anyhow::Result;

use super::sampling::{CheckerboardPath, offset_for_sample, quarter_projection, quarter_size, sample_positions};
use crate::attachments;
use crate::fullscreen::uniform_buffer;
use crate::gpu::Gpu;
use crate::probe::sample_positions::{RecordStorage, record_fragments, storage_pair};
use crate::readback::read_rgba8;
use crate::rects::{Rect, RectBatch, RectFragment, RectPipeline};
use crate::shaders;

/// The full-resolution pixel each of a quarter pixel's two samples landed on (None: no rect there).
pub type Landing = [Option<(u32, u32)>; 2];

/// What no rect covered.
const NOTHING: u32 = u32::MAX;

fn encode(x: u32, y: u32) -> [f32; 4] {
    [x & 255, x >> 8, y & 255, y >> 8].map(|b| b as f32 / 255.0)
}

fn decode(word: u32) -> Option<(u32, u32)> {
    (word != NOTHING).then_some((word & 0xffff, word >> 16))
}

/// The full-resolution pixel rects in quarter-resolution pixels for jitter `phase`, shifted by
/// `offset` quarter pixels: each pixel's corners go through `quarter_projection`, the transform
/// the scene passes draw with, so a wrong projection moves the rects.
fn pixel_rects(screen: (u32, u32), phase: u32, offset: [f32; 2]) -> Vec<(Rect, [f32; 4])> {
    let to_quarter = quarter_projection(screen, phase, offset);
    let quarter = quarter_size(screen);
    let (width, height) = (screen.0 as f32, screen.1 as f32);
    // Full-resolution pixel corner → full-resolution NDC → quarter NDC → quarter pixels.
    let corner = |x: u32, y: u32| {
        let ndc = glam::Vec3::new(x as f32 / width * 2.0 - 1.0, 1.0 - y as f32 / height * 2.0, 0.5);
        let quarter_ndc = to_quarter.project_point3(ndc);
        ((quarter_ndc.x + 1.0) * 0.5 * quarter.0 as f32, (1.0 - quarter_ndc.y) * 0.5 * quarter.1 as f32)
    };
    let mut rects = Vec::with_capacity((screen.0 * screen.1) as usize);
    for y in 0..screen.1 {
        for x in 0..screen.0 {
            let ((x0, y0), (x1, y1)) = (corner(x, y), corner(x + 1, y + 1));
            rects.push((Rect::new(x0, y0, x1, y1), encode(x, y)));
        }
    }
    rects
}

/// Per quarter pixel (row-major), the full-resolution pixel each of its two samples landed on.
pub fn measure_landing(gpu: &Gpu, screen: (u32, u32), path: CheckerboardPath, phase: u32) -> Result<Vec<Landing>> {
    let quarter = quarter_size(screen);
    let count = (quarter.0 * quarter.1) as usize;
    gpu.scoped("checkerboard sample landing", || match path {
        CheckerboardPath::OffsetPasses => {
            let positions = sample_positions();
            let format = wgpu::TextureFormat::Rgba8Unorm;
            let pipeline = RectPipeline {
                colour_format: Some(format),
                fragment: RectFragment::InstanceColour,
                ..RectPipeline::new("pixel ids")
            }
            .create(gpu);
            let mut landed = vec![[None; 2]; count];
            for sample in 0..2 {
                let rects =
                    RectBatch::new(gpu, quarter, &pixel_rects(screen, phase, offset_for_sample(sample, &positions)));
                let target = gpu.texture(
                    "pixel ids",
                    quarter,
                    format,
                    1,
                    wgpu::TextureUsages::RENDER_ATTACHMENT | wgpu::TextureUsages::COPY_SRC,
                );
                let view = target.create_view(&Default::default());
                let mut encoder = gpu.encoder("pixel ids");
                {
                    let mut pass = encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
                        label: Some("pixel ids"),
                        color_attachments: &[attachments::colour(&view, None, wgpu::Color::WHITE)],
                        ..Default::default()
                    });
                    pass.set_pipeline(&pipeline);
                    rects.draw(&mut pass, ..);
                }
                gpu.submit(encoder);
                for (slot, pixel) in landed.iter_mut().zip(read_rgba8(gpu, &target)?.pixels()) {
                    slot[sample] = decode(u32::from_le_bytes(pixel.0));
                }
            }
            Ok(landed)
        }
        CheckerboardPath::Msaa2x => {
            let rects = pixel_rects(screen, phase, [0.0, 0.0]);
            let grid = uniform_buffer(gpu, "quarter grid", bytemuck::cast_slice(&[quarter.0, 0, 0, 0]));
            let (storage, readback) = storage_pair(gpu, "landed samples", (count * 2 * 4) as u64);
            let bytes = record_fragments(
                gpu,
                quarter,
                2,
                RectFragment::Shader { file: shaders::CBR_SAMPLE_ID_RECORD, entry: "fs_record_sample_pixel" },
                &rects,
                &[grid.as_entire_binding(), storage.as_entire_binding()],
                RecordStorage { buffer: &storage, readback: &readback, fill: NOTHING },
            )?;
            let words: &[u32] = bytemuck::cast_slice(&bytes);
            Ok(words.chunks_exact(2).map(|w| [decode(w[0]), decode(w[1])]).collect())
        }
    })
}
