//! Two runs of the kit compared case by case (a case run is its name and parameters): new
//! failures, fixes, other outcome changes, cases only one run has, numeric metrics that changed,
//! and GPU-time changes judged against the noise — the repeats of both runs where they have them
//! (Mann–Whitney U), else the spread of earlier runs of the case on the adapter. Written as
//! markdown for a merge-request comment.

use std::collections::BTreeMap;
use std::fmt::Write as _;

use fragkit_report::noise::mann_whitney_p;
use fragkit_report::readable::counted;
use fragkit_report::report::{CaseRecord, Report, ReportedOutcome, is_timing_metric};

/// One case run present in both reports whose outcome differs.
#[derive(Clone, Debug, PartialEq, serde::Serialize)]
pub struct OutcomeChange {
    pub case: String,
    pub base: ReportedOutcome,
    pub new: ReportedOutcome,
    pub reason: String,
}

/// A numeric metric whose value differs between the runs.
#[derive(Clone, Debug, PartialEq, serde::Serialize)]
pub struct MetricChange {
    pub case: String,
    pub metric: String,
    pub base: f64,
    pub new: f64,
}

/// Both runs' repeats, compared: the Mann–Whitney p-value, and the smallest p these numbers of
/// repeats can give (2 / C(m + n, m): 0.1 for 3 against 3), which must lie below `--alpha` for
/// the test to judge at all.
#[derive(Clone, Debug, PartialEq, serde::Serialize)]
pub struct RepeatsTest {
    pub p: f64,
    pub smallest_p: f64,
    pub base_runs: usize,
    pub new_runs: usize,
}

/// Earlier runs of the case on the adapter, and where the new time ranks among them: under no
/// change it is one more draw of the same distribution, so the share of earlier times at least as
/// far out is its p-value (two-sided, (1 + k) / (n + 1) doubled), whatever the distribution. It
/// catches what repeats within a run cannot: the drift between runs (another day, another
/// machine state); it needs more than 2 / alpha − 1 earlier runs to judge at all.
#[derive(Clone, Debug, PartialEq, serde::Serialize)]
pub struct HistoryRank {
    pub runs: usize,
    pub median_ms: f64,
    pub p: f64,
    pub smallest_p: f64,
}

/// What a GPU-time change was judged against. Each test that can reach `--alpha` must call it
/// beyond the noise; `not_judged` says why no test was asked (a failing case, a cold time against
/// a warm median), and a test that cannot reach alpha says so in the verdict.
#[derive(Clone, Debug, Default, PartialEq, serde::Serialize)]
pub struct TimeEvidence {
    pub repeats: Option<RepeatsTest>,
    pub history: Option<HistoryRank>,
    pub not_judged: Option<String>,
}

impl TimeEvidence {
    /// Whether some test could call a change beyond the noise at `alpha`.
    pub fn can_judge(&self, alpha: f64) -> bool {
        self.not_judged.is_none()
            && (self.repeats.as_ref().is_some_and(|r| r.smallest_p < alpha)
                || self.history.as_ref().is_some_and(|h| h.smallest_p < alpha))
    }
}

#[derive(Clone, Debug, PartialEq, serde::Serialize)]
pub struct TimeChange {
    pub case: String,
    pub base_ms: f64,
    pub new_ms: f64,
    pub evidence: TimeEvidence,
    /// Whether the evidence could judge at the comparison's alpha.
    pub judged: bool,
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
    /// Largest p-value (repeats' Mann–Whitney, or the history's rank) that counts as beyond the
    /// noise.
    pub alpha: f64,
}

impl Default for TimeJudgement {
    fn default() -> Self {
        Self { threshold: 0.05, alpha: 0.01 }
    }
}

/// The smallest two-sided Mann–Whitney p-value samples of `m` and `n` untied values can give.
pub fn smallest_repeats_p(m: usize, n: usize) -> f64 {
    // C(m + n, m), in floating point (it overflows nothing that matters: the p is then tiny).
    let orders = (1..=m).fold(1.0f64, |c, i| c * (n + i) as f64 / i as f64);
    (2.0 / orders).min(1.0)
}

