//! Two runs of the kit compared case by case (a case run is its name and parameters): new
//! failures, fixes, other outcome changes, cases only one run has, numeric metrics that changed,
//! and the GPU time's ratio. Written as markdown for a merge-request comment.

use std::collections::BTreeMap;
use std::fmt::Write as _;

use super::report::{CaseRecord, Report, ReportedOutcome};

/// One case run present in both reports whose outcome differs.
#[derive(Clone, Debug, PartialEq)]
pub struct OutcomeChange {
    pub case: String,
    pub base: ReportedOutcome,
    pub new: ReportedOutcome,
    pub reason: String,
}

/// A numeric metric whose value differs between the runs.
#[derive(Clone, Debug, PartialEq)]
pub struct MetricChange {
    pub case: String,
    pub metric: String,
    pub base: f64,
    pub new: f64,
}

#[derive(Clone, Debug, Default, PartialEq)]
pub struct Comparison {
    /// Passing (or not failing) in the base run, failing in the new one.
    pub regressions: Vec<OutcomeChange>,
    /// Failing in the base run, not in the new one.
    pub fixes: Vec<OutcomeChange>,
    /// Other outcome changes (e.g. pass to not_supported).
    pub other_changes: Vec<OutcomeChange>,
    pub only_in_base: Vec<String>,
    pub only_in_new: Vec<String>,
    pub metric_changes: Vec<MetricChange>,
    /// Per case run in both with GPU times: new / base.
    pub gpu_time_ratios: Vec<(String, f64)>,
}

pub fn compare(base: &Report, new: &Report) -> Comparison {
    let index = |report: &Report| -> BTreeMap<String, CaseRecord> {
        report.cases.iter().map(|c| (c.run_name(), c.clone())).collect()
    };
    let (base_cases, new_cases) = (index(base), index(new));
    let mut comparison = Comparison {
        only_in_base: base_cases.keys().filter(|k| !new_cases.contains_key(*k)).cloned().collect(),
        only_in_new: new_cases.keys().filter(|k| !base_cases.contains_key(*k)).cloned().collect(),
        ..Default::default()
    };
    for (case, now) in &new_cases {
        let Some(before) = base_cases.get(case) else { continue };
        if before.outcome != now.outcome {
            let change = OutcomeChange {
                case: case.clone(),
                base: before.outcome,
                new: now.outcome,
                reason: now.reason.clone(),
            };
            match (before.outcome.is_failure(false), now.outcome.is_failure(false)) {
                (false, true) => comparison.regressions.push(change),
                (true, false) => comparison.fixes.push(change),
                _ => comparison.other_changes.push(change),
            }
        }
        let (then, current) = (before.numeric_metrics(), now.numeric_metrics());
        for (metric, &value) in &current {
            if let Some(&old) = then.get(metric)
                && old.to_bits() != value.to_bits()
            {
                comparison.metric_changes.push(MetricChange {
                    case: case.clone(),
                    metric: metric.clone(),
                    base: old,
                    new: value,
                });
            }
        }
        if let (Some(a), Some(b)) = (before.gpu_ms, now.gpu_ms)
            && a > 0.0
        {
            comparison.gpu_time_ratios.push((case.clone(), b / a));
        }
    }
    comparison
}

