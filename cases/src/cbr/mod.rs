//! `cbr.*`: checkerboard rendering.

pub mod deferred_full_resolution;
pub mod exact_sources;
pub mod extremes;
pub mod jitter_coverage;
pub mod layout_mapping;
pub mod reconstruct_moving;
pub mod reconstruct_static;
pub mod sample_quadrants;
pub mod upscale_bilinear;
