//! `fragkit import --db PATH REPORT.json…`: record reports written elsewhere (shard machines, older
//! runs) in a results database, each as one run of kind `import` in one transaction, with the
//! time, commit and tag the report holds. A report already imported is refused (`--again` records
//! it once more).

use std::path::PathBuf;

use anyhow::{Context, Result, bail};
use fragkit_report::report::Report;
use fragkit_results::database::{Database, RunInfo};

#[derive(clap::Args)]
pub struct ImportArgs {
    /// The reports to record.
    #[arg(required = true)]
    reports: Vec<PathBuf>,
    /// The results database (SQLite file; created where missing).
    #[arg(long)]
    db: String,
    /// Tag the recorded runs (default: the tag the report was run with).
    #[arg(long)]
    tag: Option<String>,
    /// Record a report even where it was imported before.
    #[arg(long)]
    again: bool,
}

/// The report file's identity: FNV-1a over its bytes (stable across builds, unlike std's hasher).
fn report_digest(bytes: &[u8]) -> String {
    let hash = bytes
        .iter()
        .fold(0xcbf2_9ce4_8422_2325u64, |hash, &byte| (hash ^ u64::from(byte)).wrapping_mul(0x0100_0000_01b3));
    format!("fnv1a64:{hash:016x}:{}", bytes.len())
}

pub fn import(args: ImportArgs) -> Result<()> {
    // Read every report and check it against the database first: a corrupt or repeated one
    // stops the import before anything is written.
    let mut db = Database::open(&args.db)?;
    let mut reports = Vec::new();
    for path in &args.reports {
        let bytes = std::fs::read(path).with_context(|| format!("reading {}", path.display()))?;
        let report = Report::read(path)?;
        let digest = report_digest(&bytes);
        if let (false, Some(id)) = (args.again, db.imported_as(&digest)?) {
            bail!("{} was imported before, as run {id}; --again records it once more", path.display());
        }
        if reports.iter().any(|(_, _, seen)| *seen == digest) {
            bail!("{} is given twice (or two files hold the same report)", path.display());
        }
        reports.push((path, report, digest));
    }
    for (path, report, digest) in reports {
        let info = RunInfo::imported(report.run.as_ref(), args.tag.clone());
        let id = db.record(&report, &info, Some(&digest))?;
        println!("{}: run {id} ({} cases)", path.display(), report.cases.len());
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_digest_is_fnv1a_and_tells_reports_apart() {
        // FNV-1a 64 of "a" (the published test vector).
        assert_eq!(report_digest(b"a"), "fnv1a64:af63dc4c8601ec8c:1");
        assert_ne!(report_digest(b"{}"), report_digest(b"{ }"));
    }
}