impl Comparison {
    /// Markdown for a merge-request comment.
    pub fn markdown(&self, base: &str, new: &str) -> String {
        let mut md = format!("## fragkit: {new} against {base}\n\n");
        let _ = writeln!(
            md,
            "{} regressions, {} fixes, {} other outcome changes, {} metric changes; {} case runs only in the base, {} only in the new run.\n",
            self.regressions.len(),
            self.fixes.len(),
            self.other_changes.len(),
            self.metric_changes.len(),
            self.only_in_base.len(),
            self.only_in_new.len()
        );
        for (title, changes) in
            [("Regressions", &self.regressions), ("Fixes", &self.fixes), ("Other outcome changes", &self.other_changes)]
        {
            if changes.is_empty() {
                continue;
            }
            let _ = writeln!(md, "### {title}\n\n| case | was | now | reason |\n|---|---|---|---|");
            for c in changes {
                let reason = c.reason.lines().next().unwrap_or_default().replace('|', "\\|");
                let _ = writeln!(md, "| `{}` | {} | {} | {reason} |", c.case, c.base.label(), c.new.label());
            }
            md.push('\n');
        }
        for (title, cases) in [("Only in the base run", &self.only_in_base), ("Only in the new run", &self.only_in_new)]
        {
            if !cases.is_empty() {
                let _ = writeln!(
                    md,
                    "### {title}\n\n{}\n",
                    cases.iter().map(|c| format!("`{c}`")).collect::<Vec<_>>().join(", ")
                );
            }
        }
        if !self.metric_changes.is_empty() {
            let _ = writeln!(md, "### Metric changes\n\n| case | metric | was | now |\n|---|---|---|---|");
            for m in &self.metric_changes {
                let _ = writeln!(md, "| `{}` | {} | {} | {} |", m.case, m.metric, m.base, m.new);
            }
            md.push('\n');
        }
        if !self.gpu_time_ratios.is_empty() {
            let mut ratios: Vec<&(String, f64)> = self.gpu_time_ratios.iter().collect();
            ratios.sort_by(|a, b| b.1.total_cmp(&a.1));
            let _ = writeln!(
                md,
                "### GPU time, new / base (one run each: a ratio, not a judgement against noise)\n\n| case | ratio |\n|---|---|"
            );
            for (case, ratio) in ratios.iter().take(10) {
                let _ = writeln!(md, "| `{case}` | {ratio:.2} |");
            }
        }
        md
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::gpu::AdapterDescription;

    fn record(name: &str, outcome: ReportedOutcome, metric: f64) -> CaseRecord {
        CaseRecord {
            name: name.into(),
            outcome,
            reason: "why".into(),
            params: BTreeMap::new(),
            metrics: [("m".to_owned(), serde_json::json!({"x": metric, "list": [1, 2]}))].into(),
            gpu_ms: Some(2.0),
            wall_ms: 1.0,
            evidence: Vec::new(),
            attempts: 1,
        }
    }

    fn report(cases: Vec<CaseRecord>) -> Report {
        Report { adapter: AdapterDescription::default(), cases }
    }

    #[test]
    fn regressions_fixes_and_metric_changes_are_told_apart() {
        use ReportedOutcome::*;
        let base = report(vec![
            record("a", Pass, 1.0),
            record("b", Fail, 1.0),
            record("c", Pass, 1.0),
            record("gone", Pass, 1.0),
        ]);
        let new = report(vec![
            record("a", Fail, 1.0),
            record("b", Pass, 1.0),
            record("c", NotSupported, 3.0),
            record("added", Pass, 1.0),
        ]);
        let c = compare(&base, &new);
        assert_eq!(c.regressions.iter().map(|r| r.case.as_str()).collect::<Vec<_>>(), ["a"]);
        assert_eq!(c.fixes.iter().map(|r| r.case.as_str()).collect::<Vec<_>>(), ["b"]);
        assert_eq!(c.other_changes.iter().map(|r| r.case.as_str()).collect::<Vec<_>>(), ["c"]);
        assert_eq!(c.metric_changes, [MetricChange { case: "c".into(), metric: "m.x".into(), base: 1.0, new: 3.0 }]);
        assert_eq!(
            (c.only_in_base.as_slice(), c.only_in_new.as_slice()),
            (&["gone".to_owned()][..], &["added".to_owned()][..])
        );
        assert!(c.markdown("base", "new").contains("| `a` | pass | FAIL | why |"));
        assert_eq!(compare(&base, &base).regressions.len(), 0);
    }
}
