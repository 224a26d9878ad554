//! `oit.*`: order-independent transparency by stochastic alpha-to-coverage.

fragkit::cases! {
    a2c_transfer: CASE;
    a2c_coverage_stats: CASE;
    order_independence: CASE;
    quads_converges: CASE;
    post_filter: CASE;
    weighted_blended: CASE;
    baselines_exact: CASE;
    extremes: CASE;
}

use fragkit::Gpu;
use fragkit::caps::{broken_sample_counts, common_sample_counts, matches_standard};
use fragkit::harness::Outcome;
use fragkit::probe::sample_positions::measure;
use fragkit::probe::sample_projections::measure_projections;

/// Multisample counts to test: those the adapter claims, above 1, where a target of that count
/// really renders that many samples (llvmpipe's GL "2x" runs 4): at the standard positions where
/// single samples can be read; where no route can (GLES 3.0: no sample mask, no fragment
/// storage; GLES 3.2: naga's per-sample GLSL ES does not compile), by the resolve levels of an
/// unmasked edge sweep — alpha-to-coverage needs N samples, not their positions. With none, the
/// outcome to end the case with: `not_supported` with what the probes found, or `fail` where an
/// advertised count does not render at all (the adapter's or wgpu's failure, not a missing
/// capability).
pub fn multisample_counts(gpu: &Gpu) -> anyhow::Result<Result<Vec<u32>, Outcome>> {
    let advertised: Vec<u32> = common_sample_counts(gpu).into_iter().filter(|&n| n > 1).collect();
    let renders = |n: u32| -> anyhow::Result<bool> {
        let positions = measure(gpu, n)?;
        Ok(match positions.read_single_samples() {
            true => positions.agreed().is_some_and(|p| matches_standard(n, p)),
            false => measure_projections(gpu, n).is_ok_and(|p| p.rendered_samples == n),
        })
    };
    let real: Vec<u32> = advertised.iter().copied().filter(|&n| renders(n).unwrap_or(false)).collect();
    if !real.is_empty() {
        return Ok(Ok(real));
    }
    let broken = broken_sample_counts(gpu)?;
    Ok(Err(if advertised.is_empty() {
        Outcome::NotSupported("multisampling: the adapter advertises no count above 1".into())
    } else if !broken.is_empty() {
        Outcome::Fail(broken.into_iter().map(|(_, problem)| problem).collect::<Vec<_>>().join("; "))
    } else {
        Outcome::NotSupported(format!(
            "multisampling: of the advertised {advertised:?}, no count renders that many samples (at the standard positions, kit.msaa.sample_positions.Nx)"
        ))
    }))
}
