//! `fragkit import --db PATH REPORT.json…`: record reports written elsewhere (shard machines, older
//! runs) in a results database, each as one run in one transaction.

use std::path::PathBuf;

use anyhow::Result;
use fragkit::harness::database::{Database, RunInfo};
use fragkit::harness::report::Report;

#[derive(clap::Args)]
pub struct ImportArgs {
    /// The reports to record.
    #[arg(required = true)]
    reports: Vec<PathBuf>,
    /// The results database (SQLite file; created where missing).
    #[arg(long)]
    db: String,
    /// Tag the recorded runs.
    #[arg(long)]
    tag: Option<String>,
}

pub fn import(args: ImportArgs) -> Result<()> {
    // Read every report first: a corrupt one stops the import before anything is written.
    let reports = args.reports.iter().map(|path| Ok((path, Report::read(path)?))).collect::<Result<Vec<_>>>()?;
    let mut db = Database::open(&args.db)?;
    for (path, report) in reports {
        // The report does not say when or where it ran: recorded as imported now, from here.
        let info = RunInfo { git_commit: None, ..RunInfo::now(args.tag.clone()) };
        let id = db.record(&report, &info)?;
        println!("{}: run {id} ({} cases)", path.display(), report.cases.len());
    }
    Ok(())
}
