//! Coarse pixel shading against full-resolution deferred shading (`fragkit::bench::cps`): the
//! corridor with 200 lights at 640×360, foveated LOD at three fovea sizes. The speed-up is the
//! median of per-round ratios, each round timing full resolution and CPS back to back, set
//! against the ideal one implied by the shaded texel counts, with where the rest goes. Writes
//! target/fragkit-bench/cps.json. Run with `cargo bench --profile dev --bench cps`; `fragkit bench
//! cps` measures the same from the binary.

mod common;

use criterion::{Criterion, criterion_group, criterion_main};

fn cps_bench(c: &mut Criterion) {
    common::criterion_then_rounds(c, "cps", 9);
}

criterion_group!(benches, cps_bench);
criterion_main!(benches);
