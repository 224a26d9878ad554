//! Known driver issues, as data: a case that fails on an adapter matching an entry is reported
//! as `known_issue`; a listed case that passes is an `unexpected_pass` and fails the run until
//! the entry is removed (as wgpu's test harness and the WebGPU CTS do).

use std::path::Path;

use anyhow::{Context, Result};
use glob::{MatchOptions, Pattern};
use serde::Deserialize;

use crate::adapter::AdapterDescription;

#[derive(Clone, Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct KnownIssue {
    /// Case name glob, or a list of them (one cause behind several cases).
    pub case: CaseGlobs,
    /// Globs over the adapter's description; an absent field matches anything.
    pub backend: Option<String>,
    pub adapter: Option<String>,
    pub driver: Option<String>,
    pub driver_info: Option<String>,
    /// Glob that every problem of the failure must match (a case joins its problems with
    /// "; "); absent: any failure. A failure this entry does not explain stays a failure.
    pub failure: Option<String>,
    /// Why it fails, with the measured evidence.
    pub reason: String,
    /// Where the issue depends on the parameters: why some parameter sets cannot show it. With
    /// this, a pass away from the defaults (a sweep, `--set`) is a plain pass; at the defaults a
    /// pass still means the entry is stale.
    pub may_pass: Option<String>,
    /// Where the issue shows only on some runs or machines (a heap corruption that needs a CPU's
    /// newer instruction sets to crash): why. With this, a pass is a plain pass anywhere.
    pub intermittent: Option<String>,
    /// The one kind of failure the entry expects — `fail`, `crash` or `timeout` — as a baseline
    /// (`check --write-baseline`) records it; absent: any.
    pub outcome: Option<FailureKind>,
}

/// Which kind of failure a reason reports: a crash's and a timeout's reasons start so.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum FailureKind {
    Fail,
    Crash,
    Timeout,
}

impl FailureKind {
    /// The name an expectations file gives it (`outcome = "…"`).
    pub fn name(self) -> &'static str {
        match self {
            Self::Fail => "fail",
            Self::Crash => "crash",
            Self::Timeout => "timeout",
        }
    }

    pub fn of(reason: &str) -> Self {
        if reason.starts_with("crash:") {
            Self::Crash
        } else if reason.starts_with("timeout:") {
            Self::Timeout
        } else {
            Self::Fail
        }
    }
}

/// One case glob or several.
#[derive(Clone, Debug, Deserialize)]
#[serde(untagged)]
pub enum CaseGlobs {
    One(String),
    Many(Vec<String>),
}

impl CaseGlobs {
    pub fn globs(&self) -> &[String] {
        match self {
            Self::One(glob) => std::slice::from_ref(glob),
            Self::Many(globs) => globs,
        }
    }
}

/// A message of the Vulkan validation layer (`check --validation`) that is not the kit's fault:
/// a case that raises only listed messages keeps its verdict (the messages stay in its
/// diagnostics); any other message fails it.
#[derive(Clone, Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct KnownValidationMessage {
    /// Glob over the message as the kit names it: "MESSAGE-ID: first line of the message".
    pub message: String,
    /// Globs over the adapter's description; an absent field matches anything.
    pub backend: Option<String>,
    pub adapter: Option<String>,
    pub driver: Option<String>,
    pub driver_info: Option<String>,
    /// Whose fault it is: the driver, wgpu-hal, naga, or the validation layer itself.
    pub layer: String,
    /// Why, with the evidence.
    pub reason: String,
}

#[derive(Clone, Debug, Default, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Expectations {
    #[serde(default, rename = "known_issue")]
    pub known_issues: Vec<KnownIssue>,
    #[serde(default, rename = "known_validation_message")]
    pub known_validation_messages: Vec<KnownValidationMessage>,
}

