//! The runner as a GPU fleet uses it (issue 38): parallel children, skip lists, an early stop,
//! the adapter the run promised, resuming a killed run, validation by choice, every adapter
//! found, and the sharded recipe of docs/command-line.md run as written.

mod command_line;

use std::path::{Path, PathBuf};
use std::process::Command;

use command_line::{fragkit, fresh_postgres_database};
use serde_json::Value;

/// A folder of the test's own, empty.
fn scratch(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("fragkit-fleet-{name}-{}", std::process::id()));
    std::fs::remove_dir_all(&dir).ok();
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

fn read_report(path: &Path) -> Value {
    serde_json::from_str(&std::fs::read_to_string(path).unwrap_or_else(|e| panic!("{}: {e}", path.display()))).unwrap()
}

/// (name, outcome) of each case run of a report, in its order.
fn outcomes(report: &Value) -> Vec<(String, String)> {
    report["cases"]
        .as_array()
        .unwrap()
        .iter()
        .map(|c| (c["name"].as_str().unwrap().to_owned(), c["outcome"].as_str().unwrap().to_owned()))
        .collect()
}

/// Each case run's metrics less its timings (which differ from run to run by nature).
fn untimed_metrics(report: &Value) -> Vec<Value> {
    report["cases"]
        .as_array()
        .unwrap()
        .iter()
        .map(|c| {
            let mut metrics = c["metrics"].as_object().cloned().unwrap_or_default();
            metrics.retain(|name, _| !fragkit_report::report::is_timing_metric(name));
            Value::Object(metrics)
        })
        .collect()
}

/// `--jobs 2` runs two children at once (the timed cases alone) and ends with the verdicts,
/// the order and the non-timing metrics of `--jobs 1`, crashes included.
#[test]
fn two_jobs_give_the_verdicts_and_metrics_of_one() {
    let dir = scratch("jobs");
    let mut reports = Vec::new();
    for jobs in ["1", "2"] {
        let json = dir.join(format!("jobs{jobs}.json"));
        let (code, text) = fragkit(&[
            "check",
            "kit.*",
            "fault.abort",
            "fault.segfault",
            "--jobs",
            jobs,
            "--json",
            json.to_str().unwrap(),
        ]);
        assert_eq!(code, 1, "the two crashes fail the run: {text}");
        reports.push(read_report(&json));
    }
    assert_eq!(outcomes(&reports[0]), outcomes(&reports[1]));
    assert_eq!(untimed_metrics(&reports[0]), untimed_metrics(&reports[1]));
    let crashed = outcomes(&reports[1]).iter().filter(|(_, outcome)| outcome == "crash").count();
    assert_eq!(crashed, 2, "{:?}", outcomes(&reports[1]));
    let (code, text) = fragkit(&["check", "kit.hash.values", "--jobs", "0"]);
    assert!(code == 2 && text.contains("--jobs"), "{text}");
    std::fs::remove_dir_all(&dir).ok();
}

