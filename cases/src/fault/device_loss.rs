//! `fault.device_loss`: renders and reads back a frame, destroys the device (`Device::destroy`,
//! wgpu's way to simulate a loss), and renders again. The second read-back must end in an error,
//! not hang or return stale pixels; the runner records the case as `fail` naming the loss, opens a
//! new device and runs the remaining cases on it.

use anyhow::{Result, bail};
use fragkit::cbr::FullResolutionScene;
use fragkit::cbr::measure::read_hdr;
use fragkit::cbr::scene::flat_rects;
use fragkit::harness::{Case, Ctx, Outcome};
use fragkit::shaders::CBR_SCENE;

pub const CASE: Case = Case {
    name: "fault.device_loss",
    summary: "the device destroyed mid-case: that case fails naming the loss, the run goes on (fails on purpose)",
    requires: wgpu::Features::empty(),
    params: &[],
    sweep: &[],
    budget_s: 1,
    timed_verdict: false,
    shaders: &[CBR_SCENE],
    run,
};

fn run(ctx: &mut Ctx) -> Result<Outcome> {
    let screen = (16, 16);
    let scene = flat_rects(screen, 1, glam::Vec2::ZERO);
    let mut render = FullResolutionScene::new(ctx.gpu, &scene, screen)?;
    render.render(ctx.gpu, 0)?;
    let before = read_hdr(ctx.gpu, render.output())?;
    ctx.metric("pixels_read_before_the_loss", before.len() / 4);

    ctx.gpu.device.destroy();
    let after = render.render(ctx.gpu, 0).and_then(|_| read_hdr(ctx.gpu, render.output()));
    match after {
        Ok(_) => bail!("the device was destroyed, yet a frame rendered and read back"),
        Err(error) => {
            ctx.metric("error_after_the_loss", format!("{error:#}"));
            Ok(Outcome::Pass)
        }
    }
}
