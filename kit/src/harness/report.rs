//! The JSON report: `{"adapter": {...}, "cases": [{"name", "outcome", "reason", "params",
//! "metrics", "gpu_ms", "wall_ms"}]}`, written atomically.

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

use anyhow::{Context, Result};
use serde::Serialize;

use super::params::Params;
use crate::gpu::AdapterDescription;

/// A case's outcome as reported, after the expectations file was applied.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum ReportedOutcome {
    Pass,
    Fail,
    NotSupported,
    /// Failed, as the expectations file says it does on this adapter.
    KnownIssue,
    /// Listed in the expectations file but passed: the entry is stale.
    UnexpectedPass,
}

impl ReportedOutcome {
    /// Whether this outcome fails a CI run.
    pub fn is_failure(self) -> bool {
        matches!(self, Self::Fail | Self::UnexpectedPass)
    }

    pub fn label(self) -> &'static str {
        match self {
            Self::Pass => "pass",
            Self::Fail => "FAIL",
            Self::NotSupported => "not_supported",
            Self::KnownIssue => "known_issue",
            Self::UnexpectedPass => "UNEXPECTED_PASS",
        }
    }
}

#[derive(Clone, Debug, Serialize)]
pub struct CaseRecord {
    pub name: String,
    pub outcome: ReportedOutcome,
    pub reason: String,
    pub params: Params,
    pub metrics: BTreeMap<String, serde_json::Value>,
    /// Sum of the case's timed passes; null where the adapter has no timestamps.
    pub gpu_ms: Option<f64>,
    pub wall_ms: f64,
    pub evidence: Vec<PathBuf>,
}

#[derive(Clone, Debug, Serialize)]
pub struct Report {
    pub adapter: AdapterDescription,
    pub cases: Vec<CaseRecord>,
}

impl Report {
    pub fn failures(&self) -> usize {
        self.cases.iter().filter(|c| c.outcome.is_failure()).count()
    }

    /// Writes the report through a temporary file and a rename, so that an interrupted run never
    /// leaves a half-written report behind.
    pub fn write_atomically(&self, path: &Path) -> Result<()> {
        let text = serde_json::to_string_pretty(self).context("serialising the report")?;
        let temporary = path.with_extension("json.tmp");
        std::fs::write(&temporary, text).with_context(|| format!("writing {}", temporary.display()))?;
        std::fs::rename(&temporary, path).with_context(|| format!("moving the report into place at {}", path.display()))
    }
}
