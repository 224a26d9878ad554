//! `oit.post_filter`: stochastic transparency's post-filter on known inputs. Seeded frames (most
//! pixels varying within the restart tolerance, some jumping beyond it) are fed through the
//! renderer's own `PostFilter` (`shaders/oit/temporal.wgsl`, `shaders/oit/bilateral.wgsl`), and
//! the accumulation and the bilateral result are compared with CPU models of their definitions:
//! the running mean h ← h + (x − h) / (n + 1), restarting at x where a channel moved beyond the
//! tolerance; and the 5×5 bilateral with spatial σ 1.5 and range σ, normalised by its weights.
//! The CPU rounds to f16 wherever the GPU stores; a correct GPU may still round differently by one
//! f16 ulp a store, so the bound is one ulp (of values ≤ 1: 2^-10) for each store a result passed.

use anyhow::Result;
use fragkit::harness::{Case, Ctx, Outcome, ParamKind, ParamSpec, Sweep, SweepRange, Verdict};
use fragkit::oit::filter::{PostFilter, read_rgb};
use fragkit::query::GpuTimer;
use fragkit::scene::hash::SeededRng;
use fragkit::shaders::{FULLSCREEN, OIT_BILATERAL, OIT_TEMPORAL};

pub const CASE: Case = Case {
    name: "oit.post_filter",
    summary: "temporal accumulation and bilateral filter equal CPU models of their definitions on known frames",
    requires: wgpu::Features::empty(),
    params: &[
        ParamSpec { name: "size", kind: ParamKind::SizeFrom(1), default: "24x16", help: "frame size" },
        ParamSpec { name: "frames", kind: ParamKind::CountIn(1, 64), default: "6", help: "frames accumulated" },
        ParamSpec { name: "seed", kind: ParamKind::CountIn(0, 1 << 20), default: "4", help: "frame seed" },
    ],
    sweep: &[
        Sweep { param: "size", range: SweepRange::Size { min: (1, 1), max: (64, 64) } },
        Sweep { param: "frames", range: SweepRange::Count(1, 64) },
        Sweep { param: "seed", range: SweepRange::Count(0, 1 << 20) },
    ],
    budget_s: 1,
    timed_verdict: false,
    shaders: &[FULLSCREEN, OIT_TEMPORAL, OIT_BILATERAL],
    run,
};

/// The renderer's restart tolerance and range σ for this test: small enough that seeded jumps
/// restart some pixels and the range weights vary.
const TOLERANCE: f32 = 0.25;
const RANGE_SIGMA: f32 = 0.2;

fn f16(value: f64) -> f64 {
    f64::from(half::f16::from_f64(value).to_f32())
}

/// Seeded frames: a per-pixel base in 0.2..0.8, a small wobble each frame, and a jump of 0.5 on
/// one pixel in eight (beyond the tolerance: the history restarts there).
fn frames(size: (u32, u32), count: u32, seed: u32) -> Vec<Vec<[f64; 3]>> {
    let mut rng = SeededRng::new(seed);
    let pixels = (size.0 * size.1) as usize;
    let base: Vec<[f64; 3]> = (0..pixels).map(|_| [0; 3].map(|_| 0.2 + 0.6 * f64::from(rng.unit()))).collect();
    (0..count)
        .map(|_| {
            base.iter()
                .map(|b| {
                    let jump = if rng.range(0, 8) == 0 { 0.5 } else { 0.0 };
                    b.map(|c| f16((c + jump + 0.2 * f64::from(rng.unit()) - 0.1).fract().abs()))
                })
                .collect()
        })
        .collect()
}

fn upload(ctx: &Ctx, size: (u32, u32), frame: &[[f64; 3]]) -> wgpu::Texture {
    let texture = ctx.gpu.texture(
        "known frame",
        size,
        wgpu::TextureFormat::Rgba16Float,
        1,
        wgpu::TextureUsages::TEXTURE_BINDING | wgpu::TextureUsages::COPY_DST,
    );
    let bytes: Vec<u8> =
        frame.iter().flat_map(|p| [p[0], p[1], p[2], 1.0]).flat_map(|c| half::f16::from_f64(c).to_le_bytes()).collect();
    ctx.gpu.queue.write_texture(
        texture.as_image_copy(),
        &bytes,
        wgpu::TexelCopyBufferLayout { offset: 0, bytes_per_row: Some(size.0 * 8), rows_per_image: None },
        texture.size(),
    );
    texture
}

