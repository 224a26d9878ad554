//! Snapshots of a configuration's run (`check --matrix … --snapshots DIR`): each case run's outcome
//! and metrics, timings left out, one JSON file a configuration (`DIR/<name>.json`), held against
//! later runs of that configuration bit for bit — what determinism promises on one adapter, and
//! what the test suite's insta snapshots hold for the default adapter. A case run an intermittent
//! known issue names is left out (its outcome is one of two), and a known issue's metrics too.

use std::collections::BTreeMap;
use std::path::Path;

use anyhow::{Context, Result};

use fragkit_report::expectations::Expectations;
use fragkit_report::report::{Report, ReportedOutcome, is_timing_metric};

/// Per case run (`CaseRecord::run_name`): `{"outcome": …, "metrics": {…}}`.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Snapshot(pub BTreeMap<String, serde_json::Value>);

impl Snapshot {
    /// What a run shows of each case run that can be held to a snapshot.
    pub fn of(report: &Report, expectations: &Expectations) -> Self {
        let mut entries = BTreeMap::new();
        for case in &report.cases {
            let intermittent =
                expectations.find(&case.name, &report.adapter).iter().any(|issue| issue.intermittent.is_some());
            if intermittent {
                continue;
            }
            // A known issue's numbers are a failure's, which nothing promises (softpipe's CPS
            // failures differ run to run): its outcome is held, not its metrics.
            let mut metrics = case.metrics.clone();
            metrics.retain(|name, _| !is_timing_metric(name) && case.outcome != ReportedOutcome::KnownIssue);
            entries.insert(case.run_name(), serde_json::json!({"outcome": case.outcome, "metrics": metrics}));
        }
        Self(entries)
    }

    /// The snapshot stored at `path`, or None where there is none yet.
    pub fn load(path: &Path) -> Result<Option<Self>> {
        if !path.exists() {
            return Ok(None);
        }
        let text = std::fs::read_to_string(path).with_context(|| format!("reading the snapshot {}", path.display()))?;
        let entries = serde_json::from_str(&text)
            .with_context(|| format!("{} is no snapshot (a JSON object of case runs)", path.display()))?;
        Ok(Some(Self(entries)))
    }

    pub fn write(&self, path: &Path) -> Result<()> {
        let text = serde_json::to_string_pretty(&self.0).expect("JSON values serialise") + "\n";
        std::fs::write(path, text).with_context(|| format!("writing the snapshot {}", path.display()))
    }

    /// How `new` departs from this stored snapshot, one line a case run: a case run the snapshot
    /// lacks, or one whose outcome or metrics differ (the first differing values named). Case
    /// runs the new run did not run are no departure (a run of a subset).
    pub fn departures(&self, new: &Snapshot) -> Vec<String> {
        let mut lines = Vec::new();
        for (case, now) in &new.0 {
            match self.0.get(case) {
                None => lines.push(format!("{case}: not in the snapshot")),
                Some(stored) if stored != now => {
                    let mut differences = Vec::new();
                    differing_values(case, stored, now, &mut differences);
                    let shown: Vec<String> = differences.iter().take(3).cloned().collect();
                    let more = differences.len().saturating_sub(3);
                    let more = if more > 0 { format!(" and {more} more") } else { String::new() };
                    lines.push(format!("{}{more}", shown.join("; ")));
                }
                Some(_) => {}
            }
        }
        lines
    }

    /// This snapshot with `new`'s case runs put in (an update keeps what the run did not run).
    pub fn updated_with(&self, new: &Snapshot) -> Snapshot {
        let mut entries = self.0.clone();
        entries.extend(new.0.iter().map(|(case, value)| (case.clone(), value.clone())));
        Snapshot(entries)
    }
}

