//! `fault.leak`: the checkerboard soak (`soak.cbr`) with a leak added on purpose — every frame
//! makes a 64 KiB buffer, fills it and forgets it, as a renderer that loses a per-frame staging
//! buffer would. The soak's leak check must fail it with the growth in bytes a frame: about
//! 64 KiB of resident memory, one wgpu buffer and its 64 KiB of buffer memory.

use anyhow::Result;
use fragkit::cbr::Checkerboard;
use fragkit::gpu::Gpu;
use fragkit::harness::{Case, Ctx, Outcome};

use crate::soak::{self, PARAMS, Soaked};

pub const CASE: Case = Case {
    name: "fault.leak",
    summary: "the checkerboard soak leaking a 64 KiB buffer a frame on purpose: the leak check fails it",
    requires: wgpu::Features::empty(),
    params: PARAMS,
    sweep: &[],
    // A leaking soak runs on to four times its length: softpipe's 4000 frames.
    budget_s: 197,
    timed_verdict: false,
    shaders: soak::cbr::SHADERS,
    run,
};

/// Bytes leaked a frame.
const LEAK_BYTES: usize = 64 << 10;

struct Leaking(Checkerboard);

impl Soaked for Leaking {
    type Setup = <Checkerboard as Soaked>::Setup;

    fn setup(gpu: &Gpu) -> Result<Self::Setup> {
        <Checkerboard as Soaked>::setup(gpu)
    }

    fn new(gpu: &Gpu, setup: &Self::Setup, size: (u32, u32)) -> Result<Self> {
        <Checkerboard as Soaked>::new(gpu, setup, size).map(Self)
    }

    fn render(&mut self, gpu: &Gpu, frame: u32) -> Result<()> {
        Soaked::render(&mut self.0, gpu, frame)?;
        let buffer = gpu.device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("fault.leak: forgotten per-frame buffer"),
            size: LEAK_BYTES as u64,
            usage: wgpu::BufferUsages::COPY_DST,
            mapped_at_creation: false,
        });
        // Filled, so the driver's memory behind it is touched (resident), then never destroyed.
        gpu.queue.write_buffer(&buffer, 0, &vec![0xa5; LEAK_BYTES]);
        std::mem::forget(buffer);
        Ok(())
    }

    fn output(&self, gpu: &Gpu) -> Result<Vec<u8>> {
        Soaked::output(&self.0, gpu)
    }
}

fn run(ctx: &mut Ctx) -> Result<Outcome> {
    soak::soak::<Leaking>(ctx)
}
