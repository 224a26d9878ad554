//! The JSON report: `{"adapter": {...}, "cases": [{"name", "outcome", "reason", "params",
//! "metrics", "gpu_ms", "wall_ms", "attempts"}]}`, written atomically, read back for `fragkit
//! merge` (the shards of one run) with clear errors for a corrupt or truncated file.

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

use anyhow::{Context, Result, bail};
use serde::{Deserialize, Serialize};

use crate::adapter::AdapterDescription;
use crate::param_value::ParamValue;
use crate::run_info::RunInfo;
use crate::sink::Shard;

/// A case's outcome as reported, after the expectations file was applied.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum ReportedOutcome {
    Pass,
    Fail,
    NotSupported,
    /// Failed, as the expectations file says it does on this adapter.
    KnownIssue,
    /// Listed in the expectations file but passed: the entry is stale.
    UnexpectedPass,
    /// Failed, then passed when run again (`--retry`): for a deterministic kit, a finding.
    Flaky,
    /// The process running the case died (a signal, an abort) before recording it.
    Crash,
    /// The case ran past its time limit and its process was killed.
    Timeout,
    /// Left out by a skip list (`--skips`, `--exclude`): the reason names the entry.
    Skip,
    /// Not run: the run stopped first (`--max-fails`).
    NotRun,
}

impl ReportedOutcome {
    /// Whether this outcome fails a CI run (a flaky case only when `flaky_fails`).
    pub fn is_failure(self, flaky_fails: bool) -> bool {
        matches!(self, Self::Fail | Self::UnexpectedPass | Self::Crash | Self::Timeout)
            || (flaky_fails && self == Self::Flaky)
    }

    pub fn label(self) -> &'static str {
        match self {
            Self::Pass => "pass",
            Self::Fail => "FAIL",
            Self::NotSupported => "not_supported",
            Self::KnownIssue => "known_issue",
            Self::UnexpectedPass => "UNEXPECTED_PASS",
            Self::Flaky => "FLAKY",
            Self::Crash => "CRASH",
            Self::Timeout => "TIMEOUT",
            Self::Skip => "skip",
            Self::NotRun => "not_run",
        }
    }
}

/// A case run's key across reports: its name, and its parameters where it has any.
pub fn run_name(name: &str, params: &BTreeMap<String, ParamValue>) -> String {
    let params: Vec<String> =
        params.iter().map(|(k, v)| format!("{k}={}", serde_json::to_string(v).unwrap_or_default())).collect();
    if params.is_empty() { name.to_owned() } else { format!("{name} [{}]", params.join(" ")) }
}

#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct CaseRecord {
    pub name: String,
    pub outcome: ReportedOutcome,
    pub reason: String,
    pub params: BTreeMap<String, ParamValue>,
    pub metrics: BTreeMap<String, serde_json::Value>,
    /// Sum of the case's timed passes; null where the adapter has no timestamps.
    pub gpu_ms: Option<f64>,
    /// GPU time of every timed repeat (`check --repeat N`, `fragkit bench`'s rounds), where
    /// more than one ran: what `fragkit compare` judges a time change against.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub gpu_ms_repeats: Vec<f64>,
    pub wall_ms: f64,
    pub evidence: Vec<PathBuf>,
    /// Runs of the case: 1, or more where `--retry` ran a failure again.
    #[serde(default = "one")]
    pub attempts: u32,
    /// Warnings and errors wgpu, naga or the driver logged while the case ran.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub diagnostics: Vec<String>,
}

fn one() -> u32 {
    1
}

/// Metrics that are timings, by their top-level name: they vary run to run, so snapshots leave
/// them out and `compare` judges GPU times by the noise instead of listing them as changes.
const TIMING_METRICS: &[&str] =
    &["equal_ms", "always_ms", "time_ratio", "level0_ms", "foveated_lighting", "probe_time_ratio"];

/// Whether a top-level metric is a timing (listed, or named `*_ms`).
pub fn is_timing_metric(name: &str) -> bool {
    TIMING_METRICS.contains(&name) || name.ends_with("_ms")
}

