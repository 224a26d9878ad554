//! `--matrix`: a subcommand run over the adapter matrix (`cases/adapters.toml`), each
//! configuration in a child process of this binary with its environment set there (drivers read
//! it when they load), its reports in a folder of the run's, and one summary at the end.

use std::ffi::OsString;
use std::path::{Path, PathBuf};
use std::process::{Child, Command, ExitStatus, Stdio};

use anyhow::{Context, Result, bail};
use fragkit::harness::child_process::{arguments_without, ending, log_tail};

use super::configurations::{Configuration, Matrix};

#[derive(clap::Args, Clone, Debug)]
pub struct MatrixArgs {
    /// Run over the adapter matrix instead of one adapter: `all`, configuration names separated
    /// by commas (`fragkit adapters` lists them), or `found`: every adapter the instance
    /// enumerates here, named by backend and adapter. Each runs in a process of its own.
    #[arg(long, value_name = "NAMES")]
    pub matrix: Option<String>,
    /// The adapter matrix file (default: the one built in, cases/adapters.toml).
    #[arg(long, value_name = "FILE")]
    pub adapters_file: Option<PathBuf>,
    /// With --matrix: the folder for each configuration's reports and log.
    #[arg(long, value_name = "DIR", default_value = "fragkit-matrix")]
    pub reports: PathBuf,
}

impl MatrixArgs {
    pub fn load(&self) -> Result<Matrix> {
        match &self.adapters_file {
            Some(path) => Matrix::load(path),
            None => Matrix::built_in(),
        }
    }

    /// The matrix `names` runs over, and the names to select from it: `found` is every adapter
    /// enumerated here, all of them; anything else names configurations of the matrix file.
    pub fn resolve(&self, names: &str) -> Result<(Matrix, String)> {
        if names.trim() != "found" {
            return Ok((self.load()?, names.to_owned()));
        }
        let found: Vec<fragkit_report::AdapterDescription> =
            fragkit::gpu::all_adapters().iter().map(|adapter| fragkit::gpu::describe(&adapter.get_info())).collect();
        anyhow::ensure!(!found.is_empty(), "--matrix found: the instance enumerates no adapter here");
        Ok((Matrix::found(&found), "all".to_owned()))
    }
}

/// What became of a configuration's child.
pub enum ChildEnd {
    /// The configuration is absent from this machine (why); no child ran.
    Absent(String),
    Exited(ExitStatus),
}

/// What a configuration's child left behind.
pub struct ChildRun<'a> {
    pub configuration: &'a Configuration,
    pub end: ChildEnd,
    pub log: PathBuf,
}

impl ChildRun<'_> {
    /// How the child ended, in words: its exit code, the signal that killed it, or why none ran.
    pub fn ending(&self) -> String {
        match &self.end {
            ChildEnd::Absent(why) => format!("absent: {why}"),
            ChildEnd::Exited(status) => ending(status),
        }
    }

    /// True when a child ran and did not exit 0.
    pub fn failed(&self) -> bool {
        matches!(&self.end, ChildEnd::Exited(status) if !status.success())
    }
}

/// Refuses what --matrix cannot combine with: a backend, adapter or driver chosen for all
/// configurations.
pub fn check_selection_is_free(selector: &fragkit::gpu::AdapterSelector) -> Result<()> {
    if selector.backend.is_some() || selector.adapter_name.is_some() || selector.driver_info.is_some() {
        bail!(
            "--matrix picks each configuration's backend, adapter and driver; drop --backend/--adapter/--driver-info (or WGPU_BACKEND/WGPU_ADAPTER_NAME)"
        );
    }
    Ok(())
}

/// What the parent prints while the children run.
#[derive(Clone, Copy, PartialEq, Eq)]
pub enum Show {
    Nothing,
    /// A line as each configuration starts, or why it is absent.
    Progress,
    /// Progress, then each configuration's whole output as it ends.
    Logs,
}

