//! The connection under the results database: an embedded SQLite file or a PostgreSQL server,
//! behind one small interface — transactions that run SQL with `$1`-style parameters and return
//! rows of plain values — so that both hold the same schema and answer the same queries.

use std::time::Duration;

use anyhow::{Context, Result, bail};
use rusqlite::TransactionBehavior;

/// A parameter of a statement, typed so that PostgreSQL accepts a null for its column.
#[derive(Clone, Debug)]
pub enum Param<'a> {
    Int(Option<i64>),
    Real(Option<f64>),
    Text(Option<&'a str>),
}

impl From<i64> for Param<'_> {
    fn from(v: i64) -> Self {
        Self::Int(Some(v))
    }
}
impl From<f64> for Param<'_> {
    fn from(v: f64) -> Self {
        Self::Real(Some(v))
    }
}
impl From<Option<f64>> for Param<'_> {
    fn from(v: Option<f64>) -> Self {
        Self::Real(v)
    }
}
impl<'a> From<&'a str> for Param<'a> {
    fn from(v: &'a str) -> Self {
        Self::Text(Some(v))
    }
}
impl<'a> From<&'a String> for Param<'a> {
    fn from(v: &'a String) -> Self {
        Self::Text(Some(v))
    }
}
impl<'a> From<Option<&'a str>> for Param<'a> {
    fn from(v: Option<&'a str>) -> Self {
        Self::Text(v)
    }
}

/// One value of a result row.
#[derive(Clone, Debug, PartialEq)]
pub enum Value {
    Null,
    Int(i64),
    Real(f64),
    Text(String),
}

/// A result row, with typed accessors that say which column was not what the schema promises.
#[derive(Clone, Debug)]
pub struct Row(pub Vec<Value>);

impl Row {
    pub fn int(&self, i: usize) -> Result<i64> {
        match self.0.get(i) {
            Some(Value::Int(v)) => Ok(*v),
            other => bail!("column {i}: expected an integer, found {other:?}"),
        }
    }
    pub fn real(&self, i: usize) -> Result<Option<f64>> {
        match self.0.get(i) {
            Some(Value::Real(v)) => Ok(Some(*v)),
            Some(Value::Int(v)) => Ok(Some(*v as f64)),
            Some(Value::Null) => Ok(None),
            other => bail!("column {i}: expected a number, found {other:?}"),
        }
    }
    pub fn text(&self, i: usize) -> Result<String> {
        match self.0.get(i) {
            Some(Value::Text(v)) => Ok(v.clone()),
            other => bail!("column {i}: expected text, found {other:?}"),
        }
    }
    pub fn optional_text(&self, i: usize) -> Result<Option<String>> {
        match self.0.get(i) {
            Some(Value::Null) => Ok(None),
            _ => self.text(i).map(Some),
        }
    }
}

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Dialect {
    Sqlite,
    Postgres,
}

pub enum Store {
    Sqlite(rusqlite::Connection),
    Postgres(Box<PostgresConnection>),
}

/// A PostgreSQL client and what it was opened from, to connect again after the server went away.
pub struct PostgresConnection {
    client: postgres::Client,
    conninfo: String,
}

/// How long a transaction keeps trying to reach a PostgreSQL server that went away (a restart,
/// a network drop) before the error stands: long enough for a server restart.
const RECONNECT_WINDOW: Duration = Duration::from_secs(120);

/// Whether an error is the connection's, not the statement's: worth connecting again for.
fn is_connection_error(error: &anyhow::Error) -> bool {
    error.chain().any(|cause| {
        cause.downcast_ref::<postgres::Error>().is_some_and(|e| {
            e.is_closed()
                || e.code().is_some_and(|code| code.code().starts_with("08") || code.code() == "57P01")
                || std::error::Error::source(e).is_some_and(|s| s.is::<std::io::Error>())
        })
    })
}

