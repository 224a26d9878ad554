//! The record stream between `fragkit check` and the child process that runs its cases: one
//! JSON line per event, flushed as it happens, so that what a child recorded before it died (a
//! driver abort, a hang the parent killed) is never lost. The parent reads the lines back, hands
//! the records to its sinks, records the case the child died in as `crash` or `timeout`, and
//! starts a new child after it.

use std::fs::File;
use std::io::{Read, Seek, SeekFrom, Write};
use std::path::Path;

use anyhow::{Context, Result};
use serde::{Deserialize, Serialize};

use fragkit_report::AdapterDescription;
use fragkit_report::report::{CaseRecord, Report};
use fragkit_report::sink::Sink;

#[derive(Debug, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum StreamLine {
    /// The child opened its device and will run this many case runs.
    Start { adapter: AdapterDescription, runs: usize },
    /// One case run finished.
    Record(Box<CaseRecord>),
    /// The next case run waits for the case lock (`true`: its clock stops) or has started.
    Waiting(bool),
    /// The child ran every case; what wgpu and the driver logged outside the cases.
    Finished { diagnostics: Vec<String> },
}

/// Appends the stream's lines to a file.
pub struct StreamSink {
    file: File,
}

impl StreamSink {
    pub fn create(path: &Path) -> Result<Self> {
        let file = std::fs::OpenOptions::new()
            .create(true)
            .append(true)
            .open(path)
            .with_context(|| format!("opening the record stream {}", path.display()))?;
        Ok(Self { file })
    }

    fn write(&mut self, line: &StreamLine) -> Result<()> {
        let mut text = serde_json::to_string(line)?;
        text.push('\n');
        self.file.write_all(text.as_bytes()).context("writing the record stream")?;
        self.file.flush().context("flushing the record stream")
    }
}

impl Sink for StreamSink {
    fn start(&mut self, adapter: &AdapterDescription, runs: usize) -> Result<()> {
        self.write(&StreamLine::Start { adapter: adapter.clone(), runs })
    }

    fn record(&mut self, record: &CaseRecord) -> Result<()> {
        self.write(&StreamLine::Record(Box::new(record.clone())))
    }

    fn waiting(&mut self, waiting: bool) -> Result<()> {
        self.write(&StreamLine::Waiting(waiting))
    }

    fn finish(&mut self, report: &Report) -> Result<()> {
        self.write(&StreamLine::Finished { diagnostics: report.diagnostics.clone() })
    }
}

/// Reads the complete lines a stream file holds past `offset` bytes; returns them and the offset
/// after the last complete line (a line still being written is left for the next read).
/// Only the bytes past `offset` are read: the parent polls a growing file.
pub fn read_new_lines(path: &Path, offset: u64) -> Result<(Vec<StreamLine>, u64)> {
    let reading = || format!("reading the record stream {}", path.display());
    let mut file = match File::open(path) {
        Ok(file) => file,
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => return Ok((Vec::new(), offset)),
        Err(e) => return Err(e).with_context(reading),
    };
    file.seek(SeekFrom::Start(offset)).with_context(reading)?;
    let mut bytes = Vec::new();
    file.read_to_end(&mut bytes).with_context(reading)?;
    let complete = bytes.iter().rposition(|&b| b == b'\n').map_or(0, |i| i + 1);
    let mut lines = Vec::new();
    for line in bytes[..complete].split(|&b| b == b'\n').filter(|l| !l.is_empty()) {
        lines.push(serde_json::from_slice(line).context("a record stream line is not valid")?);
    }
    Ok((lines, offset + complete as u64))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_partly_written_line_waits_for_the_next_read() {
        let path = std::env::temp_dir().join(format!("fragkit-stream-test-{}", std::process::id()));
        let start =
            serde_json::to_string(&StreamLine::Start { adapter: AdapterDescription::default(), runs: 3 }).unwrap();
        std::fs::write(&path, format!("{start}\n{{\"finished\"")).unwrap();
        let (lines, offset) = read_new_lines(&path, 0).unwrap();
        assert!(matches!(lines.as_slice(), [StreamLine::Start { runs: 3, .. }]));
        assert_eq!(offset as usize, start.len() + 1);
        std::fs::write(&path, format!("{start}\n{{\"finished\":{{\"diagnostics\":[]}}}}\n")).unwrap();
        let (lines, _) = read_new_lines(&path, offset).unwrap();
        assert!(matches!(lines.as_slice(), [StreamLine::Finished { .. }]));
        std::fs::remove_file(&path).ok();
    }

    #[test]
    fn a_sinks_events_are_read_back_in_order_and_a_missing_stream_holds_none() {
        let path = std::env::temp_dir().join(format!("fragkit-stream-sink-{}", std::process::id()));
        std::fs::remove_file(&path).ok();
        assert!(read_new_lines(&path, 7).unwrap().0.is_empty() && read_new_lines(&path, 7).unwrap().1 == 7);
        let adapter = AdapterDescription { name: "gpu".into(), ..Default::default() };
        let record = CaseRecord::unmeasured("kit.a", fragkit_report::report::ReportedOutcome::Pass, "");
        let mut sink = StreamSink::create(&path).unwrap();
        sink.start(&adapter, 2).unwrap();
        sink.record(&record).unwrap();
        sink.waiting(true).unwrap();
        let report = Report {
            adapter: adapter.clone(),
            cases: vec![record],
            diagnostics: vec!["logged".into()],
            shard: None,
            run: None,
        };
        sink.finish(&report).unwrap();
        let (lines, offset) = read_new_lines(&path, 0).unwrap();
        assert_eq!(offset, std::fs::metadata(&path).unwrap().len());
        match lines.as_slice() {
            [
                StreamLine::Start { adapter: a, runs: 2 },
                StreamLine::Record(r),
                StreamLine::Waiting(true),
                StreamLine::Finished { diagnostics },
            ] => {
                assert_eq!(
                    (a.name.as_str(), r.name.as_str(), diagnostics.as_slice()),
                    ("gpu", "kit.a", &["logged".to_owned()][..])
                );
            }
            other => panic!("{other:?}"),
        }
        // A stream that cannot be opened for another reason than its absence is an error.
        assert!(read_new_lines(&path.join("below a file"), 0).is_err());
        // A line that is not the stream's is an error, not skipped.
        std::fs::write(&path, "{\"nonsense\": 1}\n").unwrap();
        assert!(read_new_lines(&path, 0).is_err());
        std::fs::remove_file(&path).ok();
    }
}
