//! Running the `fragkit` binary from a test, shared by the command-line test binaries.

// Each test binary uses part of this module.
#![allow(dead_code)]

use std::path::Path;
use std::process::Command;

/// Runs `fragkit args`: its exit code and its stdout followed by its stderr. A panic fails the test.
pub fn fragkit(args: &[&str]) -> (i32, String) {
    let output = Command::new(env!("CARGO_BIN_EXE_fragkit")).args(args).output().expect("running fragkit");
    let text = String::from_utf8_lossy(&output.stdout).into_owned() + &String::from_utf8_lossy(&output.stderr);
    assert!(!text.contains("panicked"), "fragkit {args:?} panicked:\n{text}");
    (output.status.code().unwrap_or(-1), text)
}

/// Copies `from` recursively to `to` (the shader tree for a mutated copy).
pub fn copy_tree(from: &Path, to: &Path) {
    std::fs::create_dir_all(to).unwrap();
    for entry in std::fs::read_dir(from).unwrap() {
        let entry = entry.unwrap();
        let target = to.join(entry.file_name());
        if entry.file_type().unwrap().is_dir() {
            copy_tree(&entry.path(), &target);
        } else {
            std::fs::copy(entry.path(), target).unwrap();
        }
    }
}
