//! `cbr.reconstruct.exact_sources`: every pixel of every frame held to the CPU model of the
//! reconstruction (kit/src/cbr/model.rs, the definition of shaders/cbr/reconstruct.wgsl in f64),
//! fed with the scene's rects, the camera's pan and the sample placement, never with the GPU's
//! frames. The scenes (kit/src/cbr/branch_scenes.rs) drive each branch: objects crossing (CSO's
//! depth test), moving objects under a still occluder (the object-motion pass's depth test),
//! depth differences at 0.8 and 1.2 of the tolerance, transparent rects (the deferred path's
//! forward buffer), motion just past, well past and just short of half a pixel (the edge rule),
//! and camera and object motion together. Frames 0 to frames−1: the first frame, and both phases
//! with history. Per pixel, the source must be the model's and the colour within the f16 bounds
//! the model derives; pixels the formats leave open (an edge within the sub-pixel precision of a
//! sample, a motion within its rounding of a decision) are counted, not checked. Forward and
//! deferred, each with CSO and ASO.

use std::collections::{BTreeMap, BTreeSet};

use anyhow::Result;
use fragkit::cbr::branch_scenes::branch_scenes;
use fragkit::cbr::measure::{read_hdr, read_sources};
use fragkit::cbr::model::{Expected, ReconstructionModel};
use fragkit::cbr::model_comparison::Comparison;
use fragkit::cbr::sampling::CheckerboardPath;
use fragkit::cbr::{Checkerboard, CheckerboardConfig, Detection, Shading};
use fragkit::harness::{Case, Ctx, Outcome, ParamKind, ParamSpec, Sweep, SweepRange, Verdict};
use fragkit::shaders::{CBR_RECONSTRUCT, CBR_SCENE, CBR_SHADE_MSAA_SAMPLES, CBR_SHADE_SAMPLES, CBR_UNPACK_SAMPLES, FRAGMENT_STORAGE, FULLSCREEN, RECT, SAMPLE_COVERAGE_RECORD};

pub const CASE: Case = Case {
    name: "cbr.reconstruct.exact_sources",
    summary: "every reconstructed pixel's source and colour match the CPU model of the reconstruction",
    requires: wgpu::Features::empty(),
    params: &[
        ParamSpec { name: "size", kind: ParamKind::SizeFrom(16), default: "64x48", help: "screen size" },
        ParamSpec {
            name: "frames",
            kind: ParamKind::CountIn(2, 6),
            default: "4",
            help: "frames rendered, every one checked",
        },
        ParamSpec {
            name: "tolerance_percent",
            kind: ParamKind::CountIn(1, 50),
            default: "5",
            help: "CSO's relative depth tolerance, percent",
        },
    ],
    sweep: &[
        Sweep { param: "size", range: SweepRange::Size { min: (16, 16), max: (200, 150) } },
        Sweep { param: "frames", range: SweepRange::Count(2, 6) },
        Sweep { param: "tolerance_percent", range: SweepRange::Count(1, 50) },
    ],
    budget_s: 8,
    timed_verdict: false,
    shaders: &[RECT, FULLSCREEN, SAMPLE_COVERAGE_RECORD, FRAGMENT_STORAGE, CBR_SCENE, CBR_SHADE_SAMPLES, CBR_SHADE_MSAA_SAMPLES, CBR_UNPACK_SAMPLES, CBR_RECONSTRUCT],
    run,
};

fn run(ctx: &mut Ctx) -> Result<Outcome> {
    let path = CheckerboardPath::for_adapter(ctx.gpu);
    ctx.metric("path", path.name());
    let screen = ctx.params.size("size")?;
    let frames = ctx.params.count_u32("frames")?;
    let tolerance = ctx.params.count("tolerance_percent")? as f32 / 100.0;
    let mut verdict = Verdict::new();
    let mut seen: BTreeMap<&str, BTreeSet<&str>> = BTreeMap::new();
    for scene in branch_scenes(screen, tolerance) {
        for detection in [Detection::Cso { tolerance }, Detection::Aso] {
            // Expected: the model's account of every pixel of every frame (shading-independent).
            let model = ReconstructionModel::new(&scene.rects, scene.camera, screen, detection)?;
            let expected_frames: Vec<Vec<Expected>> = (0..frames).map(|frame| model.frame(frame)).collect();
            for shading in Shading::ALL {
                let key = format!("{}.{}.{}", scene.name, shading.name(), detection.name());
                let config = CheckerboardConfig { detection, ..CheckerboardConfig::new(screen, path, shading) };
                let mut checkerboard = Checkerboard::new(ctx.gpu, &scene.scene(screen), config)?;
                let mut tally: BTreeMap<&str, u64> = BTreeMap::new();
                let mut wrong_pixels = 0;
                for frame in 0..frames {
                    // Render, read back, and hold every pixel to the model's account of it.
                    checkerboard.render(ctx.gpu, frame)?;
                    let colours = read_hdr(ctx.gpu, &checkerboard.reconstruction.colour)?;
                    let sources = read_sources(ctx.gpu, &checkerboard.reconstruction)?;
                    let expected = &expected_frames[frame as usize];
                    let comparison = Comparison::of(expected, &colours, &sources, screen.0);
                    for (name, count) in &comparison.tally {
                        *tally.entry(name).or_default() += count;
                    }
                    seen.entry(scene.name).or_default().extend(comparison.known_sources());
                    if !comparison.differences.is_empty() {
                        wrong_pixels += comparison.differences.len();
                        verdict.fail(format!(
                            "{key}, frame {frame}: {} pixels differ from the model, e.g. {}",
                            comparison.differences.len(),
                            comparison.differences[..comparison.differences.len().min(3)].join("; ")
                        ));
                        ctx.evidence_image(
                            &format!("{key}.frame{frame}"),
                            &comparison.evidence(screen, expected, &colours)?,
                        )?;
                    }
                }
                ctx.metric(&format!("{key}.checked"), &tally);
                ctx.metric(&format!("{key}.wrong"), wrong_pixels);
            }
        }
    }
    // The scenes must reach the branches they are built for at this size and tolerance, or a
    // bug there would pass unseen.
    for scene in branch_scenes(screen, tolerance) {
        let missing: Vec<&str> = scene
            .exercises
            .iter()
            .map(|s| s.name())
            .filter(|s| !seen.get(scene.name).is_some_and(|seen| seen.contains(s)))
            .collect();
        if !missing.is_empty() {
            verdict.fail(format!("{}: no pixel the model knows came from {}", scene.name, missing.join(", ")));
        }
    }
    Ok(verdict.outcome())
}