/// Where a results database is, parsed from `--db`.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum Location {
    /// An SQLite file: a plain path, or `sqlite:PATH` / `sqlite://PATH`.
    Sqlite(std::path::PathBuf),
    /// A PostgreSQL server: a `postgres://` or `postgresql://` URL (any case), or a libpq
    /// `key=value` connection string (`host=… dbname=…`).
    Postgres(String),
}

impl Location {
    /// Parses `--db`: by scheme where there is one (an unknown scheme is refused, not taken for a
    /// file name), a libpq `key=value` string, else an SQLite path. Never echoes a password.
    pub fn parse(text: &str) -> Result<Self> {
        if text.trim().is_empty() {
            bail!("--db is empty: give an SQLite file's path or a postgres:// URL");
        }
        if let Some((scheme, rest)) = text.split_once("://")
            && !scheme.is_empty()
            && scheme.chars().all(|c| c.is_ascii_alphanumeric() || "+-.".contains(c))
        {
            return match scheme.to_ascii_lowercase().as_str() {
                "postgres" | "postgresql" => Ok(Self::Postgres(format!("postgresql://{rest}"))),
                "sqlite" | "file" if !rest.is_empty() => Ok(Self::Sqlite(rest.into())),
                other => bail!(
                    "--db {}: a {other}:// database is not one fragkit records into; give an SQLite file's path or a postgres:// URL",
                    redact(text)
                ),
            };
        }
        if let Some(path) = text.strip_prefix("sqlite:") {
            anyhow::ensure!(!path.is_empty(), "--db sqlite: names no file");
            return Ok(Self::Sqlite(path.into()));
        }
        if looks_like_libpq_keywords(text) {
            return Ok(Self::Postgres(text.to_owned()));
        }
        Ok(Self::Sqlite(text.into()))
    }
}

/// Whether `text` is a libpq keyword/value connection string: words `key=value` separated by
/// spaces, the first key a libpq keyword.
fn looks_like_libpq_keywords(text: &str) -> bool {
    const KEYWORDS: &[&str] = &[
        "host",
        "hostaddr",
        "port",
        "dbname",
        "user",
        "password",
        "sslmode",
        "connect_timeout",
        "application_name",
        "options",
    ];
    text.split_whitespace().next().and_then(|word| word.split_once('=')).is_some_and(|(key, _)| KEYWORDS.contains(&key))
}

/// How a command uses the database: a run records into it (an SQLite file is created where
/// missing, and must be writable and whole before the run starts), a reader reads what is there
/// (a missing file is an error, never created; a reader, too, brings an older schema up to date).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Access {
    Record,
    Read,
}

impl Store {
    /// Connects to `location` for `access`.
    pub fn open(location: &Location, access: Access) -> Result<Self> {
        let path = match location {
            Location::Postgres(conninfo) => {
                let client = postgres::Client::connect(conninfo, postgres::NoTls)
                    .with_context(|| format!("connecting to the results database {}", redact(conninfo)))?;
                return Ok(Self::Postgres(Box::new(PostgresConnection { client, conninfo: conninfo.clone() })));
            }
            Location::Sqlite(path) => path,
        };
        let shown = path.display();
        let flags = match access {
            Access::Record => rusqlite::OpenFlags::SQLITE_OPEN_READ_WRITE | rusqlite::OpenFlags::SQLITE_OPEN_CREATE,
            Access::Read => {
                anyhow::ensure!(path.is_file(), "no results database at {shown} (a reader never creates one)");
                rusqlite::OpenFlags::SQLITE_OPEN_READ_WRITE
            }
        } | rusqlite::OpenFlags::SQLITE_OPEN_NO_MUTEX
            | rusqlite::OpenFlags::SQLITE_OPEN_URI;
        let connection = rusqlite::Connection::open_with_flags(path, flags)
            .with_context(|| format!("opening the results database {shown}"))?;
        // Writers queue for each other instead of failing.
        connection.busy_timeout(Duration::from_secs(60)).context("setting the database's busy timeout")?;
        if access == Access::Record {
            // SQLite opens a file it may not write read-only, without a word.
            anyhow::ensure!(
                !connection.is_readonly(rusqlite::MAIN_DB).unwrap_or(true),
                "the results database {shown} is read-only: a run could not be recorded"
            );
        }
        // A damaged page is found now, not by a later reader.
        let verdict: String = connection
            .query_row("PRAGMA quick_check", [], |row| row.get(0))
            .with_context(|| format!("checking the results database {shown}"))?;
        anyhow::ensure!(verdict == "ok", "the results database {shown} is damaged: {verdict}");
        Ok(Self::Sqlite(connection))
    }

