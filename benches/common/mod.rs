//! What every bench file does with a `fragkit::bench::Bench` (the code `fragkit bench` runs too):
//! criterion times each variant's GPU time, then side-by-side rounds give the speed-ups, printed
//! and written to <technique>.json in FRAGKIT_BENCH_DIR (default target/fragkit-bench).

use std::time::Duration;

use criterion::Criterion;
use fragkit::bench::{for_technique, measure};
use fragkit::{AdapterSelector, Gpu};

fn ms(duration: f64) -> Duration {
    Duration::from_secs_f64(duration * 1e-3)
}

pub fn criterion_then_rounds(c: &mut Criterion, technique: &str, rounds: usize) {
    let gpu = Gpu::open(&AdapterSelector::default()).unwrap_or_else(|e| panic!("{e:#}"));
    let mut bench = for_technique(&gpu, technique).unwrap_or_else(|e| panic!("{e:#}"));
    let d = &gpu.description;
    let mut group = c.benchmark_group(format!("{}/{}", d.name, d.backend));
    group.sample_size(10).warm_up_time(Duration::from_secs(1)).measurement_time(Duration::from_secs(6));
    let name = bench.name();
    for (variant, label) in bench.variants().iter().enumerate() {
        group.bench_function(format!("{technique}_{name}/{label}"), |b| {
            b.iter_custom(|n| {
                (0..n).map(|_| ms(bench.run(&gpu, variant).unwrap_or_else(|e| panic!("{e:#}")).gpu_ms)).sum()
            })
        });
    }
    group.finish();

    let result = measure(&gpu, technique, bench.as_mut(), rounds).unwrap_or_else(|e| panic!("{e:#}"));
    for line in result.lines() {
        println!("{line}");
    }
    let summary = serde_json::to_string_pretty(&result).unwrap_or_else(|e| panic!("the summary: {e}"));
    let dir = std::env::var_os("FRAGKIT_BENCH_DIR")
        .map(std::path::PathBuf::from)
        .unwrap_or_else(|| std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("target/fragkit-bench"));
    std::fs::create_dir_all(&dir)
        .and_then(|_| std::fs::write(dir.join(format!("{technique}.json")), summary))
        .unwrap_or_else(|e| panic!("writing the summary: {e}"));
}
