//! How finely the rasteriser snaps vertex positions: Vulkan (`subPixelPrecisionBits`) and GL
//! (`SUBPIXEL_BITS`) promise at least 4 bits, WebGPU nothing finer, and adapters differ (lavapipe
//! 8, SwiftShader 4). Measured, not queried: `shaders/kit/sloped_edge.wgsl` draws 256 quads whose
//! left vertices sit (k + 1/4)/256 px into a pixel, and each quad's covered-pixel count gives the
//! snapped offset to 1/256 px. The kit's expectations hold for 4 bits; this says what the adapter
//! has, for reports.

use anyhow::Result;
use serde::Serialize;

use crate::attachments::colour;
use crate::gpu::Gpu;
use crate::readback::read_rgba8;
use crate::shaders;

/// The coarsest sub-pixel precision Vulkan and GL permit.
pub const COARSEST_BITS: u32 = 4;

/// The farthest (px, per axis) snapping may move a vertex at the coarsest precision: less than
/// one 1/16-px grid step, whichever way the rasteriser rounds.
pub const COARSEST_SNAP: f32 = 1.0 / (1 << COARSEST_BITS) as f32;

/// The probe's resolution: offsets and measurements are in 1/256 px.
const RESOLUTION: u32 = 256;
const TARGET: (u32, u32) = (2 * RESOLUTION, RESOLUTION);

#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct SubpixelPrecision {
    /// Bits of the grid the snapped offsets lie on; 8 means "8 or more" (the probe's resolution).
    pub bits: u32,
    /// The largest distance (px) snapping moved a vertex: under half a step when it rounds to
    /// nearest, under a whole step when it truncates.
    pub largest_move: f32,
    /// Offsets (1/256 px) where the snapped position read back outside [0, 1] px (none on a
    /// working rasteriser).
    pub unreadable: Vec<u32>,
}

impl SubpixelPrecision {
    /// True when snapping moved no vertex a whole step of the grid it claims, and the grid is
    /// no coarser than the specifications allow.
    pub fn within_specification(&self) -> bool {
        self.unreadable.is_empty()
            && self.bits >= COARSEST_BITS
            && self.largest_move < 1.0 / (1u32 << self.bits) as f32 + 0.5 / RESOLUTION as f32
    }
}

/// The offset k's snapped position (in 1/256 px) from its quad's covered pixels: 256 (3/2 − s)
/// of them, exact while s lies on the 1/256 grid.
fn snapped_from_covered(covered: u32) -> Option<u32> {
    (3 * RESOLUTION / 2).checked_sub(covered).filter(|&s| s <= RESOLUTION)
}

/// The grid (bits) a snapped offset of `s`/256 px lies on: the fewest bits that write it.
fn bits_of(s: u32) -> u32 {
    if s == 0 { 0 } else { RESOLUTION.trailing_zeros() - s.trailing_zeros().min(RESOLUTION.trailing_zeros()) }
}

pub fn measure(gpu: &Gpu) -> Result<SubpixelPrecision> {
    let covered = gpu.scoped("sub-pixel precision probe", || {
        let format = wgpu::TextureFormat::Rgba8Unorm;
        let usage = wgpu::TextureUsages::RENDER_ATTACHMENT | wgpu::TextureUsages::COPY_SRC;
        let target = gpu.texture("sloped edges", TARGET, format, 1, usage);
        let view = target.create_view(&Default::default());
        let module = shaders::SLOPED_EDGE.module(gpu);
        let pipeline = gpu.device.create_render_pipeline(&wgpu::RenderPipelineDescriptor {
            label: Some("sloped edges"),
            layout: None,
            vertex: wgpu::VertexState {
                module: &module,
                entry_point: Some("vs_sloped_edge"),
                compilation_options: Default::default(),
                buffers: &[],
            },
            primitive: Default::default(),
            depth_stencil: None,
            multisample: Default::default(),
            fragment: Some(wgpu::FragmentState {
                module: &module,
                entry_point: Some("fs_sloped_edge"),
                compilation_options: Default::default(),
                targets: &[Some(format.into())],
            }),
            multiview_mask: None,
            cache: None,
        });
        let mut encoder = gpu.encoder("sub-pixel precision probe");
        {
            let mut pass = encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
                label: Some("sloped edges"),
                color_attachments: &[colour(&view, None, wgpu::Color::TRANSPARENT)],
                ..Default::default()
            });
            pass.set_pipeline(&pipeline);
            pass.draw(0..6, 0..RESOLUTION);
        }
        gpu.submit(encoder);
        let image = read_rgba8(gpu, &target)?;
        Ok((0..RESOLUTION)
            .map(|k| {
                let columns = [2 * k, 2 * k + 1];
                (0..TARGET.1)
                    .flat_map(|y| columns.map(|x| (x, y)))
                    .filter(|&(x, y)| image.get_pixel(x, y).0[0] > 127)
                    .count() as u32
            })
            .collect::<Vec<u32>>())
    })?;
    let mut bits = 0;
    let mut largest_move = 0.0f32;
    let mut unreadable = Vec::new();
    for (k, &count) in covered.iter().enumerate() {
        match snapped_from_covered(count) {
            Some(s) => {
                bits = bits.max(bits_of(s % RESOLUTION));
                let offset = (k as f32 + 0.25) / RESOLUTION as f32;
                largest_move = largest_move.max((s as f32 / RESOLUTION as f32 - offset).abs());
            }
            None => unreadable.push(k as u32),
        }
    }
    Ok(SubpixelPrecision { bits, largest_move, unreadable })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn bits_of_grid_points() {
        assert_eq!(bits_of(0), 0);
        assert_eq!(bits_of(128), 1);
        assert_eq!(bits_of(16), 4);
        assert_eq!(bits_of(24), 5);
        assert_eq!(bits_of(1), 8);
    }

    #[test]
    fn the_specification_holds_only_with_every_offset_read_a_fine_enough_grid_and_no_whole_step_moved() {
        let at = |bits: u32, largest_move: f32, unreadable: Vec<u32>| {
            SubpixelPrecision { bits, largest_move, unreadable }.within_specification()
        };
        // Four bits (a 1/16 px grid): a move under one step (plus the probe's 1/512 px) holds.
        let step = 1.0 / 16.0;
        assert!(at(4, step + 0.5 / 256.0 - 1e-6, vec![]) && at(8, 0.0, vec![]));
        // Each condition alone fails it: one offset unreadable, three bits, a whole step moved.
        assert!(!at(4, 0.0, vec![17]));
        assert!(!at(3, 0.0, vec![]));
        assert!(!at(4, step + 0.5 / 256.0, vec![]));
        assert!(!at(8, 1.0 / 256.0 + 0.5 / 256.0, vec![]));
    }

    #[test]
    fn covered_counts_give_the_snapped_offset() {
        // s = 0: the edge runs from the pixel's left side, 384 of 512 pixels covered.
        assert_eq!(snapped_from_covered(384), Some(0));
        assert_eq!(snapped_from_covered(128), Some(256));
        assert_eq!(snapped_from_covered(127), None);
    }
}
