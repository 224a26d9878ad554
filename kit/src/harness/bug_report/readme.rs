//! A bug report's README, in the order driver trackers (Mesa's GitLab, the Khronos and wgpu
//! issue templates) ask for: what happens against what should, on which driver and version,
//! how to reproduce it — with fragkit, and without it — and what is attached.

use std::fmt::Write as _;

use fragkit_report::AdapterDescription;
use fragkit_report::expectations::KnownIssue;
use fragkit_report::report::CaseRecord;

use super::capture::CapturedRun;
use super::shaders::WrittenShader;
use super::{KitReadback, Replay, Replayed};
use crate::harness::Case;
use crate::harness::reproduce::is_driver_variable;

/// Everything the README says.
pub struct Readme<'a> {
    pub record: &'a CaseRecord,
    pub case: &'a Case,
    pub adapter: &'a AdapterDescription,
    pub reproduce: &'a str,
    pub known: &'a [&'a KnownIssue],
    pub captured: &'a CapturedRun,
    pub departures: &'a [String],
    pub shaders: &'a [WrittenShader],
    pub readbacks: &'a [KitReadback],
    pub replay: Option<&'a Replay>,
    pub replayed: Option<&'a Replayed>,
}

/// The reason without the kit's own suffixes (the reproduce line, the known issue's text).
fn finding(reason: &str) -> &str {
    let end = [" [reproduce: ", " [known: "].iter().filter_map(|s| reason.find(s)).min().unwrap_or(reason.len());
    &reason[..end]
}