/// A skip list's case (scoped to this backend) and an excluded one are recorded `skip` with
/// their reasons in the JSON report, JUnit and HTML, never left out; bad skip lists are refused.
#[test]
fn a_skipped_case_is_recorded_with_its_reason_everywhere() {
    let dir = scratch("skips");
    let skips = dir.join("fleet.skips");
    std::fs::write(&skips, "# Hangs the fleet's GPUs (bug 123)\nkit.msaa.sample_mask backend=vulkan\nkit.hash.* backend=metal # not here\n")
        .unwrap();
    let (json, junit, html) = (dir.join("run.json"), dir.join("run.xml"), dir.join("site"));
    let (code, text) = fragkit(&[
        "--backend",
        "vulkan",
        "check",
        "kit.msaa.sample_mask",
        "kit.hash.values",
        "kit.determinism",
        "--skips",
        skips.to_str().unwrap(),
        "--exclude",
        "kit.determin*",
        "--json",
        json.to_str().unwrap(),
        "--junit",
        junit.to_str().unwrap(),
        "--html",
        html.to_str().unwrap(),
    ]);
    assert_eq!(code, 0, "{text}");
    assert!(text.contains("skipped: 2 case runs"), "the summary counts them: {text}");
    let report = read_report(&json);
    let expected = [("kit.msaa.sample_mask", "skip"), ("kit.hash.values", "pass"), ("kit.determinism", "skip")];
    assert_eq!(outcomes(&report), expected.map(|(n, o)| (n.to_owned(), o.to_owned())));
    let reason = |i: usize| report["cases"][i]["reason"].as_str().unwrap().to_owned();
    assert_eq!(reason(0), format!("skipped: Hangs the fleet's GPUs (bug 123) ({}:2)", skips.display()));
    assert_eq!(reason(2), "skipped: --exclude kit.determin*");
    let xml = std::fs::read_to_string(&junit).unwrap();
    assert!(xml.contains("<skipped message=\"skip: skipped: Hangs the fleet&apos;s GPUs (bug 123)"), "{xml}");
    let case_page = std::fs::read_dir(&html)
        .unwrap()
        .flatten()
        .flat_map(|e| std::fs::read_dir(e.path()).into_iter().flatten().flatten().chain([e]))
        .map(|e| std::fs::read_to_string(e.path()).unwrap_or_default())
        .find(|page| page.contains("<td class=\"skip\">skip</td>") && page.contains("bug 123"));
    assert!(case_page.is_some(), "no HTML page shows the skip with its reason");

    std::fs::write(&skips, "kit.msaa.* vendor=amd\n").unwrap();
    let (code, text) = fragkit(&["check", "kit.hash.values", "--skips", skips.to_str().unwrap()]);
    assert!(code == 2 && text.contains("fleet.skips:1: unknown field \"vendor\""), "{text}");
    let (code, text) = fragkit(&["check", "kit.hash.values", "--skips", dir.join("absent").to_str().unwrap()]);
    assert!(code == 2 && text.contains("reading the skip list"), "{text}");
    std::fs::remove_dir_all(&dir).ok();
}

/// Lavapipe made non-conformant on purpose (LP_PERF=no_depth: depth testing off): the run stops
/// after 2 unexpected failures, the rest recorded `not_run`, counted, exit 1.
#[test]
fn max_fails_stops_a_broken_driver_after_two_and_records_the_rest_as_not_run() {
    let dir = scratch("max-fails");
    let json = dir.join("run.json");
    let output = Command::new(env!("CARGO_BIN_EXE_fragkit"))
        .args(["--backend", "vulkan", "check", "--max-fails", "2", "--json", json.to_str().unwrap()])
        .env("LP_PERF", "no_depth")
        .output()
        .unwrap();
    let text = String::from_utf8_lossy(&output.stdout).into_owned() + &String::from_utf8_lossy(&output.stderr);
    assert_eq!(output.status.code(), Some(1), "{text}");
    let report = read_report(&json);
    let outcomes = outcomes(&report);
    let count = |outcome: &str| outcomes.iter().filter(|(_, o)| o == outcome).count();
    assert_eq!(count("fail"), 2, "{outcomes:?}");
    assert!(count("not_run") > 0, "{outcomes:?}");
    let (_, listed) = fragkit(&["list"]);
    let default_cases = listed.lines().filter(|l| !l.starts_with(' ') && !l.contains("[opt-in")).count();
    assert_eq!(outcomes.len(), default_cases, "every case is recorded, run or not: {outcomes:?}");
    let first_unrun = report["cases"].as_array().unwrap().iter().find(|c| c["outcome"] == "not_run").unwrap();
    assert!(first_unrun["reason"].as_str().unwrap().contains("stopped after 2 unexpected failures (--max-fails 2)"));
    assert!(text.contains(&format!("not run: {} case runs", count("not_run"))), "{text}");
    let (code, text) = fragkit(&["check", "kit.hash.values", "--max-fails", "0"]);
    assert!(code == 2 && text.contains("--max-fails"), "{text}");
    std::fs::remove_dir_all(&dir).ok();
}

