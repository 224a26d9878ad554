//! `check --bug-report` (issue 39): a folder per case run that did not pass, whose capture
//! replays without fragkit, wgpu or naga and shows the pixels the case judged.

use std::path::{Path, PathBuf};
use std::process::Command;

/// A folder of the test's own, empty.
fn scratch(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("fragkit-bug-report-{name}-{}", std::process::id()));
    std::fs::remove_dir_all(&dir).ok();
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

fn fragkit(args: &[&str], path: Option<&str>) -> (i32, String) {
    let mut command = Command::new(env!("CARGO_BIN_EXE_fragkit"));
    command.args(args);
    if let Some(path) = path {
        command.env("PATH", path);
    }
    let output = command.output().unwrap();
    let text = String::from_utf8_lossy(&output.stdout).into_owned() + &String::from_utf8_lossy(&output.stderr);
    assert!(!text.contains("panicked"), "{text}");
    (output.status.code().unwrap_or(-1), text)
}

/// Whether apitrace is installed; without it the GL test is skipped with a note, except under CI
/// (`.ci/setup` installs it).
fn have_apitrace() -> bool {
    let found = Command::new("sh").args(["-c", "command -v apitrace && command -v eglretrace"]).output();
    let found = found.is_ok_and(|o| o.status.success());
    if !found {
        assert!(std::env::var_os("CI").is_none(), "CI must test GL bug reports: .ci/setup installs apitrace");
        eprintln!("note: apitrace is not installed (apt-get install apitrace): GL bug report test skipped");
    }
    found
}

/// The one folder a bug report run wrote.
fn only_folder(dir: &Path) -> PathBuf {
    let folders: Vec<PathBuf> = std::fs::read_dir(dir).unwrap().map(|e| e.unwrap().path()).collect();
    assert_eq!(folders.len(), 1, "{folders:?}");
    folders[0].clone()
}

fn rgba(path: &Path) -> image::RgbaImage {
    image::open(path).unwrap_or_else(|e| panic!("{}: {e}", path.display())).to_rgba8()
}

/// Two wgpu-hal GL issues on llvmpipe GL, the ignored sample mask (`kit.msaa.sample_mask`) and
/// the resolve under a scissor (`kit.scissor.msaa`): each folder's `replay`, run from the folder
/// in a shell with nothing but /usr/bin and /bin on the PATH, writes every texture the case read
/// back, and each equals the kit's read-back pixel for pixel (eglretrace writes GL's bottom row
/// first: flipped).
#[test]
fn gl_known_issues_replay_their_failing_pixels_without_fragkit() {
    if !have_apitrace() {
        return;
    }
    let dir = scratch("gl");
    let (code, text) = fragkit(
        &[
            "--backend",
            "gl",
            "check",
            "kit.msaa.sample_mask",
            "kit.scissor.msaa",
            "--bug-report",
            dir.to_str().unwrap(),
            "--bug-report-known",
        ],
        None,
    );
    assert_eq!(code, 0, "{text}");
    let mask = dir.join("kit.msaa.sample_mask");
    let scissor = std::fs::read_dir(&dir)
        .unwrap()
        .map(|e| e.unwrap().path())
        .find(|p| p.file_name().unwrap().to_string_lossy().starts_with("kit.scissor.msaa"))
        .expect("kit.scissor.msaa's folder");
    for (folder, case, images) in [(mask, "kit.msaa.sample_mask", 12), (scissor, "kit.scissor.msaa", 3)] {
        let readme = std::fs::read_to_string(folder.join("README.md")).unwrap();
        for expected in [
            &format!("# {case}"),
            "known_issue on llvmpipe",
            "## What the case checks",
            "## Driver",
            "wgpu-hal",
            &format!("fragkit check {case} --backend gl"),
            "The captured run's outcome and metrics (timings left out) equal the first run's.",
            "shaders/glsl/",
            "equal to the kit's, pixel for pixel",
        ] {
            assert!(readme.contains(expected), "{case}: README lacks {expected:?}:\n{readme}");
        }
        assert!(folder.join("capture/case.trace").is_file() && folder.join("shaders/glsl").is_dir());
        replay_bare(&folder);
        let mut compared = 0;
        for entry in std::fs::read_dir(folder.join("readbacks")).unwrap() {
            let kit = entry.unwrap().path();
            if kit.extension().is_none_or(|e| e != "png") {
                continue;
            }
            let replayed = rgba(&folder.join("replayed").join(kit.file_name().unwrap()));
            let flipped = image::imageops::flip_vertical(&replayed);
            assert_eq!(flipped, rgba(&kit), "{} differs from its replay", kit.display());
            compared += 1;
        }
        assert_eq!(compared, images, "{case}: the RGBA8 textures it reads back");
    }
    std::fs::remove_dir_all(&dir).ok();
}

