//! A report as JUnit XML, the dialect GitLab, Jenkins and GitHub's test reporters read: one
//! `<testsuite>` for the adapter, a `<testcase>` per case run (classname: the case's area, e.g.
//! `cbr.reconstruct`). `fail` and `unexpected_pass` are `<failure>`s with the reason,
//! `not_supported` and `known_issue` `<skipped>` with theirs, `flaky` passes (with its story in
//! `<system-out>`) unless flaky cases fail the run.

use std::collections::BTreeMap;
use std::fmt::Write as _;
use std::path::Path;

use anyhow::Result;

use super::markup::escape;
use fragkit_report::report::{CaseRecord, Report, ReportedOutcome, write_through_temporary};
use fragkit_report::sink::Sink;

/// The case's area: its name up to the last dot.
fn classname(name: &str) -> &str {
    name.rsplit_once('.').map_or(name, |(area, _)| area)
}

/// A test name unique within the report: the case name, with its parameters where the case ran
/// more than once (a sweep).
fn test_name(record: &CaseRecord, runs_of_case: usize) -> String {
    if runs_of_case <= 1 { record.name.clone() } else { record.run_name() }
}

/// The JUnit XML of `report`.
pub fn to_junit(report: &Report, flaky_fails: bool) -> String {
    let mut runs_of: BTreeMap<&str, usize> = BTreeMap::new();
    for case in &report.cases {
        *runs_of.entry(case.name.as_str()).or_default() += 1;
    }
    let failures = report.failures(flaky_fails);
    let skipped = report
        .cases
        .iter()
        .filter(|c| matches!(c.outcome, ReportedOutcome::NotSupported | ReportedOutcome::KnownIssue))
        .count();
    let seconds: f64 = report.cases.iter().map(|c| c.wall_ms).sum::<f64>() / 1e3;
    let a = &report.adapter;
    let suite = format!("fragkit on {} ({}, {} {})", a.name, a.backend, a.driver, a.driver_info);
    let mut xml = String::from("<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n");
    let tests = report.cases.len();
    let _ = writeln!(
        xml,
        "<testsuites name=\"fragkit\" tests=\"{tests}\" failures=\"{failures}\" errors=\"0\" skipped=\"{skipped}\" time=\"{seconds:.3}\">"
    );
    let _ = writeln!(
        xml,
        "  <testsuite name=\"{}\" tests=\"{tests}\" failures=\"{failures}\" errors=\"0\" skipped=\"{skipped}\" time=\"{seconds:.3}\">",
        escape(&suite)
    );
    xml.push_str("    <properties>\n");
    for (name, value) in [
        ("adapter", &a.name),
        ("backend", &a.backend),
        ("driver", &a.driver),
        ("driver_info", &a.driver_info),
        ("device_type", &a.device_type),
    ] {
        let _ = writeln!(xml, "      <property name=\"{name}\" value=\"{}\"/>", escape(value));
    }
    xml.push_str("    </properties>\n");
    for case in &report.cases {
        let _ = write!(
            xml,
            "    <testcase name=\"{}\" classname=\"{}\" time=\"{:.3}\"",
            escape(&test_name(case, runs_of[case.name.as_str()])),
            escape(classname(&case.name)),
            case.wall_ms / 1e3
        );
        let first_line = case.reason.lines().next().unwrap_or_default();
        let body = match case.outcome {
            ReportedOutcome::Pass => None,
            ReportedOutcome::Flaky if !flaky_fails => {
                Some(format!("      <system-out>{}</system-out>\n", escape(&case.reason)))
            }
            ReportedOutcome::Fail
            | ReportedOutcome::UnexpectedPass
            | ReportedOutcome::Flaky
            | ReportedOutcome::Crash
            | ReportedOutcome::Timeout => Some(format!(
                "      <failure message=\"{}\" type=\"{}\">{}</failure>\n",
                escape(first_line),
                case.outcome.label(),
                escape(&case.reason)
            )),
            ReportedOutcome::NotSupported
            | ReportedOutcome::KnownIssue
            | ReportedOutcome::Skip
            | ReportedOutcome::NotRun => {
                Some(format!("      <skipped message=\"{}: {}\"/>\n", case.outcome.label(), escape(first_line)))
            }
        };
        match body {
            None => xml.push_str("/>\n"),
            Some(body) => {
                xml.push_str(">\n");
                xml.push_str(&body);
                xml.push_str("    </testcase>\n");
            }
        }
    }
    xml.push_str("  </testsuite>\n</testsuites>\n");
    xml
}

/// Writes the JUnit XML when the run finishes.
pub struct JunitSink<'a> {
    pub path: &'a Path,
    pub flaky_fails: bool,
}

impl Sink for JunitSink<'_> {
    fn finish(&mut self, report: &Report) -> Result<()> {
        write_junit(report, self.path, self.flaky_fails)
    }
}

/// Writes `report` as JUnit XML to `path` through a temporary file and a rename.
pub fn write_junit(report: &Report, path: &Path, flaky_fails: bool) -> Result<()> {
    write_through_temporary(path, &to_junit(report, flaky_fails))
}

#[cfg(test)]
mod tests {
    use super::*;
    use fragkit_report::AdapterDescription;

    fn record(name: &str, outcome: ReportedOutcome, reason: &str) -> CaseRecord {
        CaseRecord { wall_ms: 1500.0, ..CaseRecord::unmeasured(name, outcome, reason) }
    }

