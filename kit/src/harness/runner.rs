//! Runs one case in isolation: requirements first, then the body inside error scopes and a panic
//! guard, so that a validation error or a panic fails that case and the run goes on.

use std::collections::BTreeMap;
use std::panic::{AssertUnwindSafe, catch_unwind};
use std::path::Path;
use std::time::Instant;

use anyhow::{Result, bail};
use glob::Pattern;

use super::case::{Case, Ctx, Outcome};
use super::params::Params;
use crate::diagnostics;
use crate::gpu::Gpu;
use fragkit_report::AdapterDescription;
use fragkit_report::expectations::{Expectations, KnownIssue};
use fragkit_report::report::{CaseRecord, ReportedOutcome};

/// Prefixes of the cases that run only when a pattern starting with the prefix names them:
/// fault injection (which fails on purpose) and long soaks.
pub const OPT_IN: &[&str] = &["fault.", "soak."];

fn opt_in_prefix(name: &str) -> Option<&'static str> {
    OPT_IN.iter().copied().find(|prefix| name.starts_with(prefix))
}

/// Whether a case runs only when a pattern starting with its prefix names it.
pub fn is_opt_in(name: &str) -> bool {
    opt_in_prefix(name).is_some()
}

/// Cases whose names match any of `patterns` (globs; none means all but the opt-in ones). A
/// pattern that matches nothing is an error, so a typo never silently runs zero cases.
pub fn select<'c>(cases: &'c [Case], patterns: &[String]) -> Result<Vec<&'c Case>> {
    if patterns.is_empty() {
        return Ok(cases.iter().filter(|c| opt_in_prefix(c.name).is_none()).collect());
    }
    let mut selected: Vec<&Case> = Vec::new();
    for text in patterns {
        let pattern = Pattern::new(text).map_err(|e| anyhow::anyhow!("bad case pattern {text:?}: {e}"))?;
        let named = |c: &&Case| opt_in_prefix(c.name).is_none_or(|prefix| text.starts_with(prefix));
        let matching: Vec<&Case> = cases.iter().filter(|c| pattern.matches(c.name)).filter(named).collect();
        if matching.is_empty() {
            let names: Vec<&str> = cases.iter().map(|c| c.name).collect();
            bail!("case pattern {text:?} matches no case; cases are: {}", names.join(", "));
        }
        for case in matching {
            if !selected.iter().any(|c| c.name == case.name) {
                selected.push(case);
            }
        }
    }
    Ok(selected)
}

/// Checks that every `--set` key names a parameter of at least one selected case.
pub fn check_overrides(cases: &[&Case], overrides: &BTreeMap<String, String>) -> Result<()> {
    for key in overrides.keys() {
        let owners: Vec<&Case> = cases.iter().copied().filter(|c| c.params.iter().any(|p| p.name == key)).collect();
        if owners.is_empty() {
            let known: Vec<&str> = cases.iter().flat_map(|c| c.params.iter().map(|p| p.name)).collect();
            bail!("--set {key}: no selected case has a parameter {key:?}; parameters of the selected cases: {known:?}");
        }
        for case in owners {
            Params::resolve(case.name, case.params, overrides)?;
        }
    }
    Ok(())
}

/// Checks every size parameter of the selected cases against the adapter's texture limit
/// (`max_texture_dimension_2d`), so that a size no target can have is refused before anything
/// runs.
pub fn check_sizes(max: u32, cases: &[&Case], overrides: &BTreeMap<String, String>) -> Result<()> {
    for case in cases {
        let params = Params::resolve(case.name, case.params, overrides)?;
        for spec in case.params.iter().filter(|s| s.kind.is_size()) {
            let source = if overrides.contains_key(spec.name) { "--set" } else { "the default" };
            for (w, h) in params.sizes(spec.name)? {
                if w > max || h > max {
                    bail!(
                        "parameter {:?} of {} (from {source}): size {w}x{h} exceeds this adapter's texture limit {max}x{max}",
                        spec.name,
                        case.name
                    );
                }
            }
        }
    }
    Ok(())
}

fn panic_message(payload: Box<dyn std::any::Any + Send>) -> String {
    payload
        .downcast_ref::<&str>()
        .map(|s| s.to_string())
        .or_else(|| payload.downcast_ref::<String>().cloned())
        .unwrap_or_else(|| "panic with a non-text payload".into())
}

