//! Coarse pixel shading against full-resolution deferred shading: the corridor with 200 lights at
//! 640×360, foveated LOD (top level 5), nearest composite; the default fovea (inner radius 24 px)
//! and two wider ones, whose ideal speed-ups are lower. GPU time from timestamp queries around
//! every pass (CPS: LOD, pyramids, lighting, composite; full resolution: its lighting pass), the
//! G-buffer excluded from both. The speed-up is the median of per-round ratios, each round timing
//! full resolution and CPS back to back, so that the machine's drift between them cancels. Prints
//! it against the ideal one implied by the shaded texel counts, with where the rest goes (the
//! fixed passes, the cost per shaded texel), and writes target/fragkit-bench/cps.json. Run with
//! `cargo bench --profile dev --bench cps`.

use std::time::Duration;

use criterion::{Criterion, criterion_group, criterion_main};
use fragkit::cps::renderer::{CpsFrame, CpsOutput};
use fragkit::cps::{CompositeMode, CpsConfig, CpsRenderer, LodPolicy};
use fragkit::deferred::DeferredInputs;
use fragkit::deferred::lighting::FullResolution;
use fragkit::query::{GpuTimer, median};
use fragkit::scene::corridor::corridor;
use fragkit::{AdapterSelector, Gpu};

const SIZE: (u32, u32) = (640, 360);
/// Foveation inner radii in pixels; the first is the policy's default.
const INNER_RADII: [f32; 3] = [24.0, 48.0, 96.0];
/// Back-to-back rounds behind each ratio.
const ROUNDS: usize = 9;

fn ms(duration: f64) -> Duration {
    Duration::from_secs_f64(duration * 1e-3)
}

/// Medians over the rounds of one configuration.
struct Split {
    speedup: f64,
    full_ms: f64,
    cps_ms: f64,
    /// LOD buffer and the LOD-present and stencil pyramids.
    build_ms: f64,
    lighting_ms: f64,
    composite_ms: f64,
    shaded: u64,
}

fn cps_vs_full_resolution(c: &mut Criterion) {
    let gpu = Gpu::open(&AdapterSelector::default()).unwrap_or_else(|e| panic!("{e:#}"));
    assert!(gpu.has(wgpu::Features::TIMESTAMP_QUERY), "this benchmark reads GPU timestamps");
    let inputs = DeferredInputs::new(&gpu, &corridor(1, 200), SIZE).unwrap_or_else(|e| panic!("{e:#}"));
    let frame = CpsFrame { gbuffer: &inputs.gbuffer, lights: &inputs.lights, eye: inputs.eye };
    let fullres = FullResolution::new(&gpu, SIZE);
    let renderers: Vec<(f32, CpsRenderer)> = INNER_RADII
        .iter()
        .map(|&inner_radius| {
            let policy = LodPolicy::Foveated { focus: (0.5, 0.5), inner_radius };
            let config = CpsConfig::new(5, policy, CompositeMode::Nearest);
            (inner_radius, CpsRenderer::new(&gpu, SIZE, config).unwrap_or_else(|e| panic!("{e:#}")))
        })
        .collect();

    let full_ms = || {
        let mut timer = GpuTimer::new(&gpu, 1);
        fullres.render(&gpu, &inputs, &mut timer).unwrap_or_else(|e| panic!("{e:#}"));
        timer.read(&gpu).unwrap_or_else(|e| panic!("{e:#}")).iter().map(|t| t.ms).sum::<f64>()
    };
    let cps_frame = |cps: &CpsRenderer| -> CpsOutput { cps.render(&gpu, &frame).unwrap_or_else(|e| panic!("{e:#}")) };

    let d = &gpu.description;
    let mut group = c.benchmark_group(format!("{}/{}", d.name, d.backend));
    group.sample_size(10).warm_up_time(Duration::from_secs(1)).measurement_time(Duration::from_secs(8));
    group.bench_function("cps_640x360_200_lights/full_resolution", |b| {
        b.iter_custom(|n| (0..n).map(|_| ms(full_ms())).sum())
    });
    for (radius, cps) in &renderers {
        group.bench_function(format!("cps_640x360_200_lights/cps_foveated_r{radius}"), |b| {
            b.iter_custom(|n| (0..n).map(|_| ms(cps_frame(cps).gpu_ms(""))).sum())
        });
    }
    group.finish();

    let splits: Vec<Split> = renderers
        .iter()
        .map(|(_, cps)| {
            let rounds: Vec<(f64, CpsOutput)> = (0..ROUNDS).map(|_| (full_ms(), cps_frame(cps))).collect();
            let of = |f: &dyn Fn(&(f64, CpsOutput)) -> f64| median(rounds.iter().map(f).collect());
            Split {
                speedup: of(&|(full, out)| full / out.gpu_ms("")),
                full_ms: of(&|(full, _)| *full),
                cps_ms: of(&|(_, out)| out.gpu_ms("")),
                build_ms: of(&|(_, out)| out.gpu_ms("lod") + out.gpu_ms("pyramid")),
                lighting_ms: of(&|(_, out)| out.gpu_ms("light")),
                composite_ms: of(&|(_, out)| out.gpu_ms("composite")),
                shaded: rounds[0].1.shaded_texels.iter().sum(),
            }
        })
        .collect();

    let pixels = f64::from(SIZE.0 * SIZE.1);
    let rows: Vec<serde_json::Value> = INNER_RADII
        .iter()
        .zip(&splits)
        .map(|(radius, s)| {
            let ideal = pixels / s.shaded as f64;
            // Lighting cost per shaded texel relative to full resolution's per pixel: 1 would
            // be the ideal; the fixed passes are the rest of the gap.
            let texel_cost = (s.lighting_ms / s.shaded as f64) / (s.full_ms / pixels);
            println!(
                "cps r={radius}: full resolution {:.2} ms, CPS {:.2} ms (build {:.2}, lighting {:.2}, composite {:.2}), \
                 speed-up {:.2}x; ideal from {} shaded texels {ideal:.2}x; {:.0} % of ideal; \
                 a shaded texel costs {texel_cost:.2} full-resolution pixels",
                s.full_ms,
                s.cps_ms,
                s.build_ms,
                s.lighting_ms,
                s.composite_ms,
                s.speedup,
                s.shaded,
                100.0 * s.speedup / ideal
            );
            serde_json::json!({
                "inner_radius": radius, "full_resolution_ms": s.full_ms, "cps_ms": s.cps_ms,
                "build_ms": s.build_ms, "lighting_ms": s.lighting_ms, "composite_ms": s.composite_ms,
                "shaded_texels": s.shaded, "speedup": s.speedup, "ideal_speedup": ideal,
                "fraction_of_ideal": s.speedup / ideal, "texel_cost_in_full_resolution_pixels": texel_cost,
            })
        })
        .collect();
    let summary = serde_json::json!({ "adapter": d, "size": SIZE, "lights": 200, "rounds": ROUNDS, "foveated": rows });
    let dir = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("target/fragkit-bench");
    std::fs::create_dir_all(&dir)
        .and_then(|_| std::fs::write(dir.join("cps.json"), summary.to_string()))
        .unwrap_or_else(|e| panic!("writing the summary: {e}"));
}

criterion_group!(benches, cps_vs_full_resolution);
criterion_main!(benches);
