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

/// Repeats each run needs for the Mann–Whitney test to reach below `alpha` (> 0: no number of
/// repeats reaches below 0).
pub fn repeats_needed(alpha: f64) -> usize {
    assert!(alpha > 0.0, "no number of repeats reaches a p-value below alpha = {alpha}");
    (1..).find(|&n| smallest_repeats_p(n, n) < alpha).expect("some number of repeats reaches any alpha > 0")
}

/// The smallest two-sided rank p-value a history of `n` earlier runs can give.
pub fn smallest_history_p(n: usize) -> f64 {
    (2.0 / (n as f64 + 1.0)).min(1.0)
}

/// Earlier runs a history needs for its rank test to reach below `alpha` (> 0).
pub fn history_needed(alpha: f64) -> usize {
    assert!(alpha > 0.0, "no history reaches a p-value below alpha = {alpha}");
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
        for needed in [repeats_needed, history_needed] {
            assert!(std::panic::catch_unwind(|| needed(0.0)).is_err(), "alpha 0 is refused, not looped on");
        }
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
    fn the_history_rank_p_counts_earlier_times_at_least_as_far_out_on_the_nearer_side() {
        let earlier = [1.0, 2.0, 3.0, 4.0, 5.0];
        // Beyond every earlier time on either side: 2 · (1 + 0) / 6.
        assert_eq!(rank_p(&earlier, 0.5), 1.0 / 3.0);
        assert_eq!(rank_p(&earlier, 6.0), 1.0 / 3.0);
        // One earlier time at or below: 2 · (1 + 1) / 6; ties count on both sides.
        assert_eq!(rank_p(&earlier, 1.5), 2.0 / 3.0);
        assert_eq!(rank_p(&earlier, 1.0), 2.0 / 3.0);
        assert_eq!(rank_p(&earlier, 5.0), 2.0 / 3.0);
        // In the middle the p is capped at 1.
        assert_eq!(rank_p(&earlier, 3.0), 1.0);
        // A repeat count whose smallest p equals alpha cannot reach below it.
        assert_eq!((smallest_repeats_p(3, 3), repeats_needed(0.1)), (0.1, 4));
        assert_eq!((smallest_history_p(19), history_needed(0.1)), (0.1, 20));
    }

    /// `base` → `new` judged at `judgement` against `history` (single and repeated alike).
    fn judged_at(judgement: TimeJudgement, base: CaseRecord, new: CaseRecord, history: &[f64]) -> Option<TimeChange> {
        let earlier = BTreeMap::from([("t".to_owned(), history.to_vec())]);
        let history = GpuHistory { single: earlier.clone(), repeated: earlier };
        compare(&report(vec![base]), &report(vec![new]), &judgement, &history).time_changes.first().cloned()
    }

    #[test]
    fn the_threshold_is_a_strict_bound_on_either_side_and_a_time_needs_both_runs_timed() {
        let judgement = TimeJudgement { threshold: 0.25, alpha: 0.01 };
        let steady: Vec<f64> = (0..250).map(|i| 9.9 + 0.2 * f64::from(i % 50) / 49.0).collect();
        let at = |new: f64| judged_at(judgement, timed(&[10.0]), timed(&[new]), &steady).unwrap();
        // Exactly 1.25 and 1 / 1.25 of the base are within the threshold; just past them is not.
        assert!(at(12.5).judged && !at(12.5).regression && at(12.6).regression);
        assert!(!at(8.0).improvement && at(7.9).improvement && !at(7.9).regression);
        // 20 % faster is within a 25 % threshold however clear the history.
        assert!(!at(8.3).improvement);
        // Nothing to judge where either run has no time or a time of zero.
        for (base, new) in [(None, Some(1.0)), (Some(1.0), None), (Some(0.0), Some(1.0)), (Some(1.0), Some(0.0))] {
            let record = |ms| CaseRecord { gpu_ms: ms, ..record("t", ReportedOutcome::Pass, 1.0) };
            assert_eq!(judged_at(judgement, record(base), record(new), &steady), None, "{base:?} → {new:?}");
        }
        // The history's median is reported with the rank.
        let history = at(12.6).evidence.history.unwrap();
        let median = fragkit_report::noise::median(steady.clone());
        assert_eq!((history.runs, history.median_ms, history.p), (250, median, 2.0 / 251.0));
    }

    #[test]
    fn repeats_are_tested_only_where_both_runs_have_several_and_a_p_of_alpha_is_not_beyond_it() {
        let base = [10.0, 10.1, 9.9, 10.05, 9.95];
        let slower = [14.0, 14.1, 13.9, 14.05, 9.96];
        // One repeat on a side is no sample to test.
        let one_repeat = |ms: f64| CaseRecord { gpu_ms_repeats: vec![ms], ..timed(&[ms]) };
        let one = judged_at(TimeJudgement::default(), one_repeat(10.0), timed(&slower), &[]).unwrap();
        assert_eq!(one.evidence.repeats, None, "{one:?}");
        let one = judged_at(TimeJudgement::default(), timed(&base), one_repeat(14.0), &[]).unwrap();
        assert_eq!(one.evidence.repeats, None, "{one:?}");
        // At alpha equal to the repeats' own p the change is not beyond the noise; just above it is.
        let p = mann_whitney_p(&base, &slower);
        let at_alpha =
            |alpha| judged_at(TimeJudgement { threshold: 0.05, alpha }, timed(&base), timed(&slower), &[]).unwrap();
        assert!(at_alpha(p).judged && !at_alpha(p).regression, "{:?}", at_alpha(p));
        assert!(at_alpha(p * 1.0001).regression);
        // So for the history's rank p: 13 ms outranks all 250 earlier times, p = 2 / 251.
        let steady: Vec<f64> = (0..250).map(|i| 9.9 + 0.2 * f64::from(i % 50) / 49.0).collect();
        let rank_p = 2.0 / 251.0;
        let history_at = |alpha| {
            judged_at(TimeJudgement { threshold: 0.05, alpha }, timed(&[10.0]), timed(&[13.0]), &steady).unwrap()
        };
        assert!(history_at(rank_p * 1.0001).regression);
        // A time level with the slowest earlier one: p = 2 · (1 + 1) / 251, judged (the smallest
        // p is half that) and beyond the noise only at an alpha above it.
        let distinct: Vec<f64> = (0..250).map(|i| 9.9 + 0.2 * f64::from(i) / 249.0).collect();
        let tie_at = |alpha| {
            judged_at(TimeJudgement { threshold: 0.05, alpha }, timed(&[9.0]), timed(&[10.1]), &distinct).unwrap()
        };
        let tied_p = 4.0 / 251.0;
        assert_eq!(tie_at(tied_p).evidence.history.unwrap().p, tied_p);
        assert!(tie_at(tied_p).judged && !tie_at(tied_p).regression, "{:?}", tie_at(tied_p));
        assert!(tie_at(tied_p * 1.0001).regression);
        // Faster, but no faster than the noise: no improvement.
        let noisy = [7.0, 14.0, 9.0, 13.0, 6.0];
        let change = judged_at(TimeJudgement::default(), timed(&base), timed(&noisy), &[]).unwrap();
        assert!(change.ratio() < 0.95 && change.judged && !change.improvement, "{change:?}");
    }

    #[test]
    fn a_run_regressed_by_a_new_failure_or_by_a_slower_time_alone() {
        let base = [10.0, 10.1, 9.9, 10.05, 9.95];
        let slower: Vec<f64> = base.iter().map(|t| t * 2.0).collect();
        let run = |repeats: &[f64], outcome| report(vec![CaseRecord { outcome, ..timed(repeats) }]);
        let judge = TimeJudgement::default();
        let none = GpuHistory::default();
        assert!(
            !compare(&run(&base, ReportedOutcome::Pass), &run(&base, ReportedOutcome::Pass), &judge, &none).regressed()
        );
        let time = compare(&run(&base, ReportedOutcome::Pass), &run(&slower, ReportedOutcome::Pass), &judge, &none);
        assert!(time.regressions.is_empty() && time.regressed());
        let failure = compare(&run(&base, ReportedOutcome::Pass), &run(&base, ReportedOutcome::Fail), &judge, &none);
        assert!(failure.time_changes.iter().all(|t| !t.regression) && failure.regressed());
    }

    fn change(case: &str, base_ms: f64, new_ms: f64, judged: bool) -> TimeChange {
        let ratio = new_ms / base_ms;
        TimeChange {
            case: case.into(),
            base_ms,
            new_ms,
            evidence: TimeEvidence::default(),
            judged,
            regression: judged && ratio > 1.05,
            improvement: judged && ratio < 1.0 / 1.05,
        }
    }

    #[test]
    fn the_markdown_lists_every_section_and_orders_times_by_how_far_they_moved() {
        use ReportedOutcome::*;
        let outcome =
            |case: &str, base, new| OutcomeChange { case: case.into(), base, new, reason: "a | b\nmore".into() };
        let comparison = Comparison {
            regressions: vec![outcome("r", Pass, Fail)],
            fixes: vec![outcome("f", Fail, Pass)],
            other_changes: Vec::new(),
            only_in_base: vec!["gone".into(), "gone2".into()],
            only_in_new: Vec::new(),
            metric_changes: vec![MetricChange { case: "m".into(), metric: "e.max".into(), base: 0.5, new: 0.25 }],
            time_changes: vec![
                TimeChange {
                    evidence: TimeEvidence {
                        repeats: Some(RepeatsTest { p: 0.004, smallest_p: 0.0079, base_runs: 5, new_runs: 5 }),
                        history: Some(HistoryRank { runs: 3, median_ms: 1.0, p: 0.5, smallest_p: 0.5 }),
                        not_judged: None,
                    },
                    ..change("slow", 1.0, 2.0, true)
                },
                change("slower", 1.0, 3.0, true),
                change("fast", 2.0, 1.0, true),
                change("same", 1.0, 1.01, true),
                TimeChange {
                    evidence: TimeEvidence {
                        not_judged: Some("the case is FAIL in the new run".into()),
                        ..Default::default()
                    },
                    ..change("failing", 1.0, 9.0, false)
                },
            ],
            alpha: 0.01,
        };
        let md = comparison.markdown("base", "new");
        let expected = "## fragkit: new against base

1 regression, 1 fix, 0 other outcome changes, 1 metric change; 2 case runs only in the base, 0 only in the new run.

### Regressions

| case | was | now | reason |
|---|---|---|---|
| `r` | pass | FAIL | a \\| b |

### Fixes

| case | was | now | reason |
|---|---|---|---|
| `f` | FAIL | pass | a \\| b |

### Only in the base run

`gone`, `gone2`

### Metric changes

| case | metric | was | now |
|---|---|---|---|
| `m` | e.max | 0.5 | 0.25 |

### GPU time

5 case runs timed in both: 2 slower and 1 faster beyond the threshold and the noise; 4 judged, 1 that could not be.

**Not every time could be judged**: at --alpha 0.01 the repeats need 5 runs a side (`check --repeat 5` for both runs), a history 200 earlier runs; a time that could not be judged is no verdict of \"within noise\".

| case | base ms | new ms | new / base | judged by | verdict |
|---|---|---|---|---|---|
| `slower` | 1.000 | 3.000 | 3.000 | one time each, no history | **slower** |
| `slow` | 1.000 | 2.000 | 2.000 | 5 vs 5 repeats, Mann–Whitney p = 4.00e-3; 3 earlier runs, median 1.000 ms: rank p = 5.00e-1 (p ≥ 0.500 at best) | **slower** |
| `fast` | 2.000 | 1.000 | 0.500 | one time each, no history | faster |

";
        assert_eq!(md, expected);
        // With nothing beyond the noise, the five largest moves either way are shown.
        let quiet = Comparison {
            time_changes: [1.5, 0.5, 1.01, 0.9, 1.2, 3.0, 1.02]
                .iter()
                .enumerate()
                .map(|(i, &r)| TimeChange {
                    regression: false,
                    improvement: false,
                    ..change(&format!("c{i}"), 1.0, r, i != 2)
                })
                .collect(),
            alpha: 0.01,
            ..Default::default()
        };
        let md = quiet.markdown("b", "n");
        let rows: Vec<&str> =
            md.lines().filter(|l| l.starts_with("| `")).map(|l| l.split('`').nth(1).unwrap()).collect();
        assert_eq!(rows, ["c5", "c1", "c0", "c4", "c3"], "{md}");
        assert!(
            md.contains("| within noise |") && !md.contains("cannot judge") && !md.contains("### Regressions"),
            "{md}"
        );
        assert!(!Comparison::default().markdown("b", "n").contains("### GPU time"));
        let all_judged =
            Comparison { time_changes: vec![change("a", 1.0, 1.01, true)], alpha: 0.01, ..Default::default() };
        let md = all_judged.markdown("b", "n");
        assert!(md.contains("1 judged, 0 that could not be") && !md.contains("Not every time"), "{md}");
    }

    #[test]
    fn a_test_judges_only_where_its_smallest_p_lies_strictly_below_alpha() {
        let repeats = |smallest_p| TimeEvidence {
            repeats: Some(RepeatsTest { p: 0.0, smallest_p, base_runs: 3, new_runs: 3 }),
            ..Default::default()
        };
        let history = |smallest_p| TimeEvidence {
            history: Some(HistoryRank { runs: 5, median_ms: 1.0, p: 0.0, smallest_p }),
            ..Default::default()
        };
        for evidence in [repeats(0.1), history(0.1)] {
            assert!(
                !evidence.can_judge(0.1) && evidence.can_judge(0.1001) && !evidence.can_judge(0.05),
                "{evidence:?}"
            );
            let refused = TimeEvidence { not_judged: Some("why".into()), ..evidence };
            assert!(!refused.can_judge(0.5));
        }
        // Either test reaching alpha is enough to judge.
        let both = TimeEvidence { history: history(0.001).history, ..repeats(0.5) };
        assert!(both.can_judge(0.01));
        let change = TimeChange {
            case: "t".into(),
            base_ms: 8.0,
            new_ms: 12.0,
            evidence: TimeEvidence::default(),
            judged: false,
            regression: false,
            improvement: false,
        };
        assert_eq!(change.ratio(), 1.5);
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
