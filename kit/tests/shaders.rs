//! Every WGSL file under `shaders/` is registered, validates with naga once the common snippets
//! are prepended, and has no compute entry point: the kit is render-only.

use std::collections::BTreeSet;
use std::path::{Path, PathBuf};

use fragkit::shaders::{ALL, COMMON};

fn wgsl_files(dir: &Path, root: &Path, found: &mut BTreeSet<String>) {
    for entry in std::fs::read_dir(dir).expect("reading shaders/") {
        let path = entry.expect("directory entry").path();
        if path.is_dir() {
            wgsl_files(&path, root, found);
        } else if path.extension().is_some_and(|e| e == "wgsl") {
            found.insert(path.strip_prefix(root).unwrap().to_string_lossy().replace('\\', "/"));
        }
    }
}

fn shaders_dir() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../shaders")
}

#[test]
fn every_shader_file_is_registered() {
    let mut on_disk = BTreeSet::new();
    wgsl_files(&shaders_dir(), &shaders_dir(), &mut on_disk);
    let registered: BTreeSet<String> =
        ALL.iter().map(|f| f.path.to_owned()).chain(COMMON.iter().map(|(p, _)| (*p).to_owned())).collect();
    assert_eq!(on_disk, registered, "shaders on disk vs shaders::ALL + shaders::COMMON");
}

fn validate(name: &str, source: &str) -> naga::Module {
    validate_with(name, source, naga::valid::Capabilities::all()).unwrap_or_else(|e| panic!("{e}"))
}

fn validate_with(name: &str, source: &str, capabilities: naga::valid::Capabilities) -> Result<naga::Module, String> {
    let module =
        naga::front::wgsl::parse_str(source).unwrap_or_else(|e| panic!("{name}: {}", e.emit_to_string(source)));
    naga::valid::Validator::new(naga::valid::ValidationFlags::all(), capabilities)
        .validate(&module)
        .map_err(|e| format!("{name}: {e:?}"))?;
    Ok(module)
}

/// GL 3.3 (softpipe) has no per-sample shading; the checkerboard scene's single-sampled passes
/// (offset passes, full-resolution reference) must not need it, while its 2x form does.
#[test]
fn the_single_sampled_checkerboard_scene_needs_no_per_sample_shading() {
    let without = naga::valid::Capabilities::all() - naga::valid::Capabilities::MULTISAMPLED_SHADING;
    let scene = fragkit::shaders::CBR_SCENE;
    validate_with(scene.path, &scene.single_sampled(), without).unwrap();
    let error = validate_with(scene.path, &scene.assembled(), without).unwrap_err();
    assert!(error.contains("MULTISAMPLED_SHADING"), "{error}");
}

#[test]
fn every_shader_validates_and_has_no_compute_entry_point() {
    // The common snippets build on each other in order, as they are prepended.
    let common: String = COMMON.iter().map(|(_, source)| *source).collect::<Vec<_>>().join("\n");
    let module = validate("shaders/common/*", &common);
    assert!(module.entry_points.is_empty(), "common snippets must not declare entry points");
    for file in ALL {
        let module = validate(file.path, &file.assembled());
        assert!(!module.entry_points.is_empty(), "{}: no entry point", file.path);
        for entry in &module.entry_points {
            assert_ne!(entry.stage, naga::ShaderStage::Compute, "{}: compute entry point {:?}", file.path, entry.name);
        }
    }
}

#[test]
fn the_compute_check_catches_a_compute_entry_point() {
    let module = validate("inline", "@compute @workgroup_size(1) fn main() {}");
    assert!(module.entry_points.iter().any(|e| e.stage == naga::ShaderStage::Compute));
}

/// Where fragment shaders have no storage buffers (GL 3.3) the reconstruction compiles with its
/// parameters in a uniform buffer: the very source the renderer builds then, valid, `rebuild` in
/// the uniform address space and nothing else changed.
#[test]
fn the_reconstruction_with_its_parameters_in_a_uniform_buffer_validates() {
    use fragkit::cbr::reconstruct::ParameterBuffer;
    let storage = ParameterBuffer::Storage.shader_source().unwrap();
    let uniform = ParameterBuffer::Uniform.shader_source().unwrap();
    assert_eq!(storage, fragkit::shaders::CBR_RECONSTRUCT.assembled());
    let module = validate("cbr/reconstruct.wgsl (uniform parameters)", &uniform);
    let spaces: Vec<_> = module
        .global_variables
        .iter()
        .filter(|(_, v)| v.name.as_deref() == Some("rebuild"))
        .map(|(_, v)| v.space)
        .collect();
    assert_eq!(spaces, [naga::AddressSpace::Uniform]);
    assert_eq!(uniform.lines().count(), storage.lines().count());
}
