//! Coarse pixel shading against full-resolution deferred shading: the corridor with 200 lights at
//! 640×360, foveated LOD (top level 5), nearest composite. GPU time from timestamp queries around
//! every pass (CPS: LOD, pyramids, lighting, composite; full resolution: its lighting pass), the
//! G-buffer excluded from both. Prints the speed-up against the ideal one implied by the shaded
//! texel counts and writes them to target/fragkit-bench/cps.json. Run with
//! `cargo bench --profile dev --bench cps`.

use std::time::Duration;

use criterion::{Criterion, criterion_group, criterion_main};
use fragkit::cps::renderer::CpsFrame;
use fragkit::cps::{CompositeMode, CpsConfig, CpsRenderer, LodPolicy};
use fragkit::deferred::DeferredInputs;
use fragkit::deferred::lighting::FullResolution;
use fragkit::query::{GpuTimer, median};
use fragkit::scene::corridor::corridor;
use fragkit::{AdapterSelector, Gpu};

const SIZE: (u32, u32) = (640, 360);

fn ms(duration: f64) -> Duration {
    Duration::from_secs_f64(duration * 1e-3)
}

fn cps_vs_full_resolution(c: &mut Criterion) {
    let gpu = Gpu::open(&AdapterSelector::default()).unwrap_or_else(|e| panic!("{e:#}"));
    assert!(gpu.has(wgpu::Features::TIMESTAMP_QUERY), "this benchmark reads GPU timestamps");
    let inputs = DeferredInputs::new(&gpu, &corridor(1, 200), SIZE).unwrap_or_else(|e| panic!("{e:#}"));
    let frame = CpsFrame { gbuffer: &inputs.gbuffer, lights: &inputs.lights, eye: inputs.eye };
    let fullres = FullResolution::new(&gpu, SIZE);
    let cps = CpsRenderer::new(&gpu, SIZE, CpsConfig::new(5, LodPolicy::foveated(), CompositeMode::Nearest))
        .unwrap_or_else(|e| panic!("{e:#}"));

    let full_ms = || {
        let mut timer = GpuTimer::new(&gpu, 1);
        fullres.render(&gpu, &inputs, &mut timer).unwrap_or_else(|e| panic!("{e:#}"));
        timer.read(&gpu).unwrap_or_else(|e| panic!("{e:#}")).iter().map(|t| t.ms).sum::<f64>()
    };
    let cps_ms = || cps.render(&gpu, &frame).unwrap_or_else(|e| panic!("{e:#}")).gpu_ms("");

    let d = &gpu.description;
    let mut group = c.benchmark_group(format!("{}/{}", d.name, d.backend));
    group.sample_size(10).warm_up_time(Duration::from_secs(1)).measurement_time(Duration::from_secs(8));
    group.bench_function("cps_640x360_200_lights/full_resolution", |b| {
        b.iter_custom(|n| (0..n).map(|_| ms(full_ms())).sum())
    });
    group.bench_function("cps_640x360_200_lights/cps_foveated", |b| {
        b.iter_custom(|n| (0..n).map(|_| ms(cps_ms())).sum())
    });
    group.finish();

    // The ratio the target is stated in, from medians of fresh runs.
    let (full, coarse) = (median((0..9).map(|_| full_ms()).collect()), median((0..9).map(|_| cps_ms()).collect()));
    let shaded: u64 = cps.render(&gpu, &frame).unwrap_or_else(|e| panic!("{e:#}")).shaded_texels.iter().sum();
    let ideal = f64::from(SIZE.0 * SIZE.1) / shaded as f64;
    let speedup = full / coarse;
    println!(
        "cps: full resolution {full:.2} ms, CPS {coarse:.2} ms, speed-up {speedup:.2}x; ideal from {shaded} shaded texels {ideal:.2}x; {:.0} % of ideal",
        100.0 * speedup / ideal
    );
    let summary = serde_json::json!({
        "adapter": d, "size": SIZE, "lights": 200, "full_resolution_ms": full, "cps_ms": coarse,
        "speedup": speedup, "ideal_speedup": ideal, "fraction_of_ideal": speedup / ideal,
    });
    let dir = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("target/fragkit-bench");
    std::fs::create_dir_all(&dir)
        .and_then(|_| std::fs::write(dir.join("cps.json"), summary.to_string()))
        .unwrap_or_else(|e| panic!("writing the summary: {e}"));
}

criterion_group!(benches, cps_vs_full_resolution);
criterion_main!(benches);
