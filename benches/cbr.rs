//! Checkerboard rendering against full resolution where pixel shading dominates
//! (`fragkit::bench::cbr`): the static textured corridor with 200 lights at 320×180, forward and
//! deferred, on each path this adapter has. Writes target/fragkit-bench/cbr.json. Run with
//! `cargo bench --profile dev --bench cbr`; `fragkit bench cbr` measures the same from the binary.

mod common;

use criterion::{Criterion, criterion_group, criterion_main};

fn cbr_bench(c: &mut Criterion) {
    common::criterion_then_rounds(c, "cbr", 15);
}

criterion_group!(benches, cbr_bench);
criterion_main!(benches);
