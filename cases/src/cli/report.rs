//! `fragkit report <technique>`: sweep a technique's settings and write error against GPU time
//! (JSON, markdown, PNG plot).

use std::path::PathBuf;

use anyhow::{Context, Result};
use clap::Subcommand;
use fragkit::gpu::{AdapterSelector, Gpu};

use super::{frame_count, light_count, lod_level, oit_scene, parse_size};

#[derive(Subcommand)]
pub enum ReportTechnique {
    /// OIT: method × sample count × frames × post-filter, against the exact composite.
    Oit {
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
    },
    /// CPS: policy × top level × light count × composite, against full resolution and the naive way.
    Cps {
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
    },
    /// CBR: full resolution, checkerboarding (forward/deferred × ASO/CSO × path) and a half-resolution
    /// upscale, on static and moving sequences.
    Cbr {
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
    },
}

pub fn report(selector: &AdapterSelector, technique: ReportTechnique) -> Result<()> {
    match technique {
        ReportTechnique::Oit { out, size, scene, frames, seed } => {
            let scene = oit_scene(&scene, seed)?;
            let sweep = fragkit::oit::report::OitSweep { size, frame_counts: frames, seed };
            let gpu = Gpu::open(selector)?;
            fragkit::deferred::gbuffer::check_size(&gpu, size).context("--size")?;
            let progress = indicatif::ProgressBar::new_spinner();
            let rows = gpu.scoped("oit report", || {
                fragkit::oit::report::run_sweep(&gpu, &scene, &sweep, |row| {
                    progress.set_message(format!("{} {}x {} frames", row.method, row.samples, row.frames));
                    progress.tick();
                })
            })?;
            progress.finish_and_clear();
            fragkit::oit::report::write_report(&out, &gpu.description, &rows)?;
            println!("{}", out.join("oit_report.md").display());
        }
        ReportTechnique::Cps { out, size, lights, max_levels, repeats } => {
            let sweep = fragkit::cps::report::CpsSweep {
                size,
                light_counts: lights,
                max_levels,
                repeats,
                ..Default::default()
            };
            let gpu = Gpu::open(selector)?;
            fragkit::deferred::gbuffer::check_size(&gpu, size).context("--size")?;
            let progress = indicatif::ProgressBar::new_spinner();
            let rows = gpu.scoped("cps report", || {
                fragkit::cps::report::run_sweep(&gpu, &sweep, |row| {
                    progress.set_message(format!(
                        "{} lights, {} {} level {}",
                        row.lights, row.method, row.composite, row.max_level
                    ));
                    progress.tick();
                })
            })?;
            progress.finish_and_clear();
            fragkit::cps::report::write_report(&out, &gpu.description, &rows)?;
            println!("{}", out.join("cps_report.md").display());
        }
        ReportTechnique::Cbr { out, size, lights, frames, motions } => {
            let motions = motions.iter().map(|m| fragkit::cbr::scene::Motion::parse(m)).collect::<Result<Vec<_>>>()?;
            anyhow::ensure!(
                frames >= 2,
                "--frames {frames}: a sequence needs at least 2 frames (warm-up and one timed)"
            );
            let gpu = Gpu::open(selector)?;
            fragkit::cbr::renderer::check_checkerboard_screen(&gpu, size).context("--size")?;
            let defaults = fragkit::cbr::report::CbrSweep::for_adapter(&gpu);
            let sweep = fragkit::cbr::report::CbrSweep {
                size,
                lights,
                frames,
                motions: if motions.is_empty() { defaults.motions.clone() } else { motions },
                ..defaults
            };
            let progress = indicatif::ProgressBar::new_spinner();
            let rows = gpu.scoped("cbr report", || {
                fragkit::cbr::report::run_sweep(&gpu, &sweep, |sequence| {
                    progress.set_message(sequence.to_owned());
                    progress.tick();
                })
            })?;
            progress.finish_and_clear();
            fragkit::cbr::report::write_report(&out, &gpu.description, &sweep, &rows)?;
            println!("{}", out.join("cbr_report.md").display());
        }
    }
    Ok(())
}