/// Every number (booleans as 0/1) in a metric value, by dotted path (`a.b.0`).
fn flatten_metric(path: &str, value: &serde_json::Value, out: &mut BTreeMap<String, f64>) {
    match value {
        serde_json::Value::Number(n) => out.extend(n.as_f64().map(|f| (path.to_owned(), f))),
        serde_json::Value::Bool(b) => {
            out.insert(path.to_owned(), f64::from(u8::from(*b)));
        }
        serde_json::Value::Array(items) => {
            for (i, item) in items.iter().enumerate() {
                flatten_metric(&format!("{path}.{i}"), item, out);
            }
        }
        serde_json::Value::Object(fields) => {
            for (k, v) in fields {
                flatten_metric(&format!("{path}.{k}"), v, out);
            }
        }
        _ => {}
    }
}

impl CaseRecord {
    /// A record of `name` with nothing measured: a case that never ran far enough to measure
    /// (its process died), or a record made up by a test.
    pub fn unmeasured(name: &str, outcome: ReportedOutcome, reason: &str) -> Self {
        Self {
            name: name.into(),
            outcome,
            reason: reason.into(),
            params: BTreeMap::new(),
            metrics: BTreeMap::new(),
            gpu_ms: None,
            gpu_ms_repeats: Vec::new(),
            wall_ms: 0.0,
            evidence: Vec::new(),
            attempts: 1,
            diagnostics: Vec::new(),
        }
    }
}

impl CaseRecord {
    /// The case run's name: the case's, followed by its parameters (`name [k=v …]`) where it has any.
    pub fn run_name(&self) -> String {
        run_name(&self.name, &self.params)
    }

    /// The metrics flattened to numbers, by dotted path.
    pub fn numeric_metrics(&self) -> BTreeMap<String, f64> {
        let mut out = BTreeMap::new();
        for (name, value) in &self.metrics {
            flatten_metric(name, value, &mut out);
        }
        out
    }
}

#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct Report {
    pub adapter: AdapterDescription,
    pub cases: Vec<CaseRecord>,
    /// Warnings and errors logged before the first case (opening the device, e.g. EGL's).
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub diagnostics: Vec<String>,
    /// Which shard of a run this is (`check --shard K/N`): `merge` joins only a whole set.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub shard: Option<Shard>,
    /// When, where and from what commit the run was made (absent in reports of older kits).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub run: Option<RunInfo>,
}

/// Refuses shards that are not one whole set: a report of a shard beside one that is none, shards
/// of different counts, one shard twice, or one missing (the run would look complete).
fn check_whole_set_of_shards(reports: &[(PathBuf, Report)]) -> Result<()> {
    let shards: Vec<(&PathBuf, Option<Shard>)> = reports.iter().map(|(path, r)| (path, r.shard)).collect();
    let Some(count) = shards.iter().find_map(|(_, shard)| shard.map(|s| s.count)) else {
        return Ok(());
    };
    let mut seen = vec![None; count as usize];
    for (path, shard) in &shards {
        let Some(shard) = shard else {
            bail!("{} is no shard's report (no --shard), the others are shards of {count}", path.display());
        };
        if shard.count != count {
            bail!("{} is shard {}/{}, the others are shards of {count}", path.display(), shard.index, shard.count);
        }
        if let Some(earlier) = seen[shard.index as usize - 1].replace(*path) {
            bail!("{} and {} are both shard {}/{count}", earlier.display(), path.display(), shard.index);
        }
    }
    let missing: Vec<String> =
        (1..=count).filter(|k| seen[*k as usize - 1].is_none()).map(|k| format!("{k}/{count}")).collect();
    if !missing.is_empty() {
        bail!(
            "shard {} missing: {} of {count} shards given, and a merge of part of a run would pass for the whole",
            missing.join(", "),
            count as usize - missing.len()
        );
    }
    Ok(())
}

impl Report {
    pub fn failures(&self, flaky_fails: bool) -> usize {
        self.cases.iter().filter(|c| c.outcome.is_failure(flaky_fails)).count()
    }

