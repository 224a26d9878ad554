//! `fragkit check`: run the selected cases (a sweep's draws, one shard's share) on one adapter and
//! hand every record to the sinks asked for: the table, the JSON report, JUnit XML, the HTML
//! report, the results database.

use std::collections::BTreeMap;
use std::ffi::OsString;
use std::path::{Path, PathBuf};
use std::process::ExitCode;

use anyhow::{Context, Result, bail};
use fragkit::gpu::AdapterSelector;
use fragkit::harness::Case;
use fragkit::harness::bug_report::{self, BugReports};
use fragkit::harness::child_process::{arguments_without, log_tail};
use fragkit::harness::params::parse_overrides;
use fragkit::harness::reproduce::Reproduction;
use fragkit::harness::run::{CaseRun, RunOptions, plan_runs};
use fragkit::harness::runner::{check_overrides, select};
use fragkit::harness::supervise::{CaseTimeout, Supervision, run_child, supervise};
use fragkit_report::AdapterDescription;
use fragkit_report::expectations::Expectations;
use fragkit_report::readable::counted;
use fragkit_report::report::{Report, ReportedOutcome};
use fragkit_report::run_info::{RunInfo, RunKind};
use fragkit_report::sink::{JsonSink, Shard, Sink, partial_path};
use fragkit_report::skips::SkipList;
use fragkit_report::summary::run_summary;
use fragkit_results::baseline::baseline;
use fragkit_results::database::{Database, DatabaseSink};
use fragkit_results::github::GithubSink;
use fragkit_results::html::{Column, HtmlSink, write_site};
use fragkit_results::junit::JunitSink;
use fragkit_results::snapshot::Snapshot;

use super::matrix::{ChildEnd, MatrixArgs, Show, check_selection_is_free, print_table, run_children};
use super::table::TableSink;

/// How many of the slowest case runs the end-of-run summary names.
const SLOWEST_SHOWN: usize = 5;

/// How to run one case of this kit on its own, for reproduce lines.
const COMMAND: &str = "fragkit check";

