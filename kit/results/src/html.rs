//! The HTML report: one self-contained static page set (no network, no external files) for a
//! person or a CI artifact browser. `index.html` is the matrix of case runs × runs (a run per
//! adapter, or runs over time; each run with its kind, date, commit and tag) with outcomes, a
//! regression against the run before on the same adapter marked; `case/N.html` each case run's
//! outcome, reason, parameters, GPU time, metrics and evidence (result, reference, error mask);
//! `compare.html` each run against the one before it on the same adapter (regressions, fixes,
//! metric and GPU-time changes); `reports.html` the technique reports' plots and tables. Evidence
//! and plots are copied under `files/`; pages of an earlier write of the same folder are removed.

use std::collections::BTreeMap;
use std::fmt::Write as _;
use std::path::{Path, PathBuf};

use anyhow::{Context, Result};

use super::compare::{Comparison, GpuHistory, TimeJudgement, compare};
use super::markup::escape;
use fragkit_report::readable::{counted, number, utc_time};
use fragkit_report::report::{CaseRecord, Report};
use fragkit_report::run_info::RunInfo;

/// One column of the matrix.
pub struct Column {
    /// e.g. "run 12" or a report's file name.
    pub label: String,
    pub report: Report,
    /// False for a database run whose process ended before it finished.
    pub complete: bool,
}

impl Column {
    pub fn new(label: String, report: Report) -> Self {
        Self { label, report, complete: true }
    }

    /// "name (backend)": which runs are one adapter's.
    fn adapter(&self) -> String {
        format!("{} ({})", self.report.adapter.name, self.report.adapter.backend)
    }
}

/// The page set's mark in its index, so that a later write of the folder knows which old pages
/// are its own to remove.
const GENERATOR: &str = "<meta name=\"generator\" content=\"fragkit html\">";

