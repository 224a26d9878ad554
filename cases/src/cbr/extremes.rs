//! `cbr.extremes`: checkerboarding on the inputs that break naive implementations. The smallest
//! screen (2×2) and odd sizes reconstruct a static flat scene exactly; the very first frame (no
//! N−1) fills exactly the pixels frame 0 did not sample; motion larger than the screen sends
//! every unsampled pixel to the off-screen fill; a camera panning over nothing but the far plane
//! (depth 1) reprojects without NaN and reproduces the background bit for bit. No output pixel
//! may be NaN or infinite.

use anyhow::Result;
use fragkit::cbr::measure::{ComparedFrame, measure_against, render_with_reference};
use fragkit::cbr::sampling::{CheckerboardPath, sampled_pixels};
use fragkit::cbr::scene::flat_rects;
use fragkit::cbr::{CheckerboardConfig, PixelSource, Shading};
use fragkit::harness::{Case, Ctx, Outcome};
use glam::Vec2;

pub const CASE: Case = Case {
    name: "cbr.extremes",
    summary: "2x2 and odd screens, the first frame, motion past the screen, the far plane: exact, finite",
    requires: wgpu::Features::empty(),
    params: &[],
    sweep: &[],
    run,
};

fn check_finite(key: &str, image: &[f32], problems: &mut Vec<String>) {
    let bad = image.chunks_exact(4).filter(|t| t.iter().any(|v| !v.is_finite())).count();
    if bad > 0 {
        problems.push(format!("{key}: {bad} pixels NaN or infinite"));
    }
}

fn run(ctx: &mut Ctx) -> Result<Outcome> {
    let path = CheckerboardPath::for_adapter(ctx.gpu);
    ctx.metric("path", path.name());
    let mut problems = Vec::new();

    for shading in Shading::ALL {
        // Tiny and odd screens, static: exact but for the gap column.
        for screen in [(2, 2), (3, 3), (5, 2), (2, 7)] {
            let key = format!("{}.static_{}x{}", shading.name(), screen.0, screen.1);
            let scene = flat_rects(screen, 11, Vec2::ZERO);
            let ComparedFrame { result, reference, .. } =
                render_with_reference(ctx.gpu, &scene, CheckerboardConfig::new(screen, path, shading), 2)?;
            let (error, _) = measure_against(screen, &result, &reference, 0)?;
            ctx.metric(&key, error.inexact_pixels);
            check_finite(&key, &result, &mut problems);
            if error.inexact_pixels > 0 {
                problems.push(format!("{key}: {} pixels differ from full resolution", error.inexact_pixels));
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
        ctx.metric(&key, serde_json::json!({"first_frame_fills": first, "misclassified": wrong}));
        check_finite(&key, &result, &mut problems);
        if wrong > 0 || first != sampled.iter().filter(|s| !**s).count() {
            problems.push(format!("{key}: {wrong} pixels misclassified, {first} first-frame fills"));
        }

        // Motion larger than the screen: no history anywhere.
        let key = format!("{}.motion_past_screen", shading.name());
        let scene = flat_rects(screen, 5, Vec2::new(1000.0, -700.0));
        let ComparedFrame { result, sources, .. } = render_with_reference(ctx.gpu, &scene, config, 3)?;
        let history = sources.iter().filter(|s| **s == PixelSource::History).count();
        let off_screen = sources.iter().filter(|s| **s == PixelSource::OffScreen).count();
        ctx.metric(&key, serde_json::json!({"history": history, "off_screen": off_screen}));
        check_finite(&key, &result, &mut problems);
        let unsampled = sampled_pixels(screen, 0).iter().filter(|s| !**s).count();
        if history > 0 || off_screen != unsampled {
            problems.push(format!(
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
        check_finite(&key, &result, &mut problems);
        if error.inexact_pixels > 0 {
            problems.push(format!("{key}: {} background pixels changed", error.inexact_pixels));
        }
    }
    Ok(if problems.is_empty() { Outcome::Pass } else { Outcome::Fail(problems.join("; ")) })
}
