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
use capture::{APITRACE, RENDERDOC};
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
        let reading = match (&captured.tool, &captured.trace) {
            (Ok(APITRACE), Some(trace)) => read_apitrace(trace)?,
            _ => TraceReading::default(),
        };
        let shaders =
            shaders::write_shaders(&folder.join("shaders"), run.case.shaders, &adapter.backend, &reading.shaders)?;
        let readbacks = kit_readbacks(&folder.join("readbacks"))?;
        let replay = match (&captured.tool, &captured.trace) {
            (Ok(APITRACE), Some(_)) => {
                Some(write_gl_replay(&folder, &reading, &readbacks, adapter.driver_info.starts_with("OpenGL ES"))?)
            }
            (Ok(RENDERDOC), Some(_)) => Some(write_renderdoc_replay(&folder, &readbacks)?),
            _ => None,
        };
        let replayed = replay.as_ref().map(|replay| replay.run_and_compare(&folder));
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
            replayed: replayed.as_ref(),
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

/// What the replay script shows: per kit read-back, where the capture shows it (a trace's
/// snapshot call, a capture's copy) or why it does not.
pub struct Replay {
    pub pairs: Vec<(KitReadback, Result<u64, String>)>,
    /// Whether the replay writes images bottom row first (eglretrace), flipped against the
    /// kit's.
    pub bottom_up: bool,
}

/// How long the replay may take when the kit runs it once (eglretrace has been seen to hang on
/// a context it cannot make).
const REPLAY_TIMEOUT: std::time::Duration = std::time::Duration::from_secs(120);

/// Runs `command` (its output discarded but for stderr's end), killed past `timeout`.
fn run_with_timeout(mut command: Command, timeout: std::time::Duration) -> Result<(), String> {
    let mut child = command
        .stdout(std::process::Stdio::null())
        .stderr(std::process::Stdio::piped())
        .spawn()
        .map_err(|e| format!("replay could not start: {e}"))?;
    let mut stderr = child.stderr.take();
    let reader = std::thread::spawn(move || {
        let mut text = String::new();
        if let Some(stderr) = stderr.as_mut() {
            std::io::Read::read_to_string(stderr, &mut text).ok();
        }
        text
    });
    let started = std::time::Instant::now();
    let status = loop {
        match child.try_wait() {
            Ok(Some(status)) => break Some(status),
            Ok(None) if started.elapsed() > timeout => {
                child.kill().ok();
                child.wait().ok();
                break None;
            }
            Ok(None) => std::thread::sleep(std::time::Duration::from_millis(50)),
            Err(e) => return Err(format!("waiting for the replay: {e}")),
        }
    };
    let stderr = reader.join().unwrap_or_default();
    let tail: Vec<&str> = stderr.lines().filter(|l| !l.trim().is_empty()).rev().take(3).collect();
    let tail = tail.into_iter().rev().collect::<Vec<_>>().join(" / ");
    match status {
        Some(status) if status.success() => Ok(()),
        Some(status) => Err(format!("replay failed ({status}): {tail}")),
        None => Err(format!("replay was killed after {} s: {tail}", timeout.as_secs())),
    }
}

/// The replay run once after writing: its verdict per read-back, or why it did not run.
pub struct Replayed {
    pub ran: Result<(), String>,
    /// Per read-back with an image: equal to the kit's, or how it differs.
    pub verdicts: Vec<(u32, Result<(), String>)>,
}

impl Replay {
    /// Runs `folder/replay` and holds each replayed image to the kit's read-back.
    pub fn run_and_compare(&self, folder: &Path) -> Replayed {
        let ran = run_with_timeout(Command::new(folder.join("replay")), REPLAY_TIMEOUT);
        let mut verdicts = Vec::new();
        for (kit, shown) in &self.pairs {
            let (Some(image), Ok(_)) = (&kit.image, shown) else {
                continue;
            };
            let replayed = folder.join("replayed").join(format!("readback-{:03}.png", kit.index));
            let verdict = match (image::open(folder.join("readbacks").join(image)), image::open(&replayed)) {
                (Ok(kit_image), Ok(replayed_image)) => {
                    let replayed_image = replayed_image.to_rgba8();
                    let replayed_image =
                        if self.bottom_up { image::imageops::flip_vertical(&replayed_image) } else { replayed_image };
                    let kit_image = kit_image.to_rgba8();
                    if kit_image.dimensions() != replayed_image.dimensions() {
                        Err(format!("{:?} against the kit's {:?}", replayed_image.dimensions(), kit_image.dimensions()))
                    } else {
                        let differing = kit_image.pixels().zip(replayed_image.pixels()).filter(|(a, b)| a != b).count();
                        if differing == 0 { Ok(()) } else { Err(format!("{differing} pixels differ")) }
                    }
                }
                (_, Err(e)) => Err(format!("no replayed image: {e}")),
                (Err(e), _) => Err(format!("the kit's image: {e}")),
            };
            verdicts.push((kit.index, verdict));
        }
        Replayed { ran, verdicts }
    }
}

