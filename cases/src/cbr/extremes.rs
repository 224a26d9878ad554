//! `cbr.extremes`: checkerboarding on the inputs that break naive implementations. The smallest
//! screen (2×2) and odd sizes reconstruct a static flat scene exactly; the very first frame (no
//! N−1) fills exactly the pixels frame 0 did not sample; motion larger than the screen sends
//! every unsampled pixel to the off-screen fill; a camera panning over nothing but the far plane
//! (depth 1) reprojects without NaN and reproduces the background bit for bit. No output pixel
//! may be NaN or infinite. The first frame's fills are held to the fill's definition (a CPU
//! model of `reconstruct` in shaders/cbr/reconstruct.wgsl: the mean of the sampled cardinal
//! neighbours through the reversible tonemap).

use anyhow::Result;
use fragkit::cbr::measure::{ComparedFrame, measure_against, render_with_reference};
use fragkit::cbr::sampling::{CheckerboardPath, sampled_pixels};
use fragkit::cbr::scene::flat_rects;
use fragkit::cbr::{CheckerboardConfig, PixelSource, Shading};
use fragkit::harness::{Case, Ctx, Outcome, Verdict};
use fragkit::shaders::{CBR_RECONSTRUCT, CBR_SCENE, CBR_SHADE_MSAA_SAMPLES, CBR_SHADE_SAMPLES, CBR_UNPACK_SAMPLES, FRAGMENT_STORAGE, FULLSCREEN, RECT, SAMPLE_COVERAGE_RECORD};
use glam::Vec2;

pub const CASE: Case = Case {
    name: "cbr.extremes",
    summary: "2x2 and odd screens, the first frame, motion past the screen, the far plane: exact, finite",
    requires: wgpu::Features::empty(),
    params: &[],
    sweep: &[],
    budget_s: 4,
    timed_verdict: false,
    shaders: &[RECT, FULLSCREEN, SAMPLE_COVERAGE_RECORD, FRAGMENT_STORAGE, CBR_SCENE, CBR_SHADE_SAMPLES, CBR_SHADE_MSAA_SAMPLES, CBR_UNPACK_SAMPLES, CBR_RECONSTRUCT],
    run,
};

fn check_finite(key: &str, image: &[f32], verdict: &mut Verdict) {
    let bad = image.chunks_exact(4).filter(|t| t.iter().any(|v| !v.is_finite())).count();
    if bad > 0 {
        verdict.fail(format!("{key}: {bad} pixels NaN or infinite"));
    }
}

/// The reversible tonemap the fill averages through (shaders/common/checkerboard.wgsl).
fn compress(c: [f64; 3]) -> [f64; 3] {
    let m = c[0].max(c[1]).max(c[2]);
    c.map(|v| v / (1.0 + m))
}

fn expand(c: [f64; 3]) -> [f64; 3] {
    let m = c[0].max(c[1]).max(c[2]);
    c.map(|v| v / (1.0 - m).max(1e-4))
}

/// The f32 arithmetic of the fill (a division, a sum of four, a mean, a division, each rounding
/// to half an ulp, 2^-24 relative; expansion by 1/(1 − max) at most doubles it for colours below
/// 1), rounded up.
const F32_ARITHMETIC: f64 = 1.0 / (1u64 << 20) as f64;

/// How many first-frame fills differ from the fill's definition — the mean of the pixel's
/// cardinal neighbours frame 0 sampled, through the reversible tonemap — computed in f64 from
/// those neighbours as the reconstruction wrote them (exact copies of the f16 samples), beyond
/// one f16 ulp of the result (the target's conversion: round to nearest loses half of one, a
/// truncating one, as llvmpipe's, all of it) plus the f32 arithmetic's error.
fn fills_off_definition(screen: (u32, u32), result: &[f32], sources: &[PixelSource]) -> usize {
    let (w, h) = (screen.0 as i64, screen.1 as i64);
    let colour = |x: i64, y: i64| {
        let i = (y * w + x) as usize * 4;
        [0, 1, 2].map(|c| f64::from(result[i + c]))
    };
    let mut wrong = 0;
    for (i, source) in sources.iter().enumerate() {
        if *source != PixelSource::FirstFrame {
            continue;
        }
        let (x, y) = (i as i64 % w, i as i64 / w);
        let neighbours: Vec<[f64; 3]> = [(-1, 0), (1, 0), (0, -1), (0, 1)]
            .iter()
            .map(|(dx, dy)| (x + dx, y + dy))
            .filter(|&(nx, ny)| (0..w).contains(&nx) && (0..h).contains(&ny))
            .filter(|&(nx, ny)| sources[(ny * w + nx) as usize] == PixelSource::Current)
            .map(|(nx, ny)| compress(colour(nx, ny)))
            .collect();
        let count = neighbours.len() as f64;
        let mean = [0, 1, 2].map(|c| neighbours.iter().map(|n| n[c]).sum::<f64>() / count);
        let expected = expand(mean);
        let got = colour(x, y);
        let off = (0..3).any(|c| {
            let ulp = (expected[c].abs().max(f64::from(half::f16::MIN_POSITIVE))).log2().floor().exp2() / 1024.0;
            (got[c] - expected[c]).abs() > ulp + expected[c].abs() * F32_ARITHMETIC || !got[c].is_finite()
        });
        wrong += usize::from(off || neighbours.is_empty());
    }
    wrong
}

