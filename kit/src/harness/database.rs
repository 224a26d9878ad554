//! The results database: every run of the kit — when, kit version and git commit, host, tag,
//! adapter — with each case run's outcome, reason, parameters, metrics (kept whole as JSON, and
//! flattened to numbers for queries), GPU and wall times, attempts and evidence paths. An embedded
//! SQLite file (bundled SQLite: nothing to install). The schema is versioned and migrated
//! forward on open; a database newer than this kit is refused. A run is written in one
//! transaction, so a killed run leaves nothing half-written, and writers wait for each other
//! (busy timeout), so two runs writing at once both land.

use std::path::{Path, PathBuf};
use std::time::Duration;

use anyhow::{Context, Result, bail};
use rusqlite::{Connection, OptionalExtension, TransactionBehavior, params};

use super::report::{CaseRecord, Report, ReportedOutcome};
use crate::gpu::AdapterDescription;

/// Schema migrations, applied in order; the database's `user_version` says how many ran.
const MIGRATIONS: &[&str] = &[
    // 1: runs and their case runs.
    "CREATE TABLE runs (
        id INTEGER PRIMARY KEY,
        started_unix INTEGER NOT NULL,
        kit_version TEXT NOT NULL,
        git_commit TEXT,
        host TEXT,
        tag TEXT,
        adapter TEXT NOT NULL,
        backend TEXT NOT NULL,
        driver TEXT NOT NULL,
        driver_info TEXT NOT NULL,
        device_type TEXT NOT NULL
    );
    CREATE TABLE case_runs (
        id INTEGER PRIMARY KEY,
        run_id INTEGER NOT NULL REFERENCES runs(id),
        position INTEGER NOT NULL,
        name TEXT NOT NULL,
        params TEXT NOT NULL,
        outcome TEXT NOT NULL,
        reason TEXT NOT NULL,
        gpu_ms REAL,
        wall_ms REAL NOT NULL,
        attempts INTEGER NOT NULL,
        evidence TEXT NOT NULL,
        metrics TEXT NOT NULL
    );
    CREATE INDEX case_runs_by_run ON case_runs(run_id, position);
    CREATE INDEX case_runs_by_name ON case_runs(name);
    CREATE TABLE metrics (
        case_run_id INTEGER NOT NULL REFERENCES case_runs(id),
        name TEXT NOT NULL,
        value REAL NOT NULL
    );
    CREATE INDEX metrics_by_case_run ON metrics(case_run_id);",
];

/// Where and how a run was made, beyond its report.
#[derive(Clone, Debug, Default)]
pub struct RunInfo {
    pub started_unix: i64,
    pub kit_version: String,
    pub git_commit: Option<String>,
    pub host: Option<String>,
    pub tag: Option<String>,
}

impl RunInfo {
    /// This process's run: now, the kit's version, the commit of the source tree it was built
    /// from where git can tell, this host.
    pub fn now(tag: Option<String>) -> Self {
        let started_unix =
            std::time::SystemTime::now().duration_since(std::time::UNIX_EPOCH).map_or(0, |d| d.as_secs() as i64);
        let git_commit = std::process::Command::new("git")
            .args(["-C", env!("CARGO_MANIFEST_DIR"), "rev-parse", "HEAD"])
            .output()
            .ok()
            .filter(|o| o.status.success())
            .map(|o| String::from_utf8_lossy(&o.stdout).trim().to_owned());
        let host = std::fs::read_to_string("/proc/sys/kernel/hostname")
            .ok()
            .or_else(|| std::env::var("HOSTNAME").ok())
            .map(|h| h.trim().to_owned());
        Self { started_unix, kit_version: env!("CARGO_PKG_VERSION").to_owned(), git_commit, host, tag }
    }
}

/// Which run of a database: `latest`, `latest~N` (N runs before the latest), a run id, or
/// `tag:NAME` (the latest run with that tag).
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum RunRef {
    Latest(u32),
    Id(i64),
    Tag(String),
}

impl RunRef {
    pub fn parse(text: &str) -> Result<Self> {
        if text == "latest" {
            return Ok(Self::Latest(0));
        }
        if let Some(back) = text.strip_prefix("latest~") {
            return back
                .parse()
                .map(Self::Latest)
                .map_err(|_| anyhow::anyhow!("run {text:?}: expected latest~N with N a whole number"));
        }
        if let Some(tag) = text.strip_prefix("tag:") {
            return Ok(Self::Tag(tag.to_owned()));
        }
        text.parse().map(Self::Id).map_err(|_| {
            anyhow::anyhow!("run {text:?}: expected a run id, latest, latest~N or tag:NAME (or a JSON report's path)")
        })
    }
}

