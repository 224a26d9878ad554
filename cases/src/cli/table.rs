//! The results table `fragkit check` and `fragkit merge` print: one line a case.

use fragkit_report::report::Report;
use fragkit_report::sink::Sink;

/// The most telling metric of a case, shown in the table.
fn key_metric(metrics: &std::collections::BTreeMap<String, serde_json::Value>) -> String {
    const KEYS: &[&str] = &["positions", "time_ratio", "differing_pixels", "4x.pixels_differing", "precision"];
    KEYS.iter().find_map(|k| metrics.get(*k).map(|v| format!("{k}={}", compact(v)))).unwrap_or_default()
}

fn compact(value: &serde_json::Value) -> String {
    match value {
        serde_json::Value::Number(n) => n.as_f64().map_or(n.to_string(), |f| format!("{f:.3}")),
        other => cut(&other.to_string(), 60),
    }
}

/// The table's width: a 120-column terminal. Reasons are cut with `…`; the JSON report and
/// `--json` keep them whole.
const WIDTH: usize = 120;

/// `text` cut to `width` characters, `…` marking the cut.
fn cut(text: &str, width: usize) -> String {
    if text.chars().count() <= width {
        return text.to_owned();
    }
    let kept: String = text.chars().take(width.saturating_sub(1)).collect();
    format!("{kept}…")
}

/// The outcome column: the outcome and, where the case ran more than once (`--retry`), how
/// many attempts it took.
fn outcome_cell(record: &fragkit_report::report::CaseRecord) -> String {
    match record.attempts {
        0 | 1 => record.outcome.label().to_owned(),
        attempts => format!("{} ×{attempts} runs", record.outcome.label()),
    }
}

pub fn print_table(report: &Report) {
    // case 34, outcome 15, gpu ms 8, wall ms 8, key metric 16 and the gaps: the reason gets the rest.
    let reason_width = WIDTH - (34 + 1 + 15 + 1 + 8 + 1 + 8 + 2 + 16 + 1);
    println!("{:<34} {:<15} {:>8} {:>8}  {:<16} reason", "case", "outcome", "gpu ms", "wall ms", "key metric");
    for c in &report.cases {
        let gpu_ms = c.gpu_ms.map_or("-".into(), |ms| format!("{ms:.2}"));
        // One line a case: wgpu's multi-line messages are joined.
        let reason = c.reason.lines().map(str::trim).filter(|l| !l.is_empty()).collect::<Vec<_>>().join(" / ");
        println!(
            "{:<34} {:<15} {:>8} {:>8.1}  {:<16} {}",
            cut(&c.name, 34),
            outcome_cell(c),
            gpu_ms,
            c.wall_ms,
            cut(&key_metric(&c.metrics), 16),
            cut(&reason, reason_width)
        );
    }
}

/// Every reason the table cut, whole, with what wgpu and the driver logged during the case
/// (`-v`).
pub fn print_reasons(report: &Report) {
    for c in report.cases.iter().filter(|c| !c.reason.is_empty() || !c.diagnostics.is_empty()) {
        println!("\n{} ({}):\n    {}", c.name, c.outcome.label(), c.reason.lines().collect::<Vec<_>>().join("\n    "));
        print_diagnostics(&c.diagnostics);
    }
}

fn print_diagnostics(diagnostics: &[String]) {
    for line in diagnostics {
        println!("    logged: {}", line.lines().collect::<Vec<_>>().join("\n            "));
    }
}

/// Below the table: what was logged during the failing cases (it may explain them), and how many
/// records the report keeps otherwise.
pub fn print_diagnostics_summary(report: &Report) {
    let failing: Vec<_> =
        report.cases.iter().filter(|c| c.outcome.is_failure(true) && !c.diagnostics.is_empty()).collect();
    for c in &failing {
        println!("\n{} ({}) logged:", c.name, c.outcome.label());
        print_diagnostics(&c.diagnostics);
    }
    let kept = report.diagnostics.len() + report.cases.iter().map(|c| c.diagnostics.len()).sum::<usize>();
    if kept > 0 {
        let plural = if kept == 1 { "" } else { "s" };
        println!("{kept} log record{plural} of wgpu and the driver kept in the report's diagnostics; -v prints them");
    }
}

/// Prints the table when the run finishes, with a progress bar while it runs.
pub struct TableSink {
    progress: indicatif::ProgressBar,
    /// Also print every reason whole, and the log records, below the table.
    verbose: bool,
}

impl TableSink {
    pub fn new(verbose: bool) -> Self {
        Self { progress: indicatif::ProgressBar::hidden(), verbose }
    }
}

impl Sink for TableSink {
    fn start(&mut self, d: &fragkit_report::AdapterDescription, runs: usize) -> anyhow::Result<()> {
        println!("adapter: {} ({}, {} {})", d.name, d.backend, d.driver, d.driver_info);
        self.progress = indicatif::ProgressBar::new(runs as u64);
        self.progress
            .set_style(indicatif::ProgressStyle::with_template("{bar:30} {pos}/{len} {msg}").expect("static template"));
        Ok(())
    }

    fn record(&mut self, record: &fragkit_report::report::CaseRecord) -> anyhow::Result<()> {
        self.progress.set_message(record.name.clone());
        self.progress.inc(1);
        Ok(())
    }

    fn finish(&mut self, report: &Report) -> anyhow::Result<()> {
        self.progress.finish_and_clear();
        print_table(report);
        if self.verbose {
            print_reasons(report);
        } else {
            print_diagnostics_summary(report);
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use fragkit_report::report::{CaseRecord, ReportedOutcome};

    use super::*;

    #[test]
    fn the_outcome_column_says_how_many_attempts_a_retried_case_took() {
        let record: CaseRecord = serde_json::from_value(serde_json::json!({
            "name": "kit.a", "outcome": "flaky", "reason": "", "params": {}, "metrics": {},
            "gpu_ms": null, "wall_ms": 1.0, "evidence": [], "attempts": 3
        }))
        .unwrap();
        assert_eq!(outcome_cell(&record), "FLAKY ×3 runs");
        let once = CaseRecord { attempts: 1, outcome: ReportedOutcome::Pass, ..record };
        assert_eq!(outcome_cell(&once), "pass");
    }
}
