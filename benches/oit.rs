//! Order-independent transparency on the 16-layer stiff scene at 256×256
//! (`fragkit::bench::oit`): one stochastic frame and weighted blended OIT against exact depth
//! peeling. Timings on a 2-core CPU rasteriser wander by ±30 %: 21 rounds. Writes
//! target/fragkit-bench/oit.json. Run with `cargo bench --profile dev --bench oit`; `fragkit bench
//! oit` measures the same from the binary.

mod common;

use criterion::{Criterion, criterion_group, criterion_main};

fn oit_bench(c: &mut Criterion) {
    common::criterion_then_rounds(c, "oit", 21);
}

criterion_group!(benches, oit_bench);
criterion_main!(benches);
