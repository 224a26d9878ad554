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

/// Both runs' repeats, compared: the Mann–Whitney p-value.
#[derive(Clone, Debug, PartialEq)]
pub struct RepeatsTest {
    pub p: f64,
    pub base_runs: usize,
    pub new_runs: usize,
}

/// Earlier runs of the case on the adapter: their median and spread (scaled MAD), and how many
/// spreads the new time lies from that median. It catches what repeats within a run cannot: the
/// drift between runs (another day, another machine state).
#[derive(Clone, Debug, PartialEq)]
pub struct HistorySpread {
    pub runs: usize,
    pub median_ms: f64,
    pub spread_ms: f64,
    pub spreads: f64,
}

/// What a GPU-time change was judged against: each that is available must call it beyond the
/// noise; neither (one time each, no history) leaves a ratio, not a judgement.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct TimeEvidence {
    pub repeats: Option<RepeatsTest>,
    pub history: Option<HistorySpread>,
    /// False where one run has repeats (a warm median) and the other a single, cold time.
    pub comparable: bool,
}

impl TimeEvidence {
    pub fn judged(&self) -> bool {
        self.repeats.is_some() || self.history.is_some()
    }
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
        // A run's first time includes compiling its pipelines (tens of ms on a CPU driver); a
        // median of repeats is a warm time. Only like is judged against like.
        if base.gpu_ms_repeats.is_empty() != new.gpu_ms_repeats.is_empty() {
            return Some(TimeChange {
                case: case.to_owned(),
                base_ms,
                new_ms,
                evidence: TimeEvidence { repeats: None, history: None, comparable: false },
                regression: false,
                improvement: false,
            });
        }
        let ratio = new_ms / base_ms;
        let (slower, faster) = (ratio > 1.0 + self.threshold, ratio < 1.0 / (1.0 + self.threshold));
        let (base_runs, new_runs) = (base.gpu_ms_repeats.len(), new.gpu_ms_repeats.len());
        let repeats = (base_runs >= MIN_REPEATS && new_runs >= MIN_REPEATS).then(|| RepeatsTest {
            p: mann_whitney_p(&base.gpu_ms_repeats, &new.gpu_ms_repeats),
            base_runs,
            new_runs,
        });
        let history = (history.len() >= MIN_HISTORY).then(|| {
            let (median_ms, spread_ms) = median_and_spread(history);
            let spreads = if spread_ms > 0.0 { (new_ms - median_ms) / spread_ms } else { f64::INFINITY };
            HistorySpread { runs: history.len(), median_ms, spread_ms, spreads }
        });
        let evidence = TimeEvidence { repeats, history, comparable: true };
        let beyond_noise = evidence.judged()
            && evidence.repeats.as_ref().is_none_or(|r| r.p < self.alpha)
            && evidence.history.as_ref().is_none_or(|h| (new_ms - h.median_ms).abs() > self.spreads * h.spread_ms);
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

/// GPU times of earlier runs of each case run (`CaseRecord::run_name`) on one adapter, kept apart
/// by kind: single (cold) times and medians of repeats (warm).
#[derive(Clone, Debug, Default)]
pub struct GpuHistory {
    pub single: BTreeMap<String, Vec<f64>>,
    pub repeated: BTreeMap<String, Vec<f64>>,
}

impl GpuHistory {
    /// The earlier times of `case` of the same kind as `record`'s.
    fn like(&self, case: &str, record: &CaseRecord) -> &[f64] {
        let by_kind = if record.gpu_ms_repeats.is_empty() { &self.single } else { &self.repeated };
        by_kind.get(case).map_or(&[], Vec::as_slice)
    }
}

/// Compares `new` against `base`, judging GPU times against the runs' repeats and `history`
/// (earlier runs on the new run's adapter; empty where there is no database).
pub fn compare(base: &Report, new: &Report, judgement: &TimeJudgement, history: &GpuHistory) -> Comparison {
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
        comparison.time_changes.extend(judgement.judge(case, before, now, history.like(case, now)));
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
        let judged = |t: &&TimeChange| t.evidence.judged();
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
            let mut judged_by = Vec::new();
            if let Some(RepeatsTest { p, base_runs, new_runs }) = &t.evidence.repeats {
                judged_by.push(format!("{base_runs} vs {new_runs} repeats, Mann–Whitney p = {p:.2e}"));
            }
            if let Some(HistorySpread { runs, median_ms, spread_ms, spreads }) = &t.evidence.history {
                judged_by.push(format!(
                    "{runs} earlier runs: median {median_ms:.3} ms ± {spread_ms:.3}, {spreads:+.1} spreads"
                ));
            }
            let judged_by = match (judged_by.is_empty(), t.evidence.comparable) {
                (_, false) => "not comparable: a warm median of repeats against a single cold time".to_owned(),
                (true, true) => "one time each".to_owned(),
                (false, true) => judged_by.join("; "),
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
            diagnostics: Vec::new(),
        }
    }