    #[test]
    fn outcomes_map_to_failures_and_skips_with_escaped_reasons() {
        let report = Report {
            adapter: AdapterDescription { name: "llvmpipe <x>".into(), ..Default::default() },
            cases: vec![
                record("kit.a", ReportedOutcome::Pass, ""),
                record("cbr.b.c", ReportedOutcome::Fail, "2 < 3 & \"more\"\nsecond line"),
                record("oit.d", ReportedOutcome::NotSupported, "no 8x"),
                record("cps.e", ReportedOutcome::Flaky, "failed, then pass"),
            ],
            diagnostics: Vec::new(),
            shard: None,
            run: None,
        };
        let xml = to_junit(&report, false);
        assert!(xml.contains("tests=\"4\" failures=\"1\" errors=\"0\" skipped=\"1\""));
        assert!(xml.contains("classname=\"cbr.b\""));
        assert!(xml.contains("<failure message=\"2 &lt; 3 &amp; &quot;more&quot;\" type=\"FAIL\">"));
        assert!(xml.contains("<skipped message=\"not_supported: no 8x\"/>"));
        assert!(xml.contains("llvmpipe &lt;x&gt;"));
        assert!(to_junit(&report, true).contains("failures=\"2\""));
    }

    /// xmllint (Debian's libxml2-utils, installed by .ci/setup), or None with a note outside CI.
    fn xmllint() -> Option<&'static str> {
        let found = std::process::Command::new("xmllint").arg("--version").output().is_ok_and(|o| o.status.success());
        if !found {
            assert!(std::env::var_os("CI").is_none(), "CI must validate the JUnit XML: .ci/setup installs xmllint");
            eprintln!("note: no xmllint here (bash .ci/setup installs it): schema validation skipped");
        }
        found.then_some("xmllint")
    }

    #[test]
    fn every_outcome_validates_against_the_junit_schema_readers_take() {
        let Some(xmllint) = xmllint() else { return };
        let mut cases: Vec<CaseRecord> = [
            ReportedOutcome::Pass,
            ReportedOutcome::Fail,
            ReportedOutcome::NotSupported,
            ReportedOutcome::KnownIssue,
            ReportedOutcome::UnexpectedPass,
            ReportedOutcome::Flaky,
        ]
        .into_iter()
        .enumerate()
        .map(|(i, outcome)| record(&format!("kit.case{i}"), outcome, "why <1> & \u{7} \u{FFFE}\u{FFFF} \"two\"\nlines"))
        .collect();
        // A sweep: one case run twice with different parameters.
        cases.push(CaseRecord {
            params: [("n".to_owned(), fragkit_report::param_value::ParamValue::Count(2))].into(),
            ..record("kit.case0", ReportedOutcome::Pass, "")
        });
        let report =
            Report { adapter: AdapterDescription::default(), cases, diagnostics: Vec::new(), shard: None, run: None };
        let schema = concat!(env!("CARGO_MANIFEST_DIR"), "/src/junit.xsd");
        for flaky_fails in [false, true] {
            let path = std::env::temp_dir().join(format!("fragkit-junit-{}-{flaky_fails}.xml", std::process::id()));
            write_junit(&report, &path, flaky_fails).unwrap();
            let output =
                std::process::Command::new(xmllint).args(["--noout", "--schema", schema]).arg(&path).output().unwrap();
            let text = String::from_utf8_lossy(&output.stderr).into_owned();
            assert!(output.status.success(), "{text}\n{}", to_junit(&report, flaky_fails));
            std::fs::remove_file(&path).ok();
        }
    }

    #[test]
    fn a_sweeps_case_runs_are_told_apart_and_times_are_in_seconds() {
        let swept = |n: u64| CaseRecord {
            params: [("n".to_owned(), fragkit_report::param_value::ParamValue::Count(n))].into(),
            ..record("kit.sweep", ReportedOutcome::Pass, "")
        };
        let flaky = record("kit.flaky", ReportedOutcome::Flaky, "failed <once>, then passed");
        let report = Report {
            adapter: AdapterDescription::default(),
            cases: vec![swept(1), swept(2), record("kit.single", ReportedOutcome::Pass, ""), flaky],
            diagnostics: Vec::new(),
            shard: None,
            run: None,
        };
        let xml = to_junit(&report, false);
        for expected in [
            "<testsuites name=\"fragkit\" tests=\"4\" failures=\"0\" errors=\"0\" skipped=\"0\" time=\"6.000\">",
            "<testcase name=\"kit.sweep [n=1]\" classname=\"kit\" time=\"1.500\"/>",
            "<testcase name=\"kit.sweep [n=2]\"",
            "<testcase name=\"kit.single\" classname=\"kit\" time=\"1.500\"/>",
            "<testcase name=\"kit.flaky\" classname=\"kit\" time=\"1.500\">\n      <system-out>failed &lt;once&gt;, then passed</system-out>\n    </testcase>",
        ] {
            assert!(xml.contains(expected), "{expected} not in {xml}");
        }
        let failing = to_junit(&report, true);
        assert!(
            failing.contains("<failure message=\"failed &lt;once&gt;, then passed\" type=\"FLAKY\">")
                && !failing.contains("<system-out>"),
            "{failing}"
        );
        let path = std::env::temp_dir().join(format!("fragkit-junit-sink-{}.xml", std::process::id()));
        JunitSink { path: &path, flaky_fails: false }.finish(&report).unwrap();
        assert_eq!(std::fs::read_to_string(&path).unwrap(), xml);
        std::fs::remove_file(&path).ok();
    }
}