/// Writes `replay`: eglretrace with no display snapshots the trace after each call that last
/// drew a texture the case read back, and the script names each image after the read-back it
/// shows (`replayed/readback-NNN.png`). The texture reads pair with the trace's `glReadPixels`
/// in order, where their sizes agree.
fn write_gl_replay(folder: &Path, reading: &TraceReading, readbacks: &[KitReadback], gles: bool) -> Result<Replay> {
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
    if gles {
        // Measured with apitrace 11.1 on Mesa 22.3: under the version overrides that make
        // llvmpipe a GLES adapter for wgpu, eglretrace cannot make the traced GLES context
        // ("waffle_context_create failed" with MESA_GL_VERSION_OVERRIDE=3.2; a hang with
        // MESA_GLES_VERSION_OVERRIDE alone); without them the driver's own GLES replays it.
        script.push_str(
            "# A GLES trace: replayed on the driver's own GLES (eglretrace cannot make the context under\n\
             # Mesa's version overrides).\n\
             unset MESA_GL_VERSION_OVERRIDE MESA_GLES_VERSION_OVERRIDE\n",
        );
    }
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
    Ok(Replay { pairs, bottom_up: true })
}

/// The Python half of a RenderDoc replay: every image-to-buffer copy the capture holds (the
/// case's read-backs, in order), its source image saved as PNG at that event.
const RENDERDOC_REPLAY: &str = r#"# Replays capture/case.rdc with RenderDoc's Python module alone, headless, on this machine's
# Vulkan driver, and saves the source image of each image-to-buffer copy (the case's read-backs,
# in order) as replayed/readback-NNN.png.
import os
import sys

import renderdoc as rd

here = os.path.dirname(os.path.abspath(__file__))
rd.InitialiseReplay(rd.GlobalEnvironment(), [])
capture = rd.OpenCaptureFile()
status = capture.OpenFile(os.path.join(here, "case.rdc"), "", None)
if status != rd.ResultCode.Succeeded:
    sys.exit(f"opening the capture: {status}")
status, controller = capture.OpenCapture(rd.ReplayOptions(), None)
if status != rd.ResultCode.Succeeded:
    sys.exit(f"replaying the capture: {status}")


def actions(children):
    for action in children:
        yield action
        yield from actions(action.children)


structured = controller.GetStructuredFile()
index = 0
for action in actions(controller.GetRootActions()):
    if not (action.flags & rd.ActionFlags.Copy) or action.GetName(structured) != "vkCmdCopyImageToBuffer()":
        continue
    controller.SetFrameEvent(action.eventId, True)
    save = rd.TextureSave()
    save.resourceId = action.copySource
    save.mip = action.copySourceSubresource.mip
    save.slice.sliceIndex = action.copySourceSubresource.slice
    save.destType = rd.FileType.PNG
    path = os.path.join(here, "..", "replayed", f"readback-{index:03}.png")
    result = controller.SaveTexture(save, path)
    print(f"readback {index:03}: event {action.eventId}: {result}")
    index += 1
controller.Shutdown()
capture.Shutdown()
rd.ShutdownReplay()
"#;

/// The shell half: the Python with RenderDoc's module (Debian's is the system one).
const RENDERDOC_REPLAY_SCRIPT: &str = r#"#!/bin/sh
# Replays capture/case.rdc with RenderDoc's Python module alone (Debian: apt-get install
# python3-renderdoc) on this machine's Vulkan driver, with no display, and writes each texture
# the case read back, as the driver renders it now, into replayed/readback-NNN.png.
set -e
cd "$(dirname "$0")"
rm -rf replayed
mkdir -p replayed
for python in /usr/bin/python3 python3; do
    if "$python" -c 'import renderdoc' 2>/dev/null; then exec "$python" capture/replay.py; fi
done
echo "replay needs RenderDoc's Python module (Debian: apt-get install python3-renderdoc)" >&2
exit 2
"#;

/// Writes `replay` and `capture/replay.py` for a RenderDoc capture: the image-to-buffer copies
/// pair with the kit's read-backs in order.
fn write_renderdoc_replay(folder: &Path, readbacks: &[KitReadback]) -> Result<Replay> {
    std::fs::write(folder.join("capture/replay.py"), RENDERDOC_REPLAY).context("writing capture/replay.py")?;
    let script = RENDERDOC_REPLAY_SCRIPT;
    let path = folder.join("replay");
    std::fs::write(&path, script).with_context(|| format!("writing {}", path.display()))?;
    use std::os::unix::fs::PermissionsExt;
    std::fs::set_permissions(&path, std::fs::Permissions::from_mode(0o755)).context("making replay executable")?;
    let pairs = readbacks.iter().enumerate().map(|(i, kit)| (kit.clone(), Ok(i as u64))).collect();
    Ok(Replay { pairs, bottom_up: false })
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
