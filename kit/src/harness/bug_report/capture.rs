//! The case run again for its bug report, alone in a child process of its own, under the
//! backend's capture tool where the kit has one: apitrace for GL (the child's EGL and GL calls,
//! replayable headless with `eglretrace`). The child also keeps what the case read back
//! (`FRAGKIT_READBACK_DIR`) and its evidence images; its record is held to the first run's.

use std::ffi::OsString;
use std::io::Write;
use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};
use std::time::{Duration, Instant};

use anyhow::{Context, Result, bail};
use fragkit_report::expectations::FailureKind;
use fragkit_report::report::{CaseRecord, is_timing_metric};

use super::super::stream::{StreamLine, read_new_lines};
use crate::graphics_debugger::DEBUGGER_CAPTURE_ENV;
use crate::readback_log::READBACK_DIR_ENV;

/// A capture tool: what runs the child under it, and where it comes from.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct CaptureTool {
    /// The program that records (`apitrace`, `renderdoccmd`).
    pub program: &'static str,
    /// What a replay needs (`eglretrace`; RenderDoc's Python module).
    pub replayer: &'static str,
    /// The Debian packages holding them.
    pub packages: &'static str,
    /// The capture's file name in the report's `capture/`.
    pub file: &'static str,
}

/// apitrace 11.1 (Debian 12): `apitrace trace --api egl` records the GL calls of the process it
/// starts; `eglretrace` replays them.
pub const APITRACE: CaptureTool =
    CaptureTool { program: "apitrace", replayer: "eglretrace", packages: "apitrace", file: "case.trace" };

/// RenderDoc 1.24 (Debian 12): `renderdoccmd capture` loads it into the process it starts, and
/// the runner brackets the case's GPU work with its in-application capture (wgpu's
/// `start_graphics_debugger_capture`); its Python module replays the capture headless.
/// gfxreconstruct 0.9.18 is not used: its replay goes frame by frame, from one present to the
/// next, and the kit never presents ("File did not contain any frames"); and under its default
/// memory tracking (`page_guard`) lavapipe's `kit.scissor.msaa` changes its result (1x: 640
/// pixels differ; the 4x target does not render) where with `GFXRECON_MEMORY_TRACKING_MODE`
/// `assisted` or `unassisted` it does not: the page guard's shadow copies of mapped memory are
/// at fault, not the driver.
pub const RENDERDOC: CaptureTool = CaptureTool {
    program: "renderdoccmd",
    replayer: "python3's renderdoc module",
    packages: "renderdoccmd python3-renderdoc",
    file: "case.rdc",
};

/// The tool that captures a run on `backend`, or why there is none.
pub fn tool_for(backend: &str) -> Result<CaptureTool, &'static str> {
    match backend {
        "gl" => Ok(APITRACE),
        "vulkan" => Ok(RENDERDOC),
        _ => Err("the kit captures GL (apitrace) and Vulkan (RenderDoc) runs only"),
    }
}

/// The Python that has RenderDoc's module (Debian's is the system one, whatever else is first on
/// the PATH), or None.
pub fn renderdoc_python() -> Option<&'static str> {
    ["/usr/bin/python3", "python3"]
        .into_iter()
        .find(|python| Command::new(python).args(["-c", "import renderdoc"]).output().is_ok_and(|o| o.status.success()))
}

/// Whether `program` runs here (found on the PATH).
pub fn on_path(program: &str) -> bool {
    std::env::var_os("PATH").is_some_and(|paths| std::env::split_paths(&paths).any(|dir| dir.join(program).is_file()))
}

/// An error naming the package where `backend`'s capture tool is missing.
pub fn check_tool(backend: &str) -> Result<()> {
    let Ok(tool) = tool_for(backend) else {
        return Ok(());
    };
    let missing = if !on_path(tool.program) {
        Some(tool.program)
    } else if tool == APITRACE && !on_path(APITRACE.replayer) {
        Some(APITRACE.replayer)
    } else if tool == RENDERDOC && renderdoc_python().is_none() {
        Some(RENDERDOC.replayer)
    } else {
        None
    };
    if let Some(missing) = missing {
        bail!(
            "--bug-report on the {backend} backend captures with {}, and {missing} is missing here (Debian: apt-get install {})",
            tool.program,
            tool.packages
        );
    }
    Ok(())
}

/// The case's second run.
pub struct CapturedRun {
    /// Its record, where the child wrote one.
    pub record: Option<CaseRecord>,
    /// The capture file, where a tool made one.
    pub trace: Option<PathBuf>,
    /// The tool, or why none ran.
    pub tool: Result<CaptureTool, &'static str>,
    /// What the child and the tool wrote on stderr, last lines.
    pub stderr_tail: String,
    /// How it ended, where not with a record.
    pub death: Option<Death>,
}

