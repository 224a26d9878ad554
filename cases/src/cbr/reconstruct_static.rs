//! `cbr.reconstruct.static`: a static scene checkerboarded over two frames matches the
//! full-resolution render of the same frame. Flat-shaded rects whose edges lie on pixel
//! boundaries must match bit for bit (every pixel is a sample of one of the two frames at its
//! exact centre). The lit, textured corridor with glass panes cannot match exactly (its shading
//! is interpolated in a different projection, and the deferred path stores normals in f16 and
//! albedo in 8 bits), so it is held to references measured in the same run from the same frame:
//! it must beat the quarter-resolution render upscaled bilinearly and the same frame
//! reconstructed without history (a static scene's history is exact). The documented gap column
//! is excluded from every comparison. Forward
//! and deferred, on the path this adapter uses. Texture LOD: exact gradients (×0.5) must beat the
//! whitepaper's −0.5 bias against full resolution
//! (where the corridor is at least 24 pixels on its short side; see `LOD_CLAIM_MIN_SIDE`).

use anyhow::Result;
use fragkit::cbr::measure::{SameFrameReferences, measure_against, render_with_reference, source_counts};
use fragkit::cbr::sampling::{CheckerboardPath, documented_gaps};
use fragkit::cbr::scene::{Motion, flat_rects, textured_corridor};
use fragkit::cbr::scene_pass::TextureLod;
use fragkit::cbr::{CheckerboardConfig, Shading};
use fragkit::harness::{Case, Ctx, Outcome, ParamKind, ParamSpec, Sweep, SweepRange, Verdict};
use fragkit::shaders::{CBR_RECONSTRUCT, CBR_SCENE, CBR_SHADE_MSAA_SAMPLES, CBR_SHADE_SAMPLES, CBR_UNPACK_SAMPLES, CBR_UPSCALE, FRAGMENT_STORAGE, FULLSCREEN, RECT, SAMPLE_COVERAGE_RECORD};
use glam::Vec2;

pub const CASE: Case = Case {
    name: "cbr.reconstruct.static",
    summary: "static scenes: flat-shaded reconstruction is exact, lit and textured within tolerance",
    requires: wgpu::Features::empty(),
    params: &[
        ParamSpec {
            name: "sizes",
            kind: ParamKind::SizesFrom(2),
            default: "64x48,37x23",
            help: "flat-scene screen sizes",
        },
        ParamSpec {
            name: "corridor_size",
            kind: ParamKind::SizesFrom(8),
            default: "96x64",
            help: "lit corridor size, at least 8x8 (smaller is nearly all border; cbr.extremes covers it)",
        },
        ParamSpec { name: "lights", kind: ParamKind::CountIn(1, 4096), default: "16", help: "corridor point lights" },
    ],
    sweep: &[
        Sweep { param: "sizes", range: SweepRange::Size { min: (2, 2), max: (300, 200) } },
        Sweep { param: "corridor_size", range: SweepRange::Size { min: (8, 8), max: (200, 150) } },
        Sweep { param: "lights", range: SweepRange::Count(1, 4096) },
    ],
    budget_s: 4,
    timed_verdict: false,
    shaders: &[RECT, FULLSCREEN, SAMPLE_COVERAGE_RECORD, FRAGMENT_STORAGE, CBR_SCENE, CBR_SHADE_SAMPLES, CBR_SHADE_MSAA_SAMPLES, CBR_UNPACK_SAMPLES, CBR_RECONSTRUCT, CBR_UPSCALE],
    run,
};

/// Exact gradients beat the −0.5 bias where the corridor's short side has at least this many
/// pixels; below it every surface samples the last few mips and they tie or swap (measured on
/// lavapipe for 8x8..200x150 and 1..100 lights: the first loss at 16x17, none from 24x24). The
/// metric shows both everywhere.
const LOD_CLAIM_MIN_SIDE: u32 = 24;

/// Display steps within which two pixels count as equal in the differing-pixel metric.
const DISPLAY_TOLERANCE: u8 = 8;

