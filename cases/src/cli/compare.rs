//! `fragkit compare BASE NEW`: two JSON reports compared case by case — regressions, fixes,
//! other outcome changes, metric changes, GPU-time ratios — as markdown (stdout, or `--markdown`
//! for a merge-request comment); exit 1 when the new run fails a case the base run did not.

use std::path::PathBuf;
use std::process::ExitCode;

use anyhow::{Context, Result};
use fragkit::harness::compare::compare;
use fragkit::harness::report::Report;

#[derive(clap::Args)]
pub struct CompareArgs {
    /// The base run's JSON report.
    base: PathBuf,
    /// The new run's JSON report.
    new: PathBuf,
    /// Also write the markdown here.
    #[arg(long)]
    markdown: Option<PathBuf>,
}

pub fn compare_reports(args: CompareArgs) -> Result<ExitCode> {
    let (base, new) = (Report::read(&args.base)?, Report::read(&args.new)?);
    if base.adapter != new.adapter {
        eprintln!(
            "note: the runs are on different adapters ({} {} / {} {}); outcomes still compare case by case",
            base.adapter.name, base.adapter.backend, new.adapter.name, new.adapter.backend
        );
    }
    let comparison = compare(&base, &new);
    let markdown = comparison.markdown(&args.base.display().to_string(), &args.new.display().to_string());
    print!("{markdown}");
    if let Some(path) = &args.markdown {
        std::fs::write(path, &markdown).with_context(|| format!("writing {}", path.display()))?;
    }
    Ok(if comparison.regressions.is_empty() { ExitCode::SUCCESS } else { ExitCode::from(1) })
}
