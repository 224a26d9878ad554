//! A run of selected cases on one adapter: the list of case runs (a sweep's draws included), a
//! deterministic share of it for one shard machine, and the loop that runs each case in
//! isolation, re-runs failures (`--retry`), reopens a lost device and hands every record to the
//! run's sinks (table, JSON, JUnit, …), so that each sink sees the same records.

use std::collections::BTreeMap;
use std::path::Path;

use anyhow::Result;

use super::case::Case;
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
    /// Append to a failure the command line that reproduces it, this command (the suite's way
    /// to run one case: `fragkit check`) with the case and its `--set`s (sweeps).
    pub reproduce_command: Option<&'a str>,
    /// Re-run a failed case up to this many times; passing on a retry makes it `flaky`.
    pub retries: u32,
    /// Above 1: after the case's run (its verdict, and the warm-up: it compiles the pipelines
    /// and touches every resource first, and runs about a third slower here), run it this many
    /// more times and keep their GPU times, so that `fragkit compare` can judge a time change
    /// against the noise; the GPU time reported is their median. A repeat whose outcome differs
    /// makes the case `flaky`.
    pub repeats: u32,
}

/// Runs `run` `repeats` more times after `record`, the warm-up, keeping their GPU times: the
/// warm-up's own time is the cold one, and kept among them it would overlap a slower build's
/// warm times (a ×2 slower shader went unflagged for it).
fn repeat(gpu: &Gpu, run: &CaseRun, options: &RunOptions, mut record: CaseRecord) -> CaseRecord {
    if record.gpu_ms.is_none() {
        return record;
    }
    let mut times = Vec::new();
    for attempt in 1..=options.repeats {
        if gpu.lost().is_some() {
            break;
        }
        let again = run_case(gpu, run.case, &run.overrides, options.expectations, options.evidence_dir);
        if again.outcome != record.outcome {
            record.reason = format!(
                "repeat {attempt} of {} was {} ({}) where the first run was {} ({})",
                options.repeats,
                again.outcome.label(),
                again.reason,
                record.outcome.label(),
                record.reason
            );
            record.outcome = ReportedOutcome::Flaky;
            break;
        }
        times.extend(again.gpu_ms);
    }
    if !times.is_empty() {
        record.gpu_ms = Some(fragkit_report::noise::median(times.clone()));
        record.gpu_ms_repeats = times;
    }
    record
}

/// Runs `runs` on `gpu`, handing every record to `sinks`; returns the report.
pub fn run(mut gpu: Gpu, runs: &[CaseRun], options: &RunOptions, sinks: &mut [&mut dyn Sink]) -> Result<Report> {
    for sink in sinks.iter_mut() {
        sink.start(&gpu.description, runs.len())?;
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
        let mut record = run_case(&gpu, run.case, &run.overrides, options.expectations, options.evidence_dir);
        while record.outcome == ReportedOutcome::Fail && record.attempts <= options.retries && gpu.lost().is_none() {
            let again = run_case(&gpu, run.case, &run.overrides, options.expectations, options.evidence_dir);
            let attempts = record.attempts + 1;
            if again.outcome == ReportedOutcome::Fail {
                record = CaseRecord { attempts, ..again };
            } else {
                let first = std::mem::take(&mut record.reason);
                record = CaseRecord {
                    outcome: ReportedOutcome::Flaky,
                    reason: format!("failed, then {} on attempt {attempts}: {first}", again.outcome.label()),
                    attempts,
                    ..again
                };
            }
        }
        if options.repeats > 1 && !record.outcome.is_failure(true) {
            record = repeat(&gpu, run, options, record);
        }
        if let Some(command) = options.reproduce_command.filter(|_| record.outcome.is_failure(true)) {
            record.reason =
                format!("{} [reproduce: {}]", record.reason, sweep::reproduce_line(command, run.case, &run.overrides));
        }
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
}
