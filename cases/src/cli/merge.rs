//! `fragkit merge`: one report from the JSON reports of one run's shards (`check --shard K/N`),
//! printed as the table, written as JSON and, when asked, JUnit XML; exit 1 on any unexpected
//! failure in it.

use fragkit_report::readable::counted;
use std::path::PathBuf;
use std::process::ExitCode;

use anyhow::Result;
use fragkit_report::report::Report;
use fragkit_results::junit::write_junit;

use super::table::print_table;

#[derive(clap::Args)]
pub struct MergeArgs {
    /// The shards' reports.
    #[arg(required = true)]
    reports: Vec<PathBuf>,
    /// Write the merged JSON report here.
    #[arg(long)]
    json: Option<PathBuf>,
    /// Write the merged report as JUnit XML here.
    #[arg(long)]
    junit: Option<PathBuf>,
    /// Count flaky cases as failures.
    #[arg(long)]
    flaky_fails: bool,
}

pub fn merge(args: MergeArgs) -> Result<ExitCode> {
    let reports =
        args.reports.iter().map(|path| Ok((path.clone(), Report::read(path)?))).collect::<Result<Vec<_>>>()?;
    let merged = Report::merge(reports)?;
    let d = &merged.adapter;
    println!("adapter: {} ({}, {} {})", d.name, d.backend, d.driver, d.driver_info);
    print_table(&merged);
    if let Some(path) = &args.json {
        merged.write_atomically(path)?;
    }
    if let Some(path) = &args.junit {
        write_junit(&merged, path, args.flaky_fails)?;
    }
    let failures = merged.failures(args.flaky_fails);
    println!(
        "{} from {}: {}",
        counted(merged.cases.len(), "case", "cases"),
        counted(args.reports.len(), "report", "reports"),
        counted(failures, "unexpected failure", "unexpected failures")
    );
    Ok(if failures == 0 { ExitCode::SUCCESS } else { ExitCode::from(1) })
}
