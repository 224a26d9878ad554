//! Pixel-space rectangles drawn as instanced quads (`shaders/kit/rect.wgsl`): the probes'
//! stencil patterns, coverage edges and fills.

use bytemuck::{Pod, Zeroable};
use wgpu::util::DeviceExt;

use crate::gpu::Gpu;
use crate::shaders::{self, ShaderFile};

/// A rectangle in framebuffer pixels (origin top-left, y down), half-open: [x0, x1) × [y0, y1).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Rect {
    pub x0: f32,
    pub y0: f32,
    pub x1: f32,
    pub y1: f32,
}

impl Rect {
    pub fn new(x0: f32, y0: f32, x1: f32, y1: f32) -> Self {
        Self { x0, y0, x1, y1 }
    }

    pub fn full(width: u32, height: u32) -> Self {
        Self::new(0.0, 0.0, width as f32, height as f32)
    }

    /// Its corners in clip space on a `target`-sized framebuffer (y up): x0, y0, x1, y1.
    pub fn clip(&self, target: (u32, u32)) -> [f32; 4] {
        let (w, h) = (target.0 as f32, target.1 as f32);
        [self.x0 / w * 2.0 - 1.0, 1.0 - self.y0 / h * 2.0, self.x1 / w * 2.0 - 1.0, 1.0 - self.y1 / h * 2.0]
    }

    /// Whether a point is inside under the top-left fill convention (left and top edges
    /// included, right and bottom excluded).
    pub fn covers(&self, x: f32, y: f32) -> bool {
        x >= self.x0 && x < self.x1 && y >= self.y0 && y < self.y1
    }
}

#[repr(C)]
#[derive(Clone, Copy, Pod, Zeroable)]
struct RectInstance {
    clip: [f32; 4],
    colour: [f32; 4],
}

/// Instances ready to draw on a target of a given size.
#[derive(Clone)]
pub struct RectBatch {
    buffer: wgpu::Buffer,
    count: u32,
}

impl RectBatch {
    pub fn new(gpu: &Gpu, target: (u32, u32), rects: &[(Rect, [f32; 4])]) -> Self {
        let instances: Vec<RectInstance> =
            rects.iter().map(|(r, colour)| RectInstance { clip: r.clip(target), colour: *colour }).collect();
        let buffer = gpu.device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
            label: Some("rect instances"),
            contents: bytemuck::cast_slice(&instances),
            usage: wgpu::BufferUsages::VERTEX,
        });
        Self { buffer, count: rects.len() as u32 }
    }

    /// Draws instances `range` (all with `..`).
    pub fn draw(&self, pass: &mut wgpu::RenderPass<'_>, range: impl std::ops::RangeBounds<u32>) {
        pass.set_vertex_buffer(0, self.buffer.slice(..));
        pass.draw(0..6, instances(range, self.count));
    }
}

/// The instances `range` names among `count`.
fn instances(range: impl std::ops::RangeBounds<u32>, count: u32) -> std::ops::Range<u32> {
    use std::ops::Bound;
    let start = match range.start_bound() {
        Bound::Included(&s) => s,
        Bound::Excluded(&s) => s + 1,
        Bound::Unbounded => 0,
    };
    let end = match range.end_bound() {
        Bound::Included(&e) => e + 1,
        Bound::Excluded(&e) => e,
        Bound::Unbounded => count,
    };
    start..end
}

/// Which fragment stage a rect pipeline runs.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum RectFragment {
    /// No fragment stage: depth/stencil only.
    None,
    /// The instance colour (`shaders/kit/rect.wgsl`).
    InstanceColour,
    /// A fragment entry point of another shader file, which the rect's vertex outputs feed
    /// (`shaders/kit/rect.wgsl`'s `RectOut`): a probe's or a technique's own stage.
    Shader { file: ShaderFile, entry: &'static str },
}

/// The fixed-function state of a rect pipeline.
#[derive(Clone, Debug)]
pub struct RectPipeline {
    pub label: &'static str,
    pub colour_format: Option<wgpu::TextureFormat>,
    /// The channels of the colour target written (none: a draw into a pass with a colour
    /// attachment that only marks the stencil).
    pub colour_writes: wgpu::ColorWrites,
    pub fragment: RectFragment,
    pub depth_stencil: Option<wgpu::DepthStencilState>,
    pub samples: u32,
    pub sample_mask: u64,
    pub alpha_to_coverage: bool,
}

impl RectPipeline {
    pub fn new(label: &'static str) -> Self {
        Self {
            label,
            colour_format: None,
            colour_writes: wgpu::ColorWrites::ALL,
            fragment: RectFragment::None,
            depth_stencil: None,
            samples: 1,
            sample_mask: !0,
            alpha_to_coverage: false,
        }
    }

