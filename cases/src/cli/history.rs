//! `fragkit history CASE --db PATH [--metric gpu_ms] [--adapter GLOB] --out FILE.png`: a case's
//! metric over the recorded runs, one line per adapter, driver changes marked with a cross, and
//! the table behind the plot.

use std::path::PathBuf;

use anyhow::{Context, Result};
use fragkit::harness::database::Database;
use fragkit::plot::{PlotLine, lines};

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
    println!("| run | adapter | driver | {} |\n|---|---|---|---|", args.metric);
    let mut plotted: Vec<PlotLine> = Vec::new();
    for point in &points {
        let shown = point.value.map_or("-".into(), |v| format!("{v:.4}"));
        println!("| {} | {} | {} | {shown} |", point.run_id, point.adapter, point.driver_info);
        let line = match plotted.iter_mut().position(|l| l.series == point.adapter) {
            Some(i) => &mut plotted[i],
            None => {
                plotted.push(PlotLine { series: point.adapter.clone(), points: Vec::new(), marked: Vec::new() });
                plotted.last_mut().expect("just pushed")
            }
        };
        let Some(value) = point.value else { continue };
        let x = point.run_id as f64;
        // A driver change on this adapter since its previous run: marked.
        let previous = points.iter().rev().find(|p| p.run_id < point.run_id && p.adapter == point.adapter);
        if previous.is_some_and(|p| p.driver_info != point.driver_info) {
            line.marked.push(x);
        }
        line.points.push((x, value));
    }
    let title = format!("{} {} by run (x: driver changed)", args.case, args.metric);
    lines(&args.out, &title, "run", &args.metric, &plotted)?;
    println!("{}", args.out.display());
    Ok(())
}
