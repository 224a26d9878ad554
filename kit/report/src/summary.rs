//! The end of a run in a few lines, as deqp-runner ends its: the slowest case runs, the flaky
//! ones, what was skipped or not run, and the failures that are new — those no known issue or
//! baseline lists (a listed one is `known_issue`).

use crate::readable::counted;
use crate::report::{CaseRecord, Report, ReportedOutcome};

/// The summary's lines: the `slowest` case runs by wall time, then each kind of finding the run
/// has. `against` names what a new failure is new against ("the expectations", "the baseline").
pub fn run_summary(report: &Report, flaky_fails: bool, slowest: usize, against: &str) -> Vec<String> {
    // A case's name, with its parameters where the run holds several runs of it (a sweep).
    let name = |case: &CaseRecord| {
        let runs = report.cases.iter().filter(|c| c.name == case.name).count();
        if runs > 1 { case.run_name() } else { case.name.clone() }
    };
    let mut lines = Vec::new();
    let mut ran: Vec<_> =
        report.cases.iter().filter(|c| !matches!(c.outcome, ReportedOutcome::Skip | ReportedOutcome::NotRun)).collect();
    ran.sort_by(|a, b| b.wall_ms.total_cmp(&a.wall_ms));
    if !ran.is_empty() {
        let named: Vec<String> =
            ran.iter().take(slowest).map(|c| format!("{} {:.1} s", name(c), c.wall_ms / 1e3)).collect();
        lines.push(format!("slowest: {}", named.join(", ")));
    }
    let of = |outcome: ReportedOutcome| -> Vec<String> {
        report.cases.iter().filter(|c| c.outcome == outcome).map(name).collect()
    };
    let flaky = of(ReportedOutcome::Flaky);
    if !flaky.is_empty() {
        let counted_as = if flaky_fails { "failures" } else { "passes" };
        lines.push(format!("flaky (counted as {counted_as}): {}", flaky.join(", ")));
    }
    for (outcome, what) in [(ReportedOutcome::Skip, "skipped"), (ReportedOutcome::NotRun, "not run")] {
        let runs = of(outcome);
        if !runs.is_empty() {
            lines.push(format!("{what}: {}", counted(runs.len(), "case run", "case runs")));
        }
    }
    let new: Vec<String> = report
        .cases
        .iter()
        .filter(|c| c.outcome.is_failure(flaky_fails))
        .map(|c| format!("{} ({})", name(c), c.outcome.label()))
        .collect();
    if !new.is_empty() {
        lines.push(format!("new against {against}: {}", new.join(", ")));
    }
    lines
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::adapter::AdapterDescription;
    use crate::param_value::ParamValue;

    fn run(cases: &[(&str, ReportedOutcome, f64)]) -> Report {
        Report {
            adapter: AdapterDescription::default(),
            cases: cases
                .iter()
                .map(|&(name, outcome, wall_ms)| CaseRecord { wall_ms, ..CaseRecord::unmeasured(name, outcome, "") })
                .collect(),
            diagnostics: Vec::new(),
            shard: None,
            run: None,
        }
    }

    #[test]
    fn the_summary_names_the_slowest_the_flaky_the_left_out_and_the_new_failures() {
        use ReportedOutcome::*;
        let report = run(&[
            ("kit.a", Pass, 1500.0),
            ("kit.b", Flaky, 200.0),
            ("kit.c", Fail, 4000.0),
            ("kit.d", KnownIssue, 100.0),
            ("kit.e", Skip, 0.0),
            ("kit.f", NotRun, 0.0),
            ("kit.g", NotRun, 0.0),
            ("kit.h", Crash, 50.0),
        ]);
        assert_eq!(
            run_summary(&report, false, 2, "the baseline"),
            [
                "slowest: kit.c 4.0 s, kit.a 1.5 s",
                "flaky (counted as passes): kit.b",
                "skipped: 1 case run",
                "not run: 2 case runs",
                "new against the baseline: kit.c (FAIL), kit.h (CRASH)",
            ]
        );
        let strict = run_summary(&report, true, 1, "the expectations");
        assert_eq!(strict[1], "flaky (counted as failures): kit.b");
        assert_eq!(strict[4], "new against the expectations: kit.b (FLAKY), kit.c (FAIL), kit.h (CRASH)");
        // Parameters name a case run only where the run holds several of that case.
        let mut sweep = run(&[("kit.a", Fail, 3.0), ("kit.a", Pass, 2.0), ("kit.b", Pass, 1.0)]);
        for (case, seed) in sweep.cases.iter_mut().zip([1, 2, 3]) {
            case.params.insert("seed".into(), ParamValue::Count(seed));
        }
        assert_eq!(
            run_summary(&sweep, false, 3, "x"),
            [
                "slowest: kit.a [seed=1] 0.0 s, kit.a [seed=2] 0.0 s, kit.b 0.0 s",
                "new against x: kit.a [seed=1] (FAIL)"
            ]
        );
        // A run of passes: only the slowest; no case run: nothing.
        assert_eq!(run_summary(&run(&[("kit.a", Pass, 10.0)]), false, 5, "x"), ["slowest: kit.a 0.0 s"]);
        assert!(run_summary(&run(&[("kit.e", Skip, 0.0)]), false, 5, "x") == ["skipped: 1 case run"]);
    }
}