/// Patterns were checked by [`Expectations::parse`]; one that still fails to parse matches nothing.
pub(crate) fn glob_matches(pattern: &str, text: &str) -> bool {
    // Every option named: glob's defaults are not this file's contract.
    let options =
        MatchOptions { case_sensitive: false, require_literal_separator: false, require_literal_leading_dot: false };
    Pattern::new(pattern).is_ok_and(|p| p.matches_with(text, options))
}

/// Whether `adapter` lies in an entry's scope: globs over its backend, name, driver and driver
/// info, in that order; an absent glob matches anything.
pub(crate) fn in_scope(scope: [&Option<String>; 4], adapter: &AdapterDescription) -> bool {
    let fields = [&adapter.backend, &adapter.name, &adapter.driver, &adapter.driver_info];
    scope.into_iter().zip(fields).all(|(pattern, text)| pattern.as_deref().is_none_or(|p| glob_matches(p, text)))
}

impl Expectations {
    pub fn parse(text: &str, origin: &str) -> Result<Self> {
        let parsed: Self = toml::from_str(text).with_context(|| format!("parsing expectations file {origin}"))?;
        // Reject bad globs now rather than at the first match.
        for issue in &parsed.known_issues {
            let patterns = [
                issue.backend.as_ref(),
                issue.adapter.as_ref(),
                issue.driver.as_ref(),
                issue.driver_info.as_ref(),
                issue.failure.as_ref(),
            ];
            for pattern in issue.case.globs().iter().chain(patterns.into_iter().flatten()) {
                Pattern::new(pattern).with_context(|| {
                    format!("expectations file {origin}: bad pattern {pattern:?} in the entry for {:?}", issue.case)
                })?;
            }
        }
        for known in &parsed.known_validation_messages {
            let patterns = [&known.backend, &known.adapter, &known.driver, &known.driver_info];
            for pattern in std::iter::once(&known.message).chain(patterns.into_iter().flatten()) {
                Pattern::new(pattern).with_context(|| {
                    format!(
                        "expectations file {origin}: bad pattern {pattern:?} in the validation message {:?}",
                        known.message
                    )
                })?;
            }
        }
        Ok(parsed)
    }

    /// These entries and `other`'s (a baseline beside the known issues).
    pub fn extend(&mut self, other: Self) {
        self.known_issues.extend(other.known_issues);
        self.known_validation_messages.extend(other.known_validation_messages);
    }

    /// The entry that lists a validation message ("MESSAGE-ID: message") on this adapter.
    pub fn known_validation_message(
        &self,
        message: &str,
        adapter: &AdapterDescription,
    ) -> Option<&KnownValidationMessage> {
        self.known_validation_messages.iter().find(|known| {
            glob_matches(&known.message, message)
                && in_scope([&known.backend, &known.adapter, &known.driver, &known.driver_info], adapter)
        })
    }

    pub fn load(path: &Path) -> Result<Self> {
        let text =
            std::fs::read_to_string(path).with_context(|| format!("reading expectations file {}", path.display()))?;
        Self::parse(&text, &path.display().to_string())
    }

    /// The known issues listed for this case on this adapter.
    pub fn find(&self, case: &str, adapter: &AdapterDescription) -> Vec<&KnownIssue> {
        self.known_issues.iter().filter(|issue| issue.matches(case, adapter)).collect()
    }

    /// The entries that explain a failure, when together they explain every one of its problems
    /// (a case joins its problems with "; "); None when some problem is unexplained.
    pub fn explain<'a>(
        &'a self,
        case: &str,
        adapter: &AdapterDescription,
        reason: &str,
    ) -> Option<Vec<&'a KnownIssue>> {
        let kind = FailureKind::of(reason);
        let mut listed = self.find(case, adapter);
        listed.retain(|issue| issue.outcome.is_none_or(|expected| expected == kind));
        let mut used: Vec<&KnownIssue> = Vec::new();
        for problem in reason.split("; ") {
            let issue = listed.iter().find(|issue| issue.explains(problem))?;
            if !used.iter().any(|u| std::ptr::eq(*u, *issue)) {
                used.push(issue);
            }
        }
        Some(used)
    }
}

