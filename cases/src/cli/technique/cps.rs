//! Coarse pixel shading in `fragkit render` and `fragkit report`.

use std::path::{Path, PathBuf};

use anyhow::{Context, Result};
use fragkit::gpu::Gpu;

use super::Technique;
use crate::cli::{light_count, lod_level, parse_size};

pub struct Cps;

/// Coarse pixel shading: LOD buffer, stencil masks, lit mips, the three composites.
#[derive(clap::Args)]
pub struct RenderArgs {
    #[arg(long)]
    out: PathBuf,
    #[arg(long, default_value = "320x180", value_parser = parse_size)]
    size: (u32, u32),
    /// foveated or content.
    #[arg(long, default_value = "foveated")]
    policy: String,
    #[arg(long, default_value_t = 5, value_parser = lod_level())]
    max_level: u32,
    #[arg(long, default_value_t = 200, value_parser = light_count())]
    lights: u32,
    #[arg(long, default_value_t = 1)]
    seed: u32,
}

/// Coarse pixel shading: policy × top level × light count × composite, against full resolution
/// and the naive way.
#[derive(clap::Args)]
pub struct ReportArgs {
    #[arg(long)]
    out: PathBuf,
    #[arg(long, default_value = "320x180", value_parser = parse_size)]
    size: (u32, u32),
    #[arg(long, value_delimiter = ',', default_value = "1,16,64,200", value_parser = light_count())]
    lights: Vec<u32>,
    #[arg(long, value_delimiter = ',', default_value = "2,4,6", value_parser = lod_level())]
    max_levels: Vec<u32>,
    #[arg(long, default_value_t = 3, value_parser = clap::value_parser!(u32).range(1..=1000))]
    repeats: u32,
}

impl Technique for Cps {
    const NAME: &'static str = "cps";
    type Render = RenderArgs;
    type Report = ReportArgs;

    fn check_render(args: &RenderArgs) -> Result<()> {
        fragkit::cps::LodPolicy::parse(&args.policy).map(|_| ())
    }

    fn render_out(args: &RenderArgs) -> &Path {
        &args.out
    }

    fn pictures(gpu: &Gpu, args: &RenderArgs) -> Result<Vec<(String, image::RgbaImage)>> {
        let policy = fragkit::cps::LodPolicy::parse(&args.policy)?;
        fragkit::deferred::gbuffer::check_size(gpu, args.size).context("--size")?;
        fragkit::cps::pictures::render_all(gpu, args.size, policy, args.max_level, args.lights, args.seed)
    }

    fn check_report(_: &ReportArgs) -> Result<()> {
        Ok(())
    }

    fn report(gpu: &Gpu, args: &ReportArgs, progress: &dyn Fn(String)) -> Result<PathBuf> {
        fragkit::deferred::gbuffer::check_size(gpu, args.size).context("--size")?;
        let sweep = fragkit::cps::report::CpsSweep {
            size: args.size,
            light_counts: args.lights.clone(),
            max_levels: args.max_levels.clone(),
            repeats: args.repeats,
            ..Default::default()
        };
        let rows = fragkit::cps::report::run_sweep(gpu, &sweep, |row| {
            progress(format!("{} lights, {} {} level {}", row.lights, row.method, row.composite, row.max_level));
        })?;
        fragkit_results::plot::tradeoff(&fragkit::cps::report::write_report(&args.out, &gpu.description, &rows)?)?;
        Ok(args.out.join("cps_report.md"))
    }
}
