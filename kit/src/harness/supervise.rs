//! Cases run in child processes, as deqp-runner runs its case lists: a driver that aborts, a
//! shader that never ends or a process killed from outside costs one case, not the run. Each
//! child (this program again, with `--child-stream FILE`) opens its device, says which it is, and
//! runs the case runs its parent hands it on stdin, streaming each record; `jobs` children run at
//! once, each handed the next case run as it frees up (the timed cases run alone: `case_lock`).
//! The parent hands the records to its sinks in the list's order, records the case a child died
//! in as `crash` (or `timeout`, when no record came within the case's time and the parent killed
//! it: `CaseTimeout`) and starts a new child in its place, so every output holds every case.
//! Before any case runs it holds the adapter to what the run expects and records the case runs a
//! skip list names `skip`; after `max_fails` unexpected failures the rest are `not_run`.

use std::collections::{BTreeMap, VecDeque};
use std::ffi::OsString;
use std::io::Write;
use std::path::{Path, PathBuf};
use std::process::{Child, ChildStdin, Command, ExitStatus, Stdio};
use std::time::{Duration, Instant};

use anyhow::{Context, Result, bail};
use fragkit_report::AdapterDescription;
use fragkit_report::expectations::Expectations;
use fragkit_report::param_value::ParamValue;
use fragkit_report::readable::counted;
use fragkit_report::report::{CaseRecord, Report, ReportedOutcome, run_name};
use fragkit_report::sink::Sink;
use fragkit_report::skips::SkipList;

use super::case::Case;
use super::child_process::{ending, log_tail};
use super::params::Params;
use super::reproduce::Reproduction;
use super::run::{CaseRun, RunOptions, run};
use super::runner::check_sizes;
use super::stream::{StreamLine, StreamSink, read_new_lines};
use crate::gpu::{AdapterSelector, Gpu};

/// How often the parent looks for new records and children's ends.
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
            Self::FromBudget => SHORTEST.max(Duration::from_secs(u64::from(BUDGET_FACTOR) * u64::from(case.budget_s))),
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

/// Files of one child, removed when it ends.
struct Scratch {
    stream: PathBuf,
    stderr: PathBuf,
}

impl Scratch {
    /// Named by this process's id and the child's number, and emptied: a process killed before
    /// it could remove its files leaves them behind, and a later one given the same id must not
    /// read its records.
    fn new(child: usize) -> Result<Self> {
        let base = std::env::temp_dir().join(format!("fragkit-child-{}-{child}", std::process::id()));
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

/// How a child ended while it ran a case.
enum Death {
    Status(ExitStatus),
    TimedOut,
}

/// How a supervisor starts its children and judges their deaths.
pub struct Supervision<'a> {
    /// The child's command line after the program: the parent's own, less what only the parent
    /// writes. The child is this program (`std::env::current_exe`), given `arguments` and then
    /// [`CHILD_STREAM`] FILE, and must answer them with [`run_child`].
    pub arguments: Vec<OsString>,
    /// How to run one case again where it ran, for the reproduce lines of deaths.
    pub reproduction: &'a Reproduction,
    pub expectations: &'a Expectations,
    pub timeout: CaseTimeout,
    /// Echo what each child logged, after it.
    pub verbose: bool,
    /// How many children run cases at once (`--jobs`; at least 1).
    pub jobs: usize,
    /// The case runs left out on this adapter (`--skips`, `--exclude`), recorded `skip`.
    pub skips: &'a SkipList,
    /// After this many unexpected failures no case starts; the rest are recorded `not_run`.
    pub max_fails: Option<usize>,
    /// Whether a flaky case counts as an unexpected failure.
    pub flaky_fails: bool,
    /// Judges the adapter the first child opened, before any case runs (`--expect-adapter`): an
    /// error ends the run.
    pub accept_adapter: &'a dyn Fn(&AdapterDescription) -> Result<()>,
    /// What an interrupted run of this list recorded (`--resume`): those case runs keep their
    /// records and do not run again. Each must be a case run of the list.
    pub recorded: &'a [CaseRecord],
}

/// The flag that makes a program a supervised child: stream each record into this file, and
/// run the case runs whose indices come on stdin, one a line.
pub const CHILD_STREAM: &str = "--child-stream";

/// A child process and where it stands.
struct Worker {
    child: Child,
    /// Where the parent writes the next case run's index; None once closed.
    stdin: Option<ChildStdin>,
    scratch: Scratch,
    /// How far its stream has been read.
    offset: u64,
    started: Instant,
    /// It has opened its device (its stream's first line).
    opened: bool,
    /// The case run it was handed and since when it runs (None while it waits for the case
    /// lock: its clock stops).
    busy: Option<(usize, Option<Instant>)>,
}

impl Worker {
    fn start(program: &Path, arguments: &[OsString], number: usize) -> Result<Self> {
        let scratch = Scratch::new(number)?;
        let stderr = std::fs::File::create(&scratch.stderr)
            .with_context(|| format!("creating {} for the case child's errors", scratch.stderr.display()))?;
        let mut child = Command::new(program)
            .args(arguments)
            .arg(CHILD_STREAM)
            .arg(&scratch.stream)
            .stdin(Stdio::piped())
            .stdout(Stdio::null())
            .stderr(stderr)
            .spawn()
            .with_context(|| format!("starting {} for the cases", program.display()))?;
        let stdin = child.stdin.take();
        Ok(Self { child, stdin, scratch, offset: 0, started: Instant::now(), opened: false, busy: None })
    }

