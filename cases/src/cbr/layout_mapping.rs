//! `cbr.layout.mapping`: the sample layout's WGSL functions, which the reconstruction and the
//! deferred shade passes call, agree with the definition of where checkerboard samples land
//! (kit/src/cbr/sampling.rs: sample s of quarter pixel q sees pixel ⌊2(q + p_s) + (phase, 0)⌋ for
//! the standard 2x positions p_s, and sits at layout texel (q.y + s·Hq, Wq − 1 − q.x), its view
//! turned a quarter): every pixel maps to the texel holding its sample (or none), and every
//! texel's pixel centre is that pixel's centre, exactly, both phases, odd sizes included.

use anyhow::Result;
use fragkit::cbr::frame::layout_size;
use fragkit::cbr::layout_values::evaluate_layout;
use fragkit::cbr::sampling::{check_screen, quarter_size, sample_pixel, sample_positions};
use fragkit::harness::{Case, Ctx, Outcome, ParamKind, ParamSpec, Sweep, SweepRange, Verdict};
use fragkit::shaders::{CBR_LAYOUT_VALUES, FULLSCREEN};

pub const CASE: Case = Case {
    name: "cbr.layout.mapping",
    summary: "the layout functions place every checkerboard sample where the sampling definition says",
    requires: wgpu::Features::empty(),
    params: &[ParamSpec {
        name: "sizes",
        kind: ParamKind::SizesFrom(2),
        default: "2x2,7x5,64x48",
        help: "full-resolution sizes",
    }],
    sweep: &[Sweep { param: "sizes", range: SweepRange::Size { min: (2, 2), max: (400, 300) } }],
    budget_s: 1,
    timed_verdict: false,
    shaders: &[FULLSCREEN, CBR_LAYOUT_VALUES],
    run,
};

/// Every place (row-major, `width` wide) where `got` differs from `defined`, described.
fn mismatches<T: PartialEq + std::fmt::Debug>(got: &[T], defined: &[T], width: u32, what: &str) -> Vec<String> {
    (0..got.len())
        .filter(|&i| got[i] != defined[i])
        .map(|i| format!("{what} ({}, {}): {:?}, defined {:?}", i as u32 % width, i as u32 / width, got[i], defined[i]))
        .collect()
}

fn run(ctx: &mut Ctx) -> Result<Outcome> {
    let positions = sample_positions();
    let mut verdict = Verdict::new();
    for screen in ctx.params.sizes("sizes")? {
        check_screen(screen)?;
        let quarter = quarter_size(screen);
        let layout = layout_size(screen);
        for phase in 0..2 {
            let got = evaluate_layout(ctx.gpu, screen, phase)?;
            // Expected: the definition, walked from every sample to its pixel.
            let mut texel_of_pixel = vec![None; (screen.0 * screen.1) as usize];
            let mut centre_of_texel = vec![[0.0f32; 2]; (layout.0 * layout.1) as usize];
            for (qy, qx, sample) in
                (0..quarter.1).flat_map(|y| (0..quarter.0).flat_map(move |x| [(y, x, 0), (y, x, 1)]))
            {
                let (x, y) = sample_pixel((qx, qy), sample, phase, &positions);
                let texel = (qy + sample as u32 * quarter.1, quarter.0 - 1 - qx);
                centre_of_texel[(texel.1 * layout.0 + texel.0) as usize] = [x as f32 + 0.5, y as f32 + 0.5];
                if (0..i64::from(screen.0)).contains(&x) && (0..i64::from(screen.1)).contains(&y) {
                    texel_of_pixel[(y as u32 * screen.0 + x as u32) as usize] = Some(texel);
                }
            }
            let name = format!("{}x{}.phase{phase}", screen.0, screen.1);
            let pixel_errors = mismatches(&got.texel_of_pixel, &texel_of_pixel, screen.0, "pixel");
            let centre_errors = mismatches(&got.centre_of_texel, &centre_of_texel, layout.0, "texel");
            ctx.metric(&format!("{name}.wrong_pixels"), pixel_errors.len());
            ctx.metric(&format!("{name}.wrong_centres"), centre_errors.len());
            for (what, errors) in [("pixels", pixel_errors), ("texel centres", centre_errors)] {
                if !errors.is_empty() {
                    verdict.fail(format!(
                        "{name}: {} {what} wrong, e.g. {}",
                        errors.len(),
                        errors[..errors.len().min(2)].join(", ")
                    ));
                }
            }
        }
    }
    Ok(verdict.outcome())
}