const STYLE: &str = "
body { font: 14px/1.4 system-ui, sans-serif; margin: 1.5em; color: #222; }
table { border-collapse: collapse; margin: 0.5em 0 1.5em; }
th, td { border: 1px solid #ccc; padding: 0.25em 0.5em; text-align: left; vertical-align: top; }
th { background: #f3f3f3; }
td.pass { background: #d9f2d9; } td.fail, td.unexpected_pass { background: #f7c6c6; font-weight: bold; }
td.not_supported, td.skip, td.not_run { background: #eee; color: #666; } td.known_issue { background: #fbe8c0; }
td.flaky { background: #f3d1f3; font-weight: bold; } td.absent { color: #aaa; }
td.regressed { outline: 3px solid #b00; outline-offset: -3px; } .incomplete { color: #b00; font-weight: bold; }
.evidence figcaption { display: flex; } .evidence figcaption span { flex: 1; text-align: center; }
pre { white-space: pre-wrap; background: #f7f7f7; padding: 0.5em; max-width: 70em; }
.evidence { display: flex; flex-wrap: wrap; gap: 1em; }
.evidence figure { margin: 0; } .evidence img { image-rendering: pixelated; min-width: 24em; max-width: 48em; border: 1px solid #ccc; }
img.broken { outline: 3px solid red; }
nav a { margin-right: 1em; }
";

/// Marks an evidence image that did not load, on the page and in the console (so that a
/// browser test sees it).
const SCRIPT: &str = "
window.addEventListener('load', () => {
  for (const img of document.images) {
    if (!img.complete || img.naturalWidth === 0) {
      img.classList.add('broken');
      console.error('image did not load: ' + img.getAttribute('src'));
    }
  }
});
const filter = document.getElementById('filter');
if (filter) {
  filter.addEventListener('input', () => {
    const needle = filter.value.toLowerCase();
    for (const row of document.querySelectorAll('#matrix tr.case')) {
      row.hidden = !row.dataset.name.toLowerCase().includes(needle);
    }
  });
}
";

fn page(title: &str, depth: usize, body: &str) -> String {
    let up = "../".repeat(depth);
    format!(
        "<!DOCTYPE html>\n<html lang=\"en\"><head><meta charset=\"utf-8\">{GENERATOR}<title>{title}</title><style>{STYLE}</style></head>\n<body>\n<nav><a href=\"{up}index.html\">matrix</a><a href=\"{up}compare.html\">comparison</a><a href=\"{up}reports.html\">technique reports</a></nav>\n<h1>{title}</h1>\n{body}\n<script>{SCRIPT}</script>\n</body></html>\n",
        title = escape(title)
    )
}

fn outcome_class(record: &CaseRecord) -> String {
    serde_json::to_value(record.outcome).ok().and_then(|v| v.as_str().map(str::to_owned)).unwrap_or_default()
}

/// Writes the page set for `columns` into `dir`; `report_dirs` are folders `fragkit report`
/// wrote (their PNG plots and markdown tables go on the reports page). Returns the index's path.
pub fn write_site(dir: &Path, columns: &[Column], report_dirs: &[PathBuf]) -> Result<PathBuf> {
    anyhow::ensure!(!columns.is_empty(), "an HTML report needs at least one run");
    remove_earlier_pages(dir)?;
    for sub in ["case", "files"] {
        std::fs::create_dir_all(dir.join(sub)).with_context(|| format!("creating {}", dir.join(sub).display()))?;
    }
    // Case runs in order of first appearance across the columns.
    let mut order: Vec<String> = Vec::new();
    let mut cells: BTreeMap<String, Vec<Option<&CaseRecord>>> = BTreeMap::new();
    for (i, column) in columns.iter().enumerate() {
        for record in &column.report.cases {
            let key = record.run_name();
            let row = cells.entry(key.clone()).or_insert_with(|| {
                order.push(key.clone());
                vec![None; columns.len()]
            });
            row[i] = Some(record);
        }
    }
    let mut copier = FileCopier { dir: dir.join("files"), copied: 0 };
    let previous = comparisons_with_previous(columns);
    let mut index = matrix(columns, &order, &cells, &previous);
    for (n, key) in order.iter().enumerate() {
        let body = case_page(columns, &cells[key], &mut copier)?;
        write(&dir.join(format!("case/{n}.html")), &page(key, 1, &body))?;
    }
    let _ = write!(
        index,
        "<p>{} in {}.</p>",
        counted(order.len(), "case run", "case runs"),
        counted(columns.len(), "run", "runs")
    );
    let index_path = dir.join("index.html");
    write(&index_path, &page("fragkit results", 0, &index))?;
    write(&dir.join("compare.html"), &page("Comparison", 0, &comparison_page(columns, &previous)))?;
    write(&dir.join("reports.html"), &page("Technique reports", 0, &reports_page(report_dirs, &mut copier)?))?;
    Ok(index_path)
}

/// Removes the case pages and copied files of an earlier page set in `dir` (one whose index
/// fragkit wrote), so that no page of a case no longer shown survives.
fn remove_earlier_pages(dir: &Path) -> Result<()> {
    let ours = std::fs::read_to_string(dir.join("index.html")).is_ok_and(|index| index.contains(GENERATOR));
    if !ours {
        return Ok(());
    }
    for sub in ["case", "files"] {
        let path = dir.join(sub);
        if path.is_dir() {
            std::fs::remove_dir_all(&path).with_context(|| format!("removing the earlier {}", path.display()))?;
        }
    }
    Ok(())
}

/// For each column, the column before it on the same adapter and the comparison of the two: what
/// the matrix marks and the comparison page lists.
fn comparisons_with_previous(columns: &[Column]) -> Vec<Option<(&Column, Comparison)>> {
    (0..columns.len())
        .map(|i| {
            previous_on_adapter(columns, i).map(|before| {
                let judgement = TimeJudgement::default();
                (before, compare(&before.report, &columns[i].report, &judgement, &GpuHistory::default()))
            })
        })
        .collect()
}

/// The column before column `i` on the same adapter.
fn previous_on_adapter(columns: &[Column], i: usize) -> Option<&Column> {
    let adapter = columns[i].adapter();
    columns[..i].iter().rev().find(|c| c.adapter() == adapter)
}

/// A column's heading: its label, adapter and driver, and what the run says of itself.
fn column_heading(column: &Column) -> String {
    let a = &column.report.adapter;
    let mut lines = vec![
        format!("{} ({})", escape(&a.name), escape(&a.backend)),
        format!("{} {}", escape(&a.driver), escape(&a.driver_info)),
    ];
    if let Some(run) = &column.report.run {
        let commit = run
            .git_commit
            .as_deref()
            .map_or("commit unknown".to_owned(), |c| format!("commit {}", &c[..c.len().min(10)]));
        lines.push(format!("{} · {} · {}", run.kind.name(), utc_time(run.started_unix), escape(&commit)));
        if let Some(tag) = &run.tag {
            lines.push(format!("tag {}", escape(tag)));
        }
        if let Some(dir) = &run.shader_override {
            lines.push(format!("<span class=\"incomplete\">shaders from {}</span>", escape(dir)));
        }
    }
    lines.push(format!(
        "{}, {}",
        counted(column.report.cases.len(), "case", "cases"),
        counted(column.report.failures(false), "unexpected failure", "unexpected failures")
    ));
    if !column.complete {
        lines.push("<span class=\"incomplete\">incomplete: the run ended before its last case</span>".to_owned());
    }
    format!("<th>{}<br><small>{}</small></th>", escape(&column.label), lines.join("<br>"))
}

fn write(path: &Path, text: &str) -> Result<()> {
    std::fs::write(path, text).with_context(|| format!("writing {}", path.display()))
}

fn matrix(
    columns: &[Column],
    order: &[String],
    cells: &BTreeMap<String, Vec<Option<&CaseRecord>>>,
    previous: &[Option<(&Column, Comparison)>],
) -> String {
    let mut html = String::from(
        "<p><label>Filter cases: <input id=\"filter\" type=\"search\" placeholder=\"e.g. cps.\"></label></p>\n<table id=\"matrix\">\n<thead><tr><th>case run</th>",
    );
    for column in columns {
        html.push_str(&column_heading(column));
    }
    html.push_str("</tr></thead>\n<tbody>\n");
    // Per column, the case runs that regressed since the column before it on the same adapter.
    let regressed: Vec<Vec<&str>> = previous
        .iter()
        .map(|p| p.iter().flat_map(|(_, c)| c.regressions.iter().map(|r| r.case.as_str())).collect())
        .collect();
    for (n, key) in order.iter().enumerate() {
        let _ = write!(
            html,
            "<tr class=\"case\" data-name=\"{}\"><td><a href=\"case/{n}.html\">{}</a></td>",
            escape(key),
            escape(key)
        );
        for (cell, regressed) in cells[key].iter().zip(&regressed) {
            match cell {
                Some(record) => {
                    let reason = record.reason.lines().next().unwrap_or_default();
                    let (class, mark) = match regressed.contains(&key.as_str()) {
                        true => (format!("{} regressed", outcome_class(record)), " ▼ regressed"),
                        false => (outcome_class(record), ""),
                    };
                    let _ = write!(
                        html,
                        "<td class=\"{class}\" title=\"{}\"><a href=\"case/{n}.html\">{}</a>{mark}</td>",
                        escape(reason),
                        record.outcome.label()
                    );
                }
                None => html.push_str("<td class=\"absent\">—</td>"),
            }
        }
        html.push_str("</tr>\n");
    }
    html.push_str("</tbody></table>\n");
    html
}

/// Copies evidence and plots under `files/` with unique names.
struct FileCopier {
    dir: PathBuf,
    copied: usize,
}

impl FileCopier {
    /// The copy's path relative to the site's root, or None where the file is gone.
    fn copy(&mut self, source: &Path) -> Result<Option<String>> {
        if !source.is_file() {
            return Ok(None);
        }
        let name = source.file_name().map(|n| n.to_string_lossy().into_owned()).unwrap_or_default();
        let name: String = name.chars().map(|c| if c.is_ascii_alphanumeric() || c == '.' { c } else { '_' }).collect();
        let target = format!("{}_{name}", self.copied);
        self.copied += 1;
        std::fs::copy(source, self.dir.join(&target))
            .with_context(|| format!("copying {} into the HTML report", source.display()))?;
        Ok(Some(format!("files/{target}")))
    }
}

fn case_page(columns: &[Column], cells: &[Option<&CaseRecord>], copier: &mut FileCopier) -> Result<String> {
    let mut html = String::new();
    for (column, cell) in columns.iter().zip(cells) {
        let Some(record) = cell else { continue };
        let _ = write!(
            html,
            "<h2>{} — {} ({})</h2>\n<table><tr><th>outcome</th><td class=\"{}\">{}</td></tr>",
            escape(&column.label),
            escape(&column.report.adapter.name),
            escape(&column.report.adapter.backend),
            outcome_class(record),
            record.outcome.label()
        );
        let gpu = match (record.gpu_ms, record.gpu_ms_repeats.len()) {
            (Some(ms), 0) => format!("{ms:.3} ms"),
            (Some(ms), n) => {
                let repeats: Vec<String> = record.gpu_ms_repeats.iter().map(|&r| number(r)).collect();
                format!("{ms:.3} ms (median of {n}: {})", repeats.join(", "))
            }
            (None, _) => "not measured".to_owned(),
        };
        let _ = write!(
            html,
            "<tr><th>GPU time</th><td>{}</td></tr><tr><th>wall time</th><td>{:.1} ms</td></tr><tr><th>attempts</th><td>{}</td></tr>",
            escape(&gpu),
            record.wall_ms,
            record.attempts
        );
        for (name, value) in &record.params {
            let value = serde_json::to_string(value).unwrap_or_default();
            let _ = write!(html, "<tr><th>{}</th><td>{}</td></tr>", escape(name), escape(&value));
        }
        html.push_str("</table>\n");
        if !record.reason.is_empty() {
            let _ = writeln!(html, "<h3>Reason</h3><pre>{}</pre>", escape(&record.reason));
        }
        if !record.diagnostics.is_empty() {
            let _ = writeln!(
                html,
                "<h3>Logged by wgpu and the driver</h3><pre>{}</pre>",
                escape(&record.diagnostics.join("\n"))
            );
        }
        let metrics = record.numeric_metrics();
        if !metrics.is_empty() {
            html.push_str("<h3>Metrics</h3><table><tr><th>metric</th><th>value</th></tr>");
            for (name, value) in &metrics {
                let _ = write!(html, "<tr><td>{}</td><td>{}</td></tr>", escape(name), number(*value));
            }
            html.push_str("</table>\n");
        }
        if !record.evidence.is_empty() {
            html.push_str("<h3>Evidence</h3><div class=\"evidence\">");
            for path in &record.evidence {
                let caption = escape(&path.display().to_string());
                match copier.copy(path)? {
                    Some(copy) => {
                        // Every evidence image is a strip: result, reference, error mask.
                        let _ = write!(
                            html,
                            "<figure><img src=\"../{copy}\" alt=\"{caption}: result, reference, error mask\"><figcaption><span>result</span><span>reference</span><span>error mask</span></figcaption><small>{caption}</small></figure>"
                        );
                    }
                    None => {
                        let _ = write!(html, "<p>missing when this page was made: {caption}</p>");
                    }
                }
            }
            html.push_str("</div>\n");
        }
    }
    Ok(html)
}

/// Each run against the one before it on the same adapter (`fragkit compare` for any other pair).
fn comparison_page(columns: &[Column], previous: &[Option<(&Column, Comparison)>]) -> String {
    let mut html = String::new();
    for (column, with_previous) in columns.iter().zip(previous) {
        let Some((before, comparison)) = with_previous else { continue };
        let _ = write!(
            html,
            "<h2>{} against {} ({})</h2>",
            escape(&column.label),
            escape(&before.label),
            escape(&column.adapter())
        );
        html.push_str(&comparison_html(comparison, &before.label, &column.label));
    }
    if html.is_empty() {
        html.push_str("<p>No two runs on one adapter: nothing to compare. Each run is compared with the one before it on the same adapter; <code>fragkit compare</code> compares any two.</p>");
    }
    html
}

fn comparison_html(c: &Comparison, base: &str, new: &str) -> String {
    let mut html = format!(
        "<p><b>{}</b> against <b>{}</b>: {}, {}, {}, {}, {} slower beyond the noise.</p>\n",
        escape(new),
        escape(base),
        counted(c.regressions.len(), "regression", "regressions"),
        counted(c.fixes.len(), "fix", "fixes"),
        counted(c.other_changes.len(), "other outcome change", "other outcome changes"),
        counted(c.metric_changes.len(), "metric change", "metric changes"),
        counted(c.time_changes.iter().filter(|t| t.regression).count(), "GPU time", "GPU times")
    );
    for (title, id, changes) in [
        ("Regressions", "regressions", &c.regressions),
        ("Fixes", "fixes", &c.fixes),
        ("Other outcome changes", "other", &c.other_changes),
    ] {
        let _ = write!(html, "<h3>{title}</h3>");
        if changes.is_empty() {
            html.push_str("<p>none</p>");
            continue;
        }
        let _ = write!(html, "<table class=\"{id}\"><tr><th>case run</th><th>was</th><th>now</th><th>reason</th></tr>");
        for change in changes {
            let _ = write!(
                html,
                "<tr><td>{}</td><td>{}</td><td>{}</td><td>{}</td></tr>",
                escape(&change.case),
                change.base.label(),
                change.new.label(),
                escape(change.reason.lines().next().unwrap_or_default())
            );
        }
        html.push_str("</table>\n");
    }
    if !c.metric_changes.is_empty() {
        html.push_str(
            "<h3>Metric changes</h3><table><tr><th>case run</th><th>metric</th><th>was</th><th>now</th></tr>",
        );
        for m in &c.metric_changes {
            let _ = write!(
                html,
                "<tr><td>{}</td><td>{}</td><td>{}</td><td>{}</td></tr>",
                escape(&m.case),
                escape(&m.metric),
                number(m.base),
                number(m.new)
            );
        }
        html.push_str("</table>\n");
    }
    let judged: Vec<_> = c.time_changes.iter().filter(|t| t.regression || t.improvement).collect();
    if !judged.is_empty() {
        html.push_str("<h3>GPU time beyond the noise</h3><table><tr><th>case run</th><th>base ms</th><th>new ms</th><th>new / base</th></tr>");
        for t in judged {
            let _ = write!(
                html,
                "<tr><td>{}</td><td>{:.3}</td><td>{:.3}</td><td>{:.3}</td></tr>",
                escape(&t.case),
                t.base_ms,
                t.new_ms,
                t.ratio()
            );
        }
        html.push_str("</table>\n");
    }
    for (title, cases) in [("Only in the base run", &c.only_in_base), ("Only in the new run", &c.only_in_new)] {
        if !cases.is_empty() {
            let items: Vec<String> = cases.iter().map(|k| format!("<li>{}</li>", escape(k))).collect();
            let _ = write!(html, "<h3>{title}</h3><ul>{}</ul>", items.join(""));
        }
    }
    html
}

fn reports_page(report_dirs: &[PathBuf], copier: &mut FileCopier) -> Result<String> {
    if report_dirs.is_empty() {
        return Ok("<p>No technique reports were given (<code>fragkit html --include DIR</code>, a folder \
                   <code>fragkit report</code> wrote).</p>"
            .to_owned());
    }
    let mut html = String::new();
    for dir in report_dirs {
        let mut entries: Vec<PathBuf> = std::fs::read_dir(dir)
            .with_context(|| format!("reading the report folder {}", dir.display()))?
            .filter_map(|e| e.ok().map(|e| e.path()))
            .collect();
        entries.sort();
        let _ = write!(html, "<h2>{}</h2>", escape(&dir.display().to_string()));
        for path in entries {
            match path.extension().and_then(|e| e.to_str()) {
                Some("png") => {
                    if let Some(copy) = copier.copy(&path)? {
                        let caption = escape(&path.display().to_string());
                        let _ = write!(
                            html,
                            "<figure><img src=\"{copy}\" alt=\"{caption}\"><figcaption>{caption}</figcaption></figure>"
                        );
                    }
                }
                Some("md") => {
                    let text = std::fs::read_to_string(&path).with_context(|| format!("reading {}", path.display()))?;
                    let _ = write!(
                        html,
                        "<details><summary>{}</summary><pre>{}</pre></details>",
                        escape(&path.display().to_string()),
                        escape(&text)
                    );
                }
                _ => {}
            }
        }
    }
    Ok(html)
}

/// Writes the single-run page set when `fragkit check --html DIR` finishes.
pub struct HtmlSink<'a> {
    pub dir: &'a Path,
    pub run: RunInfo,
}

impl fragkit_report::sink::Sink for HtmlSink<'_> {
    fn finish(&mut self, report: &Report) -> Result<()> {
        let column = Column::new("this run".to_owned(), Report { run: Some(self.run.clone()), ..report.clone() });
        write_site(self.dir, &[column], &[]).map(|_| ())
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use fragkit_report::AdapterDescription;
    use fragkit_report::report::ReportedOutcome::{self, *};
    use fragkit_report::run_info::RunKind;

    fn adapter(name: &str) -> AdapterDescription {
        AdapterDescription {
            name: name.into(),
            backend: "vulkan".into(),
            driver: "drv".into(),
            driver_info: "Mesa 1".into(),
            ..Default::default()
        }
    }

    fn record(name: &str, outcome: ReportedOutcome) -> CaseRecord {
        CaseRecord::unmeasured(name, outcome, "first line\nsecond <line>")
    }

    fn column(label: &str, gpu: &str, cases: Vec<CaseRecord>) -> Column {
        Column::new(
            label.into(),
            Report { adapter: adapter(gpu), cases, diagnostics: Vec::new(), shard: None, run: None },
        )
    }

    /// A fresh folder under the temp dir.
    fn folder(name: &str) -> PathBuf {
        let dir = std::env::temp_dir().join(format!("fragkit-html-{name}-{}", std::process::id()));
        std::fs::remove_dir_all(&dir).ok();
        std::fs::create_dir_all(&dir).unwrap();
        dir
    }

    fn read(path: PathBuf) -> String {
        std::fs::read_to_string(&path).unwrap_or_else(|e| panic!("{}: {e}", path.display()))
    }

    #[test]
    fn the_matrix_marks_only_a_regression_since_the_run_before_on_the_same_adapter() {
        let dir = folder("matrix");
        let columns = [
            column("run 1", "gpu", vec![record("kit.a", Pass), record("kit.b", Fail)]),
            column("run 2", "other", vec![record("kit.a", Fail)]),
            Column {
                complete: false,
                ..column("run 3", "gpu", vec![record("kit.a", Fail), record("kit.b", Pass), record("kit.c", Pass)])
            },
        ];
        let index = read(write_site(&dir, &columns, &[]).unwrap());
        assert!(index.contains(GENERATOR) && index.contains("<title>fragkit results</title>"));
        assert!(index.contains("<p>3 case runs in 3 runs.</p>"), "{index}");
        // kit.a regressed in run 3 against run 1 (same adapter); run 2's failure is on another.
        let row = |case: &str| index.lines().find(|l| l.contains(&format!("data-name=\"{case}\""))).unwrap().to_owned();
        let a = row("kit.a");
        assert_eq!(a.matches("regressed").count(), 2, "{a}");
        assert!(
            a.contains("<td class=\"fail regressed\" title=\"first line\"><a href=\"case/0.html\">FAIL</a> ▼ regressed</td></tr>"),
            "{a}"
        );
        assert!(a.contains("<td class=\"fail\" title=\"first line\"><a href=\"case/0.html\">FAIL</a></td><td"), "{a}");
        let b = row("kit.b");
        assert!(!b.contains("regressed") && b.contains("<td class=\"absent\">—</td>"), "{b}");
        assert!(row("kit.c").contains("<a href=\"case/2.html\">kit.c</a>"));
        // The incomplete run says so in its heading, and only it.
        assert_eq!(index.matches("incomplete: the run ended before its last case").count(), 1);
        assert!(index.contains("3 cases, 1 unexpected failure"), "{index}");
        for n in 0..3 {
            assert!(dir.join(format!("case/{n}.html")).is_file());
        }
        let compare = read(dir.join("compare.html"));
        assert!(
            compare.contains("<h2>run 3 against run 1 (gpu (vulkan))</h2>")
                && compare.contains(
                    "<p><b>run 3</b> against <b>run 1</b>: 1 regression, 1 fix, 0 other outcome changes, 0 metric changes, 0 GPU times slower beyond the noise.</p>"
                )
                && !compare.contains("run 2 against"),
            "{compare}"
        );
        assert!(compare.contains("<table class=\"regressions\"><tr><th>case run</th><th>was</th><th>now</th><th>reason</th></tr><tr><td>kit.a</td><td>pass</td><td>FAIL</td><td>first line</td></tr>"), "{compare}");
        assert!(compare.contains("<h3>Only in the new run</h3><ul><li>kit.c</li></ul>"), "{compare}");
        // A single run has nothing to compare, and no technique reports were given.
        let single = folder("single");
        write_site(&single, &columns[..1], &[]).unwrap();
        assert!(read(single.join("compare.html")).contains("No two runs on one adapter"));
        assert!(read(single.join("reports.html")).contains("No technique reports were given"));
        assert!(write_site(&single, &[], &[]).is_err());
        std::fs::remove_dir_all(&dir).ok();
        std::fs::remove_dir_all(&single).ok();
    }

    #[test]
    fn a_case_page_shows_every_field_and_copies_its_evidence() {
        let dir = folder("case");
        let image = dir.join("result image.png");
        std::fs::write(&image, b"png").unwrap();
        let measured = CaseRecord {
            gpu_ms: Some(2.0),
            gpu_ms_repeats: vec![3.0, 2.0, 1.5],
            wall_ms: 12.25,
            attempts: 2,
            params: [("size".to_owned(), fragkit_report::param_value::ParamValue::Count(64))].into(),
            metrics: [("error".to_owned(), serde_json::json!({"max": 0.5}))].into(),
            diagnostics: vec!["driver said <this>".into()],
            evidence: vec![image, dir.join("gone.png")],
            ..record("kit.a", Fail)
        };
        // The later run's evidence has the same file name: it gets a copy of its own.
        let later_image = dir.join("later").join("result image.png");
        std::fs::create_dir_all(later_image.parent().unwrap()).unwrap();
        std::fs::write(&later_image, b"later").unwrap();
        let single = CaseRecord {
            gpu_ms: Some(1.25),
            reason: String::new(),
            params: measured.params.clone(),
            evidence: vec![later_image],
            ..record("kit.a", Pass)
        };
        let mut later = column("run 2", "gpu", vec![single]);
        later.report.run = Some(RunInfo {
            kind: RunKind::Bench,
            started_unix: 86_400,
            git_commit: Some("0123456789abcdef".into()),
            tag: Some("nightly".into()),
            shader_override: Some("/tmp/shaders".into()),
            ..Default::default()
        });
        let columns = [column("run 1", "gpu", vec![measured]), later];
        let index = read(write_site(&dir, &columns, &[]).unwrap());
        assert!(
            index.contains("bench · 1970-01-02 00:00 UTC · commit 0123456789<br>tag nightly<br><span class=\"incomplete\">shaders from /tmp/shaders</span>"),
            "{index}"
        );
        assert!(
            index.contains(
                "<th>run 1<br><small>gpu (vulkan)<br>drv Mesa 1<br>1 case, 1 unexpected failure</small></th>"
            ),
            "{index}"
        );
        let page = read(dir.join("case/0.html"));
        for expected in [
            "<h2>run 1 — gpu (vulkan)</h2>\n<table><tr><th>outcome</th><td class=\"fail\">FAIL</td></tr>",
            "<tr><th>GPU time</th><td>2.000 ms (median of 3: 3, 2, 1.5)</td></tr><tr><th>wall time</th><td>12.2 ms</td></tr><tr><th>attempts</th><td>2</td></tr><tr><th>size</th><td>64</td></tr></table>",
            "<h3>Reason</h3><pre>first line\nsecond &lt;line&gt;</pre>",
            "<h3>Logged by wgpu and the driver</h3><pre>driver said &lt;this&gt;</pre>",
            "<h3>Metrics</h3><table><tr><th>metric</th><th>value</th></tr><tr><td>error.max</td><td>0.5</td></tr></table>",
            "<figure><img src=\"../files/0_result_image.png\"",
            "<p>missing when this page was made:",
            "<h2>run 2 — gpu (vulkan)</h2>",
            "<tr><th>GPU time</th><td>1.250 ms</td></tr>",
        ] {
            assert!(page.contains(expected), "{expected:?} not in {page}");
        }
        assert_eq!(page.matches("<h3>Reason</h3>").count(), 1, "an empty reason has no section");
        assert_eq!(std::fs::read(dir.join("files/0_result_image.png")).unwrap(), b"png");
        assert!(page.contains("<img src=\"../files/1_result_image.png\""), "{page}");
        assert_eq!(std::fs::read(dir.join("files/1_result_image.png")).unwrap(), b"later");
        let unmeasured = folder("unmeasured");
        write_site(&unmeasured, &[column("r", "gpu", vec![record("kit.a", Pass)])], &[]).unwrap();
        let page = read(unmeasured.join("case/0.html"));
        assert!(page.contains("<td>not measured</td>") && !page.contains("<h3>Metrics</h3>"), "{page}");
        assert!(!page.contains("<h3>Evidence</h3>") && !page.contains("Logged by wgpu"), "{page}");
        std::fs::remove_dir_all(&dir).ok();
        std::fs::remove_dir_all(&unmeasured).ok();
    }

    #[test]
    fn the_comparison_page_lists_metric_and_time_changes() {
        let dir = folder("changes");
        let timed = |ms: f64, metric: f64| CaseRecord {
            gpu_ms: Some(ms),
            gpu_ms_repeats: vec![ms, ms * 1.001, ms * 0.999, ms * 1.002, ms * 0.998],
            metrics: [("m".to_owned(), serde_json::json!(metric))].into(),
            ..record("kit.t", Pass)
        };
        let columns = [column("base", "gpu", vec![timed(10.0, 1.0)]), column("new", "gpu", vec![timed(20.0, 2.5)])];
        write_site(&dir, &columns, &[]).unwrap();
        let compare = read(dir.join("compare.html"));
        for expected in [
            "1 metric change,".to_owned(),
            "1 GPU time slower beyond the noise".to_owned(),
            "<tr><td>kit.t</td><td>m</td><td>1</td><td>2.5</td></tr>".to_owned(),
            "<h3>GPU time beyond the noise</h3>".to_owned(),
            "<tr><td>kit.t</td><td>10.000</td><td>20.000</td><td>2.000</td></tr>".to_owned(),
            "<h3>Fixes</h3><p>none</p>".to_owned(),
        ] {
            assert!(compare.contains(&expected), "{expected:?} not in {compare}");
        }
        std::fs::remove_dir_all(&dir).ok();
    }

    #[test]
    fn the_reports_page_shows_plots_and_tables_and_a_rewrite_removes_only_its_own_pages() {
        let dir = folder("rewrite");
        let reports = folder("reports");
        std::fs::write(reports.join("b-plot.png"), b"png").unwrap();
        std::fs::write(reports.join("a-table.md"), "| a <b> |").unwrap();
        std::fs::write(reports.join("notes.txt"), "skipped").unwrap();
        let three = column("r", "gpu", vec![record("kit.a", Pass), record("kit.b", Pass), record("kit.c", Pass)]);
        write_site(&dir, &[three], std::slice::from_ref(&reports)).unwrap();
        let page = read(dir.join("reports.html"));
        let (table, plot) =
            (page.find("<details><summary>").unwrap(), page.find("<figure><img src=\"files/0_b_plot.png\"").unwrap());
        assert!(table < plot && page.contains("<pre>| a &lt;b&gt; |</pre>") && !page.contains("notes.txt"), "{page}");
        assert!(dir.join("files/0_b_plot.png").is_file() && dir.join("case/2.html").is_file());
        write_site(&dir, &[column("r", "gpu", vec![record("kit.a", Pass)])], &[]).unwrap();
        assert!(!dir.join("case/2.html").exists() && !dir.join("files/0_b_plot.png").exists());
        // A folder whose index fragkit did not write keeps its files.
        let foreign = folder("foreign");
        std::fs::write(foreign.join("index.html"), "mine").unwrap();
        std::fs::create_dir_all(foreign.join("case")).unwrap();
        std::fs::write(foreign.join("case/7.html"), "mine").unwrap();
        write_site(&foreign, &[column("r", "gpu", vec![record("kit.a", Pass)])], &[]).unwrap();
        assert!(foreign.join("case/7.html").is_file());
        assert!(write_site(&folder("missing"), &[column("r", "gpu", vec![])], &[dir.join("nowhere")]).is_err());
        for d in [dir, reports, foreign, folder("missing")] {
            std::fs::remove_dir_all(d).ok();
        }
    }

    #[test]
    fn the_sink_writes_a_single_run_page_set_with_its_run() {
        let dir = folder("sink");
        let run = RunInfo { tag: Some("mine".into()), ..Default::default() };
        let mut sink = HtmlSink { dir: &dir, run };
        let report = column("x", "gpu", vec![record("kit.a", Pass)]).report;
        fragkit_report::sink::Sink::finish(&mut sink, &report).unwrap();
        let index = read(dir.join("index.html"));
        assert!(index.contains("<th>this run<br>") && index.contains("tag mine"), "{index}");
        std::fs::remove_dir_all(&dir).ok();
    }
}
