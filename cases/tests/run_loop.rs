//! The run loop (`fragkit::harness::run`): retries tell a flaky case from a failing one, every
//! sink sees the same records, and a record holds what its case measured and how long it took.

use std::sync::atomic::{AtomicU32, Ordering};

use fragkit::harness::run::{CaseRun, RunOptions, run};
use fragkit::harness::{Case, Ctx, Outcome};
use fragkit::{AdapterSelector, Gpu};
use fragkit_report::expectations::Expectations;
use fragkit_report::report::{CaseRecord, Report, ReportedOutcome};
use fragkit_report::sink::Sink;

static FLAKY_CALLS: AtomicU32 = AtomicU32::new(0);

/// A parameterless test case of the run loop, with a budget of a second and no shaders.
const fn test_case(name: &'static str, summary: &'static str, run: fn(&mut Ctx) -> anyhow::Result<Outcome>) -> Case {
    Case {
        name,
        summary,
        requires: wgpu::Features::empty(),
        params: &[],
        sweep: &[],
        budget_s: 1,
        timed_verdict: false,
        shaders: &[],
        run,
    }
}

const FLAKY: Case = test_case("test.flaky", "fails on its first run only", |_| {
    Ok(if FLAKY_CALLS.fetch_add(1, Ordering::SeqCst) == 0 { Outcome::Fail("first run".into()) } else { Outcome::Pass })
});

const BROKEN: Case = test_case("test.broken", "always fails", |_| Ok(Outcome::Fail("always".into())));

const MEASURED: Case = test_case("test.measured", "records a metric and an evidence image after 50 ms", |ctx| {
    std::thread::sleep(std::time::Duration::from_millis(50));
    ctx.metric("answer", 42);
    ctx.evidence_image("tile", &image::RgbaImage::new(2, 2))?;
    Ok(Outcome::Pass)
});

#[derive(Default)]
struct Collect {
    records: Vec<String>,
    finished: usize,
}

impl Sink for Collect {
    fn record(&mut self, record: &CaseRecord) -> anyhow::Result<()> {
        self.records.push(record.name.clone());
        Ok(())
    }
    fn finish(&mut self, report: &Report) -> anyhow::Result<()> {
        self.finished = report.cases.len();
        Ok(())
    }
}

#[test]
fn retries_report_flaky_cases_and_keep_failing_ones_failed() {
    let gpu = Gpu::open(&AdapterSelector::default()).unwrap_or_else(|e| panic!("{e:#}"));
    let expectations = Expectations::parse(fragkit_cases::EXPECTATIONS, "built in").unwrap();
    let options =
        RunOptions { expectations: &expectations, evidence_dir: None, reproduction: None, retries: 2, repeats: 1 };
    let runs = [&FLAKY, &BROKEN].map(|case| CaseRun { case, overrides: Default::default() });
    let (mut first, mut second) = (Collect::default(), Collect::default());
    let report = run(gpu, &runs, runs.len(), &options, &mut [&mut first, &mut second]).unwrap();

    let flaky = &report.cases[0];
    assert_eq!((flaky.outcome, flaky.attempts), (ReportedOutcome::Flaky, 2), "{}", flaky.reason);
    assert!(flaky.reason.contains("first run"), "{}", flaky.reason);
    let broken = &report.cases[1];
    assert_eq!((broken.outcome, broken.attempts), (ReportedOutcome::Fail, 3));
    assert_eq!(report.failures(false), 1);
    assert_eq!(report.failures(true), 2);
    for sink in [&first, &second] {
        assert_eq!(sink.records, ["test.flaky", "test.broken"]);
        assert_eq!(sink.finished, 2);
    }
}

/// A case's metrics and evidence images reach its record (the images written to the evidence
/// folder, named by the case), and its wall time is its own, in milliseconds.
#[test]
fn a_record_holds_the_cases_metrics_evidence_and_wall_time() {
    let gpu = Gpu::open(&AdapterSelector::default()).unwrap_or_else(|e| panic!("{e:#}"));
    let expectations = Expectations::default();
    let evidence = std::env::temp_dir().join(format!("fragkit-run-loop-evidence-{}", std::process::id()));
    std::fs::create_dir_all(&evidence).unwrap();
    let options = RunOptions {
        expectations: &expectations,
        evidence_dir: Some(&evidence),
        reproduction: None,
        retries: 0,
        repeats: 1,
    };
    let runs = [CaseRun { case: &MEASURED, overrides: Default::default() }];
    let started = std::time::Instant::now();
    let report = run(gpu, &runs, runs.len(), &options, &mut []).unwrap();
    let whole_ms = started.elapsed().as_secs_f64() * 1e3;

    let record = &report.cases[0];
    assert_eq!(record.outcome, ReportedOutcome::Pass, "{}", record.reason);
    assert_eq!(record.metrics.get("answer"), Some(&serde_json::json!(42)));
    let image = evidence.join("test.measured.tile.png");
    assert_eq!(record.evidence, std::slice::from_ref(&image));
    assert_eq!(image::open(&image).unwrap().to_rgba8().dimensions(), (2, 2));
    assert!(record.wall_ms >= 50.0 && record.wall_ms <= whole_ms, "{} ms of {whole_ms} ms", record.wall_ms);
    std::fs::remove_dir_all(&evidence).ok();
}
