//! A baseline, as deqp-runner keeps one: the failures a run had, written as expectations entries
//! (`check --write-baseline FILE`), so that a later run given it (`check --baseline FILE`) is
//! judged against it. Each entry holds one case on exactly this adapter and driver and the kind of
//! failure it had (`fail`, `crash`, `timeout`): the same again is `known_issue`; another kind, or
//! a new failure, still fails; a pass is an `unexpected_pass` until the baseline is written again.
//! A flaky case (failed, then passed on a retry) is listed as intermittent. Entries of several
//! configurations can share a file, or each have its own.

use std::fmt::Write as _;

use fragkit_report::expectations::FailureKind;
use fragkit_report::readable::utc_time;
use fragkit_report::report::{Report, ReportedOutcome};
use fragkit_report::run_info::RunInfo;

/// TOML text, quoted and escaped.
fn quoted(text: &str) -> String {
    toml::Value::String(text.to_owned()).to_string()
}

/// A glob that matches `text` and nothing else.
fn exact(text: &str) -> String {
    quoted(&glob::Pattern::escape(text))
}

/// The baseline of `report`: one entry per case that failed (or was flaky).
pub fn baseline(report: &Report, run: &RunInfo) -> String {
    let a = &report.adapter;
    let commit = run.git_commit.as_deref().unwrap_or("unknown");
    let mut text = format!(
        "# fragkit baseline of {} ({}, {}), written by the run of {} (commit {commit}).\n",
        a.name,
        a.backend,
        a.driver_info,
        utc_time(run.started_unix)
    );
    let mut seen: Vec<&str> = Vec::new();
    for case in &report.cases {
        let flaky = case.outcome == ReportedOutcome::Flaky;
        let failed = matches!(case.outcome, ReportedOutcome::Fail | ReportedOutcome::Crash | ReportedOutcome::Timeout);
        // One entry per case: its runs (a sweep's) share it.
        if !(flaky || failed) || seen.contains(&case.name.as_str()) {
            continue;
        }
        seen.push(&case.name);
        let first_line = case.reason.lines().next().unwrap_or_default();
        let _ = write!(
            text,
            "\n[[known_issue]]\ncase = {}\nbackend = {}\nadapter = {}\ndriver_info = {}\nreason = {}\n",
            exact(&case.name),
            exact(&a.backend),
            exact(&a.name),
            exact(&a.driver_info),
            quoted(&format!("baseline ({}): {first_line}", case.outcome.label()))
        );
        if flaky {
            text.push_str("intermittent = \"flaky in the baseline run: it failed, then passed on a retry\"\n");
        } else {
            let _ = writeln!(text, "outcome = \"{}\"", FailureKind::of(&case.reason).name());
        }
    }
    text
}

#[cfg(test)]
mod tests {
    use super::*;
    use fragkit_report::AdapterDescription;
    use fragkit_report::expectations::Expectations;
    use fragkit_report::report::CaseRecord;

    #[test]
    fn a_baseline_expects_each_failure_again_on_this_adapter_and_nothing_else() {
        let adapter = AdapterDescription {
            name: "llvmpipe (LLVM 15.0.6, 256 bits)".into(),
            backend: "vulkan".into(),
            driver_info: "Mesa 22.3.6 [x]".into(),
            ..Default::default()
        };
        let report = Report {
            adapter: adapter.clone(),
            cases: vec![
                CaseRecord::unmeasured("kit.a", ReportedOutcome::Fail, "3 pixels \"differ\"\nmore"),
                CaseRecord::unmeasured(
                    "kit.b",
                    ReportedOutcome::Crash,
                    "crash: the process running the case was killed by signal 6",
                ),
                CaseRecord::unmeasured("kit.c", ReportedOutcome::Pass, ""),
                CaseRecord::unmeasured("kit.d", ReportedOutcome::Flaky, "1 pixel"),
            ],
            diagnostics: Vec::new(),
            shard: None,
            run: None,
        };
        let text = baseline(&report, &RunInfo::default());
        let expectations = Expectations::parse(&text, "baseline").unwrap();
        assert_eq!(expectations.known_issues.len(), 3, "{text}");
        // The same failure again is explained; another kind of failure is not.
        assert!(expectations.explain("kit.a", &adapter, "5 pixels differ").is_some());
        assert!(expectations.explain("kit.a", &adapter, "crash: the process running the case was killed").is_none());
        assert!(expectations.explain("kit.b", &adapter, "crash: killed by signal 11").is_some());
        assert!(expectations.explain("kit.b", &adapter, "timeout: no record for 30 s").is_none());
        assert!(expectations.explain("kit.c", &adapter, "1 pixel").is_none());
        // Only on this adapter and driver (its brackets matched literally).
        let other = AdapterDescription { driver_info: "Mesa 22.3.6 x".into(), ..adapter.clone() };
        assert!(expectations.explain("kit.a", &other, "5 pixels differ").is_none());
        assert!(expectations.known_issues[2].intermittent.is_some());
    }
}
