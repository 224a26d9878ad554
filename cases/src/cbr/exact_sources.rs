//! `cbr.reconstruct.exact_sources`: two flat rects cross each other over a static rect and a
//! backdrop, each moving whole pixels a frame (`crossing_rects`). The CPU knows which rect every
//! pixel shows in frames N and N−1, so it lists exactly which pixels frame N did not sample that
//! are truly disoccluded (their surface, followed back along its own motion, was hidden in frame
//! N−1) and which have good history. Wherever a missing pixel and its four neighbours show one
//! surface (the reconstruction reads motion and depth from the neighbours, so at an edge it cannot
//! know), CSO must send the disoccluded set — exactly — to the fill, take every other pixel from
//! the right history texel (its colour is its rect's, within f16 rounding), and report off-screen
//! sources; sampled pixels must hold their rect's colour. ASO must send every pixel that moved
//! at least a quarter-resolution pixel to the fill as assumed missing, unless its history is
//! stale (moved with an object where the pixel does not), and otherwise agree with CSO. Forward
//! and deferred, each with CSO and ASO.

use std::collections::BTreeMap;

use anyhow::Result;
use fragkit::cbr::measure::{read_hdr, read_sources};
use fragkit::cbr::sampling::{CheckerboardPath, sampled_pixels};
use fragkit::cbr::scene::{PixelRect, crossing_rects};
use fragkit::cbr::{Checkerboard, CheckerboardConfig, Detection, PixelSource, Shading};
use fragkit::harness::{Case, Ctx, Outcome, ParamKind, ParamSpec, Sweep, SweepRange};

pub const CASE: Case = Case {
    name: "cbr.reconstruct.exact_sources",
    summary: "CSO sends exactly the truly disoccluded pixels to the fill and takes the rest from history",
    requires: wgpu::Features::empty(),
    params: &[
        ParamSpec { name: "size", kind: ParamKind::SizesFrom(16), default: "64x48", help: "screen size" },
        ParamSpec {
            name: "frames",
            kind: ParamKind::CountIn(2, 6),
            default: "3",
            help: "frames rendered; the last is measured",
        },
    ],
    sweep: &[
        Sweep { param: "size", range: SweepRange::Size { min: (16, 16), max: (200, 150) } },
        Sweep { param: "frames", range: SweepRange::Count(2, 6) },
    ],
    budget_s: 1,
    run,
};

/// f16 keeps 11 significant bits, so storing a colour moves it by at most 2^-11 of its value; the
/// fill's compress/expand round trip adds a few f32 ulps. 2^-10 relative covers both.
const COLOUR_TOLERANCE: f32 = 1.0 / 1024.0;

/// The rect pixel (x, y) shows in `frame` (front-most by distance), if on screen.
fn surface(rects: &[PixelRect], x: i64, y: i64, frame: u32) -> Option<usize> {
    (0..rects.len())
        .filter(|&i| rects[i].covers(x, y, frame))
        .min_by(|&a, &b| rects[a].distance.total_cmp(&rects[b].distance))
}

/// A quarter-resolution pixel, less the reconstruction's edge slack (`QUARTER_PIXEL - EDGE_SLACK`
/// in reconstruct.wgsl): motion at least this long is judged by CSO's depth test or ASO's
/// assumption.
const QUARTER_PIXEL: f64 = 2.0 - 1.0 / 64.0;

