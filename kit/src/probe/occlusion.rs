//! Whether occlusion queries count passing samples or only say "some passed" (GL uses
//! `ANY_SAMPLES_PASSED_CONSERVATIVE`; WebGPU allows either).

use anyhow::Result;
use serde::Serialize;

use crate::attachments::colour;
use crate::gpu::Gpu;
use crate::query::OcclusionQueries;
use crate::rects::{Rect, RectBatch, RectPipeline};

#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum OcclusionPrecision {
    /// The query returned the number of passing samples.
    Exact,
    /// The query returned 1 for several passing samples (and 0 for none).
    Boolean,
    /// Anything else: the returned values are given.
    Wrong { for_none: u64, for_some: u64, expected: u64 },
}

impl OcclusionPrecision {
    /// Whether a query's answer `measured` can be right for a draw of which `expected` samples
    /// passed: an exact query counts them; a Boolean one (GL's `ANY_SAMPLES_PASSED_CONSERVATIVE`)
    /// must say 1 where any passed and may say 1 where none did ("conservative"). Nothing holds
    /// for a query the probe found wrong.
    pub fn allows(self, measured: u64, expected: u64) -> bool {
        match self {
            Self::Exact => measured == expected,
            Self::Boolean if expected > 0 => measured == 1,
            Self::Boolean => measured <= 1,
            Self::Wrong { .. } => false,
        }
    }
}

/// Draws a 3×2-pixel rect on an 8×8 target (6 samples pass) and an empty one (0 pass).
pub fn measure_occlusion_precision(gpu: &Gpu) -> Result<OcclusionPrecision> {
    gpu.scoped("occlusion precision probe", || {
        let size = (8, 8);
        let format = wgpu::TextureFormat::Rgba8Unorm;
        let target = gpu.texture("occlusion probe", size, format, 1, wgpu::TextureUsages::RENDER_ATTACHMENT);
        let view = target.create_view(&Default::default());
        let rects = RectBatch::new(
            gpu,
            size,
            &[(Rect::new(2.0, 3.0, 5.0, 5.0), [1.0; 4]), (Rect::new(4.0, 4.0, 4.0, 7.0), [1.0; 4])],
        );
        let pipeline = RectPipeline {
            colour_format: Some(format),
            fragment: crate::rects::RectFragment::InstanceColour,
            ..RectPipeline::new("occlusion probe")
        }
        .create(gpu);
        let queries = OcclusionQueries::new(gpu, 2);
        let mut encoder = gpu.encoder("occlusion probe");
        {
            let mut pass = encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
                label: Some("occlusion probe"),
                color_attachments: &[colour(&view, None, wgpu::Color::BLACK)],
                occlusion_query_set: Some(queries.set()),
                ..Default::default()
            });
            pass.set_pipeline(&pipeline);
            pass.begin_occlusion_query(0);
            rects.draw(&mut pass, 0..1);
            pass.end_occlusion_query();
            pass.begin_occlusion_query(1);
            rects.draw(&mut pass, 1..2);
            pass.end_occlusion_query();
        }
        queries.resolve(&mut encoder);
        gpu.submit(encoder);
        let counts = queries.read(gpu)?;
        Ok(match (counts[0], counts[1]) {
            (6, 0) => OcclusionPrecision::Exact,
            (1, 0) => OcclusionPrecision::Boolean,
            (some, none) => OcclusionPrecision::Wrong { for_none: none, for_some: some, expected: 6 },
        })
    })
}

#[cfg(test)]
mod tests {
    use super::OcclusionPrecision;

    #[test]
    fn a_boolean_query_must_see_any_passing_sample_and_may_see_one_where_none_passed() {
        let boolean = OcclusionPrecision::Boolean;
        assert!(boolean.allows(1, 2) && boolean.allows(0, 0) && boolean.allows(1, 0));
        assert!(!boolean.allows(0, 2) && !boolean.allows(2, 2));
        assert!(OcclusionPrecision::Exact.allows(2, 2) && !OcclusionPrecision::Exact.allows(1, 2));
        assert!(!OcclusionPrecision::Wrong { for_none: 0, for_some: 0, expected: 6 }.allows(0, 0));
    }
}