impl std::fmt::Display for RunRef {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            Self::Latest(0) => write!(f, "latest"),
            Self::Latest(back) => write!(f, "latest~{back}"),
            Self::Id(id) => write!(f, "{id}"),
            Self::Tag(tag) => write!(f, "tag:{tag}"),
        }
    }
}

pub struct Database {
    connection: Connection,
    path: PathBuf,
}

fn outcome_name(outcome: ReportedOutcome) -> String {
    serde_json::to_value(outcome).ok().and_then(|v| v.as_str().map(str::to_owned)).unwrap_or_default()
}

impl Database {
    /// Opens (creating where missing) the database at `path` and migrates it to this kit's schema.
    pub fn open(path: &Path) -> Result<Self> {
        let connection =
            Connection::open(path).with_context(|| format!("opening the results database {}", path.display()))?;
        connection.busy_timeout(Duration::from_secs(60)).context("setting the database's busy timeout")?;
        let mut database = Self { connection, path: path.to_owned() };
        database.migrate()?;
        Ok(database)
    }

    pub fn path(&self) -> &Path {
        &self.path
    }

    fn migrate(&mut self) -> Result<()> {
        let what = || format!("the results database {}", self.path.display());
        let transaction = self
            .connection
            .transaction_with_behavior(TransactionBehavior::Immediate)
            .with_context(|| format!("{} is not an SQLite database, or is locked", what()))?;
        let version: i64 = transaction
            .query_row("PRAGMA user_version", [], |row| row.get(0))
            .with_context(|| format!("{} is not an SQLite database", what()))?;
        let known = MIGRATIONS.len() as i64;
        if version > known {
            bail!("{} has schema version {version}; this kit knows up to {known}: use a newer fragkit", what());
        }
        if version == 0 {
            let tables: i64 = transaction.query_row("SELECT count(*) FROM sqlite_master", [], |row| row.get(0))?;
            if tables > 0 {
                bail!("{} holds other tables and no fragkit schema version: not a fragkit results database", what());
            }
        }
        for (i, migration) in MIGRATIONS.iter().enumerate().skip(version as usize) {
            transaction
                .execute_batch(migration)
                .with_context(|| format!("migrating {} to version {}", what(), i + 1))?;
            transaction.pragma_update(None, "user_version", i as i64 + 1)?;
        }
        transaction.commit().with_context(|| format!("committing the migration of {}", what()))
    }

    /// Records a run in one transaction; returns its id.
    pub fn record(&mut self, report: &Report, info: &RunInfo) -> Result<i64> {
        let transaction = self.connection.transaction_with_behavior(TransactionBehavior::Immediate)?;
        let a = &report.adapter;
        transaction.execute(
            "INSERT INTO runs (started_unix, kit_version, git_commit, host, tag, adapter, backend, driver, driver_info, device_type)
             VALUES (?1, ?2, ?3, ?4, ?5, ?6, ?7, ?8, ?9, ?10)",
            params![
                info.started_unix,
                info.kit_version,
                info.git_commit,
                info.host,
                info.tag,
                a.name,
                a.backend,
                a.driver,
                a.driver_info,
                a.device_type
            ],
        )?;
        let run_id = transaction.last_insert_rowid();
        for (position, case) in report.cases.iter().enumerate() {
            transaction.execute(
                "INSERT INTO case_runs (run_id, position, name, params, outcome, reason, gpu_ms, wall_ms, attempts, evidence, metrics)
                 VALUES (?1, ?2, ?3, ?4, ?5, ?6, ?7, ?8, ?9, ?10, ?11)",
                params![
                    run_id,
                    position as i64,
                    case.name,
                    serde_json::to_string(&case.params)?,
                    outcome_name(case.outcome),
                    case.reason,
                    case.gpu_ms,
                    case.wall_ms,
                    case.attempts,
                    serde_json::to_string(&case.evidence)?,
                    serde_json::to_string(&case.metrics)?,
                ],
            )?;
            let case_run_id = transaction.last_insert_rowid();
            let mut insert =
                transaction.prepare_cached("INSERT INTO metrics (case_run_id, name, value) VALUES (?1, ?2, ?3)")?;
            for (name, value) in case.numeric_metrics() {
                insert.execute(params![case_run_id, name, value])?;
            }
        }
        transaction.commit().with_context(|| format!("committing the run to {}", self.path.display()))?;
        Ok(run_id)
    }

