//! `cbr.*`: checkerboard rendering.

pub mod jitter_coverage;
pub mod sample_quadrants;
