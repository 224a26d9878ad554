//! How many samples an N-sample target really renders, and where they lie along each axis, where
//! no single sample can be read (no honoured sample mask, no fragment storage: GLES 3.0, WebGL2).
//! The edge sweep of `probe::sample_positions` drawn with every sample enabled, resolved: pixel i
//! averages the samples whose coordinate lies beyond the edge i/256 into it, so along the sweep
//! the resolve steps down from all samples to none, one level per sample coordinate (two samples
//! sharing a coordinate step together). The levels say how many samples there are; the steps say
//! each axis's sorted sample coordinates — a projection of the positions, without which sample
//! sits where.

use anyhow::{Result, bail};
use serde::Serialize;

use super::sample_positions::{Axis, Interval, STEPS, resolved_sweep, standard_positions};
use super::subpixel_precision::COARSEST_SNAP;
use crate::gpu::Gpu;

/// What one unmasked sweep per axis showed of an N-sample target.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct SampleProjections {
    /// The samples the resolve levels count: the most distinct coordinates either axis showed.
    pub rendered_samples: u32,
    /// Each axis's sample coordinates, in increasing order (one interval a sample).
    pub x: Vec<Interval>,
    pub y: Vec<Interval>,
}

impl SampleProjections {
    /// True when the target renders `samples` samples whose coordinates on each axis are the
    /// standard table's, within the coarsest sub-pixel snap (`caps::matches_standard`'s rule).
    pub fn matches_standard(&self, samples: u32) -> bool {
        let Some(table) = standard_positions(samples) else {
            return false;
        };
        let sorted = |axis: usize| {
            let mut values: Vec<f32> = table.iter().map(|p| p[axis]).collect();
            values.sort_by(f32::total_cmp);
            values
        };
        let holds = |measured: &[Interval], standard: Vec<f32>| {
            measured.len() == standard.len()
                && measured.iter().zip(standard).all(|(interval, value)| interval.within(COARSEST_SNAP, value))
        };
        self.rendered_samples == samples && holds(&self.x, sorted(0)) && holds(&self.y, sorted(1))
    }
}

/// The resolved coverage of each strip pixel of an unmasked sweep, as a count of `levels`
/// equal steps: pixel values must be multiples of 255 / levels (±1 for the resolve's rounding).
fn covered_levels(values: &[u8], levels: u32) -> Option<Vec<u32>> {
    values
        .iter()
        .map(|&v| {
            let level = (f64::from(v) * f64::from(levels) / 255.0).round();
            ((f64::from(v) - level * 255.0 / f64::from(levels)).abs() <= 1.0).then_some(level as u32)
        })
        .collect()
}

/// Each sample's coordinate along one axis, in increasing order, from an unmasked sweep.
fn sweep_axis(gpu: &Gpu, samples: u32, axis: Axis) -> Result<Vec<Interval>> {
    let values = resolved_sweep(gpu, samples, axis, u64::MAX)?;
    // The first pixel's edge lies on its left (top) side: every sample is covered there.
    if values[0] < 254 {
        bail!("{samples}x sweep along {axis:?}: the fully covered pixel resolved {} of 255", values[0]);
    }
    let distinct = {
        let mut seen = values.clone();
        seen.sort_unstable();
        seen.dedup();
        seen.len() as u32
    };
    // Each coordinate is one step; a target of M samples resolves multiples of 255 / M. Try the
    // counts the steps allow, fewest first: M is at least the steps seen.
    let steps = distinct.saturating_sub(1).max(1);
    let Some((rendered, covered)) =
        (steps..=64).find_map(|levels| covered_levels(&values, levels).map(|covered| (levels, covered)))
    else {
        bail!("{samples}x sweep along {axis:?}: resolved values {values:?} are no multiples of 1/M for any M up to 64");
    };
    if covered.windows(2).any(|pair| pair[1] > pair[0]) {
        bail!("{samples}x sweep along {axis:?}: coverage is not monotonic along the sweep ({covered:?})");
    }
    // A drop of d levels at pixel i: d coordinates crossed between (i - 1)/256 and i/256 (the
    // interval `sample_positions` gives a sample covered in pixels 0..i).
    let mut coordinates = Vec::new();
    let mut previous = rendered;
    for (i, &now) in covered.iter().chain(std::iter::once(&0)).enumerate().map(|(i, c)| (i as u32, c)) {
        for _ in now..previous {
            coordinates.push(Interval { lo: (i.max(1) - 1) as f32 / STEPS as f32, hi: i as f32 / STEPS as f32 });
        }
        previous = previous.min(now);
    }
    Ok(coordinates)
}

/// Sweeps an N-sample target along both axes with every sample enabled.
pub fn measure_projections(gpu: &Gpu, samples: u32) -> Result<SampleProjections> {
    super::scoped(gpu, &format!("{samples}x sample projections (unmasked resolve)"), || {
        let x = sweep_axis(gpu, samples, Axis::X)?;
        let y = sweep_axis(gpu, samples, Axis::Y)?;
        Ok(SampleProjections { rendered_samples: x.len().max(y.len()) as u32, x, y })
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn resolve_levels_are_read_as_equal_steps_of_the_real_count() {
        // A "2x" target that renders 4 samples: quarters, never halves alone.
        let quarters = [255, 191, 128, 64, 0];
        assert_eq!(covered_levels(&quarters, 4), Some(vec![4, 3, 2, 1, 0]));
        assert_eq!(covered_levels(&quarters, 2), None);
        assert_eq!(covered_levels(&[255, 128, 127, 0], 2), Some(vec![2, 1, 1, 0]));
    }
}