    /// The id of the run `which` names.
    pub fn resolve(&self, which: &RunRef) -> Result<i64> {
        let found: Option<i64> = match which {
            RunRef::Id(id) => {
                self.connection.query_row("SELECT id FROM runs WHERE id = ?1", [id], |r| r.get(0)).optional()?
            }
            RunRef::Latest(back) => self
                .connection
                .query_row("SELECT id FROM runs ORDER BY id DESC LIMIT 1 OFFSET ?1", [back], |r| r.get(0))
                .optional()?,
            RunRef::Tag(tag) => self
                .connection
                .query_row("SELECT id FROM runs WHERE tag = ?1 ORDER BY id DESC LIMIT 1", [tag], |r| r.get(0))
                .optional()?,
        };
        found.ok_or_else(|| {
            let runs: i64 = self.connection.query_row("SELECT count(*) FROM runs", [], |r| r.get(0)).unwrap_or(0);
            anyhow::anyhow!("{} holds no run {which} ({runs} runs recorded)", self.path.display())
        })
    }

    /// The report of run `id`, as `fragkit check --json` would have written it.
    pub fn load(&self, id: i64) -> Result<Report> {
        let adapter = self.connection.query_row(
            "SELECT adapter, backend, driver, driver_info, device_type FROM runs WHERE id = ?1",
            [id],
            |r| {
                Ok(AdapterDescription {
                    name: r.get(0)?,
                    backend: r.get(1)?,
                    driver: r.get(2)?,
                    driver_info: r.get(3)?,
                    device_type: r.get(4)?,
                })
            },
        )?;
        let mut statement = self.connection.prepare(
            "SELECT name, params, outcome, reason, gpu_ms, wall_ms, attempts, evidence, metrics
             FROM case_runs WHERE run_id = ?1 ORDER BY position",
        )?;
        let rows = statement.query_map([id], |r| {
            Ok((
                r.get::<_, String>(0)?,
                r.get::<_, String>(1)?,
                r.get::<_, String>(2)?,
                r.get::<_, String>(3)?,
                r.get::<_, Option<f64>>(4)?,
                r.get::<_, f64>(5)?,
                r.get::<_, u32>(6)?,
                r.get::<_, String>(7)?,
                r.get::<_, String>(8)?,
            ))
        })?;
        let mut cases = Vec::new();
        for row in rows {
            let (name, params, outcome, reason, gpu_ms, wall_ms, attempts, evidence, metrics) = row?;
            let corrupt =
                |what: &str| format!("run {id}'s case {name}: its {what} in {} does not parse", self.path.display());
            cases.push(CaseRecord {
                params: serde_json::from_str(&params).with_context(|| corrupt("parameters"))?,
                outcome: serde_json::from_value(serde_json::Value::String(outcome))
                    .with_context(|| corrupt("outcome"))?,
                evidence: serde_json::from_str(&evidence).with_context(|| corrupt("evidence"))?,
                metrics: serde_json::from_str(&metrics).with_context(|| corrupt("metrics"))?,
                name,
                reason,
                gpu_ms,
                wall_ms,
                attempts,
            });
        }
        Ok(Report { adapter, cases })
    }