    /// Hands it case run `index`; false where it can no longer take one (it died).
    fn hand(&mut self, index: usize) -> bool {
        let Some(stdin) = self.stdin.as_mut() else { return false };
        if writeln!(stdin, "{index}").and_then(|()| stdin.flush()).is_err() {
            return false;
        }
        self.busy = Some((index, Some(Instant::now())));
        true
    }
}

impl Drop for Worker {
    fn drop(&mut self) {
        // A run that ends on an error leaves no child behind.
        self.child.kill().ok();
        let _ = self.child.wait();
    }
}

/// A supervised run in progress: the case runs' records as they come, handed to the sinks in
/// the list's order.
struct Schedule<'r, 'c> {
    runs: &'r [CaseRun<'c>],
    records: Vec<Option<CaseRecord>>,
    /// The case runs no child has been handed yet, in order.
    pending: VecDeque<usize>,
    /// How many records (a prefix of the list) the sinks have.
    delivered: usize,
    unexpected: usize,
    report: Option<Report>,
}

impl Schedule<'_, '_> {
    /// The first child opened `adapter`: judge it, skip what the skip lists name there, start the
    /// sinks.
    fn open(
        &mut self,
        adapter: AdapterDescription,
        supervision: &Supervision,
        sinks: &mut [&mut dyn Sink],
    ) -> Result<()> {
        (supervision.accept_adapter)(&adapter)?;
        let mut recorded: BTreeMap<String, &CaseRecord> =
            supervision.recorded.iter().map(|record| (record.run_name(), record)).collect();
        for (index, run) in self.runs.iter().enumerate() {
            let skipped = supervision.skips.reason(run.case.name, &adapter);
            let key = run_name(run.case.name, &resolved_params(run));
            self.records[index] = match (recorded.remove(&key), skipped) {
                (Some(record), _) => Some(record.clone()),
                (None, Some(reason)) => Some(unrun(run, ReportedOutcome::Skip, &format!("skipped: {reason}"))),
                (None, None) => {
                    self.pending.push_back(index);
                    None
                }
            };
        }
        if let Some(stray) = recorded.keys().next() {
            bail!(
                "the run to resume recorded {stray}, which this command line does not run ({} more like it): resume with the cases, --set, --sweep and --shard it ran with",
                recorded.len() - 1
            );
        }
        for sink in sinks.iter_mut() {
            sink.start(&adapter, self.runs.len())?;
        }
        self.report = Some(Report { adapter, cases: Vec::new(), diagnostics: Vec::new(), shard: None, run: None });
        Ok(())
    }

