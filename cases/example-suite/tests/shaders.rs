//! The suite's own shaders validate with naga and have no compute entry point, as the kit's do
//! (kit/tests/shaders.rs): the suite is render-only too.

#[test]
fn every_shader_validates_and_has_no_compute_entry_point() {
    let dir = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("shaders");
    let mut checked = 0;
    for entry in std::fs::read_dir(&dir).expect("reading the suite's shaders/") {
        let path = entry.expect("directory entry").path();
        let source = std::fs::read_to_string(&path).expect("reading a shader");
        let module = naga::front::wgsl::parse_str(&source)
            .unwrap_or_else(|e| panic!("{}: {}", path.display(), e.emit_to_string(&source)));
        naga::valid::Validator::new(naga::valid::ValidationFlags::all(), naga::valid::Capabilities::all())
            .validate(&module)
            .unwrap_or_else(|e| panic!("{}: {e:?}", path.display()));
        let compute: Vec<&str> = module
            .entry_points
            .iter()
            .filter(|e| e.stage == naga::ShaderStage::Compute)
            .map(|e| e.name.as_str())
            .collect();
        assert!(compute.is_empty(), "{}: compute entry points {compute:?}", path.display());
        checked += 1;
    }
    assert!(checked > 0, "no shader under {}", dir.display());
}
