//! Where a run's records go (`Sink`: the table, the JSON report, JUnit, the results database…),
//! and which share of a run one shard machine takes.

use std::path::Path;

use anyhow::{Result, bail};

use crate::adapter::AdapterDescription;
use crate::report::{CaseRecord, Report};
use crate::run_info::RunInfo;

/// Shard `index` of `count` (1-based, as `--shard K/N` spells it).
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
pub struct Shard {
    pub index: u32,
    pub count: u32,
}

impl Shard {
    /// Parses `K/N` with 1 ≤ K ≤ N.
    pub fn parse(text: &str) -> Result<Self> {
        let parsed = text
            .split_once('/')
            .and_then(|(k, n)| Some((k.trim().parse::<u32>().ok()?, n.trim().parse::<u32>().ok()?)));
        match parsed {
            Some((index, count)) if (1..=count).contains(&index) => Ok(Self { index, count }),
            _ => bail!("--shard {text:?}: expected K/N with 1 <= K <= N, e.g. 2/4"),
        }
    }

    /// This shard's runs: every N-th of the list, starting at the K-th. The list is the same on
    /// every machine (registry order, seeded draws), so the shards together run each once.
    pub fn select<T>(self, runs: Vec<T>) -> Vec<T> {
        runs.into_iter()
            .enumerate()
            .filter(|(i, _)| *i as u32 % self.count == self.index - 1)
            .map(|(_, run)| run)
            .collect()
    }
}

/// Where a run's records go. `record` sees each case as it finishes; `finish` the whole report,
/// also when the run stops early (a device that cannot be reopened).
pub trait Sink {
    fn start(&mut self, _adapter: &AdapterDescription, _runs: usize) -> Result<()> {
        Ok(())
    }
    fn record(&mut self, _record: &CaseRecord) -> Result<()> {
        Ok(())
    }
    fn finish(&mut self, report: &Report) -> Result<()>;
}

/// Writes the JSON report when the run finishes (atomically).
pub struct JsonSink<'a> {
    pub path: &'a Path,
    /// The run's shard, written into the report for `merge`.
    pub shard: Option<Shard>,
    /// The run's kind, time and commit, written into the report for `import`.
    pub run: RunInfo,
}

impl Sink for JsonSink<'_> {
    fn finish(&mut self, report: &Report) -> Result<()> {
        Report { shard: self.shard, run: Some(self.run.clone()), ..report.clone() }.write_atomically(self.path)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_shard_takes_every_nth_run_from_its_own() {
        assert_eq!(Shard { index: 2, count: 3 }.select((0..8).collect()), [1, 4, 7]);
        assert_eq!(Shard { index: 1, count: 1 }.select((0..3).collect()), [0, 1, 2]);
    }

    #[test]
    fn the_json_sink_writes_the_report_with_its_shard_and_run() {
        let path = std::env::temp_dir().join(format!("fragkit-json-sink-{}.json", std::process::id()));
        let shard = Shard { index: 2, count: 4 };
        let run = RunInfo { tag: Some("nightly".into()), ..RunInfo::default() };
        let report = Report {
            adapter: AdapterDescription::default(),
            cases: Vec::new(),
            diagnostics: Vec::new(),
            shard: None,
            run: None,
        };
        JsonSink { path: &path, shard: Some(shard), run: run.clone() }.finish(&report).unwrap();
        let written = Report::read(&path).unwrap();
        std::fs::remove_file(&path).ok();
        assert_eq!(written.shard, Some(shard));
        assert_eq!(written.run, Some(run));
    }

    #[test]
    fn shards_together_take_every_run_once() {
        let mut seen: Vec<u32> = (1..=3).flat_map(|k| Shard { index: k, count: 3 }.select((0..5).collect())).collect();
        seen.sort_unstable();
        assert_eq!(seen, [0, 1, 2, 3, 4]);
    }

    #[test]
    fn shard_spellings_outside_one_to_n_are_refused() {
        assert_eq!(Shard::parse("2/4").unwrap(), Shard { index: 2, count: 4 });
        for bad in ["3/2", "0/4", "1/0", "1", "a/b", "-1/2"] {
            assert!(Shard::parse(bad).is_err(), "{bad} accepted");
        }
    }
}