    fn report(cases: Vec<CaseRecord>) -> Report {
        Report { adapter: AdapterDescription::default(), cases, diagnostics: Vec::new() }
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
        let c = compare(&base, &new, &TimeJudgement::default(), &GpuHistory::default());
        assert_eq!(c.regressions.iter().map(|r| r.case.as_str()).collect::<Vec<_>>(), ["a"]);
        assert_eq!(c.fixes.iter().map(|r| r.case.as_str()).collect::<Vec<_>>(), ["b"]);
        assert_eq!(c.other_changes.iter().map(|r| r.case.as_str()).collect::<Vec<_>>(), ["c"]);
        assert_eq!(c.metric_changes, [MetricChange { case: "c".into(), metric: "m.x".into(), base: 1.0, new: 3.0 }]);
        assert_eq!(
            (c.only_in_base.as_slice(), c.only_in_new.as_slice()),
            (&["gone".to_owned()][..], &["added".to_owned()][..])
        );
        assert!(c.markdown("base", "new").contains("| `a` | pass | FAIL | why |"));
        assert_eq!(compare(&base, &base, &TimeJudgement::default(), &GpuHistory::default()).regressions.len(), 0);
    }

    fn timed(repeats: &[f64]) -> CaseRecord {
        CaseRecord {
            gpu_ms: Some(crate::query::median(repeats.to_vec())),
            gpu_ms_repeats: if repeats.len() > 1 { repeats.to_vec() } else { Vec::new() },
            ..record("t", ReportedOutcome::Pass, 1.0)
        }
    }

    fn judge(base: &[f64], new: &[f64], history: &[f64]) -> TimeChange {
        let earlier = BTreeMap::from([("t".to_owned(), history.to_vec())]);
        let history = GpuHistory { single: earlier.clone(), repeated: earlier };
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
        assert_eq!(
            (unjudged.evidence, unjudged.regression),
            (TimeEvidence { comparable: true, ..Default::default() }, false)
        );
        // A cold single time against a warm median is not judged at all.
        let mixed = judge(&[10.0, 10.1, 9.9], &[40.0], &history);
        assert!(!mixed.evidence.comparable && !mixed.regression);
    }

    #[test]
    fn repeats_and_history_must_both_call_it_beyond_the_noise() {
        let base = [10.0, 10.1, 9.9, 10.02, 10.05, 9.95, 10.08];
        let new: Vec<f64> = base.iter().map(|t| t * 1.1).collect();
        // Within the run, 10 % slower is clear; but earlier runs wandered as far.
        let wandering = [9.0, 11.5, 10.0, 12.0, 8.5];
        let change = judge(&base, &new, &wandering);
        assert!(change.evidence.repeats.as_ref().unwrap().p < 0.01 && !change.regression, "{change:?}");
        // A steady history confirms it.
        assert!(judge(&base, &new, &[10.0, 10.1, 9.95, 10.05]).regression);
    }
}