/// The paths (`case.outcome`, `case.metrics.name[2]`) at which two JSON values differ.
fn differing_values(path: &str, stored: &serde_json::Value, now: &serde_json::Value, out: &mut Vec<String>) {
    use serde_json::Value;
    match (stored, now) {
        (Value::Object(a), Value::Object(b)) => {
            let keys: std::collections::BTreeSet<&String> = a.keys().chain(b.keys()).collect();
            for key in keys {
                let (x, y) = (a.get(key).unwrap_or(&Value::Null), b.get(key).unwrap_or(&Value::Null));
                differing_values(&format!("{path}.{key}"), x, y, out);
            }
        }
        (Value::Array(a), Value::Array(b)) if a.len() == b.len() => {
            for (i, (x, y)) in a.iter().zip(b).enumerate() {
                differing_values(&format!("{path}[{i}]"), x, y, out);
            }
        }
        (a, b) if a != b => out.push(format!("{path}: {a} in the snapshot, {b} now")),
        _ => {}
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use serde_json::json;

    fn snapshot(entries: &[(&str, serde_json::Value)]) -> Snapshot {
        Snapshot(entries.iter().map(|(k, v)| (k.to_string(), v.clone())).collect())
    }

    #[test]
    fn departures_name_the_values_that_changed_and_the_new_case_runs() {
        let stored = snapshot(&[
            ("a", json!({"outcome": "pass", "metrics": {"m": {"count": 3, "list": [1, 2]}}})),
            ("b", json!({"outcome": "pass", "metrics": {}})),
            ("only_stored", json!({"outcome": "pass", "metrics": {}})),
        ]);
        let new = snapshot(&[
            ("a", json!({"outcome": "pass", "metrics": {"m": {"count": 4, "list": [1, 5]}}})),
            ("b", json!({"outcome": "known_issue", "metrics": {}})),
            ("added", json!({"outcome": "pass", "metrics": {}})),
        ]);
        assert_eq!(
            stored.departures(&new),
            [
                "a.metrics.m.count: 3 in the snapshot, 4 now; a.metrics.m.list[1]: 2 in the snapshot, 5 now",
                "added: not in the snapshot",
                "b.outcome: \"pass\" in the snapshot, \"known_issue\" now",
            ]
        );
        assert!(stored.departures(&stored).is_empty());
        let updated = stored.updated_with(&new);
        assert_eq!(updated.0.len(), 4);
        assert!(updated.departures(&new).is_empty());
    }

    #[test]
    fn a_snapshot_holds_outcomes_and_untimed_metrics_and_leaves_out_intermittent_cases() {
        use fragkit_report::AdapterDescription;
        use fragkit_report::report::CaseRecord;
        let measured = |name: &str, outcome| CaseRecord {
            metrics: [("error".to_owned(), json!(0.5)), ("gpu_ms".to_owned(), json!(3.0))].into(),
            ..CaseRecord::unmeasured(name, outcome, "")
        };
        let report = Report {
            adapter: AdapterDescription { name: "gpu".into(), backend: "vulkan".into(), ..Default::default() },
            cases: vec![
                measured("kit.a", ReportedOutcome::Pass),
                measured("kit.known", ReportedOutcome::KnownIssue),
                measured("kit.wobbly", ReportedOutcome::Pass),
            ],
            diagnostics: Vec::new(),
            shard: None,
            run: None,
        };
        let expectations = Expectations::parse(
            "[[known_issue]]\ncase = \"kit.wobbly\"\nreason = \"r\"\nintermittent = \"sometimes\"\n\n[[known_issue]]\ncase = \"kit.known\"\nreason = \"r\"\n",
            "test",
        )
        .unwrap();
        let held = Snapshot::of(&report, &expectations);
        assert_eq!(
            held,
            snapshot(&[
                ("kit.a", json!({"outcome": "pass", "metrics": {"error": 0.5}})),
                ("kit.known", json!({"outcome": "known_issue", "metrics": {}})),
            ])
        );
        // Written and loaded back whole; no file is no snapshot; a file of something else is an error.
        let path = std::env::temp_dir().join(format!("fragkit-snapshot-{}.json", std::process::id()));
        std::fs::remove_file(&path).ok();
        assert_eq!(Snapshot::load(&path).unwrap(), None);
        held.write(&path).unwrap();
        assert_eq!(Snapshot::load(&path).unwrap(), Some(held));
        std::fs::write(&path, "[1, 2]").unwrap();
        assert!(Snapshot::load(&path).is_err());
        std::fs::remove_file(&path).ok();
    }

    #[test]
    fn a_departure_names_three_differences_and_counts_the_rest() {
        let stored = snapshot(&[("a", json!({"m": [1, 2, 3, 4, 5], "list": [1, 2]}))]);
        let new = snapshot(&[("a", json!({"m": [0, 0, 0, 0, 0], "list": [1, 2, 3]}))]);
        assert_eq!(
            stored.departures(&new),
            [
                "a.list: [1,2] in the snapshot, [1,2,3] now; a.m[0]: 1 in the snapshot, 0 now; a.m[1]: 2 in the snapshot, 0 now and 3 more"
            ]
        );
        let three = snapshot(&[("a", json!({"m": [0, 0, 0, 4, 5], "list": [1, 2]}))]);
        assert_eq!(
            stored.departures(&three),
            ["a.m[0]: 1 in the snapshot, 0 now; a.m[1]: 2 in the snapshot, 0 now; a.m[2]: 3 in the snapshot, 0 now"]
        );
    }
}
