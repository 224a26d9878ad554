//! The soak cases, shortened (160 frames in 16 resize cycles): they must run to the end on every
//! resize and reproduce their last frame bit for bit, and wgpu's live objects must not grow. The
//! process-memory verdict is the full run's (`fragkit check 'soak.*'`); here it is only recorded. `fault.leak`, the checkerboard soak leaking a 64 KiB buffer a frame, must fail
//! with that leak measured after running on to four times its length.

mod support;

use std::collections::BTreeMap;

use fragkit::harness::runner::run_case;
use fragkit_report::report::ReportedOutcome;

fn shortened() -> BTreeMap<String, String> {
    [("frames", "160"), ("cycles", "16")].map(|(k, v)| (k.to_owned(), v.to_owned())).into()
}

#[test]
fn soaks_run_through_resizes_and_reproduce_their_last_frame() {
    let gpu = support::gpu().lock().unwrap_or_else(|e| e.into_inner());
    for case in fragkit_cases::all().iter().filter(|c| c.name.starts_with("soak.")) {
        let record = run_case(&gpu, case, &shortened(), &support::expectations(), None);
        // A short run's process memory may still be filling its caches: only wgpu's objects and
        // the frame are held here.
        assert_ne!(record.outcome, ReportedOutcome::Crash, "{}: {}", case.name, record.reason);
        assert!(!record.reason.contains("wgpu_"), "{}: {}", case.name, record.reason);
        assert_eq!(record.metrics["last_frame_bytes_differing_from_fresh"], 0, "{}: {:?}", case.name, record.metrics);
        // 16 cycles, or 32 or 64 where growth made the soak run on.
        let cycles = record.metrics["cycles"].as_u64().unwrap_or(0);
        assert!([16, 32, 64].contains(&cycles), "{}: {cycles} cycles", case.name);
        assert_eq!(
            record.metrics["resident_mib_per_cycle"].as_array().map(Vec::len),
            Some(cycles as usize),
            "{}",
            case.name
        );
        assert!(!record.metrics.contains_key("wgpu_buffers_growth_per_frame"), "{}: {:?}", case.name, record.metrics);
    }
}

#[test]
fn a_buffer_leaked_every_frame_is_caught_and_measured() {
    let gpu = support::gpu().lock().unwrap_or_else(|e| e.into_inner());
    let case = fragkit_cases::all().iter().find(|c| c.name == "fault.leak").expect("fault.leak is registered");
    let record = run_case(&gpu, case, &shortened(), &support::expectations(), None);
    assert_eq!(record.outcome, ReportedOutcome::Fail, "{}", record.reason);
    // The leak keeps growing as the soak runs on, to four times its length.
    assert!(record.reason.contains("wgpu_buffers keeps growing through 640 frames: 1.0 a frame"), "{}", record.reason);
    assert_eq!(record.metrics["wgpu_buffer_bytes_growth_per_frame"], 65536.0, "{:?}", record.metrics);
    assert!(record.reason.contains("resident_in_use (the live heap: "), "{}", record.reason);
}
