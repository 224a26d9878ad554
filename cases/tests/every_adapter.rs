//! Every case on every adapter this machine has (lavapipe on Vulkan and llvmpipe on GL here):
//! each ends in an honest outcome, none crashes, hangs or fails unexpectedly.

use std::collections::BTreeMap;

use fragkit::Gpu;
use fragkit::gpu::all_adapters;
use fragkit::harness::runner::{is_opt_in, run_case};
use fragkit_report::expectations::Expectations;

#[test]
fn every_case_on_every_adapter() {
    let expectations = Expectations::parse(fragkit_cases::EXPECTATIONS, "cases/expectations.toml").unwrap();
    let adapters = all_adapters();
    assert!(!adapters.is_empty(), "no adapter: install mesa-vulkan-drivers");
    let mut failures = Vec::new();
    for adapter in adapters {
        let gpu = Gpu::from_adapter(adapter).unwrap_or_else(|e| panic!("{e:#}"));
        // Opt-in cases (fault injection, soaks) have their own tests.
        for case in fragkit_cases::all().iter().filter(|c| !is_opt_in(c.name)) {
            let record = run_case(&gpu, case, &BTreeMap::new(), &expectations, None);
            eprintln!("{} / {}: {:?} {}", gpu.description.backend, case.name, record.outcome, record.reason);
            if record.outcome.is_failure(false) {
                failures.push(format!("{} on {}: {}", case.name, gpu.description.backend, record.reason));
            }
        }
    }
    assert!(failures.is_empty(), "unexpected failures:\n{}", failures.join("\n"));
}
