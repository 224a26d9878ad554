//! Where, when and how a run was made, beyond its case records: its kind (a `check`, a `bench`,
//! an `import` of a report written elsewhere), start time, kit version, the commit the kit was
//! built from, host, tag, and whether its shaders came from `FRAGKIT_SHADER_DIR` instead of the
//! built-in copies. Written into the JSON report, so an imported report keeps it.

use anyhow::{Result, bail};
use serde::{Deserialize, Serialize};

/// Environment variable naming a folder the kit reads its shaders from at run time instead of
/// its built-in copies (development, mutation testing): a run made so says so.
pub const SHADER_DIR_ENV: &str = "FRAGKIT_SHADER_DIR";

/// The commit the kit was built from (kit/report/build.rs), where the build could ask git.
pub const BUILD_COMMIT: Option<&str> = option_env!("FRAGKIT_GIT_COMMIT");

/// What made a run.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum RunKind {
    /// `fragkit check`: verdicts.
    #[default]
    Check,
    /// `fragkit bench`: timings of the techniques.
    Bench,
    /// `fragkit import`: a report recorded after the fact.
    Import,
}

impl RunKind {
    pub fn name(self) -> &'static str {
        match self {
            Self::Check => "check",
            Self::Bench => "bench",
            Self::Import => "import",
        }
    }

    pub fn parse(text: &str) -> Result<Self> {
        Ok(match text {
            "check" => Self::Check,
            "bench" => Self::Bench,
            "import" => Self::Import,
            other => bail!("run kind {other:?}: expected check, bench or import"),
        })
    }
}

#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct RunInfo {
    #[serde(default)]
    pub kind: RunKind,
    pub started_unix: i64,
    pub kit_version: String,
    #[serde(default)]
    pub git_commit: Option<String>,
    #[serde(default)]
    pub host: Option<String>,
    #[serde(default)]
    pub tag: Option<String>,
    /// The folder shaders were read from (`FRAGKIT_SHADER_DIR`) where not the built-in copies:
    /// such a run measured other shaders than its commit's.
    #[serde(default)]
    pub shader_override: Option<String>,
}

impl RunInfo {
    /// This process's run of `kind`: now, this kit's version and build commit, this host, the
    /// shader override in force.
    pub fn now(kind: RunKind, tag: Option<String>) -> Self {
        let started_unix =
            std::time::SystemTime::now().duration_since(std::time::UNIX_EPOCH).map_or(0, |d| d.as_secs() as i64);
        let host = std::fs::read_to_string("/proc/sys/kernel/hostname")
            .ok()
            .or_else(|| std::env::var("HOSTNAME").ok())
            .map(|h| h.trim().to_owned());
        Self {
            kind,
            started_unix,
            kit_version: env!("CARGO_PKG_VERSION").to_owned(),
            git_commit: BUILD_COMMIT.map(str::to_owned),
            host,
            tag,
            shader_override: std::env::var_os(SHADER_DIR_ENV).map(|dir| dir.to_string_lossy().into_owned()),
        }
    }

    /// A report's run, recorded now by `import`: when, where and from what it ran are the
    /// report's (where it says; a report written before it did is recorded as imported now).
    pub fn imported(recorded: Option<&RunInfo>, tag: Option<String>) -> Self {
        match recorded {
            Some(run) => Self { kind: RunKind::Import, tag: tag.or_else(|| run.tag.clone()), ..run.clone() },
            None => {
                // What built the report is not known: only when and where it was recorded.
                let now = Self::now(RunKind::Import, None);
                Self {
                    kind: RunKind::Import,
                    started_unix: now.started_unix,
                    kit_version: now.kit_version,
                    git_commit: None,
                    host: now.host,
                    tag,
                    shader_override: None,
                }
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn kinds_round_trip_and_unknown_ones_are_refused() {
        for kind in [RunKind::Check, RunKind::Bench, RunKind::Import] {
            assert_eq!(RunKind::parse(kind.name()).unwrap(), kind);
        }
        assert!(RunKind::parse("soak").is_err());
    }

    #[test]
    fn an_imported_report_keeps_when_and_from_what_it_ran() {
        let ran = RunInfo {
            started_unix: 7,
            git_commit: Some("abc".into()),
            tag: Some("nightly".into()),
            ..Default::default()
        };
        let imported = RunInfo::imported(Some(&ran), None);
        assert_eq!(
            (imported.kind, imported.started_unix, imported.git_commit.as_deref()),
            (RunKind::Import, 7, Some("abc"))
        );
        assert_eq!(imported.tag.as_deref(), Some("nightly"));
        assert_eq!(RunInfo::imported(Some(&ran), Some("again".into())).tag.as_deref(), Some("again"));
        let unknown = RunInfo::imported(None, Some("t".into()));
        assert_eq!((unknown.kind, unknown.git_commit, unknown.tag.as_deref()), (RunKind::Import, None, Some("t")));
    }

    #[test]
    fn a_run_now_is_of_its_kind_this_kits_version_and_this_time() {
        let before = std::time::SystemTime::now().duration_since(std::time::UNIX_EPOCH).unwrap().as_secs() as i64;
        let run = RunInfo::now(RunKind::Bench, Some("t".into()));
        assert_eq!((run.kind, run.tag.as_deref(), run.kit_version.as_str()), (RunKind::Bench, Some("t"), "0.1.0"));
        assert!((before..=before + 60).contains(&run.started_unix), "{}", run.started_unix);
    }
}