    /// Reads a report `fragkit check --json` wrote.
    pub fn read(path: &Path) -> Result<Self> {
        let text = std::fs::read_to_string(path).with_context(|| format!("reading the report {}", path.display()))?;
        serde_json::from_str(&text).with_context(|| {
            format!("{} is not a fragkit report (corrupt or truncated JSON, or another format)", path.display())
        })
    }

    /// One run from runs of the same case list in separate processes (`check` N times; for a
    /// gate, a base and a new build's runs interleaved): each case run's GPU-time repeats become
    /// the runs' times, one per process — the unit the drift between processes acts on, which
    /// repeats within one process never see — its time their median, its record the first
    /// failing run's (else the first run's). Every run must hold the same case runs on one adapter.
    pub fn pool_processes(reports: Vec<(PathBuf, Report)>) -> Result<Self> {
        let Some((first_path, first)) = reports.first() else {
            bail!("nothing to pool: give the runs' reports");
        };
        let mut cases = Vec::new();
        for case in &first.cases {
            let key = case.run_name();
            let mut records = Vec::new();
            for (path, report) in &reports {
                if report.adapter != first.adapter {
                    bail!(
                        "{} ran on another adapter than {}: pooled runs are one adapter's",
                        path.display(),
                        first_path.display()
                    );
                }
                let record = report.cases.iter().find(|c| c.run_name() == key).with_context(|| {
                    format!(
                        "{} holds no {key}, {} does: pooled runs are of one case list",
                        path.display(),
                        first_path.display()
                    )
                })?;
                records.push(record);
            }
            let chosen = records.iter().find(|r| r.outcome.is_failure(true)).unwrap_or(&records[0]);
            let times: Option<Vec<f64>> = records.iter().map(|r| r.gpu_ms).collect();
            // The kit's one median of times (`query::median`), as a run's repeats get.
            let gpu_ms = times.as_deref().map(|t| crate::noise::median(t.to_vec()));
            cases.push(CaseRecord { gpu_ms, gpu_ms_repeats: times.unwrap_or_default(), ..(*chosen).clone() });
        }
        for (path, report) in &reports {
            if report.cases.len() != first.cases.len() {
                bail!(
                    "{} holds {} case runs, {} {}: pooled runs are of one case list",
                    path.display(),
                    report.cases.len(),
                    first_path.display(),
                    first.cases.len()
                );
            }
        }
        Ok(Self { cases, ..first.clone() })
    }

    /// One report from the shards of a run: every report of the same adapter, no case run with
    /// the same parameters twice, and of reports that say which shard they are (`check --shard`
    /// writes it), every shard 1..=N once.
    pub fn merge(reports: Vec<(PathBuf, Report)>) -> Result<Self> {
        let Some((first_path, first)) = reports.first() else {
            bail!("nothing to merge: give the shards' reports");
        };
        check_whole_set_of_shards(&reports)?;
        let adapter = first.adapter.clone();
        let mut cases: Vec<CaseRecord> = Vec::new();
        for (path, report) in &reports {
            if report.adapter != adapter {
                bail!(
                    "{} ran on {} ({}, {}), {} on {} ({}, {}): merge joins the shards of one adapter's run",
                    path.display(),
                    report.adapter.name,
                    report.adapter.backend,
                    report.adapter.driver_info,
                    first_path.display(),
                    adapter.name,
                    adapter.backend,
                    adapter.driver_info
                );
            }
            for case in &report.cases {
                if cases.iter().any(|c| c.name == case.name && c.params == case.params) {
                    bail!(
                        "{} runs {} with parameters another report already holds: overlapping shards",
                        path.display(),
                        case.name
                    );
                }
                cases.push(case.clone());
            }
        }
        // Each shard opened its own device: their opening records, one after another.
        let diagnostics = reports.iter().flat_map(|(_, r)| r.diagnostics.iter().cloned()).collect();
        // The set's run: the first shard's kind, commit and tag (each started on its own).
        let run = reports.first().and_then(|(_, r)| r.run.clone());
        Ok(Self { adapter, cases, diagnostics, shard: None, run })
    }

