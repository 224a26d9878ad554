//! The property test: every case that declares parameter ranges runs with a few parameter sets
//! drawn from them under a fixed seed (more with `fragkit check --sweep N --seed S`), and none may
//! end in an unexpected failure; each failure names the command that reproduces it.

mod support;

use std::collections::BTreeMap;

use fragkit::harness::Case;
use fragkit::harness::params::Params;
use fragkit::harness::reproduce::Reproduction;
use fragkit::harness::run::plan_runs;
use fragkit::harness::sweep::draw;

/// Sets per case: enough to leave the defaults on every run, few enough for the suite's budget.
const DRAWS: u32 = 2;
const SEED: u64 = 20_261_201;

#[test]
fn every_declared_range_lies_inside_its_parameter() {
    for case in fragkit_cases::all() {
        for sweep in case.sweep {
            assert!(
                case.params.iter().any(|p| p.name == sweep.param),
                "{}: sweeps {:?}, which it does not declare",
                case.name,
                sweep.param
            );
        }
        for index in 0..200 {
            let drawn = draw(case, SEED, index);
            if let Err(e) = Params::resolve(case.name, case.params, &drawn) {
                panic!("{}: drawn set {drawn:?} is outside the parameters' own ranges: {e:#}", case.name);
            }
        }
    }
}

#[test]
fn drawn_parameter_sets_hold() {
    let mut failures = Vec::new();
    // The runs `fragkit check --sweep DRAWS --seed SEED` plans for the cases with ranges.
    let swept: Vec<&Case> = fragkit_cases::all().iter().filter(|c| !c.sweep.is_empty()).collect();
    let reproduction = Reproduction::of_process("fragkit check", &Default::default());
    for run in plan_runs(&swept, &BTreeMap::new(), Some((DRAWS, SEED))) {
        let (record, slug, _) = support::run_with(run.case, &run.overrides);
        // The slug starts with the backend (`vulkan_llvmpipe_…`).
        let backend = slug.split('_').next().unwrap_or_default();
        let reproduce = reproduction.line(run.case, &run.overrides, backend);
        eprintln!("{:<14} {reproduce}", record.outcome.label());
        if record.outcome.is_failure(false) {
            failures.push(format!("{}: {}\n  reproduce: {reproduce}", run.case.name, record.reason));
        }
    }
    assert!(failures.is_empty(), "{} drawn parameter sets failed:\n{}", failures.len(), failures.join("\n"));
}
