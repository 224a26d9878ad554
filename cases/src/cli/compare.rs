//! `fragkit compare BASE NEW`: two runs (JSON reports, or runs of a results database: an id,
//! `latest`, `latest~N`, `latest@GLOB`, `tag:NAME`) compared case by case — regressions, fixes,
//! other outcome changes, metric changes, GPU-time changes judged against the noise — as markdown
//! (stdout, or `--markdown` for a merge-request comment); exit 1 when the new run fails a case
//! the base run did not, or is slower beyond the threshold and the noise.

use std::path::PathBuf;
use std::process::ExitCode;

use anyhow::{Context, Result};
use fragkit_report::report::Report;
use fragkit_results::compare::{TimeJudgement, compare};
use fragkit_results::database::{Database, RunRef};

#[derive(clap::Args)]
pub struct CompareArgs {
    /// The base run: a JSON report, several (A.json,B.json,…: runs in separate processes, each
    /// taken as one repeat), or with --db a run id, latest, latest~N, latest@GLOB or tag:NAME.
    base: String,
    /// The new run, spelled likewise.
    new: String,
    /// The results database the runs are in (an SQLite file or a postgres:// URL); its earlier
    /// runs on the new run's adapter also give the noise a single GPU time is judged against.
    #[arg(long)]
    db: Option<String>,
    /// Also write the markdown here.
    #[arg(long)]
    markdown: Option<PathBuf>,
    /// Also write the comparison as JSON here (every change with its numbers and verdict, and
    /// whether it regressed: what a CI step reads).
    #[arg(long)]
    json: Option<PathBuf>,
    /// Smallest relative GPU-time change that counts as a regression (0.05: 5 % slower).
    #[arg(long, default_value_t = 0.05, value_parser = fraction)]
    threshold: f64,
    /// Largest p-value (the Mann–Whitney test of two runs' repeats, or a single time's rank among
    /// the database's earlier runs) that counts as beyond the noise. At 0.01 the repeats need 5 a
    /// side (`check --repeat 5` for both runs); fewer are reported as "cannot judge".
    #[arg(long, default_value_t = 0.01, value_parser = fraction)]
    alpha: f64,
}

fn fraction(text: &str) -> Result<f64, String> {
    match text.parse::<f64>() {
        Ok(v) if v > 0.0 && v < 1.0 => Ok(v),
        _ => Err(format!("{text:?}: expected a number between 0 and 1")),
    }
}

/// A run named on the command line: a JSON report's path, else a run of the database (with its
/// id, which bounds the history it is judged against).
fn load(which: &str, db: Option<&mut Database>) -> Result<(Report, Option<i64>)> {
    let path = std::path::Path::new(which);
    if path.is_file() {
        return Ok((Report::read(path)?, None));
    }
    if which.contains(',') {
        // Several runs' reports, one per process: pooled, each a repeat of the side.
        let reports = which
            .split(',')
            .map(|part| Ok((PathBuf::from(part), Report::read(std::path::Path::new(part))?)))
            .collect::<Result<Vec<_>>>()?;
        return Ok((Report::pool_processes(reports)?, None));
    }
    let Some(db) = db else {
        anyhow::bail!("{which:?} is no report file; to name a run of a results database, give --db PATH|URL");
    };
    let id = db.resolve(&RunRef::parse(which)?)?;
    Ok((db.load(id)?, Some(id)))
}

pub fn compare_reports(args: CompareArgs) -> Result<ExitCode> {
    let mut db = args.db.as_deref().map(Database::open_existing).transpose()?;
    let (base, _) = load(&args.base, db.as_mut())?;
    let (new, new_id) = load(&args.new, db.as_mut())?;
    // A run that ran nothing would compare as "no regressions".
    for (which, name, report) in [("base", &args.base, &base), ("new", &args.new, &new)] {
        anyhow::ensure!(
            !report.cases.is_empty(),
            "the {which} run {name} holds no case runs: there is nothing to compare"
        );
    }
    for (name, report) in [(&args.base, &base), (&args.new, &new)] {
        if let Some(dir) = report.run.as_ref().and_then(|run| run.shader_override.as_ref()) {
            eprintln!("note: run {name} read its shaders from {dir} (FRAGKIT_SHADER_DIR), not its commit's");
        }
    }
    if base.adapter != new.adapter {
        eprintln!(
            "note: the runs are on different adapters ({} {} / {} {}); outcomes still compare case by case",
            base.adapter.name, base.adapter.backend, new.adapter.name, new.adapter.backend
        );
    }
    let history = match db.as_mut() {
        Some(db) => db.gpu_history(&new.adapter, new_id)?,
        None => Default::default(),
    };
    let judgement = TimeJudgement { threshold: args.threshold, alpha: args.alpha };
    let comparison = compare(&base, &new, &judgement, &history);
    let markdown = comparison.markdown(&args.base, &args.new);
    print!("{markdown}");
    if let Some(path) = &args.markdown {
        std::fs::write(path, &markdown).with_context(|| format!("writing {}", path.display()))?;
    }
    if let Some(path) = &args.json {
        let json = serde_json::json!({
            "base": args.base,
            "new": args.new,
            "regressed": comparison.regressed(),
            "comparison": comparison,
        });
        std::fs::write(path, serde_json::to_string_pretty(&json)?)
            .with_context(|| format!("writing {}", path.display()))?;
    }
    Ok(if comparison.regressed() { ExitCode::from(1) } else { ExitCode::SUCCESS })
}