/// On an adapter other than the one promised, exit 2 with what was found, before any case ran;
/// without a Vulkan driver the backend wgpu falls back to is said on stderr.
#[test]
fn the_wrong_adapter_exits_2_before_any_case() {
    let dir = scratch("expect-adapter");
    let (json, db) = (dir.join("run.json"), dir.join("runs.sqlite"));
    let (code, text) = fragkit(&[
        "check",
        "kit.hash.values",
        "--expect-adapter",
        "*radeon*,*geforce*",
        "--json",
        json.to_str().unwrap(),
        "--db",
        db.to_str().unwrap(),
    ]);
    assert_eq!(code, 2, "{text}");
    assert!(text.contains("the adapter is not the one expected (--expect-adapter *radeon*,*geforce*): found llvmpipe"));
    assert!(text.contains("no case ran") && !text.contains("kit.hash.values  "), "{text}");
    assert!(!json.exists() && !dir.join("run.json.partial").exists(), "a report was written");
    let (code, runs) = fragkit(&["compare", "--db", db.to_str().unwrap(), "latest", "latest"]);
    assert!(code == 2 && runs.contains("holds no run"), "a run was recorded: {runs}");
    // The right adapter, by driver or backend: the run goes on.
    let (code, text) = fragkit(&["--backend", "vulkan", "check", "kit.hash.values", "--expect-adapter", "llvmpipe"]);
    assert_eq!(code, 0, "{text}");
    // No Vulkan driver: wgpu falls back to GL, and the run says so.
    let output = Command::new(env!("CARGO_BIN_EXE_fragkit"))
        .args(["check", "kit.hash.values", "--expect-adapter", "vulkan"])
        .env("VK_ICD_FILENAMES", "/nonexistent")
        .env_remove("WGPU_BACKEND")
        .output()
        .unwrap();
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert_eq!(output.status.code(), Some(2), "{stderr}");
    assert!(stderr.contains("no backend was named (--backend, WGPU_BACKEND) and wgpu chose"), "{stderr}");
    assert!(stderr.contains("on gl, not Vulkan") && stderr.contains("backend gl); no case ran"), "{stderr}");
    std::fs::remove_dir_all(&dir).ok();
}

/// Starts `check ARGS`, waits until its child hangs in fault.hang with kit.hash.values recorded,
/// and kills both, as a CI job's timeout would.
fn kill_while_hanging(args: &[&str]) {
    let mut parent = Command::new(env!("CARGO_BIN_EXE_fragkit"))
        .args(args)
        .stdout(std::process::Stdio::null())
        .stderr(std::process::Stdio::null())
        .spawn()
        .unwrap();
    let stream = std::env::temp_dir().join(format!("fragkit-child-{}-0.stream", parent.id()));
    let started = std::time::Instant::now();
    while !std::fs::read_to_string(&stream).is_ok_and(|text| text.contains("\"kit.hash.values\"")) {
        assert!(started.elapsed().as_secs() < 120, "the first case never finished");
        std::thread::sleep(std::time::Duration::from_millis(50));
    }
    // Time for the parent to record it, and the child to start hanging.
    std::thread::sleep(std::time::Duration::from_millis(1500));
    let children = Command::new("pgrep").args(["-P", &parent.id().to_string()]).output().unwrap();
    parent.kill().unwrap();
    parent.wait().unwrap();
    for child in String::from_utf8_lossy(&children.stdout).split_whitespace() {
        Command::new("kill").args(["-9", child]).status().unwrap();
    }
}

