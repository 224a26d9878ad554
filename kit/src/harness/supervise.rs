//! Cases run in a child process, as deqp-runner runs its case lists: a driver that aborts, a
//! shader that never ends or a process killed from outside costs one case, not the run. The child
//! (this program again, with `--child-stream FILE --skip N`) runs the case list from run N and streams each record;
//! the parent hands the records to its sinks as they come, records the case a child died in as
//! `crash` (or `timeout`, when no record came within the case's time and the parent killed it:
//! `CaseTimeout`) and starts a new child after it, so every output holds every case.

use std::ffi::OsString;
use std::path::{Path, PathBuf};
use std::process::{Child, Command, ExitStatus, Stdio};
use std::time::{Duration, Instant};

use anyhow::{Context, Result, bail};
use fragkit_report::AdapterDescription;
use fragkit_report::expectations::Expectations;
use fragkit_report::report::{CaseRecord, Report, ReportedOutcome};
use fragkit_report::sink::Sink;

use super::case::Case;
use super::child_process::{ending, log_tail};
use super::params::Params;
use super::run::{CaseRun, RunOptions, run};
use super::runner::check_sizes;
use super::stream::{StreamLine, StreamSink, read_new_lines};
use super::sweep::reproduce_line;
use crate::gpu::{AdapterSelector, Gpu};

/// How often the parent looks for new records and a child's end.
const POLL: Duration = Duration::from_millis(20);

/// How long a case may go without a record before the process running it is killed.
#[derive(Clone, Copy, Debug)]
pub enum CaseTimeout {
    /// `--timeout SECONDS`: the same for every case.
    Fixed(Duration),
    /// From each case's own budget (`Case::budget_s`, its slowest wall time at its defaults on
    /// the matrix): `BUDGET_FACTOR` times it — room for a sweep's larger draws and a loaded
    /// machine — and never under `SHORTEST`, which covers opening a device in a new child.
    FromBudget,
}

const BUDGET_FACTOR: u32 = 10;
const SHORTEST: Duration = Duration::from_secs(30);

impl CaseTimeout {
    pub fn of(self, case: &Case) -> Duration {
        match self {
            Self::Fixed(timeout) => timeout,
            Self::FromBudget => SHORTEST.max(Duration::from_secs(u64::from(BUDGET_FACTOR * case.budget_s))),
        }
    }

    /// Where a case's timeout came from, for its record.
    fn origin(self, case: &Case) -> String {
        match self {
            Self::Fixed(_) => "--timeout".to_owned(),
            Self::FromBudget => {
                format!("{BUDGET_FACTOR}× the case's budget of {} s, at least {} s", case.budget_s, SHORTEST.as_secs())
            }
        }
    }
}

/// Files of one supervised run, removed when it ends.
struct Scratch {
    stream: PathBuf,
    stderr: PathBuf,
}

impl Scratch {
    /// Named by this process's id, and emptied: a process killed before it could remove its
    /// files leaves them behind, and a later one given the same id must not read its records.
    fn new() -> Result<Self> {
        let base = std::env::temp_dir().join(format!("fragkit-child-{}", std::process::id()));
        let scratch = Self { stream: base.with_extension("stream"), stderr: base.with_extension("stderr") };
        std::fs::File::create(&scratch.stream)
            .with_context(|| format!("creating the record stream {}", scratch.stream.display()))?;
        Ok(scratch)
    }
}

impl Drop for Scratch {
    fn drop(&mut self) {
        std::fs::remove_file(&self.stream).ok();
        std::fs::remove_file(&self.stderr).ok();
    }
}

/// How a child ended, short of finishing its list.
enum Death {
    Status(ExitStatus),
    TimedOut,
}

/// How a supervisor starts its children and judges their deaths.
pub struct Supervision<'a> {
    /// The child's command line after the program: the parent's own, less what only the parent
    /// writes. The child is this program (`std::env::current_exe`), given `arguments` and then
    /// [`CHILD_STREAM`] FILE [`CHILD_SKIP`] N, and must answer them with [`run_child`].
    pub arguments: Vec<OsString>,
    /// The command that runs one case on its own (`fragkit check`), for reproduce lines.
    pub command: &'a str,
    pub expectations: &'a Expectations,
    pub timeout: CaseTimeout,
    /// Echo what each child logged, after it.
    pub verbose: bool,
}

/// The flag that makes a program a supervised child: stream each record into this file.
pub const CHILD_STREAM: &str = "--child-stream";
/// The flag that tells a child which case run of the list to start at.
pub const CHILD_SKIP: &str = "--skip";

