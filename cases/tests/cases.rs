//! One test per registered case, generated from the registry: it fails when the case ends in an unexpected failure (a fail
//! not listed in cases/expectations.toml, or a listed one that passed). Where the result is
//! adapter-specific, its outcome and metrics (timings left out) are snapshotted per adapter.

mod support;

use fragkit::harness::runner::is_opt_in;
use fragkit_report::report::{CaseRecord, is_timing_metric};

fn check(name: &str) {
    let (record, slug, built) = support::run(name);
    let case = fragkit_cases::all().iter().find(|c| c.name == name).expect("registered");
    let unlisted: Vec<&str> = built.into_iter().filter(|path| !case.shaders.iter().any(|f| f.path == *path)).collect();
    assert!(unlisted.is_empty(), "{name} built modules from shader files its `shaders` does not list: {unlisted:?}");
    assert!(
        !record.outcome.is_failure(false),
        "{name}: {:?}: {}\nmetrics: {}",
        record.outcome,
        record.reason,
        serde_json::to_string_pretty(&record.metrics).unwrap()
    );
    if support::has_snapshots(&slug) {
        snapshot(&record, &slug);
    }
}

fn snapshot(record: &CaseRecord, slug: &str) {
    let mut metrics = record.metrics.clone();
    metrics.retain(|k, _| !is_timing_metric(k));
    let mut settings = insta::Settings::clone_current();
    settings.set_snapshot_path("../../snapshots");
    settings.set_snapshot_suffix(slug);
    settings.set_prepend_module_to_snapshot(false);
    settings.bind(|| {
        insta::assert_json_snapshot!(
            record.name.clone(),
            serde_json::json!({"outcome": record.outcome, "metrics": metrics})
        );
    });
}

/// One test per registered case, named after it (`cargo test --test cases kit.hash` runs those
/// whose names hold `kit.hash`). Opt-in cases are tested where they are meant to run: fault.* by
/// tests/cli.rs (between ordinary cases), soak.* by tests/soak.rs.
fn main() {
    let arguments = libtest_mimic::Arguments::from_args();
    let trials = fragkit_cases::all()
        .iter()
        .filter(|case| !is_opt_in(case.name))
        .map(|case| libtest_mimic::Trial::test(case.name, move || catch(case.name)))
        .collect();
    libtest_mimic::run(&arguments, trials).exit();
}

/// A case's check as a trial's result: its assertion message when it fails.
fn catch(name: &'static str) -> Result<(), libtest_mimic::Failed> {
    std::panic::catch_unwind(|| check(name)).map_err(|panic| {
        let message = panic
            .downcast_ref::<String>()
            .cloned()
            .or_else(|| panic.downcast_ref::<&str>().map(|s| (*s).to_owned()))
            .unwrap_or_else(|| "the check panicked".to_owned());
        message.into()
    })
}