impl Readme<'_> {
    pub fn text(&self) -> String {
        let (record, adapter) = (self.record, self.adapter);
        let mut t = String::new();
        let _ = writeln!(
            t,
            "# {}: {} on {} ({})\n",
            record.run_name(),
            record.outcome.label(),
            adapter.name,
            adapter.backend
        );
        let _ = writeln!(t, "## What the case checks\n\n{}\n", self.case.summary);
        let _ = writeln!(t, "## What happened\n\n{}\n", finding(&record.reason));
        let metrics = record.numeric_metrics();
        if !metrics.is_empty() {
            t.push_str("Measured (the case's metrics):\n\n| metric | value |\n|---|---|\n");
            for (name, value) in &metrics {
                let _ = writeln!(t, "| `{name}` | {value} |");
            }
            t.push('\n');
        }
        let _ = writeln!(
            t,
            "## Driver\n\n- adapter: {}\n- backend: {}\n- driver: {}\n- driver info (version): {}\n- device type: {}\n",
            adapter.name, adapter.backend, adapter.driver, adapter.driver_info, adapter.device_type
        );
        let environment: Vec<String> = std::env::vars()
            .filter(|(name, _)| is_driver_variable(name))
            .map(|(name, value)| format!("{name}={value}"))
            .collect();
        if !environment.is_empty() {
            let _ = writeln!(t, "The driver stack's variables of the run:\n\n```\n{}\n```\n", environment.join("\n"));
        }
        t.push_str("## Whose fault\n\n");
        if self.known.is_empty() {
            t.push_str(
                "Not yet attributed: the kit lists no known issue for this case on this adapter. Run the same line on \
                 other configurations (`fragkit check CASE --matrix all`) to see which layer it follows: one driver only \
                 points at the driver; every GL driver at wgpu-hal's GL backend or naga's GLSL; every adapter at the kit.\n\n",
            );
        }
        for issue in self.known {
            let _ = writeln!(t, "Listed in the kit's expectations (cases/expectations.toml):\n\n> {}\n", issue.reason);
            for (what, note) in [("It shows only on some runs", &issue.intermittent), ("It may pass", &issue.may_pass)]
            {
                if let Some(note) = note {
                    let _ = writeln!(t, "{what}: {note}\n");
                }
            }
        }
        let _ = writeln!(t, "## Reproduce with fragkit\n\n```sh\n{}\n```\n", self.reproduce);
        self.replay_section(&mut t);
        self.shader_section(&mut t);
        self.attachments_section(&mut t);
        t
    }

    fn replay_section(&self, t: &mut String) {
        t.push_str("## Replay without fragkit\n\n");
        let captured = self.captured;
        match (&captured.tool, &captured.trace) {
            (Ok(tool), Some(trace)) => {
                let size = std::fs::metadata(trace).map(|m| m.len()).unwrap_or(0);
                let file = trace.file_name().map(|f| f.to_string_lossy().into_owned()).unwrap_or_default();
                let how = if tool.program == "apitrace" {
                    "holds every EGL and GL call of the case's own process, recorded by `apitrace trace --api egl`"
                } else {
                    "holds the case's GPU work, captured by RenderDoc's in-application API around the case (the \
                     process started by `renderdoccmd capture`)"
                };
                let _ = writeln!(
                    t,
                    "`capture/{file}` ({size} bytes) {how}. `./replay` replays it with {} alone (Debian: `apt-get \
                     install {}`), headless, and writes each texture the case read back into \
                     `replayed/readback-NNN.png`, as this machine's driver renders it; `readbacks/` holds what the kit \
                     read (`.png` for 8-bit RGBA, `.bin` raw rows, `.json` their format).{}\n",
                    tool.replayer,
                    tool.packages,
                    if self.replay.is_some_and(|r| r.bottom_up) {
                        " eglretrace writes an image bottom row first: flip it to compare."
                    } else {
                        ""
                    }
                );
                if let Some(replay) = self.replay {
                    t.push_str("| read-back | format | size | shown by | replayed here |\n|---|---|---|---|---|\n");
                    for (kit, shown) in &replay.pairs {
                        let (shown, verdict) = match shown {
                            Ok(at) => {
                                let verdict = self
                                    .replayed
                                    .and_then(|r| r.verdicts.iter().find(|(index, _)| *index == kit.index))
                                    .map_or("not compared (no 8-bit RGBA image)".to_owned(), |(_, v)| match v {
                                        Ok(()) => "equal to the kit's, pixel for pixel".to_owned(),
                                        Err(why) => format!("**differs**: {why}"),
                                    });
                                let by = if replay.bottom_up {
                                    format!("snapshot after call {at}")
                                } else {
                                    format!("image-to-buffer copy {at}")
                                };
                                (by, verdict)
                            }
                            Err(why) => (format!("not shown: {why}"), "-".to_owned()),
                        };
                        let _ = writeln!(
                            t,
                            "| {:03} | {} | {}x{} | {shown} | {verdict} |",
                            kit.index, kit.format, kit.width, kit.height
                        );
                    }
                    t.push('\n');
                }
                if let Some(Replayed { ran: Err(why), .. }) = self.replayed {
                    let _ = writeln!(t, "Run once here after writing this folder, the replay failed: {why}\n");
                }
                let differs = self.replayed.is_some_and(|r| r.verdicts.iter().any(|(_, v)| v.is_err()));
                if differs && self.replay.is_some_and(|r| r.bottom_up) {
                    t.push_str(
                        "Where a replayed image differs, the replay is not the run, and the kit does not yet know which \
                         part: the snapshot reads the texture straight from its framebuffer where the case read it through \
                         `glReadPixels` into a pixel-pack buffer (wgpu-hal's copy to a buffer); a GLES trace replays on \
                         the driver's own GLES rather than the run's overridden version (see `replay`); some drivers \
                         answer differently from run to run. The read-backs in `readbacks/` are what the case judged.\n\n",
                    );
                }
            }
            (Err(why), _) => {
                let _ = writeln!(t, "No capture: {why}.\n");
            }
            (Ok(tool), None) => {
                let _ = writeln!(t, "No capture: {} wrote no trace (its stderr is below).\n", tool.program);
            }
        }
        if let (true, Some(death)) = (self.departures.is_empty(), &captured.death) {
            let _ = writeln!(
                t,
                "The captured run died as the first did: it {death}.\n\n```\n{}\n```\n",
                captured.stderr_tail
            );
        } else if self.departures.is_empty() {
            t.push_str("The captured run's outcome and metrics (timings left out) equal the first run's.\n\n");
        } else {
            t.push_str("**The captured run departs from the first run** — the capture changes the result:\n\n");
            for departure in self.departures {
                let _ = writeln!(t, "- {departure}");
            }
            let _ = writeln!(t, "\nWhat the run under the capture wrote last:\n\n```\n{}\n```\n", captured.stderr_tail);
        }
    }

    fn shader_section(&self, t: &mut String) {
        if self.shaders.is_empty() {
            return;
        }
        t.push_str("## Shaders\n\n");
        for shader in self.shaders {
            let _ = writeln!(t, "- `shaders/{}`: {}", shader.path, shader.about);
        }
        t.push('\n');
    }

    fn attachments_section(&self, t: &mut String) {
        t.push_str("## Attached\n\n");
        t.push_str(
            "- `evidence/`: the case's evidence images from the captured run (result, expectation, error mask)\n",
        );
        let _ = writeln!(t, "- `readbacks/`: the {} texture read-backs the case judged", self.readbacks.len());
        if self.captured.trace.is_some() {
            t.push_str("- `capture/case.trace`, `replay`\n");
        }
        t.push_str(
            "\n## What to send upstream\n\nThis folder: the README is the report's text; `replay` and the capture let the \
             driver's developers see the pixels with their own tools, and the shaders show what the driver compiled. For a \
             fault in wgpu-hal or naga (the kit's expectations say which), send it to wgpu \
             (https://github.com/gfx-rs/wgpu/issues); for a driver's, to its tracker (Mesa: \
             https://gitlab.freedesktop.org/mesa/mesa/-/issues).\n",
        );
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_finding_is_the_reason_without_the_kits_suffixes() {
        assert_eq!(finding("1x: 3 pixels differ [reproduce: fragkit check x]"), "1x: 3 pixels differ");
        assert_eq!(finding("bad [known: a driver bug] [reproduce: y]"), "bad");
        assert_eq!(finding("plain"), "plain");
    }
}
