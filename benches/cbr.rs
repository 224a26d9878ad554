//! Checkerboard rendering against full resolution where pixel shading dominates: the static
//! textured corridor with 200 lights at 320×180, forward shading, CSO, on the path this adapter
//! uses (and the 2x path too where the kit measured a real one). GPU time of a whole frame from
//! timestamp queries around every pass (checkerboarding: scene passes and reconstruction; full
//! resolution: its scene pass). Prints the speed-ups and writes them to
//! target/fragkit-bench/cbr.json. Run with `cargo bench --profile dev --bench cbr`.

use std::time::Duration;

use criterion::{Criterion, criterion_group, criterion_main};
use fragkit::cbr::sampling::CheckerboardPath;
use fragkit::cbr::scene::{Motion, textured_corridor};
use fragkit::cbr::{Checkerboard, CheckerboardConfig, FullResolutionScene, Shading};
use fragkit::query::median;
use fragkit::{AdapterSelector, Gpu};

const SIZE: (u32, u32) = (320, 180);
const LIGHTS: u32 = 200;

fn ms(duration: f64) -> Duration {
    Duration::from_secs_f64(duration * 1e-3)
}

fn cbr_vs_full_resolution(c: &mut Criterion) {
    let gpu = Gpu::open(&AdapterSelector::default()).unwrap_or_else(|e| panic!("{e:#}"));
    assert!(gpu.has(wgpu::Features::TIMESTAMP_QUERY), "this benchmark reads GPU timestamps");
    let scene = textured_corridor(5, LIGHTS, Motion::Static);
    let mut fullres = FullResolutionScene::new(&gpu, &scene, SIZE).unwrap_or_else(|e| panic!("{e:#}"));
    let mut paths = vec![CheckerboardPath::OffsetPasses];
    if CheckerboardPath::for_adapter(&gpu) == CheckerboardPath::Msaa2x {
        paths.push(CheckerboardPath::Msaa2x);
    }
    let mut renderers: Vec<(CheckerboardPath, Shading, Checkerboard)> = paths
        .iter()
        .flat_map(|&path| Shading::ALL.map(|shading| (path, shading)))
        .map(|(path, shading)| {
            let renderer = Checkerboard::new(&gpu, &scene, CheckerboardConfig::new(SIZE, path, shading))
                .unwrap_or_else(|e| panic!("{e:#}"));
            (path, shading, renderer)
        })
        .collect();

    let d = &gpu.description;
    let mut group = c.benchmark_group(format!("{}/{}", d.name, d.backend));
    group.sample_size(10).warm_up_time(Duration::from_secs(1)).measurement_time(Duration::from_secs(6));
    let mut frame = 0;
    group.bench_function("cbr_320x180_200_lights/full_resolution", |b| {
        b.iter_custom(|n| (0..n).map(|_| ms(fullres.render(&gpu, 0).unwrap_or_else(|e| panic!("{e:#}")))).sum())
    });
    for (path, shading, renderer) in &mut renderers {
        group.bench_function(format!("cbr_320x180_200_lights/{}_{}", path.name(), shading.name()), |b| {
            b.iter_custom(|n| {
                (0..n)
                    .map(|_| {
                        frame += 1;
                        ms(renderer.render(&gpu, frame).unwrap_or_else(|e| panic!("{e:#}")).gpu_ms)
                    })
                    .sum()
            })
        });
    }
    group.finish();

    // The ratios the target is stated in, from medians of fresh runs.
    let full = median((0..15).map(|_| fullres.render(&gpu, 0).unwrap_or_else(|e| panic!("{e:#}"))).collect());
    let mut summary = serde_json::json!({"adapter": d, "size": SIZE, "lights": LIGHTS, "full_resolution_ms": full});
    for (path, shading, renderer) in &mut renderers {
        let cbr = median(
            (0..15)
                .map(|_| {
                    frame += 1;
                    renderer.render(&gpu, frame).unwrap_or_else(|e| panic!("{e:#}")).gpu_ms
                })
                .collect(),
        );
        let name = format!("{}_{}", path.name(), shading.name());
        println!("cbr {name}: full resolution {full:.2} ms, checkerboard {cbr:.2} ms, speed-up {:.2}x", full / cbr);
        summary[format!("{name}_ms")] = serde_json::json!(cbr);
        summary[format!("{name}_speedup")] = serde_json::json!(full / cbr);
    }
    let dir = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("target/fragkit-bench");
    std::fs::create_dir_all(&dir)
        .and_then(|_| std::fs::write(dir.join("cbr.json"), summary.to_string()))
        .unwrap_or_else(|e| panic!("writing the summary: {e}"));
}

criterion_group!(benches, cbr_vs_full_resolution);
criterion_main!(benches);
