//! Order-independent transparency on the 16-layer stiff scene at 256×256: one stochastic frame
//! (4x, the paper's variant) against exact depth peeling and weighted blended OIT. GPU time from
//! timestamp queries around every pass; writes the ratios to target/fragkit-bench/oit.json. Run
//! with `cargo bench --profile dev --bench oit`.

use std::time::Duration;

use criterion::{Criterion, criterion_group, criterion_main};
use fragkit::oit::run::{Accumulation, Method, run_method};
use fragkit::oit::scene::QuadScene;
use fragkit::oit::stochastic::Stochastic;
use fragkit::query::median;
use fragkit::{AdapterSelector, Gpu};

const SIZE: (u32, u32) = (256, 256);

fn oit_methods(c: &mut Criterion) {
    let gpu = Gpu::open(&AdapterSelector::default()).unwrap_or_else(|e| panic!("{e:#}"));
    assert!(gpu.has(wgpu::Features::TIMESTAMP_QUERY), "this benchmark reads GPU timestamps");
    let scene = QuadScene::stiff(16, 1);
    let once = Accumulation { frames: 1, seed: 1, filtered: false };
    let methods = [
        ("stochastic_4x", Method::Stochastic(Stochastic::Paper), 4),
        ("depth_peeling", Method::DepthPeeling, 1),
        ("weighted_blended", Method::WeightedBlended, 1),
    ];
    let time = |method: &Method, samples: u32| {
        run_method(&gpu, &scene, SIZE, samples, method, once).unwrap_or_else(|e| panic!("{e:#}")).gpu_ms
    };
    let d = &gpu.description;
    let mut group = c.benchmark_group(format!("{}/{}", d.name, d.backend));
    group.sample_size(10).warm_up_time(Duration::from_secs(1)).measurement_time(Duration::from_secs(6));
    for (name, method, samples) in &methods {
        group.bench_function(format!("oit_16_layers_256x256/{name}"), |b| {
            b.iter_custom(|n| (0..n).map(|_| Duration::from_secs_f64(time(method, *samples) * 1e-3)).sum())
        });
    }
    group.finish();

    // Timings on a 2-core CPU rasteriser wander by ±30 %: a median of 21 runs.
    let [stochastic, peeling, weighted] =
        methods.map(|(_, method, samples)| median((0..21).map(|_| time(&method, samples)).collect()));
    println!(
        "oit: stochastic {stochastic:.2} ms, depth peeling {peeling:.2} ms ({:.1}x slower), weighted blended {weighted:.2} ms",
        peeling / stochastic
    );
    let summary = serde_json::json!({
        "adapter": d, "size": SIZE, "layers": 16, "stochastic_ms": stochastic, "depth_peeling_ms": peeling,
        "weighted_blended_ms": weighted, "peeling_over_stochastic": peeling / stochastic,
    });
    let dir = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("target/fragkit-bench");
    std::fs::create_dir_all(&dir)
        .and_then(|_| std::fs::write(dir.join("oit.json"), summary.to_string()))
        .unwrap_or_else(|e| panic!("writing the summary: {e}"));
}

criterion_group!(benches, oit_methods);
criterion_main!(benches);