/// Whether RenderDoc's capture tool and Python module are installed; without them the Vulkan test
/// is skipped with a note, except under CI (`.ci/setup` installs them).
fn have_renderdoc() -> bool {
    let found = Command::new("sh")
        .args([
            "-c",
            "command -v renderdoccmd && (/usr/bin/python3 -c 'import renderdoc' || python3 -c 'import renderdoc')",
        ])
        .output()
        .is_ok_and(|o| o.status.success());
    if !found {
        assert!(std::env::var_os("CI").is_none(), "CI must test Vulkan bug reports: .ci/setup installs RenderDoc");
        eprintln!("note: RenderDoc is not installed (apt-get install renderdoccmd python3-renderdoc): test skipped");
    }
    found
}

/// Runs a report folder's `replay` from the folder with only /usr/bin and /bin on the PATH.
fn replay_bare(folder: &Path) {
    let replay = Command::new(folder.join("replay"))
        .env_clear()
        .env("PATH", "/usr/bin:/bin")
        .env("HOME", std::env::var("HOME").unwrap_or_default())
        .env("XDG_RUNTIME_DIR", std::env::var("XDG_RUNTIME_DIR").unwrap_or_else(|_| "/tmp".into()))
        .output()
        .unwrap();
    assert!(replay.status.success(), "{}", String::from_utf8_lossy(&replay.stderr));
}

/// lavapipe's scissored 4x draw (a known driver issue of `kit.scissor.msaa`): RenderDoc's
/// capture of the case's GPU work replays with RenderDoc's Python module alone and shows every
/// texture the case read back as the kit read it; the shaders are naga's SPIR-V with spirv-dis's
/// text.
#[test]
fn a_vulkan_driver_issue_replays_its_failing_pixels_with_renderdoc_alone() {
    if !have_renderdoc() {
        return;
    }
    let dir = scratch("vulkan");
    let (code, text) = fragkit(
        &[
            "--backend",
            "vulkan",
            "check",
            "kit.scissor.msaa",
            "--bug-report",
            dir.to_str().unwrap(),
            "--bug-report-known",
        ],
        None,
    );
    assert_eq!(code, 0, "{text}");
    let folder = only_folder(&dir);
    let readme = std::fs::read_to_string(folder.join("README.md")).unwrap();
    for expected in
        ["driver (lavapipe", "capture/case.rdc", "equal to the kit's, pixel for pixel", "equal the first run's"]
    {
        assert!(readme.contains(expected), "README lacks {expected:?}:\n{readme}");
    }
    assert!(folder.join("shaders/spirv/kit/rect.spv").is_file());
    let disassembly = std::fs::read_to_string(folder.join("shaders/spirv/kit/rect.spvasm")).unwrap();
    assert!(disassembly.contains("OpEntryPoint"), "{disassembly}");
    replay_bare(&folder);
    let mut compared = 0;
    for entry in std::fs::read_dir(folder.join("readbacks")).unwrap() {
        let kit = entry.unwrap().path();
        if kit.extension().is_none_or(|e| e != "png") {
            continue;
        }
        let replayed = rgba(&folder.join("replayed").join(kit.file_name().unwrap()));
        assert_eq!(replayed, rgba(&kit), "{} differs from its replay", kit.display());
        compared += 1;
    }
    assert_eq!(compared, 3, "the case reads back three RGBA8 textures");
    std::fs::remove_dir_all(&dir).ok();
}

/// A run that passes writes no folder; a GL report without apitrace on the PATH exits 2 before
/// any case runs, naming the package.
#[test]
fn passes_get_no_folder_and_a_missing_tool_exits_2_naming_its_package() {
    let dir = scratch("none");
    let (code, text) =
        fragkit(&["--backend", "vulkan", "check", "kit.hash.values", "--bug-report", dir.to_str().unwrap()], None);
    assert_eq!(code, 0, "{text}");
    assert!(text.contains("bug reports: no case run to report"), "{text}");
    assert_eq!(std::fs::read_dir(&dir).unwrap().count(), 0);
    let (code, text) = fragkit(
        &["--backend", "gl", "check", "kit.hash.values", "--bug-report", dir.to_str().unwrap()],
        Some("/nonexistent"),
    );
    assert_eq!(code, 2, "{text}");
    assert!(text.contains("apt-get install apitrace") && !text.contains("kit.hash.values "), "{text}");
    let (code, text) = fragkit(
        &["--backend", "vulkan", "check", "kit.hash.values", "--bug-report", dir.to_str().unwrap()],
        Some("/nonexistent"),
    );
    assert_eq!(code, 2, "{text}");
    assert!(text.contains("apt-get install renderdoccmd python3-renderdoc"), "{text}");
    std::fs::remove_dir_all(&dir).ok();
}