#[derive(clap::Args)]
pub struct CheckArgs {
    patterns: Vec<String>,
    /// Override a parameter: key=value.
    #[arg(long = "set", value_name = "KEY=VALUE")]
    sets: Vec<String>,
    /// Write the JSON report here.
    #[arg(long)]
    json: Option<PathBuf>,
    /// Write a JUnit XML report here (fail and unexpected_pass as failures; not_supported,
    /// known_issue, skip and not_run as skipped).
    #[arg(long)]
    junit: Option<PathBuf>,
    /// Write a browsable HTML report of this run into this folder (with --out, its evidence
    /// images side by side).
    #[arg(long)]
    html: Option<PathBuf>,
    /// Write evidence images into this folder.
    #[arg(long)]
    out: Option<PathBuf>,
    /// Known-issues file (default: the one built in, cases/expectations.toml).
    #[arg(long)]
    expectations: Option<PathBuf>,
    /// A baseline (`--write-baseline`) to judge the run against, beside the known issues: a
    /// failure it lists, of the kind it lists, is `known_issue`; repeatable.
    #[arg(long, value_name = "FILE")]
    baseline: Vec<PathBuf>,
    /// Write this run's failures as a baseline for later runs (`--baseline`).
    #[arg(long, value_name = "FILE")]
    write_baseline: Option<PathBuf>,
    /// Run again only the case runs this report (`--json`) counts as failures, each with the
    /// parameters it ran with.
    #[arg(long, value_name = "REPORT", conflicts_with_all = ["patterns", "sweep", "sets", "shard"])]
    rerun_failed: Option<PathBuf>,
    /// GitHub Actions outputs: an `::error` annotation per unexpected failure, and a markdown
    /// summary appended to `$GITHUB_STEP_SUMMARY`.
    #[arg(long)]
    github: bool,
    /// Run each case with N parameter sets drawn from its declared ranges (cases without
    /// ranges run once at their defaults); `--set` pins a parameter. Failures print the
    /// command that reproduces them.
    #[arg(long, value_name = "N", value_parser = clap::value_parser!(u32).range(1..=10_000))]
    sweep: Option<u32>,
    /// Seed of the sweep's draws.
    #[arg(long, default_value_t = 1, requires = "sweep")]
    seed: u64,
    /// Run only shard K of N (every N-th case run, from the K-th); `fragkit merge` joins the
    /// shards' JSON reports.
    #[arg(long, value_name = "K/N")]
    shard: Option<String>,
    /// Run a failed case again up to N times; one that then passes is reported `flaky`.
    #[arg(long, value_name = "N", default_value_t = 0, value_parser = clap::value_parser!(u32).range(0..=100))]
    retry: u32,
    /// Above 1: after each case's run (its verdict and warm-up, whose time is cold), run it N more
    /// times and record their GPU times (the median is reported), so that `fragkit compare`
    /// judges a time change against the noise.
    #[arg(long, value_name = "N", default_value_t = 1, value_parser = clap::value_parser!(u32).range(1..=1000))]
    repeat: u32,
    /// Count flaky cases as failures (exit 1).
    #[arg(long)]
    flaky_fails: bool,
    /// Record the run in this results database: an SQLite file (created where missing) or a
    /// postgres:// URL.
    #[arg(long)]
    db: Option<String>,
    /// Tag the recorded run (`fragkit compare tag:NAME …`).
    #[arg(long, requires = "db")]
    tag: Option<String>,
    /// Seconds any case may go without recording before its process is killed and the case
    /// recorded as `timeout` (default: each case's own, 10× its budget and at least 30 s).
    #[arg(long, value_name = "SECONDS", value_parser = clap::value_parser!(u64).range(1..))]
    timeout: Option<u64>,
    /// Run up to N cases at once, each child process handed the next case as it frees up (with
    /// --matrix: N configurations at once). Cases whose verdict rests on a measured time run
    /// alone. Verdicts are those of --jobs 1.
    #[arg(long, value_name = "N", default_value_t = 1, value_parser = clap::value_parser!(u32).range(1..=256))]
    jobs: u32,
    /// A skip list: a case glob a line, optionally scoped with backend=, adapter=, driver=,
    /// driver_info= globs; `#` comments give the reason (repeatable). Skipped cases are
    /// recorded `skip` with it.
    #[arg(long, value_name = "FILE")]
    skips: Vec<PathBuf>,
    /// Leave out the cases this glob names, recorded `skip` (repeatable).
    #[arg(long, value_name = "GLOB")]
    exclude: Vec<String>,
    /// Stop after N unexpected failures: the cases not yet started are recorded `not_run`.
    #[arg(long, value_name = "N", value_parser = clap::value_parser!(u32).range(1..))]
    max_fails: Option<u32>,
    /// Exit 2 before any case runs unless the adapter's name, driver or backend matches one of
    /// these globs (repeatable, or separated by commas): a runner whose driver failed to load
    /// must not test another adapter and pass.
    #[arg(long, value_name = "GLOB", value_delimiter = ',')]
    expect_adapter: Vec<String>,
    /// Continue an interrupted run: with --db, the newest interrupted check run there; else the
    /// report so far beside --json (`<json>.partial`). Give the command line it ran with: the case
    /// runs it recorded keep their records, the others run, and the run becomes complete.
    #[arg(long, conflicts_with = "rerun_failed")]
    resume: bool,
    /// Write a bug report into DIR/<case run>/ for each case run that does not pass: a README in
    /// the form driver trackers ask for, the evidence, the shaders (WGSL, and what the driver got),
    /// a capture of the case's own process (apitrace on GL) and a `replay` script that needs only
    /// the capture tool. With --matrix, DIR/<configuration>/<case run>/.
    #[arg(long, value_name = "DIR")]
    bug_report: Option<PathBuf>,
    /// With --bug-report: known issues get their report too.
    #[arg(long, requires = "bug_report")]
    bug_report_known: bool,
    /// Run as the child of a supervising `check`: stream each record into this file.
    #[arg(long, hide = true)]
    child_stream: Option<PathBuf>,
    /// Run as configuration NAME of a `check --matrix` (its parent sets its environment): the
    /// reproduce lines name the configuration.
    #[arg(long, hide = true, value_name = "NAME")]
    as_configuration: Option<String>,
    /// With --matrix: hold each configuration's outcomes and metrics (timings left out) to its
    /// snapshot, DIR/<name>.json (the repository's: snapshots/matrix); a departure fails the run.
    #[arg(long, value_name = "DIR", requires = "matrix")]
    snapshots: Option<PathBuf>,
    /// With --snapshots: write each configuration's snapshot from this run instead (case runs it
    /// did not run keep their entries).
    #[arg(long, requires = "snapshots")]
    update_snapshots: bool,
    #[command(flatten)]
    matrix: MatrixArgs,
}