/// Runs this binary once per configuration of `names`, `jobs` at once: with
/// `arguments(configuration)` after `--backend B --adapter A`, the variables any configuration
/// sets cleared and this one's set, stdout and stderr into `<reports>/<name>.log`. The runs come
/// back in the configurations' order.
pub fn run_children<'a>(
    matrix: &'a Matrix,
    names: &str,
    reports: &Path,
    show: Show,
    jobs: usize,
    arguments: impl Fn(&Configuration) -> Vec<OsString>,
) -> Result<Vec<ChildRun<'a>>> {
    let configurations = matrix.select(names)?;
    std::fs::create_dir_all(reports).with_context(|| format!("creating the matrix folder {}", reports.display()))?;
    let program = std::env::current_exe().context("finding this program to run each configuration")?;
    let matrix_variables: Vec<&String> = matrix.configurations.iter().flat_map(|c| c.env.keys()).collect();
    let mut ends: Vec<Option<ChildEnd>> = Vec::new();
    let mut running: Vec<(usize, Child)> = Vec::new();
    let log_of = |configuration: &Configuration| reports.join(format!("{}.log", configuration.file_stem()));
    let finished = |index: usize, status: ExitStatus, ends: &mut Vec<Option<ChildEnd>>| {
        let configuration: &Configuration = configurations[index];
        if show == Show::Logs {
            println!(
                "== {} ({})\n{}",
                configuration.name,
                ending(&status),
                log_tail(&log_of(configuration), usize::MAX)
            );
        }
        ends[index] = Some(ChildEnd::Exited(status));
    };
    for (index, configuration) in configurations.iter().enumerate() {
        let log = log_of(configuration);
        if let Some(why) = configuration.absent_because() {
            if show != Show::Nothing {
                println!("{}: absent ({why})", configuration.name);
            }
            ends.push(Some(ChildEnd::Absent(why)));
            continue;
        }
        ends.push(None);
        // A free slot first: at most `jobs` configurations run at once.
        while running.len() >= jobs.max(1) {
            let mut still = Vec::new();
            for (at, mut child) in running.drain(..) {
                match child.try_wait().with_context(|| format!("waiting for {}", configurations[at].name))? {
                    Some(status) => finished(at, status, &mut ends),
                    None => still.push((at, child)),
                }
            }
            running = still;
            if running.len() >= jobs.max(1) {
                std::thread::sleep(std::time::Duration::from_millis(50));
            }
        }
        let log_file = std::fs::File::create(&log).with_context(|| format!("creating {}", log.display()))?;
        let mut command = Command::new(&program);
        for variable in &matrix_variables {
            command.env_remove(variable);
        }
        command
            .envs(&configuration.env)
            .env_remove("WGPU_BACKEND")
            .env_remove("WGPU_ADAPTER_NAME")
            .arg("--backend")
            .arg(&configuration.backend)
            .arg("--adapter")
            .arg(&configuration.adapter)
            .args(configuration.driver_info.iter().flat_map(|glob| ["--driver-info", glob.as_str()]))
            .args(arguments(configuration))
            .stdin(Stdio::null())
            .stdout(log_file.try_clone().context("sharing the log file")?)
            .stderr(log_file);
        if show != Show::Nothing {
            println!("{}: running ({})", configuration.name, log.display());
        }
        let child =
            command.spawn().with_context(|| format!("starting {} for {}", program.display(), configuration.name))?;
        running.push((index, child));
    }
    for (at, mut child) in running {
        let status = child.wait().with_context(|| format!("waiting for {}", configurations[at].name))?;
        finished(at, status, &mut ends);
    }
    Ok(configurations
        .into_iter()
        .zip(ends)
        .map(|(configuration, end)| ChildRun {
            configuration,
            end: end.unwrap_or_else(|| ChildEnd::Absent("never started".to_owned())),
            log: log_of(configuration),
        })
        .collect())
}

/// `caps`/`bench --matrix`: each configuration in its own process, one after another (never two
/// at once: timings would share the CPU), its output shown in turn, its JSON written to
/// `<reports>/<name>.<command>.json` (and, with --db, its own database run).
pub fn run_each_showing_output(
    selector: &fragkit::gpu::AdapterSelector,
    args: &MatrixArgs,
    names: &str,
    command: &str,
) -> Result<()> {
    check_selection_is_free(selector)?;
    let (matrix, names) = args.resolve(names)?;
    let names = names.as_str();
    let reports = &args.reports;
    let inherited = arguments_without(
        std::env::args_os().skip(1),
        &["--matrix", "--adapters-file", "--reports", "--json", "--backend", "--adapter", "--driver-info"],
        &[],
    );
    // One after another: their timings would share the CPU.
    let runs = run_children(&matrix, names, reports, Show::Logs, 1, |configuration| {
        let mut arguments = inherited.clone();
        let json = reports.join(format!("{}.{command}.json", configuration.file_stem()));
        arguments.extend(["--json".into(), json.into()]);
        arguments
    })?;
    let failed: Vec<&str> = runs.iter().filter(|run| run.failed()).map(|run| run.configuration.name.as_str()).collect();
    anyhow::ensure!(
        failed.is_empty(),
        "{command} failed on {}; their logs are in {}",
        failed.join(", "),
        reports.display()
    );
    Ok(())
}

/// Prints rows as columns padded to their widest cell; the first row is the heading.
pub fn print_table<const N: usize>(rows: &[[String; N]]) {
    let widths: Vec<usize> = (0..N).map(|i| rows.iter().map(|r| r[i].chars().count()).max().unwrap_or(0)).collect();
    for row in rows {
        let cells: Vec<String> = row.iter().zip(&widths).map(|(cell, &w)| format!("{cell:<w$}")).collect();
        println!("{}", cells.join("  ").trim_end());
    }
}
