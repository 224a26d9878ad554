//! The technique table: each technique (one file here) says how to render its pictures and how
//! to sweep its report; `fragkit render`, `fragkit report` and `fragkit bench` dispatch through
//! the one list in [`techniques!`], and do the shared part (output folder, device, size check,
//! progress, writing) once.

pub mod cbr;
pub mod cps;
pub mod oit;

use std::path::{Path, PathBuf};

use anyhow::{Context, Result};
use fragkit::gpu::{AdapterSelector, Gpu};

/// What `render` and `report` need of a technique.
pub trait Technique {
    /// Prefix of its files and name of its bench (`fragkit bench <name>`).
    const NAME: &'static str;
    type Render: clap::Args;
    type Report: clap::Args;

    /// Checks the arguments that need no device (scene names, frame counts).
    fn check_render(args: &Self::Render) -> Result<()>;
    /// Renders the intermediates and results a person looks at, by name.
    fn pictures(gpu: &Gpu, args: &Self::Render) -> Result<Vec<(String, image::RgbaImage)>>;
    fn render_out(args: &Self::Render) -> &Path;

    fn check_report(args: &Self::Report) -> Result<()>;
    /// Runs the sweep, telling `progress` what it is at, and writes the report into its folder;
    /// returns the markdown file's path.
    fn report(gpu: &Gpu, args: &Self::Report, progress: &dyn Fn(String)) -> Result<PathBuf>;
}

/// `fragkit render <technique>`: the pictures as PNGs, one path printed per file.
pub fn render<T: Technique>(selector: &AdapterSelector, args: T::Render) -> Result<()> {
    T::check_render(&args)?;
    let out = T::render_out(&args);
    std::fs::create_dir_all(out).with_context(|| format!("creating {}", out.display()))?;
    let gpu = Gpu::open(selector)?;
    let pictures = gpu.scoped(&format!("render {}", T::NAME), || T::pictures(&gpu, &args))?;
    for (name, image) in pictures {
        let path = out.join(format!("{}_{name}.png", T::NAME));
        image.save(&path).with_context(|| format!("writing {}", path.display()))?;
        println!("{}", path.display());
    }
    Ok(())
}

/// `fragkit report <technique>`: the sweep with a progress line; prints the markdown's path.
pub fn report<T: Technique>(selector: &AdapterSelector, args: T::Report) -> Result<()> {
    T::check_report(&args)?;
    let gpu = Gpu::open(selector)?;
    let progress = indicatif::ProgressBar::new_spinner();
    let written = gpu.scoped(&format!("{} report", T::NAME), || {
        T::report(&gpu, &args, &|at| {
            progress.set_message(at);
            progress.tick();
        })
    })?;
    progress.finish_and_clear();
    println!("{}", written.display());
    Ok(())
}

/// The table: each technique's variant in the `render` and `report` subcommands, dispatched to
/// its implementation. A new technique is one line here and one file beside this one.
macro_rules! techniques {
    ($($variant:ident => $technique:ty),* $(,)?) => {
        #[derive(clap::Subcommand)]
        pub enum RenderCommand {
            $($variant(<$technique as Technique>::Render),)*
        }

        #[derive(clap::Subcommand)]
        pub enum ReportCommand {
            $($variant(<$technique as Technique>::Report),)*
        }

        impl RenderCommand {
            pub fn run(self, selector: &AdapterSelector) -> Result<()> {
                match self {
                    $(Self::$variant(args) => render::<$technique>(selector, args),)*
                }
            }
        }

        impl ReportCommand {
            pub fn run(self, selector: &AdapterSelector) -> Result<()> {
                match self {
                    $(Self::$variant(args) => report::<$technique>(selector, args),)*
                }
            }
        }
    };
}

// Each subcommand's help is its arguments' doc comment (in the technique's file).
techniques! {
    Oit => oit::Oit,
    Cps => cps::Cps,
    Cbr => cbr::Cbr,
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_technique_has_a_bench_of_its_name() {
        for name in [oit::Oit::NAME, cps::Cps::NAME, cbr::Cbr::NAME] {
            assert!(fragkit::bench::TECHNIQUES.contains(&name), "fragkit bench {name}");
        }
    }
}