/// How to run one case again where this run runs it: this process's driver environment and
/// adapter selection, or the matrix configuration it runs as (`--as-configuration`).
fn reproduction(selector: &AdapterSelector, args: &CheckArgs) -> Result<Reproduction> {
    let reproduction = Reproduction::of_process(COMMAND, selector);
    let Some(name) = &args.as_configuration else {
        return Ok(reproduction);
    };
    let matrix = args.matrix.load()?;
    let configuration = matrix.select(name)?[0];
    let mut flags = vec!["--matrix".to_owned(), name.clone()];
    if let Some(file) = &args.matrix.adapters_file {
        flags.extend(["--adapters-file".to_owned(), file.display().to_string()]);
    }
    Ok(reproduction.as_configuration(&flags, &configuration.env))
}

/// Fails now, not after the run, when an output file cannot be written.
fn check_writable(path: &Path) -> Result<()> {
    let probe = path.with_extension("probe.tmp");
    std::fs::write(&probe, b"").with_context(|| format!("the report path {} is not writable", path.display()))?;
    std::fs::remove_file(&probe).ok();
    Ok(())
}

pub fn check(selector: &AdapterSelector, args: CheckArgs, verbose: bool) -> Result<ExitCode> {
    // Check every input before touching the GPU.
    let cases = select(fragkit_cases::all(), &args.patterns)?;
    let overrides = parse_overrides(&args.sets)?;
    check_overrides(&cases, &overrides)?;
    let shard = args.shard.as_deref().map(Shard::parse).transpose()?;
    let mut expectations = match &args.expectations {
        Some(path) => Expectations::load(path)?,
        None => Expectations::parse(fragkit_cases::EXPECTATIONS, "cases/expectations.toml (built in)")?,
    };
    for path in &args.baseline {
        expectations.extend(Expectations::load(path)?);
    }
    let rerun = args.rerun_failed.as_deref().map(|path| failed_runs(path, args.flaky_fails)).transpose()?;
    let skips = skip_list(&args.skips, &args.exclude)?;
    for glob in &args.expect_adapter {
        glob::Pattern::new(glob).with_context(|| format!("--expect-adapter {glob:?} is not a glob"))?;
    }
    if let Some(dir) = &args.out {
        std::fs::create_dir_all(dir).with_context(|| format!("creating the evidence folder {}", dir.display()))?;
    }
    if let Some(dir) = &args.html {
        std::fs::create_dir_all(dir).with_context(|| format!("creating the HTML report folder {}", dir.display()))?;
    }
    for path in args.json.iter().chain(&args.junit).chain(&args.write_baseline) {
        check_writable(path)?;
    }
    if let Some(names) = args.matrix.matrix.clone() {
        return check_matrix(selector, &args, &names, &expectations);
    }
    let reproduction = reproduction(selector, &args)?;
    if let Some(stream) = &args.child_stream {
        let planned = planned_runs(&args, &cases, &overrides, shard, rerun.as_deref());
        let options = RunOptions {
            expectations: &expectations,
            evidence_dir: args.out.as_deref(),
            reproduction: Some(&reproduction),
            retries: args.retry,
            repeats: args.repeat,
        };
        run_child(selector, &planned, &options, stream)?;
        return Ok(ExitCode::SUCCESS);
    }
    // Open (and migrate) the database now: a wrong or newer one is refused before the run.
    let mut database = args.db.as_deref().map(Database::open).transpose()?;
    let resumed = args.resume.then(|| interrupted(&args, database.as_mut())).transpose()?;
    let runs = planned_runs(&args, &cases, &overrides, shard, rerun.as_deref());
    if runs.is_empty() {
        println!("nothing to run: the report holds no failures to run again");
        return Ok(ExitCode::SUCCESS);
    }
    if let Some(shard) = shard {
        println!("shard {}/{}: {} case runs", shard.index, shard.count, runs.len());
    }

    let mut table = TableSink::new(verbose);
    let info = match &resumed {
        Some((_, report)) => report.run.clone().unwrap_or_else(|| RunInfo::now(RunKind::Check, args.tag.clone())),
        None => RunInfo::now(RunKind::Check, args.tag.clone()),
    };
    let recorded = resumed.as_ref().map_or(&[][..], |(_, report)| report.cases.as_slice());
    if let Some((id, report)) = &resumed {
        let from = id.map_or_else(|| "the report so far".to_owned(), |id| format!("run {id}"));
        println!("resuming {from}: {} recorded, the rest run", counted(report.cases.len(), "case run", "case runs"));
    }
    let mut json = args.json.as_deref().map(|path| JsonSink::new(path, shard, info.clone()));
    let mut junit = args.junit.as_deref().map(|path| JunitSink { path, flaky_fails: args.flaky_fails });
    let mut database = database.map(|database| match &resumed {
        Some((Some(id), report)) => DatabaseSink::resuming(database, info.clone(), *id, &report.cases),
        _ => DatabaseSink::new(database, info.clone()),
    });
    let mut html = args.html.as_deref().map(|dir| HtmlSink { dir, run: info.clone() });
    let mut github = args.github.then(|| GithubSink::new(args.flaky_fails));
    // The HTML pages last: they are the most likely to fail, and the others are written by then.
    let mut sinks: Vec<&mut dyn Sink> = vec![&mut table];
    sinks.extend(json.as_mut().map(|sink| sink as &mut dyn Sink));
    sinks.extend(junit.as_mut().map(|sink| sink as &mut dyn Sink));
    sinks.extend(database.as_mut().map(|sink| sink as &mut dyn Sink));
    sinks.extend(github.as_mut().map(|sink| sink as &mut dyn Sink));
    sinks.extend(html.as_mut().map(|sink| sink as &mut dyn Sink));
    // The child gets this command line without what only the parent writes.
    let child_arguments = arguments_without(
        std::env::args_os().skip(1),
        &["--json", "--junit", "--html", "--db", "--tag", "--write-baseline"],
        &["--github", "--resume"],
    );
    let timeout = match args.timeout {
        Some(seconds) => CaseTimeout::Fixed(std::time::Duration::from_secs(seconds)),
        None => CaseTimeout::FromBudget,
    };
    let accept_adapter = |adapter: &AdapterDescription| {
        if let Some((_, report)) = &resumed {
            anyhow::ensure!(
                report.adapter == *adapter,
                "the run to resume ran on {} ({}); this one opened {} ({})",
                report.adapter.name,
                report.adapter.backend,
                adapter.name,
                adapter.backend
            );
        }
        accept_adapter(selector, &args.expect_adapter, adapter)?;
        if args.bug_report.is_some() {
            // Before any case runs: a report without its capture is not what was asked for.
            bug_report::capture::check_tool(&adapter.backend)?;
        }
        Ok(())
    };
    let supervision = Supervision {
        arguments: child_arguments,
        reproduction: &reproduction,
        expectations: &expectations,
        timeout,
        verbose,
        jobs: args.jobs as usize,
        skips: &skips,
        max_fails: args.max_fails.map(|n| n as usize),
        flaky_fails: args.flaky_fails,
        accept_adapter: &accept_adapter,
        recorded,
    };
    let report = supervise(&runs, &supervision, &mut sinks)?;
    if let Some(DatabaseSink { database, run_id: Some(id), .. }) = &database {
        println!("recorded as run {id} in {}", database.location());
    }
    if let Some(dir) = &args.bug_report {
        write_bug_reports(selector, &args, dir, &report, &runs, &reproduction, &expectations, timeout)?;
    }
    if let Some(path) = &args.write_baseline {
        std::fs::write(path, baseline(&report, &info))
            .with_context(|| format!("writing the baseline {}", path.display()))?;
        println!("baseline of this run's failures: {}", path.display());
    }
    let against = if args.baseline.is_empty() { "the expectations" } else { "the expectations and the baseline" };
    for line in run_summary(&report, args.flaky_fails, SLOWEST_SHOWN, against) {
        println!("{line}");
    }
    let failures = report.failures(args.flaky_fails);
    println!(
        "{}: {}",
        counted(report.cases.len(), "case", "cases"),
        counted(failures, "unexpected failure", "unexpected failures")
    );
    Ok(if failures == 0 { ExitCode::SUCCESS } else { ExitCode::from(1) })
}