/// Runs one case and applies the expectations file to its outcome.
pub fn run_case(
    gpu: &Gpu,
    case: &Case,
    overrides: &BTreeMap<String, String>,
    expectations: &Expectations,
    evidence_dir: Option<&Path>,
) -> CaseRecord {
    let started = Instant::now();
    // Start the case's GPU clock from zero, whatever ran before.
    if let Err(e) = gpu.take_gpu_ms() {
        log::warn!("resetting the GPU clock before {}: {e:#}", case.name);
    }
    let (params, params_error) = match Params::resolve(case.name, case.params, overrides) {
        Ok(params) => (params, None),
        Err(e) => (Params::default(), Some(format!("{e:#}"))),
    };
    let mut ctx = Ctx::new(gpu, case.name, params, evidence_dir.map(Path::to_path_buf));
    let missing = case.requires - gpu.device.features();
    let outcome = if let Some(error) = params_error {
        Outcome::Fail(error)
    } else if !missing.is_empty() {
        Outcome::NotSupported(format!("adapter lacks {missing:?}"))
    } else {
        let guarded = catch_unwind(AssertUnwindSafe(|| {
            crate::graphics_debugger::bracket(gpu, || gpu.scoped(case.name, || (case.run)(&mut ctx)))
        }));
        match guarded {
            Ok(Ok(outcome)) => outcome,
            Ok(Err(error)) => {
                let text = format!("{error:#}");
                match super::capability::missing_capability(&text) {
                    Some(capability) => Outcome::NotSupported(capability),
                    None => Outcome::Fail(text),
                }
            }
            Err(payload) => Outcome::Fail(format!("panicked: {}", panic_message(payload))),
        }
    };
    // A lost device fails the case whatever it reported; the caller reopens the device.
    let (gpu_ms, outcome) = match (gpu.lost(), outcome) {
        (Some(lost), outcome) => (None, lost_device_failure(&lost, outcome)),
        (None, outcome) => match gpu.take_gpu_ms() {
            Ok(ms) => (ms, outcome),
            Err(e) => (None, Outcome::Fail(format!("reading the case's GPU time: {e:#}"))),
        },
    };
    // Errors the GL driver raised during the case are part of its verdict: a draw GL refused
    // fails the case by name, not only by the pixels it left.
    let diagnostics = diagnostics::take();
    let outcome = with_errors(outcome, "the driver raised GL errors", &diagnostics::gl_api_errors(&diagnostics));
    // So are the validation layer's (`--validation`), less the messages the expectations list.
    let unlisted: Vec<String> = diagnostics::validation_errors(&diagnostics)
        .into_iter()
        .filter(|(message, _)| expectations.known_validation_message(message, &gpu.description).is_none())
        .map(|(message, count)| format!("{message} (x{count})"))
        .collect();
    let outcome = with_errors(outcome, "the validation layer reported", &unlisted);
    let (outcome, reason) = judged(outcome, case.name, &gpu.description, expectations, !overrides.is_empty());
    CaseRecord {
        name: case.name.to_owned(),
        outcome,
        reason,
        params: ctx.params.to_map(),
        metrics: ctx.metrics,
        gpu_ms,
        gpu_ms_repeats: Vec::new(),
        wall_ms: started.elapsed().as_secs_f64() * 1e3,
        evidence: ctx.evidence,
        attempts: 1,
        diagnostics,
    }
}

/// The failure of a case during which the device was lost (`lost`: why), whatever the case
/// reported; what it saw where it failed too.
fn lost_device_failure(lost: &str, outcome: Outcome) -> Outcome {
    let detail = match outcome {
        Outcome::Fail(why) => format!("; the case saw: {why}"),
        _ => String::new(),
    };
    Outcome::Fail(format!("device lost during the case ({lost}){detail}"))
}

/// A case's outcome as the expectations judge it on `adapter`: a failure an entry explains is a
/// known issue (an unexplained one a failure, saying which entries did not explain it); a pass
/// of a listed case is an unexpected pass, unless every entry is intermittent, or the case ran
/// away from its defaults (`--set`, a sweep) and every entry may pass there.
fn judged(
    outcome: Outcome,
    case: &str,
    adapter: &AdapterDescription,
    expectations: &Expectations,
    away_from_defaults: bool,
) -> (ReportedOutcome, String) {
    let listed = expectations.find(case, adapter);
    let reasons = |issues: &[&KnownIssue]| issues.iter().map(|i| i.reason.as_str()).collect::<Vec<_>>().join(" | ");
    match outcome {
        Outcome::Pass if listed.is_empty() => (ReportedOutcome::Pass, String::new()),
        Outcome::Pass if listed.iter().all(|i| i.intermittent.is_some()) => {
            let why: Vec<&str> = listed.iter().filter_map(|i| i.intermittent.as_deref()).collect();
            (ReportedOutcome::Pass, format!("the listed known issues do not show on every run: {}", why.join(" | ")))
        }
        Outcome::Pass if away_from_defaults && listed.iter().all(|i| i.may_pass.is_some()) => {
            let why: Vec<&str> = listed.iter().filter_map(|i| i.may_pass.as_deref()).collect();
            (
                ReportedOutcome::Pass,
                format!("the listed known issues cannot show with these parameters: {}", why.join(" | ")),
            )
        }
        Outcome::Pass => (
            ReportedOutcome::UnexpectedPass,
            format!(
                "passed, but the expectations file lists it as a known issue ({}); remove the entry",
                reasons(&listed)
            ),
        ),
        Outcome::Fail(why) => match expectations.explain(case, adapter, &why) {
            Some(known) => (ReportedOutcome::KnownIssue, format!("{why} [known: {}]", reasons(&known))),
            _ if listed.is_empty() => (ReportedOutcome::Fail, why),
            _ => (
                ReportedOutcome::Fail,
                format!(
                    "{why} [known issues are listed for this case, but they do not explain all of this failure: {}]",
                    reasons(&listed)
                ),
            ),
        },
        Outcome::NotSupported(why) => (ReportedOutcome::NotSupported, why),
    }
}

