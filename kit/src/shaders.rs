//! The WGSL sources under `shaders/`. WGSL has no includes, so every pass file is compiled with
//! the common snippets prepended; `tests/shaders.rs` validates each assembled module with naga.
//!
//! For mutation testing and shader development, `FRAGKIT_SHADER_DIR=<dir>` makes every module read
//! its files from `<dir>/<path>` at run time instead of the copies built into the binary, so a
//! changed shader needs no rebuild (`mutants/run`).

use std::borrow::Cow;

use crate::gpu::Gpu;

/// Helper functions every pass may call (no bindings, no entry points).
pub const COMMON: &[(&str, &str)] = &[
    ("common/fullscreen.wgsl", include_str!("../../shaders/common/fullscreen.wgsl")),
    ("common/hash.wgsl", include_str!("../../shaders/common/hash.wgsl")),
    ("common/lighting.wgsl", include_str!("../../shaders/common/lighting.wgsl")),
    ("common/opacity.wgsl", include_str!("../../shaders/common/opacity.wgsl")),
    ("common/checkerboard.wgsl", include_str!("../../shaders/common/checkerboard.wgsl")),
    ("common/foveation.wgsl", include_str!("../../shaders/common/foveation.wgsl")),
];

/// One pass's shader file, named by its path under `shaders/`.
#[derive(Clone, Copy, Debug)]
pub struct ShaderFile {
    pub path: &'static str,
    pub source: &'static str,
}

macro_rules! shader_files {
    ($($name:ident => $path:literal),* $(,)?) => {
        $(pub const $name: ShaderFile = ShaderFile { path: $path, source: include_str!(concat!("../../shaders/", $path)) };)*
        /// Every pass file the kit compiles.
        pub const ALL: &[ShaderFile] = &[$($name),*];
    };
}

shader_files! {
    RECT => "kit/rect.wgsl",
    FULLSCREEN => "kit/fullscreen.wgsl",
    SAMPLE_POSITION => "kit/sample_position.wgsl",
    SAMPLE_COVERAGE_RECORD => "kit/sample_coverage_record.wgsl",
    SLOPED_EDGE => "kit/sloped_edge.wgsl",
    ALPHA_RAMP => "kit/alpha_ramp.wgsl",
    HEAVY_SHADING => "kit/heavy_shading.wgsl",
    FRAGMENT_COUNTER => "kit/fragment_counter.wgsl",
    FRAGMENT_STORAGE => "kit/fragment_storage.wgsl",
    INDIRECT_DRAW => "kit/indirect_draw.wgsl",
    NOISE_TRIANGLES => "kit/noise_triangles.wgsl",
    MIP_FETCH => "kit/mip_fetch.wgsl",
    HASH_VALUES => "kit/hash_values.wgsl",
    DEPTH_BITS => "kit/depth_bits.wgsl",
    GBUFFER => "deferred/gbuffer.wgsl",
    DEFERRED_LIGHTING => "deferred/lighting.wgsl",
    CPS_EDGE_MASK => "cps/edge_mask.wgsl",
    CPS_LOD => "cps/lod.wgsl",
    CPS_MASK_REDUCE => "cps/mask_reduce.wgsl",
    CPS_LIGHTING => "cps/lighting.wgsl",
    CPS_COMPOSITE => "cps/composite.wgsl",
    CPS_STENCIL_MARK => "cps/stencil_mark.wgsl",
    TEXARRAY_FETCH => "texarray/fetch.wgsl",
    CBR_SAMPLE_ID_RECORD => "cbr/sample_id_record.wgsl",
    CBR_LAYOUT_VALUES => "cbr/layout_values.wgsl",
    CBR_SCENE => "cbr/scene.wgsl",
    CBR_SHADE_SAMPLES => "cbr/shade_samples.wgsl",
    CBR_SHADE_MSAA_SAMPLES => "cbr/shade_msaa_samples.wgsl",
    CBR_UNPACK_SAMPLES => "cbr/unpack_samples.wgsl",
    CBR_RECONSTRUCT => "cbr/reconstruct.wgsl",
    CBR_UPSCALE => "cbr/upscale.wgsl",
    CBR_TURN_BACK => "cbr/turn_back.wgsl",
    OIT_QUAD => "oit/quad.wgsl",
    OIT_NOISE_STEP => "oit/noise_step.wgsl",
    OIT_STOCHASTIC => "oit/stochastic.wgsl",
    OIT_SAMPLE_MASK => "oit/sample_mask.wgsl",
    OIT_PLAIN_COVERAGE => "oit/plain_coverage.wgsl",
    OIT_SORTED_BLEND => "oit/sorted_blend.wgsl",
    OIT_WEIGHTED_ACCUMULATE => "oit/weighted_accumulate.wgsl",
    OIT_WEIGHTED_COMPOSITE => "oit/weighted_composite.wgsl",
    OIT_PEEL => "oit/peel.wgsl",
    OIT_UNDER => "oit/under.wgsl",
    OIT_TEMPORAL => "oit/temporal.wgsl",
    OIT_BILATERAL => "oit/bilateral.wgsl",
}