/// The temporal accumulation's definition, rounding to f16 at each store.
fn accumulate(frames: &[Vec<[f64; 3]>]) -> Vec<[f64; 3]> {
    let mut history = frames[0].clone();
    for (n, frame) in frames.iter().enumerate().skip(1) {
        for (h, x) in history.iter_mut().zip(frame) {
            let restart = (0..3).any(|c| (x[c] - h[c]).abs() > f64::from(TOLERANCE));
            *h = if restart { *x } else { std::array::from_fn(|c| f16(h[c] + (x[c] - h[c]) / (n as f64 + 1.0))) };
        }
    }
    history
}

/// The bilateral filter's definition: 5×5 taps clamped to the image, weight
/// exp(−|d|²/(2·1.5²) − |Δc|²/(2σ²)), normalised by the sum of the weights.
fn bilateral(size: (u32, u32), image: &[[f64; 3]]) -> Vec<[f64; 3]> {
    let (w, h) = (i64::from(size.0), i64::from(size.1));
    let at = |x: i64, y: i64| image[(y.clamp(0, h - 1) * w + x.clamp(0, w - 1)) as usize];
    let sigma = f64::from(RANGE_SIGMA);
    (0..h)
        .flat_map(|y| (0..w).map(move |x| (x, y)))
        .map(|(x, y)| {
            let own = at(x, y);
            let (mut sum, mut weights) = ([0.0; 3], 0.0);
            for dy in -2..=2 {
                for dx in -2..=2 {
                    let texel = at(x + dx, y + dy);
                    let range: f64 = (0..3).map(|c| (texel[c] - own[c]).powi(2)).sum();
                    let weight =
                        (-((dx * dx + dy * dy) as f64) / (2.0 * 1.5 * 1.5) - range / (2.0 * sigma * sigma)).exp();
                    (0..3).for_each(|c| sum[c] += texel[c] * weight);
                    weights += weight;
                }
            }
            sum.map(|s| s / weights)
        })
        .collect()
}

/// Pixels where a channel differs by more than `stores` f16 ulps of values ≤ 1 (2^-10 each).
fn beyond(gpu: &[[f32; 3]], cpu: &[[f64; 3]], stores: u32) -> (usize, f64) {
    let bound = f64::from(stores) / 1024.0;
    let worst =
        gpu.iter().zip(cpu).flat_map(|(g, c)| (0..3).map(move |i| (f64::from(g[i]) - c[i]).abs())).fold(0.0, f64::max);
    let count = gpu.iter().zip(cpu).filter(|(g, c)| (0..3).any(|i| (f64::from(g[i]) - c[i]).abs() > bound)).count();
    (count, worst)
}

fn run(ctx: &mut Ctx) -> Result<Outcome> {
    let size = ctx.params.size("size")?;
    let count = ctx.params.count_u32("frames")?;
    let known = frames(size, count, ctx.params.count_u32("seed")?);

    // Render: the renderer's own post-filter over the known frames.
    let mut filter = PostFilter::new(ctx.gpu, size);
    filter.tolerance = TOLERANCE;
    filter.range_sigma = RANGE_SIGMA;
    let mut timer = GpuTimer::new(ctx.gpu, count + 1);
    for frame in &known {
        filter.accumulate(ctx.gpu, &upload(ctx, size, frame), &mut timer);
    }
    let accumulated = read_rgb(ctx.gpu, filter.accumulated())?;
    let filtered = read_rgb(ctx.gpu, filter.filter(ctx.gpu, &mut timer))?;

    // Expected: the definitions; the bilateral model reads the GPU's accumulation (its input) so
    // that each stage is judged on its own.
    let expected_accumulation = accumulate(&known);
    let accumulation_input: Vec<[f64; 3]> = accumulated.iter().map(|p| p.map(f64::from)).collect();
    let expected_filtered = bilateral(size, &accumulation_input);
    let (wrong_accumulation, worst_accumulation) = beyond(&accumulated, &expected_accumulation, count);
    let (wrong_filtered, worst_filtered) = beyond(&filtered, &expected_filtered, 1);
    ctx.metric("accumulation", serde_json::json!({"pixels_beyond_bound": wrong_accumulation, "worst": worst_accumulation, "bound": f64::from(count) / 1024.0}));
    ctx.metric(
        "bilateral",
        serde_json::json!({"pixels_beyond_bound": wrong_filtered, "worst": worst_filtered, "bound": 1.0 / 1024.0}),
    );

    let mut verdict = Verdict::new();
    if wrong_accumulation > 0 {
        verdict.fail(format!("temporal accumulation: {wrong_accumulation} pixels differ from the running mean (worst {worst_accumulation:.2e}, bound {:.2e})", f64::from(count) / 1024.0));
    }
    if wrong_filtered > 0 {
        verdict.fail(format!("bilateral: {wrong_filtered} pixels differ from the filter's definition (worst {worst_filtered:.2e}, bound {:.2e})", 1.0 / 1024.0));
    }
    Ok(verdict.outcome())
}