    pub fn dialect(&self) -> Dialect {
        match self {
            Self::Sqlite(_) => Dialect::Sqlite,
            Self::Postgres(_) => Dialect::Postgres,
        }
    }

    /// Runs `work` in one transaction, committed when it returns Ok, rolled back otherwise (or
    /// when the process dies first). SQLite takes the write lock at the start, so two writers
    /// queue rather than deadlock. Where a PostgreSQL server went away, the transaction is run
    /// again on a new connection, retried with backoff for up to `RECONNECT_WINDOW`.
    pub fn transaction<T>(&mut self, mut work: impl FnMut(&mut Transaction) -> Result<T>) -> Result<T> {
        match self {
            Self::Sqlite(connection) => {
                let tx = connection.transaction_with_behavior(TransactionBehavior::Immediate)?;
                let mut transaction = Transaction::Sqlite(tx);
                let result = work(&mut transaction)?;
                let Transaction::Sqlite(tx) = transaction else { unreachable!("built as SQLite above") };
                tx.commit().context("committing")?;
                Ok(result)
            }
            Self::Postgres(connection) => {
                let started = std::time::Instant::now();
                let mut wait = Duration::from_millis(250);
                loop {
                    let attempt = (|| {
                        let tx = connection.client.transaction()?;
                        let mut transaction = Transaction::Postgres(tx);
                        let result = work(&mut transaction)?;
                        let Transaction::Postgres(tx) = transaction else { unreachable!("built as PostgreSQL above") };
                        tx.commit().context("committing")?;
                        Ok(result)
                    })();
                    match attempt {
                        Err(error) if is_connection_error(&error) && started.elapsed() < RECONNECT_WINDOW => {
                            log::warn!("the results database went away ({error:#}); connecting again in {wait:?}");
                            std::thread::sleep(wait);
                            wait = (wait * 2).min(Duration::from_secs(8));
                            if let Ok(client) = postgres::Client::connect(&connection.conninfo, postgres::NoTls) {
                                connection.client = client;
                            }
                        }
                        other => return other,
                    }
                }
            }
        }
    }
}

/// A location without its password, for messages: a URL's `user:password@`, a libpq string's
/// `password=…`.
pub fn redact(location: &str) -> String {
    if looks_like_libpq_keywords(location) {
        return location
            .split_whitespace()
            .map(|word| if word.starts_with("password=") { "password=***" } else { word })
            .collect::<Vec<_>>()
            .join(" ");
    }
    match (location.find("://"), location.rfind('@')) {
        (Some(scheme), Some(at)) if at > scheme => {
            let credentials = &location[scheme + 3..at];
            match credentials.split_once(':') {
                Some((user, _)) => format!("{}{user}:***{}", &location[..scheme + 3], &location[at..]),
                None => location.to_owned(),
            }
        }
        _ => location.to_owned(),
    }
}

pub enum Transaction<'a> {
    Sqlite(rusqlite::Transaction<'a>),
    Postgres(postgres::Transaction<'a>),
}

/// `$1`-style placeholders as SQLite spells them (`?1`): same numbers, any order.
fn sqlite_sql(sql: &str) -> String {
    sql.replace('$', "?")
}

fn sqlite_param(p: &Param) -> rusqlite::types::Value {
    use rusqlite::types::Value as V;
    match p {
        Param::Int(v) => v.map_or(V::Null, V::Integer),
        Param::Real(v) => v.map_or(V::Null, V::Real),
        Param::Text(v) => v.map_or(V::Null, |s| V::Text(s.to_owned())),
    }
}

fn postgres_params<'p>(params: &'p [Param]) -> Vec<Box<dyn postgres::types::ToSql + Sync + 'p>> {
    params
        .iter()
        .map(|p| -> Box<dyn postgres::types::ToSql + Sync> {
            match p {
                Param::Int(v) => Box::new(*v),
                Param::Real(v) => Box::new(*v),
                Param::Text(v) => Box::new(*v),
            }
        })
        .collect()
}

