//! Where a run's records go (`Sink`: the table, the JSON report, JUnit, the results database…),
//! and which share of a run one shard machine takes.

use std::path::{Path, PathBuf};
use std::time::{Duration, Instant};

use anyhow::{Context, Result, bail};

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
    /// The next case waits (`true`) for a case elsewhere that runs alone, or for the others to
    /// end where it runs alone itself, until it starts (`false`): a supervisor stops that
    /// case's clock meanwhile.
    fn waiting(&mut self, _waiting: bool) -> Result<()> {
        Ok(())
    }
    fn finish(&mut self, report: &Report) -> Result<()>;
}

/// Writes the JSON report when the run finishes (atomically). While it runs, the report so far
/// stands beside it as `<path>.partial` (rewritten at most every [`PARTIAL_EVERY`]): what
/// `check --resume` continues from when the run is killed. Finishing removes it.
pub struct JsonSink<'a> {
    path: &'a Path,
    /// The run's shard, written into the report for `merge`.
    shard: Option<Shard>,
    /// The run's kind, time and commit, written into the report for `import`.
    run: RunInfo,
    /// The report so far, and when it was last written.
    partial: Report,
    written: Option<Instant>,
}

/// How often at most the report so far is rewritten: a killed run loses no more than the case
/// runs of this long, and a long sweep does not rewrite a growing file at every record.
pub const PARTIAL_EVERY: Duration = Duration::from_secs(2);

/// Where the report so far of a run writing `path` stands.
pub fn partial_path(path: &Path) -> PathBuf {
    let mut partial = path.as_os_str().to_owned();
    partial.push(".partial");
    PathBuf::from(partial)
}

impl<'a> JsonSink<'a> {
    pub fn new(path: &'a Path, shard: Option<Shard>, run: RunInfo) -> Self {
        let partial = Report {
            adapter: AdapterDescription::default(),
            cases: Vec::new(),
            diagnostics: Vec::new(),
            shard,
            run: Some(run.clone()),
        };
        Self { path, shard, run, partial, written: None }
    }
}

impl Sink for JsonSink<'_> {
    fn start(&mut self, adapter: &AdapterDescription, _runs: usize) -> Result<()> {
        self.partial.adapter = adapter.clone();
        Ok(())
    }

    fn record(&mut self, record: &CaseRecord) -> Result<()> {
        self.partial.cases.push(record.clone());
        if self.written.is_none_or(|at| at.elapsed() >= PARTIAL_EVERY) {
            self.partial.write_atomically(&partial_path(self.path))?;
            self.written = Some(Instant::now());
        }
        Ok(())
    }

    fn finish(&mut self, report: &Report) -> Result<()> {
        Report { shard: self.shard, run: Some(self.run.clone()), ..report.clone() }.write_atomically(self.path)?;
        let partial = partial_path(self.path);
        match std::fs::remove_file(&partial) {
            Err(e) if e.kind() != std::io::ErrorKind::NotFound => {
                Err(e).with_context(|| format!("removing {}", partial.display()))
            }
            _ => Ok(()),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::report::ReportedOutcome;

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
        let mut sink = JsonSink::new(&path, Some(shard), run.clone());
        let adapter = AdapterDescription { name: "gpu".into(), ..AdapterDescription::default() };
        sink.start(&adapter, 2).unwrap();
        // The first record is written at once beside the report, the next within PARTIAL_EVERY.
        sink.record(&CaseRecord::unmeasured("kit.a", ReportedOutcome::Pass, "")).unwrap();
        sink.record(&CaseRecord::unmeasured("kit.b", ReportedOutcome::Pass, "")).unwrap();
        let partial = Report::read(&partial_path(&path)).unwrap();
        let names: Vec<&str> = partial.cases.iter().map(|c| c.name.as_str()).collect();
        assert_eq!((partial.adapter.name.as_str(), names.as_slice()), ("gpu", &["kit.a"][..]));
        assert_eq!((partial.shard, partial.run.as_ref()), (Some(shard), Some(&run)));
        assert!(!path.exists(), "the report is written when the run finishes");
        sink.finish(&report).unwrap();
        let written = Report::read(&path).unwrap();
        std::fs::remove_file(&path).ok();
        assert_eq!(written.shard, Some(shard));
        assert_eq!(written.run, Some(run));
        assert!(!partial_path(&path).exists(), "the partial report is gone once the run finished");
        assert_eq!(partial_path(Path::new("r.json")), Path::new("r.json.partial"));
        // A run that recorded nothing has no report so far to remove; one that cannot be removed
        // is an error.
        JsonSink::new(&path, None, RunInfo::default()).finish(&report).unwrap();
        std::fs::create_dir_all(partial_path(&path).join("in the way")).unwrap();
        let error = JsonSink::new(&path, None, RunInfo::default()).finish(&report).unwrap_err();
        assert!(format!("{error:#}").contains("removing"), "{error:#}");
        std::fs::remove_dir_all(partial_path(&path)).ok();
        std::fs::remove_file(&path).ok();
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
