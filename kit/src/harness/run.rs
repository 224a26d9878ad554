//! A run of selected cases on one adapter: the list of case runs (a sweep's draws included), a
//! deterministic share of it for one shard machine, and the loop that runs each case in
//! isolation, re-runs failures (`--retry`), reopens a lost device and hands every record to the
//! run's sinks (table, JSON, JUnit, …), so that each sink sees the same records.

use std::collections::BTreeMap;
use std::path::Path;

use anyhow::Result;

use super::case::Case;
use super::case_lock;
use super::reproduce::Reproduction;
use super::runner::run_case;
use super::sweep;
use crate::diagnostics;
use crate::gpu::Gpu;
use fragkit_report::expectations::Expectations;
use fragkit_report::report::{CaseRecord, Report, ReportedOutcome};
use fragkit_report::sink::Sink;

/// One case to run with its `--set` overrides (drawn from its ranges under a sweep).
#[derive(Clone)]
pub struct CaseRun<'c> {
    pub case: &'c Case,
    pub overrides: BTreeMap<String, String>,
}

/// The runs of `cases`: each once with `overrides`, or under `sweep` = (N, seed) N draws from its
/// declared ranges (once for a case without ranges), `overrides` pinning what they name. Each run
/// keeps only the overrides of its case's own parameters, so that its reproduce line names what
/// it ran with and nothing another case was given.
pub fn plan_runs<'c>(
    cases: &[&'c Case],
    overrides: &BTreeMap<String, String>,
    sweep: Option<(u32, u64)>,
) -> Vec<CaseRun<'c>> {
    match sweep {
        None => cases.iter().map(|&case| CaseRun { case, overrides: own(case, overrides.clone()) }).collect(),
        Some((count, seed)) => cases
            .iter()
            .flat_map(|&case| {
                let draws = if case.sweep.is_empty() { 1 } else { count };
                (0..draws).map(move |index| {
                    let mut drawn = sweep::draw(case, seed, index);
                    drawn.extend(overrides.iter().map(|(k, v)| (k.clone(), v.clone())));
                    CaseRun { case, overrides: own(case, drawn) }
                })
            })
            .collect(),
    }
}

/// `overrides` less those naming no parameter of `case`.
fn own(case: &Case, mut overrides: BTreeMap<String, String>) -> BTreeMap<String, String> {
    overrides.retain(|key, _| case.params.iter().any(|p| p.name == key));
    overrides
}

/// How a run treats its cases.
pub struct RunOptions<'a> {
    pub expectations: &'a Expectations,
    pub evidence_dir: Option<&'a Path>,
    /// Append to a failure the command line that reproduces it: the case, its `--set`s, and
    /// what chose and shaped the adapter ([`Reproduction`]).
    pub reproduction: Option<&'a Reproduction>,
    /// Re-run a failed case up to this many times; passing on a retry makes it `flaky`.
    pub retries: u32,
    /// Above 1: after the case's run (its verdict, and the warm-up: it compiles the pipelines
    /// and touches every resource first, and runs about a third slower here), run it this many
    /// more times and keep their GPU times, so that `fragkit compare` can judge a time change
    /// against the noise; the GPU time reported is their median. A repeat whose outcome differs
    /// makes the case `flaky`.
    pub repeats: u32,
}

/// A failed case run retried up to `retries` times (`again` runs the case once more, None where
/// it cannot: the device is lost): failing every time stays a failure, the last one's record with
/// every attempt counted; anything else on a retry makes it `flaky`, naming the failure before.
fn retried(mut record: CaseRecord, retries: u32, mut again: impl FnMut() -> Option<CaseRecord>) -> CaseRecord {
    while record.outcome == ReportedOutcome::Fail && record.attempts <= retries {
        let Some(next) = again() else { break };
        let attempts = record.attempts + 1;
        if next.outcome == ReportedOutcome::Fail {
            record = CaseRecord { attempts, ..next };
        } else {
            let first = std::mem::take(&mut record.reason);
            record = CaseRecord {
                outcome: ReportedOutcome::Flaky,
                reason: format!("failed, then {} on attempt {attempts}: {first}", next.outcome.label()),
                attempts,
                ..next
            };
        }
    }
    record
}

/// With `repeats` above 1, a timed case run that did not fail run `repeats` more times after
/// `record`, the warm-up (`again` as for [`retried`]), keeping their GPU times: the warm-up's own
/// time is the cold one, and kept among them it would overlap a slower build's warm times (a ×2
/// slower shader went unflagged for it). The time reported is their median; a repeat whose
/// outcome differs makes the case `flaky`.
fn repeated(mut record: CaseRecord, repeats: u32, mut again: impl FnMut() -> Option<CaseRecord>) -> CaseRecord {
    if repeats <= 1 || record.outcome.is_failure(true) || record.gpu_ms.is_none() {
        return record;
    }
    let mut times = Vec::new();
    for attempt in 1..=repeats {
        let Some(next) = again() else { break };
        if next.outcome != record.outcome {
            record.reason = format!(
                "repeat {attempt} of {repeats} was {} ({}) where the first run was {} ({})",
                next.outcome.label(),
                next.reason,
                record.outcome.label(),
                record.reason
            );
            record.outcome = ReportedOutcome::Flaky;
            break;
        }
        times.extend(next.gpu_ms);
    }
    if !times.is_empty() {
        record.gpu_ms = Some(fragkit_report::noise::median(times.clone()));
        record.gpu_ms_repeats = times;
    }
    record
}