fn run(ctx: &mut Ctx) -> Result<Outcome> {
    let path = CheckerboardPath::for_adapter(ctx.gpu);
    ctx.metric("path", path.name());
    let lights = ctx.params.count_u32("lights")?;
    let mut verdict = Verdict::new();
    for shading in Shading::ALL {
        for screen in ctx.params.sizes("sizes")? {
            let key = format!("{}.flat.{}x{}", shading.name(), screen.0, screen.1);
            let scene = flat_rects(screen, 3, Vec2::ZERO);
            let frame = render_with_reference(ctx.gpu, &scene, CheckerboardConfig::new(screen, path, shading), 2)?;
            let (error, evidence) = measure_against(screen, &frame.result, &frame.reference, 0)?;
            let sources = frame.sources;
            let counts = source_counts(&sources);
            let filled: u64 = sources.iter().filter(|s| s.is_filled()).count() as u64;
            ctx.metric(&key, serde_json::json!({"inexact_pixels": error.inexact_pixels, "sources": counts}));
            if error.inexact_pixels > 0 {
                ctx.evidence_image(&key, &evidence)?;
                verdict.fail(format!(
                    "{key}: {} of {} pixels differ from full resolution",
                    error.inexact_pixels, error.compared_pixels
                ));
            }
            // Static: only the gap column lacks a sample in both frames.
            let gaps = documented_gaps(screen).len() as u64;
            if filled != gaps {
                verdict.fail(format!("{key}: {filled} pixels filled from neighbours, expected the {gaps} gap pixels"));
            }
        }
        let screen = ctx.params.sizes("corridor_size")?[0];
        let key = format!("{}.corridor.{}x{}", shading.name(), screen.0, screen.1);
        let scene = textured_corridor(5, lights, Motion::Static);
        let frame = render_with_reference(ctx.gpu, &scene, CheckerboardConfig::new(screen, path, shading), 2)?;
        let (error, evidence) = measure_against(screen, &frame.result, &frame.reference, DISPLAY_TOLERANCE)?;
        let share = error.differing_pixels as f64 / error.compared_pixels as f64;
        ctx.metric(
            &key,
            serde_json::json!({"psnr_db": error.psnr_db, "flip": error.flip, "differing_share": share, "non_finite": error.non_finite_pixels}),
        );
        // Texture LOD in the quarter-resolution passes: exact gradients (the default) against
        // the whitepaper's −0.5 bias, which blurs the textured floor and walls.
        let biased =
            CheckerboardConfig { lod: TextureLod::Bias(-0.5), ..CheckerboardConfig::new(screen, path, shading) };
        let biased_frame = render_with_reference(ctx.gpu, &scene, biased, 2)?;
        let (biased_error, _) = measure_against(screen, &biased_frame.result, &frame.reference, DISPLAY_TOLERANCE)?;
        ctx.metric(&format!("{key}.lod_bias_-0.5_psnr_db"), biased_error.psnr_db);
        if screen.0.min(screen.1) >= LOD_CLAIM_MIN_SIDE && biased_error.psnr_db >= error.psnr_db {
            verdict.fail(format!(
                "{key}: LOD bias -0.5 ({:.2} dB) is not worse than exact gradients ({:.2} dB)",
                biased_error.psnr_db, error.psnr_db
            ));
        }
        let same_frame = SameFrameReferences::measure(
            ctx.gpu,
            &scene,
            CheckerboardConfig::new(screen, path, shading),
            1,
            &frame.reference,
        )?;
        let references = [
            ("the upscaled quarter resolution", same_frame.upscale_psnr_db),
            ("the same frame without history", same_frame.without_history_psnr_db),
        ];
        ctx.metric(&format!("{key}.upscale_psnr_db"), same_frame.upscale_psnr_db);
        ctx.metric(&format!("{key}.without_history_psnr_db"), same_frame.without_history_psnr_db);
        let beaten: Vec<String> = references
            .iter()
            .filter(|(_, db)| !SameFrameReferences::beats(error.psnr_db, *db))
            .map(|(what, db)| format!("{what} ({db:.2} dB)"))
            .collect();
        if !beaten.is_empty() || error.non_finite_pixels > 0 {
            ctx.evidence_image(&key, &evidence)?;
            verdict.fail(format!(
                "{key}: PSNR {:.2} dB does not beat {}; {} non-finite pixels",
                error.psnr_db,
                if beaten.is_empty() { "-".into() } else { beaten.join(", ") },
                error.non_finite_pixels
            ));
        }
    }
    Ok(verdict.outcome())
}
