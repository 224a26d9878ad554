//! Shared set-up for the case tests: one GPU for the whole test binary (the adapter chosen the
//! way `fragkit check` chooses it: WGPU_BACKEND / WGPU_ADAPTER_NAME, else the default), used by
//! one test at a time so that timed cases are not disturbed by the others.

// Each test binary uses part of this module.
#![allow(dead_code)]

use std::collections::BTreeMap;
use std::path::Path;
use std::sync::{Mutex, OnceLock};

use fragkit::harness::Case;
use fragkit::harness::runner::run_case;
use fragkit::{AdapterSelector, Gpu};
use fragkit_report::expectations::Expectations;
use fragkit_report::report::CaseRecord;

pub fn gpu() -> &'static Mutex<Gpu> {
    static GPU: OnceLock<Mutex<Gpu>> = OnceLock::new();
    GPU.get_or_init(|| {
        let gpu = Gpu::open(&AdapterSelector::default()).unwrap_or_else(|e| panic!("{e:#}"));
        Mutex::new(gpu)
    })
}

pub fn expectations() -> Expectations {
    Expectations::parse(fragkit_cases::EXPECTATIONS, "cases/expectations.toml").expect("built-in expectations parse")
}

/// Runs one registered case on the shared GPU with its default parameters; also returns the
/// shader files modules were built from while it ran.
pub fn run(name: &str) -> (CaseRecord, String, Vec<&'static str>) {
    let case = fragkit_cases::all().iter().find(|c| c.name == name).unwrap_or_else(|| panic!("no case {name}"));
    run_with(case, &BTreeMap::new())
}

/// Runs one case on the shared GPU with `overrides` applied to its parameters; also returns the
/// shader files modules were built from while it ran.
pub fn run_with(case: &Case, overrides: &BTreeMap<String, String>) -> (CaseRecord, String, Vec<&'static str>) {
    let gpu = gpu().lock().unwrap_or_else(|poisoned| poisoned.into_inner());
    gpu.take_shader_paths();
    let record = run_case(&gpu, case, overrides, &expectations(), None);
    (record, gpu.description.slug(), gpu.take_shader_paths())
}

/// Whether this adapter has snapshots of its own (or new ones are being recorded). An adapter
/// without them is skipped explicitly: lavapipe's snapshots must not judge another GPU.
pub fn has_snapshots(slug: &str) -> bool {
    if std::env::var("INSTA_UPDATE").is_ok_and(|v| v == "always" || v == "new") {
        return true;
    }
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("../snapshots");
    let suffix = format!("@{slug}.snap");
    let found = std::fs::read_dir(&dir)
        .is_ok_and(|entries| entries.flatten().any(|e| e.file_name().to_string_lossy().ends_with(&suffix)));
    if !found {
        eprintln!(
            "SKIPPED snapshots: none recorded for adapter {slug}; record them with \
             `INSTA_UPDATE=always cargo test -p fragkit-cases` and review the new files in snapshots/"
        );
    }
    found
}