    /// Per run holding case `case` (oldest first) on an adapter whose "name (backend)" matches
    /// `adapter` (a glob): the mean of `metric` over its runs of that case — `gpu_ms`, `wall_ms`
    /// or a flattened metric path such as `foveated.seam_free.seam_error`.
    pub fn history(&self, case: &str, metric: &str, adapter: &glob::Pattern) -> Result<Vec<HistoryPoint>> {
        let value = match metric {
            "gpu_ms" => "avg(c.gpu_ms)",
            "wall_ms" => "avg(c.wall_ms)",
            _ => {
                "(SELECT avg(m.value) FROM metrics m JOIN case_runs c2 ON m.case_run_id = c2.id
                   WHERE c2.run_id = r.id AND c2.name = ?1 AND m.name = ?2)"
            }
        };
        let sql = format!(
            "SELECT r.id, r.started_unix, r.adapter, r.backend, r.driver_info, {value}
             FROM runs r JOIN case_runs c ON c.run_id = r.id
             WHERE c.name = ?1 GROUP BY r.id ORDER BY r.id"
        );
        let mut statement = self.connection.prepare(&sql)?;
        let bound = if statement.parameter_count() == 2 { params![case, metric] } else { params![case] };
        let rows = statement.query_map(bound, |r| {
            Ok(HistoryPoint {
                run_id: r.get(0)?,
                started_unix: r.get(1)?,
                adapter: format!("{} ({})", r.get::<_, String>(2)?, r.get::<_, String>(3)?),
                driver_info: r.get(4)?,
                value: r.get(5)?,
            })
        })?;
        let points: Vec<HistoryPoint> =
            rows.collect::<rusqlite::Result<Vec<_>>>()?.into_iter().filter(|p| adapter.matches(&p.adapter)).collect();
        if points.is_empty() {
            bail!("{} holds no run of {case} on an adapter matching {:?}", self.path.display(), adapter.as_str());
        }
        Ok(points)
    }
}

/// One run's value in a case's history.
#[derive(Clone, Debug, PartialEq)]
pub struct HistoryPoint {
    pub run_id: i64,
    pub started_unix: i64,
    /// "name (backend)".
    pub adapter: String,
    pub driver_info: String,
    /// None where the run did not measure it (no timestamps, no such metric).
    pub value: Option<f64>,
}

/// Records the run in the database (opened, and so checked, before the run) when it finishes.
pub struct DatabaseSink {
    pub database: Database,
    pub info: RunInfo,
    pub run_id: Option<i64>,
}

impl super::run::Sink for DatabaseSink {
    fn finish(&mut self, report: &Report) -> Result<()> {
        self.run_id = Some(self.database.record(report, &self.info)?);
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use std::collections::BTreeMap;

    use super::*;

    fn report() -> Report {
        Report {
            adapter: AdapterDescription { name: "gpu".into(), backend: "vulkan".into(), ..Default::default() },
            cases: vec![CaseRecord {
                name: "kit.a".into(),
                outcome: ReportedOutcome::KnownIssue,
                reason: "why".into(),
                params: BTreeMap::new(),
                metrics: [("m".to_owned(), serde_json::json!({"x": 1.5, "ok": true}))].into(),
                gpu_ms: Some(2.0),
                wall_ms: 3.0,
                evidence: vec![PathBuf::from("e.png")],
                attempts: 1,
            }],
        }
    }

    #[test]
    fn a_recorded_run_loads_back_as_its_report_and_refs_resolve() {
        let path = std::env::temp_dir().join(format!("fragkit-db-{}.sqlite", std::process::id()));
        std::fs::remove_file(&path).ok();
        let mut db = Database::open(&path).unwrap();
        let first = db.record(&report(), &RunInfo { tag: Some("base".into()), ..Default::default() }).unwrap();
        let second = db.record(&report(), &RunInfo::default()).unwrap();
        assert_eq!(db.resolve(&RunRef::parse("latest").unwrap()).unwrap(), second);
        assert_eq!(db.resolve(&RunRef::parse("latest~1").unwrap()).unwrap(), first);
        assert_eq!(db.resolve(&RunRef::parse("tag:base").unwrap()).unwrap(), first);
        assert!(db.resolve(&RunRef::Id(99)).is_err());
        let loaded = db.load(first).unwrap();
        assert_eq!(serde_json::to_value(&loaded).unwrap(), serde_json::to_value(report()).unwrap());
        drop(db);
        // A schema newer than this kit is refused.
        Connection::open(&path).unwrap().pragma_update(None, "user_version", 99).unwrap();
        assert!(Database::open(&path).err().unwrap().to_string().contains("schema version 99"));
        std::fs::remove_file(&path).ok();
    }

    #[test]
    fn run_refs_parse_or_say_what_they_expect() {
        assert_eq!(RunRef::parse("latest~2").unwrap(), RunRef::Latest(2));
        assert_eq!(RunRef::parse("17").unwrap(), RunRef::Id(17));
        assert!(RunRef::parse("latest~x").is_err());
        assert!(RunRef::parse("yesterday").is_err());
    }
}
