//! The command line: bad input gets a clear message and a non-zero exit, never a panic.

mod command_line;

use std::process::Command;

use command_line::{copy_tree, fragkit, fresh_postgres_database};

#[test]
fn unknown_case_pattern_is_an_error() {
    let (code, text) = fragkit(&["check", "nope.*"]);
    assert_eq!(code, 2, "{text}");
    assert!(text.contains("\"nope.*\" matches no case"), "{text}");
}

#[test]
fn unknown_parameter_is_an_error() {
    let (code, text) = fragkit(&["check", "kit.determinism", "--set", "colour=red"]);
    assert_eq!(code, 2, "{text}");
    assert!(text.contains("no selected case has a parameter \"colour\""), "{text}");
}

#[test]
fn unparsable_parameter_is_an_error() {
    let (code, text) = fragkit(&["check", "kit.determinism", "--set", "size=0x4"]);
    assert_eq!(code, 2, "{text}");
    assert!(text.contains("size \"0x4\" is empty"), "{text}");
}

#[test]
fn unknown_backend_is_an_error() {
    let (code, text) = fragkit(&["--backend", "glide", "check", "kit.determinism"]);
    assert_eq!(code, 2, "{text}");
    assert!(text.contains("unknown backend \"glide\""), "{text}");
}

#[test]
fn unknown_adapter_is_an_error() {
    let (code, text) = fragkit(&["--adapter", "no-such-gpu", "check", "kit.determinism"]);
    assert_eq!(code, 2, "{text}");
    assert!(text.contains("no adapter name contains \"no-such-gpu\""), "{text}");
}

#[test]
fn an_adapter_other_than_the_promised_driver_is_an_error() {
    let (code, text) = fragkit(&["--driver-info", "OpenGL ES 9.9*", "check", "kit.determinism"]);
    assert_eq!(code, 2, "{text}");
    assert!(text.contains("no adapter's driver info matches \"OpenGL ES 9.9*\""), "{text}");
}

#[test]
fn corrupt_expectations_file_is_an_error() {
    let path = std::env::temp_dir().join("fragkit-corrupt-expectations.toml");
    std::fs::write(&path, "[[known_issue]]\ncase = \"kit.*\"\nreasn = \"typo\"\n").unwrap();
    let (code, text) = fragkit(&["check", "kit.determinism", "--expectations", path.to_str().unwrap()]);
    assert_eq!(code, 2, "{text}");
    assert!(text.contains("parsing expectations file"), "{text}");
}

#[test]
fn check_writes_a_json_report_and_list_names_every_case() {
    let path = std::env::temp_dir().join("fragkit-cli-report.json");
    let (code, text) = fragkit(&["check", "kit.determinism", "--json", path.to_str().unwrap()]);
    assert_eq!(code, 0, "{text}");
    let report: serde_json::Value = serde_json::from_str(&std::fs::read_to_string(&path).unwrap()).unwrap();
    assert!(report["adapter"]["name"].is_string());
    for key in ["name", "outcome", "reason", "params", "metrics", "gpu_ms", "wall_ms"] {
        assert!(report["cases"][0].get(key).is_some(), "report case lacks {key}: {report}");
    }
    let (code, listing) = fragkit(&["list"]);
    assert_eq!(code, 0);
    for case in fragkit_cases::all() {
        assert!(listing.contains(case.name), "list lacks {}", case.name);
    }
}

#[test]
fn a_listed_case_that_passes_fails_the_run_as_an_unexpected_pass() {
    let path = std::env::temp_dir().join("fragkit-stale-expectations.toml");
    std::fs::write(&path, "[[known_issue]]\ncase = \"kit.determinism\"\nreason = \"stale entry\"\n").unwrap();
    let (code, text) = fragkit(&["check", "kit.determinism", "--expectations", path.to_str().unwrap()]);
    assert_eq!(code, 1, "{text}");
    assert!(text.contains("UNEXPECTED_PASS"), "{text}");
}

#[test]
fn bad_values_are_refused_naming_the_value_the_range_and_the_source() {
    let out = std::env::temp_dir().join("fragkit-bad-input");
    let out = out.to_str().unwrap();
    let cases: &[(&[&str], &str)] = &[
        (&["check", "cbr.reconstruct.static", "--set", "lights=0"], "0 is outside the allowed range 1..=4096"),
        (&["check", "cbr.reconstruct.static", "--set", "sizes=100000x4"], "exceeds this adapter's texture limit"),
        (&["check", "cbr.reconstruct.static", "--set", "sizes=1x1"], "both sides must be at least 2"),
        (&["check", "cps.composite.matches_reference", "--set", "max_level=9"], "9 is outside the allowed range 0..=8"),
        (&["check", "kit.determinism", "--set", "size=-3x4"], "\"-3\" in size \"-3x4\" is not an integer"),
        (&["render", "cps", "--out", out, "--lights", "0"], "0 is not in 1..=65536"),
        (&["render", "cps", "--out", out, "--max-level", "9"], "9 is not in 0..=8"),
        (&["render", "cps", "--out", out, "--size", "100000x10"], "--size: render size 100000x10 exceeds"),
        (&["render", "cbr", "--out", out, "--size", "1x1"], "smaller than 2x2"),
        (&["render", "cbr", "--out", out, "--motion", "pan_NaNx0"], "\"NaN\" is not a finite number"),
        (&["render", "cbr", "--out", out, "--detection", "cso:-1"], "must be a finite number >= 0"),
        (&["render", "oit", "--out", out, "--samples", "3"], "--samples 3: this adapter offers sample counts"),
        (&["render", "oit", "--out", out, "--frames", "0"], "0 is not in 1..=100000"),
        (&["report", "cbr", "--out", out, "--frames", "1"], "at least 2 frames"),
        (&["render", "cps", "--out", "/proc/fragkit-forbidden"], "creating /proc/fragkit-forbidden"),
        (&["check", "kit.determinism", "--json", "/proc/fragkit-forbidden/r.json"], "is not writable"),
    ];
    for (args, needle) in cases {
        let (code, text) = fragkit(args);
        assert_eq!(code, 2, "fragkit {args:?}: {text}");
        assert!(text.contains(needle), "fragkit {args:?} should say {needle:?}:\n{text}");
    }
}

