//! `kit.*`: conformance of the adapter features the techniques rely on.

fragkit::cases! {
    raster_subpixel_precision: CASE;
    msaa_sample_positions: CASE_1X, CASE_2X, CASE_4X, CASE_8X;
    msaa_sample_mask: CASE;
    occlusion_exact: CASE;
    scissor_msaa: CASE;
    early_rejection: CASE;
    determinism: CASE;
    hash_values: CASE;
    deferred_gbuffer: CASE;
    deferred_lighting: CASE;
    fetch_per_pixel_level: CASE;
    draw_indirect: CASE;
}