/// What the CPU expects of every pixel (row-major) in `frame`, None where the reconstruction
/// cannot know (a missing pixel whose neighbours show other surfaces).
fn expected_sources(
    rects: &[PixelRect],
    screen: (u32, u32),
    frame: u32,
    detection: Detection,
) -> Vec<Option<PixelSource>> {
    let (now, before) = (sampled_pixels(screen, frame % 2), sampled_pixels(screen, 1 - frame % 2));
    let on_screen = |x: i64, y: i64| (0..i64::from(screen.0)).contains(&x) && (0..i64::from(screen.1)).contains(&y);
    let index = |x: i64, y: i64| (y * i64::from(screen.0) + x) as usize;
    let expected = |x: i64, y: i64| -> Option<PixelSource> {
        if now[index(x, y)] {
            return Some(PixelSource::Current);
        }
        let shown = surface(rects, x, y, frame)?;
        let interior = [(-1, 0), (1, 0), (0, -1), (0, 1)]
            .iter()
            .all(|(dx, dy)| on_screen(x + dx, y + dy) && surface(rects, x + dx, y + dy, frame) == Some(shown));
        if !interior {
            return None;
        }
        let (vx, vy) = rects[shown].velocity;
        let (bx, by) = (x - i64::from(vx), y - i64::from(vy));
        Some(if !on_screen(bx, by) {
            PixelSource::OffScreen
        } else if !before[index(bx, by)] {
            if now[index(bx, by)] { PixelSource::JitterCancelled } else { PixelSource::OffScreen }
        } else {
            let then = surface(rects, bx, by, frame - 1);
            let moving = |rect: Option<usize>| rect.is_some_and(|i| rects[i].velocity != (0, 0));
            let far = f64::from(vx).hypot(f64::from(vy)) >= QUARTER_PIXEL;
            if moving(then) != moving(Some(shown)) {
                // History that moved with an object where this pixel does not (or the reverse).
                PixelSource::Disoccluded
            } else if far && detection == Detection::Aso {
                PixelSource::Assumed
            } else if then != Some(shown) {
                PixelSource::Disoccluded
            } else {
                PixelSource::History
            }
        })
    };
    (0..i64::from(screen.1))
        .flat_map(|y| (0..i64::from(screen.0)).map(move |x| (x, y)))
        .map(|(x, y)| expected(x, y))
        .collect()
}

fn run(ctx: &mut Ctx) -> Result<Outcome> {
    let path = CheckerboardPath::for_adapter(ctx.gpu);
    ctx.metric("path", path.name());
    let screen = ctx.params.sizes("size")?[0];
    let frames = u32::try_from(ctx.params.count("frames")?)?;
    let last = frames - 1;
    let (scene, rects) = crossing_rects(screen);
    let mut problems = Vec::new();
    for (shading, detection) in
        Shading::ALL.into_iter().flat_map(|s| [(s, Detection::DEFAULT_CSO), (s, Detection::Aso)])
    {
        // Expected: the CPU's account of every pixel whose source it can know.
        let expected = expected_sources(&rects, screen, last, detection);
        let mut tally: BTreeMap<String, u64> = BTreeMap::new();
        for source in &expected {
            *tally.entry(source.map_or("edge_unknowable", PixelSource::name).into()).or_default() += 1;
        }
        let config = CheckerboardConfig { detection, ..CheckerboardConfig::new(screen, path, shading) };
        let mut checkerboard = Checkerboard::new(ctx.gpu, &scene, config)?;
        for frame in 0..frames {
            checkerboard.render(ctx.gpu, frame)?;
        }
        let colours = read_hdr(ctx.gpu, &checkerboard.reconstruction.colour)?;
        let sources = read_sources(ctx.gpu, &checkerboard.reconstruction)?;

        let mut wrong = Vec::new();
        for y in 0..i64::from(screen.1) {
            for x in 0..i64::from(screen.0) {
                let i = (y * i64::from(screen.0) + x) as usize;
                let Some(expected) = expected[i] else { continue };
                if sources[i] != expected {
                    wrong.push(format!("({x}, {y}) {} not {}", sources[i].name(), expected.name()));
                    continue;
                }
                let shown = surface(&rects, x, y, last).expect("every pixel shows the backdrop at least");
                let (got, albedo) = (&colours[i * 4..i * 4 + 3], rects[shown].albedo);
                if got.iter().zip(albedo).any(|(g, a)| (g - a).abs() > COLOUR_TOLERANCE * a.max(1.0 / 255.0)) {
                    wrong.push(format!("({x}, {y}) from {} shows {got:?}, its rect is {albedo:?}", expected.name()));
                }
            }
        }
        let key = format!("{}.{}", shading.name(), detection.name());
        ctx.metric(&format!("{key}.expected"), &tally);
        ctx.metric(&format!("{key}.wrong"), wrong.len());
        if !wrong.is_empty() {
            problems.push(format!(
                "{key}: {} pixels wrong, e.g. {}",
                wrong.len(),
                wrong[..wrong.len().min(4)].join("; ")
            ));
        }
    }
    Ok(if problems.is_empty() { Outcome::Pass } else { Outcome::Fail(problems.join("; ")) })
}
