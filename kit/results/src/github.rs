//! GitHub Actions outputs of a run (`check --github`, on by default where `GITHUB_ACTIONS=true`):
//! an `::error` workflow command per unexpected failure as it is recorded (an annotation on the
//! run's page, titled by the case run) and, at the end, a markdown summary appended to the file
//! `GITHUB_STEP_SUMMARY` names (counts, and every unexpected failure with its reason).

use std::fmt::Write as _;
use std::io::Write as _;
use std::path::PathBuf;

use anyhow::{Context, Result};

use fragkit_report::AdapterDescription;
use fragkit_report::readable::counted;
use fragkit_report::report::{CaseRecord, Report};

/// A workflow command's message: `%`, CR and LF escaped as the runner reads them back.
fn escape_data(text: &str) -> String {
    text.replace('%', "%25").replace('\r', "%0D").replace('\n', "%0A")
}

/// A workflow command's property (`title=`): `:` and `,` escaped too.
fn escape_property(text: &str) -> String {
    escape_data(text).replace(':', "%3A").replace(',', "%2C")
}

/// The annotation of one recorded case run, where it counts as a failure.
pub fn annotation(record: &CaseRecord, adapter: &AdapterDescription, flaky_fails: bool) -> Option<String> {
    record.outcome.is_failure(flaky_fails).then(|| {
        let title =
            format!("{} {} on {} ({})", record.run_name(), record.outcome.label(), adapter.name, adapter.backend);
        format!("::error title={}::{}", escape_property(&title), escape_data(&record.reason))
    })
}

/// The step summary of a finished run, in markdown.
pub fn step_summary(report: &Report, flaky_fails: bool) -> String {
    let a = &report.adapter;
    let failures: Vec<&CaseRecord> = report.cases.iter().filter(|c| c.outcome.is_failure(flaky_fails)).collect();
    let mut md = format!(
        "### fragkit check on {} ({}, {})\n\n{}: {}.\n",
        a.name,
        a.backend,
        a.driver_info.trim(),
        counted(report.cases.len(), "case run", "case runs"),
        counted(failures.len(), "unexpected failure", "unexpected failures")
    );
    if !failures.is_empty() {
        md.push_str("\n| case run | outcome | reason |\n|---|---|---|\n");
        for case in failures {
            let reason = case.reason.lines().next().unwrap_or_default().replace('|', "\\|");
            let _ = writeln!(md, "| `{}` | {} | {reason} |", case.run_name(), case.outcome.label());
        }
    }
    md
}

/// Prints the annotations as records come (to standard output, where the runner reads workflow
/// commands) and appends the summary when the run finishes.
pub struct GithubSink {
    pub flaky_fails: bool,
    /// `GITHUB_STEP_SUMMARY`, where set.
    pub summary: Option<PathBuf>,
    adapter: AdapterDescription,
    commands: Box<dyn std::io::Write>,
}

impl GithubSink {
    pub fn new(flaky_fails: bool) -> Self {
        let summary = std::env::var_os("GITHUB_STEP_SUMMARY").filter(|v| !v.is_empty()).map(PathBuf::from);
        Self::writing_to(flaky_fails, summary, Box::new(std::io::stdout()))
    }

    /// A sink that writes its workflow commands to `commands` and its summary to `summary`.
    pub fn writing_to(flaky_fails: bool, summary: Option<PathBuf>, commands: Box<dyn std::io::Write>) -> Self {
        Self { flaky_fails, summary, adapter: AdapterDescription::default(), commands }
    }
}

impl fragkit_report::sink::Sink for GithubSink {
    fn start(&mut self, adapter: &AdapterDescription, _runs: usize) -> Result<()> {
        self.adapter = adapter.clone();
        Ok(())
    }

    fn record(&mut self, record: &CaseRecord) -> Result<()> {
        if let Some(line) = annotation(record, &self.adapter, self.flaky_fails) {
            writeln!(self.commands, "{line}").context("writing a workflow command")?;
        }
        Ok(())
    }