/// Runs `runs` in children of this program, handing every record to `sinks` as it comes;
/// returns the report. A child that dies (a signal, an abort, an exit before recording) or
/// goes quiet past its case's timeout costs that case alone: it is recorded `crash` or
/// `timeout` (or `known_issue`, where the expectations list that death) and a new child
/// continues from the case after it.
pub fn supervise(runs: &[CaseRun], supervision: &Supervision, sinks: &mut [&mut dyn Sink]) -> Result<Report> {
    let Supervision { arguments, timeout, verbose, .. } = supervision;
    let (timeout, verbose) = (*timeout, *verbose);
    let program = std::env::current_exe().context("finding this program to run the cases in a child")?;
    let scratch = Scratch::new()?;
    let mut report: Option<Report> = None;
    let mut offset = 0u64;
    let mut done = 0usize;
    while done < runs.len() || report.is_none() {
        let mut child = start_child(&program, arguments, &scratch, done)?;
        let mut last_progress = Instant::now();
        // None: the child ran its list to the end.
        let death = loop {
            let exited = child.try_wait().context("waiting for the case child")?;
            let (lines, next) = read_new_lines(&scratch.stream, offset)?;
            offset = next;
            let mut finished = false;
            for line in lines {
                last_progress = Instant::now();
                match line {
                    StreamLine::Start { adapter, runs: count } => {
                        if report.is_none() {
                            for sink in sinks.iter_mut() {
                                sink.start(&adapter, done + count)?;
                            }
                            report = Some(Report {
                                adapter,
                                cases: Vec::new(),
                                diagnostics: Vec::new(),
                                shard: None,
                                run: None,
                            });
                        }
                    }
                    StreamLine::Record(record) => {
                        let report = report.as_mut().context("the case child recorded before it started")?;
                        for sink in sinks.iter_mut() {
                            sink.record(&record)?;
                        }
                        report.cases.push(*record);
                        done += 1;
                    }
                    StreamLine::Finished { diagnostics } => {
                        report
                            .as_mut()
                            .context("the case child finished before it started")?
                            .diagnostics
                            .extend(diagnostics);
                        finished = true;
                    }
                }
            }
            if finished {
                let _ = child.wait();
                break None;
            }
            if let Some(status) = exited {
                break Some(Death::Status(status));
            }
            // The case now running (or, before the first record, the first): its own time.
            let allowed = runs.get(done).map_or(SHORTEST, |run| timeout.of(run.case));
            if last_progress.elapsed() > allowed {
                child.kill().ok();
                let _ = child.wait();
                break Some(Death::TimedOut);
            }
            std::thread::sleep(POLL);
        };
        if verbose {
            // What the child logged as it went (-v), after it.
            eprint!("{}", std::fs::read_to_string(&scratch.stderr).unwrap_or_default());
        }
        let Some(death) = death else { break };
        let stderr_tail = log_tail(&scratch.stderr, 12);
        let Some(report) = report.as_mut() else {
            // The child never opened its device: an input or setup error, in its own words.
            bail!(
                "{}",
                if stderr_tail.is_empty() {
                    "the case child ended before opening a device".into()
                } else {
                    stderr_tail
                }
            );
        };
        if let Death::Status(status) = &death {
            if status.code() == Some(2) {
                // The child's own error (a device it could not reopen): what ran is kept.
                for sink in sinks.iter_mut() {
                    sink.finish(report)?;
                }
                bail!("{stderr_tail}");
            }
        }
        let Some(run) = runs.get(done) else { break };
        let stderr_whole = std::fs::read_to_string(&scratch.stderr).unwrap_or_default();
        let death = DeathReport { death, message: last_message(&stderr_whole), stderr_tail };
        let record = death_record(run, &death, &report.adapter, supervision);
        for sink in sinks.iter_mut() {
            sink.record(&record)?;
        }
        report.cases.push(record);
        done += 1;
    }
    let report = report.context("no case ran")?;
    for sink in sinks.iter_mut() {
        sink.finish(&report)?;
    }
    Ok(report)
}

fn start_child(program: &Path, arguments: &[OsString], scratch: &Scratch, skip: usize) -> Result<Child> {
    let stderr = std::fs::File::create(&scratch.stderr)
        .with_context(|| format!("creating {} for the case child's errors", scratch.stderr.display()))?;
    Command::new(program)
        .args(arguments)
        .arg(CHILD_STREAM)
        .arg(&scratch.stream)
        .arg(CHILD_SKIP)
        .arg(skip.to_string())
        .stdin(Stdio::null())
        .stdout(Stdio::null())
        .stderr(stderr)
        .spawn()
        .with_context(|| format!("starting {} for the cases", program.display()))
}

