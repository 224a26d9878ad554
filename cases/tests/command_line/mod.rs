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

/// A fresh, empty PostgreSQL database named `name` on the server `.ci/run` starts (its URL in
/// FRAGKIT_TEST_POSTGRES, from `bash .ci/postgres`). Without one the PostgreSQL tests are skipped
/// with a note, except under CI, where they must run.
pub fn fresh_postgres_database(name: &str) -> Option<String> {
    let Ok(server) = std::env::var("FRAGKIT_TEST_POSTGRES") else {
        assert!(
            std::env::var_os("CI").is_none(),
            "CI must test the PostgreSQL backend: run `export FRAGKIT_TEST_POSTGRES=$(bash .ci/postgres)` first"
        );
        eprintln!("note: FRAGKIT_TEST_POSTGRES is unset (see .ci/postgres): PostgreSQL test skipped");
        return None;
    };
    let database = format!("fragkit_test_{name}");
    let status = Command::new("psql")
        .env("PGOPTIONS", "-c client_min_messages=warning")
        .args([server.as_str(), "-q", "-c", &format!("DROP DATABASE IF EXISTS {database}")])
        .args(["-c", &format!("CREATE DATABASE {database}")])
        .status()
        .expect("running psql");
    assert!(status.success(), "creating {database} on {server}");
    let (base, _) = server.rsplit_once('/').expect("a URL ending in /DATABASE");
    Some(format!("{base}/{database}"))
}