#[test]
fn faults_fail_their_own_case_and_the_run_goes_on_on_a_new_device() {
    let path = std::env::temp_dir().join("fragkit-fault-report.json");
    let (code, text) = fragkit(&[
        "check",
        "fault.validation_error",
        "fault.device_loss",
        "kit.determinism",
        "--json",
        path.to_str().unwrap(),
    ]);
    assert_eq!(code, 1, "{text}");
    let report: serde_json::Value = serde_json::from_str(&std::fs::read_to_string(&path).unwrap()).unwrap();
    let cases = report["cases"].as_array().unwrap();
    let outcome = |i: usize| (cases[i]["name"].as_str().unwrap(), cases[i]["outcome"].as_str().unwrap());
    assert_eq!(cases.len(), 3, "{report}");
    assert_eq!(outcome(0), ("fault.validation_error", "fail"));
    assert!(cases[0]["reason"].as_str().unwrap().contains("Dimension X is zero"), "{report}");
    assert_eq!(outcome(1), ("fault.device_loss", "fail"));
    assert!(cases[1]["reason"].as_str().unwrap().contains("device lost during the case (Destroyed"), "{report}");
    // The loss surfaced as an error inside the case, not a hang or stale pixels.
    assert!(cases[1]["metrics"]["error_after_the_loss"].is_string(), "{report}");
    assert_eq!(outcome(2), ("kit.determinism", "pass"), "the case after the loss runs on a new device");
}

#[test]
fn a_crashing_or_hanging_case_costs_that_case_and_the_run_goes_on_in_a_new_process() {
    let path = std::env::temp_dir().join(format!("fragkit-crash-report-{}.json", std::process::id()));
    let junit = path.with_extension("xml");
    let (code, text) = fragkit(&[
        "check",
        "fault.abort",
        "kit.hash.values",
        "fault.segfault",
        "fault.hang",
        "fault.out_of_memory",
        "kit.determinism",
        "--timeout",
        "3",
        "--json",
        path.to_str().unwrap(),
        "--junit",
        junit.to_str().unwrap(),
    ]);
    assert_eq!(code, 1, "{text}");
    let report: serde_json::Value = serde_json::from_str(&std::fs::read_to_string(&path).unwrap()).unwrap();
    let cases = report["cases"].as_array().unwrap();
    let outcomes: Vec<(&str, &str)> =
        cases.iter().map(|c| (c["name"].as_str().unwrap(), c["outcome"].as_str().unwrap())).collect();
    assert_eq!(
        outcomes,
        [
            ("fault.abort", "crash"),
            ("kit.hash.values", "pass"),
            ("fault.segfault", "crash"),
            ("fault.hang", "timeout"),
            ("fault.out_of_memory", "crash"),
            ("kit.determinism", "pass")
        ],
        "{report}"
    );
    let reason = |i: usize| cases[i]["reason"].as_str().unwrap();
    assert!(reason(0).contains("signal 6 (SIGABRT)") && reason(0).contains("aborting on purpose"), "{}", reason(0));
    assert!(reason(2).contains("signal 11 (SIGSEGV)") && reason(2).contains("--backend"), "{}", reason(2));
    assert!(reason(3).contains("no record for 3 s"), "{}", reason(3));
    assert!(reason(4).contains("memory allocation of 4398046511104 bytes failed"), "{}", reason(4));
    let xml = std::fs::read_to_string(&junit).unwrap();
    assert_eq!(xml.matches("type=\"CRASH\"").count(), 3, "{xml}");
    assert!(text.contains("6 cases: 4 unexpected failures"), "{text}");
    std::fs::remove_file(&path).ok();
    std::fs::remove_file(&junit).ok();
}

/// The pids of the processes whose parent is `parent` and whose command line holds `marker`.
fn children_of(parent: u32, marker: &str) -> Vec<u32> {
    let mut found = Vec::new();
    for entry in std::fs::read_dir("/proc").unwrap().flatten() {
        let Ok(pid) = entry.file_name().to_string_lossy().parse::<u32>() else { continue };
        let stat = std::fs::read_to_string(entry.path().join("stat")).unwrap_or_default();
        // The parent's pid is the second field after the command's closing parenthesis.
        let ppid = stat.rsplit_once(')').and_then(|(_, rest)| rest.split_whitespace().nth(1)?.parse::<u32>().ok());
        let cmdline = std::fs::read(entry.path().join("cmdline")).unwrap_or_default();
        if ppid == Some(parent) && String::from_utf8_lossy(&cmdline).contains(marker) {
            found.push(pid);
        }
    }
    found
}

