//! A reproduce line reproduces (issue 39): run as printed, by a shell with nothing of the run's
//! environment, it meets the same driver in the same state and gets the same outcome.

use std::path::{Path, PathBuf};
use std::process::Command;

use serde_json::Value;

/// A folder of the test's own, empty.
fn scratch(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("fragkit-reproduce-{name}-{}", std::process::id()));
    std::fs::remove_dir_all(&dir).ok();
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

/// The (outcome, reason) of the one case run of a JSON report.
fn only_case(path: &Path) -> (String, String) {
    let text = std::fs::read_to_string(path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
    let report: Value = serde_json::from_str(&text).unwrap();
    let cases = report["cases"].as_array().unwrap();
    assert_eq!(cases.len(), 1, "{text}");
    (cases[0]["outcome"].as_str().unwrap().to_owned(), cases[0]["reason"].as_str().unwrap().to_owned())
}

/// The line inside a reason's `[reproduce: …]`.
fn reproduce_line(reason: &str) -> String {
    let start = reason.rfind("[reproduce: ").unwrap_or_else(|| panic!("no reproduce line in {reason:?}")) + 12;
    reason[start..reason.len() - 1].to_owned()
}

/// Runs `line` (with `extra` appended) in `sh` with an environment of PATH (this build's
/// `fragkit` first), HOME and XDG_RUNTIME_DIR only; its exit code and output.
fn run_as_printed(line: &str, extra: &str) -> (i32, String) {
    let binary = Path::new(env!("CARGO_BIN_EXE_fragkit"));
    let path = format!("{}:/usr/bin:/bin", binary.parent().unwrap().display());
    let runtime = std::env::var("XDG_RUNTIME_DIR").unwrap_or_else(|_| "/tmp".to_owned());
    let output = Command::new("/bin/sh")
        .arg("-c")
        .arg(format!("{line} {extra}"))
        .env_clear()
        .env("PATH", path)
        .env("HOME", std::env::var("HOME").unwrap_or_default())
        .env("XDG_RUNTIME_DIR", runtime)
        .output()
        .unwrap();
    let text = String::from_utf8_lossy(&output.stdout).into_owned() + &String::from_utf8_lossy(&output.stderr);
    (output.status.code().unwrap_or(-1), text)
}

/// Lavapipe with depth testing off (LP_PERF=no_depth) fails the 1x sample-position probe; the
/// line carries the variable, and run as printed fails again. Without it the same command passes:
/// the variable is what made the failure.
#[test]
fn a_failure_made_by_the_driver_environment_reproduces_from_its_line() {
    let dir = scratch("environment");
    let json = dir.join("run.json");
    let output = Command::new(env!("CARGO_BIN_EXE_fragkit"))
        .args(["--backend", "vulkan", "check", "kit.msaa.sample_positions.1x", "--json", json.to_str().unwrap()])
        .env("LP_PERF", "no_depth")
        .env("HOME_IS_NOT_A_DRIVER_VARIABLE", "1")
        .output()
        .unwrap();
    assert_eq!(output.status.code(), Some(1), "{}", String::from_utf8_lossy(&output.stdout));
    let (outcome, reason) = only_case(&json);
    assert_eq!(outcome, "fail", "{reason}");
    let line = reproduce_line(&reason);
    assert!(
        line.starts_with("LP_PERF=no_depth ") && line.contains("fragkit check kit.msaa.sample_positions.1x"),
        "{line}"
    );
    assert!(line.ends_with("--backend vulkan") && !line.contains("HOME_IS_NOT"), "{line}");

    let again = dir.join("again.json");
    let (code, text) = run_as_printed(&line, &format!("--json {}", again.display()));
    assert_eq!(code, 1, "{line}\n{text}");
    let (outcome, again_reason) = only_case(&again);
    assert_eq!(outcome, "fail", "{again_reason}");
    assert_eq!(reproduce_line(&again_reason), line, "the rerun prints the same line");

    let without = line.trim_start_matches("LP_PERF=no_depth ");
    let (code, text) = run_as_printed(without, &format!("--json {}", dir.join("without.json").display()));
    assert_eq!(code, 0, "{without}\n{text}");
    std::fs::remove_dir_all(&dir).ok();
}

/// A crash in a matrix configuration's run names the configuration (whose variables the line
/// leaves to it) and, run as printed, crashes in that configuration again.
#[test]
fn a_crash_in_a_matrix_configuration_reproduces_from_its_line() {
    let dir = scratch("matrix");
    let reports = dir.join("reports");
    let output = Command::new(env!("CARGO_BIN_EXE_fragkit"))
        .args(["check", "fault.abort", "--matrix", "lavapipe-4lane", "--reports", reports.to_str().unwrap()])
        .output()
        .unwrap();
    assert_eq!(output.status.code(), Some(1), "{}", String::from_utf8_lossy(&output.stdout));
    let (outcome, reason) = only_case(&reports.join("lavapipe-4lane.json"));
    assert_eq!(outcome, "crash", "{reason}");
    let line = reproduce_line(&reason);
    assert_eq!(line, "fragkit check fault.abort --matrix lavapipe-4lane");

    let again = dir.join("again");
    let (code, text) = run_as_printed(&line, &format!("--reports {}", again.display()));
    assert_eq!(code, 1, "{line}\n{text}");
    let (outcome, again_reason) = only_case(&again.join("lavapipe-4lane.json"));
    assert_eq!(outcome, "crash", "{again_reason}");
    assert_eq!(reproduce_line(&again_reason), line);
    std::fs::remove_dir_all(&dir).ok();
}