/// A run killed in its second case and resumed — from the database, or from the JSON report so
/// far — ends complete with every case recorded once; nothing to resume is an error.
#[test]
fn a_killed_run_resumed_ends_complete_with_every_case_once() {
    let dir = scratch("resume");
    let (db, json) = (dir.join("runs.sqlite"), dir.join("run.json"));
    let (db, json) = (db.to_str().unwrap(), json.to_str().unwrap());
    let cases = ["kit.hash.values", "fault.hang", "kit.determinism"];
    for source in [["--db", db], ["--json", json]] {
        let mut args = vec!["check"];
        args.extend(cases);
        args.extend(source);
        kill_while_hanging(&args);
        // The JSON report so far holds the first case run as the killed run recorded it.
        let partial = Path::new(json).with_extension("json.partial");
        let recorded = (source[0] == "--json").then(|| read_report(&partial)["cases"][0].clone());
        args.extend(["--timeout", "2", "--resume"]);
        if source[0] == "--db" {
            args.extend(["--json", json]);
        }
        let (code, text) = fragkit(&args);
        assert_eq!(code, 1, "fault.hang times out: {text}");
        assert!(text.contains("1 case run recorded, the rest run"), "{text}");
        let expected = [("kit.hash.values", "pass"), ("fault.hang", "timeout"), ("kit.determinism", "pass")];
        assert_eq!(outcomes(&read_report(Path::new(json))), expected.map(|(n, o)| (n.to_owned(), o.to_owned())));
        assert!(!partial.exists());
        if let Some(recorded) = recorded {
            let kept = &read_report(Path::new(json))["cases"][0];
            assert_eq!(kept["wall_ms"], recorded["wall_ms"], "the recorded case run ran again: {kept} {recorded}");
        }
    }
    // The database's run is complete, once: compared with the JSON report it holds the same.
    let (code, text) = fragkit(&["compare", "--db", db, json, "latest"]);
    assert_eq!(code, 0, "{text}");
    assert!(text.contains("0 case runs only in the base, 0 only in the new run"), "{text}");
    let (code, text) = fragkit(&["check", "kit.hash.values", "--db", db, "--resume"]);
    assert!(code == 2 && text.contains("holds no interrupted check run to resume"), "{text}");
    let (code, text) = fragkit(&["check", "kit.hash.values", "--json", json, "--resume"]);
    assert!(code == 2 && text.contains("no report so far at"), "{text}");
    let (code, text) = fragkit(&["check", "kit.hash.values", "--resume"]);
    assert!(code == 2 && text.contains("give its --db or --json"), "{text}");
    std::fs::remove_dir_all(&dir).ok();
}

/// Under --validation lavapipe passes: the one message the 1.3.239 layer raises is listed in the
/// expectations with whose fault it is. Without that entry the affected cases fail, naming it.
#[test]
fn validation_fails_a_case_on_an_unlisted_message_and_passes_a_listed_one() {
    if fragkit::gpu::validation_layer_manifest().is_none() {
        assert!(
            std::env::var_os("CI").is_none(),
            "CI must test --validation: .ci/setup installs vulkan-validationlayers"
        );
        eprintln!("SKIPPED: the Vulkan validation layer is not installed (apt-get install vulkan-validationlayers)");
        return;
    }
    let dir = scratch("validation");
    let json = dir.join("run.json");
    let run = |expectations: Option<&Path>| {
        let mut args = vec!["--backend", "vulkan", "--validation", "check", "kit.hash.values", "kit.msaa.sample_mask"];
        args.extend(["--json", json.to_str().unwrap()]);
        if let Some(path) = expectations {
            args.extend(["--expectations", path.to_str().unwrap()]);
        }
        let (code, text) = fragkit(&args);
        (code, text, read_report(&json))
    };
    let (code, text, _) = run(None);
    assert_eq!(code, 0, "{text}");
    // The built-in expectations without their validation message.
    let built_in = fragkit_cases::EXPECTATIONS;
    let without = &built_in[..built_in.find("[[known_validation_message]]").unwrap()];
    let expectations = dir.join("expectations.toml");
    std::fs::write(&expectations, without).unwrap();
    let (code, text, report) = run(Some(&expectations));
    assert_eq!(code, 1, "{text}");
    for case in report["cases"].as_array().unwrap() {
        assert_eq!(case["outcome"], "fail", "{case}");
        let reason = case["reason"].as_str().unwrap();
        assert!(
            reason.starts_with("the validation layer reported: UNASSIGNED-CoreValidation-Shader-InconsistentSpirv: SPIR-V module not valid: Invalid source language operand: 10 (x"),
            "{reason}"
        );
    }
    // Without --validation the layer never loads.
    let (code, text) = fragkit(&[
        "--backend",
        "vulkan",
        "check",
        "kit.hash.values",
        "-v",
        "--expectations",
        expectations.to_str().unwrap(),
    ]);
    assert!(code == 0 && !text.contains("CoreValidation"), "{text}");
    std::fs::remove_dir_all(&dir).ok();
}