impl KnownIssue {
    /// Whether this entry explains one problem of a failure.
    fn explains(&self, problem: &str) -> bool {
        self.failure.as_deref().is_none_or(|pattern| glob_matches(pattern, problem))
    }

    fn matches(&self, case: &str, adapter: &AdapterDescription) -> bool {
        self.case.globs().iter().any(|glob| glob_matches(glob, case))
            && in_scope([&self.backend, &self.adapter, &self.driver, &self.driver_info], adapter)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn lavapipe() -> AdapterDescription {
        AdapterDescription {
            name: "llvmpipe (LLVM 15.0.6, 256 bits)".into(),
            backend: "vulkan".into(),
            driver: "llvmpipe".into(),
            driver_info: "Mesa 22.3.6 (LLVM 15.0.6)".into(),
            device_type: "Cpu".into(),
        }
    }

    const ENTRY: &str = r#"
        [[known_issue]]
        case = "kit.scissor.*"
        backend = "vulkan"
        adapter = "LLVMPIPE*"
        driver_info = "Mesa 22.3*"
        failure = "4x: *"
        reason = "row above and column left"
    "#;

    #[test]
    fn an_entry_matches_by_case_and_adapter_globs() {
        let expectations = Expectations::parse(ENTRY, "test").unwrap();
        assert_eq!(expectations.find("kit.scissor.msaa", &lavapipe()).len(), 1);
        assert!(expectations.find("kit.determinism", &lavapipe()).is_empty());
        let gl = AdapterDescription { backend: "gl".into(), ..lavapipe() };
        assert!(expectations.find("kit.scissor.msaa", &gl).is_empty());
        let newer = AdapterDescription { driver_info: "Mesa 24.0.1".into(), ..lavapipe() };
        assert!(expectations.find("kit.scissor.msaa", &newer).is_empty());
    }

    #[test]
    fn an_entry_explains_only_the_failures_it_describes() {
        let two =
            format!("{ENTRY}\n[[known_issue]]\ncase = \"kit.scissor.msaa\"\nfailure = \"2x: *\"\nreason = \"other\"\n");
        let expectations = Expectations::parse(&two, "test").unwrap();
        let adapter = lavapipe();
        assert!(
            expectations
                .explain("kit.scissor.msaa", &adapter, "4x: 31 pixels differ; 4x: 861 samples, expected 800")
                .is_some()
        );
        assert_eq!(
            expectations.explain("kit.scissor.msaa", &adapter, "4x: 31 pixels; 2x: 5 pixels").map(|v| v.len()),
            Some(2)
        );
        assert!(
            expectations
                .explain("kit.scissor.msaa", &adapter, "1x: 1000 pixels differ; 4x: 31 pixels differ")
                .is_none()
        );
    }

    #[test]
    fn a_list_of_case_globs_matches_any_of_them() {
        let list = "[[known_issue]]\ncase = [\"kit.occlusion.exact\", \"oit.a2c.*\"]\nreason = \"one cause\"\n";
        let expectations = Expectations::parse(list, "test").unwrap();
        for case in ["kit.occlusion.exact", "oit.a2c.transfer"] {
            assert_eq!(expectations.find(case, &lavapipe()).len(), 1, "{case}");
        }
        assert!(expectations.find("oit.extremes", &lavapipe()).is_empty());
        let bad = Expectations::parse("[[known_issue]]\ncase = [\"ok\", \"[x\"]\nreason = \"y\"\n", "test");
        assert!(bad.is_err());
    }

    #[test]
    fn unknown_fields_and_bad_globs_are_errors() {
        let typo = Expectations::parse("[[known_issue]]\ncase = \"x\"\nreasn = \"y\"\n", "test").unwrap_err();
        assert!(format!("{typo:#}").contains("reasn"), "{typo:#}");
        let glob = Expectations::parse("[[known_issue]]\ncase = \"[x\"\nreason = \"y\"\n", "test").unwrap_err();
        assert!(format!("{glob:#}").contains("bad pattern"), "{glob:#}");
    }

    #[test]
    fn an_entry_for_one_kind_of_failure_explains_that_kind_only() {
        for kind in [FailureKind::Fail, FailureKind::Crash, FailureKind::Timeout] {
            let text = format!("[[known_issue]]\ncase = \"kit.*\"\noutcome = \"{}\"\nreason = \"r\"\n", kind.name());
            let expectations = Expectations::parse(&text, "test").unwrap();
            assert_eq!(expectations.known_issues[0].outcome, Some(kind));
            for (reason, of) in [
                ("4x: 31 pixels differ", FailureKind::Fail),
                ("crash: the process running the case was killed", FailureKind::Crash),
                ("timeout: no record for 30 s", FailureKind::Timeout),
            ] {
                assert_eq!(FailureKind::of(reason), of);
                let explained = expectations.explain("kit.a", &lavapipe(), reason).is_some();
                assert_eq!(explained, of == kind, "an entry for {} and {reason:?}", kind.name());
            }
        }
    }

    #[test]
    fn a_baseline_extends_the_known_issues_and_a_file_loads_as_its_text_parses() {
        let mut expectations = Expectations::default();
        expectations.extend(Expectations::parse(ENTRY, "test").unwrap());
        assert_eq!(expectations.find("kit.scissor.msaa", &lavapipe()).len(), 1);
        let path = std::env::temp_dir().join(format!("fragkit-expectations-{}.toml", std::process::id()));
        std::fs::write(&path, ENTRY).unwrap();
        let loaded = Expectations::load(&path).unwrap();
        std::fs::remove_file(&path).ok();
        assert_eq!(loaded.find("kit.scissor.msaa", &lavapipe()).len(), 1);
        let missing = Expectations::load(&path).unwrap_err();
        assert!(format!("{missing:#}").contains(&path.display().to_string()), "{missing:#}");
    }

    #[test]
    fn a_validation_message_is_known_on_the_adapters_its_entry_names() {
        let text = r#"
            [[known_validation_message]]
            message = "UNASSIGNED-CoreValidation-Shader-InconsistentSpirv: *source language operand: 10"
            driver_info = "Mesa 22.3*"
            layer = "vulkan-validationlayers 1.3.239"
            reason = "its SPIRV-Tools predate SourceLanguage WGSL"
        "#;
        let mut expectations = Expectations::default();
        expectations.extend(Expectations::parse(text, "test").unwrap());
        let message = "UNASSIGNED-CoreValidation-Shader-InconsistentSpirv: Invalid source language operand: 10";
        let known = expectations.known_validation_message(message, &lavapipe()).unwrap();
        assert_eq!(known.layer, "vulkan-validationlayers 1.3.239");
        let newer = AdapterDescription { driver_info: "Mesa 24.0".into(), ..lavapipe() };
        assert!(expectations.known_validation_message(message, &newer).is_none());
        assert!(expectations.known_validation_message("VUID-vkCmdDraw-None-02699: x", &lavapipe()).is_none());
        let bad = text.replace("Mesa 22.3*", "[");
        let error = format!("{:#}", Expectations::parse(&bad, "test").unwrap_err());
        assert!(error.contains("bad pattern \"[\" in the validation message"), "{error}");
    }

    /// Property tests: which entries apply, and which explain a failure, against a plain reading
    /// of each field — an absent glob matches anything; `*` any run of characters, `?` one,
    /// anything else itself, letters in either case — with a glob matcher written out here.
    mod plain_reading {
        use proptest::prelude::*;

        use super::super::*;

        fn plain_glob(pattern: &[char], text: &[char]) -> bool {
            match pattern.split_first() {
                None => text.is_empty(),
                Some(('*', rest)) => (0..=text.len()).any(|skip| plain_glob(rest, &text[skip..])),
                Some((&p, rest)) => text.split_first().is_some_and(|(&t, text)| {
                    (p == '?' || p.to_lowercase().eq(t.to_lowercase())) && plain_glob(rest, text)
                }),
            }
        }

        fn plain(pattern: &Option<String>, text: &str) -> bool {
            pattern
                .as_ref()
                .is_none_or(|p| plain_glob(&p.chars().collect::<Vec<_>>(), &text.chars().collect::<Vec<_>>()))
        }

        // Each field's texts from a small pool, so that entries match as often as they miss.
        const BACKENDS: &[&str] = &["vulkan", "gl"];
        const NAMES: &[&str] = &["llvmpipe (LLVM 15.0.6, 256 bits)", "SwiftShader Device (Subzero)", "softpipe"];
        const DRIVERS: &[&str] = &["llvmpipe", "softpipe", ""];
        const DRIVER_INFOS: &[&str] = &["Mesa 22.3.6 (LLVM 15.0.6)", "4.5 (Core Profile) Mesa 22.3.6"];
        const CASES: &[&str] = &["kit.msaa.sample_mask", "kit.msaa.sample_count", "oit.extremes"];
        const PROBLEMS: &[&str] = &["wrong pixels: 12", "wrong samples: 3", "crash: signal 11"];

        fn text(pool: &'static [&'static str]) -> impl Strategy<Value = String> {
            proptest::sample::select(pool).prop_map(str::to_owned)
        }

        /// A text of the pool made a glob: characters turned to `*` or `?`, to the other case,
        /// or dropped — near misses as well as matches. Each one `parse` accepts.
        fn glob(pool: &'static [&'static str]) -> impl Strategy<Value = String> {
            (text(pool), proptest::collection::vec((any::<prop::sample::Index>(), 0..4u8), 0..4)).prop_map(
                |(text, edits)| {
                    let mut chars: Vec<char> = text.chars().collect();
                    for (at, edit) in edits {
                        if chars.is_empty() {
                            break;
                        }
                        let i = at.index(chars.len());
                        match edit {
                            0 => chars[i] = '*',
                            1 => chars[i] = '?',
                            2 => chars[i] = chars[i].to_ascii_uppercase(),
                            _ => {
                                chars.remove(i);
                            }
                        }
                    }
                    // `**` is the glob crate's path wildcard, which `parse` refuses outside a
                    // path component of its own: one `*` for a run of them.
                    chars.dedup_by(|a, b| *a == '*' && *b == '*');
                    chars.into_iter().collect()
                },
            )
        }