/// How a second run ended without a record.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum Death {
    /// It ended: its exit status or signal.
    Ended(String),
    /// The timeout passed (seconds) and it was killed.
    TimedOut(u64),
}

impl std::fmt::Display for Death {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            Self::Ended(status) => write!(f, "ended ({status}) without a record"),
            Self::TimedOut(seconds) => write!(f, "was killed after {seconds} s without a record"),
        }
    }
}

/// Runs `program arguments` (a supervised child's command line for one case run, streaming
/// into `folder/capture/record.stream`) under `backend`'s capture tool, handed case run 0,
/// keeping its read-backs in `folder/readbacks`; kills it after `timeout`.
pub fn rerun(
    program: &Path,
    arguments: &[OsString],
    backend: &str,
    folder: &Path,
    timeout: Duration,
) -> Result<CapturedRun> {
    let capture = folder.join("capture");
    let readbacks = folder.join("readbacks");
    for dir in [&capture, &readbacks] {
        std::fs::create_dir_all(dir).with_context(|| format!("creating {}", dir.display()))?;
    }
    let stream = capture.join("record.stream");
    let tool = tool_for(backend);
    let mut command = match tool {
        Ok(APITRACE) => {
            let mut command = Command::new(APITRACE.program);
            command.args(["trace", "--api", "egl", "--output"]).arg(capture.join(APITRACE.file)).arg(program);
            command
        }
        Ok(RENDERDOC) => {
            // The capture goes to `<template>_capture.rdc`; the runner starts and ends it.
            let mut command = Command::new(RENDERDOC.program);
            command
                .args(["capture", "--capture-file"])
                .arg(capture.join("renderdoc"))
                .arg("--wait-for-exit")
                .arg(program);
            command.env(DEBUGGER_CAPTURE_ENV, "1");
            command
        }
        _ => Command::new(program),
    };
    command
        .args(arguments)
        .arg("--child-stream")
        .arg(&stream)
        .env(READBACK_DIR_ENV, &readbacks)
        .stdin(Stdio::piped())
        .stdout(Stdio::null())
        .stderr(Stdio::piped());
    let mut child =
        command.spawn().with_context(|| format!("starting {:?} for the bug report", command.get_program()))?;
    child.stdin.take().context("the child's stdin")?.write_all(b"0\n").context("handing the case run to the child")?;
    let mut stderr = child.stderr.take().context("the child's stderr")?;
    let reader = std::thread::spawn(move || {
        let mut text = String::new();
        std::io::Read::read_to_string(&mut stderr, &mut text).ok();
        text
    });
    let started = Instant::now();
    let status = loop {
        if let Some(status) = child.try_wait().context("waiting for the bug report's run")? {
            break Some(status);
        }
        if started.elapsed() > timeout {
            child.kill().ok();
            child.wait().ok();
            break None;
        }
        std::thread::sleep(Duration::from_millis(20));
    };
    let stderr_text = reader.join().unwrap_or_default();
    let (lines, _) = read_new_lines(&stream, 0)?;
    let record = lines.into_iter().find_map(|line| match line {
        StreamLine::Record(record) => Some(*record),
        _ => None,
    });
    let death = match status {
        _ if record.is_some() => None,
        None => Some(Death::TimedOut(timeout.as_secs())),
        Some(status) => Some(Death::Ended(status.to_string())),
    };
    let tail: Vec<&str> = stderr_text.lines().rev().take(20).collect();
    let trace = match tool {
        Ok(tool) => captured_file(&capture, tool)?,
        Err(_) => None,
    };
    Ok(CapturedRun { record, trace, tool, stderr_tail: tail.into_iter().rev().collect::<Vec<_>>().join("\n"), death })
}

/// The capture a tool left in `capture`, as `tool.file`: apitrace writes it so; RenderDoc names
/// its file after the template and the capture.
fn captured_file(capture: &Path, tool: CaptureTool) -> Result<Option<PathBuf>> {
    let path = capture.join(tool.file);
    if tool == RENDERDOC {
        let written = std::fs::read_dir(capture)
            .with_context(|| format!("listing {}", capture.display()))?
            .filter_map(|entry| entry.ok().map(|e| e.path()))
            .find(|p| p.extension().is_some_and(|e| e == "rdc"));
        if let Some(written) = written {
            std::fs::rename(&written, &path).with_context(|| format!("renaming {}", written.display()))?;
        }
    }
    Ok(path.is_file().then_some(path))
}