/// `--matrix found` runs every adapter the instance enumerates, each in its own process, named
/// by backend and adapter.
#[test]
fn the_found_matrix_runs_every_adapter_here() {
    let dir = scratch("found");
    let (code, text) = fragkit(&["check", "--matrix", "found", "kit.hash.values", "--reports", dir.to_str().unwrap()]);
    assert_eq!(code, 0, "{text}");
    for name in ["vulkan_llvmpipe", "gl_llvmpipe"] {
        // The table's row comes after the line that said it started.
        let row = text.lines().rfind(|l| l.starts_with(name)).unwrap_or_else(|| panic!("no {name} row: {text}"));
        assert!(row.ends_with("exit 0"), "{row}");
    }
    std::fs::remove_dir_all(&dir).ok();
}

/// docs/command-line.md's sharded CI recipe, run as written: two shards record into one
/// PostgreSQL database under the pipeline's tag, and the merge job joins their reports.
#[test]
fn the_documented_shard_recipe_records_both_shards_and_merges_them() {
    let Some(db) = fresh_postgres_database("shard_recipe") else { return };
    let dir = scratch("shards");
    let recipe =
        std::fs::read_to_string(Path::new(env!("CARGO_MANIFEST_DIR")).join("../docs/command-line.md")).unwrap();
    // Every line of the recipes that holds `marker`, as the shell runs it (the YAML's "- " and
    // "run: " off).
    let commands = |marker: &str| -> Vec<String> {
        let lines: Vec<String> = recipe
            .lines()
            .filter(|l| l.contains(marker))
            .map(|l| l.trim().trim_start_matches("- ").trim_start_matches("run: ").to_owned())
            .collect();
        assert_eq!(lines.len(), 2, "one {marker:?} line in each recipe: {lines:?}");
        lines
    };
    let shards = commands("fragkit check --shard ${INDEX}/${TOTAL}");
    assert_eq!(shards[1], format!("{} --github", shards[0]), "the two recipes run the same shard command");
    let merges = commands("fragkit merge shard-*.json");
    assert_eq!(merges[0], merges[1]);
    let (shard, merge) = (&shards[0], &merges[0]);
    for index in ["1", "2"] {
        let script = format!(
            "INDEX={index} TOTAL=2 FRAGKIT_DB='{db}' PIPELINE=7 EXPECTED_ADAPTER=llvmpipe CASES='kit.hash.values kit.determinism kit.raster.*'\n{shard}"
        );
        let output = Command::new("sh")
            .arg("-c")
            .arg(script.replace("fragkit ", &format!("{} ", env!("CARGO_BIN_EXE_fragkit"))))
            .current_dir(&dir)
            .output()
            .unwrap();
        assert!(
            output.status.success(),
            "{}{}",
            String::from_utf8_lossy(&output.stdout),
            String::from_utf8_lossy(&output.stderr)
        );
    }
    let output = Command::new("sh")
        .arg("-c")
        .arg(merge.replace("fragkit ", &format!("{} ", env!("CARGO_BIN_EXE_fragkit"))))
        .current_dir(&dir)
        .output()
        .unwrap();
    let text = String::from_utf8_lossy(&output.stdout);
    assert!(output.status.success(), "{text}{}", String::from_utf8_lossy(&output.stderr));
    let merged = read_report(&dir.join("merged.json"));
    let mut names: Vec<String> = outcomes(&merged).into_iter().map(|(n, _)| n).collect();
    names.sort();
    let (_, listed) = fragkit(&["list", "kit.raster.*"]);
    let raster = listed.lines().filter(|l| l.starts_with("kit.raster.")).count();
    assert_eq!(names.len(), 2 + raster, "{names:?}");
    // Both shards are runs of the database, under the pipeline's tag.
    let site = dir.join("site");
    let (code, text) = fragkit(&["html", "--db", &db, "--run", "1", "--run", "2", "--out", site.to_str().unwrap()]);
    assert_eq!(code, 0, "{text}");
    let index = std::fs::read_to_string(site.join("index.html")).unwrap();
    assert!(index.matches("pipeline-7").count() >= 2, "both runs are headed by the pipeline's tag: {index}");
    std::fs::remove_dir_all(&dir).ok();
}
