//! `Caps`: what an adapter can do, each entry filled by a measurement (a tiny render) where one
//! is possible, by the API's claim only where nothing can be rendered to check it.

use anyhow::Result;
use serde::Serialize;

use crate::gpu::Gpu;
use crate::probe::alpha_to_coverage::{AlphaToCoverage, measure_alpha_to_coverage};
use crate::probe::occlusion::{OcclusionPrecision, measure_occlusion_precision};
use crate::probe::sample_positions::{
    PerSampleShading, PositionsMeasurement, SamplePosition, measure, measure_per_sample_shading, standard_positions,
};
use crate::probe::subpixel_precision::{self, COARSEST_SNAP, SubpixelPrecision};
use fragkit_report::AdapterDescription;

/// Formats whose multisample support the report lists.
pub const PROBED_FORMATS: &[wgpu::TextureFormat] = &[
    wgpu::TextureFormat::Rgba8Unorm,
    wgpu::TextureFormat::Rgba16Float,
    wgpu::TextureFormat::Depth24PlusStencil8,
    wgpu::TextureFormat::Depth32Float,
];

pub const SAMPLE_COUNTS: &[u32] = &[1, 2, 4, 8];

#[derive(Clone, Debug, Serialize)]
pub struct FormatSamples {
    pub format: String,
    /// What the adapter claims (with `TEXTURE_ADAPTER_SPECIFIC_FORMAT_FEATURES` where present).
    pub advertised: Vec<u32>,
}

/// What rendering to an N-sample target really did.
#[derive(Clone, Debug, Serialize)]
pub struct MultisampleMeasurement {
    pub samples: u32,
    /// The edge sweep by every route the adapter allows, or the error that stopped it.
    pub positions: Result<PositionsMeasurement, String>,
    /// True when the routes agree and every sample lies at its standard position.
    pub standard_positions: bool,
    pub per_sample_shading: Result<PerSampleShading, String>,
    pub alpha_to_coverage: Result<AlphaToCoverage, String>,
}

#[derive(Clone, Debug, Serialize)]
pub struct Caps {
    pub adapter: AdapterDescription,
    pub max_texture_dimension_2d: u32,
    /// The rasteriser's vertex snapping, measured (the kit's expectations assume only 4 bits).
    pub subpixel_precision: Result<SubpixelPrecision, String>,
    pub format_samples: Vec<FormatSamples>,
    /// Sample counts advertised for every probed colour and depth format alike.
    pub advertised_sample_counts: Vec<u32>,
    pub multisample: Vec<MultisampleMeasurement>,
    pub occlusion: Result<OcclusionPrecision, String>,
    pub timestamps: bool,
    pub timestamp_period_ns: f32,
    pub early_depth_test_feature: bool,
    pub fragment_storage_writes: bool,
}

/// Sample counts the adapter claims for `format`.
pub fn advertised_sample_counts(gpu: &Gpu, format: wgpu::TextureFormat) -> Vec<u32> {
    let claimed = if gpu.has(wgpu::Features::TEXTURE_ADAPTER_SPECIFIC_FORMAT_FEATURES) {
        gpu.adapter.get_texture_format_features(format).flags.supported_sample_counts()
    } else {
        format.guaranteed_format_features(gpu.device.features()).flags.supported_sample_counts()
    };
    SAMPLE_COUNTS.iter().copied().filter(|n| claimed.contains(n)).collect()
}

/// The counts above 1 that every probed format claims but whose targets do not render, each
/// with what the probe saw (`probe::multisample_render`).
pub fn broken_sample_counts(gpu: &Gpu) -> Result<Vec<(u32, String)>> {
    let mut broken = Vec::new();
    for samples in common_sample_counts(gpu).into_iter().filter(|&n| n > 1) {
        if let Some(problem) = crate::probe::multisample_render::render_problem(gpu, samples)? {
            broken.push((samples, problem));
        }
    }
    Ok(broken)
}

/// Sample counts that every probed format claims.
pub fn common_sample_counts(gpu: &Gpu) -> Vec<u32> {
    SAMPLE_COUNTS
        .iter()
        .copied()
        .filter(|&n| PROBED_FORMATS.iter().all(|&f| advertised_sample_counts(gpu, f).contains(&n)))
        .collect()
}

/// True when each sample's measured interval holds its standard position, give or take what
/// vertex snapping at the coarsest precision Vulkan and GL permit (4 bits) may move the swept
/// edge: less than 1/16 px. Standard positions lie 1/8 px apart or more on each axis, so no
/// sample can pass for another's.
pub fn matches_standard(samples: u32, positions: &[SamplePosition]) -> bool {
    let Some(table) = standard_positions(samples) else {
        return false;
    };
    positions.len() == table.len()
        && positions.iter().zip(table).all(|(measured, &[x, y])| {
            measured.x.is_some_and(|i| i.within(COARSEST_SNAP, x))
                && measured.y.is_some_and(|i| i.within(COARSEST_SNAP, y))
        })
}