fn postgres_value(row: &postgres::Row, i: usize) -> Result<Value> {
    use postgres::types::Type;
    let ty = row.columns()[i].type_().clone();
    let value = if ty == Type::INT8 {
        row.try_get::<_, Option<i64>>(i)?.map(Value::Int)
    } else if ty == Type::INT4 {
        row.try_get::<_, Option<i32>>(i)?.map(|v| Value::Int(v.into()))
    } else if ty == Type::FLOAT8 {
        row.try_get::<_, Option<f64>>(i)?.map(Value::Real)
    } else if ty == Type::FLOAT4 {
        row.try_get::<_, Option<f32>>(i)?.map(|v| Value::Real(v.into()))
    } else if ty == Type::TEXT || ty == Type::VARCHAR || ty == Type::NAME {
        row.try_get::<_, Option<String>>(i)?.map(Value::Text)
    } else {
        bail!("column {i} has type {ty}, which the results database does not use")
    };
    Ok(value.unwrap_or(Value::Null))
}

impl Transaction<'_> {
    pub fn dialect(&self) -> Dialect {
        match self {
            Self::Sqlite(_) => Dialect::Sqlite,
            Self::Postgres(_) => Dialect::Postgres,
        }
    }

    /// Runs statements without parameters (a migration).
    pub fn batch(&mut self, sql: &str) -> Result<()> {
        match self {
            Self::Sqlite(tx) => tx.execute_batch(sql)?,
            Self::Postgres(tx) => tx.batch_execute(sql)?,
        }
        Ok(())
    }

    pub fn execute(&mut self, sql: &str, params: &[Param]) -> Result<u64> {
        match self {
            Self::Sqlite(tx) => {
                let values: Vec<rusqlite::types::Value> = params.iter().map(sqlite_param).collect();
                let mut statement = tx.prepare_cached(&sqlite_sql(sql))?;
                Ok(statement.execute(rusqlite::params_from_iter(values))? as u64)
            }
            Self::Postgres(tx) => {
                let owned = postgres_params(params);
                let refs: Vec<&(dyn postgres::types::ToSql + Sync)> = owned.iter().map(|b| b.as_ref()).collect();
                Ok(tx.execute(sql, &refs)?)
            }
        }
    }

    pub fn query(&mut self, sql: &str, params: &[Param]) -> Result<Vec<Row>> {
        match self {
            Self::Sqlite(tx) => {
                let values: Vec<rusqlite::types::Value> = params.iter().map(sqlite_param).collect();
                let mut statement = tx.prepare_cached(&sqlite_sql(sql))?;
                let columns = statement.column_count();
                let rows = statement.query_map(rusqlite::params_from_iter(values), |row| {
                    (0..columns)
                        .map(|i| {
                            use rusqlite::types::ValueRef;
                            Ok(match row.get_ref(i)? {
                                ValueRef::Null => Value::Null,
                                ValueRef::Integer(v) => Value::Int(v),
                                ValueRef::Real(v) => Value::Real(v),
                                ValueRef::Text(t) => Value::Text(String::from_utf8_lossy(t).into_owned()),
                                ValueRef::Blob(_) => Value::Null,
                            })
                        })
                        .collect::<rusqlite::Result<Vec<Value>>>()
                        .map(Row)
                })?;
                Ok(rows.collect::<rusqlite::Result<Vec<Row>>>()?)
            }
            Self::Postgres(tx) => {
                let owned = postgres_params(params);
                let refs: Vec<&(dyn postgres::types::ToSql + Sync)> = owned.iter().map(|b| b.as_ref()).collect();
                tx.query(sql, &refs)?
                    .iter()
                    .map(|row| (0..row.len()).map(|i| postgres_value(row, i)).collect::<Result<Vec<_>>>().map(Row))
                    .collect()
            }
        }
    }

    /// The first row of `sql`'s result, if any.
    pub fn query_one(&mut self, sql: &str, params: &[Param]) -> Result<Option<Row>> {
        Ok(self.query(sql, params)?.into_iter().next())
    }
}

