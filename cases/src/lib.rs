//! fragkit's render cases, one per file under `<area>/`, and the registry the CLI and the tests
//! share.

use fragkit::harness::Case;

pub mod cbr;
pub mod cps;
pub mod fault;
pub mod kit;
pub mod oit;
pub mod soak;
pub mod texarray;

/// The known issues of this kit's cases on the adapters it was run on (cases/expectations.toml),
/// built in so that an installed `fragkit` needs no checkout.
pub const EXPECTATIONS: &str = include_str!("../expectations.toml");

/// Every case, in the order `fragkit check` runs them (opt-in ones only when named).
pub const ALL: &[Case] = &[
    kit::subpixel_precision::CASE,
    kit::msaa_sample_positions::CASE_1X,
    kit::msaa_sample_positions::CASE_2X,
    kit::msaa_sample_positions::CASE_4X,
    kit::msaa_sample_positions::CASE_8X,
    kit::sample_mask::CASE,
    kit::occlusion_exact::CASE,
    kit::scissor_msaa::CASE,
    kit::early_rejection::CASE,
    kit::determinism::CASE,
    kit::hash_values::CASE,
    kit::deferred_gbuffer::CASE,
    kit::deferred_lighting::CASE,
    kit::mip_fetch::CASE,
    kit::indirect_draw::CASE,
    cps::lod_policy::CASE,
    cps::stencil_equal_counts::CASE,
    cps::level_lighting::CASE,
    cps::all_fine_equals_fullres::CASE,
    cps::composite_matches_reference::CASE,
    cps::composite_linear_precision::CASE,
    cps::composite_seam_free_sweep::CASE,
    cps::early_rejection::CASE,
    cps::extremes::CASE,
    texarray::index_exactness::CASE,
    oit::a2c_transfer::CASE,
    oit::coverage_stats::CASE,
    oit::order_independence::CASE,
    oit::quads_converges::CASE,
    oit::post_filter::CASE,
    oit::weighted_blended::CASE,
    oit::baselines_exact::CASE,
    oit::extremes::CASE,
    cbr::layout_mapping::CASE,
    cbr::sample_quadrants::CASE,
    cbr::jitter_coverage::CASE,
    cbr::reconstruct_static::CASE,
    cbr::reconstruct_moving::CASE,
    cbr::exact_sources::CASE,
    cbr::extremes::CASE,
    cbr::deferred_full_resolution::CASE,
    cbr::upscale_bilinear::CASE,
    // Opt-in (only when a pattern names them): see `fragkit::harness::runner::OPT_IN`.
    fault::validation_error::CASE,
    fault::device_loss::CASE,
    fault::process_death::ABORT,
    fault::process_death::SEGFAULT,
    fault::hang::CASE,
    fault::out_of_memory::CASE,
    soak::cps::CASE,
    soak::oit::CASE,
    soak::cbr::CASE,
];
