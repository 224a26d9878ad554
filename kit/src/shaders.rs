//! The kit's shader table: the WGSL sources under `shaders/`, each with the module that builds
//! pipelines from it. WGSL has no includes, so every pass file is compiled with
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

/// One pass's shader file, named by its path under `shaders/`, with the module that builds
/// pipelines from it.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct ShaderFile {
    pub path: &'static str,
    pub source: &'static str,
    /// The Rust module whose pipelines use it (`fragkit::cbr::reconstruct`).
    pub module: &'static str,
}

macro_rules! shader_files {
    ($($name:ident => $path:literal in $module:literal),* $(,)?) => {
        $(pub const $name: ShaderFile = ShaderFile {
            path: $path,
            source: include_str!(concat!("../../shaders/", $path)),
            module: $module,
        };)*
        /// Every pass file the kit compiles.
        pub const ALL: &[ShaderFile] = &[$($name),*];
    };
}

shader_files! {
    RECT => "kit/rect.wgsl" in "fragkit::rects",
    FULLSCREEN => "kit/fullscreen.wgsl" in "fragkit::fullscreen",
    SAMPLE_POSITION => "kit/sample_position.wgsl" in "fragkit::probe::sample_positions",
    SAMPLE_COVERAGE_RECORD => "kit/sample_coverage_record.wgsl" in "fragkit::probe::sample_positions",
    SLOPED_EDGE => "kit/sloped_edge.wgsl" in "fragkit::probe::subpixel_precision",
    ALPHA_RAMP => "kit/alpha_ramp.wgsl" in "fragkit::probe::alpha_to_coverage",
    HEAVY_SHADING => "kit/heavy_shading.wgsl" in "fragkit::probe::stencil_gated_draw",
    FRAGMENT_COUNTER => "kit/fragment_counter.wgsl" in "fragkit::probe::stencil_gated_draw",
    FRAGMENT_STORAGE => "kit/fragment_storage.wgsl" in "fragkit::probe::fragment_storage",
    INDIRECT_DRAW => "kit/indirect_draw.wgsl" in "fragkit::probe::indirect_draw",
    NOISE_TRIANGLES => "kit/noise_triangles.wgsl" in "fragkit-cases kit::determinism",
    MIP_FETCH => "kit/mip_fetch.wgsl" in "fragkit::probe::mip_fetch",
    HASH_VALUES => "kit/hash_values.wgsl" in "fragkit::probe::hash_values",
    DEPTH_BITS => "kit/depth_bits.wgsl" in "fragkit::depth_readback",
    GBUFFER => "deferred/gbuffer.wgsl" in "fragkit::deferred::gbuffer",
    DEFERRED_LIGHTING => "deferred/lighting.wgsl" in "fragkit::deferred::lighting",
    CPS_EDGE_MASK => "cps/edge_mask.wgsl" in "fragkit::cps::renderer",
    CPS_LOD => "cps/lod.wgsl" in "fragkit::cps::renderer",
    CPS_MASK_REDUCE => "cps/mask_reduce.wgsl" in "fragkit::cps::targets",
    CPS_LIGHTING => "cps/lighting.wgsl" in "fragkit::cps::renderer",
    CPS_COMPOSITE => "cps/composite.wgsl" in "fragkit::cps::renderer",
    CPS_STENCIL_MARK => "cps/stencil_mark.wgsl" in "fragkit::cps::stencil_marks",
    TEXARRAY_FETCH => "texarray/fetch.wgsl" in "fragkit::texarray",
    CBR_SAMPLE_ID_RECORD => "cbr/sample_id_record.wgsl" in "fragkit::cbr::sampling",
    CBR_LAYOUT_VALUES => "cbr/layout_values.wgsl" in "fragkit::cbr::layout_values",
    CBR_SCENE => "cbr/scene.wgsl" in "fragkit::cbr::scene_pass",
    CBR_SHADE_SAMPLES => "cbr/shade_samples.wgsl" in "fragkit::cbr::frame",
    CBR_SHADE_MSAA_SAMPLES => "cbr/shade_msaa_samples.wgsl" in "fragkit::cbr::frame",
    CBR_UNPACK_SAMPLES => "cbr/unpack_samples.wgsl" in "fragkit::cbr::frame",
    CBR_RECONSTRUCT => "cbr/reconstruct.wgsl" in "fragkit::cbr::reconstruct",
    CBR_UPSCALE => "cbr/upscale.wgsl" in "fragkit::cbr::renderer",
    CBR_TURN_BACK => "cbr/turn_back.wgsl" in "fragkit::cbr::renderer",
    OIT_QUAD => "oit/quad.wgsl" in "fragkit::oit::stochastic",
    OIT_NOISE_STEP => "oit/noise_step.wgsl" in "fragkit::oit::stochastic",
    OIT_STOCHASTIC => "oit/stochastic.wgsl" in "fragkit::oit::stochastic",
    OIT_SAMPLE_MASK => "oit/sample_mask.wgsl" in "fragkit::oit::stochastic",
    OIT_PLAIN_COVERAGE => "oit/plain_coverage.wgsl" in "fragkit::oit::methods",
    OIT_SORTED_BLEND => "oit/sorted_blend.wgsl" in "fragkit::oit::methods",
    OIT_WEIGHTED_ACCUMULATE => "oit/weighted_accumulate.wgsl" in "fragkit::oit::methods",
    OIT_WEIGHTED_COMPOSITE => "oit/weighted_composite.wgsl" in "fragkit::oit::methods",
    OIT_PEEL => "oit/peel.wgsl" in "fragkit::oit::methods",
    OIT_UNDER => "oit/under.wgsl" in "fragkit::oit::methods",
    OIT_TEMPORAL => "oit/temporal.wgsl" in "fragkit::oit::filter",
    OIT_BILATERAL => "oit/bilateral.wgsl" in "fragkit::oit::filter",
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
        gpu.built_from(self.path);
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
