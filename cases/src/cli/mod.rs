//! The `fragkit` command line: the argument definitions, and one file per subcommand.

pub mod adapters;
pub mod bench;
pub mod caps;
pub mod check;
pub mod compare;
pub mod configurations;
pub mod history;
pub mod html;
pub mod import;
pub mod list;
pub mod matrix;
pub mod merge;
pub mod table;
pub mod technique;

use anyhow::Result;
use clap::{Parser, Subcommand};

#[derive(Parser)]
#[command(name = "fragkit", version, about = "Deterministic, compute-free GPU conformance kit")]
pub struct Cli {
    /// Backend: vulkan, gl, metal, dx12.
    #[arg(long, global = true, env = "WGPU_BACKEND")]
    pub backend: Option<String>,
    /// Substring of the adapter name.
    #[arg(long, global = true, env = "WGPU_ADAPTER_NAME")]
    pub adapter: Option<String>,
    /// Glob the adapter's driver info must match (e.g. 'OpenGL ES 3.0*'); no matching adapter is
    /// an error, never another adapter.
    #[arg(long, global = true)]
    pub driver_info: Option<String>,
    /// Load the Vulkan validation layer (Debian: vulkan-validationlayers): an error it reports
    /// during a case fails that case, unless the expectations list the message. Off by default,
    /// in every build: timings never depend on what else is installed. (GL's debug output is
    /// always on: the kit's GL verdicts read the driver's API errors.)
    #[arg(long, global = true)]
    pub validation: bool,
    /// Print what wgpu and the driver log (kept in the JSON report otherwise) and every reason
    /// whole.
    #[arg(long, short, global = true)]
    pub verbose: bool,
    #[command(subcommand)]
    pub command: Command,
}

#[derive(Subcommand)]
pub enum Command {
    /// Every adapter on every backend, and what each configuration of the adapter matrix
    /// resolves to here (or why it is absent).
    Adapters(adapters::AdaptersArgs),
    /// Measure the selected adapter's capabilities with tiny renders.
    Caps(caps::CapsArgs),
    /// List cases with their parameters and requirements (-v: the shader files each case's
    /// pipelines are built from, and the module that builds each).
    List { pattern: Option<String> },
    /// Render a technique's intermediates and results as PNGs for a person to look at.
    Render {
        #[command(subcommand)]
        technique: technique::RenderCommand,
    },
    /// Sweep a technique's settings and write error against GPU time (JSON, markdown, PNG plot).
    Report {
        #[command(subcommand)]
        technique: technique::ReportCommand,
    },
    /// Time each technique against its baseline in rounds (speed-ups, where the time goes);
    /// record them with --db.
    Bench(bench::BenchArgs),
    /// Run cases (glob patterns; all when none) and exit 1 on any unexpected failure.
    Check(Box<check::CheckArgs>),
    /// Plot a case's metric over the runs of a results database, one line per adapter.
    History(history::HistoryArgs),
    /// Write a browsable HTML report (matrix, case pages with evidence, comparison, plots) of JSON
    /// reports or database runs.
    Html(html::HtmlArgs),
    /// Record JSON reports written elsewhere in a results database.
    Import(import::ImportArgs),
    /// Compare two runs (JSON reports or database runs) case by case (markdown); exit 1 on a regression.
    Compare(compare::CompareArgs),
    /// Join the JSON reports of one run's shards (`check --shard K/N`) into one report.
    Merge(merge::MergeArgs),
}

/// Light counts: at least one; 65536 lights are 2048 rows of the 64-wide light texture, within
/// WebGPU's guaranteed 8192.
pub fn light_count() -> clap::builder::RangedI64ValueParser<u32> {
    clap::value_parser!(u32).range(1..=65_536)
}

pub fn frame_count() -> clap::builder::RangedI64ValueParser<u32> {
    clap::value_parser!(u32).range(1..=100_000)
}

/// CPS levels: 0..=8 (2^8-pixel coarse fragments, the stencil pyramid's top).
pub fn lod_level() -> clap::builder::RangedI64ValueParser<u32> {
    clap::value_parser!(u32).range(0..=fragkit::cps::MAX_LEVEL as i64)
}

pub fn parse_size(text: &str) -> Result<(u32, u32), String> {
    match fragkit::harness::ParamKind::Sizes.parse(text) {
        Ok(fragkit_report::param_value::ParamValue::Sizes(sizes)) if sizes.len() == 1 => Ok(sizes[0]),
        Ok(_) => Err(format!("{text:?}: expected one size like 320x180")),
        Err(e) => Err(format!("{e:#}")),
    }
}

/// A named OIT scene: `paper`, `intersecting` or `stiff_<layers>`.
pub fn oit_scene(name: &str, seed: u32) -> Result<fragkit::oit::scene::QuadScene> {
    use fragkit::oit::scene::QuadScene;
    match name {
        "paper" => Ok(QuadScene::paper()),
        "intersecting" => Ok(QuadScene::intersecting()),
        other => match other.strip_prefix("stiff_").map(str::parse::<u32>) {
            Some(Ok(layers)) if (1..=256).contains(&layers) => Ok(QuadScene::stiff(layers, seed)),
            _ => anyhow::bail!("unknown OIT scene {other:?}; expected paper, intersecting or stiff_<1..=256>"),
        },
    }
}