/// How the second run departs from the first: a death where the first died the same way (a
/// crash's, a timeout's) departs in nothing; a record, as [`record_departures`] says.
pub fn departures(first: &CaseRecord, second: &CapturedRun) -> Vec<String> {
    match (&second.record, &second.death) {
        (Some(record), _) => record_departures(first, record),
        (None, Some(death)) => {
            let same = matches!(
                (FailureKind::of(&first.reason), death),
                (FailureKind::Crash, Death::Ended(_)) | (FailureKind::Timeout, Death::TimedOut(_))
            );
            if same {
                Vec::new()
            } else {
                vec![format!("the captured run {death}; the first run was {}", first.outcome.label())]
            }
        }
        (None, None) => vec!["the captured run wrote no record".to_owned()],
    }
}

/// How the second run's record departs from the first's: its outcome, and each metric (timings
/// left out) that differs; empty where they agree.
pub fn record_departures(first: &CaseRecord, second: &CaseRecord) -> Vec<String> {
    let mut departures = Vec::new();
    if first.outcome != second.outcome {
        departures.push(format!(
            "outcome {} where the first run was {}",
            second.outcome.label(),
            first.outcome.label()
        ));
    }
    let untimed = |record: &CaseRecord| {
        let mut metrics = record.numeric_metrics();
        metrics.retain(|name, _| !is_timing_metric(name.split('.').next().unwrap_or_default()));
        metrics
    };
    let (a, b) = (untimed(first), untimed(second));
    for name in a.keys().chain(b.keys().filter(|k| !a.contains_key(*k))) {
        match (a.get(name), b.get(name)) {
            (Some(x), Some(y)) if x.to_bits() == y.to_bits() => {}
            (x, y) => departures.push(format!("{name}: {} where the first run had {}", shown(y), shown(x))),
        }
    }
    departures
}

fn shown(value: Option<&f64>) -> String {
    value.map_or_else(|| "nothing".to_owned(), |v| v.to_string())
}

#[cfg(test)]
mod tests {
    use fragkit_report::report::ReportedOutcome;

    use super::*;

    fn record(outcome: ReportedOutcome, metrics: &[(&str, f64)]) -> CaseRecord {
        let mut record = CaseRecord::unmeasured("kit.a", outcome, "why");
        record.metrics = metrics.iter().map(|(k, v)| ((*k).to_owned(), serde_json::json!(v))).collect();
        record
    }

    #[test]
    fn a_second_run_departs_in_its_outcome_or_any_untimed_metric() {
        use ReportedOutcome::*;
        let first = record(Fail, &[("wrong", 3.0), ("gpu_ms", 1.0), ("time_ratio", 2.0)]);
        assert!(record_departures(&first, &record(Fail, &[("wrong", 3.0), ("gpu_ms", 9.0)])).is_empty());
        assert_eq!(
            record_departures(&first, &record(Pass, &[("wrong", 0.0), ("extra", 1.0)])),
            [
                "outcome pass where the first run was FAIL",
                "wrong: 0 where the first run had 3",
                "extra: 1 where the first run had nothing"
            ]
        );
    }

    /// A second run that dies departs in nothing where the first died the same way.
    #[test]
    fn a_death_matches_a_first_run_that_died_the_same_way() {
        let died =
            |death| CapturedRun { record: None, trace: None, tool: Err("none"), stderr_tail: String::new(), death };
        let crash =
            CaseRecord::unmeasured("kit.a", ReportedOutcome::KnownIssue, "crash: killed by signal 6 [known: x]");
        let timeout = CaseRecord::unmeasured("kit.a", ReportedOutcome::Timeout, "timeout: no record for 30 s");
        let fail = record(ReportedOutcome::Fail, &[]);
        let ended = died(Some(Death::Ended("signal: 6 (SIGABRT)".into())));
        let killed = died(Some(Death::TimedOut(30)));
        assert!(departures(&crash, &ended).is_empty());
        assert!(departures(&timeout, &killed).is_empty());
        assert_eq!(
            departures(&crash, &killed),
            ["the captured run was killed after 30 s without a record; the first run was known_issue"]
        );
        assert_eq!(
            departures(&fail, &ended),
            ["the captured run ended (signal: 6 (SIGABRT)) without a record; the first run was FAIL"]
        );
        assert_eq!(departures(&fail, &died(None)), ["the captured run wrote no record"]);
    }

    #[test]
    fn gl_runs_are_captured_with_apitrace_and_vulkan_runs_with_renderdoc() {
        assert_eq!(tool_for("gl"), Ok(APITRACE));
        assert_eq!(tool_for("vulkan"), Ok(RENDERDOC));
        assert!(tool_for("metal").is_err());
        assert!(on_path("sh") && !on_path("no-such-program-here"));
        // No tool needed where none captures.
        assert!(check_tool("metal").is_ok());
    }
}
