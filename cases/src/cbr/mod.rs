//! `cbr.*`: checkerboard rendering.

pub mod extremes;
pub mod jitter_coverage;
pub mod reconstruct_moving;
pub mod reconstruct_static;
pub mod sample_quadrants;
