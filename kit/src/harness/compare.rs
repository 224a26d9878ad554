//! Two runs of the kit compared case by case (a case run is its name and parameters): new
//! failures, fixes, other outcome changes, cases only one run has, numeric metrics that changed,
//! and GPU-time changes judged against the noise — the repeats of both runs where they have them
//! (Mann–Whitney U), else the spread of earlier runs of the case on the adapter. Written as
//! markdown for a merge-request comment.

use std::collections::BTreeMap;
use std::fmt::Write as _;

use super::noise::{mann_whitney_p, median_and_spread};
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

/// What a GPU-time change was judged against.
#[derive(Clone, Debug, PartialEq)]
pub enum TimeEvidence {
    /// Both runs' repeats: the Mann–Whitney p-value.
    Repeats { p: f64, base_runs: usize, new_runs: usize },
    /// Earlier runs of the case on the adapter: their median and spread (scaled MAD), and how
    /// many spreads the new time lies from that median.
    History { runs: usize, median_ms: f64, spread_ms: f64, spreads: f64 },
    /// One time on each side and no history: a ratio, not a judgement.
    Unjudged,
}

#[derive(Clone, Debug, PartialEq)]
pub struct TimeChange {
    pub case: String,
    pub base_ms: f64,
    pub new_ms: f64,
    pub evidence: TimeEvidence,
    /// Slower beyond the threshold and beyond the noise.
    pub regression: bool,
    /// Faster beyond the threshold and beyond the noise.
    pub improvement: bool,
}

impl TimeChange {
    pub fn ratio(&self) -> f64 {
        self.new_ms / self.base_ms
    }
}

/// How GPU-time changes are judged.
#[derive(Clone, Copy, Debug)]
pub struct TimeJudgement {
    /// Smallest relative change that counts (0.05: 5 % slower or faster).
    pub threshold: f64,
    /// Largest Mann–Whitney p-value that counts as beyond the noise.
    pub alpha: f64,
    /// Against history: spreads (scaled MADs) from the history's median that count.
    pub spreads: f64,
}

impl Default for TimeJudgement {
    fn default() -> Self {
        Self { threshold: 0.05, alpha: 0.01, spreads: 3.0 }
    }
}

/// Repeats a comparison needs on each side before it judges by them.
const MIN_REPEATS: usize = 3;
/// Earlier runs a history needs before it judges by it.
const MIN_HISTORY: usize = 3;

impl TimeJudgement {
    /// Judges `base` → `new` for one case run; `history` holds earlier runs' GPU times of it on
    /// the new run's adapter.
    fn judge(&self, case: &str, base: &CaseRecord, new: &CaseRecord, history: &[f64]) -> Option<TimeChange> {
        let (base_ms, new_ms) = (base.gpu_ms?, new.gpu_ms?);
        if base_ms <= 0.0 || new_ms <= 0.0 {
            return None;
        }
        let ratio = new_ms / base_ms;
        let (slower, faster) = (ratio > 1.0 + self.threshold, ratio < 1.0 / (1.0 + self.threshold));
        let (base_runs, new_runs) = (base.gpu_ms_repeats.len(), new.gpu_ms_repeats.len());
        let (evidence, beyond_noise) = if base_runs >= MIN_REPEATS && new_runs >= MIN_REPEATS {
            let p = mann_whitney_p(&base.gpu_ms_repeats, &new.gpu_ms_repeats);
            (TimeEvidence::Repeats { p, base_runs, new_runs }, p < self.alpha)
        } else if history.len() >= MIN_HISTORY {
            let (median_ms, spread_ms) = median_and_spread(history);
            let spreads = if spread_ms > 0.0 { (new_ms - median_ms) / spread_ms } else { f64::INFINITY };
            let beyond = (new_ms - median_ms).abs() > self.spreads * spread_ms;
            (TimeEvidence::History { runs: history.len(), median_ms, spread_ms, spreads }, beyond)
        } else {
            (TimeEvidence::Unjudged, false)
        };
        Some(TimeChange {
            case: case.to_owned(),
            base_ms,
            new_ms,
            evidence,
            regression: slower && beyond_noise,
            improvement: faster && beyond_noise,
        })
    }
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
    /// Per case run in both with GPU times: the change and its judgement.
    pub time_changes: Vec<TimeChange>,
}

impl Comparison {
    /// Whether the new run is worse: a new failure, or a GPU time slower beyond the noise.
    pub fn regressed(&self) -> bool {
        !self.regressions.is_empty() || self.time_changes.iter().any(|t| t.regression)
    }
}

