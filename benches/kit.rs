//! What early stencil rejection buys on this adapter (`fragkit::bench::stencil`): a heavy fragment
//! shader behind a stencil-Equal gate passing 1.98 % of the pixels versus stencil Always. Writes
//! target/fragkit-bench/kit.json. Run with `cargo bench --profile dev --bench kit`; `fragkit bench
//! kit` measures the same from the binary.

mod common;

use criterion::{Criterion, criterion_group, criterion_main};

fn kit_bench(c: &mut Criterion) {
    common::criterion_then_rounds(c, "kit", 9);
}

criterion_group!(benches, kit_bench);
criterion_main!(benches);
