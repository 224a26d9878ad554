//! `kit.fetch.per_pixel_level`: `textureLoad` from a mipmapped texture at a level that differs
//! between neighbouring pixels (what a composite over a mip pyramid does: each pixel reads its
//! own level) returns every pixel's own level's texel. Level maps vary per pixel, per 2×2 quad, per 4×4 and
//! per 8×8 block (seeded), so a failure also says at what granularity the adapter may vary the
//! level; each is fetched with the level straight from the map and with the level as a loop
//! counter (uniform across lanes). The measurement is `fragkit::probe::mip_fetch`. The CPS
//! composite keeps its levels in one atlas, so it reads at per-pixel offsets, never at per-pixel
//! levels, and is correct where this probe fails (GL llvmpipe).

use anyhow::Result;
use fragkit::harness::{Case, Ctx, Outcome, ParamKind, ParamSpec, Sweep, SweepRange, Verdict};
use fragkit::image_compare::side_by_side;
use fragkit::probe::mip_fetch::{PRESENT, levels, measure};
use fragkit::shaders::{FULLSCREEN, MIP_FETCH};
use image::{Rgba, RgbaImage};

pub const CASE: Case = Case {
    name: "kit.fetch.per_pixel_level",
    summary: "textureLoad at a mip level that varies between neighbouring pixels reads each pixel's own level",
    requires: wgpu::Features::empty(),
    params: &[
        ParamSpec {
            name: "size",
            kind: ParamKind::Size,
            default: "64x64",
            help: "target and base mip size (powers of two, at most 4096)",
        },
        ParamSpec { name: "seed", kind: ParamKind::CountIn(0, u32::MAX as u64), default: "1", help: "seed of the level maps" },
    ],
    sweep: &[Sweep { param: "seed", range: SweepRange::Count(0, 1 << 20) }],
    budget_s: 1,
    timed_verdict: false,
    shaders: &[FULLSCREEN, MIP_FETCH],
    run,
};

fn describe(value: u32) -> String {
    if value & PRESENT == 0 {
        format!("{value} (no texel: out of the level's bounds)")
    } else {
        format!("level {} texel ({}, {})", (value >> 24) & 0x7f, value & 0xfff, (value >> 12) & 0xfff)
    }
}

/// A picture of fetched values: red = level, green and blue = texel coordinates.
fn picture(values: &[u32], size: (u32, u32), levels: u32) -> RgbaImage {
    RgbaImage::from_fn(size.0, size.1, |x, y| {
        let v = values[(y * size.0 + x) as usize];
        let level = ((v >> 24) & 0x7f).min(levels);
        Rgba([(255 * level / levels.max(1)) as u8, (((v >> 12) & 0xfff) * 37) as u8, ((v & 0xfff) * 53) as u8, 255])
    })
}

fn run(ctx: &mut Ctx) -> Result<Outcome> {
    // Setup, render and measure: seeded level maps of every block size, fetched both ways.
    let size = ctx.params.size("size")?;
    let seed = ctx.params.count_u32("seed")?;
    let measurements = measure(ctx.gpu, size, seed)?;
    let levels = levels(size);
    ctx.metric("levels", levels);

    // Compare with the expectation: each pixel reads its own level's texel p >> level.
    let mut verdict = Verdict::new();
    for m in &measurements {
        let wrong = m.wrong();
        let label = format!("{}.{}x{}", m.way, m.block, m.block);
        ctx.metric(&format!("{label}.wrong_fetches"), wrong.len());
        let Some(&first) = wrong.first() else { continue };
        let (x, y) = (first as u32 % size.0, first as u32 / size.0);
        verdict.fail(format!(
            "level {} per {}x{} block: {} of {} fetches read another texel (pixel ({x}, {y}) at level {} read {})",
            m.way,
            m.block,
            m.block,
            wrong.len(),
            m.expected.len(),
            m.level_map[first],
            describe(m.fetched[first])
        ));
        let mask = RgbaImage::from_fn(size.0, size.1, |x, y| {
            let i = (y * size.0 + x) as usize;
            if m.fetched[i] == m.expected[i] { Rgba([0, 0, 0, 255]) } else { Rgba([255, 0, 0, 255]) }
        });
        let evidence = side_by_side(&picture(&m.fetched, size, levels), &picture(&m.expected, size, levels), &mask);
        ctx.evidence_image(&label, &evidence)?;
    }
    Ok(verdict.outcome())
}
