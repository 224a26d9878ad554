//! `fragkit`: list adapters, measure capabilities, list and run the conformance cases, render and
//! report the techniques, merge shards' reports, compare two runs. Each subcommand lives in `cli/`.

mod cli;

use std::process::ExitCode;

use anyhow::Result;
use clap::Parser;
use cli::{Cli, Command};
use fragkit::gpu::AdapterSelector;

/// Without `XDG_RUNTIME_DIR` the window-system client libraries Mesa's drivers load print
/// "error: XDG_RUNTIME_DIR is invalid or not set" (harmless: the kit renders offscreen). Give
/// them a private one, as a login session would.
#[cfg(unix)]
fn ensure_runtime_dir() {
    if std::env::var_os("XDG_RUNTIME_DIR").is_some() {
        return;
    }
    let user = std::env::var("USER").unwrap_or_else(|_| "user".into());
    let dir = std::env::temp_dir().join(format!("fragkit-runtime-{user}"));
    let private = {
        use std::os::unix::fs::DirBuilderExt;
        std::fs::DirBuilder::new().recursive(true).mode(0o700).create(&dir).is_ok()
    };
    if private {
        // SAFETY: the first thing main does, before any thread exists.
        unsafe { std::env::set_var("XDG_RUNTIME_DIR", &dir) };
    }
}

#[cfg(not(unix))]
fn ensure_runtime_dir() {}

fn main() -> ExitCode {
    ensure_runtime_dir();
    let cli = Cli::parse();
    // wgpu's and the drivers' records are captured (into the reports) and printed only with -v;
    // RUST_LOG prints them all as they come, for developers.
    if std::env::var_os("RUST_LOG").is_some() {
        env_logger::Builder::from_env(env_logger::Env::default()).init();
    } else if let Err(e) = fragkit::diagnostics::capture(cli.verbose) {
        eprintln!("error: {e:#}");
        return ExitCode::from(2);
    }
    match run(cli) {
        Ok(code) => code,
        Err(error) => {
            eprintln!("error: {error:#}");
            ExitCode::from(2)
        }
    }
}

fn run(cli: Cli) -> Result<ExitCode> {
    fragkit::shaders::check_shader_dir()?;
    let selector = AdapterSelector {
        backend: cli.backend,
        adapter_name: cli.adapter,
        driver_info: cli.driver_info,
        validation: cli.validation,
    };
    match cli.command {
        Command::Adapters(args) => return cli::adapters::adapters(&selector, args, cli.verbose),
        Command::Caps(args) => cli::caps::caps(&selector, args)?,
        Command::List { pattern } => cli::list::list(pattern, cli.verbose)?,
        Command::Render { technique } => technique.run(&selector)?,
        Command::Report { technique } => technique.run(&selector)?,
        Command::Bench(args) => cli::bench::bench(&selector, args)?,
        Command::Check(args) => return cli::check::check(&selector, *args, cli.verbose),
        Command::Merge(args) => return cli::merge::merge(args),
        Command::Compare(args) => return cli::compare::compare_reports(args),
        Command::Html(args) => cli::html::html(args)?,
        Command::Import(args) => cli::import::import(args)?,
        Command::History(args) => cli::history::history(args)?,
    }
    Ok(ExitCode::SUCCESS)
}
