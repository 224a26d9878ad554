//! `fragkit bench [cps|oit|cbr|kit]…`: each technique against its baseline, timed side by side
//! in rounds — the measurements `cargo bench` makes, from the same code (`fragkit::bench`) — printed
//! with the speed-ups and where the time goes, and recorded in a results database with every
//! round's GPU time (so that `fragkit compare` judges a change against the noise).

use std::path::PathBuf;

use anyhow::{Context, Result};
use fragkit::bench::{BenchResult, TECHNIQUES, for_technique, measure};
use fragkit::gpu::{AdapterSelector, Gpu};
use fragkit_report::report::Report;
use fragkit_results::database::{Database, RunInfo, RunKind};

use super::matrix::{MatrixArgs, run_each_showing_output};

#[derive(clap::Args)]
pub struct BenchArgs {
    /// Which benches: cps, oit, cbr, kit (all when none).
    #[arg(value_parser = clap::builder::PossibleValuesParser::new(TECHNIQUES))]
    techniques: Vec<String>,
    /// Rounds per bench: every variant timed once a round, back to back.
    #[arg(long, default_value_t = 9, value_parser = clap::value_parser!(u32).range(1..=1000))]
    rounds: u32,
    /// Also write the results as JSON.
    #[arg(long)]
    json: Option<PathBuf>,
    /// Record the results in this results database (an SQLite file or a postgres:// URL), one
    /// case run per variant named bench.<technique>.<scene>.<variant>.
    #[arg(long)]
    db: Option<String>,
    /// Tag the recorded run.
    #[arg(long, requires = "db")]
    tag: Option<String>,
    #[command(flatten)]
    matrix: MatrixArgs,
}

pub fn bench(selector: &AdapterSelector, args: BenchArgs) -> Result<()> {
    if let Some(names) = &args.matrix.matrix {
        return run_each_showing_output(selector, &args.matrix, names, "bench");
    }
    let techniques: Vec<&str> = if args.techniques.is_empty() {
        TECHNIQUES.to_vec()
    } else {
        args.techniques.iter().map(String::as_str).collect()
    };
    // A wrong database is refused before the GPU time is spent.
    let mut database = args.db.as_deref().map(Database::open).transpose()?;
    let gpu = Gpu::open(selector)?;
    let mut results: Vec<BenchResult> = Vec::new();
    for technique in techniques {
        let result = gpu.scoped(technique, || {
            let mut bench = for_technique(&gpu, technique)?;
            measure(&gpu, technique, bench.as_mut(), args.rounds as usize)
        })?;
        for line in result.lines() {
            println!("{line}");
        }
        results.push(result);
    }
    if let Some(path) = &args.json {
        let text = serde_json::to_string_pretty(&results)?;
        std::fs::write(path, text).with_context(|| format!("writing {}", path.display()))?;
    }
    if let Some(database) = database.as_mut() {
        let report = Report {
            adapter: gpu.description.clone(),
            cases: results.iter().flat_map(BenchResult::records).collect(),
            diagnostics: fragkit::diagnostics::take(),
            shard: None,
            run: None,
        };
        let id = database.record(&report, &RunInfo::now(RunKind::Bench, args.tag.clone()), None)?;
        println!("recorded as run {id} in {}", database.location());
    }
    Ok(())
}