/// A failure's reason (a flaky case's too) with the command line that reproduces it on the
/// adapter of `backend`, where a reproduction is given.
fn with_reproduce_line(
    mut record: CaseRecord,
    reproduction: Option<&Reproduction>,
    run: &CaseRun,
    backend: &str,
) -> CaseRecord {
    if let Some(reproduction) = reproduction.filter(|_| record.outcome.is_failure(true)) {
        record.reason =
            format!("{} [reproduce: {}]", record.reason, reproduction.line(run.case, &run.overrides, backend));
    }
    record
}

/// Runs `runs` (`count` of them: a supervised child takes them one by one as its parent hands
/// them out) on `gpu`, each under the case lock (`case_lock`), handing every record to `sinks`;
/// returns the report.
pub fn run<'r, 'c: 'r>(
    mut gpu: Gpu,
    runs: impl IntoIterator<Item = &'r CaseRun<'c>>,
    count: usize,
    options: &RunOptions,
    sinks: &mut [&mut dyn Sink],
) -> Result<Report> {
    for sink in sinks.iter_mut() {
        sink.start(&gpu.description, count)?;
    }
    // What opening the device logged (EGL probing a missing DRI driver, say) belongs to the run.
    let mut report = Report {
        adapter: gpu.description.clone(),
        cases: Vec::new(),
        diagnostics: diagnostics::take(),
        shard: None,
        run: None,
    };
    for run in runs {
        let lock =
            case_lock::lock_for(run.case, |waiting| sinks.iter_mut().try_for_each(|sink| sink.waiting(waiting)))?;
        let run_once = || run_case(&gpu, run.case, &run.overrides, options.expectations, options.evidence_dir);
        // Again, while the device is not lost.
        let again = || gpu.lost().is_none().then(run_once);
        let record = retried(run_once(), options.retries, again);
        let record = repeated(record, options.repeats, again);
        let record = with_reproduce_line(record, options.reproduction, run, &gpu.description.backend);
        drop(lock);
        for sink in sinks.iter_mut() {
            sink.record(&record)?;
        }
        report.cases.push(record);
        if gpu.lost().is_some() {
            // The lost case is recorded as failed; the rest run on a fresh device.
            match gpu.reopen() {
                Ok(fresh) => gpu = fresh,
                Err(e) => {
                    for sink in sinks.iter_mut() {
                        sink.finish(&report)?;
                    }
                    return Err(
                        e.context("reopening the device after it was lost; the report holds the cases that ran")
                    );
                }
            }
        }
    }
    for sink in sinks.iter_mut() {
        sink.finish(&report)?;
    }
    Ok(report)
}

#[cfg(test)]
mod tests {
    use fragkit_report::sink::Shard;

    use crate::harness::{ParamKind, ParamSpec};

    use super::*;

    #[test]
    fn shards_together_run_every_case_once() {
        let cases = ["a", "b", "c", "d", "e"].map(Case::passing);
        let selected: Vec<&Case> = cases.iter().collect();
        let runs = plan_runs(&selected, &BTreeMap::new(), None);
        let mut seen: Vec<&str> = (1..=3)
            .flat_map(|k| Shard { index: k, count: 3 }.select(runs.clone()).into_iter().map(|r| r.case.name))
            .collect();
        seen.sort_unstable();
        assert_eq!(seen, ["a", "b", "c", "d", "e"]);
    }

    #[test]
    fn a_run_keeps_only_its_own_cases_overrides() {
        let sized = Case {
            params: &[ParamSpec { name: "size", kind: ParamKind::Size, default: "4x4", help: "" }],
            ..Case::passing("sized")
        };
        let plain = Case::passing("plain");
        let overrides = BTreeMap::from([("size".to_owned(), "8x8".to_owned())]);
        let runs = plan_runs(&[&sized, &plain], &overrides, None);
        assert_eq!(runs[0].overrides, overrides);
        assert!(runs[1].overrides.is_empty(), "{:?}", runs[1].overrides);
    }

    /// A case run's records, one a run of it, in order.
    fn script(records: Vec<CaseRecord>) -> impl FnMut() -> Option<CaseRecord> {
        let mut records = records.into_iter();
        move || records.next()
    }

    fn ran(outcome: ReportedOutcome, reason: &str, gpu_ms: Option<f64>) -> CaseRecord {
        CaseRecord { gpu_ms, ..CaseRecord::unmeasured("kit.a", outcome, reason) }
    }