    /// Files case run `index`'s record; past `max_fails` unexpected failures, the case runs not
    /// yet handed out are recorded `not_run`.
    fn file(&mut self, index: usize, record: CaseRecord, supervision: &Supervision) {
        if record.outcome.is_failure(supervision.flaky_fails) {
            self.unexpected += 1;
        }
        self.records[index] = Some(record);
        if let Some(limit) = supervision.max_fails.filter(|&limit| self.unexpected >= limit) {
            let why = format!(
                "not run: the run stopped after {} (--max-fails {limit})",
                counted(self.unexpected, "unexpected failure", "unexpected failures")
            );
            for index in std::mem::take(&mut self.pending) {
                self.records[index] = Some(unrun(&self.runs[index], ReportedOutcome::NotRun, &why));
            }
        }
    }

    /// Hands the sinks every record that now follows the ones they have, in the list's order.
    fn deliver(&mut self, sinks: &mut [&mut dyn Sink]) -> Result<()> {
        let Some(report) = self.report.as_mut() else { return Ok(()) };
        while let Some(Some(record)) = self.records.get_mut(self.delivered).map(Option::take) {
            for sink in sinks.iter_mut() {
                sink.record(&record)?;
            }
            report.cases.push(record);
            self.delivered += 1;
        }
        Ok(())
    }

    fn complete(&self) -> bool {
        self.report.is_some() && self.delivered == self.runs.len()
    }

    /// Ends the sinks with what ran (also on an error that stops the run).
    fn finish(&mut self, sinks: &mut [&mut dyn Sink]) -> Result<Report> {
        let report = self.report.take().context("no case ran")?;
        for sink in sinks.iter_mut() {
            sink.finish(&report)?;
        }
        Ok(report)
    }
}

/// A case run's parameters, resolved as its record holds them (none where they do not resolve:
/// the run itself then fails on them).
fn resolved_params(run: &CaseRun) -> BTreeMap<String, ParamValue> {
    Params::resolve(run.case.name, run.case.params, &run.overrides).map(|p| p.to_map()).unwrap_or_default()
}

/// The record of a case run that did not run, with its parameters.
fn unrun(run: &CaseRun, outcome: ReportedOutcome, reason: &str) -> CaseRecord {
    CaseRecord { params: resolved_params(run), ..CaseRecord::unmeasured(run.case.name, outcome, reason) }
}

/// Runs `runs` in children of this program, `supervision.jobs` at once, handing every record to
/// `sinks` in the list's order; returns the report. A child that dies (a signal, an abort, an
/// exit before recording) or goes quiet past its case's timeout costs that case alone: it is
/// recorded `crash` or `timeout` (or `known_issue`, where the expectations list that death) and
/// a new child takes its place.
pub fn supervise(runs: &[CaseRun], supervision: &Supervision, sinks: &mut [&mut dyn Sink]) -> Result<Report> {
    let program = std::env::current_exe().context("finding this program to run the cases in a child")?;
    let mut schedule = Schedule {
        runs,
        records: vec![None; runs.len()],
        pending: VecDeque::new(),
        delivered: 0,
        unexpected: 0,
        report: None,
    };
    let mut started = 1;
    let mut workers = vec![Worker::start(&program, &supervision.arguments, 0)?];
    let mut diagnostics = Vec::new();
    while !schedule.complete() {
        let mut index = 0;
        while index < workers.len() {
            let ended = watch(&mut workers[index], &mut schedule, supervision, sinks, &mut diagnostics);
            match ended {
                Ok(false) => index += 1,
                Ok(true) => {
                    let worker = workers.swap_remove(index);
                    if supervision.verbose {
                        // What the child logged as it went (-v), after it.
                        eprint!("{}", std::fs::read_to_string(&worker.scratch.stderr).unwrap_or_default());
                    }
                }
                Err(e) => {
                    // What ran is kept: the sinks end with it.
                    if schedule.report.is_some() {
                        schedule.deliver(sinks)?;
                        schedule.finish(sinks)?;
                    }
                    return Err(e);
                }
            }
        }
        schedule.deliver(sinks)?;
        if schedule.report.is_some() {
            for worker in workers.iter_mut().filter(|w| w.opened && w.busy.is_none()) {
                let Some(next) = schedule.pending.pop_front() else { break };
                if !worker.hand(next) {
                    schedule.pending.push_front(next);
                }
            }
            let busy = workers.iter().filter(|w| w.busy.is_some()).count();
            if another_child_wanted(workers.len(), busy, schedule.pending.len(), supervision.jobs) {
                workers.push(Worker::start(&program, &supervision.arguments, started)?);
                started += 1;
            }
        }
        if !schedule.complete() {
            std::thread::sleep(POLL);
        }
    }
    // Every case run is recorded: each child, told there is no more, ends with its diagnostics.
    for worker in &mut workers {
        worker.stdin = None;
    }
    for mut worker in workers {
        let deadline = Instant::now() + SHORTEST;
        while worker.child.try_wait().ok().flatten().is_none() && Instant::now() < deadline {
            std::thread::sleep(POLL);
        }
        let (lines, _) = read_new_lines(&worker.scratch.stream, worker.offset)?;
        for line in lines {
            if let StreamLine::Finished { diagnostics: logged } = line {
                diagnostics.extend(logged);
            }
        }
        if supervision.verbose {
            eprint!("{}", std::fs::read_to_string(&worker.scratch.stderr).unwrap_or_default());
        }
    }
    if let Some(report) = schedule.report.as_mut() {
        report.diagnostics = diagnostics;
    }
    schedule.finish(sinks)
}