/// The URL of the PostgreSQL server the tests use (FRAGKIT_TEST_POSTGRES, from `bash
/// .ci/postgres`), or None with a note where it is unset — never under CI, which must test the
/// PostgreSQL backend.
#[cfg(test)]
pub(crate) fn test_server() -> Option<String> {
    let Ok(server) = std::env::var("FRAGKIT_TEST_POSTGRES") else {
        assert!(std::env::var_os("CI").is_none(), "CI must test the PostgreSQL backend (.ci/postgres)");
        eprintln!("note: FRAGKIT_TEST_POSTGRES is unset (see .ci/postgres): PostgreSQL test skipped");
        return None;
    };
    Some(server)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn database_locations_parse_by_scheme_and_never_show_a_password() {
        assert_eq!(Location::parse("runs.sqlite").unwrap(), Location::Sqlite("runs.sqlite".into()));
        assert_eq!(Location::parse("sqlite:x.db").unwrap(), Location::Sqlite("x.db".into()));
        assert_eq!(Location::parse("sqlite:///tmp/x.db").unwrap(), Location::Sqlite("/tmp/x.db".into()));
        assert_eq!(Location::parse("POSTGRES://u:p@h/db").unwrap(), Location::Postgres("postgresql://u:p@h/db".into()));
        let keywords = "host=/tmp password=hunter2 dbname=fragkit";
        assert_eq!(Location::parse(keywords).unwrap(), Location::Postgres(keywords.into()));
        assert_eq!(redact(keywords), "host=/tmp password=*** dbname=fragkit");
        assert_eq!(redact("postgres://u:hunter2@h/db"), "postgres://u:***@h/db");
        for refused in ["", "  ", "mysql://u:hunter2@h/db", "http://h/x", "sqlite:"] {
            let error = format!("{:#}", Location::parse(refused).unwrap_err());
            assert!(!error.contains("hunter2"), "{error}");
        }
    }

    #[test]
    fn passwords_stay_out_of_messages() {
        assert_eq!(redact("postgres://kit:secret@db:5432/runs"), "postgres://kit:***@db:5432/runs");
        assert_eq!(redact("postgres://kit@db/runs"), "postgres://kit@db/runs");
        assert_eq!(redact("results.sqlite"), "results.sqlite");
    }

    #[test]
    fn an_empty_sqlite_url_and_a_url_of_no_scheme_are_not_files() {
        for refused in ["sqlite://", "file://"] {
            assert!(Location::parse(refused).is_err(), "{refused}");
        }
        assert_eq!(Location::parse("file:///tmp/x.db").unwrap(), Location::Sqlite("/tmp/x.db".into()));
        // An '@' before the scheme is no user's: nothing to redact.
        assert_eq!(redact("me@box://u:secret@h/db"), "me@box://u:***@h/db");
        assert_eq!(redact("a@b://c"), "a@b://c");
    }

    #[test]
    fn an_sqlite_file_opened_read_only_is_refused_for_recording_and_read_through_a_uri() {
        let path = std::env::temp_dir().join(format!("fragkit-store-ro-{}.sqlite", std::process::id()));
        std::fs::remove_file(&path).ok();
        let mut store = Store::open(&Location::Sqlite(path.clone()), Access::Record).unwrap();
        store.transaction(|tx| tx.batch("CREATE TABLE t (x BIGINT); INSERT INTO t VALUES (7)")).unwrap();
        drop(store);
        let read_only = Location::Sqlite(format!("file:{}?mode=ro", path.display()).into());
        let error = format!("{:#}", Store::open(&read_only, Access::Record).err().unwrap());
        assert!(error.contains("is read-only: a run could not be recorded"), "{error}");
        // The same URI names no file a reader could find; the plain path reads.
        assert!(Store::open(&read_only, Access::Read).is_err());
        let mut reader = Store::open(&Location::Sqlite(path.clone()), Access::Read).unwrap();
        let row = reader.transaction(|tx| tx.query_one("SELECT x FROM t WHERE x = $1", &[7i64.into()])).unwrap();
        assert_eq!(row.unwrap().0, [Value::Int(7)]);
        std::fs::remove_file(&path).ok();
    }

    /// A connection to the tests' PostgreSQL server, where there is one.
    fn postgres() -> Option<Store> {
        test_server().map(|server| Store::open(&Location::parse(&server).unwrap(), Access::Record).unwrap())
    }

    #[test]
    fn postgres_values_of_every_type_the_store_reads_and_nulls_of_each_parameter() {
        let Some(mut store) = postgres() else { return };
        let row = store
            .transaction(|tx| {
                tx.query_one(
                    "SELECT 1::int4, 2::int8, 2.5::float4, 0.25::float8, 'v'::varchar, 'n'::name, 't'::text,
                        $1::int8, $2::float8, $3::text, $4::int8, $5::float8, $6::text",
                    &[Param::Int(None), Param::Real(None), Param::Text(None), 9i64.into(), 0.5f64.into(), "w".into()],
                )
            })
            .unwrap()
            .unwrap();
        use Value::*;
        assert_eq!(
            row.0,
            [
                Int(1),
                Int(2),
                Real(2.5),
                Real(0.25),
                Text("v".into()),
                Text("n".into()),
                Text("t".into()),
                Null,
                Null,
                Null,
                Int(9),
                Real(0.5),
                Text("w".into())
            ]
        );
        let error = store.transaction(|tx| tx.query("SELECT 'x'::bytea", &[])).unwrap_err();
        assert!(format!("{error:#}").contains("column 0 has type bytea"), "{error:#}");
    }

    #[test]
    fn a_server_that_ends_the_session_is_connected_to_again_and_a_bad_statement_is_not_retried() {
        let Some(mut store) = postgres() else { return };
        // The server ends this session (as a restart would) in the first attempt only.
        let mut attempts = 0;
        let started = std::time::Instant::now();
        let result = store.transaction(|tx| {
            attempts += 1;
            if attempts == 1 {
                tx.query("SELECT pg_terminate_backend(pg_backend_pid())", &[])?;
            }
            tx.query_one("SELECT count(*) FROM information_schema.tables", &[])?.context("a count")?.int(0)
        });
        assert!(result.is_ok() && attempts == 2, "{result:?} after {attempts} attempts");
        // A statement's own error stands at once.
        let started_bad = std::time::Instant::now();
        let error = store.transaction(|tx| tx.batch("SELEKT 1")).unwrap_err();
        assert!(!is_connection_error(&error) && format!("{error:#}").contains("syntax error"), "{error:#}");
        assert!(started_bad.elapsed() < Duration::from_secs(5) && started.elapsed() < Duration::from_secs(60));
        // A session ended by the server, and a server that is not there, are the connection's.
        let refused = postgres::Client::connect("postgresql://fragkit@127.0.0.1:1/none", postgres::NoTls)
            .err()
            .map(anyhow::Error::from)
            .unwrap();
        assert!(is_connection_error(&refused.context("connecting")), "a refused connection");
        let server = test_server().expect("the store above connected to it");
        let mut client = postgres::Client::connect(&server, postgres::NoTls).unwrap();
        let terminated = client
            .query("SELECT pg_terminate_backend(pg_backend_pid())", &[])
            .map_err(anyhow::Error::from)
            .unwrap_err();
        assert!(is_connection_error(&terminated), "{terminated:#}");
    }
}
