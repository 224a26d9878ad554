//! Order-independent transparency in `fragkit render` and `fragkit report`.

use std::path::{Path, PathBuf};

use anyhow::{Context, Result};
use fragkit::gpu::Gpu;

use super::Technique;
use crate::cli::{frame_count, oit_scene, parse_size};

pub struct Oit;

/// Order-independent transparency: every method's image and error map against the exact composite.
#[derive(clap::Args)]
pub struct RenderArgs {
    #[arg(long)]
    out: PathBuf,
    #[arg(long, default_value = "160x160", value_parser = parse_size)]
    size: (u32, u32),
    /// paper, intersecting, or stiff_<layers>.
    #[arg(long, default_value = "paper")]
    scene: String,
    #[arg(long, default_value_t = 4, value_parser = clap::value_parser!(u32).range(1..=64))]
    samples: u32,
    #[arg(long, default_value_t = 16, value_parser = frame_count())]
    frames: u32,
    #[arg(long, default_value_t = 1)]
    seed: u32,
}

/// Order-independent transparency: method × sample count × frames × post-filter, against the
/// exact composite.
#[derive(clap::Args)]
pub struct ReportArgs {
    #[arg(long)]
    out: PathBuf,
    #[arg(long, default_value = "128x128", value_parser = parse_size)]
    size: (u32, u32),
    /// paper, intersecting, or stiff_<layers>.
    #[arg(long, default_value = "paper")]
    scene: String,
    #[arg(long, value_delimiter = ',', default_value = "1,4,16,64", value_parser = frame_count())]
    frames: Vec<u32>,
    #[arg(long, default_value_t = 1)]
    seed: u32,
}

impl Technique for Oit {
    const NAME: &'static str = "oit";
    type Render = RenderArgs;
    type Report = ReportArgs;

    fn check_render(args: &RenderArgs) -> Result<()> {
        oit_scene(&args.scene, args.seed).map(|_| ())
    }

    fn render_out(args: &RenderArgs) -> &Path {
        &args.out
    }

    fn pictures(gpu: &Gpu, args: &RenderArgs) -> Result<Vec<(String, image::RgbaImage)>> {
        let scene = oit_scene(&args.scene, args.seed)?;
        let offered = fragkit::caps::common_sample_counts(gpu);
        anyhow::ensure!(
            offered.contains(&args.samples),
            "--samples {}: this adapter offers sample counts {offered:?}",
            args.samples
        );
        fragkit::deferred::gbuffer::check_size(gpu, args.size).context("--size")?;
        let pictures =
            fragkit::oit::pictures::render_all(gpu, &scene, args.size, args.samples, args.frames, args.seed)?;
        Ok(pictures.into_iter().map(|(name, image)| (format!("{}_{name}", scene.name), image)).collect())
    }

    fn check_report(args: &ReportArgs) -> Result<()> {
        oit_scene(&args.scene, args.seed).map(|_| ())
    }

    fn report(gpu: &Gpu, args: &ReportArgs, progress: &dyn Fn(String)) -> Result<PathBuf> {
        let scene = oit_scene(&args.scene, args.seed)?;
        fragkit::deferred::gbuffer::check_size(gpu, args.size).context("--size")?;
        let sweep =
            fragkit::oit::report::OitSweep { size: args.size, frame_counts: args.frames.clone(), seed: args.seed };
        let rows = fragkit::oit::report::run_sweep(gpu, &scene, &sweep, |row| {
            progress(format!("{} {}x {} frames", row.method, row.samples, row.frames));
        })?;
        fragkit_results::plot::tradeoff(&fragkit::oit::report::write_report(&args.out, &gpu.description, &rows)?)?;
        Ok(args.out.join("oit_report.md"))
    }
}