/// `--bug-report DIR`: a folder per case run that did not pass (known issues too with
/// `--bug-report-known`), each from the case run again alone in a child of its own under the
/// backend's capture tool.
#[allow(clippy::too_many_arguments)]
fn write_bug_reports(
    selector: &AdapterSelector,
    args: &CheckArgs,
    dir: &Path,
    report: &Report,
    runs: &[CaseRun],
    reproduction: &Reproduction,
    expectations: &Expectations,
    timeout: CaseTimeout,
) -> Result<()> {
    let backend = report.adapter.backend.clone();
    let child_arguments = |run: &CaseRun, evidence: &Path| -> Vec<OsString> {
        let mut words: Vec<OsString> = vec!["--backend".into(), backend.clone().into()];
        for (flag, value) in [("--adapter", &selector.adapter_name), ("--driver-info", &selector.driver_info)] {
            if let Some(value) = value {
                words.extend([flag.into(), value.into()]);
            }
        }
        if selector.validation {
            words.push("--validation".into());
        }
        words.extend(["check".into(), run.case.name.into()]);
        for (key, value) in &run.overrides {
            words.extend(["--set".into(), format!("{key}={value}").into()]);
        }
        for path in args
            .expectations
            .iter()
            .map(|p| ("--expectations", p))
            .chain(args.baseline.iter().map(|p| ("--baseline", p)))
        {
            words.extend([path.0.into(), path.1.into()]);
        }
        words.extend(["--out".into(), evidence.into()]);
        words
    };
    let reports = BugReports {
        dir,
        known: args.bug_report_known,
        program: std::env::current_exe().context("finding this program to run the bug reports' cases")?,
        child_arguments: &child_arguments,
        reproduction,
        expectations,
        timeout,
    };
    let written = reports.write(report, runs)?;
    for one in &written {
        let note =
            if one.departures.is_empty() { "" } else { " (the captured run departs from the first: see its README)" };
        println!("bug report: {}{note}", one.folder.display());
    }
    if written.is_empty() {
        println!("bug reports: no case run to report in {}", dir.display());
    }
    Ok(())
}

