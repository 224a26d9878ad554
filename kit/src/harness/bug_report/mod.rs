//! Bug reports a driver developer can act on without fragkit (`check --bug-report DIR`): per
//! case run that did not pass, a folder with a README in the form upstream trackers ask for, the
//! evidence, the shaders as WGSL and as the driver got them, a capture of the case's own process
//! and a `replay` script that shows its pixels with the capture tool alone.

pub mod capture;
pub mod gl_trace;
pub mod readme;
pub mod shaders;

use std::ffi::OsString;
use std::path::{Path, PathBuf};
use std::process::Command;

use anyhow::{Context, Result};
use fragkit_report::AdapterDescription;
use fragkit_report::expectations::Expectations;
use fragkit_report::report::{CaseRecord, Report, ReportedOutcome};

use super::reproduce::Reproduction;
use super::run::CaseRun;
use super::supervise::CaseTimeout;
use capture::APITRACE;
use gl_trace::TraceReading;

/// What `--bug-report` asked for, and how to run one case run again.
pub struct BugReports<'a> {
    pub dir: &'a Path,
    /// `--bug-report-known`: known issues get their folder too.
    pub known: bool,
    /// This program.
    pub program: PathBuf,
    /// The supervised child's command line for one case run, less `--child-stream`: selection,
    /// the case, its `--set`s, the expectations, evidence into the given folder.
    pub child_arguments: &'a dyn Fn(&CaseRun, &Path) -> Vec<OsString>,
    pub reproduction: &'a Reproduction,
    pub expectations: &'a Expectations,
    /// How long the case's second run may go without a record (the first run's).
    pub timeout: CaseTimeout,
}

/// Whether a record gets a folder: every outcome that is not a pass, a skip or a run left out —
/// and known issues where asked.
pub fn wanted(record: &CaseRecord, known: bool) -> bool {
    use ReportedOutcome::*;
    match record.outcome {
        Fail | Crash | Timeout | UnexpectedPass | Flaky => true,
        KnownIssue => known,
        Pass | NotSupported | Skip | NotRun => false,
    }
}

/// A folder name for a case run: its name, its parameters, nothing a shell or a file system
/// would trip on.
pub fn folder_name(record: &CaseRecord) -> String {
    let mut name = String::new();
    for c in record.run_name().chars() {
        if c.is_ascii_alphanumeric() || "._-=".contains(c) {
            name.push(c);
        } else if !name.ends_with('_') {
            name.push('_');
        }
    }
    name.trim_end_matches('_').to_owned()
}

/// One folder written.
pub struct Written {
    pub folder: PathBuf,
    /// Whether the captured run departed from the first.
    pub departures: Vec<String>,
}

impl BugReports<'_> {
    /// A folder for each wanted record of `report`, whose case runs are `runs` (in its order).
    pub fn write(&self, report: &Report, runs: &[CaseRun]) -> Result<Vec<Written>> {
        std::fs::create_dir_all(self.dir)
            .with_context(|| format!("creating the bug report folder {}", self.dir.display()))?;
        let mut written = Vec::new();
        for (record, run) in report.cases.iter().zip(runs) {
            if !wanted(record, self.known) {
                continue;
            }
            anyhow::ensure!(
                record.name == run.case.name,
                "the report's {} is not the run list's {}",
                record.name,
                run.case.name
            );
            written.push(self.write_one(&report.adapter, record, run)?);
        }
        Ok(written)
    }

    fn write_one(&self, adapter: &AdapterDescription, record: &CaseRecord, run: &CaseRun) -> Result<Written> {
        let folder = self.dir.join(folder_name(record));
        if folder.exists() {
            std::fs::remove_dir_all(&folder).with_context(|| format!("clearing {}", folder.display()))?;
        }
        std::fs::create_dir_all(&folder).with_context(|| format!("creating {}", folder.display()))?;
        let arguments = (self.child_arguments)(run, &folder.join("evidence"));
        let captured = capture::rerun(&self.program, &arguments, &adapter.backend, &folder, self.timeout.of(run.case))?;
        let departures = capture::departures(record, &captured);
        let reading = match &captured.trace {
            Some(trace) => read_apitrace(trace)?,
            None => TraceReading::default(),
        };
        let shaders =
            shaders::write_shaders(&folder.join("shaders"), run.case.shaders, &adapter.backend, &reading.shaders)?;
        let readbacks = kit_readbacks(&folder.join("readbacks"))?;
        let replay = match &captured.trace {
            Some(_) => Some(write_gl_replay(&folder, &reading, &readbacks)?),
            None => None,
        };
        let known = self.expectations.find(run.case.name, adapter);
        let text = readme::Readme {
            record,
            case: run.case,
            adapter,
            reproduce: &self.reproduction.line(run.case, &run.overrides, &adapter.backend),
            known: &known,
            captured: &captured,
            departures: &departures,
            shaders: &shaders,
            readbacks: &readbacks,
            replay: replay.as_ref(),
        }
        .text();
        std::fs::write(folder.join("README.md"), text)
            .with_context(|| format!("writing {}/README.md", folder.display()))?;
        Ok(Written { folder, departures })
    }
}

/// `apitrace dump` of a trace, read.
fn read_apitrace(trace: &Path) -> Result<TraceReading> {
    let output = Command::new(APITRACE.program)
        .args(["dump", "--color=never"])
        .arg(trace)
        .output()
        .with_context(|| format!("running apitrace dump on {}", trace.display()))?;
    anyhow::ensure!(
        output.status.success(),
        "apitrace dump {} failed: {}",
        trace.display(),
        String::from_utf8_lossy(&output.stderr)
    );
    Ok(gl_trace::read_trace(&String::from_utf8_lossy(&output.stdout)))
}

