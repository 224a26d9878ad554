//! Deferred shading: the G-buffer of a scene, its lights in a texture, and full-resolution
//! lighting (the reference coarse pixel shading is measured against).

pub mod gbuffer;
pub mod lighting;
pub mod lights;
pub mod phong;
pub mod surface_model;

use anyhow::Result;
use glam::Vec3;

use crate::gpu::Gpu;
use crate::query::GpuTimer;
use crate::scene::corridor::Scene;

/// A scene ready to light: its G-buffer at one size, its lights, the eye.
pub struct DeferredInputs {
    pub gbuffer: gbuffer::Gbuffer,
    pub lights: lights::LightTexture,
    pub eye: Vec3,
}

impl DeferredInputs {
    pub fn new(gpu: &Gpu, scene: &Scene, size: (u32, u32)) -> Result<Self> {
        let lights = lights::LightTexture::new(gpu, &scene.lights)?;
        let mut timer = GpuTimer::new(gpu, 1);
        let gbuffer = gbuffer::render_gbuffer(gpu, scene, size, &mut timer)?;
        Ok(Self { gbuffer, lights, eye: scene.camera.eye })
    }
}