/// The interrupted run `--resume` continues: the newest interrupted check run of --db (with its
/// id), else the report so far beside --json.
fn interrupted(args: &CheckArgs, database: Option<&mut Database>) -> Result<(Option<i64>, Report)> {
    if let Some(database) = database {
        let (id, report) = database.interrupted_run(None)?;
        return Ok((Some(id), report));
    }
    let Some(json) = &args.json else {
        bail!(
            "--resume continues a run recorded with --db, or one whose --json report so far remains: give its --db or --json"
        );
    };
    let partial = partial_path(json);
    anyhow::ensure!(
        partial.exists(),
        "--resume: no report so far at {} (that run finished, or recorded no case before it ended)",
        partial.display()
    );
    Ok((None, Report::read(&partial)?))
}

/// The skip lists' entries and the `--exclude` globs, in one list.
fn skip_list(files: &[PathBuf], excluded: &[String]) -> Result<SkipList> {
    let mut skips = SkipList::default();
    for path in files {
        skips.entries.extend(SkipList::load(path)?.entries);
    }
    for glob in excluded {
        skips.entries.push(SkipList::exclude(glob)?);
    }
    Ok(skips)
}

/// Holds the adapter the run opened to `--expect-adapter` (any glob matching its name, driver
/// or backend), and says on stderr when wgpu chose a backend other than Vulkan by itself (no
/// Vulkan driver loaded, say).
fn accept_adapter(selector: &AdapterSelector, expected: &[String], adapter: &AdapterDescription) -> Result<()> {
    let named = selector.backend.is_some() || std::env::var_os("WGPU_BACKEND").is_some();
    if !named && adapter.backend != "vulkan" {
        eprintln!(
            "note: no backend was named (--backend, WGPU_BACKEND) and wgpu chose {} on {}, not Vulkan",
            adapter.name, adapter.backend
        );
    }
    if expected.is_empty() {
        return Ok(());
    }
    let options = glob::MatchOptions { case_sensitive: false, ..Default::default() };
    let matches = |glob: &String| {
        glob::Pattern::new(glob).is_ok_and(|pattern| {
            [&adapter.name, &adapter.driver, &adapter.backend].iter().any(|field| pattern.matches_with(field, options))
        })
    };
    anyhow::ensure!(
        expected.iter().any(matches),
        "the adapter is not the one expected (--expect-adapter {}): found {} (driver {}, {}, backend {}); no case ran",
        expected.join(","),
        adapter.name,
        adapter.driver,
        adapter.driver_info,
        adapter.backend
    );
    Ok(())
}

