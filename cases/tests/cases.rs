//! One test per registered case: it fails when the case ends in an unexpected failure (a fail
//! not listed in cases/expectations.toml, or a listed one that passed). Where the result is
//! adapter-specific, its outcome and metrics (timings left out) are snapshotted per adapter.

mod support;

use fragkit_report::report::{CaseRecord, is_timing_metric};

fn check(name: &str) {
    let (record, slug) = support::run(name);
    assert!(
        !record.outcome.is_failure(false),
        "{name}: {:?}: {}\nmetrics: {}",
        record.outcome,
        record.reason,
        serde_json::to_string_pretty(&record.metrics).unwrap()
    );
    if support::has_snapshots(&slug) {
        snapshot(&record, &slug);
    }
}

fn snapshot(record: &CaseRecord, slug: &str) {
    let mut metrics = record.metrics.clone();
    metrics.retain(|k, _| !is_timing_metric(k));
    let mut settings = insta::Settings::clone_current();
    settings.set_snapshot_path("../../snapshots");
    settings.set_snapshot_suffix(slug);
    settings.set_prepend_module_to_snapshot(false);
    settings.bind(|| {
        insta::assert_json_snapshot!(
            record.name.clone(),
            serde_json::json!({"outcome": record.outcome, "metrics": metrics})
        );
    });
}

macro_rules! case_tests {
    ($($test:ident => $name:literal),* $(,)?) => {
        $(#[test] fn $test() { check($name); })*

        #[test]
        fn every_registered_case_has_a_test() {
            let tested: Vec<&str> = vec![$($name),*];
            // Opt-in cases are tested where they are meant to run: fault.* by tests/cli.rs
            // (between ordinary cases), soak.* by tests/soak.rs.
            let opt_in = |name: &str| fragkit::harness::runner::OPT_IN.iter().any(|p| name.starts_with(p));
            for case in fragkit_cases::ALL.iter().filter(|c| !opt_in(c.name)) {
                assert!(tested.contains(&case.name), "case {} has no test in cases/tests/cases.rs", case.name);
            }
        }
    };
}

case_tests! {
    kit_raster_subpixel_precision => "kit.raster.subpixel_precision",
    kit_msaa_sample_positions_1x => "kit.msaa.sample_positions.1x",
    kit_msaa_sample_positions_2x => "kit.msaa.sample_positions.2x",
    kit_msaa_sample_positions_4x => "kit.msaa.sample_positions.4x",
    kit_msaa_sample_positions_8x => "kit.msaa.sample_positions.8x",
    kit_msaa_sample_mask => "kit.msaa.sample_mask",
    kit_occlusion_exact => "kit.occlusion.exact",
    kit_scissor_msaa => "kit.scissor.msaa",
    kit_early_rejection => "kit.early_rejection",
    kit_determinism => "kit.determinism",
    kit_hash_values => "kit.hash.values",
    kit_deferred_gbuffer => "kit.deferred.gbuffer",
    kit_deferred_lighting => "kit.deferred.lighting",
    kit_fetch_per_pixel_level => "kit.fetch.per_pixel_level",
    kit_draw_indirect => "kit.draw.indirect",
    cps_lod_policy => "cps.lod_policy",
    cps_stencil_equal_counts => "cps.stencil_equal.counts",
    cps_level_lighting => "cps.level_lighting",
    cps_all_fine_equals_fullres => "cps.all_fine_equals_fullres",
    cps_composite_matches_reference => "cps.composite.matches_reference",
    cps_composite_linear_precision => "cps.composite.linear_precision",
    cps_composite_seam_free_sweep => "cps.composite.seam_free_sweep",
    cps_early_rejection => "cps.early_rejection",
    cps_extremes => "cps.extremes",
    texarray_index_exactness => "texarray.index_exactness",
    oit_a2c_transfer => "oit.a2c.transfer",
    oit_a2c_coverage_stats => "oit.a2c.coverage_stats",
    oit_order_independence => "oit.order_independence",
    oit_quads_converges => "oit.quads.converges",
    oit_post_filter => "oit.post_filter",
    oit_weighted_blended => "oit.weighted_blended",
    oit_baselines_exact => "oit.baselines.exact",
    oit_extremes => "oit.extremes",
    cbr_layout_mapping => "cbr.layout.mapping",
    cbr_sample_quadrants => "cbr.sample_quadrants",
    cbr_jitter_coverage => "cbr.jitter.coverage",
    cbr_reconstruct_static => "cbr.reconstruct.static",
    cbr_reconstruct_moving => "cbr.reconstruct.moving",
    cbr_reconstruct_exact_sources => "cbr.reconstruct.exact_sources",
    cbr_extremes => "cbr.extremes",
    cbr_deferred_full_resolution => "cbr.deferred_full_resolution",
    cbr_upscale_bilinear => "cbr.upscale.bilinear",
}