/// Repeats each run needs for the Mann–Whitney test to reach below `alpha`.
pub fn repeats_needed(alpha: f64) -> usize {
    (1..).find(|&n| smallest_repeats_p(n, n) < alpha).expect("some number of repeats reaches any alpha > 0")
}

/// The smallest two-sided rank p-value a history of `n` earlier runs can give.
pub fn smallest_history_p(n: usize) -> f64 {
    (2.0 / (n as f64 + 1.0)).min(1.0)
}

/// Earlier runs a history needs for its rank test to reach below `alpha`.
pub fn history_needed(alpha: f64) -> usize {
    (1..).find(|&n| smallest_history_p(n) < alpha).expect("some history reaches any alpha > 0")
}

/// The history's two-sided rank p-value of `new` among `earlier`.
fn rank_p(earlier: &[f64], new: f64) -> f64 {
    let n = earlier.len() as f64;
    let at_least = earlier.iter().filter(|&&t| t >= new).count() as f64;
    let at_most = earlier.iter().filter(|&&t| t <= new).count() as f64;
    (2.0 * (1.0 + at_least.min(at_most)) / (n + 1.0)).min(1.0)
}

impl TimeJudgement {
    /// Judges `base` → `new` for one case run; `history` holds earlier runs' GPU times of it on
    /// the new run's adapter.
    fn judge(&self, case: &str, base: &CaseRecord, new: &CaseRecord, history: &[f64]) -> Option<TimeChange> {
        let (base_ms, new_ms) = (base.gpu_ms?, new.gpu_ms?);
        if base_ms <= 0.0 || new_ms <= 0.0 {
            return None;
        }
        let unjudged = |why: String| TimeChange {
            case: case.to_owned(),
            base_ms,
            new_ms,
            evidence: TimeEvidence { not_judged: Some(why), ..Default::default() },
            judged: false,
            regression: false,
            improvement: false,
        };
        // A failing case's time measures whatever it did before failing: its outcome is the news.
        for (which, record) in [("base", base), ("new", new)] {
            if record.outcome.is_failure(false) {
                return Some(unjudged(format!("the case is {} in the {which} run", record.outcome.label())));
            }
        }
        // A run's first time includes compiling its pipelines (tens of ms on a CPU driver); a
        // median of repeats is a warm time. Only like is judged against like.
        if base.gpu_ms_repeats.is_empty() != new.gpu_ms_repeats.is_empty() {
            return Some(unjudged("not comparable: a warm median of repeats against a single cold time".to_owned()));
        }
        let ratio = new_ms / base_ms;
        let (slower, faster) = (ratio > 1.0 + self.threshold, ratio < 1.0 / (1.0 + self.threshold));
        let (base_runs, new_runs) = (base.gpu_ms_repeats.len(), new.gpu_ms_repeats.len());
        let repeats = (base_runs > 1 && new_runs > 1).then(|| RepeatsTest {
            p: mann_whitney_p(&base.gpu_ms_repeats, &new.gpu_ms_repeats),
            smallest_p: smallest_repeats_p(base_runs, new_runs),
            base_runs,
            new_runs,
        });
        let history = (!history.is_empty()).then(|| HistoryRank {
            runs: history.len(),
            median_ms: median(history),
            p: rank_p(history, new_ms),
            smallest_p: smallest_history_p(history.len()),
        });
        let evidence = TimeEvidence { repeats, history, not_judged: None };
        let judged = evidence.can_judge(self.alpha);
        // Every test that can reach alpha must call it beyond the noise.
        let beyond_noise = judged
            && evidence.repeats.as_ref().is_none_or(|r| r.smallest_p >= self.alpha || r.p < self.alpha)
            && evidence.history.as_ref().is_none_or(|h| h.smallest_p >= self.alpha || h.p < self.alpha);
        Some(TimeChange {
            case: case.to_owned(),
            base_ms,
            new_ms,
            evidence,
            judged,
            regression: slower && beyond_noise,
            improvement: faster && beyond_noise,
        })
    }
}

fn median(values: &[f64]) -> f64 {
    fragkit_report::noise::median(values.to_vec())
}

