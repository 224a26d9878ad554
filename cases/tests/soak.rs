//! The soak cases, shortened (160 frames, a resize every 20): they must run to the end on every
//! resize and reproduce their last frame bit for bit. The memory verdict needs the full run
//! (`fragkit check 'soak.*'`: 1000 frames, a resize every 100); here it is only recorded.

mod support;

use std::collections::BTreeMap;

use fragkit::harness::runner::run_case;
use fragkit_report::report::ReportedOutcome;

#[test]
fn soaks_run_through_resizes_and_reproduce_their_last_frame() {
    let overrides: BTreeMap<String, String> =
        [("frames", "160"), ("resize_every", "20")].map(|(k, v)| (k.to_owned(), v.to_owned())).into();
    let gpu = support::gpu().lock().unwrap_or_else(|e| e.into_inner());
    for case in fragkit_cases::all().iter().filter(|c| c.name.starts_with("soak.")) {
        let record = run_case(&gpu, case, &overrides, &support::expectations(), None);
        let memory_only = record.reason.starts_with("resident memory grew") && !record.reason.contains(';');
        assert!(
            record.outcome != ReportedOutcome::Fail || memory_only,
            "{}: {:?}: {}",
            case.name,
            record.outcome,
            record.reason
        );
        assert_eq!(record.metrics["last_frame_bytes_differing_from_fresh"], 0, "{}: {:?}", case.name, record.metrics);
        assert_eq!(record.metrics["resizes"], 7, "{}", case.name);
    }
}
