//! `cbr.*`: checkerboard rendering.

fragkit::cases! {
    layout_mapping: CASE;
    sample_quadrants: CASE;
    jitter_coverage: CASE;
    reconstruct_static: CASE;
    reconstruct_moving: CASE;
    reconstruct_exact_sources: CASE;
    extremes: CASE;
    deferred_full_resolution: CASE;
    upscale_bilinear: CASE;
}
