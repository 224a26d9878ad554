//! `soak.cps`: coarse pixel shading of the corridor (foveated, seam-free composite), the camera
//! walking forward, the G-buffer re-rendered every frame.

use anyhow::Result;
use fragkit::cps::renderer::CpsFrame;
use fragkit::cps::{CompositeMode, CpsConfig, CpsRenderer, LodPolicy};
use fragkit::deferred::gbuffer::GbufferPass;
use fragkit::deferred::lights::LightTexture;
use fragkit::gpu::Gpu;
use fragkit::harness::{Case, Ctx, Outcome};
use fragkit::query::GpuTimer;
use fragkit::readback::read_texture;
use fragkit::scene::corridor::{Scene, corridor};
use fragkit::shaders::{CPS_COMPOSITE, CPS_LIGHTING, CPS_LOD, CPS_STENCIL_MARK, FULLSCREEN, GBUFFER, RECT};

use super::{PARAMS, Soaked, soak};

pub const CASE: Case = Case {
    name: "soak.cps",
    summary: "coarse pixel shading over many frames and resizes: no memory growth, last frame reproducible",
    requires: wgpu::Features::empty(),
    params: PARAMS,
    sweep: &[],
    budget_s: 51,
    timed_verdict: false,
    shaders: &[RECT, FULLSCREEN, GBUFFER, CPS_LOD, CPS_LIGHTING, CPS_COMPOSITE, CPS_STENCIL_MARK],
    run,
};

struct CpsSoak {
    scene: Scene,
    lights: LightTexture,
    gbuffer: GbufferPass,
    renderer: CpsRenderer,
}

impl Soaked for CpsSoak {
    type Setup = ();

    fn setup(_gpu: &Gpu) -> Result<()> {
        Ok(())
    }

    fn new(gpu: &Gpu, _setup: &(), size: (u32, u32)) -> Result<Self> {
        let scene = corridor(1, 8);
        let config = CpsConfig::new(4, LodPolicy::foveated(), CompositeMode::SeamFree);
        Ok(Self {
            lights: LightTexture::new(gpu, &scene.lights)?,
            gbuffer: GbufferPass::new(gpu, size)?,
            renderer: CpsRenderer::new(gpu, size, config)?,
            scene,
        })
    }

    fn render(&mut self, gpu: &Gpu, frame: u32) -> Result<()> {
        let mut scene = self.scene.clone();
        scene.camera.eye.z -= 0.01 * (frame % 200) as f32;
        self.gbuffer.render(gpu, &scene, &mut GpuTimer::new(gpu, 1));
        let frame = CpsFrame { gbuffer: &self.gbuffer.gbuffer, lights: &self.lights, eye: scene.camera.eye };
        self.renderer.render(gpu, &frame)?;
        Ok(())
    }

    fn output(&self, gpu: &Gpu) -> Result<Vec<u8>> {
        Ok(read_texture(gpu, &self.renderer.image, wgpu::TextureAspect::All, 0)?.bytes)
    }
}

fn run(ctx: &mut Ctx) -> Result<Outcome> {
    soak::<CpsSoak>(ctx)
}
