//! An example suite: cases a renderer author writes for their own renderer, outside the kit, on
//! fragkit's public API alone. `cargo run -p fragkit-example-suite -- --json FILE` runs them
//! through the kit's runner — each in a child process, known issues applied — and writes a
//! report in the kit's format, which `fragkit compare`, `html` and `import` read like any other.

mod fault_abort;
mod gradient;

use std::process::ExitCode;

use fragkit::harness::Case;
use fragkit::harness::suite::Suite;

/// The suite's cases, in run order; `fault.*` ones only when a pattern names them.
const CASES: &[Case] = &[gradient::CASE, fault_abort::CASE];

fn main() -> ExitCode {
    Suite {
        name: "fragkit-example-suite",
        cases: CASES,
        expectations: include_str!("../expectations.toml"),
        expectations_origin: "cases/example-suite/expectations.toml",
    }
    .main()
}