/// The run's case list: every selected case (a sweep's draws), this shard's share of it.
fn planned_runs<'c>(
    args: &CheckArgs,
    cases: &[&'c Case],
    overrides: &BTreeMap<String, String>,
    shard: Option<Shard>,
    rerun: Option<&[CaseRun<'c>]>,
) -> Vec<CaseRun<'c>> {
    if let Some(failed) = rerun {
        return failed.to_vec();
    }
    let runs = plan_runs(cases, overrides, args.sweep.map(|count| (count, args.seed)));
    match shard {
        Some(shard) => shard.select(runs),
        None => runs,
    }
}

/// `--rerun-failed REPORT`: the case runs that report counts as failures, each with the
/// parameters it ran with.
fn failed_runs(path: &Path, flaky_fails: bool) -> Result<Vec<CaseRun<'static>>> {
    let report = Report::read(path)?;
    let mut runs = Vec::new();
    for record in report.cases.iter().filter(|c| c.outcome.is_failure(flaky_fails)) {
        let case = fragkit_cases::all()
            .iter()
            .find(|c| c.name == record.name)
            .with_context(|| format!("{}: case {} is not one of this kit's", path.display(), record.name))?;
        let overrides = record.params.iter().map(|(name, value)| (name.clone(), value.to_text())).collect();
        runs.push(CaseRun { case, overrides });
    }
    Ok(runs)
}

/// One configuration's run against its snapshot at `path` (or, updating, written into it): the
/// table's word for it and the departures that fail the run.
fn hold_to_snapshot(
    report: &Report,
    expectations: &Expectations,
    path: &Path,
    update: bool,
) -> Result<(String, Vec<String>)> {
    let now = Snapshot::of(report, expectations);
    let stored = Snapshot::load(path)?;
    if update {
        stored.unwrap_or_default().updated_with(&now).write(path)?;
        return Ok(("written".to_owned(), Vec::new()));
    }
    let Some(stored) = stored else {
        let missing = format!("no snapshot at {} (write it with --update-snapshots)", path.display());
        return Ok(("missing".to_owned(), vec![missing]));
    };
    let departures = stored.departures(&now);
    let verdict = if departures.is_empty() { "same".to_owned() } else { format!("{} differ", departures.len()) };
    Ok((verdict, departures))
}

