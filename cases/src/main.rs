//! `fragkit`: list adapters, measure capabilities, list and run the conformance cases, render and
//! report the techniques, merge shards' reports, compare two runs. Each subcommand lives in `cli/`.

mod cli;

use std::process::ExitCode;

use anyhow::Result;
use clap::Parser;
use cli::{Cli, Command};
use fragkit::gpu::AdapterSelector;

fn main() -> ExitCode {
    env_logger::Builder::from_env(env_logger::Env::default().default_filter_or("warn")).init();
    let cli = Cli::parse();
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
        Command::Adapters => cli::adapters::adapters()?,
        Command::Caps { json } => cli::caps::caps(&selector, json)?,
        Command::List { pattern } => cli::list::list(pattern)?,
        Command::Render { technique } => technique.run(&selector)?,
        Command::Report { technique } => technique.run(&selector)?,
        Command::Bench(args) => cli::bench::bench(&selector, args)?,
        Command::Check(args) => return cli::check::check(&selector, args),
        Command::Merge(args) => return cli::merge::merge(args),
        Command::Compare(args) => return cli::compare::compare_reports(args),
        Command::Html(args) => cli::html::html(args)?,
        Command::Import(args) => cli::import::import(args)?,
        Command::History(args) => cli::history::history(args)?,
    }
    Ok(ExitCode::SUCCESS)
}
