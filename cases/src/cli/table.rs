//! The results table `fragkit check` and `fragkit merge` print: one line a case.

use fragkit::harness::report::Report;
use fragkit::harness::run::Sink;

/// The most telling metric of a case, shown in the table.
fn key_metric(metrics: &std::collections::BTreeMap<String, serde_json::Value>) -> String {
    const KEYS: &[&str] = &["positions", "time_ratio", "differing_pixels", "4x.pixels_differing", "precision"];
    KEYS.iter().find_map(|k| metrics.get(*k).map(|v| format!("{k}={}", compact(v)))).unwrap_or_default()
}

fn compact(value: &serde_json::Value) -> String {
    match value {
        serde_json::Value::Number(n) => n.as_f64().map_or(n.to_string(), |f| format!("{f:.3}")),
        other => {
            let text = other.to_string();
            if text.len() > 60 { format!("{}…", &text[..60]) } else { text }
        }
    }
}

pub fn print_table(report: &Report) {
    println!("{:<34} {:<15} {:>9} {:>9}  {:<40} reason", "case", "outcome", "gpu ms", "wall ms", "key metric");
    for c in &report.cases {
        let gpu_ms = c.gpu_ms.map_or("-".into(), |ms| format!("{ms:.2}"));
        println!(
            "{:<34} {:<15} {:>9} {:>9.1}  {:<40} {}",
            c.name,
            c.outcome.label(),
            gpu_ms,
            c.wall_ms,
            key_metric(&c.metrics),
            // One line a case: wgpu's multi-line messages are joined.
            c.reason.lines().map(str::trim).filter(|l| !l.is_empty()).collect::<Vec<_>>().join(" / ")
        );
    }
}

/// Prints the table when the run finishes, with a progress bar while it runs.
pub struct TableSink {
    progress: indicatif::ProgressBar,
}

impl TableSink {
    pub fn new() -> Self {
        Self { progress: indicatif::ProgressBar::hidden() }
    }
}

impl Sink for TableSink {
    fn start(&mut self, _adapter: &fragkit::gpu::AdapterDescription, runs: usize) -> anyhow::Result<()> {
        self.progress = indicatif::ProgressBar::new(runs as u64);
        self.progress
            .set_style(indicatif::ProgressStyle::with_template("{bar:30} {pos}/{len} {msg}").expect("static template"));
        Ok(())
    }

    fn record(&mut self, record: &fragkit::harness::report::CaseRecord) -> anyhow::Result<()> {
        self.progress.set_message(record.name.clone());
        self.progress.inc(1);
        Ok(())
    }

    fn finish(&mut self, report: &Report) -> anyhow::Result<()> {
        self.progress.finish_and_clear();
        print_table(report);
        Ok(())
    }
}