    fn finish(&mut self, report: &Report) -> Result<()> {
        let Some(path) = &self.summary else { return Ok(()) };
        let mut file = std::fs::OpenOptions::new()
            .create(true)
            .append(true)
            .open(path)
            .with_context(|| format!("opening the step summary {} (GITHUB_STEP_SUMMARY)", path.display()))?;
        file.write_all(step_summary(report, self.flaky_fails).as_bytes())
            .with_context(|| format!("writing the step summary {}", path.display()))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use fragkit_report::report::ReportedOutcome;

    #[test]
    fn a_failure_becomes_one_escaped_annotation_and_a_summary_row() {
        let record = CaseRecord::unmeasured("kit.a", ReportedOutcome::Fail, "50% off: 3, 4\nsecond line");
        let adapter = AdapterDescription { name: "gpu, one".into(), backend: "vulkan".into(), ..Default::default() };
        assert_eq!(
            annotation(&record, &adapter, false).unwrap(),
            "::error title=kit.a FAIL on gpu%2C one (vulkan)::50%25 off: 3, 4%0Asecond line"
        );
        let pass = CaseRecord { outcome: ReportedOutcome::Pass, ..record.clone() };
        assert_eq!(annotation(&pass, &adapter, false), None);
        let report = Report { adapter, cases: vec![record, pass], diagnostics: Vec::new(), shard: None, run: None };
        let summary = step_summary(&report, false);
        assert!(summary.contains("2 case runs: 1 unexpected failure."), "{summary}");
        assert!(summary.contains("| `kit.a` | FAIL | 50% off: 3, 4 |"), "{summary}");
    }

    /// A writer whose bytes stay readable after the sink that owns it is gone.
    #[derive(Clone, Default)]
    struct Shared(std::rc::Rc<std::cell::RefCell<Vec<u8>>>);

    impl std::io::Write for Shared {
        fn write(&mut self, bytes: &[u8]) -> std::io::Result<usize> {
            self.0.borrow_mut().extend_from_slice(bytes);
            Ok(bytes.len())
        }
        fn flush(&mut self) -> std::io::Result<()> {
            Ok(())
        }
    }

    #[test]
    fn the_sink_annotates_failures_on_its_adapter_and_appends_the_summary() {
        use fragkit_report::sink::Sink;
        let path = std::env::temp_dir().join(format!("fragkit-step-summary-{}.md", std::process::id()));
        std::fs::write(&path, "earlier step\n").unwrap();
        let commands = Shared::default();
        let mut sink = GithubSink::writing_to(true, Some(path.clone()), Box::new(commands.clone()));
        let adapter = AdapterDescription { name: "gpu".into(), backend: "gl".into(), ..Default::default() };
        sink.start(&adapter, 3).unwrap();
        let cases = [
            CaseRecord::unmeasured("kit.a", ReportedOutcome::Pass, ""),
            CaseRecord::unmeasured("kit.b", ReportedOutcome::Flaky, "once"),
            CaseRecord::unmeasured("kit.c", ReportedOutcome::Fail, "twice"),
        ];
        for case in &cases {
            sink.record(case).unwrap();
        }
        let printed = String::from_utf8(commands.0.borrow().clone()).unwrap();
        assert_eq!(
            printed,
            "::error title=kit.b FLAKY on gpu (gl)::once\n::error title=kit.c FAIL on gpu (gl)::twice\n"
        );
        let report = Report { adapter, cases: cases.to_vec(), diagnostics: Vec::new(), shard: None, run: None };
        sink.finish(&report).unwrap();
        let summary = std::fs::read_to_string(&path).unwrap();
        assert!(summary.starts_with("earlier step\n### fragkit check on gpu (gl, )"), "{summary}");
        assert!(summary.contains("3 case runs: 2 unexpected failures."), "{summary}");
        // No summary file: nothing to append to.
        let mut quiet = GithubSink::writing_to(false, None, Box::new(Shared::default()));
        quiet.finish(&report).unwrap();
        let mut unwritable = GithubSink::writing_to(false, Some(std::env::temp_dir()), Box::new(Shared::default()));
        assert!(unwritable.finish(&report).is_err());
        std::fs::remove_file(&path).ok();
    }
}