        fn scope() -> impl Strategy<Value = [Option<String>; 4]> {
            [
                proptest::option::of(glob(BACKENDS)),
                proptest::option::of(glob(NAMES)),
                proptest::option::of(glob(DRIVERS)),
                proptest::option::of(glob(DRIVER_INFOS)),
            ]
        }

        fn issue() -> impl Strategy<Value = KnownIssue> {
            (
                proptest::collection::vec(glob(CASES), 1..3),
                scope(),
                proptest::option::of(glob(PROBLEMS)),
                proptest::option::of(proptest::sample::select(
                    &[FailureKind::Fail, FailureKind::Crash, FailureKind::Timeout][..],
                )),
            )
                .prop_map(|(case, [backend, adapter, driver, driver_info], failure, outcome)| KnownIssue {
                    case: CaseGlobs::Many(case),
                    backend,
                    adapter,
                    driver,
                    driver_info,
                    failure,
                    reason: "test".into(),
                    may_pass: None,
                    intermittent: None,
                    outcome,
                })
        }

        fn adapter() -> impl Strategy<Value = AdapterDescription> {
            (text(BACKENDS), text(NAMES), text(DRIVERS), text(DRIVER_INFOS)).prop_map(
                |(backend, name, driver, driver_info)| AdapterDescription {
                    backend,
                    name,
                    driver,
                    driver_info,
                    device_type: "Cpu".into(),
                },
            )
        }

