//! The HTML report in a real browser: `fragkit html` of two runs (the second with a case broken),
//! opened in headless Chromium (Debian's `chromium`, installed by .ci/setup). The matrix must have
//! a row per case run, the pages must load without a console message (the page itself reports an
//! image that did not load there), the comparison must list the broken case, and a screenshot is
//! saved for a person.

use std::path::{Path, PathBuf};
use std::process::Command;

fn fragkit(args: &[&str]) -> String {
    let output = Command::new(env!("CARGO_BIN_EXE_fragkit")).args(args).output().expect("running fragkit");
    let text = String::from_utf8_lossy(&output.stdout).into_owned() + &String::from_utf8_lossy(&output.stderr);
    assert!(output.status.success(), "fragkit {args:?}:\n{text}");
    text
}

/// The Chromium binary, or None (with a note) where there is none outside CI.
fn chromium() -> Option<&'static str> {
    let found = ["chromium", "chromium-browser", "google-chrome"]
        .into_iter()
        .find(|name| Command::new(name).arg("--version").output().is_ok_and(|o| o.status.success()));
    if found.is_none() {
        assert!(std::env::var_os("CI").is_none(), "CI must test the HTML report in Chromium: .ci/setup installs it");
        eprintln!("note: no chromium here (bash .ci/setup installs it): browser test skipped");
    }
    found
}

/// What headless Chromium makes of `page`: the DOM after the load event, and its console lines.
fn open_in_chromium(browser: &str, page: &Path, profile: &Path, screenshot: Option<&Path>) -> (String, Vec<String>) {
    let url = format!("file://{}", page.canonicalize().unwrap().display());
    let mut command = Command::new("timeout");
    command.args(["120", browser, "--headless", "--no-sandbox", "--disable-gpu", "--enable-logging=stderr", "--v=0"]);
    command.arg(format!("--user-data-dir={}", profile.display()));
    command.arg("--virtual-time-budget=3000");
    match screenshot {
        Some(path) => command.arg(format!("--screenshot={}", path.display())).arg("--window-size=1280,900"),
        None => command.arg("--dump-dom"),
    };
    let output = command.arg(&url).output().expect("running chromium");
    assert!(output.status.success(), "chromium on {url}: {}", String::from_utf8_lossy(&output.stderr));
    let console =
        String::from_utf8_lossy(&output.stderr).lines().filter(|l| l.contains("CONSOLE")).map(str::to_owned).collect();
    (String::from_utf8_lossy(&output.stdout).into_owned(), console)
}

#[test]
fn the_html_report_loads_in_chromium_with_a_row_per_case_and_the_regression_listed() {
    let Some(browser) = chromium() else { return };
    let dir = PathBuf::from(env!("CARGO_TARGET_TMPDIR")).join("html-report");
    std::fs::remove_dir_all(&dir).ok();
    std::fs::create_dir_all(&dir).unwrap();
    let (base, new, evidence) = (dir.join("base.json"), dir.join("new.json"), dir.join("evidence"));
    fragkit(&[
        "check",
        "kit.hash.values",
        "kit.msaa.*",
        "kit.scissor.msaa",
        "--json",
        base.to_str().unwrap(),
        "--out",
        evidence.to_str().unwrap(),
    ]);
    // The new run: the same with kit.hash.values failing.
    let mut report: serde_json::Value = serde_json::from_str(&std::fs::read_to_string(&base).unwrap()).unwrap();
    let cases = report["cases"].as_array_mut().unwrap();
    let broken = cases.iter_mut().find(|c| c["name"] == "kit.hash.values").unwrap();
    broken["outcome"] = "fail".into();
    broken["reason"] = "<b>3 values differ</b> & more".into();
    let rows = cases.len();
    std::fs::write(&new, report.to_string()).unwrap();
    // A technique report folder: a plot and its table.
    let plots = dir.join("plots");
    std::fs::create_dir_all(&plots).unwrap();
    image::RgbaImage::from_pixel(64, 32, image::Rgba([40, 90, 200, 255])).save(plots.join("plot.png")).unwrap();
    std::fs::write(plots.join("table.md"), "| a | b |\n|---|---|\n| 1 | 2 |\n").unwrap();

    let site = dir.join("site");
    fragkit(&[
        "html",
        base.to_str().unwrap(),
        new.to_str().unwrap(),
        "--include",
        plots.to_str().unwrap(),
        "--out",
        site.to_str().unwrap(),
    ]);

    let profile = dir.join("chromium-profile");
    let (dom, console) = open_in_chromium(browser, &site.join("index.html"), &profile, None);
    assert!(console.is_empty(), "console messages on the matrix: {console:#?}");
    assert_eq!(dom.matches("<tr class=\"case\"").count(), rows, "a matrix row per case run");
    assert!(dom.contains("<td class=\"fail regressed\""), "the broken case shows as failed, marked as regressed");
    assert_eq!(dom.matches("▼ regressed").count(), 1, "only the broken case is marked");
    assert!(dom.contains("check · 20") && dom.contains("commit "), "each run's kind, date and commit: {dom}");

    let (dom, console) = open_in_chromium(browser, &site.join("compare.html"), &profile, None);
    assert!(console.is_empty(), "console messages on the comparison: {console:#?}");
    let regressions = dom.split("class=\"regressions\"").nth(1).expect("a regressions table");
    assert!(regressions.contains("kit.hash.values") && regressions.contains("&lt;b&gt;3 values differ"), "{dom}");

    for page in
        std::fs::read_dir(site.join("case")).unwrap().map(|e| e.unwrap().path()).chain([site.join("reports.html")])
    {
        let (dom, console) = open_in_chromium(browser, &page, &profile, None);
        assert!(console.is_empty(), "console messages on {}: {console:#?}", page.display());
        assert!(!dom.contains("class=\"broken\""), "an image did not load on {}", page.display());
    }

    let screenshot = dir.join("index.png");
    open_in_chromium(browser, &site.join("index.html"), &profile, Some(&screenshot));
    assert!(std::fs::read(&screenshot).unwrap().starts_with(b"\x89PNG"), "a screenshot in {}", screenshot.display());
    // Written again with fewer case runs: no page of the earlier set is left behind.
    let mut fewer = report.clone();
    fewer["cases"].as_array_mut().unwrap().truncate(2);
    std::fs::write(&new, fewer.to_string()).unwrap();
    fragkit(&["html", new.to_str().unwrap(), "--out", site.to_str().unwrap()]);
    assert_eq!(std::fs::read_dir(site.join("case")).unwrap().count(), 2, "stale case pages were left");
}