impl Caps {
    pub fn measure(gpu: &Gpu) -> Result<Self> {
        let common_counts = common_sample_counts(gpu);
        let multisample = common_counts
            .iter()
            .map(|&samples| {
                let positions = measure(gpu, samples).map_err(|e| format!("{e:#}"));
                let mask_honoured = positions.as_ref().is_ok_and(|p| p.sample_mask_honoured);
                let standard_positions = positions
                    .as_ref()
                    .ok()
                    .and_then(PositionsMeasurement::agreed)
                    .is_some_and(|p| matches_standard(samples, p));
                MultisampleMeasurement {
                    samples,
                    positions,
                    standard_positions,
                    per_sample_shading: measure_per_sample_shading(gpu, samples).map_err(|e| format!("{e:#}")),
                    alpha_to_coverage: if samples > 1 {
                        measure_alpha_to_coverage(gpu, samples, mask_honoured).map_err(|e| format!("{e:#}"))
                    } else {
                        Err("alpha-to-coverage needs more than one sample".into())
                    },
                }
            })
            .collect();
        let limits = gpu.device.limits();
        Ok(Self {
            adapter: gpu.description.clone(),
            max_texture_dimension_2d: limits.max_texture_dimension_2d,
            subpixel_precision: subpixel_precision::measure(gpu).map_err(|e| format!("{e:#}")),
            format_samples: PROBED_FORMATS
                .iter()
                .map(|&f| FormatSamples { format: format!("{f:?}"), advertised: advertised_sample_counts(gpu, f) })
                .collect(),
            advertised_sample_counts: common_counts,
            multisample,
            occlusion: measure_occlusion_precision(gpu).map_err(|e| format!("{e:#}")),
            timestamps: gpu.has(wgpu::Features::TIMESTAMP_QUERY),
            timestamp_period_ns: gpu.queue.get_timestamp_period(),
            early_depth_test_feature: gpu.has(wgpu::Features::SHADER_EARLY_DEPTH_TEST),
            // A render that writes storage, not the flag (softpipe's GL 3.3 claims it, naga refuses).
            fragment_storage_writes: crate::probe::fragment_storage::fragment_storage_problem(gpu)?.is_none(),
        })
    }

    /// Sample counts where a real N-sample target rendered N samples at the standard positions.
    pub fn real_sample_counts(&self) -> Vec<u32> {
        self.multisample.iter().filter(|m| m.standard_positions).map(|m| m.samples).collect()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::probe::sample_positions::Interval;

    fn at(x: f32, y: f32, half_width: f32) -> SamplePosition {
        let interval = |v: f32| Some(Interval { lo: v - half_width, hi: v + half_width });
        SamplePosition { x: interval(x), y: interval(y) }
    }

    /// Standard when every sample's intervals hold its table position up to 1/16 px on either
    /// side, in the table's order; a missing coordinate, a sample off by more, the wrong count
    /// or a count with no table is not.
    #[test]
    fn positions_match_the_standard_table_within_the_coarsest_snap_only() {
        let two = |a: [f32; 2], b: [f32; 2]| vec![at(a[0], a[1], 0.002), at(b[0], b[1], 0.002)];
        assert!(matches_standard(2, &two([0.75, 0.75], [0.25, 0.25])));
        // Up to just inside 1/16 beyond the interval, either side, either axis.
        assert!(matches_standard(2, &two([0.75 + 0.06, 0.75], [0.25, 0.25 - 0.06])));
        assert!(!matches_standard(2, &two([0.75 + 0.07, 0.75], [0.25, 0.25])));
        assert!(!matches_standard(2, &two([0.75, 0.75 - 0.07], [0.25, 0.25])));
        assert!(!matches_standard(2, &two([0.75, 0.75], [0.25, 0.25 + 0.07])));
        // The order counts: swapped samples are another pattern.
        assert!(!matches_standard(2, &two([0.25, 0.25], [0.75, 0.75])));
        let mut missing = two([0.75, 0.75], [0.25, 0.25]);
        missing[1].y = None;
        assert!(!matches_standard(2, &missing));
        missing[1] = SamplePosition { x: None, ..at(0.25, 0.25, 0.002) };
        assert!(!matches_standard(2, &missing));
        assert!(!matches_standard(2, &two([0.75, 0.75], [0.25, 0.25])[..1]));
        assert!(!matches_standard(3, &two([0.75, 0.75], [0.25, 0.25])));
        assert!(matches_standard(1, &[at(0.5, 0.5, 0.0)]));
    }
}