fn run(ctx: &mut Ctx) -> Result<Outcome> {
    let path = CheckerboardPath::for_adapter(ctx.gpu);
    ctx.metric("path", path.name());
    let mut verdict = Verdict::new();

    for shading in Shading::ALL {
        // Tiny and odd screens, static: exact but for the gap column.
        for screen in [(2, 2), (3, 3), (5, 2), (2, 7)] {
            let key = format!("{}.static_{}x{}", shading.name(), screen.0, screen.1);
            let scene = flat_rects(screen, 11, Vec2::ZERO);
            let ComparedFrame { result, reference, .. } =
                render_with_reference(ctx.gpu, &scene, CheckerboardConfig::new(screen, path, shading), 2)?;
            let (error, _) = measure_against(screen, &result, &reference, 0)?;
            ctx.metric(&key, error.inexact_pixels);
            check_finite(&key, &result, &mut verdict);
            if error.inexact_pixels > 0 {
                verdict.fail(format!("{key}: {} pixels differ from full resolution", error.inexact_pixels));
            }
        }

        let screen = (33, 17);
        let config = CheckerboardConfig::new(screen, path, shading);
        // The first frame: every pixel frame 0 did not sample is filled (the gap column is
        // sampled by neither phase and is filled too).
        let key = format!("{}.first_frame", shading.name());
        let ComparedFrame { result, sources, .. } =
            render_with_reference(ctx.gpu, &flat_rects(screen, 5, Vec2::ZERO), config, 1)?;
        let sampled = sampled_pixels(screen, 0);
        let wrong = sources
            .iter()
            .zip(&sampled)
            .filter(|(source, sampled)| **sampled != (**source == PixelSource::Current))
            .count();
        let first = sources.iter().filter(|s| **s == PixelSource::FirstFrame).count();
        let wrong_fills = fills_off_definition(screen, &result, &sources);
        ctx.metric(
            &key,
            serde_json::json!({"first_frame_fills": first, "misclassified": wrong, "fills_off_definition": wrong_fills}),
        );
        check_finite(&key, &result, &mut verdict);
        if wrong > 0 || first != sampled.iter().filter(|s| !**s).count() || wrong_fills > 0 {
            verdict.fail(format!(
                "{key}: {wrong} pixels misclassified, {first} first-frame fills, {wrong_fills} fills off their definition"
            ));
        }

        // Motion larger than the screen: no history anywhere.
        let key = format!("{}.motion_past_screen", shading.name());
        let scene = flat_rects(screen, 5, Vec2::new(1000.0, -700.0));
        let ComparedFrame { result, sources, .. } = render_with_reference(ctx.gpu, &scene, config, 3)?;
        let history = sources.iter().filter(|s| **s == PixelSource::History).count();
        let off_screen = sources.iter().filter(|s| **s == PixelSource::OffScreen).count();
        ctx.metric(&key, serde_json::json!({"history": history, "off_screen": off_screen}));
        check_finite(&key, &result, &mut verdict);
        let unsampled = sampled_pixels(screen, 0).iter().filter(|s| !**s).count();
        if history > 0 || off_screen != unsampled {
            verdict.fail(format!(
                "{key}: {history} pixels from history, {off_screen} off-screen fills (expected {unsampled})"
            ));
        }

        // Nothing but the far plane, the camera panning: reprojection at depth 1 stays finite and
        // every pixel keeps the background.
        let key = format!("{}.far_plane", shading.name());
        let mut scene = flat_rects(screen, 5, Vec2::new(0.5, 0.5));
        scene.draws.clear();
        let ComparedFrame { result, reference, .. } = render_with_reference(ctx.gpu, &scene, config, 3)?;
        let (error, _) = measure_against(screen, &result, &reference, 0)?;
        ctx.metric(&key, error.inexact_pixels);
        check_finite(&key, &result, &mut verdict);
        if error.inexact_pixels > 0 {
            verdict.fail(format!("{key}: {} background pixels changed", error.inexact_pixels));
        }
    }
    Ok(verdict.outcome())
}