/// The supervised child's side: opens the device `selector` names and runs `runs` from case run
/// `skip` on, streaming each record into `stream` for the parent.
pub fn run_child(
    selector: &AdapterSelector,
    runs: &[CaseRun],
    skip: usize,
    options: &RunOptions,
    stream: &Path,
) -> Result<()> {
    let gpu = Gpu::open(selector)?;
    let runs = &runs[skip.min(runs.len())..];
    for planned in runs {
        check_sizes(gpu.device.limits().max_texture_dimension_2d, &[planned.case], &planned.overrides)?;
    }
    let mut sink = StreamSink::create(stream)?;
    run(gpu, runs, options, &mut [&mut sink])?;
    Ok(())
}

/// A child's death and what its stderr said.
struct DeathReport {
    death: Death,
    /// The line that says what happened (`last_message`).
    message: String,
    /// The last lines, kept in the record's diagnostics.
    stderr_tail: String,
}

/// The last line a dying process wrote before its backtrace (RUST_BACKTRACE), or its last line.
fn last_message(stderr: &str) -> String {
    let before_backtrace = stderr.rsplit_once("stack backtrace:").map_or(stderr, |(before, _)| before);
    before_backtrace.lines().rev().find(|l| !l.trim().is_empty()).unwrap_or("(nothing on stderr)").to_owned()
}

/// The record of the case a child died in: `crash` or `timeout`, or `known_issue` where the
/// expectations list that death for this adapter.
fn death_record(
    run: &CaseRun,
    report: &DeathReport,
    adapter: &AdapterDescription,
    supervision: &Supervision,
) -> CaseRecord {
    let Supervision { command, expectations, timeout, .. } = supervision;
    let DeathReport { death, message: last_error, stderr_tail } = report;
    let (outcome, what) = match death {
        Death::Status(status) => {
            let how = if status.code().is_some() {
                format!("ended ({}) before recording it", ending(status))
            } else {
                format!("was {}", ending(status))
            };
            (ReportedOutcome::Crash, format!("crash: the process running the case {how}"))
        }
        Death::TimedOut => (
            ReportedOutcome::Timeout,
            format!(
                "timeout: no record for {} s ({}); the process running the case was killed",
                timeout.of(run.case).as_secs(),
                timeout.origin(run.case)
            ),
        ),
    };
    // One problem (the expectations split a failure at "; "), so a known issue can match it.
    let why = format!("{what} (stderr ends: {last_error})");
    let (outcome, reason) = match expectations.explain(run.case.name, adapter, &why) {
        Some(known) => {
            let reasons: Vec<&str> = known.iter().map(|k| k.reason.as_str()).collect();
            (ReportedOutcome::KnownIssue, format!("{why} [known: {}]", reasons.join(" | ")))
        }
        _ => (
            outcome,
            format!(
                "{why} [reproduce: {} --backend {}]",
                reproduce_line(command, run.case, &run.overrides),
                adapter.backend
            ),
        ),
    };
    let params =
        Params::resolve(run.case.name, run.case.params, &run.overrides).map(|p| p.to_map()).unwrap_or_default();
    CaseRecord {
        params,
        diagnostics: stderr_tail.lines().map(str::to_owned).collect(),
        ..CaseRecord::unmeasured(run.case.name, outcome, &reason)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A case's timeout is ten times its budget with 30 s as the floor, or the one given.
    #[test]
    fn a_cases_timeout_is_ten_budgets_and_never_under_the_floor() {
        let budget = |budget_s| Case { budget_s, ..Case::passing("kit.a") };
        let of = |timeout: CaseTimeout, budget_s| timeout.of(&budget(budget_s)).as_secs();
        assert_eq!([1, 3, 4, 60].map(|b| of(CaseTimeout::FromBudget, b)), [30, 30, 40, 600]);
        assert_eq!(of(CaseTimeout::Fixed(Duration::from_secs(7)), 60), 7);
        assert_eq!(CaseTimeout::FromBudget.origin(&budget(4)), "10× the case's budget of 4 s, at least 30 s");
    }

    /// A killed parent leaves its stream behind; a new parent with its process id starts empty.
    #[test]
    fn a_stream_left_by_a_dead_process_with_the_same_id_is_not_read() {
        let stale = std::env::temp_dir().join(format!("fragkit-child-{}.stream", std::process::id()));
        let start = StreamLine::Start { adapter: AdapterDescription::default(), runs: 1 };
        std::fs::write(&stale, serde_json::to_string(&start).unwrap() + "\n").unwrap();
        let scratch = Scratch::new().unwrap();
        let (lines, _) = read_new_lines(&scratch.stream, 0).unwrap();
        assert!(lines.is_empty(), "{} records from a dead process", lines.len());
    }
}
