//! The command line: bad input gets a clear message and a non-zero exit, never a panic.

use std::process::Command;

fn fragkit(args: &[&str]) -> (i32, String) {
    let output = Command::new(env!("CARGO_BIN_EXE_fragkit")).args(args).output().expect("running fragkit");
    let text = String::from_utf8_lossy(&output.stdout).into_owned() + &String::from_utf8_lossy(&output.stderr);
    assert!(!text.contains("panicked"), "fragkit {args:?} panicked:\n{text}");
    (output.status.code().unwrap_or(-1), text)
}

#[test]
fn unknown_case_pattern_is_an_error() {
    let (code, text) = fragkit(&["check", "nope.*"]);
    assert_eq!(code, 2, "{text}");
    assert!(text.contains("\"nope.*\" matches no case"), "{text}");
}

#[test]
fn unknown_parameter_is_an_error() {
    let (code, text) = fragkit(&["check", "kit.determinism", "--set", "colour=red"]);
    assert_eq!(code, 2, "{text}");
    assert!(text.contains("no selected case has a parameter \"colour\""), "{text}");
}

#[test]
fn unparsable_parameter_is_an_error() {
    let (code, text) = fragkit(&["check", "kit.determinism", "--set", "size=0x4"]);
    assert_eq!(code, 2, "{text}");
    assert!(text.contains("size \"0x4\" is empty"), "{text}");
}

#[test]
fn unknown_backend_is_an_error() {
    let (code, text) = fragkit(&["--backend", "glide", "check", "kit.determinism"]);
    assert_eq!(code, 2, "{text}");
    assert!(text.contains("unknown backend \"glide\""), "{text}");
}

#[test]
fn unknown_adapter_is_an_error() {
    let (code, text) = fragkit(&["--adapter", "no-such-gpu", "check", "kit.determinism"]);
    assert_eq!(code, 2, "{text}");
    assert!(text.contains("no adapter name contains \"no-such-gpu\""), "{text}");
}

#[test]
fn corrupt_expectations_file_is_an_error() {
    let path = std::env::temp_dir().join("fragkit-corrupt-expectations.toml");
    std::fs::write(&path, "[[known_issue]]\ncase = \"kit.*\"\nreasn = \"typo\"\n").unwrap();
    let (code, text) = fragkit(&["check", "kit.determinism", "--expectations", path.to_str().unwrap()]);
    assert_eq!(code, 2, "{text}");
    assert!(text.contains("parsing expectations file"), "{text}");
}

#[test]
fn check_writes_a_json_report_and_list_names_every_case() {
    let path = std::env::temp_dir().join("fragkit-cli-report.json");
    let (code, text) = fragkit(&["check", "kit.determinism", "--json", path.to_str().unwrap()]);
    assert_eq!(code, 0, "{text}");
    let report: serde_json::Value = serde_json::from_str(&std::fs::read_to_string(&path).unwrap()).unwrap();
    assert!(report["adapter"]["name"].is_string());
    for key in ["name", "outcome", "reason", "params", "metrics", "gpu_ms", "wall_ms"] {
        assert!(report["cases"][0].get(key).is_some(), "report case lacks {key}: {report}");
    }
    let (code, listing) = fragkit(&["list"]);
    assert_eq!(code, 0);
    for case in fragkit_cases::ALL {
        assert!(listing.contains(case.name), "list lacks {}", case.name);
    }
}

#[test]
fn a_listed_case_that_passes_fails_the_run_as_an_unexpected_pass() {
    let path = std::env::temp_dir().join("fragkit-stale-expectations.toml");
    std::fs::write(&path, "[[known_issue]]\ncase = \"kit.determinism\"\nreason = \"stale entry\"\n").unwrap();
    let (code, text) = fragkit(&["check", "kit.determinism", "--expectations", path.to_str().unwrap()]);
    assert_eq!(code, 1, "{text}");
    assert!(text.contains("UNEXPECTED_PASS"), "{text}");
}
