//! Skip lists (`check --skips FILE`, `--exclude GLOB`), as deqp-runner's `--skips` files are: one
//! case glob a line, `#` comments. A case a fleet cannot afford, or one that hangs a GPU, is left
//! out of the run but never silently: it is recorded `skip` with the reason its entry gives.
//!
//! ```text
//! # Hangs the GPU on driver 1.2 (bug 123): the comment above an entry is its reason …
//! kit.msaa.*
//! cbr.*  backend=gl driver=llvmpipe   # … unless the entry has its own after it
//! ```
//! An entry may be scoped as a known issue is, by globs over the adapter's description:
//! `backend=`, `adapter=`, `driver=`, `driver_info=`; an entry without scope skips everywhere.

use std::path::Path;

use anyhow::{Context, Result, bail};
use glob::Pattern;

use crate::adapter::AdapterDescription;
use crate::expectations::{glob_matches, in_scope};

/// One line of a skip list.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct SkipEntry {
    pub case: String,
    pub backend: Option<String>,
    pub adapter: Option<String>,
    pub driver: Option<String>,
    pub driver_info: Option<String>,
    /// Why, with where the entry stands (`FILE:LINE`, or `--exclude`).
    pub reason: String,
}

/// The entries of every skip list a run was given.
#[derive(Clone, Debug, Default)]
pub struct SkipList {
    pub entries: Vec<SkipEntry>,
}

impl SkipEntry {
    fn matches(&self, case: &str, adapter: &AdapterDescription) -> bool {
        glob_matches(&self.case, case)
            && in_scope([&self.backend, &self.adapter, &self.driver, &self.driver_info], adapter)
    }
}

fn checked_glob(text: &str, origin: &str) -> Result<String> {
    Pattern::new(text).with_context(|| format!("{origin}: bad pattern {text:?}"))?;
    Ok(text.to_owned())
}

impl SkipList {
    /// Parses a skip list; `origin` names it in reasons and errors.
    pub fn parse(text: &str, origin: &str) -> Result<Self> {
        let mut entries = Vec::new();
        // The comment lines right above an entry: its reason where it has none of its own.
        let mut comment_above: Vec<&str> = Vec::new();
        for (index, line) in text.lines().enumerate() {
            let place = format!("{origin}:{}", index + 1);
            let (body, comment) = match line.split_once('#') {
                Some((body, comment)) => (body.trim(), Some(comment.trim())),
                None => (line.trim(), None),
            };
            if body.is_empty() {
                match comment {
                    // A bare "#" keeps the block going and adds nothing to it.
                    Some(text) => comment_above.extend((!text.is_empty()).then_some(text)),
                    // A blank line ends a comment block.
                    None => comment_above.clear(),
                }
                continue;
            }
            let mut words = body.split_whitespace();
            let case = checked_glob(words.next().unwrap_or_default(), &place)?;
            let mut entry = SkipEntry {
                case,
                backend: None,
                adapter: None,
                driver: None,
                driver_info: None,
                reason: String::new(),
            };
            for word in words {
                let Some((field, glob)) = word.split_once('=') else {
                    bail!(
                        "{place}: {word:?} is neither a case glob nor FIELD=GLOB (backend, adapter, driver, driver_info)"
                    );
                };
                let slot = match field {
                    "backend" => &mut entry.backend,
                    "adapter" => &mut entry.adapter,
                    "driver" => &mut entry.driver,
                    "driver_info" => &mut entry.driver_info,
                    _ => bail!("{place}: unknown field {field:?} (backend, adapter, driver, driver_info)"),
                };
                *slot = Some(checked_glob(glob, &place)?);
            }
            let why = match comment.filter(|c| !c.is_empty()) {
                Some(own) => own.to_owned(),
                None => comment_above.join(" "),
            };
            entry.reason = if why.is_empty() { format!("listed in {place}") } else { format!("{why} ({place})") };
            entries.push(entry);
        }
        Ok(Self { entries })
    }

