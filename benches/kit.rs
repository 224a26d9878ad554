//! GPU time of a heavy fragment shader behind a stencil-Equal gate passing 1.98 % of the pixels
//! versus stencil Always: what early stencil rejection buys on this adapter. Times come from
//! timestamp queries around the heavy pass (wall time of a submit-and-wait where the adapter
//! has no timestamps). Run with `cargo bench --bench kit`.

use std::time::Duration;

use criterion::{Criterion, criterion_group, criterion_main};
use fragkit::probe::stencil_gated_draw::{Gate, StencilGatedDraw};
use fragkit::{AdapterSelector, Gpu};

fn early_rejection(c: &mut Criterion) {
    let gpu = Gpu::open(&AdapterSelector::default()).unwrap_or_else(|e| panic!("{e:#}"));
    let (size, passing, iterations) = ((512, 512), (72, 72), 96);
    let draw = StencilGatedDraw::new(&gpu, size, passing, iterations).unwrap_or_else(|e| panic!("{e:#}"));
    let d = &gpu.description;
    let mut group = c.benchmark_group(format!("{}/{}", d.name, d.backend));
    group.sample_size(10).warm_up_time(Duration::from_secs(1)).measurement_time(Duration::from_secs(6));
    for (name, gate) in [("stencil_equal_1.98pct", Gate::Equal), ("stencil_always", Gate::Always)] {
        group.bench_function(format!("heavy_512x512/{name}"), |b| {
            b.iter_custom(|iterations| {
                (0..iterations)
                    .map(|_| {
                        let result = draw.draw(&gpu, gate).unwrap_or_else(|e| panic!("{e:#}"));
                        Duration::from_secs_f64(result.gpu_ms.unwrap_or(result.wall_ms) * 1e-3)
                    })
                    .sum()
            })
        });
    }
    group.finish();
}

criterion_group!(benches, early_rejection);
criterion_main!(benches);
