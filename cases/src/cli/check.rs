//! `fragkit check`: run the selected cases (a sweep's draws, one shard's share) on one adapter and
//! hand every record to the sinks asked for: the table, the JSON report, JUnit XML, the HTML
//! report, the results database.

use std::path::{Path, PathBuf};
use std::process::ExitCode;

use anyhow::{Context, Result};
use fragkit::gpu::{AdapterSelector, Gpu};
use fragkit::harness::database::{Database, DatabaseSink, RunInfo};
use fragkit::harness::expectations::{BUILT_IN, Expectations};
use fragkit::harness::html::HtmlSink;
use fragkit::harness::junit::JunitSink;
use fragkit::harness::params::parse_overrides;
use fragkit::harness::run::{JsonSink, RunOptions, Shard, Sink, plan_runs, run};
use fragkit::harness::runner::{check_overrides, check_sizes, select};

use super::table::TableSink;

#[derive(clap::Args)]
pub struct CheckArgs {
    patterns: Vec<String>,
    /// Override a parameter: key=value.
    #[arg(long = "set", value_name = "KEY=VALUE")]
    sets: Vec<String>,
    /// Write the JSON report here.
    #[arg(long)]
    json: Option<PathBuf>,
    /// Write a JUnit XML report here (fail and unexpected_pass as failures, not_supported and
    /// known_issue as skipped).
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
    /// Run each case N times and record every run's GPU time (the median is reported), so that
    /// `fragkit compare` judges a time change against the noise.
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
    let cases = select(fragkit_cases::ALL, &args.patterns)?;
    let overrides = parse_overrides(&args.sets)?;
    check_overrides(&cases, &overrides)?;
    let shard = args.shard.as_deref().map(Shard::parse).transpose()?;
    let expectations = match &args.expectations {
        Some(path) => Expectations::load(path)?,
        None => Expectations::parse(BUILT_IN, "cases/expectations.toml (built in)")?,
    };
    if let Some(dir) = &args.out {
        std::fs::create_dir_all(dir).with_context(|| format!("creating the evidence folder {}", dir.display()))?;
    }
    if let Some(dir) = &args.html {
        std::fs::create_dir_all(dir).with_context(|| format!("creating the HTML report folder {}", dir.display()))?;
    }
    for path in args.json.iter().chain(&args.junit) {
        check_writable(path)?;
    }
    // Open (and migrate) the database now: a wrong or newer one is refused before the run.
    let database = args.db.as_deref().map(Database::open).transpose()?;
    let gpu = Gpu::open(selector)?;
    let d = &gpu.description;
    println!("adapter: {} ({}, {} {})", d.name, d.backend, d.driver, d.driver_info);

    let mut runs = plan_runs(&cases, &overrides, args.sweep.map(|count| (count, args.seed)));
    if let Some(shard) = shard {
        runs = shard.select(runs);
        println!("shard {}/{}: {} case runs", shard.index, shard.count, runs.len());
    }
    for planned in &runs {
        check_sizes(&gpu, &[planned.case], &planned.overrides)?;
    }

    let options = RunOptions {
        expectations: &expectations,
        evidence_dir: args.out.as_deref(),
        reproduce_lines: args.sweep.is_some(),
        retries: args.retry,
        repeats: args.repeat,
    };
    let mut table = TableSink::new(verbose);
    let mut json = args.json.as_deref().map(|path| JsonSink { path });
    let mut junit = args.junit.as_deref().map(|path| JunitSink { path, flaky_fails: args.flaky_fails });
    let mut database =
        database.map(|database| DatabaseSink { database, info: RunInfo::now(args.tag.clone()), run_id: None });
    let mut html = args.html.as_deref().map(|dir| HtmlSink { dir });
    // The HTML pages last: they are the most likely to fail, and the others are written by then.
    let mut sinks: Vec<&mut dyn Sink> = vec![&mut table];
    sinks.extend(json.as_mut().map(|sink| sink as &mut dyn Sink));
    sinks.extend(junit.as_mut().map(|sink| sink as &mut dyn Sink));
    sinks.extend(database.as_mut().map(|sink| sink as &mut dyn Sink));
    sinks.extend(html.as_mut().map(|sink| sink as &mut dyn Sink));
    let report = run(gpu, &runs, &options, &mut sinks)?;
    if let Some(DatabaseSink { database, run_id: Some(id), .. }) = &database {
        println!("recorded as run {id} in {}", database.location());
    }
    let failures = report.failures(args.flaky_fails);
    println!("{} cases: {} unexpected failures", report.cases.len(), failures);
    Ok(if failures == 0 { ExitCode::SUCCESS } else { ExitCode::from(1) })
}
