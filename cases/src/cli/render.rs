//! `fragkit render <technique>`: a technique's intermediates and results as PNGs for a person.

use std::path::PathBuf;

use anyhow::{Context, Result};
use clap::Subcommand;
use fragkit::gpu::{AdapterSelector, Gpu};

use super::{frame_count, light_count, lod_level, oit_scene, parse_size};

#[derive(Subcommand)]
pub enum Technique {
    /// Order-independent transparency: every method's image and error map against the exact composite.
    Oit {
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
    },
    /// Coarse pixel shading: LOD buffer, stencil masks, lit mips, the three composites.
    Cps {
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
    },
    /// Checkerboard rendering: frames N−1 and N, motion, pixel sources, reconstruction, error map.
    Cbr {
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
    },
}

pub fn render(selector: &AdapterSelector, technique: Technique) -> Result<()> {
    match technique {
        Technique::Oit { out, size, scene, samples, frames, seed } => {
            let scene = oit_scene(&scene, seed)?;
            std::fs::create_dir_all(&out).with_context(|| format!("creating {}", out.display()))?;
            let gpu = Gpu::open(selector)?;
            let offered = fragkit::caps::common_sample_counts(&gpu);
            anyhow::ensure!(
                offered.contains(&samples),
                "--samples {samples}: this adapter offers sample counts {offered:?}"
            );
            fragkit::deferred::gbuffer::check_size(&gpu, size).context("--size")?;
            let pictures = gpu.scoped("render oit", || {
                fragkit::oit::pictures::render_all(&gpu, &scene, size, samples, frames, seed)
            })?;
            for (name, image) in pictures {
                let path = out.join(format!("oit_{}_{name}.png", scene.name));
                image.save(&path).with_context(|| format!("writing {}", path.display()))?;
                println!("{}", path.display());
            }
        }
        Technique::Cps { out, size, policy, max_level, lights, seed } => {
            let policy = fragkit::cps::LodPolicy::parse(&policy)?;
            std::fs::create_dir_all(&out).with_context(|| format!("creating {}", out.display()))?;
            let gpu = Gpu::open(selector)?;
            fragkit::deferred::gbuffer::check_size(&gpu, size).context("--size")?;
            let pictures = gpu.scoped("render cps", || {
                fragkit::cps::pictures::render_all(&gpu, size, policy, max_level, lights, seed)
            })?;
            for (name, image) in pictures {
                let path = out.join(format!("cps_{name}.png"));
                image.save(&path).with_context(|| format!("writing {}", path.display()))?;
                println!("{}", path.display());
            }
        }
        Technique::Cbr { out, size, motion, shading, detection, path, frames, lights, seed } => {
            let motion = fragkit::cbr::scene::Motion::parse(&motion)?;
            let shading = fragkit::cbr::Shading::parse(&shading)?;
            let detection = fragkit::cbr::Detection::parse(&detection)?;
            std::fs::create_dir_all(&out).with_context(|| format!("creating {}", out.display()))?;
            let gpu = Gpu::open(selector)?;
            fragkit::cbr::renderer::check_checkerboard_screen(&gpu, size).context("--size")?;
            let scene = fragkit::cbr::scene::textured_corridor(seed, lights, motion);
            let path = fragkit::cbr::sampling::CheckerboardPath::choose(&gpu, &path)?;
            let config = fragkit::cbr::CheckerboardConfig {
                detection,
                ..fragkit::cbr::CheckerboardConfig::new(size, path, shading)
            };
            println!("path: {}", path.name());
            let pictures =
                gpu.scoped("render cbr", || fragkit::cbr::pictures::render_all(&gpu, &scene, config, frames))?;
            for (name, image) in pictures {
                let path = out.join(format!("cbr_{name}.png"));
                image.save(&path).with_context(|| format!("writing {}", path.display()))?;
                println!("{}", path.display());
            }
        }
    }
    Ok(())
}
