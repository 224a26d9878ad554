//! `soak.cbr`: checkerboard rendering (forward, CSO) of the corridor with a box crossing it.

use anyhow::Result;
use fragkit::cbr::sampling::CheckerboardPath;
use fragkit::cbr::scene::{Motion, textured_corridor};
use fragkit::cbr::{Checkerboard, CheckerboardConfig, Shading};
use fragkit::gpu::Gpu;
use fragkit::harness::{Case, Ctx, Outcome};
use fragkit::readback::read_texture;
use fragkit::shaders::{
    CBR_RECONSTRUCT, CBR_SCENE, CBR_SHADE_MSAA_SAMPLES, CBR_UNPACK_SAMPLES, FRAGMENT_STORAGE, FULLSCREEN, RECT, SAMPLE_COVERAGE_RECORD, ShaderFile,
};

use super::{PARAMS, Soaked, soak};

pub const CASE: Case = Case {
    name: "soak.cbr",
    summary: "checkerboarding over many frames and resizes: no memory growth, last frame reproducible",
    requires: wgpu::Features::empty(),
    params: PARAMS,
    sweep: &[],
    budget_s: 85,
    timed_verdict: false,
    shaders: SHADERS,
    run,
};

/// The shader files the checkerboard soak's pipelines are built from (`fault.leak` runs it too).
pub const SHADERS: &[ShaderFile] =
    &[RECT, FULLSCREEN, SAMPLE_COVERAGE_RECORD, FRAGMENT_STORAGE, CBR_SCENE, CBR_SHADE_MSAA_SAMPLES, CBR_UNPACK_SAMPLES, CBR_RECONSTRUCT];

impl Soaked for Checkerboard {
    /// The checkerboard path this adapter gets (real 2x, or the offset passes).
    type Setup = CheckerboardPath;

    fn setup(gpu: &Gpu) -> Result<CheckerboardPath> {
        Ok(CheckerboardPath::for_adapter(gpu))
    }

    fn new(gpu: &Gpu, path: &CheckerboardPath, size: (u32, u32)) -> Result<Self> {
        let scene = textured_corridor(5, 8, Motion::Object(0.01));
        Checkerboard::new(gpu, &scene, CheckerboardConfig::new(size, *path, Shading::Forward))
    }

    fn render(&mut self, gpu: &Gpu, frame: u32) -> Result<()> {
        Checkerboard::render(self, gpu, frame).map(|_| ())
    }

    fn output(&self, gpu: &Gpu) -> Result<Vec<u8>> {
        Ok(read_texture(gpu, &self.reconstruction.colour, wgpu::TextureAspect::All, 0)?.bytes)
    }
}

fn run(ctx: &mut Ctx) -> Result<Outcome> {
    soak::<Checkerboard>(ctx)
}
