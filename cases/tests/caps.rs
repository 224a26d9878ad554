//! The measured capabilities of the test adapter, snapshotted per adapter: a driver update that
//! changes sample positions, the alpha-to-coverage transfer function or query precision shows up
//! as a snapshot diff.

mod support;

use fragkit::caps::Caps;

#[test]
fn measured_capabilities() {
    let gpu = support::gpu().lock().unwrap_or_else(|p| p.into_inner());
    let caps = Caps::measure(&gpu).unwrap_or_else(|e| panic!("{e:#}"));
    assert!(caps.real_sample_counts().contains(&1), "a single-sampled target must render at the pixel centre");
    let slug = gpu.description.slug();
    if support::has_snapshots(&slug) {
        let mut settings = insta::Settings::clone_current();
        settings.set_snapshot_path("../../snapshots");
        settings.set_snapshot_suffix(slug);
        settings.set_prepend_module_to_snapshot(false);
        settings.bind(|| insta::assert_json_snapshot!("caps", caps));
    }
}