#[derive(Clone, Debug, Default, PartialEq, serde::Serialize)]
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
    /// The alpha the times were judged at.
    pub alpha: f64,
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
        alpha: judgement.alpha,
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
        // Timings change every run; GPU time is judged below, against the noise.
        let timing = |metric: &str| is_timing_metric(metric.split('.').next().unwrap_or(metric));
        for (metric, &value) in current.iter().filter(|(metric, _)| !timing(metric)) {
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
            "{}, {}, {}, {}; {} only in the base, {} only in the new run.\n",
            counted(self.regressions.len(), "regression", "regressions"),
            counted(self.fixes.len(), "fix", "fixes"),
            counted(self.other_changes.len(), "other outcome change", "other outcome changes"),
            counted(self.metric_changes.len(), "metric change", "metric changes"),
            counted(self.only_in_base.len(), "case run", "case runs"),
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
        let judged = self.time_changes.iter().filter(|t| t.judged).count();
        let _ = writeln!(
            md,
            "### GPU time\n\n{} case runs timed in both: {} slower and {} faster beyond the threshold and the noise; {judged} judged, {} that could not be.\n",
            self.time_changes.len(),
            self.time_changes.iter().filter(|t| t.regression).count(),
            self.time_changes.iter().filter(|t| t.improvement).count(),
            self.time_changes.len() - judged,
        );
        if judged < self.time_changes.len() {
            let _ = writeln!(
                md,
                "**Not every time could be judged**: at --alpha {} the repeats need {} runs a side (`check --repeat {}` for both runs), a history {} earlier runs; a time that could not be judged is no verdict of \"within noise\".\n",
                self.alpha,
                repeats_needed(self.alpha),
                repeats_needed(self.alpha),
                history_needed(self.alpha)
            );
        }
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
            if let Some(RepeatsTest { p, smallest_p, base_runs, new_runs }) = &t.evidence.repeats {
                let reach =
                    if *smallest_p >= self.alpha { format!(" (p ≥ {smallest_p:.3} at best)") } else { String::new() };
                judged_by.push(format!("{base_runs} vs {new_runs} repeats, Mann–Whitney p = {p:.2e}{reach}"));
            }
            if let Some(HistoryRank { runs, median_ms, p, smallest_p }) = &t.evidence.history {
                let reach =
                    if *smallest_p >= self.alpha { format!(" (p ≥ {smallest_p:.3} at best)") } else { String::new() };
                judged_by.push(format!("{runs} earlier runs, median {median_ms:.3} ms: rank p = {p:.2e}{reach}"));
            }
            let judged_by = match (&t.evidence.not_judged, judged_by.is_empty()) {
                (Some(why), _) => why.clone(),
                (None, true) => "one time each, no history".to_owned(),
                (None, false) => judged_by.join("; "),
            };
            let verdict = if t.regression {
                "**slower**"
            } else if t.improvement {
                "faster"
            } else if t.judged {
                "within noise"
            } else {
                "cannot judge"
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
    use fragkit_report::AdapterDescription;

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
        Report { adapter: AdapterDescription::default(), cases, diagnostics: Vec::new(), shard: None, run: None }
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
            gpu_ms: Some(fragkit_report::noise::median(repeats.to_vec())),
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
    fn single_times_are_judged_by_their_rank_in_a_history_long_enough_for_alpha() {
        // 250 earlier runs between 9.8 and 10.3 ms: a 13 ms time outranks them all (p = 2/251).
        let steady: Vec<f64> = (0..250).map(|i| 9.8 + 0.5 * f64::from(i % 50) / 49.0).collect();
        assert!(judge(&[10.0], &[13.0], &steady).regression);
        assert!(!judge(&[10.0], &[10.2], &steady).regression);
        // A history this noisy holds 13 ms within it.
        let noisy: Vec<f64> = (0..250).map(|i| 6.0 + 9.0 * f64::from(i % 50) / 49.0).collect();
        let change = judge(&[10.0], &[13.0], &noisy);
        assert!(change.judged && !change.regression, "{change:?}");
        // Five earlier runs cannot reach p < 0.01 (at best 2/6): no verdict, and it says so.
        let short = judge(&[10.0], &[40.0], &[10.0, 10.3, 9.8, 10.1, 9.9]);
        assert!(!short.judged && !short.regression, "{short:?}");
        let unjudged = judge(&[10.0], &[20.0], &[]);
        assert_eq!((unjudged.evidence, unjudged.judged, unjudged.regression), (TimeEvidence::default(), false, false));
        // A cold single time against a warm median is not judged at all.
        let mixed = judge(&[10.0, 10.1, 9.9], &[40.0], &steady);
        assert!(mixed.evidence.not_judged.is_some() && !mixed.regression);
    }

    #[test]
    fn too_few_repeats_for_alpha_cannot_judge_and_say_what_would() {
        assert_eq!(smallest_repeats_p(3, 3), 0.1);
        assert!((smallest_repeats_p(5, 5) - 2.0 / 252.0).abs() < 1e-15);
        // 2 / (n + 1) must lie below alpha: 40 earlier runs at 0.05, 200 at 0.01.
        assert_eq!((history_needed(0.05), history_needed(0.01)), (40, 200));
        assert_eq!(repeats_needed(0.01), 5);
        assert_eq!(repeats_needed(0.05), 4);
        // Four times slower on every one of 3 repeats: p = 0.1 at best, no verdict at 0.01.
        let base = [10.0, 10.2, 9.9];
        let slower: Vec<f64> = base.iter().map(|t| t * 4.0).collect();
        let c = compare(
            &report(vec![timed(&base)]),
            &report(vec![timed(&slower)]),
            &TimeJudgement::default(),
            &GpuHistory::default(),
        );
        assert!(!c.time_changes[0].judged && !c.regressed(), "{:?}", c.time_changes[0]);
        let md = c.markdown("base", "new");
        assert!(
            md.contains("| cannot judge |") && md.contains("--repeat 5") && !md.contains("| within noise |"),
            "{md}"
        );
        // 1.5 times slower on 5 repeats each: judged, a regression.
        let base = [10.0, 10.2, 9.9, 10.1, 10.05];
        let slower: Vec<f64> = base.iter().map(|t| t * 1.5).collect();
        assert!(judge(&base, &slower, &[]).regression);
    }

    #[test]
    fn a_failing_cases_time_and_timing_metrics_are_no_changes() {
        use ReportedOutcome::*;
        let mut base = record("a", Pass, 1.0);
        base.metrics.insert("equal_ms".into(), serde_json::json!(3.0));
        let mut new = CaseRecord { outcome: Fail, gpu_ms: Some(62.0), ..record("a", Pass, 1.0) };
        new.metrics.insert("equal_ms".into(), serde_json::json!(5.0));
        let c = compare(&report(vec![base]), &report(vec![new]), &TimeJudgement::default(), &GpuHistory::default());
        assert!(c.metric_changes.is_empty(), "{:?}", c.metric_changes);
        let time = &c.time_changes[0];
        assert!(
            !time.judged && time.evidence.not_judged.as_deref() == Some("the case is FAIL in the new run"),
            "{time:?}"
        );
        assert!(c.markdown("b", "n").contains("the case is FAIL in the new run"));
    }

    #[test]
    fn repeats_and_history_must_both_call_it_beyond_the_noise() {
        let base = [10.0, 10.1, 9.9, 10.02, 10.05, 9.95, 10.08];
        let new: Vec<f64> = base.iter().map(|t| t * 1.1).collect();
        // Within the run, 10 % slower is clear; but earlier runs wandered as far.
        let wandering: Vec<f64> = (0..250).map(|i| 8.5 + 3.5 * f64::from(i % 50) / 49.0).collect();
        let change = judge(&base, &new, &wandering);
        assert!(change.evidence.repeats.as_ref().unwrap().p < 0.01 && !change.regression, "{change:?}");
        // A steady history confirms it.
        let steady: Vec<f64> = (0..250).map(|i| 9.95 + 0.1 * f64::from(i % 50) / 49.0).collect();
        assert!(judge(&base, &new, &steady).regression);
        // A history too short for alpha leaves the repeats to judge.
        assert!(judge(&base, &new, &[9.0, 11.5, 10.0, 12.0, 8.5]).regression);
    }
}