/// Whether to start one more child: fewer run than `jobs` (at least one), and fewer than the
/// case runs busy or pending need (so a pending run finds no child idle or opening to take it).
fn another_child_wanted(children: usize, busy: usize, pending: usize, jobs: usize) -> bool {
    children < jobs.max(1).min(busy + pending)
}

/// Whether a live child is out of time at `now`: the case run it was handed (`busy`: its index
/// and since when its clock runs, None while it waits for the case lock) has gone past that
/// case's timeout, or it has not opened its device within `SHORTEST` of its start.
fn out_of_time(
    busy: Option<(usize, Option<Instant>)>,
    opened: bool,
    started: Instant,
    runs: &[CaseRun],
    timeout: CaseTimeout,
    now: Instant,
) -> bool {
    match busy {
        Some((index, Some(since))) => now - since > timeout.of(runs[index].case),
        Some((_, None)) => false,
        None => !opened && now - started > SHORTEST,
    }
}

/// Reads what `worker` streamed and sees whether it died or ran out of time; true when it is
/// gone (a case it ran recorded as its death).
fn watch(
    worker: &mut Worker,
    schedule: &mut Schedule,
    supervision: &Supervision,
    sinks: &mut [&mut dyn Sink],
    diagnostics: &mut Vec<String>,
) -> Result<bool> {
    let exited = worker.child.try_wait().context("waiting for the case child")?;
    let (lines, next) = read_new_lines(&worker.scratch.stream, worker.offset)?;
    worker.offset = next;
    for line in lines {
        match line {
            StreamLine::Start { adapter, .. } => {
                worker.opened = true;
                if schedule.report.is_none() {
                    schedule.open(adapter, supervision, sinks)?;
                }
            }
            StreamLine::Waiting(waiting) => {
                if let Some((_, clock)) = worker.busy.as_mut() {
                    *clock = (!waiting).then(Instant::now);
                }
            }
            StreamLine::Record(record) => {
                let (index, _) = worker.busy.take().context("a case child recorded a case it was not handed")?;
                schedule.file(index, *record, supervision);
            }
            StreamLine::Finished { diagnostics: logged } => diagnostics.extend(logged),
        }
    }
    let death = match exited {
        Some(status) => Death::Status(status),
        None => {
            let now = Instant::now();
            if !out_of_time(worker.busy, worker.opened, worker.started, schedule.runs, supervision.timeout, now) {
                return Ok(false);
            }
            worker.child.kill().ok();
            let _ = worker.child.wait();
            Death::TimedOut
        }
    };
    let stderr_tail = log_tail(&worker.scratch.stderr, 12);
    let Some((index, _)) = worker.busy else {
        if worker.opened {
            // Idle when it ended: no case is lost.
            return Ok(true);
        }
        // It never opened a device: an input or setup error, in its own words.
        bail!(
            "{}",
            match (&death, stderr_tail.is_empty()) {
                (Death::TimedOut, _) => format!("the case child opened no device within {} s", SHORTEST.as_secs()),
                (_, true) => "the case child ended before opening a device".to_owned(),
                (_, false) => stderr_tail,
            }
        );
    };
    if let Death::Status(status) = &death
        && status.code() == Some(2)
    {
        // The child's own error (a device it could not reopen): what ran is kept.
        bail!("{stderr_tail}");
    }
    let adapter = schedule.report.as_ref().map(|r| r.adapter.clone()).unwrap_or_default();
    let stderr_whole = std::fs::read_to_string(&worker.scratch.stderr).unwrap_or_default();
    let death = DeathReport { death, message: last_message(&stderr_whole), stderr_tail };
    let record = death_record(&schedule.runs[index], &death, &adapter, supervision);
    schedule.file(index, record, supervision);
    Ok(true)
}

