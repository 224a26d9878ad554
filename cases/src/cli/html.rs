//! `fragkit html`: the browsable HTML report (`fragkit_results::html`) of JSON reports or of runs
//! of a results database — by default the latest run of each adapter there — with the technique
//! reports' plots from `--include` folders.

use std::path::PathBuf;

use anyhow::Result;
use fragkit_report::report::Report;
use fragkit_results::database::{Database, RunRef};
use fragkit_results::html::{Column, write_site};

#[derive(clap::Args)]
pub struct HtmlArgs {
    /// JSON reports (`fragkit check --json`), one column each.
    reports: Vec<PathBuf>,
    /// A results database (an SQLite file or a postgres:// URL).
    #[arg(long)]
    db: Option<String>,
    /// Runs of the database, one column each: an id, latest, latest~N, latest@GLOB or tag:NAME
    /// (default: the latest run of each adapter).
    #[arg(long = "run", requires = "db")]
    runs: Vec<String>,
    /// Folders `fragkit report` wrote: their plots and tables go on the reports page.
    #[arg(long = "include")]
    includes: Vec<PathBuf>,
    /// Where to write the page set (created where missing).
    #[arg(long)]
    out: PathBuf,
}

pub fn html(args: HtmlArgs) -> Result<()> {
    let mut columns = Vec::new();
    for path in &args.reports {
        columns.push(Column::new(path.display().to_string(), Report::read(path)?));
    }
    if let Some(location) = &args.db {
        let mut db = Database::open_existing(location)?;
        let runs = db.runs()?;
        let ids = if args.runs.is_empty() {
            // The latest finished check of each adapter, and any run after it that never
            // finished: shown as incomplete, never passed over.
            let latest = db.latest_per_adapter()?;
            let oldest = latest.first().copied().unwrap_or(i64::MAX);
            let unfinished = runs.iter().filter(|r| !r.complete && r.id > oldest).map(|r| r.id);
            let mut ids: Vec<i64> = latest.iter().copied().chain(unfinished).collect();
            if ids.is_empty() {
                ids.extend(runs.iter().filter(|r| !r.complete).map(|r| r.id));
            }
            ids.sort_unstable();
            ids
        } else {
            args.runs.iter().map(|r| db.resolve(&RunRef::parse(r)?)).collect::<Result<_>>()?
        };
        for id in ids {
            let complete = runs.iter().find(|r| r.id == id).is_none_or(|r| r.complete);
            columns.push(Column { complete, ..Column::new(format!("run {id}"), db.load(id)?) });
        }
    }
    anyhow::ensure!(!columns.is_empty(), "nothing to show: give JSON reports or --db with runs in it");
    for dir in &args.includes {
        anyhow::ensure!(dir.is_dir(), "--include {}: not a folder", dir.display());
    }
    let index = write_site(&args.out, &columns, &args.includes)?;
    println!("{}", index.display());
    Ok(())
}
