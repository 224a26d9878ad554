//! `fragkit history CASE --db PATH [--metric gpu_ms] [--adapter GLOB] --out FILE.png`: a case's
//! metric over the recorded runs, one line per adapter with each run's spread, failing runs and
//! driver changes marked, and the table behind the plot.

use std::path::PathBuf;

use anyhow::{Context, Result};
use fragkit_report::readable::number;
use fragkit_results::database::Database;
use fragkit_results::plot::{HistorySeries, RunPoint, history as history_plot};

#[derive(clap::Args)]
pub struct HistoryArgs {
    /// The case.
    case: String,
    /// The results database.
    #[arg(long)]
    db: String,
    /// gpu_ms, wall_ms, or a metric path as the database flattens it (e.g. foveated.seam_free.seam_error).
    #[arg(long, default_value = "gpu_ms")]
    metric: String,
    /// Only adapters whose "name (backend)" matches this glob.
    #[arg(long, default_value = "*")]
    adapter: String,
    /// Write the plot here (PNG).
    #[arg(long)]
    out: PathBuf,
}

pub fn history(args: HistoryArgs) -> Result<()> {
    let adapter = glob::Pattern::new(&args.adapter).with_context(|| format!("--adapter {:?}", args.adapter))?;
    let mut db = Database::open_existing(&args.db)?;
    let points = db.history(&args.case, &args.metric, &adapter)?;
    // A mistyped case or metric would plot nothing and look like a quiet history.
    anyhow::ensure!(!points.is_empty(), "no recorded run of {} on an adapter matching {:?}", args.case, args.adapter);
    anyhow::ensure!(
        points.iter().any(|p| p.value.is_some()),
        "{} has no metric {:?} in any recorded run (gpu_ms, wall_ms, or a metric's dotted path, as `compare` lists them)",
        args.case,
        args.metric
    );
    println!("| run | adapter | driver | {} | spread | failed |\n|---|---|---|---|---|---|", args.metric);
    let mut plotted: Vec<HistorySeries> = Vec::new();
    for point in &points {
        let shown = point.value.map_or("-".into(), number);
        let spread = point.spread.map_or("-".into(), |(low, high)| format!("{}–{}", number(low), number(high)));
        let failed = if point.failed { "yes" } else { "" };
        println!("| {} | {} | {} | {shown} | {spread} | {failed} |", point.run_id, point.adapter, point.driver_info);
        let Some(value) = point.value else { continue };
        // A driver change on this adapter since its previous run: marked.
        let previous = points.iter().rev().find(|p| p.run_id < point.run_id && p.adapter == point.adapter);
        let run = RunPoint {
            run: point.run_id,
            value,
            spread: point.spread,
            failed: point.failed,
            driver_changed: previous.is_some_and(|p| p.driver_info != point.driver_info),
        };
        match plotted.iter_mut().find(|s| s.name == point.adapter) {
            Some(series) => series.points.push(run),
            None => plotted.push(HistorySeries { name: point.adapter.clone(), points: vec![run] }),
        }
    }
    let title = format!("{} {} by run (bars: the run's spread)", args.case, args.metric);
    history_plot(&args.out, &title, &args.metric, &plotted)?;
    println!("{}", args.out.display());
    Ok(())
}