    #[test]
    fn a_failure_is_retried_up_to_its_retries_and_a_later_pass_is_flaky() {
        use ReportedOutcome::*;
        let fail = |why: &str| ran(Fail, why, None);
        let always = retried(fail("1st"), 2, script(vec![fail("2nd"), fail("3rd"), fail("4th")]));
        assert_eq!((always.outcome, always.attempts, always.reason.as_str()), (Fail, 3, "3rd"));
        let healed = retried(fail("1st"), 2, script(vec![fail("2nd"), ran(Pass, "", Some(4.0))]));
        assert_eq!((healed.outcome, healed.attempts), (Flaky, 3));
        assert_eq!(healed.reason, "failed, then pass on attempt 3: 2nd");
        assert_eq!(healed.gpu_ms, Some(4.0), "the passing run's record");
        let other = retried(fail("1st"), 1, script(vec![ran(NotSupported, "no 8x", None)]));
        assert_eq!((other.outcome, other.reason.as_str()), (Flaky, "failed, then not_supported on attempt 2: 1st"));
        // No retries, a device lost, or no failure: nothing runs again.
        assert_eq!(retried(fail("1st"), 0, script(vec![ran(Pass, "", None)])).outcome, Fail);
        assert_eq!(retried(fail("1st"), 3, script(vec![])).attempts, 1);
        let mut asked = false;
        let pass = retried(ran(Pass, "", None), 3, || {
            asked = true;
            None
        });
        assert!(pass.outcome == Pass && !asked);
        assert_eq!(retried(ran(Crash, "", None), 3, script(vec![ran(Pass, "", None)])).outcome, Crash);
    }

    #[test]
    fn repeats_keep_the_warm_times_and_a_changed_outcome_is_flaky() {
        use ReportedOutcome::*;
        let timed = |ms| ran(Pass, "", Some(ms));
        let warm = repeated(timed(9.0), 3, script(vec![timed(2.0), timed(1.0), timed(3.0)]));
        assert_eq!(
            (warm.outcome, warm.gpu_ms, warm.gpu_ms_repeats.as_slice()),
            (Pass, Some(2.0), &[2.0, 1.0, 3.0][..])
        );
        // The second repeat fails: flaky, naming both, with the time before it kept.
        let changed = repeated(timed(9.0), 3, script(vec![timed(2.0), ran(Fail, "3 pixels", Some(5.0)), timed(1.0)]));
        assert_eq!(changed.outcome, Flaky);
        assert_eq!(changed.reason, "repeat 2 of 3 was FAIL (3 pixels) where the first run was pass ()");
        assert_eq!((changed.gpu_ms, changed.gpu_ms_repeats.as_slice()), (Some(2.0), &[2.0][..]));
        // A device lost after one repeat: that one's time.
        let lost = repeated(timed(9.0), 3, script(vec![timed(4.0)]));
        assert_eq!((lost.gpu_ms, lost.gpu_ms_repeats.len()), (Some(4.0), 1));
        // One run asked for, a failure, or no GPU time: no repeats at all.
        for record in [timed(9.0), ran(Fail, "x", Some(9.0)), ran(Flaky, "x", Some(9.0)), ran(Pass, "", None)] {
            let repeats = if record.gpu_ms.is_some() && record.outcome == Pass { 1 } else { 3 };
            let kept = repeated(record.clone(), repeats, script(vec![timed(1.0), timed(1.0), timed(1.0)]));
            assert_eq!((kept.outcome, kept.gpu_ms, kept.gpu_ms_repeats.len()), (record.outcome, record.gpu_ms, 0));
        }
        // Repeats without GPU times (an adapter without timestamps) leave the time as it was.
        let untimed = repeated(timed(9.0), 2, script(vec![ran(Pass, "", None), ran(Pass, "", None)]));
        assert_eq!((untimed.gpu_ms, untimed.gpu_ms_repeats.len()), (Some(9.0), 0));
    }

    #[test]
    fn a_failure_names_the_command_that_reproduces_it() {
        use ReportedOutcome::*;
        let case = Case {
            params: &[ParamSpec { name: "n", kind: ParamKind::Count, default: "1", help: "" }],
            ..Case::passing("kit.a")
        };
        let run = CaseRun { case: &case, overrides: [("n".to_owned(), "2".to_owned())].into() };
        let environment = [("LP_NATIVE_VECTOR_WIDTH".to_owned(), "128".to_owned())];
        let reproduction = Reproduction::new("fragkit check", &Default::default(), environment);
        for (outcome, named) in [(Fail, true), (Flaky, true), (Crash, true), (Pass, false), (KnownIssue, false)] {
            let record = with_reproduce_line(ran(outcome, "why", None), Some(&reproduction), &run, "gl");
            let expected = if named {
                "why [reproduce: LP_NATIVE_VECTOR_WIDTH=128 fragkit check kit.a --set n=2 --backend gl]"
            } else {
                "why"
            };
            assert_eq!(record.reason, expected, "{outcome:?}");
        }
        assert_eq!(with_reproduce_line(ran(Fail, "why", None), None, &run, "gl").reason, "why");
    }
}
