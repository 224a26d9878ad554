//! `fragkit adapters`: every adapter on every backend, as a table, then what each configuration
//! of the adapter matrix resolves to on this machine (each probed in a process of its own, with
//! its environment), or why it is absent. What probing the backends logs (EGL looking for a DRI
//! driver on a machine without one) is kept out of it; `-v` prints it.

use std::process::ExitCode;

use anyhow::{Context, Result};
use fragkit::gpu::{AdapterDescription, AdapterSelector, Gpu, all_adapters, select_adapter};
use serde::{Deserialize, Serialize};

use super::matrix::{MatrixArgs, Show, print_table, run_children};

#[derive(clap::Args)]
pub struct AdaptersArgs {
    /// Print, as one JSON line, the adapter --backend/--adapter select and whether a device opens
    /// on it (what each matrix configuration's process answers).
    #[arg(long, hide = true)]
    selected: bool,
    #[command(flatten)]
    matrix: MatrixArgs,
}

/// A configuration's answer: the adapter it resolved to and whether a device opened.
#[derive(Serialize, Deserialize)]
struct Resolved {
    adapter: Option<AdapterDescription>,
    /// None when the device opened; else why not.
    problem: Option<String>,
}

pub fn adapters(selector: &AdapterSelector, args: AdaptersArgs, verbose: bool) -> Result<ExitCode> {
    if args.selected {
        let resolved = match select_adapter(selector) {
            Ok(adapter) => {
                let description = AdapterDescription::of(&adapter.get_info());
                let problem = Gpu::from_adapter(adapter).err().map(|e| format!("the device does not open: {e:#}"));
                Resolved { adapter: Some(description), problem }
            }
            Err(e) => Resolved { adapter: None, problem: Some(format!("{e:#}")) },
        };
        println!("{}", serde_json::to_string(&resolved)?);
        return Ok(ExitCode::SUCCESS);
    }
    list_adapters(verbose)?;
    println!();
    resolve_matrix(&args.matrix)
}

/// Each configuration's process prints its `Resolved` line into its log; the table shows them.
fn resolve_matrix(args: &MatrixArgs) -> Result<ExitCode> {
    let matrix = args.load()?;
    let names = args.matrix.clone().unwrap_or_else(|| "all".into());
    let reports = std::env::temp_dir().join(format!("fragkit-adapters-{}", std::process::id()));
    let runs = run_children(&matrix, &names, &reports, Show::Nothing, |_| vec!["adapters".into(), "--selected".into()])?;
    let mut rows = vec![["configuration", "backend", "environment", "resolves to", "driver info"].map(String::from)];
    for run in &runs {
        let c = run.configuration;
        let environment: Vec<String> = c.env.iter().map(|(k, v)| format!("{k}={v}")).collect();
        let (resolved, info) = match &run.absent_because {
            Some(why) => (format!("absent: {why}"), String::new()),
            None => {
                let log = std::fs::read_to_string(&run.log).with_context(|| format!("reading {}", run.log.display()))?;
                match log.lines().rev().find_map(|line| serde_json::from_str::<Resolved>(line).ok()) {
                    Some(Resolved { adapter: Some(a), problem }) => (
                        match problem {
                            None => a.name.clone(),
                            Some(problem) => format!("{}: {problem}", a.name),
                        },
                        a.driver_info.trim().to_owned(),
                    ),
                    Some(Resolved { adapter: None, problem }) => {
                        (format!("no adapter: {}", problem.unwrap_or_default()), String::new())
                    }
                    None => (format!("the probe ended without an answer ({})", run.ending()), String::new()),
                }
            }
        };
        rows.push([c.name.clone(), c.backend.clone(), environment.join(" "), resolved, info]);
    }
    std::fs::remove_dir_all(&reports).ok();
    print_table(&rows);
    Ok(ExitCode::SUCCESS)
}

fn list_adapters(verbose: bool) -> Result<()> {
    let adapters: Vec<AdapterDescription> =
        all_adapters().iter().map(|a| AdapterDescription::of(&a.get_info())).collect();
    let logged = fragkit::harness::diagnostics::take();
    if adapters.is_empty() {
        anyhow::bail!(
            "no GPU adapter found. Install a Vulkan driver; on Debian `apt-get install mesa-vulkan-drivers` gives lavapipe"
        );
    }
    let width = |column: fn(&AdapterDescription) -> &str, title: &str| {
        adapters.iter().map(|d| column(d).chars().count()).max().unwrap_or(0).max(title.len())
    };
    let widths = [
        width(|d| &d.backend, "backend"),
        width(|d| &d.name, "adapter"),
        width(|d| &d.device_type, "type"),
        width(|d| &d.driver, "driver"),
    ];
    let row = |cells: [&str; 5]| {
        println!(
            "{:<w0$}  {:<w1$}  {:<w2$}  {:<w3$}  {}",
            cells[0],
            cells[1],
            cells[2],
            cells[3],
            cells[4],
            w0 = widths[0],
            w1 = widths[1],
            w2 = widths[2],
            w3 = widths[3]
        )
    };
    row(["backend", "adapter", "type", "driver", "driver info"]);
    for d in &adapters {
        row([&d.backend, &d.name, &d.device_type, &d.driver, d.driver_info.trim()]);
    }
    if !logged.is_empty() && !verbose {
        let plural = if logged.len() == 1 { "" } else { "s" };
        println!("({} log record{plural} from probing the backends hidden; -v prints them)", logged.len());
    }
    Ok(())
}
