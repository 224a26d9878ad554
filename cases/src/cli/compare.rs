//! `fragkit compare BASE NEW`: two runs (JSON reports, or runs of a results database: an id,
//! `latest`, `latest~N`, `tag:NAME`) compared case by case — regressions, fixes,
//! other outcome changes, metric changes, GPU-time ratios — as markdown (stdout, or `--markdown`
//! for a merge-request comment); exit 1 when the new run fails a case the base run did not.

use std::path::PathBuf;
use std::process::ExitCode;

use anyhow::{Context, Result};
use fragkit::harness::compare::compare;
use fragkit::harness::database::{Database, RunRef};
use fragkit::harness::report::Report;

#[derive(clap::Args)]
pub struct CompareArgs {
    /// The base run: a JSON report, or with --db a run id, latest, latest~N or tag:NAME.
    base: String,
    /// The new run, spelled likewise.
    new: String,
    /// The results database the runs are in.
    #[arg(long)]
    db: Option<PathBuf>,
    /// Also write the markdown here.
    #[arg(long)]
    markdown: Option<PathBuf>,
}

/// A run named on the command line: a JSON report's path, else a run of the database.
fn load(which: &str, db: Option<&Database>) -> Result<Report> {
    let path = std::path::Path::new(which);
    if path.is_file() {
        return Report::read(path);
    }
    let Some(db) = db else {
        anyhow::bail!("{which:?} is no report file; to name a run of a results database, give --db PATH");
    };
    db.load(db.resolve(&RunRef::parse(which)?)?)
}

pub fn compare_reports(args: CompareArgs) -> Result<ExitCode> {
    let db = args.db.as_deref().map(Database::open).transpose()?;
    let (base, new) = (load(&args.base, db.as_ref())?, load(&args.new, db.as_ref())?);
    if base.adapter != new.adapter {
        eprintln!(
            "note: the runs are on different adapters ({} {} / {} {}); outcomes still compare case by case",
            base.adapter.name, base.adapter.backend, new.adapter.name, new.adapter.backend
        );
    }
    let comparison = compare(&base, &new);
    let markdown = comparison.markdown(&args.base, &args.new);
    print!("{markdown}");
    if let Some(path) = &args.markdown {
        std::fs::write(path, &markdown).with_context(|| format!("writing {}", path.display()))?;
    }
    Ok(if comparison.regressions.is_empty() { ExitCode::SUCCESS } else { ExitCode::from(1) })
}