        fn applies(issue: &KnownIssue, case: &str, adapter: &AdapterDescription) -> bool {
            issue.case.globs().iter().any(|glob| plain(&Some(glob.clone()), case))
                && plain(&issue.backend, &adapter.backend)
                && plain(&issue.adapter, &adapter.name)
                && plain(&issue.driver, &adapter.driver)
                && plain(&issue.driver_info, &adapter.driver_info)
        }

        proptest! {
            #[test]
            fn the_entries_found_are_those_whose_every_field_matches(
                issues in proptest::collection::vec(issue(), 1..5),
                case in text(CASES),
                adapter in adapter(),
            ) {
                let expectations = Expectations { known_issues: issues, known_validation_messages: Vec::new() };
                let found: Vec<*const KnownIssue> =
                    expectations.find(&case, &adapter).into_iter().map(|i| i as *const _).collect();
                let plainly: Vec<*const KnownIssue> = expectations
                    .known_issues
                    .iter()
                    .filter(|issue| applies(issue, &case, &adapter))
                    .map(|i| i as *const _)
                    .collect();
                prop_assert_eq!(found, plainly);
            }

            /// A failure is explained when each of its problems has an entry that applies, expects
            /// its kind (or any) and whose failure glob matches that problem; the entries named are
            /// each problem's first such, once each.
            #[test]
            fn a_failure_is_explained_when_every_problem_has_an_entry(
                issues in proptest::collection::vec(issue(), 1..5),
                case in text(CASES),
                adapter in adapter(),
                problems in proptest::collection::vec(text(PROBLEMS), 1..3),
            ) {
                let expectations = Expectations { known_issues: issues, known_validation_messages: Vec::new() };
                let reason = problems.join("; ");
                let kind = if reason.starts_with("crash:") { FailureKind::Crash } else { FailureKind::Fail };
                let mut plainly: Option<Vec<*const KnownIssue>> = Some(Vec::new());
                for problem in reason.split("; ") {
                    let first = expectations.known_issues.iter().find(|issue| {
                        applies(issue, &case, &adapter)
                            && issue.outcome.is_none_or(|outcome| outcome == kind)
                            && plain(&issue.failure, problem)
                    });
                    match (first, plainly.as_mut()) {
                        (Some(issue), Some(used)) => {
                            if !used.contains(&(issue as *const _)) {
                                used.push(issue);
                            }
                        }
                        _ => plainly = None,
                    }
                }
                let explained = expectations
                    .explain(&case, &adapter, &reason)
                    .map(|used| used.into_iter().map(|i| i as *const _).collect::<Vec<_>>());
                prop_assert_eq!(explained, plainly);
            }

            #[test]
            fn a_validation_message_is_known_by_the_first_entry_whose_every_field_matches(
                entries in proptest::collection::vec((glob(PROBLEMS), scope()), 1..5),
                message in text(PROBLEMS),
                adapter in adapter(),
            ) {
                let known_validation_messages: Vec<KnownValidationMessage> = entries
                    .into_iter()
                    .map(|(message, [backend, adapter, driver, driver_info])| KnownValidationMessage {
                        message,
                        backend,
                        adapter,
                        driver,
                        driver_info,
                        layer: "test".into(),
                        reason: "test".into(),
                    })
                    .collect();
                let expectations = Expectations { known_issues: Vec::new(), known_validation_messages };
                let known = expectations.known_validation_message(&message, &adapter).map(|k| k as *const _);
                let plainly = expectations
                    .known_validation_messages
                    .iter()
                    .find(|k| {
                        plain(&Some(k.message.clone()), &message)
                            && plain(&k.backend, &adapter.backend)
                            && plain(&k.adapter, &adapter.name)
                            && plain(&k.driver, &adapter.driver)
                            && plain(&k.driver_info, &adapter.driver_info)
                    })
                    .map(|k| k as *const _);
                prop_assert_eq!(known, plainly);
            }
        }
    }
}