/// `check --matrix`: every configuration in its own process, each writing its JSON report, JUnit
/// XML and log into the reports folder (and its own database run), then one table of them all
/// and, with --html, one HTML matrix with a column per configuration.
fn check_matrix(
    selector: &AdapterSelector,
    args: &CheckArgs,
    names: &str,
    expectations: &Expectations,
) -> Result<ExitCode> {
    check_selection_is_free(selector)?;
    anyhow::ensure!(
        args.json.is_none() && args.junit.is_none(),
        "with --matrix each configuration writes <reports>/<name>.json and <name>.junit.xml; drop --json/--junit"
    );
    anyhow::ensure!(!args.resume, "--resume takes one configuration's run: resume it without --matrix");
    anyhow::ensure!(
        args.write_baseline.is_none() && args.rerun_failed.is_none(),
        "--write-baseline and --rerun-failed take one configuration's run: give them without --matrix, per configuration"
    );
    // A configuration of the matrix file is named in its children's reproduce lines; one found
    // here is its backend and adapter, which the child's own flags name.
    let found = names.trim() == "found";
    let (matrix, names) = args.matrix.resolve(names)?;
    let names = names.as_str();
    if let Some(dir) = &args.snapshots {
        std::fs::create_dir_all(dir).with_context(|| format!("creating the snapshot folder {}", dir.display()))?;
    }
    let reports = &args.matrix.reports;
    let report_path = |stem: &str| reports.join(format!("{stem}.json"));
    for configuration in matrix.select(names)? {
        // A configuration that dies must not leave an earlier run's report to be read as its own.
        let stale = report_path(&configuration.file_stem());
        if stale.exists() {
            std::fs::remove_file(&stale).with_context(|| format!("removing the old report {}", stale.display()))?;
        }
    }
    let inherited = arguments_without(
        std::env::args_os().skip(1),
        &[
            "--matrix",
            "--adapters-file",
            "--reports",
            "--out",
            "--html",
            "--backend",
            "--adapter",
            "--driver-info",
            "--snapshots",
            "--as-configuration",
            "--bug-report",
            // The configurations run --jobs at once, each one case at a time.
            "--jobs",
        ],
        &["--update-snapshots", "--github"],
    );
    let runs = run_children(&matrix, names, reports, Show::Progress, args.jobs as usize, |configuration| {
        let stem = configuration.file_stem();
        let mut arguments = inherited.clone();
        if !found {
            arguments.extend(["--as-configuration".into(), configuration.name.clone().into()]);
            if let Some(file) = &args.matrix.adapters_file {
                arguments.extend(["--adapters-file".into(), file.into()]);
            }
        }
        if let Some(dir) = &args.bug_report {
            arguments.extend(["--bug-report".into(), dir.join(&stem).into()]);
        }
        arguments.extend(["--json".into(), report_path(&stem).into()]);
        arguments.extend(["--junit".into(), reports.join(format!("{stem}.junit.xml")).into()]);
        if let Some(out) = &args.out {
            arguments.extend(["--out".into(), out.join(&stem).into()]);
        }
        arguments
    })?;

    let mut columns = Vec::new();
    let mut table = vec![[
        "configuration".to_owned(),
        "adapter".to_owned(),
        "pass".to_owned(),
        "known_issue".to_owned(),
        "not_supported".to_owned(),
        "unexpected".to_owned(),
        "snapshot".to_owned(),
        "ending".to_owned(),
    ]];
    let mut details = Vec::new();
    let mut failed = false;
    for run in &runs {
        let name = run.configuration.name.clone();
        if matches!(run.end, ChildEnd::Absent(_)) {
            table.push([name, "-".into(), "-".into(), "-".into(), "-".into(), "-".into(), "-".into(), run.ending()]);
            continue;
        }
        let path = report_path(&run.configuration.file_stem());
        let Ok(report) = Report::read(&path) else {
            failed = true;
            table.push([
                name.clone(),
                "?".into(),
                "-".into(),
                "-".into(),
                "-".into(),
                "no report".into(),
                "-".into(),
                run.ending(),
            ]);
            details.push(format!("{name}: no report ({}); the log ends:\n{}", run.ending(), log_tail(&run.log, 8)));
            continue;
        };
        let count = |outcome: ReportedOutcome| report.cases.iter().filter(|c| c.outcome == outcome).count().to_string();
        let unexpected = report.failures(args.flaky_fails);
        failed |= unexpected > 0;
        if args.github {
            // The children's own outputs go to their logs: the annotations and summary from here.
            let mut github = GithubSink::new(args.flaky_fails);
            github.start(&report.adapter, report.cases.len())?;
            for case in &report.cases {
                github.record(case)?;
            }
            github.finish(&report)?;
        }
        for case in report.cases.iter().filter(|c| c.outcome.is_failure(args.flaky_fails)) {
            let reason: String = case.reason.chars().take(240).collect();
            details.push(format!("{name}: {} {}: {reason}", case.run_name(), case.outcome.label()));
        }
        let snapshot = match &args.snapshots {
            Some(dir) => {
                let (verdict, departures) = hold_to_snapshot(
                    &report,
                    expectations,
                    &dir.join(format!("{}.json", run.configuration.file_stem())),
                    args.update_snapshots,
                )?;
                failed |= !departures.is_empty();
                details.extend(departures.iter().map(|line| format!("{name}: snapshot: {line}")));
                verdict
            }
            None => "-".to_owned(),
        };
        table.push([
            name.clone(),
            report.adapter.name.clone(),
            count(ReportedOutcome::Pass),
            count(ReportedOutcome::KnownIssue),
            count(ReportedOutcome::NotSupported),
            unexpected.to_string(),
            snapshot,
            run.ending(),
        ]);
        columns.push(Column::new(name, report));
    }
    print_table(&table);
    for line in &details {
        println!("{line}");
    }
    if let Some(dir) = &args.html
        && !columns.is_empty()
    {
        let index = write_site(dir, &columns, &[])?;
        println!("HTML matrix: {}", index.display());
    }
    println!("reports, JUnit and logs: {}", reports.display());
    Ok(if failed { ExitCode::from(1) } else { ExitCode::SUCCESS })
}