    pub fn create(&self, gpu: &Gpu) -> wgpu::RenderPipeline {
        let rect = shaders::RECT.module(gpu);
        let targets: Vec<Option<wgpu::ColorTargetState>> = self
            .colour_format
            .map(|format| Some(wgpu::ColorTargetState { format, blend: None, write_mask: self.colour_writes }))
            .into_iter()
            .collect();
        let fragment_file = match self.fragment {
            RectFragment::None => None,
            RectFragment::InstanceColour => Some((shaders::RECT, "fs_instance_colour")),
            RectFragment::Shader { file, entry } => Some((file, entry)),
        };
        let fragment = fragment_file.map(|(file, entry)| (file.module(gpu), entry));
        gpu.device.create_render_pipeline(&wgpu::RenderPipelineDescriptor {
            label: Some(self.label),
            layout: None,
            vertex: wgpu::VertexState {
                module: &rect,
                entry_point: Some("vs_rect"),
                compilation_options: Default::default(),
                buffers: &[Some(wgpu::VertexBufferLayout {
                    array_stride: std::mem::size_of::<RectInstance>() as u64,
                    step_mode: wgpu::VertexStepMode::Instance,
                    attributes: &wgpu::vertex_attr_array![0 => Float32x4, 1 => Float32x4],
                })],
            },
            primitive: wgpu::PrimitiveState::default(),
            depth_stencil: self.depth_stencil.clone(),
            multisample: wgpu::MultisampleState {
                count: self.samples,
                mask: self.sample_mask,
                alpha_to_coverage_enabled: self.alpha_to_coverage,
            },
            fragment: fragment.as_ref().map(|(module, entry)| wgpu::FragmentState {
                module,
                entry_point: Some(entry),
                compilation_options: Default::default(),
                targets: &targets,
            }),
            multiview_mask: None,
            cache: None,
        })
    }
}

/// Stencil state that writes `reference` wherever a draw lands (compare Always, op Replace).
pub fn stencil_replace(format: wgpu::TextureFormat) -> wgpu::DepthStencilState {
    stencil_state(format, wgpu::CompareFunction::Always, wgpu::StencilOperation::Replace)
}

/// Stencil state that passes where the stencil equals `reference` and writes nothing.
pub fn stencil_equal(format: wgpu::TextureFormat) -> wgpu::DepthStencilState {
    stencil_state(format, wgpu::CompareFunction::Equal, wgpu::StencilOperation::Keep)
}

/// Stencil-only testing state (read and write mask 0xff); depth is left alone: always passes and
/// is never written where the format has depth, absent where it has none (`Stencil8`).
pub fn stencil_state(
    format: wgpu::TextureFormat,
    compare: wgpu::CompareFunction,
    pass_op: wgpu::StencilOperation,
) -> wgpu::DepthStencilState {
    let face = wgpu::StencilFaceState {
        compare,
        fail_op: wgpu::StencilOperation::Keep,
        depth_fail_op: wgpu::StencilOperation::Keep,
        pass_op,
    };
    let depth = format.has_depth_aspect();
    wgpu::DepthStencilState {
        format,
        depth_write_enabled: depth.then_some(false),
        depth_compare: depth.then_some(wgpu::CompareFunction::Always),
        stencil: wgpu::StencilState { front: face, back: face, read_mask: 0xff, write_mask: 0xff },
        bias: Default::default(),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_rect_covers_its_top_and_left_edges_but_not_its_bottom_and_right() {
        let rect = Rect::new(2.0, 3.0, 6.0, 5.0);
        for (x, y, inside) in [
            (2.0, 3.0, true),
            (5.99, 4.99, true),
            (6.0, 4.0, false),
            (4.0, 5.0, false),
            (1.99, 4.0, false),
            (4.0, 2.99, false),
        ] {
            assert_eq!(rect.covers(x, y), inside, "({x}, {y})");
        }
        assert_eq!(Rect::full(8, 4), Rect::new(0.0, 0.0, 8.0, 4.0));
    }

    #[test]
    fn clip_space_corners_and_instance_ranges_follow_their_definitions() {
        // The whole target is clip space's square, y up.
        assert_eq!(Rect::full(8, 4).clip((8, 4)), [-1.0, 1.0, 1.0, -1.0]);
        assert_eq!(Rect::new(2.0, 1.0, 6.0, 3.0).clip((8, 4)), [-0.5, 0.5, 0.5, -0.5]);
        assert_eq!(instances(.., 5), 0..5);
        assert_eq!(instances(1..3, 5), 1..3);
        assert_eq!(instances(1..=3, 5), 1..4);
        assert_eq!(instances(2.., 5), 2..5);
        use std::ops::Bound;
        assert_eq!(instances((Bound::Excluded(1), Bound::Unbounded), 5), 2..5);
    }
}
