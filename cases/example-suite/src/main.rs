//! An example suite: cases a renderer author writes for their own renderer, outside the kit, on
//! fragkit's public API alone. `cargo run -p fragkit-example-suite -- --json FILE` runs them
//! through the kit's runner — each in a child process, known issues applied — and writes a
//! report in the kit's format, which `fragkit compare`, `html` and `import` read like any other.

use std::process::ExitCode;
use std::sync::OnceLock;

use fragkit::harness::Case;
use fragkit::harness::registry::join;
use fragkit::harness::suite::Suite;

// The suite's case files and their cases, in run order (`fault.*` only when a pattern names them).
fragkit::cases! {
    gradient: CASE;
    fault_abort: CASE;
}

fn main() -> ExitCode {
    static REGISTRY: OnceLock<Vec<Case>> = OnceLock::new();
    Suite {
        name: "fragkit-example-suite",
        cases: join(&REGISTRY, &[CASES]),
        expectations: include_str!("../expectations.toml"),
        expectations_origin: "cases/example-suite/expectations.toml",
    }
    .main()
}
