//! Checkerboard rendering in `fragkit render` and `fragkit report`.

use std::path::{Path, PathBuf};

use anyhow::{Context, Result};
use fragkit::cbr::scene::Motion;
use fragkit::gpu::Gpu;

use super::Technique;
use crate::cli::{frame_count, light_count, parse_size};

pub struct Cbr;

/// Checkerboard rendering: frames N−1 and N, motion, pixel sources, reconstruction, error map.
#[derive(clap::Args)]
pub struct RenderArgs {
    #[arg(long)]
    out: PathBuf,
    #[arg(long, default_value = "192x128", value_parser = parse_size)]
    size: (u32, u32),
    /// static, pan_<x>x<y> (pixels a frame), strafe_<metres>, object_<metres>.
    #[arg(long, default_value = "strafe_0.1")]
    motion: String,
    /// forward or deferred.
    #[arg(long, default_value = "forward")]
    shading: String,
    /// cso, cso:<tolerance> or aso.
    #[arg(long, default_value = "cso")]
    detection: String,
    /// auto (the kit's measured choice), msaa2x or offset_passes.
    #[arg(long, default_value = "auto")]
    path: String,
    #[arg(long, default_value_t = 4, value_parser = frame_count())]
    frames: u32,
    #[arg(long, default_value_t = 32, value_parser = light_count())]
    lights: u32,
    #[arg(long, default_value_t = 5)]
    seed: u32,
}

/// Checkerboard rendering: full resolution, checkerboarding (forward/deferred × ASO/CSO × path)
/// and a half-resolution upscale, on static and moving sequences.
#[derive(clap::Args)]
pub struct ReportArgs {
    #[arg(long)]
    out: PathBuf,
    #[arg(long, default_value = "320x180", value_parser = parse_size)]
    size: (u32, u32),
    #[arg(long, default_value_t = 64, value_parser = light_count())]
    lights: u32,
    /// Frames a sequence runs (the first is warm-up, the last is measured).
    #[arg(long, default_value_t = 6, value_parser = frame_count())]
    frames: u32,
    /// Sequences: static, pan_<x>x<y>, strafe_<metres>, object_<metres> (default: one of each).
    #[arg(long, value_delimiter = ',')]
    motions: Vec<String>,
}

impl Technique for Cbr {
    const NAME: &'static str = "cbr";
    type Render = RenderArgs;
    type Report = ReportArgs;

    fn check_render(args: &RenderArgs) -> Result<()> {
        Motion::parse(&args.motion)?;
        fragkit::cbr::Shading::parse(&args.shading)?;
        fragkit::cbr::Detection::parse(&args.detection)?;
        Ok(())
    }

    fn render_out(args: &RenderArgs) -> &Path {
        &args.out
    }

    fn pictures(gpu: &Gpu, args: &RenderArgs) -> Result<Vec<(String, image::RgbaImage)>> {
        fragkit::cbr::renderer::check_checkerboard_screen(gpu, args.size).context("--size")?;
        let scene = fragkit::cbr::scene::textured_corridor(args.seed, args.lights, Motion::parse(&args.motion)?);
        let path = fragkit::cbr::sampling::CheckerboardPath::choose(gpu, &args.path)?;
        let config = fragkit::cbr::CheckerboardConfig {
            detection: fragkit::cbr::Detection::parse(&args.detection)?,
            ..fragkit::cbr::CheckerboardConfig::new(args.size, path, fragkit::cbr::Shading::parse(&args.shading)?)
        };
        println!("path: {}", path.name());
        fragkit::cbr::pictures::render_all(gpu, &scene, config, args.frames)
    }

    fn check_report(args: &ReportArgs) -> Result<()> {
        for motion in &args.motions {
            Motion::parse(motion)?;
        }
        anyhow::ensure!(
            args.frames >= 2,
            "--frames {}: a sequence needs at least 2 frames (warm-up and one timed)",
            args.frames
        );
        Ok(())
    }

    fn report(gpu: &Gpu, args: &ReportArgs, progress: &dyn Fn(String)) -> Result<PathBuf> {
        fragkit::cbr::renderer::check_checkerboard_screen(gpu, args.size).context("--size")?;
        let motions = args.motions.iter().map(|m| Motion::parse(m)).collect::<Result<Vec<_>>>()?;
        let defaults = fragkit::cbr::report::CbrSweep::for_adapter(gpu);
        let sweep = fragkit::cbr::report::CbrSweep {
            size: args.size,
            lights: args.lights,
            frames: args.frames,
            motions: if motions.is_empty() { defaults.motions.clone() } else { motions },
            ..defaults
        };
        let rows = fragkit::cbr::report::run_sweep(gpu, &sweep, |sequence| progress(sequence.to_owned()))?;
        fragkit_results::plot::tradeoff(&fragkit::cbr::report::write_report(
            &args.out,
            &gpu.description,
            &sweep,
            &rows,
        )?)?;
        Ok(args.out.join("cbr_report.md"))
    }
}
