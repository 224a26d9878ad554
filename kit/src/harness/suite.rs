//! A suite's own command line: what a renderer author's `main` calls with their list of cases to
//! get the kit's runner — each case in a child process (a crash or a hang costs that case), known
//! issues applied, one line per case run and the JSON report in the kit's format — without the
//! `fragkit` binary.
//!
//! ```text
//! SUITE [PATTERN…] [--json FILE] [--set KEY=VALUE]… [--backend NAME] [--adapter NAME]
//!       [--timeout SECONDS] [--jobs N] [--list] [-v]
//! ```
//! Exit status: 0 when no case failed unexpectedly, 1 when one did, 2 for bad input or a device
//! that could not be opened.

use std::ffi::OsString;
use std::path::PathBuf;
use std::process::ExitCode;
use std::time::Duration;

use anyhow::{Context, Result, bail};
use fragkit_report::AdapterDescription;
use fragkit_report::expectations::Expectations;
use fragkit_report::readable::counted;
use fragkit_report::report::{CaseRecord, Report};
use fragkit_report::run_info::{RunInfo, RunKind};
use fragkit_report::sink::{JsonSink, Sink};
use fragkit_report::skips::SkipList;

use super::case::Case;
use super::child_process::arguments_without;
use super::params::parse_overrides;
use super::reproduce::Reproduction;
use super::run::{RunOptions, plan_runs};
use super::runner::{check_overrides, select};
use super::supervise::{CHILD_STREAM, CaseTimeout, Supervision, run_child, supervise};
use crate::gpu::AdapterSelector;

/// A list of cases with its known issues, run from its own program's command line.
pub struct Suite<'a> {
    /// The program's name, for its usage text and reproduce lines.
    pub name: &'a str,
    pub cases: &'a [Case],
    /// Its known issues, in the expectations format (`cases/expectations.toml`'s), and where
    /// they come from, for errors.
    pub expectations: &'a str,
    pub expectations_origin: &'a str,
}

/// What the command line asked for.
#[derive(Default)]
struct Arguments {
    patterns: Vec<String>,
    sets: Vec<String>,
    json: Option<PathBuf>,
    selector: AdapterSelector,
    timeout: Option<Duration>,
    jobs: Option<usize>,
    list: bool,
    verbose: bool,
    /// As a supervised child: the record stream.
    child_stream: Option<PathBuf>,
}

impl Arguments {
    fn parse(words: impl IntoIterator<Item = OsString>) -> Result<Self> {
        let mut parsed = Self::default();
        let mut words = words.into_iter();
        while let Some(word) = words.next() {
            let word = word.into_string().map_err(|w| anyhow::anyhow!("argument {w:?} is not UTF-8"))?;
            let mut value = |flag: &str| -> Result<String> {
                words.next().and_then(|v| v.into_string().ok()).with_context(|| format!("{flag} needs a value"))
            };
            match word.as_str() {
                "--json" => parsed.json = Some(value("--json")?.into()),
                "--set" => parsed.sets.push(value("--set")?),
                "--backend" => parsed.selector.backend = Some(value("--backend")?),
                "--adapter" => parsed.selector.adapter_name = Some(value("--adapter")?),
                "--timeout" => {
                    let text = value("--timeout")?;
                    let seconds: u64 =
                        text.parse().ok().filter(|&s| s > 0).with_context(|| {
                            format!("--timeout {text:?}: expected a whole number of seconds above 0")
                        })?;
                    parsed.timeout = Some(Duration::from_secs(seconds));
                }
                "--jobs" => {
                    let text = value("--jobs")?;
                    let jobs: usize = text
                        .parse()
                        .ok()
                        .filter(|&n| n > 0)
                        .with_context(|| format!("--jobs {text:?}: expected a whole number of children above 0"))?;
                    parsed.jobs = Some(jobs);
                }
                "--list" => parsed.list = true,
                "-v" | "--verbose" => parsed.verbose = true,
                CHILD_STREAM => parsed.child_stream = Some(value(CHILD_STREAM)?.into()),
                flag if flag.starts_with('-') => bail!("unknown option {flag}"),
                _ => parsed.patterns.push(word),
            }
        }
        Ok(parsed)
    }
}

/// One line per case run as it finishes: outcome, case run, reason.
struct LineSink {
    verbose: bool,
}

impl Sink for LineSink {
    fn start(&mut self, adapter: &AdapterDescription, runs: usize) -> Result<()> {
        println!(
            "{} on {} ({}, {})",
            counted(runs, "case run", "case runs"),
            adapter.name,
            adapter.backend,
            adapter.driver
        );
        Ok(())
    }

    fn record(&mut self, record: &CaseRecord) -> Result<()> {
        let reason = if self.verbose { record.reason.clone() } else { record.reason.chars().take(200).collect() };
        println!("{:<15} {}  {reason}", record.outcome.label(), record.run_name());
        Ok(())
    }