/// Compares `new` against `base`. `history` maps a case run (`CaseRecord::run_name`) to GPU
/// times of earlier runs of it on the new run's adapter (empty where there is no database).
pub fn compare(
    base: &Report,
    new: &Report,
    judgement: &TimeJudgement,
    history: &BTreeMap<String, Vec<f64>>,
) -> Comparison {
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
        let earlier = history.get(case).map_or(&[][..], Vec::as_slice);
        comparison.time_changes.extend(judgement.judge(case, before, now, earlier));
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
        self.time_markdown(&mut md);
        md
    }

    fn time_markdown(&self, md: &mut String) {
        if self.time_changes.is_empty() {
            return;
        }
        let judged = |t: &&TimeChange| t.evidence != TimeEvidence::Unjudged;
        let _ = writeln!(
            md,
            "### GPU time\n\n{} case runs timed in both: {} slower and {} faster beyond the threshold and the noise; {} judged, {} with one time each and no history (run `check --repeat N`, or record runs in a database).\n",
            self.time_changes.len(),
            self.time_changes.iter().filter(|t| t.regression).count(),
            self.time_changes.iter().filter(|t| t.improvement).count(),
            self.time_changes.iter().filter(judged).count(),
            self.time_changes.iter().filter(|t| !judged(t)).count(),
        );
        let mut shown: Vec<&TimeChange> = self.time_changes.iter().filter(|t| t.regression || t.improvement).collect();
        shown.sort_by(|a, b| b.ratio().total_cmp(&a.ratio()));
        if shown.is_empty() {
            // Nothing beyond the noise: the largest ratios, for a person to look at.
            shown = self.time_changes.iter().collect();
            shown.sort_by(|a, b| (b.ratio().ln().abs()).total_cmp(&a.ratio().ln().abs()));
            shown.truncate(5);
        }
        let _ =
            writeln!(md, "| case | base ms | new ms | new / base | judged by | verdict |\n|---|---|---|---|---|---|");
        for t in shown {
            let judged_by = match &t.evidence {
                TimeEvidence::Repeats { p, base_runs, new_runs } => {
                    format!("{base_runs} vs {new_runs} repeats, Mann–Whitney p = {p:.2e}")
                }
                TimeEvidence::History { runs, median_ms, spread_ms, spreads } => {
                    format!("{runs} earlier runs: median {median_ms:.3} ms ± {spread_ms:.3}, {spreads:+.1} spreads")
                }
                TimeEvidence::Unjudged => "one time each".to_owned(),
            };
            let verdict = if t.regression {
                "**slower**"
            } else if t.improvement {
                "faster"
            } else {
                "within noise"
            };
            let _ = writeln!(
                md,
                "| `{}` | {:.3} | {:.3} | {:.3} | {judged_by} | {verdict} |",
                t.case,
                t.base_ms,
                t.new_ms,
                t.ratio()
            );
        }
        md.push('\n');
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
            gpu_ms_repeats: Vec::new(),
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
        let c = compare(&base, &new, &TimeJudgement::default(), &BTreeMap::new());
        assert_eq!(c.regressions.iter().map(|r| r.case.as_str()).collect::<Vec<_>>(), ["a"]);
        assert_eq!(c.fixes.iter().map(|r| r.case.as_str()).collect::<Vec<_>>(), ["b"]);
        assert_eq!(c.other_changes.iter().map(|r| r.case.as_str()).collect::<Vec<_>>(), ["c"]);
        assert_eq!(c.metric_changes, [MetricChange { case: "c".into(), metric: "m.x".into(), base: 1.0, new: 3.0 }]);
        assert_eq!(
            (c.only_in_base.as_slice(), c.only_in_new.as_slice()),
            (&["gone".to_owned()][..], &["added".to_owned()][..])
        );
        assert!(c.markdown("base", "new").contains("| `a` | pass | FAIL | why |"));
        assert_eq!(compare(&base, &base, &TimeJudgement::default(), &BTreeMap::new()).regressions.len(), 0);
    }

    fn timed(repeats: &[f64]) -> CaseRecord {
        CaseRecord {
            gpu_ms: Some(crate::query::median(repeats.to_vec())),
            gpu_ms_repeats: if repeats.len() > 1 { repeats.to_vec() } else { Vec::new() },
            ..record("t", ReportedOutcome::Pass, 1.0)
        }
    }

    fn judge(base: &[f64], new: &[f64], history: &[f64]) -> TimeChange {
        let history = BTreeMap::from([("t".to_owned(), history.to_vec())]);
        let c = compare(&report(vec![timed(base)]), &report(vec![timed(new)]), &TimeJudgement::default(), &history);
        c.time_changes[0].clone()
    }

    #[test]
    fn time_changes_count_only_beyond_the_threshold_and_the_noise() {
        let base = [10.0, 10.4, 9.7, 10.1, 9.9, 10.2, 10.0];
        // 20 % slower on every repeat: a regression.
        let slower: Vec<f64> = base.iter().map(|t| t * 1.2).collect();
        assert!(judge(&base, &slower, &[]).regression);
        // 20 % slower in the median, but as noisy as that: not judged a regression.
        let noisy = [7.0, 14.0, 9.0, 13.0, 12.0, 6.0, 15.0];
        let change = judge(&base, &noisy, &[]);
        assert!(change.ratio() > 1.19 && !change.regression, "{change:?}");
        // 2 % slower on every repeat: beyond the noise, within the threshold.
        let slightly: Vec<f64> = base.iter().map(|t| t * 1.02).collect();
        assert!(!judge(&base, &slightly, &[]).regression);
        // Faster beyond both: an improvement.
        let faster: Vec<f64> = base.iter().map(|t| t * 0.7).collect();
        let change = judge(&base, &faster, &[]);
        assert!(change.improvement && !change.regression);
    }

    #[test]
    fn single_times_are_judged_against_the_history_or_not_at_all() {
        let history = [10.0, 10.3, 9.8, 10.1, 9.9];
        assert!(judge(&[10.0], &[13.0], &history).regression);
        assert!(!judge(&[10.0], &[10.4], &history).regression);
        // A history this noisy holds 13 ms within its spread.
        assert!(!judge(&[10.0], &[13.0], &[6.0, 14.0, 9.0, 13.5, 7.0]).regression);
        let unjudged = judge(&[10.0], &[20.0], &[]);
        assert_eq!((unjudged.evidence, unjudged.regression), (TimeEvidence::Unjudged, false));
    }
}