pub use fragkit_report::run_info::SHADER_DIR_ENV;

/// The text of shader file `path`: from `FRAGKIT_SHADER_DIR` when set, else the built-in copy.
/// An override folder that lacks the file is a setup mistake worth stopping for, not a fallback.
fn source_of(path: &str, built_in: &'static str) -> Cow<'static, str> {
    match std::env::var_os(SHADER_DIR_ENV) {
        None => Cow::Borrowed(built_in),
        Some(dir) => {
            let file = std::path::Path::new(&dir).join(path);
            match std::fs::read_to_string(&file) {
                Ok(text) => Cow::Owned(text),
                Err(e) => panic!("{SHADER_DIR_ENV}: reading {}: {e}", file.display()),
            }
        }
    }
}

/// Checks, before any case runs, that a `FRAGKIT_SHADER_DIR` override holds every shader file.
pub fn check_shader_dir() -> anyhow::Result<()> {
    let Some(dir) = std::env::var_os(SHADER_DIR_ENV) else {
        return Ok(());
    };
    let dir = std::path::Path::new(&dir);
    let paths = COMMON.iter().map(|(path, _)| *path).chain(ALL.iter().map(|file| file.path));
    let missing: Vec<&str> = paths.filter(|path| !dir.join(path).is_file()).collect();
    anyhow::ensure!(
        missing.is_empty(),
        "{SHADER_DIR_ENV}={} lacks shader files {missing:?}; copy the whole shaders/ folder there",
        dir.display()
    );
    Ok(())
}

impl ShaderFile {
    /// The module source as compiled: common snippets, then the pass.
    pub fn assembled(&self) -> String {
        let mut source = String::new();
        for (path, common) in COMMON {
            source.push_str(&format!("// ---- {path}\n{}\n", source_of(path, common)));
        }
        source.push_str(&format!("// ---- {}\n{}", self.path, source_of(self.path, self.source)));
        source
    }

    pub fn module(&self, gpu: &Gpu) -> wgpu::ShaderModule {
        self.module_from(gpu, self.assembled())
    }

    /// This file's module compiled from `source`: its assembled text, changed for the device.
    pub fn module_from(&self, gpu: &Gpu, source: String) -> wgpu::ShaderModule {
        gpu.device.create_shader_module(wgpu::ShaderModuleDescriptor {
            label: Some(self.path),
            source: wgpu::ShaderSource::Wgsl(source.into()),
        })
    }

    /// The module source for single-sampled targets: `sample` interpolation becomes `center`.
    /// With one sample per pixel the sample *is* the pixel centre (Vulkan's standard 1x position,
    /// GL's `sample` qualifier at 1x), so the meaning is the same, while APIs without per-sample
    /// shading (GL 3.3: softpipe) refuse a shader that names `sample` at all.
    pub fn single_sampled(&self) -> String {
        self.assembled()
            .replace("@interpolate(perspective, sample)", "@interpolate(perspective, center)")
            .replace("@interpolate(linear, sample)", "@interpolate(linear, center)")
    }

    /// [`Self::module`] for a pipeline of `samples` per pixel: [`Self::single_sampled`] at 1.
    pub fn module_for_samples(&self, gpu: &Gpu, samples: u32) -> wgpu::ShaderModule {
        let source = if samples == 1 { self.single_sampled() } else { self.assembled() };
        self.module_from(gpu, source)
    }
}