/// One texture the case read back (`readbacks/readback-NNN.json`).
#[derive(Clone, Debug, serde::Deserialize)]
pub struct KitReadback {
    pub index: u32,
    pub format: String,
    pub width: u32,
    pub height: u32,
    pub image: Option<String>,
}

fn kit_readbacks(dir: &Path) -> Result<Vec<KitReadback>> {
    let mut found = Vec::new();
    let Ok(entries) = std::fs::read_dir(dir) else {
        return Ok(found);
    };
    for entry in entries {
        let path = entry?.path();
        if path.extension().is_some_and(|e| e == "json") {
            let text = std::fs::read_to_string(&path).with_context(|| format!("reading {}", path.display()))?;
            found.push(
                serde_json::from_str::<KitReadback>(&text).with_context(|| format!("reading {}", path.display()))?,
            );
        }
    }
    found.sort_by_key(|r| r.index);
    Ok(found)
}

/// What the replay script shows: per kit read-back, the trace's snapshot call, or why none.
pub struct Replay {
    pub pairs: Vec<(KitReadback, Result<u64, String>)>,
}

/// Writes `replay`: eglretrace with no display snapshots the trace after each call that last
/// drew a texture the case read back, and the script names each image after the read-back it
/// shows (`replayed/readback-NNN.png`). The texture reads pair with the trace's `glReadPixels`
/// in order, where their sizes agree.
fn write_gl_replay(folder: &Path, reading: &TraceReading, readbacks: &[KitReadback]) -> Result<Replay> {
    let pairs: Vec<(KitReadback, Result<u64, String>)> = readbacks
        .iter()
        .enumerate()
        .map(|(i, kit)| {
            let snapshot = match reading.readbacks.get(i) {
                None => Err(format!(
                    "the trace has {} glReadPixels, fewer than the kit's read-backs",
                    reading.readbacks.len()
                )),
                Some(traced) if traced.size != (kit.width, kit.height) => Err(format!(
                    "glReadPixels {} reads {}x{} where the kit's read-back {} is {}x{}",
                    traced.call, traced.size.0, traced.size.1, kit.index, kit.width, kit.height
                )),
                Some(traced) => traced.snapshot.clone(),
            };
            (kit.clone(), snapshot)
        })
        .collect();
    let calls: Vec<u64> = pairs.iter().filter_map(|(_, s)| s.as_ref().ok().copied()).collect();
    let mut script = String::from(
        "#!/bin/sh\n\
         # Replays capture/case.trace with apitrace alone (Debian: apt-get install apitrace) on this\n\
         # machine's GL driver, with no display, and writes each texture the case read back, as the\n\
         # driver renders it now, into replayed/readback-NNN.png. eglretrace writes images as GL\n\
         # stores them, bottom row first: readbacks/ holds the kit's, top row first (wgpu flips y).\n\
         set -e\n\
         cd \"$(dirname \"$0\")\"\n\
         rm -rf replayed snapshots\n\
         mkdir -p replayed snapshots\n",
    );
    if calls.is_empty() {
        script.push_str("echo 'no read-back of this case can be shown from the trace (see README.md)' >&2\nexit 1\n");
    } else {
        let list: Vec<String> = calls.iter().map(u64::to_string).collect();
        script.push_str(&format!(
            "WAFFLE_PLATFORM=surfaceless_egl eglretrace --headless --snapshot-alpha -S {} -s snapshots/ capture/case.trace\n",
            list.join(",")
        ));
        for (kit, snapshot) in &pairs {
            if let Ok(call) = snapshot {
                script.push_str(&format!("cp snapshots/{call:010}.png replayed/readback-{:03}.png\n", kit.index));
            }
        }
        script.push_str("echo \"replayed: $(ls replayed | wc -l) images in $(pwd)/replayed\"\n");
    }
    let path = folder.join("replay");
    std::fs::write(&path, script).with_context(|| format!("writing {}", path.display()))?;
    use std::os::unix::fs::PermissionsExt;
    std::fs::set_permissions(&path, std::fs::Permissions::from_mode(0o755)).context("making replay executable")?;
    Ok(Replay { pairs })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn failures_get_folders_known_issues_when_asked_and_passes_never() {
        use ReportedOutcome::*;
        let record = |outcome| CaseRecord::unmeasured("kit.a", outcome, "why");
        for outcome in [Fail, Crash, Timeout, UnexpectedPass, Flaky] {
            assert!(wanted(&record(outcome), false), "{outcome:?}");
        }
        assert!(!wanted(&record(KnownIssue), false) && wanted(&record(KnownIssue), true));
        for outcome in [Pass, NotSupported, Skip, NotRun] {
            assert!(!wanted(&record(outcome), true), "{outcome:?}");
        }
    }

    #[test]
    fn a_folder_is_named_after_the_case_run_in_safe_characters() {
        let mut record = CaseRecord::unmeasured("kit.msaa.sample_mask", ReportedOutcome::Fail, "why");
        assert_eq!(folder_name(&record), "kit.msaa.sample_mask");
        record.params.insert("size".into(), fragkit_report::param_value::ParamValue::Sizes(vec![(8, 4)]));
        assert_eq!(folder_name(&record), "kit.msaa.sample_mask_size=_8_4");
    }
}
