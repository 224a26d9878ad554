//! The documentation's links resolve: every relative link in README.md and docs/*.md names a file
//! of this repository (nothing points outside it).

use std::path::{Path, PathBuf};

fn markdown_files(root: &Path) -> Vec<PathBuf> {
    let mut files = vec![root.join("README.md")];
    let mut docs: Vec<PathBuf> = std::fs::read_dir(root.join("docs"))
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| p.extension().is_some_and(|e| e == "md"))
        .collect();
    docs.sort();
    files.extend(docs);
    files
}

/// The targets of `[text](target)` links.
fn links(text: &str) -> Vec<String> {
    text.match_indices("](")
        .filter_map(|(i, _)| text[i + 2..].split_once(')').map(|(target, _)| target.to_owned()))
        .collect()
}

#[test]
fn every_documentation_link_resolves_inside_the_repository() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).parent().unwrap();
    let mut broken = Vec::new();
    for file in markdown_files(root) {
        let text = std::fs::read_to_string(&file).unwrap();
        assert!(!text.contains("../shared"), "{} refers outside the repository", file.display());
        for target in links(&text) {
            if target.starts_with("http://") || target.starts_with("https://") || target.starts_with('#') {
                continue;
            }
            let path = file.parent().unwrap().join(target.split('#').next().unwrap());
            if !path.exists() {
                broken.push(format!("{}: {target}", file.display()));
            }
        }
    }
    assert!(broken.is_empty(), "broken links: {broken:#?}");
    let readme = std::fs::read_to_string(root.join("README.md")).unwrap();
    assert!(readme.lines().count() <= 60, "the README is the front door: one screen, the rest in docs/");
}

const SHADERS_BEGIN: &str =
    "<!-- shaders per case: generated from the registry (cases/tests/docs.rs; FRAGKIT_UPDATE_DOCS=1 rewrites it) -->";
const SHADERS_END: &str = "<!-- end of shaders per case -->";

/// docs/cases.md's table of each case's shader files, as the registry declares them (the
/// kit's shader table entries each case lists, which its test holds to what it builds).
fn shaders_table() -> String {
    let mut table = String::from("| case | shader files (`shaders/…`) and the module that builds each |\n|---|---|\n");
    for case in fragkit_cases::all() {
        let files: Vec<String> = case.shaders.iter().map(|f| format!("`{}` ({})", f.path, f.module)).collect();
        let files = if files.is_empty() { "none".to_owned() } else { files.join(", ") };
        table.push_str(&format!("| `{}` | {files} |\n", case.name));
    }
    table
}

#[test]
fn the_cases_page_names_each_cases_shaders_as_the_registry_does() {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("../docs/cases.md");
    let text = std::fs::read_to_string(&path).unwrap();
    let start = text.find(SHADERS_BEGIN).expect("docs/cases.md has the shaders-per-case section") + SHADERS_BEGIN.len();
    let end = text.find(SHADERS_END).expect("the section's end marker");
    let generated = format!("\n{}", shaders_table());
    if std::env::var_os("FRAGKIT_UPDATE_DOCS").is_some() {
        std::fs::write(&path, format!("{}{generated}{}", &text[..start], &text[end..])).unwrap();
        return;
    }
    assert_eq!(
        text[start..end],
        generated,
        "docs/cases.md's shaders per case differ from the registry; FRAGKIT_UPDATE_DOCS=1 rewrites them"
    );
}