/// The supervised child's side: opens the device `selector` names, checks every case run fits
/// it, then runs the case runs whose indices come on stdin (one a line, until it closes),
/// streaming each record into `stream` for the parent.
pub fn run_child(selector: &AdapterSelector, runs: &[CaseRun], options: &RunOptions, stream: &Path) -> Result<()> {
    let gpu = Gpu::open(selector)?;
    for planned in runs {
        check_sizes(gpu.device.limits().max_texture_dimension_2d, &[planned.case], &planned.overrides)?;
    }
    let mut sink = StreamSink::create(stream)?;
    let handed = std::io::stdin()
        .lines()
        .map_while(|line| line.ok()?.trim().parse::<usize>().ok())
        .map_while(|index| runs.get(index));
    run(gpu, handed, runs.len(), options, &mut [&mut sink])?;
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
    let Supervision { reproduction, expectations, timeout, .. } = supervision;
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
        _ => (outcome, format!("{why} [reproduce: {}]", reproduction.line(run.case, &run.overrides, &adapter.backend))),
    };
    CaseRecord {
        params: resolved_params(run),
        diagnostics: stderr_tail.lines().map(str::to_owned).collect(),
        ..CaseRecord::unmeasured(run.case.name, outcome, &reason)
    }
}

#[cfg(test)]
mod tests {
    use super::super::params::{ParamKind, ParamSpec};
    use super::*;

    /// What a sink was handed: the runs it was told of, then each record's run name and outcome.
    #[derive(Default)]
    struct Handed {
        runs: Option<usize>,
        records: Vec<(String, ReportedOutcome)>,
    }

    impl Sink for Handed {
        fn start(&mut self, _adapter: &AdapterDescription, runs: usize) -> Result<()> {
            self.runs = Some(runs);
            Ok(())
        }
        fn record(&mut self, record: &CaseRecord) -> Result<()> {
            self.records.push((record.run_name(), record.outcome));
            Ok(())
        }
        fn finish(&mut self, _report: &Report) -> Result<()> {
            Ok(())
        }
    }

    fn accept_any(_: &AdapterDescription) -> Result<()> {
        Ok(())
    }