#[test]
fn a_case_child_killed_from_outside_is_a_crash_and_the_run_completes_in_every_output() {
    let dir = std::env::temp_dir().join(format!("fragkit-killed-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let (json, junit, db) = (dir.join("run.json"), dir.join("run.xml"), dir.join("runs.sqlite"));
    let parent = Command::new(env!("CARGO_BIN_EXE_fragkit"))
        .args(["check", "fault.hang", "kit.hash.values", "--json", json.to_str().unwrap()])
        .args(["--junit", junit.to_str().unwrap(), "--db", db.to_str().unwrap()])
        .stdout(std::process::Stdio::piped())
        .stderr(std::process::Stdio::piped())
        .spawn()
        .unwrap();
    // The child running fault.hang, once it is there: killed as an OOM killer or a user would.
    let started = std::time::Instant::now();
    let child = loop {
        if let Some(&pid) = children_of(parent.id(), "--child-stream").first() {
            break pid;
        }
        assert!(started.elapsed().as_secs() < 60, "no case child appeared");
        std::thread::sleep(std::time::Duration::from_millis(50));
    };
    std::thread::sleep(std::time::Duration::from_millis(1500));
    assert!(Command::new("kill").args(["-9", &child.to_string()]).status().unwrap().success());
    let output = parent.wait_with_output().unwrap();
    let text = String::from_utf8_lossy(&output.stdout).into_owned() + &String::from_utf8_lossy(&output.stderr);
    assert_eq!(output.status.code(), Some(1), "{text}");
    let report: serde_json::Value = serde_json::from_str(&std::fs::read_to_string(&json).unwrap()).unwrap();
    let outcomes: Vec<(&str, &str)> = report["cases"]
        .as_array()
        .unwrap()
        .iter()
        .map(|c| (c["name"].as_str().unwrap(), c["outcome"].as_str().unwrap()))
        .collect();
    assert_eq!(outcomes, [("fault.hang", "crash"), ("kit.hash.values", "pass")], "{report}");
    assert!(report["cases"][0]["reason"].as_str().unwrap().contains("signal 9 (SIGKILL)"), "{report}");
    assert_eq!(std::fs::read_to_string(&junit).unwrap().matches("type=\"CRASH\"").count(), 1);
    let (code, text) = fragkit(&["compare", "--db", db.to_str().unwrap(), json.to_str().unwrap(), "latest"]);
    assert_eq!(code, 0, "the recorded run holds both cases: {text}");
    assert!(text.contains("0 case runs only in the base, 0 only in the new run"), "{text}");
    std::fs::remove_dir_all(&dir).ok();
}

#[test]
fn the_matrix_runs_each_configuration_in_its_own_process_and_reports_the_absent_ones() {
    let dir = std::env::temp_dir().join(format!("fragkit-matrix-test-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let matrix = dir.join("adapters.toml");
    // The default Vulkan adapter twice over, the second with an environment its process must
    // see (a lavapipe setting that changes the adapter's name), and one configuration absent here.
    std::fs::write(
        &matrix,
        r#"
[[configuration]]
name = "default"
about = "the default Vulkan adapter"
backend = "vulkan"
adapter = ""
installs = "apt-get install mesa-vulkan-drivers"

[[configuration]]
name = "narrow"
about = "lavapipe with 4-lane vectors"
backend = "vulkan"
adapter = ""
env = { LP_NATIVE_VECTOR_WIDTH = "128" }
installs = "apt-get install mesa-vulkan-drivers"

[[configuration]]
name = "nowhere"
about = "needs a file no machine has"
backend = "gl"
adapter = "nowhere"
requires = ["/nonexistent/fragkit-test-icd.json"]
installs = "nothing installs it"
"#,
    )
    .unwrap();
    let reports = dir.join("reports");
    let (code, text) = fragkit(&[
        "check",
        "kit.hash.values",
        "--matrix",
        "all",
        "--adapters-file",
        matrix.to_str().unwrap(),
        "--reports",
        reports.to_str().unwrap(),
    ]);
    assert_eq!(code, 0, "{text}");
    assert!(text.contains("nowhere") && text.contains("absent: missing /nonexistent/fragkit-test-icd.json"), "{text}");
    let report = |name: &str| -> serde_json::Value {
        serde_json::from_str(&std::fs::read_to_string(reports.join(format!("{name}.json"))).unwrap()).unwrap()
    };
    let (default, narrow) = (report("default"), report("narrow"));
    assert_eq!(default["cases"][0]["outcome"], "pass", "{default}");
    assert!(reports.join("narrow.junit.xml").exists() && reports.join("narrow.log").exists());
    if default["adapter"]["name"].as_str().unwrap().starts_with("llvmpipe") {
        assert!(narrow["adapter"]["name"].as_str().unwrap().contains("128 bits"), "{narrow}");
    }
    assert!(!reports.join("nowhere.json").exists());

    let (code, text) = fragkit(&["check", "--matrix", "default,typo", "--adapters-file", matrix.to_str().unwrap()]);
    assert_eq!(code, 2, "{text}");
    assert!(text.contains("no configuration \"typo\"") && text.contains("known: default, narrow, nowhere"), "{text}");
    let (code, text) = fragkit(&["--backend", "gl", "check", "--matrix", "all"]);
    assert_eq!(code, 2, "{text}");
    assert!(text.contains("drop --backend"), "{text}");
    std::fs::remove_dir_all(&dir).ok();
}

#[test]
fn shards_run_every_case_once_and_merge_into_one_report_with_junit() {
    let dir = std::env::temp_dir().join(format!("fragkit-shards-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let cases = ["kit.hash.values", "kit.msaa.sample_mask", "cbr.layout.mapping"];
    let mut reports = Vec::new();
    for k in 1..=2 {
        let json = dir.join(format!("shard{k}.json"));
        let mut args = vec!["check".to_owned(), "--shard".into(), format!("{k}/2"), "--json".into()];
        args.push(json.to_str().unwrap().into());
        args.extend(cases.iter().map(|c| c.to_string()));
        let (code, text) = fragkit(&args.iter().map(String::as_str).collect::<Vec<_>>());
        assert_eq!(code, 0, "{text}");
        reports.push(json);
    }
    let (merged, junit) = (dir.join("merged.json"), dir.join("merged.xml"));
    let (code, text) = fragkit(&[
        "merge",
        reports[0].to_str().unwrap(),
        reports[1].to_str().unwrap(),
        "--json",
        merged.to_str().unwrap(),
        "--junit",
        junit.to_str().unwrap(),
    ]);
    assert_eq!(code, 0, "{text}");
    let report: serde_json::Value = serde_json::from_str(&std::fs::read_to_string(&merged).unwrap()).unwrap();
    let mut names: Vec<&str> =
        report["cases"].as_array().unwrap().iter().map(|c| c["name"].as_str().unwrap()).collect();
    names.sort_unstable();
    assert_eq!(names, ["cbr.layout.mapping", "kit.hash.values", "kit.msaa.sample_mask"]);
    let xml = std::fs::read_to_string(&junit).unwrap();
    assert!(xml.contains("<testsuites name=\"fragkit\" tests=\"3\" failures=\"0\""), "{xml}");
    assert_eq!(xml.matches("<testcase ").count(), 3, "{xml}");

    // The same shard twice, or part of the set, is refused (the run would pass for the whole); a
    // truncated report is refused; so are impossible shards.
    let (code, text) = fragkit(&["merge", reports[0].to_str().unwrap(), reports[0].to_str().unwrap()]);
    assert_eq!(code, 2, "{text}");
    assert!(text.contains("are both shard 1/2"), "{text}");
    let (code, text) = fragkit(&["merge", reports[1].to_str().unwrap()]);
    assert_eq!(code, 2, "{text}");
    assert!(text.contains("shard 1/2 missing: 1 of 2 shards given"), "{text}");
    let truncated = dir.join("truncated.json");
    let whole = std::fs::read_to_string(&reports[1]).unwrap();
    std::fs::write(&truncated, &whole[..whole.len() / 2]).unwrap();
    let (code, text) = fragkit(&["merge", reports[0].to_str().unwrap(), truncated.to_str().unwrap()]);
    assert_eq!(code, 2, "{text}");
    assert!(text.contains("is not a fragkit report"), "{text}");
    for bad in ["3/2", "0/4", "2"] {
        let (code, text) = fragkit(&["check", "--shard", bad, "kit.hash.values"]);
        assert_eq!(code, 2, "--shard {bad}: {text}");
    }
    std::fs::remove_dir_all(&dir).ok();
}

#[test]
fn compare_reports_a_case_broken_in_the_new_run_and_exits_non_zero() {
    let dir = std::env::temp_dir().join(format!("fragkit-compare-{}", std::process::id()));
    let shaders = dir.join("shaders");
    copy_tree(&std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../shaders"), &shaders);
    let (base, same, broken) = (dir.join("base.json"), dir.join("same.json"), dir.join("broken.json"));
    let cases = ["kit.hash.values", "cbr.layout.mapping"];
    for path in [&base, &same] {
        let (code, text) = fragkit(&[&["check", "--json", path.to_str().unwrap()][..], &cases].concat());
        assert_eq!(code, 0, "{text}");
    }
    // The new run's WGSL hash differs from its definition.
    let hash = shaders.join("common/hash.wgsl");
    let text = std::fs::read_to_string(&hash).unwrap().replace("+ 2891336453u", "+ 2891336451u");
    std::fs::write(&hash, text).unwrap();
    let output = Command::new(env!("CARGO_BIN_EXE_fragkit"))
        .args([&["check", "--json", broken.to_str().unwrap()][..], &cases].concat())
        .env("FRAGKIT_SHADER_DIR", &shaders)
        .output()
        .unwrap();
    assert_eq!(output.status.code(), Some(1));

    let (code, text) = fragkit(&["compare", base.to_str().unwrap(), same.to_str().unwrap()]);
    assert_eq!(code, 0, "{text}");
    assert!(text.contains("0 regressions"), "{text}");
    let verdict = dir.join("verdict.json");
    let (code, text) =
        fragkit(&["compare", base.to_str().unwrap(), broken.to_str().unwrap(), "--json", verdict.to_str().unwrap()]);
    assert_eq!(code, 1, "{text}");
    assert!(text.contains("1 regression,") && text.contains("| `kit.hash.values` | pass | FAIL |"), "{text}");
    // The run says its shaders were not its commit's (D13), and CI can read the verdict.
    assert!(text.contains("read its shaders from") && text.contains("FRAGKIT_SHADER_DIR"), "{text}");
    let verdict: serde_json::Value = serde_json::from_str(&std::fs::read_to_string(&verdict).unwrap()).unwrap();
    assert_eq!(verdict["regressed"], true, "{verdict}");
    assert_eq!(verdict["comparison"]["regressions"][0]["case"], "kit.hash.values", "{verdict}");
    // The broken case's time is no verdict: its outcome is the news.
    assert!(text.contains("the case is FAIL in the new run"), "{text}");
    // A new run that ran nothing is no run to pass.
    let empty = dir.join("empty.json");
    let mut report: serde_json::Value = serde_json::from_str(&std::fs::read_to_string(&base).unwrap()).unwrap();
    report["cases"] = serde_json::json!([]);
    std::fs::write(&empty, report.to_string()).unwrap();
    let (code, text) = fragkit(&["compare", base.to_str().unwrap(), empty.to_str().unwrap()]);
    assert_eq!(code, 2, "{text}");
    assert!(text.contains("holds no case runs"), "{text}");
    std::fs::remove_dir_all(&dir).ok();
}

/// A run's commit is the build's, not what a `git` on the run's PATH says (D13); a run whose
/// process is killed midway keeps its finished case runs, shows as incomplete and is never taken
/// for `latest`; an imported report keeps its time and commit and is not imported twice (D18).
#[test]
fn a_killed_run_stays_incomplete_the_commit_is_the_builds_and_an_import_happens_once() {
    let dir = std::env::temp_dir().join(format!("fragkit-incomplete-{}", std::process::id()));
    std::fs::remove_dir_all(&dir).ok();
    let fake_bin = dir.join("bin");
    std::fs::create_dir_all(&fake_bin).unwrap();
    let fake_git = fake_bin.join("git");
    std::fs::write(&fake_git, "#!/bin/sh\necho deadbeef\n").unwrap();
    std::process::Command::new("chmod").args(["+x", fake_git.to_str().unwrap()]).status().unwrap();
    let path = format!("{}:{}", fake_bin.display(), std::env::var("PATH").unwrap());
    let (db, json) = (dir.join("runs.sqlite"), dir.join("run.json"));
    let (db_arg, json_arg) = (db.to_str().unwrap(), json.to_str().unwrap());
    let finished = Command::new(env!("CARGO_BIN_EXE_fragkit"))
        .args(["check", "kit.hash.values", "--db", db_arg, "--json", json_arg])
        .env("PATH", &path)
        .output()
        .unwrap();
    assert_eq!(finished.status.code(), Some(0), "{}", String::from_utf8_lossy(&finished.stderr));
    let report: serde_json::Value = serde_json::from_str(&std::fs::read_to_string(&json).unwrap()).unwrap();
    assert_eq!(report["run"]["git_commit"].as_str(), fragkit_report::run_info::BUILD_COMMIT, "{report}");
    assert_eq!(report["run"]["kind"], "check", "{report}");

    // A second run, killed (parent and case child) while it hangs in its second case.
    let mut killed = Command::new(env!("CARGO_BIN_EXE_fragkit"))
        .args(["check", "kit.hash.values", "fault.hang", "--db", db_arg])
        .stdout(std::process::Stdio::null())
        .stderr(std::process::Stdio::null())
        .spawn()
        .unwrap();
    let started = std::time::Instant::now();
    // The parent's stream from its child (supervise.rs's scratch file) holds the first record.
    let stream = std::env::temp_dir().join(format!("fragkit-child-{}-0.stream", killed.id()));
    let child = loop {
        let first_recorded = std::fs::read_to_string(&stream).is_ok_and(|text| text.contains("\"kit.hash.values\""));
        if let (true, Some(&pid)) = (first_recorded, children_of(killed.id(), "--child-stream").first()) {
            break pid;
        }
        assert!(started.elapsed().as_secs() < 120, "the first case never finished");
        std::thread::sleep(std::time::Duration::from_millis(50));
    };
    // Time for the parent to record it.
    std::thread::sleep(std::time::Duration::from_millis(1000));
    killed.kill().unwrap();
    killed.wait().unwrap();
    Command::new("kill").args(["-9", &child.to_string()]).status().unwrap();

    let site = dir.join("site");
    let (code, text) = fragkit(&["html", "--db", db_arg, "--out", site.to_str().unwrap()]);
    assert_eq!(code, 0, "{text}");
    let index = std::fs::read_to_string(site.join("index.html")).unwrap();
    assert!(index.contains("run 2") && index.contains("incomplete: the run ended before its last case"), "{index}");
    assert!(!index.contains("deadbeef"), "the commit came from the PATH's git: {index}");
    // `latest` is the finished run: comparing it with its own JSON finds nothing.
    let (code, text) = fragkit(&["compare", "--db", db_arg, json_arg, "latest"]);
    assert_eq!(code, 0, "{text}");
    assert!(text.contains("0 case runs only in the base, 0 only in the new run"), "{text}");
    // Run 2 holds its finished case run (a run without any is refused).
    let (code, text) = fragkit(&["compare", "--db", db_arg, "1", "2"]);
    assert_eq!(code, 0, "{text}");
    assert!(text.contains("0 case runs only in the base, 0 only in the new run"), "{text}");

    let (code, text) = fragkit(&["import", "--db", db_arg, json_arg]);
    assert_eq!(code, 0, "{text}");
    let (code, text) = fragkit(&["import", "--db", db_arg, json_arg]);
    assert_eq!(code, 2, "{text}");
    assert!(text.contains("was imported before, as run 3"), "{text}");
    let (code, text) = fragkit(&["html", "--db", db_arg, "--run", "3", "--out", site.to_str().unwrap()]);
    assert_eq!(code, 0, "{text}");
    let index = std::fs::read_to_string(site.join("index.html")).unwrap();
    let commit = fragkit_report::run_info::BUILD_COMMIT.map_or("commit unknown", |c| &c[..c.len().min(10)]);
    assert!(index.contains("import · 20") && index.contains(commit), "the import keeps its commit: {index}");
    std::fs::remove_dir_all(&dir).ok();
}

/// The CI outputs: a baseline written from a run with a broken case holds a later run with the
/// same break to 0 unexpected failures and makes a fixed one an unexpected pass; only the failed
/// case runs again with --rerun-failed; --github annotates the failure and writes a step summary.
#[test]
fn a_baseline_holds_the_next_run_rerun_failed_runs_the_failures_and_github_gets_annotations() {
    let dir = std::env::temp_dir().join(format!("fragkit-baseline-{}", std::process::id()));
    std::fs::remove_dir_all(&dir).ok();
    let shaders = dir.join("shaders");
    copy_tree(&std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../shaders"), &shaders);
    let hash = shaders.join("common/hash.wgsl");
    let text = std::fs::read_to_string(&hash).unwrap().replace("+ 2891336453u", "+ 2891336451u");
    std::fs::write(&hash, text).unwrap();
    let (report, baseline, summary) = (dir.join("run.json"), dir.join("baseline.toml"), dir.join("summary.md"));
    let broken = |args: &[&str]| {
        let output = Command::new(env!("CARGO_BIN_EXE_fragkit"))
            .args(args)
            .env("FRAGKIT_SHADER_DIR", &shaders)
            .env("GITHUB_STEP_SUMMARY", &summary)
            .output()
            .unwrap();
        let text = String::from_utf8_lossy(&output.stdout).into_owned() + &String::from_utf8_lossy(&output.stderr);
        (output.status.code().unwrap_or(-1), text)
    };
    let cases = ["kit.hash.values", "cbr.layout.mapping"];
    let (code, text) = broken(
        &[
            &["check", "--github", "--json", report.to_str().unwrap()][..],
            &["--write-baseline", baseline.to_str().unwrap()],
            &cases,
        ]
        .concat(),
    );
    assert_eq!(code, 1, "{text}");
    assert_eq!(text.matches("::error title=kit.hash.values FAIL on ").count(), 1, "{text}");
    let written = std::fs::read_to_string(&summary).unwrap();
    assert!(written.contains("2 case runs: 1 unexpected failure.") && written.contains("| `kit.hash.values` | FAIL |"));

    // The same break against the baseline: known; the fix against it: an unexpected pass.
    let (code, text) = broken(&[&["check", "--baseline", baseline.to_str().unwrap()][..], &cases].concat());
    assert_eq!(code, 0, "{text}");
    assert!(text.contains("known_issue") && text.contains("0 unexpected failures"), "{text}");
    let (code, text) = fragkit(&[&["check", "--baseline", baseline.to_str().unwrap()][..], &cases].concat());
    assert_eq!(code, 1, "{text}");
    assert!(text.contains("UNEXPECTED_PASS"), "{text}");

    // Only the failure runs again, with the parameters it ran with.
    let again = dir.join("again.json");
    let (code, text) =
        fragkit(&["check", "--rerun-failed", report.to_str().unwrap(), "--json", again.to_str().unwrap()]);
    assert_eq!(code, 0, "the fixed shaders pass: {text}");
    let rerun: serde_json::Value = serde_json::from_str(&std::fs::read_to_string(&again).unwrap()).unwrap();
    let names: Vec<&str> = rerun["cases"].as_array().unwrap().iter().map(|c| c["name"].as_str().unwrap()).collect();
    assert_eq!(names, ["kit.hash.values"], "{rerun}");
    let (code, text) = fragkit(&["check", "--rerun-failed", again.to_str().unwrap()]);
    assert_eq!(code, 0, "{text}");
    assert!(text.contains("nothing to run"), "{text}");
    std::fs::remove_dir_all(&dir).ok();
}

/// A private PostgreSQL server (`.ci/postgres` with its own folder and port) that this test may
/// stop and start; None where the suite has no PostgreSQL (as `fresh_postgres_database`).
fn private_postgres_server(dir: &std::path::Path, port: u16) -> Option<impl Fn(&str) -> String + '_> {
    std::env::var("FRAGKIT_TEST_POSTGRES").ok().or_else(|| {
        assert!(std::env::var_os("CI").is_none(), "CI must test the PostgreSQL backend");
        eprintln!("note: FRAGKIT_TEST_POSTGRES is unset (see .ci/postgres): PostgreSQL test skipped");
        None
    })?;
    let script = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../.ci/postgres");
    let dir = dir.to_owned();
    Some(move |action: &str| {
        let output = Command::new("bash")
            .arg(&script)
            .arg(action)
            .env("FRAGKIT_PG_DIR", &dir)
            .env("FRAGKIT_PG_PORT", port.to_string())
            .output()
            .unwrap();
        assert!(output.status.success(), ".ci/postgres {action}: {}", String::from_utf8_lossy(&output.stderr));
        String::from_utf8_lossy(&output.stdout).trim().to_owned()
    })
}

/// D7: the PostgreSQL server goes away once the run has started and comes back seconds later;
/// the run reconnects, and every case run is recorded and the run complete.
#[test]
fn a_run_outlives_a_postgres_restart_and_is_recorded_whole() {
    let dir = std::env::temp_dir().join(format!("fragkit-pg-restart-{}", std::process::id()));
    std::fs::remove_dir_all(&dir).ok();
    std::fs::create_dir_all(&dir).unwrap();
    let server_dir = dir.join("server");
    // A port of this run's own, so that a server an earlier failed run left behind is no obstacle.
    let port = 40_000 + (std::process::id() % 20_000) as u16;
    let Some(server) = private_postgres_server(&server_dir, port) else { return };
    let url = server("start");
    // Stopped however the test ends.
    struct StopOnDrop<F: Fn(&str) -> String>(F);
    impl<F: Fn(&str) -> String> Drop for StopOnDrop<F> {
        fn drop(&mut self) {
            (self.0)("stop");
        }
    }
    let server = StopOnDrop(server);
    let server = |action: &str| (server.0)(action);
    let json = dir.join("run.json");
    let run = Command::new(env!("CARGO_BIN_EXE_fragkit"))
        .args(["check", "kit.hash.values", "cbr.layout.mapping", "kit.determinism", "--db", &url])
        .args(["--json", json.to_str().unwrap()])
        .stdout(std::process::Stdio::piped())
        .stderr(std::process::Stdio::piped())
        .spawn()
        .unwrap();
    // Once the database is open and the cases run: the server stops, and starts 3 s later.
    let started = std::time::Instant::now();
    while children_of(run.id(), "--child-stream").is_empty() {
        assert!(started.elapsed().as_secs() < 60, "no case child appeared");
        std::thread::sleep(std::time::Duration::from_millis(20));
    }
    server("stop");
    std::thread::sleep(std::time::Duration::from_secs(3));
    server("start");
    let output = run.wait_with_output().unwrap();
    let text = String::from_utf8_lossy(&output.stdout).into_owned() + &String::from_utf8_lossy(&output.stderr);
    assert_eq!(output.status.code(), Some(0), "{text}");
    assert!(text.contains("recorded as run 1"), "{text}");
    let (code, text) = fragkit(&["compare", "--db", &url, json.to_str().unwrap(), "latest"]);
    server("stop");
    assert_eq!(code, 0, "the run is complete and holds every case run: {text}");
    assert!(text.contains("0 case runs only in the base, 0 only in the new run"), "{text}");
    std::fs::remove_dir_all(&dir).ok();
}

/// Two tagged check runs, a bench run, history, two processes importing at once, and the refusals
/// — the same on either backend.
fn runs_recorded_in_a_database_compare_and_concurrent_writers_both_land(db: &str, dir: &std::path::Path) {
    for tag in ["base", "new"] {
        let (code, text) =
            fragkit(&["check", "kit.hash.values", "cbr.layout.mapping", "--repeat", "3", "--db", db, "--tag", tag]);
        assert_eq!(code, 0, "{text}");
        assert!(text.contains("recorded as run"), "{text}");
    }
    let (code, text) = fragkit(&["compare", "--db", db, "latest~1", "latest", "--threshold", "0.5"]);
    assert_eq!(code, 0, "{text}");
    assert!(text.contains("0 regressions") && text.contains("3 vs 3 repeats, Mann–Whitney"), "{text}");

    let plot = dir.join("history.png");
    let (code, text) =
        fragkit(&["history", "kit.hash.values", "--db", db, "--metric", "wall_ms", "--out", plot.to_str().unwrap()]);
    assert_eq!(code, 0, "{text}");
    assert_eq!(text.lines().filter(|l| l.starts_with("| ") && !l.starts_with("| run")).count(), 2, "{text}");
    assert!(std::fs::read(&plot).unwrap().starts_with(b"\x89PNG"));

    // The bench from the binary: one case run per variant, every round's time kept.
    let (code, text) = fragkit(&["bench", "kit", "--rounds", "3", "--db", db, "--tag", "bench"]);
    assert_eq!(code, 0, "{text}");
    assert!(text.contains("stencil_equal_1.98pct") && text.contains("recorded as run"), "{text}");
    // Three rounds: the median's interval is their range, which holds it with 1 − 2/8.
    assert!(text.contains(", 75 % interval)"), "{text}");
    // GL's occlusion queries do not count texels: CPS gets no ideal rather than a wrong one.
    let (code, text) = fragkit(&["--backend", "gl", "bench", "cps", "--rounds", "1"]);
    assert_eq!(code, 0, "{text}");
    assert_eq!(text.matches("no ideal from texel counts: this adapter's occlusion queries").count(), 3, "{text}");
    assert_eq!(text.matches(" % of it; 2 render passes").count(), 3, "{text}");
    assert!(!text.contains("% of ideal"), "{text}");
    assert_eq!(text.matches("(one round: no interval)").count(), 3, "{text}");
    // D4: the bench run is typed; `latest` and the HTML matrix still mean the latest check.
    let (code, text) = fragkit(&["compare", "--db", db, "tag:new", "latest"]);
    assert_eq!(code, 0, "{text}");
    assert!(text.contains("0 case runs only in the base, 0 only in the new run"), "{text}");
    let site = dir.join("site");
    let (code, text) = fragkit(&["html", "--db", db, "--out", site.to_str().unwrap()]);
    assert_eq!(code, 0, "{text}");
    let index = std::fs::read_to_string(site.join("index.html")).unwrap();
    assert!(index.contains("cbr.layout.mapping") && index.contains("check · "), "{index}");

    // Two processes importing two reports at once: both runs land.
    let reports = [dir.join("report-1.json"), dir.join("report-2.json")];
    for report in &reports {
        let (code, text) = fragkit(&["check", "kit.hash.values", "--json", report.to_str().unwrap()]);
        assert_eq!(code, 0, "{text}");
    }
    let writers: Vec<_> = reports
        .iter()
        .map(|report| {
            Command::new(env!("CARGO_BIN_EXE_fragkit"))
                .args(["import", "--db", db, report.to_str().unwrap()])
                .spawn()
                .unwrap()
        })
        .collect();
    for mut writer in writers {
        assert!(writer.wait().unwrap().success());
    }
    let (code, text) = fragkit(&["compare", "--db", db, "tag:base", "latest"]);
    assert_eq!(code, 0, "{text}");
    assert!(text.contains("only in the base"), "{text}");
    let (code, text) = fragkit(&["compare", "--db", db, "tag:bench", "latest@*"]);
    assert_eq!(code, 0, "{text}");
    let (code, text) = fragkit(&["compare", "--db", db, "latest~5", "latest"]);
    assert_eq!(code, 2, "{text}");
    assert!(text.contains("holds no run latest~5 (5 runs recorded)"), "{text}");
    let (code, text) = fragkit(&["compare", "--db", db, "latest@no-such-adapter*", "latest"]);
    assert_eq!(code, 2, "{text}");
}

#[test]
fn runs_recorded_in_an_sqlite_database_compare_and_concurrent_writers_both_land() {
    let dir = std::env::temp_dir().join(format!("fragkit-db-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let db = dir.join("results.sqlite");
    runs_recorded_in_a_database_compare_and_concurrent_writers_both_land(db.to_str().unwrap(), &dir);

    // Not a database, a newer schema, and no --db for a run name: refused.
    let junk = dir.join("junk.sqlite");
    std::fs::write(&junk, "not a database").unwrap();
    let (code, text) = fragkit(&["check", "kit.hash.values", "--db", junk.to_str().unwrap()]);
    assert_eq!(code, 2, "{text}");
    let (code, text) = fragkit(&["compare", "latest~1", "latest"]);
    assert_eq!(code, 2, "{text}");
    std::fs::remove_dir_all(&dir).ok();
}

#[test]
fn runs_recorded_in_a_postgres_database_compare_and_concurrent_writers_both_land() {
    let Some(db) = fresh_postgres_database("round_trip") else { return };
    let dir = std::env::temp_dir().join(format!("fragkit-pg-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    runs_recorded_in_a_database_compare_and_concurrent_writers_both_land(&db, &dir);

    // A newer schema than this kit knows, someone else's tables, an unreachable server: refused.
    let psql = |url: &str, sql: &str| assert!(Command::new("psql").args([url, "-qc", sql]).status().unwrap().success());
    psql(&db, "UPDATE fragkit_schema SET version = 99");
    let (code, text) = fragkit(&["compare", "--db", &db, "latest~1", "latest"]);
    assert!(code == 2 && text.contains("schema version 99"), "{text}");
    let other = fresh_postgres_database("other_tables").unwrap();
    psql(&other, "CREATE TABLE orders (id BIGINT)");
    let (code, text) = fragkit(&["check", "kit.hash.values", "--db", &other]);
    assert!(code == 2 && text.contains("not a fragkit results database"), "{text}");
    let (code, text) = fragkit(&["check", "kit.hash.values", "--db", "postgres://fragkit@127.0.0.1:1/none"]);
    assert!(code == 2 && text.contains("connecting to the results database"), "{text}");
    std::fs::remove_dir_all(&dir).ok();
}

#[test]
fn the_store_refuses_what_it_cannot_keep_before_the_run_and_never_shows_a_secret() {
    let dir = std::env::temp_dir().join(format!("fragkit-store-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let in_dir = |args: &[&str]| {
        let output = Command::new(env!("CARGO_BIN_EXE_fragkit")).args(args).current_dir(&dir).output().unwrap();
        let text = String::from_utf8_lossy(&output.stdout).into_owned() + &String::from_utf8_lossy(&output.stderr);
        assert!(!text.contains("panicked"), "{text}");
        (output.status.code().unwrap_or(-1), text)
    };
    let files = || -> Vec<String> {
        let mut names: Vec<String> =
            std::fs::read_dir(&dir).unwrap().map(|e| e.unwrap().file_name().to_string_lossy().into_owned()).collect();
        names.sort();
        names
    };
    // An empty --db, another scheme, a libpq string (a server, not a file named with the password).
    for db in ["", "mysql://kit:hunter2@localhost/runs", "http://localhost/runs"] {
        let (code, text) = in_dir(&["check", "kit.hash.values", "--db", db]);
        assert_eq!(code, 2, "--db {db:?}: {text}");
        assert!(!text.contains("hunter2") && !text.contains("recorded as run"), "{text}");
    }
    let (code, text) =
        in_dir(&["check", "kit.hash.values", "--db", "host=/nonexistent password=hunter2 dbname=fragkit"]);
    assert_eq!(code, 2, "{text}");
    assert!(text.contains("password=***") && !text.contains("hunter2"), "{text}");
    assert!(files().is_empty(), "{:?}", files());
    // Readers never create the file they were pointed at.
    for args in [
        &["history", "kit.hash.values", "--db", "typo.sqlite", "--out", "h.png"][..],
        &["compare", "--db", "typo.sqlite", "latest~1", "latest"],
        &["html", "--db", "typo.sqlite", "--out", "site"],
    ] {
        let (code, text) = in_dir(args);
        assert_eq!(code, 2, "{args:?}: {text}");
        assert!(text.contains("no results database at typo.sqlite"), "{text}");
    }
    assert!(!dir.join("typo.sqlite").exists());
    // A damaged page and a read-only file are found before the run.
    let (code, text) = in_dir(&["check", "kit.hash.values", "--db", "runs.sqlite"]);
    assert_eq!(code, 0, "{text}");
    let (code, text) =
        in_dir(&["history", "kit.hash.values", "--db", "runs.sqlite", "--metric", "nope", "--out", "h.png"]);
    assert_eq!(code, 2, "{text}");
    assert!(text.contains("no metric \"nope\""), "{text}");
    let mut bytes = std::fs::read(dir.join("runs.sqlite")).unwrap();
    let page = 4096.min(bytes.len() / 2);
    let end = (2 * page).min(bytes.len());
    for byte in &mut bytes[page..end] {
        *byte = 0xA5;
    }
    std::fs::write(dir.join("damaged.sqlite"), &bytes).unwrap();
    let (code, text) = in_dir(&["check", "kit.hash.values", "--db", "damaged.sqlite"]);
    assert_eq!(code, 2, "{text}");
    assert!(text.contains("damaged.sqlite") && !text.contains("kit.hash.values  "), "{text}");
    std::fs::copy(dir.join("runs.sqlite"), dir.join("readonly.sqlite")).unwrap();
    let mut permissions = std::fs::metadata(dir.join("readonly.sqlite")).unwrap().permissions();
    permissions.set_readonly(true);
    std::fs::set_permissions(dir.join("readonly.sqlite"), permissions).unwrap();
    let root = runs_as_root();
    // Root writes whatever the permissions say: there the file is not read-only to it.
    if !root {
        let (code, text) = in_dir(&["check", "kit.hash.values", "--db", "readonly.sqlite"]);
        assert_eq!(code, 2, "{text}");
        assert!(text.contains("is read-only"), "{text}");
    }
    std::fs::remove_dir_all(&dir).ok();
}

/// Whether this process runs as root, whom file permissions do not stop.
fn runs_as_root() -> bool {
    std::fs::read_to_string("/proc/self/status")
        .ok()
        .and_then(|s| s.lines().find(|l| l.starts_with("Uid:")).map(|l| l.split_whitespace().nth(1) == Some("0")))
        .unwrap_or(false)
}

#[test]
fn a_parameter_set_twice_is_an_error() {
    let (code, text) = fragkit(&["check", "kit.determinism", "--set", "seed=1", "--set", "seed=2"]);
    assert_eq!(code, 2, "{text}");
    assert!(text.contains("--set seed is given twice (\"1\" and \"2\")"), "{text}");
}

#[test]
fn a_parameter_dependent_known_issue_may_pass_away_from_the_defaults_only() {
    let path = std::env::temp_dir().join(format!("fragkit-may-pass-{}.toml", std::process::id()));
    let entry = "[[known_issue]]\ncase = \"kit.determinism\"\nreason = \"shows on big screens\"\nmay_pass = \"small screens cannot show it\"\n";
    std::fs::write(&path, entry).unwrap();
    let expectations = path.to_str().unwrap();
    let (code, text) = fragkit(&["check", "kit.determinism", "--expectations", expectations, "--set", "seed=3"]);
    assert_eq!(code, 0, "{text}");
    assert!(text.contains(" pass ") && text.contains("the listed known issues cannot"), "{text}");
    let (code, text) = fragkit(&["check", "kit.determinism", "--expectations", expectations]);
    assert_eq!(code, 1, "at the defaults a pass still means the entry is stale: {text}");
    // An intermittent issue (a crash some machines never show) may pass anywhere, saying why.
    let entry = "[[known_issue]]\ncase = \"kit.determinism\"\nfailure = \"crash: *\"\nreason = \"heap corruption\"\nintermittent = \"needs AVX2\"\n";
    std::fs::write(&path, entry).unwrap();
    let (code, text) = fragkit(&["check", "kit.determinism", "--expectations", expectations, "-v"]);
    assert_eq!(code, 0, "{text}");
    assert!(text.contains("do not show on every run: needs AVX2"), "{text}");
    std::fs::remove_file(&path).ok();
}

/// stdout and stderr apart.
fn fragkit_streams(args: &[&str]) -> (i32, String, String) {
    let output = Command::new(env!("CARGO_BIN_EXE_fragkit")).args(args).output().expect("running fragkit");
    let (out, err) =
        (String::from_utf8_lossy(&output.stdout).into_owned(), String::from_utf8_lossy(&output.stderr).into_owned());
    assert!(!err.contains("panicked"), "fragkit {args:?} panicked:\n{err}");
    (output.status.code().unwrap_or(-1), out, err)
}

#[test]
fn driver_and_wgpu_logs_go_to_the_report_not_the_terminal() {
    let dir = std::env::temp_dir().join(format!("fragkit-quiet-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let json = dir.join("report.json");
    let (code, out, err) = fragkit_streams(&["check", "kit.hash.values", "--json", json.to_str().unwrap()]);
    assert_eq!(code, 0, "{out}{err}");
    assert!(!err.contains("ERROR"), "stderr: {err}");
    let (code, out, err) = fragkit_streams(&["adapters"]);
    assert_eq!(code, 0, "{out}{err}");
    assert!(!err.contains("ERROR") && out.starts_with("backend"), "{out}{err}");

    // GL's sample-mask pipeline makes naga's GLSL writer and Mesa's compiler log errors: they
    // belong to the case, in its diagnostics, and show with -v.
    if out.lines().any(|l| l.starts_with("gl ")) {
        let (code, out, err) =
            fragkit_streams(&["--backend", "gl", "check", "oit.quads.converges", "--json", json.to_str().unwrap()]);
        assert_eq!(code, 0, "{out}{err}");
        assert!(!err.contains("ERROR"), "stderr: {err}");
        let report: serde_json::Value = serde_json::from_str(&std::fs::read_to_string(&json).unwrap()).unwrap();
        let logged = report["cases"][0]["diagnostics"].to_string();
        assert!(logged.contains("int[1]"), "{logged}");
        let (_, _, err) = fragkit_streams(&["--backend", "gl", "check", "oit.quads.converges", "-v"]);
        assert!(err.contains("int[1]"), "-v prints the records: {err}");
    }
    std::fs::remove_dir_all(&dir).ok();
}

/// GL 3.3 (softpipe's API; llvmpipe started at that version here) has no storage buffers, and the
/// checkerboard reconstruction only reads its parameters: it takes them from a uniform buffer there
/// and runs (kit/src/cbr/reconstruct.rs, `ParameterBuffer`), where a storage buffer would leave the
/// technique `not_supported` on an API that has all it needs.
#[test]
fn gl_3_3_runs_the_checkerboard_reconstruction_from_a_uniform_buffer() {
    let (_, adapters) = fragkit(&["adapters"]);
    if !adapters.lines().any(|l| l.starts_with("gl ")) {
        eprintln!("SKIPPED: no GL adapter here ({adapters})");
        return;
    }
    let dir = std::env::temp_dir().join(format!("fragkit-gl33-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let json = dir.join("report.json");
    let output = Command::new(env!("CARGO_BIN_EXE_fragkit"))
        .args(["--backend", "gl", "check", "cbr.extremes", "--json", json.to_str().unwrap()])
        .env("MESA_GL_VERSION_OVERRIDE", "3.3")
        .env("MESA_GLSL_VERSION_OVERRIDE", "330")
        .output()
        .unwrap();
    let text = String::from_utf8_lossy(&output.stdout).into_owned() + &String::from_utf8_lossy(&output.stderr);
    assert_eq!(output.status.code(), Some(0), "{text}");
    let report: serde_json::Value = serde_json::from_str(&std::fs::read_to_string(&json).unwrap()).unwrap();
    assert!(report["adapter"]["driver_info"].as_str().unwrap().starts_with("3.3 "), "{}", report["adapter"]);
    assert_eq!(report["cases"][0]["outcome"], "pass", "{}", report["cases"][0]["reason"]);
    std::fs::remove_dir_all(&dir).ok();
}

/// llvmpipe's OpenGL ES contexts (cases/adapters.toml, gles-3.0 and gles-3.1): coarse pixel
/// shading runs on GLES 3.0 without indirect draws, the alpha-to-coverage OIT without a route to
/// single samples, and on GLES 3.1 the GL error behind the refused indirect draw is in the verdict.
#[test]
fn gles_keeps_the_techniques_and_names_the_gl_error() {
    let (_, adapters) = fragkit(&["adapters"]);
    if !adapters.lines().any(|l| l.starts_with("gl ")) {
        eprintln!("SKIPPED: no GL adapter here ({adapters})");
        return;
    }
    let dir = std::env::temp_dir().join(format!("fragkit-gles-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let run = |version: &str, cases: &[&str]| {
        let json = dir.join(format!("gles-{version}.json"));
        let output = Command::new(env!("CARGO_BIN_EXE_fragkit"))
            .args(["--backend", "gl", "--driver-info", &format!("OpenGL ES {version} *"), "check"])
            .args(cases)
            .args(["--json", json.to_str().unwrap()])
            .env("MESA_GL_VERSION_OVERRIDE", "3.2")
            .env("MESA_GLES_VERSION_OVERRIDE", version)
            .output()
            .unwrap();
        let text = String::from_utf8_lossy(&output.stdout).into_owned() + &String::from_utf8_lossy(&output.stderr);
        assert_eq!(output.status.code(), Some(0), "{text}");
        let report: serde_json::Value = serde_json::from_str(&std::fs::read_to_string(&json).unwrap()).unwrap();
        report["cases"].as_array().unwrap().clone()
    };
    for case in run("3.0", &["cps.level_lighting", "oit.a2c.transfer"]) {
        assert_eq!(case["outcome"], "pass", "{}: {}", case["name"], case["reason"]);
    }
    let indirect = &run("3.1", &["kit.draw.indirect"])[0];
    assert_eq!(indirect["outcome"], "known_issue", "{}", indirect["reason"]);
    assert!(
        indirect["reason"].as_str().unwrap().contains("GL_INVALID_OPERATION in glDrawArraysIndirect"),
        "{}",
        indirect["reason"]
    );
    std::fs::remove_dir_all(&dir).ok();
}