/// The outcome once the errors the case raised (GL's, the validation layer's: `what`) are
/// counted: a pass or a failure becomes a failure that names them (one more problem, joined by
/// "; "); not_supported stays, since its probe's refused attempt may raise them.
fn with_errors(outcome: Outcome, what: &str, errors: &[String]) -> Outcome {
    if errors.is_empty() {
        return outcome;
    }
    let raised = format!("{what}: {}", errors.join(", "));
    match outcome {
        Outcome::Pass => Outcome::Fail(raised),
        Outcome::Fail(why) => Outcome::Fail(format!("{why}; {raised}")),
        not_supported @ Outcome::NotSupported(_) => not_supported,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A lost device fails the case, passed or not, and keeps what a failing case saw.
    #[test]
    fn a_lost_device_fails_the_case_and_keeps_what_it_saw() {
        let failure = |outcome| match lost_device_failure("Destroyed", outcome) {
            Outcome::Fail(why) => why,
            other => panic!("{other:?}"),
        };
        assert_eq!(failure(Outcome::Pass), "device lost during the case (Destroyed)");
        assert_eq!(failure(Outcome::NotSupported("x".into())), "device lost during the case (Destroyed)");
        assert_eq!(
            failure(Outcome::Fail("2 of 64 pixels".into())),
            "device lost during the case (Destroyed); the case saw: 2 of 64 pixels"
        );
    }

    #[test]
    fn gl_errors_fail_a_passing_or_failing_case_by_name() {
        let errors = ["GL_INVALID_OPERATION in glDrawArraysIndirect (x2)".to_owned()];
        const GL: &str = "the driver raised GL errors";
        let raised = "the driver raised GL errors: GL_INVALID_OPERATION in glDrawArraysIndirect (x2)";
        assert_eq!(with_errors(Outcome::Pass, GL, &errors), Outcome::Fail(raised.into()));
        assert_eq!(
            with_errors(Outcome::Fail("6144 pixels differ".into()), GL, &errors),
            Outcome::Fail(format!("6144 pixels differ; {raised}"))
        );
        // A refused attempt (the probe of a missing capability) may raise them.
        let missing = Outcome::NotSupported("INDIRECT_EXECUTION".into());
        assert_eq!(with_errors(missing.clone(), GL, &errors), missing);
        assert_eq!(with_errors(Outcome::Pass, GL, &[]), Outcome::Pass);
    }

    #[test]
    fn opt_in_cases_run_only_when_a_pattern_with_their_prefix_names_them() {
        let cases = ["kit.a", "fault.b", "soak.c"].map(Case::passing);
        let names = |patterns: &[&str]| -> Vec<&str> {
            let patterns: Vec<String> = patterns.iter().map(|p| p.to_string()).collect();
            select(&cases, &patterns).map(|s| s.iter().map(|c| c.name).collect()).unwrap_or_default()
        };
        assert_eq!(names(&[]), ["kit.a"]);
        assert_eq!(names(&["*"]), ["kit.a"]);
        assert_eq!(names(&["soak.*"]), ["soak.c"]);
        assert_eq!(names(&["fault.b", "kit.*"]), ["fault.b", "kit.a"]);
        assert!(select(&cases, &["*.b".to_owned()]).is_err(), "a glob not naming the prefix selects nothing");
    }

    #[test]
    fn a_set_must_name_a_selected_cases_parameter_with_a_value_it_takes() {
        use crate::harness::{ParamKind, ParamSpec};
        let seeded = Case {
            params: &[ParamSpec { name: "seed", kind: ParamKind::CountIn(1, 9), default: "1", help: "" }],
            ..Case::passing("kit.seeded")
        };
        let plain = Case::passing("kit.plain");
        let cases = [&seeded, &plain];
        let set = |key: &str, value: &str| BTreeMap::from([(key.to_owned(), value.to_owned())]);
        assert!(check_overrides(&cases, &set("seed", "9")).is_ok());
        assert!(check_overrides(&cases, &BTreeMap::new()).is_ok());
        let unknown = format!("{:#}", check_overrides(&cases, &set("sead", "2")).unwrap_err());
        assert!(
            unknown.contains("no selected case has a parameter \"sead\"") && unknown.contains("[\"seed\"]"),
            "{unknown}"
        );
        let outside = format!("{:#}", check_overrides(&cases, &set("seed", "10")).unwrap_err());
        assert!(outside.contains("outside the allowed range 1..=9"), "{outside}");
        assert!(check_overrides(&[&plain], &set("seed", "2")).is_err(), "a parameter only unselected cases have");
    }

    #[test]
    fn a_panics_text_is_its_message_whatever_its_type() {
        assert_eq!(panic_message(Box::new("static text")), "static text");
        assert_eq!(panic_message(Box::new(String::from("owned text"))), "owned text");
        assert_eq!(panic_message(Box::new(7u32)), "panic with a non-text payload");
        assert!(is_opt_in("soak.cps") && is_opt_in("fault.abort") && !is_opt_in("kit.soak"));
    }

    #[test]
    fn the_expectations_judge_a_pass_and_a_failure_by_what_their_entries_say() {
        use ReportedOutcome::*;
        let expectations = Expectations::parse(
            r#"
[[known_issue]]
case = "kit.listed"
failure = "*pixels differ*"
reason = "the driver's bug"

[[known_issue]]
case = "kit.sometimes"
reason = "a race"
intermittent = "needs a newer CPU"

[[known_issue]]
case = "kit.swept"
reason = "at the default size"
may_pass = "other sizes cannot show it"
"#,
            "test",
        )
        .unwrap();
        let adapter = AdapterDescription::default();
        let judge = |outcome: Outcome, case: &str, away_from_defaults: bool| {
            judged(outcome, case, &adapter, &expectations, away_from_defaults)
        };
        assert_eq!(judge(Outcome::Pass, "kit.free", false), (Pass, String::new()));
        assert_eq!(judge(Outcome::Fail("3 pixels differ".into()), "kit.free", false), (Fail, "3 pixels differ".into()));
        assert_eq!(
            judge(Outcome::Fail("3 pixels differ".into()), "kit.listed", false),
            (KnownIssue, "3 pixels differ [known: the driver's bug]".into())
        );
        let (outcome, reason) = judge(Outcome::Fail("device lost".into()), "kit.listed", false);
        assert_eq!(outcome, Fail);
        assert!(
            reason.starts_with("device lost [known issues are listed") && reason.ends_with("the driver's bug]"),
            "{reason}"
        );
        let (outcome, reason) = judge(Outcome::Pass, "kit.listed", true);
        assert_eq!(outcome, UnexpectedPass);
        assert!(reason.contains("(the driver's bug); remove the entry"), "{reason}");
        assert_eq!(
            judge(Outcome::Pass, "kit.sometimes", false),
            (Pass, "the listed known issues do not show on every run: needs a newer CPU".into())
        );
        assert_eq!(
            judge(Outcome::Pass, "kit.swept", true),
            (Pass, "the listed known issues cannot show with these parameters: other sizes cannot show it".into())
        );
        assert_eq!(judge(Outcome::Pass, "kit.swept", false).0, UnexpectedPass, "at the defaults the entry is stale");
        assert_eq!(judge(Outcome::NotSupported("no 8x".into()), "kit.listed", false), (NotSupported, "no 8x".into()));
    }

    #[test]
    fn a_size_past_the_texture_limit_is_refused_on_either_side() {
        use crate::harness::{ParamKind, ParamSpec};
        let sized = Case {
            params: &[ParamSpec { name: "size", kind: ParamKind::Sizes, default: "8x8", help: "" }],
            ..Case::passing("kit.sized")
        };
        let set = |value: &str| BTreeMap::from([("size".to_owned(), value.to_owned())]);
        assert!(check_sizes(64, &[&sized], &set("64x64,1x1")).is_ok());
        for too_large in ["65x64", "64x65"] {
            let error = format!("{:#}", check_sizes(64, &[&sized], &set(too_large)).unwrap_err());
            assert!(
                error.contains(&format!("(from --set): size {too_large} exceeds this adapter's texture limit 64x64")),
                "{error}"
            );
        }
        let error = format!("{:#}", check_sizes(4, &[&sized], &BTreeMap::new()).unwrap_err());
        assert!(error.contains("(from the default): size 8x8"), "{error}");
        assert!(check_sizes(4, &[&Case::passing("kit.plain")], &BTreeMap::new()).is_ok());
    }
}
