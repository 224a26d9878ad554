//! `oit.*`: order-independent transparency by stochastic alpha-to-coverage.

pub mod a2c_transfer;
pub mod baselines_exact;
pub mod coverage_stats;
pub mod extremes;
pub mod order_independence;
pub mod post_filter;
pub mod quads_converges;
pub mod weighted_blended;

use fragkit::Gpu;
use fragkit::caps::{common_sample_counts, matches_standard};
use fragkit::probe::sample_positions::measure;

/// Multisample counts to test: those the adapter claims, above 1, where a target of that count
/// really renders that many samples at the standard positions (llvmpipe's GL "2x" runs 4).
pub fn multisample_counts(gpu: &Gpu) -> Vec<u32> {
    common_sample_counts(gpu)
        .into_iter()
        .filter(|&n| n > 1)
        .filter(|&n| measure(gpu, n).is_ok_and(|m| m.agreed().is_some_and(|p| matches_standard(n, p))))
        .collect()
}