    /// Writes the report through a temporary file and a rename, so that an interrupted run never
    /// leaves a half-written report behind.
    pub fn write_atomically(&self, path: &Path) -> Result<()> {
        write_through_temporary(path, &serde_json::to_string_pretty(self).context("serialising the report")?)
    }
}

/// Writes `text` to `path` through a temporary file beside it and a rename, so that an interrupted
/// run never leaves a half-written file behind.
pub fn write_through_temporary(path: &Path, text: &str) -> Result<()> {
    let mut temporary = path.as_os_str().to_owned();
    temporary.push(".tmp");
    let temporary = PathBuf::from(temporary);
    std::fs::write(&temporary, text).with_context(|| format!("writing {}", temporary.display()))?;
    std::fs::rename(&temporary, path).with_context(|| format!("moving {} into place", path.display()))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn report(times: &[(&str, Option<f64>, ReportedOutcome)]) -> Report {
        let cases = times
            .iter()
            .map(|&(name, gpu_ms, outcome)| CaseRecord { gpu_ms, ..CaseRecord::unmeasured(name, outcome, "") })
            .collect();
        Report { adapter: AdapterDescription::default(), cases, diagnostics: Vec::new(), shard: None, run: None }
    }

    #[test]
    fn pooled_runs_make_each_process_one_repeat_and_keep_a_failure() {
        use ReportedOutcome::{Fail, Pass};
        let runs = [
            report(&[("a", Some(3.0), Pass), ("b", None, Pass)]),
            report(&[("a", Some(1.0), Pass), ("b", None, Fail)]),
            report(&[("a", Some(2.0), Pass), ("b", None, Pass)]),
        ];
        let named = |i: usize| (PathBuf::from(format!("{i}.json")), runs[i].clone());
        let pooled = Report::pool_processes((0..3).map(named).collect()).unwrap();
        assert_eq!((pooled.cases[0].gpu_ms, pooled.cases[0].gpu_ms_repeats.clone()), (Some(2.0), vec![3.0, 1.0, 2.0]));
        assert_eq!((pooled.cases[1].gpu_ms, pooled.cases[1].outcome), (None, Fail));
        // An even count takes the upper of the middle two, as a run's own repeats do.
        let two = Report::pool_processes((0..2).map(named).collect()).unwrap();
        assert_eq!(two.cases[0].gpu_ms, Some(crate::noise::median(vec![3.0, 1.0])));
        assert_eq!(two.cases[0].gpu_ms, Some(3.0));
        let other = report(&[("a", Some(1.0), Pass)]);
        assert!(Report::pool_processes(vec![named(0), (PathBuf::from("x.json"), other)]).is_err());
    }

    fn shard_of(index: u32, count: u32) -> (PathBuf, Report) {
        let name = format!("kit.{index}");
        let case = CaseRecord::unmeasured(&name, ReportedOutcome::Pass, "");
        let report = Report { shard: Some(Shard { index, count }), cases: vec![case], ..report(&[]) };
        (PathBuf::from(format!("shard{index}of{count}.json")), report)
    }

    #[test]
    fn only_a_whole_set_of_shards_merges() {
        let merged = Report::merge(vec![shard_of(2, 3), shard_of(1, 3), shard_of(3, 3)]).unwrap();
        assert_eq!(merged.cases.len(), 3);
        assert_eq!(merged.shard, None);
        let error = |reports: Vec<(PathBuf, Report)>| format!("{:#}", Report::merge(reports).unwrap_err());
        assert!(error(vec![shard_of(1, 3), shard_of(3, 3)]).contains("shard 2/3 missing: 2 of 3"));
        assert!(error(vec![shard_of(1, 2), shard_of(1, 2)]).contains("are both shard 1/2"));
        assert!(error(vec![shard_of(1, 2), shard_of(2, 3)]).contains("is shard 2/3, the others are shards of 2"));
        let (path, mut unsharded) = shard_of(2, 2);
        unsharded.shard = None;
        assert!(error(vec![shard_of(1, 2), (path, unsharded)]).contains("is no shard's report"));
    }

    #[test]
    fn metrics_flatten_to_numbers_by_dotted_path() {
        let mut record = CaseRecord::unmeasured("kit.a", ReportedOutcome::Pass, "");
        record.metrics = BTreeMap::from([
            ("a".to_owned(), serde_json::json!(1.5)),
            ("b".to_owned(), serde_json::json!(true)),
            ("c".to_owned(), serde_json::json!([1, {"d": 2}])),
            ("e".to_owned(), serde_json::json!("text")),
        ]);
        let expected: BTreeMap<String, f64> =
            [("a", 1.5), ("b", 1.0), ("c.0", 1.0), ("c.1.d", 2.0)].map(|(k, v)| (k.to_owned(), v)).into();
        assert_eq!(record.numeric_metrics(), expected);
    }

    #[test]
    fn timing_metrics_are_the_listed_names_and_any_named_ms() {
        for timing in ["gpu_ms", "equal_ms", "time_ratio", "foveated_lighting"] {
            assert!(is_timing_metric(timing), "{timing}");
        }
        for other in ["pixels_differing", "ms_count", "ratio"] {
            assert!(!is_timing_metric(other), "{other}");
        }
    }

    #[test]
    fn a_record_without_attempts_ran_once() {
        let text = r#"{"name": "kit.a", "outcome": "pass", "reason": "", "params": {}, "metrics": {},
            "gpu_ms": null, "wall_ms": 1.0, "evidence": []}"#;
        let record: CaseRecord = serde_json::from_str(text).unwrap();
        assert_eq!(record.attempts, 1);
    }

    #[test]
    fn failures_count_the_failing_outcomes_and_flaky_ones_when_asked() {
        use ReportedOutcome::{
            Crash, Fail, Flaky, KnownIssue, NotRun, NotSupported, Pass, Skip, Timeout, UnexpectedPass,
        };
        let all = [Pass, Fail, NotSupported, KnownIssue, UnexpectedPass, Flaky, Crash, Timeout, Skip, NotRun];
        let run = report(&all.map(|outcome| ("kit.a", None, outcome)));
        assert_eq!(run.failures(false), 4);
        assert_eq!(run.failures(true), 5);
        let labels = all.map(ReportedOutcome::label);
        assert_eq!(
            labels,
            [
                "pass",
                "FAIL",
                "not_supported",
                "known_issue",
                "UNEXPECTED_PASS",
                "FLAKY",
                "CRASH",
                "TIMEOUT",
                "skip",
                "not_run"
            ]
        );
        let names = all.map(|outcome| serde_json::to_value(outcome).unwrap());
        assert_eq!(names[8..], ["skip", "not_run"], "as the JSON report, database and HTML name them");
    }

    #[test]
    fn merge_refuses_another_adapter_and_a_case_run_twice() {
        let error = |reports: Vec<(PathBuf, Report)>| format!("{:#}", Report::merge(reports).unwrap_err());
        let (path, mut other) = shard_of(2, 2);
        other.adapter.name = "SwiftShader".into();
        assert!(error(vec![shard_of(1, 2), (path, other)]).contains("merge joins the shards of one adapter's run"));
        let a = (PathBuf::from("a.json"), report(&[("kit.a", None, ReportedOutcome::Pass)]));
        let b = (PathBuf::from("b.json"), report(&[("kit.a", None, ReportedOutcome::Fail)]));
        assert!(error(vec![a.clone(), b]).contains("overlapping shards"));
        // The same case with other parameters is another run.
        let mut sized = CaseRecord::unmeasured("kit.a", ReportedOutcome::Pass, "");
        sized.params.insert("size".into(), ParamValue::Sizes(vec![(4, 4)]));
        let c = (PathBuf::from("c.json"), Report { cases: vec![sized], ..report(&[]) });
        assert_eq!(Report::merge(vec![a, c]).unwrap().cases.len(), 2);
    }
}