    /// A supervision of one job with timeouts from the budgets, no stop on failures, any adapter.
    fn plain_supervision<'a>(
        reproduction: &'a Reproduction,
        expectations: &'a Expectations,
        skips: &'a SkipList,
        recorded: &'a [CaseRecord],
    ) -> Supervision<'a> {
        Supervision {
            arguments: Vec::new(),
            reproduction,
            expectations,
            timeout: CaseTimeout::FromBudget,
            verbose: false,
            jobs: 1,
            skips,
            max_fails: None,
            flaky_fails: false,
            accept_adapter: &accept_any,
            recorded,
        }
    }

    const SIZED: &[ParamSpec] = &[ParamSpec { name: "size", kind: ParamKind::Size, default: "8x4", help: "" }];

    /// The schedule of four case runs — a, b (the skip list names it), c (recorded by the run
    /// being resumed) and d, with a parameter — records b `skip` and keeps c's record when the
    /// adapter opens, leaving a and d to hand out; records reach the sinks in the list's order,
    /// each once, only as the ones before them arrive; past `max_fails` unexpected failures the
    /// runs not yet handed out are `not_run`.
    #[test]
    fn the_schedule_skips_resumes_delivers_in_order_and_stops_after_max_fails() {
        use ReportedOutcome::{Fail, NotRun, Pass, Skip};
        let (a, b, c) = (Case::passing("kit.a"), Case::passing("kit.b"), Case::passing("kit.c"));
        let d = Case { params: SIZED, ..Case::passing("kit.d") };
        let runs: Vec<CaseRun> =
            [&a, &b, &c, &d].into_iter().map(|case| CaseRun { case, overrides: BTreeMap::new() }).collect();
        let skips = SkipList::parse("kit.b  # flaky here", "skips.txt").unwrap();
        let recorded = [CaseRecord::unmeasured("kit.c", Pass, "earlier")];
        let reproduction = Reproduction::new("fragkit check", &AdapterSelector::default(), Vec::new());
        let expectations = Expectations::default();
        let supervision =
            |max_fails| Supervision { max_fails, ..plain_supervision(&reproduction, &expectations, &skips, &recorded) };
        let schedule = || Schedule {
            runs: &runs,
            records: vec![None; runs.len()],
            pending: VecDeque::new(),
            delivered: 0,
            unexpected: 0,
            report: None,
        };
        let record = |name: &str, outcome| CaseRecord::unmeasured(name, outcome, "");

        // Two failures allowed: d's pass waits for a's record, then all four go, in order.
        let two = supervision(Some(2));
        let (mut running, mut sink) = (schedule(), Handed::default());
        assert!(!running.complete());
        running.open(AdapterDescription::default(), &two, &mut [&mut sink]).unwrap();
        assert_eq!(sink.runs, Some(4));
        assert_eq!(running.pending, [0, 3]);
        running.deliver(&mut [&mut sink]).unwrap();
        assert!(sink.records.is_empty() && !running.complete());
        running.file(3, CaseRecord { params: resolved_params(&runs[3]), ..record("kit.d", Pass) }, &two);
        running.deliver(&mut [&mut sink]).unwrap();
        assert!(sink.records.is_empty() && !running.complete(), "d went before a");
        running.file(0, record("kit.a", Fail), &two);
        assert_eq!(running.unexpected, 1);
        running.deliver(&mut [&mut sink]).unwrap();
        running.deliver(&mut [&mut sink]).unwrap();
        let expected = [("kit.a", Fail), ("kit.b", Skip), ("kit.c", Pass), ("kit.d [size=[[8,4]]]", Pass)];
        assert_eq!(sink.records, expected.map(|(name, outcome)| (name.to_owned(), outcome)));
        assert!(running.complete());
        assert_eq!(running.finish(&mut [&mut sink]).unwrap().cases.len(), 4);

        // One failure allowed: a's stops the run, d (not yet handed out) is not_run, with its
        // parameters.
        let one = supervision(Some(1));
        let (mut stopped, mut sink) = (schedule(), Handed::default());
        stopped.open(AdapterDescription::default(), &one, &mut [&mut sink]).unwrap();
        stopped.pending.pop_front();
        stopped.file(0, record("kit.a", Fail), &one);
        stopped.deliver(&mut [&mut sink]).unwrap();
        assert_eq!(sink.records.last(), Some(&("kit.d [size=[[8,4]]]".to_owned(), NotRun)));
        assert!(stopped.complete());
        let reason = &stopped.finish(&mut []).unwrap().cases[3].reason;
        assert_eq!(reason, "not run: the run stopped after 1 unexpected failure (--max-fails 1)");

        // A resumed record of a run this list does not hold is refused; so is an adapter the
        // run does not accept.
        let stray = [CaseRecord::unmeasured("kit.e", Pass, "")];
        let refuse = |_: &AdapterDescription| -> Result<()> { bail!("not the promised adapter") };
        let with_stray = Supervision { recorded: &stray, ..supervision(None) };
        assert!(schedule().open(AdapterDescription::default(), &with_stray, &mut []).is_err());
        let refusing = Supervision { accept_adapter: &refuse, ..supervision(None) };
        assert!(schedule().open(AdapterDescription::default(), &refusing, &mut []).is_err());
    }

    /// Read plainly: another child starts while fewer run than `jobs` (at least one) and some
    /// pending case run finds no child idle or opening to take it.
    #[test]
    fn another_child_starts_only_for_a_pending_run_no_child_can_take_within_jobs() {
        for jobs in 0..5 {
            for children in 0..6 {
                for busy in 0..=children {
                    for pending in 0..6 {
                        let plain = children < jobs.max(1) && pending > children - busy;
                        assert_eq!(
                            another_child_wanted(children, busy, pending, jobs),
                            plain,
                            "{children} children, {busy} busy, {pending} pending, --jobs {jobs}"
                        );
                    }
                }
            }
        }
        assert!(another_child_wanted(1, 1, 3, 2), "one busy child, three pending, two jobs");
        assert!(!another_child_wanted(1, 0, 1, 2), "the one pending run waits for the opening child");
    }

    /// A child runs out of time by the timeout of the case it runs (not another's), its clock
    /// stopped while it waits for the case lock; one never handed a case, when it has not opened
    /// its device within 30 s.
    #[test]
    fn a_child_is_out_of_time_by_its_own_cases_timeout_or_before_opening() {
        let quick = Case { budget_s: 1, ..Case::passing("kit.quick") };
        let slow = Case { budget_s: 60, ..Case::passing("kit.slow") };
        let runs = [&quick, &slow].map(|case| CaseRun { case, overrides: BTreeMap::new() });
        let start = Instant::now();
        let at = |seconds| start + Duration::from_secs(seconds);
        let timeout = CaseTimeout::FromBudget;
        let out = |busy, opened, now| out_of_time(busy, opened, start, &runs, timeout, now);
        assert!(out(Some((0, Some(start))), true, at(31)), "the quick case's 30 s");
        assert!(!out(Some((0, Some(start))), true, at(30)), "at its 30 s");
        assert!(!out(Some((1, Some(start))), true, at(31)), "the slow case has 600 s");
        assert!(out(Some((1, Some(start))), true, at(601)));
        assert!(!out(Some((1, Some(at(500)))), true, at(601)), "its clock started at 500 s");
        assert!(!out(Some((0, None)), true, at(10_000)), "waiting for the case lock");
        assert!(out(None, false, at(31)) && !out(None, false, at(30)), "not opened");
        assert!(!out(None, true, at(10_000)), "idle");
        let fixed =
            out_of_time(Some((1, Some(start))), true, start, &runs, CaseTimeout::Fixed(Duration::from_secs(5)), at(6));
        assert!(fixed, "--timeout 5");
    }

    /// The line a dying process wrote last, before its backtrace and blank lines.
    #[test]
    fn a_deaths_message_is_the_last_line_before_the_backtrace() {
        let stderr = "opening lavapipe\npanicked at src/a.rs:1: index out of range\n\nstack backtrace:\n  0: main\n";
        assert_eq!(last_message(stderr), "panicked at src/a.rs:1: index out of range");
        assert_eq!(last_message("one\ntwo\n  \n"), "two");
        assert_eq!(last_message(""), "(nothing on stderr)");
    }

    /// A death's record: `crash` with how the process ended, or `timeout` with the case's own
    /// timeout and where it came from, each with its message and reproduce line, the run's
    /// parameters and the stderr tail as diagnostics; `known_issue` where the expectations list
    /// that death on this adapter.
    #[test]
    fn a_deaths_record_says_how_the_child_ended_and_keeps_its_parameters_and_stderr() {
        use std::os::unix::process::ExitStatusExt;
        let case = Case { params: SIZED, budget_s: 4, ..Case::passing("kit.dies") };
        let run = CaseRun { case: &case, overrides: BTreeMap::from([("size".to_owned(), "2x2".to_owned())]) };
        let reproduction = Reproduction::new("fragkit check", &AdapterSelector::default(), Vec::new());
        let expectations = Expectations::parse(
            "[[known_issue]]\ncase = \"kit.dies\"\nadapter = \"swift*\"\nfailure = \"crash: *\"\nreason = \"driver: it aborts\"\n",
            "test",
        )
        .unwrap();
        let skips = SkipList::default();
        let supervision = plain_supervision(&reproduction, &expectations, &skips, &[]);
        let adapter =
            |name: &str| AdapterDescription { name: name.into(), backend: "vulkan".into(), ..Default::default() };
        let death = |death| DeathReport { death, message: "boom".into(), stderr_tail: "a\nboom".into() };

        let killed =
            death_record(&run, &death(Death::Status(ExitStatus::from_raw(9))), &adapter("llvmpipe"), &supervision);
        assert_eq!(killed.outcome, ReportedOutcome::Crash);
        assert!(
            killed.reason.starts_with("crash: the process running the case was killed by signal 9 (SIGKILL) (stderr ends: boom) [reproduce: fragkit check kit.dies --set size=2x2 --backend vulkan]"),
            "{}",
            killed.reason
        );
        assert_eq!(killed.params, resolved_params(&run));
        assert_eq!(killed.diagnostics, ["a", "boom"]);
        let exited =
            death_record(&run, &death(Death::Status(ExitStatus::from_raw(3 << 8))), &adapter("llvmpipe"), &supervision);
        assert!(
            exited.reason.starts_with("crash: the process running the case ended (exit 3) before recording it"),
            "{}",
            exited.reason
        );
        let timed_out = death_record(&run, &death(Death::TimedOut), &adapter("llvmpipe"), &supervision);
        assert_eq!(timed_out.outcome, ReportedOutcome::Timeout);
        assert!(
            timed_out.reason.starts_with("timeout: no record for 40 s (10× the case's budget of 4 s, at least 30 s); the process running the case was killed (stderr ends: boom)"),
            "{}",
            timed_out.reason
        );
        let known =
            death_record(&run, &death(Death::Status(ExitStatus::from_raw(6))), &adapter("swiftshader"), &supervision);
        assert_eq!(known.outcome, ReportedOutcome::KnownIssue);
        assert!(known.reason.ends_with("[known: driver: it aborts]"), "{}", known.reason);
        let elsewhere = death_record(&run, &death(Death::TimedOut), &adapter("swiftshader"), &supervision);
        assert_eq!(elsewhere.outcome, ReportedOutcome::Timeout, "the entry lists crashes only");
    }

    /// A case's timeout is ten times its budget with 30 s as the floor, or the one given.
    #[test]
    fn a_cases_timeout_is_ten_budgets_and_never_under_the_floor() {
        let budget = |budget_s| Case { budget_s, ..Case::passing("kit.a") };
        let of = |timeout: CaseTimeout, budget_s| timeout.of(&budget(budget_s)).as_secs();
        assert_eq!([1, 3, 4, 60].map(|b| of(CaseTimeout::FromBudget, b)), [30, 30, 40, 600]);
        assert_eq!(of(CaseTimeout::Fixed(Duration::from_secs(7)), 60), 7);
        assert_eq!(CaseTimeout::FromBudget.origin(&budget(4)), "10× the case's budget of 4 s, at least 30 s");
    }

    proptest::proptest! {
        /// Against the definition read plainly, at any budget (no overflow at u32's top) and any
        /// fixed timeout: from the budget, ten budgets or 30 s, whichever is longer; fixed, the
        /// one given whatever the budget.
        #[test]
        fn a_cases_timeout_is_its_definition_at_any_budget(budget_s: u32, fixed_s: u64) {
            let case = Case { budget_s, ..Case::passing("kit.a") };
            let from_budget = CaseTimeout::FromBudget.of(&case).as_secs();
            proptest::prop_assert_eq!(from_budget, (10 * u64::from(budget_s)).max(30));
            proptest::prop_assert_eq!(CaseTimeout::Fixed(Duration::from_secs(fixed_s)).of(&case).as_secs(), fixed_s);
        }
    }

    /// A killed parent leaves its stream behind; a new parent with its process id starts empty.
    #[test]
    fn a_stream_left_by_a_dead_process_with_the_same_id_is_not_read() {
        let stale = std::env::temp_dir().join(format!("fragkit-child-{}-0.stream", std::process::id()));
        let start = StreamLine::Start { adapter: AdapterDescription::default(), runs: 1 };
        std::fs::write(&stale, serde_json::to_string(&start).unwrap() + "\n").unwrap();
        let scratch = Scratch::new(0).unwrap();
        let (lines, _) = read_new_lines(&scratch.stream, 0).unwrap();
        assert!(lines.is_empty(), "{} records from a dead process", lines.len());
    }
}
