//! The example suite as its author runs it: through the kit's runner, each case in a child
//! process, a report in the kit's format.

use std::path::PathBuf;
use std::process::{Command, Output};

fn suite(arguments: &[&str], report: &str) -> (Output, serde_json::Value) {
    let path: PathBuf = std::env::temp_dir().join(format!("fragkit-example-{}-{report}.json", std::process::id()));
    let output = Command::new(env!("CARGO_BIN_EXE_fragkit-example-suite"))
        .args(arguments)
        .arg("--json")
        .arg(&path)
        .output()
        .expect("the example suite starts");
    let text = std::fs::read_to_string(&path).unwrap_or_else(|e| {
        panic!("no report at {} ({e}); stderr: {}", path.display(), String::from_utf8_lossy(&output.stderr))
    });
    std::fs::remove_file(&path).ok();
    (output, serde_json::from_str(&text).expect("the report is JSON"))
}

fn outcomes(report: &serde_json::Value) -> Vec<(String, String)> {
    report["cases"]
        .as_array()
        .expect("cases")
        .iter()
        .map(|case| (case["name"].as_str().unwrap().to_owned(), case["outcome"].as_str().unwrap().to_owned()))
        .collect()
}

#[test]
fn its_case_passes_and_the_report_is_the_kits() {
    let (output, report) = suite(&[], "default");
    assert!(output.status.success(), "{}", String::from_utf8_lossy(&output.stdout));
    assert_eq!(outcomes(&report), [("example.gradient".to_owned(), "pass".to_owned())]);
    assert!(report["adapter"]["name"].is_string() && report["run"]["kind"] == "check", "{report}");
    assert_eq!(report["cases"][0]["metrics"]["pixels_off"], 0);
}

#[test]
fn a_crash_costs_its_case_and_the_run_goes_on() {
    let (output, report) = suite(&["fault.abort", "example.gradient", "--set", "size=7x5"], "crash");
    assert_eq!(output.status.code(), Some(1), "{}", String::from_utf8_lossy(&output.stdout));
    assert_eq!(
        outcomes(&report),
        [("fault.abort".to_owned(), "crash".to_owned()), ("example.gradient".to_owned(), "pass".to_owned())]
    );
    let reason = report["cases"][0]["reason"].as_str().unwrap();
    assert!(reason.contains("SIGABRT") && reason.contains("reproduce: fragkit-example-suite fault.abort"), "{reason}");
}

#[test]
fn bad_input_is_a_clear_error_and_exit_2() {
    let output =
        Command::new(env!("CARGO_BIN_EXE_fragkit-example-suite")).arg("no.such.case").output().expect("starts");
    assert_eq!(output.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&output.stderr).contains("matches no case"));
}