    pub fn load(path: &Path) -> Result<Self> {
        let text =
            std::fs::read_to_string(path).with_context(|| format!("reading the skip list {}", path.display()))?;
        Self::parse(&text, &path.display().to_string())
    }

    /// `--exclude GLOB`: skip the cases it matches, on every adapter.
    pub fn exclude(glob: &str) -> Result<SkipEntry> {
        Ok(SkipEntry {
            case: checked_glob(glob, "--exclude")?,
            backend: None,
            adapter: None,
            driver: None,
            driver_info: None,
            reason: format!("--exclude {glob}"),
        })
    }

    /// Why the case is skipped on this adapter (the first entry that matches), if it is.
    pub fn reason(&self, case: &str, adapter: &AdapterDescription) -> Option<&str> {
        self.entries.iter().find(|e| e.matches(case, adapter)).map(|e| e.reason.as_str())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn adapter(backend: &str, name: &str, driver: &str) -> AdapterDescription {
        AdapterDescription {
            name: name.into(),
            backend: backend.into(),
            driver: driver.into(),
            driver_info: "Mesa 22.3.6".into(),
            ..Default::default()
        }
    }

    const LIST: &str = "\
# Hangs the GPU:
#
# bug 123.
kit.msaa.*

cbr.*  backend=gl driver=llvm*   # GL reconstruction is slow
soak.* adapter=*SwiftShader* driver_info=Mesa*
";

    #[test]
    fn an_entry_reads_its_reason_from_its_own_comment_or_the_block_above() {
        let list = SkipList::parse(LIST, "fleet.skips").unwrap();
        let reasons: Vec<&str> = list.entries.iter().map(|e| e.reason.as_str()).collect();
        assert_eq!(
            reasons,
            [
                "Hangs the GPU: bug 123. (fleet.skips:4)",
                "GL reconstruction is slow (fleet.skips:6)",
                "listed in fleet.skips:7"
            ]
        );
        assert_eq!(list.entries[1].backend.as_deref(), Some("gl"));
        assert_eq!(list.entries[2].driver_info.as_deref(), Some("Mesa*"));
    }

    #[test]
    fn a_scoped_entry_skips_only_on_the_adapters_it_names() {
        let list = SkipList::parse(LIST, "f").unwrap();
        let gl = adapter("gl", "llvmpipe (LLVM 15)", "llvmpipe");
        let vulkan = adapter("vulkan", "llvmpipe (LLVM 15)", "llvmpipe");
        assert!(list.reason("kit.msaa.sample_mask", &vulkan).is_some());
        assert!(list.reason("KIT.MSAA.x", &vulkan).is_some(), "case-insensitive, as expectations are");
        assert!(list.reason("cbr.reconstruct", &gl).is_some());
        assert_eq!(list.reason("cbr.reconstruct", &vulkan), None);
        assert_eq!(list.reason("soak.oit", &gl), None);
        assert!(list.reason("soak.oit", &adapter("vulkan", "SwiftShader Device", "SwiftShader")).is_some());
        assert_eq!(list.reason("kit.scissor", &gl), None);
        let excluded = SkipList { entries: vec![SkipList::exclude("oit.*").unwrap()] };
        assert_eq!(excluded.reason("oit.sorted", &gl), Some("--exclude oit.*"));
    }

    #[test]
    fn bad_lines_are_refused_with_their_place() {
        for (text, said) in [
            ("kit.[", "f:1: bad pattern \"kit.[\""),
            ("ok\nkit.a vendor=x", "f:2: unknown field \"vendor\""),
            ("kit.a gl", "f:1: \"gl\" is neither a case glob nor FIELD=GLOB"),
            ("kit.a backend=[", "f:1: bad pattern \"[\""),
        ] {
            let error = format!("{:#}", SkipList::parse(text, "f").unwrap_err());
            assert!(error.starts_with(said), "{text:?}: {error}");
        }
        assert!(SkipList::exclude("[").is_err());
        assert!(SkipList::load(Path::new("/nonexistent/skips")).is_err());
    }
}
