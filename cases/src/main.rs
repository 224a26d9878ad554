//! `fragkit`: list adapters, measure capabilities, list and run the conformance cases, render and
//! report the techniques, merge shards' reports, compare two runs. Each subcommand lives in `cli/`.

mod cli;

use std::process::ExitCode;

use anyhow::Result;
use clap::Parser;
use cli::{Cli, Command};
use fragkit::gpu::AdapterSelector;

fn main() -> ExitCode {
    let cli = Cli::parse();
    // wgpu's and the drivers' records are captured (into the reports) and printed only with -v;
    // RUST_LOG prints them all as they come, for developers.
    if std::env::var_os("RUST_LOG").is_some() {
        env_logger::Builder::from_env(env_logger::Env::default()).init();
    } else if let Err(e) = fragkit::harness::diagnostics::capture(cli.verbose) {
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
    let selector = AdapterSelector { backend: cli.backend, adapter_name: cli.adapter };
    match cli.command {
        Command::Adapters => cli::adapters::adapters(cli.verbose)?,
        Command::Caps { json } => cli::caps::caps(&selector, json)?,
        Command::List { pattern } => cli::list::list(pattern)?,
        Command::Render { technique } => technique.run(&selector)?,
        Command::Report { technique } => technique.run(&selector)?,
        Command::Bench(args) => cli::bench::bench(&selector, args)?,
        Command::Check(args) => return cli::check::check(&selector, args, cli.verbose),
        Command::Merge(args) => return cli::merge::merge(args),
        Command::Compare(args) => return cli::compare::compare_reports(args),
        Command::Html(args) => cli::html::html(args)?,
        Command::Import(args) => cli::import::import(args)?,
        Command::History(args) => cli::history::history(args)?,
    }
    Ok(ExitCode::SUCCESS)
}