    fn finish(&mut self, _report: &Report) -> Result<()> {
        Ok(())
    }
}

impl Suite<'_> {
    /// Runs the suite as this process's command line asks.
    pub fn main(&self) -> ExitCode {
        match self.run(std::env::args_os().skip(1)) {
            Ok(code) => code,
            Err(e) => {
                eprintln!("{}: error: {e:#}", self.name);
                ExitCode::from(2)
            }
        }
    }

    /// Runs the suite as `words` (a command line without the program) ask.
    pub fn run(&self, words: impl IntoIterator<Item = OsString>) -> Result<ExitCode> {
        let words: Vec<OsString> = words.into_iter().collect();
        let arguments = Arguments::parse(words.iter().cloned())?;
        let cases = select(self.cases, &arguments.patterns)?;
        if arguments.list {
            for case in &cases {
                println!("{:<40} {}", case.name, case.summary);
            }
            return Ok(ExitCode::SUCCESS);
        }
        let overrides = parse_overrides(&arguments.sets)?;
        check_overrides(&cases, &overrides)?;
        let expectations = Expectations::parse(self.expectations, self.expectations_origin)?;
        let runs = plan_runs(&cases, &overrides, None);
        let reproduction = Reproduction::of_process(self.name, &arguments.selector);
        if let Some(stream) = &arguments.child_stream {
            let options = RunOptions {
                expectations: &expectations,
                evidence_dir: None,
                reproduction: Some(&reproduction),
                retries: 0,
                repeats: 1,
            };
            run_child(&arguments.selector, &runs, &options, stream)?;
            return Ok(ExitCode::SUCCESS);
        }
        let info = RunInfo::now(RunKind::Check, None);
        let mut lines = LineSink { verbose: arguments.verbose };
        let mut json = arguments.json.as_deref().map(|path| JsonSink::new(path, None, info.clone()));
        let mut sinks: Vec<&mut dyn Sink> = vec![&mut lines];
        sinks.extend(json.as_mut().map(|sink| sink as &mut dyn Sink));
        let supervision = Supervision {
            // The children get this command line, less the report only the parent writes.
            arguments: arguments_without(words, &["--json"], &[]),
            reproduction: &reproduction,
            expectations: &expectations,
            timeout: arguments.timeout.map_or(CaseTimeout::FromBudget, CaseTimeout::Fixed),
            verbose: arguments.verbose,
            jobs: arguments.jobs.unwrap_or(1),
            skips: &SkipList::default(),
            max_fails: None,
            flaky_fails: false,
            accept_adapter: &|_| Ok(()),
            recorded: &[],
        };
        let report = supervise(&runs, &supervision, &mut sinks)?;
        let failures = report.failures(false);
        println!(
            "{}: {}",
            counted(report.cases.len(), "case run", "case runs"),
            counted(failures, "unexpected failure", "unexpected failures")
        );
        Ok(if failures == 0 { ExitCode::SUCCESS } else { ExitCode::from(1) })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn words(text: &str) -> Vec<OsString> {
        text.split_whitespace().map(OsString::from).collect()
    }

    #[test]
    fn the_command_line_is_read_and_bad_input_refused() {
        let parsed =
            Arguments::parse(words("kit.* --json r.json --set size=4x4 --backend gl --timeout 9 --jobs 2")).unwrap();
        assert_eq!(parsed.jobs, Some(2));
        assert_eq!(parsed.patterns, ["kit.*"]);
        assert_eq!(parsed.json, Some(PathBuf::from("r.json")));
        assert_eq!(parsed.sets, ["size=4x4"]);
        assert_eq!(parsed.selector.backend.as_deref(), Some("gl"));
        assert_eq!(parsed.timeout, Some(Duration::from_secs(9)));
        assert!(!parsed.list && !parsed.verbose && parsed.child_stream.is_none());
        assert_eq!(parsed.selector.adapter_name, None);
        let stream = format!("{CHILD_STREAM} s.records");
        let parsed = Arguments::parse(words(&format!("--list --adapter llvmpipe -v {stream}"))).unwrap();
        assert!(parsed.list && parsed.verbose && parsed.patterns.is_empty());
        assert_eq!(parsed.selector.adapter_name.as_deref(), Some("llvmpipe"));
        assert_eq!(parsed.child_stream, Some(PathBuf::from("s.records")));
        assert!(Arguments::parse(words("--verbose")).unwrap().verbose);
        for bad in ["--json", "--frobnicate", "--timeout 0", "--timeout x", "--jobs 0", "--jobs"] {
            assert!(Arguments::parse(words(bad)).is_err(), "{bad} accepted");
        }
    }
}
