//! The adapter matrix: named configurations (backend, adapter name, environment) that each run
//! in a process of their own, shipped as `cases/adapters.toml`.

use std::collections::BTreeMap;
use std::path::Path;

use anyhow::{Context, Result, bail};
use serde::Deserialize;

/// The matrix shipped with the kit.
pub const BUILT_IN: &str = include_str!("../../adapters.toml");

#[derive(Clone, Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Configuration {
    pub name: String,
    pub about: String,
    /// A backend name (`fragkit --backend`).
    pub backend: String,
    /// A substring of the adapter name (`fragkit --adapter`).
    pub adapter: String,
    /// A glob over the adapter's driver info (`fragkit --driver-info`): the context the
    /// environment asks for (`OpenGL ES 3.0*`), so that a driver ignoring it fails the run.
    #[serde(default)]
    pub driver_info: Option<String>,
    /// Variables set in the configuration's process, read by the loaders and drivers.
    #[serde(default)]
    pub env: BTreeMap<String, String>,
    /// Globs of files that must exist for the configuration to be present.
    #[serde(default)]
    pub requires: Vec<String>,
    /// What installs those files.
    pub installs: String,
}

#[derive(Clone, Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Matrix {
    #[serde(rename = "configuration")]
    pub configurations: Vec<Configuration>,
}

impl Configuration {
    /// Why the configuration cannot run here (a required file is missing), or None.
    pub fn absent_because(&self) -> Option<String> {
        let missing: Vec<&str> = self
            .requires
            .iter()
            .filter(|pattern| glob::glob(pattern).map_or(true, |mut found| found.next().is_none()))
            .map(String::as_str)
            .collect();
        (!missing.is_empty()).then(|| format!("missing {} ({})", missing.join(", "), self.installs))
    }

    /// A file-name-safe form of the name, for per-configuration reports.
    pub fn file_stem(&self) -> String {
        self.name.chars().map(|c| if c.is_ascii_alphanumeric() || c == '-' { c } else { '_' }).collect()
    }
}

impl Matrix {
    pub fn parse(text: &str, origin: &str) -> Result<Self> {
        let matrix: Self = toml::from_str(text).with_context(|| format!("parsing adapter matrix {origin}"))?;
        for (i, configuration) in matrix.configurations.iter().enumerate() {
            fragkit::gpu::parse_backend(&configuration.backend)
                .with_context(|| format!("{origin}: configuration {:?}", configuration.name))?;
            if matrix.configurations[..i].iter().any(|c| c.name == configuration.name) {
                bail!("{origin}: configuration {:?} is listed twice", configuration.name);
            }
        }
        Ok(matrix)
    }

    /// One configuration per adapter the instance enumerates here (`--matrix found`), named by
    /// backend and adapter, held to its driver info, with nothing set in its environment.
    pub fn found(adapters: &[fragkit_report::AdapterDescription]) -> Self {
        let configurations = adapters
            .iter()
            .map(|adapter| Configuration {
                name: adapter.slug(),
                about: format!("{} ({}), found by the instance", adapter.driver, adapter.driver_info),
                backend: adapter.backend.clone(),
                adapter: adapter.name.clone(),
                driver_info: Some(glob::Pattern::escape(&adapter.driver_info)),
                env: BTreeMap::new(),
                requires: Vec::new(),
                installs: "installed".to_owned(),
            })
            .collect();
        Self { configurations }
    }

    pub fn built_in() -> Result<Self> {
        Self::parse(BUILT_IN, "cases/adapters.toml (built in)")
    }

    pub fn load(path: &Path) -> Result<Self> {
        let text =
            std::fs::read_to_string(path).with_context(|| format!("reading adapter matrix {}", path.display()))?;
        Self::parse(&text, &path.display().to_string())
    }

    /// The configurations `names` lists (comma-separated; `all` for every one), in the matrix's
    /// order; an unknown name is an error that lists the known ones.
    pub fn select(&self, names: &str) -> Result<Vec<&Configuration>> {
        let wanted: Vec<&str> = names.split(',').map(str::trim).filter(|n| !n.is_empty()).collect();
        if wanted.is_empty() || wanted == ["all"] {
            return Ok(self.configurations.iter().collect());
        }
        let known: Vec<&str> = self.configurations.iter().map(|c| c.name.as_str()).collect();
        for name in &wanted {
            if !known.contains(name) {
                bail!("no configuration {name:?} in the adapter matrix; known: {}", known.join(", "));
            }
        }
        Ok(self.configurations.iter().filter(|c| wanted.contains(&c.name.as_str())).collect())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_built_in_matrix_parses_and_selects() {
        let matrix = Matrix::built_in().unwrap();
        assert_eq!(matrix.configurations.len(), 10);
        assert_eq!(matrix.select("all").unwrap().len(), 10);
        let chosen: Vec<&str> = matrix.select("zink, lavapipe").unwrap().iter().map(|c| c.name.as_str()).collect();
        assert_eq!(chosen, ["lavapipe", "zink"]);
        assert!(matrix.select("lavapipe,nope").is_err());
    }

    #[test]
    fn found_adapters_become_configurations_named_by_backend_and_adapter() {
        let adapter = |backend: &str, driver_info: &str| fragkit_report::AdapterDescription {
            name: "llvmpipe (LLVM 15.0.6, 256 bits)".into(),
            backend: backend.into(),
            driver: "llvmpipe".into(),
            driver_info: driver_info.into(),
            device_type: "Cpu".into(),
        };
        let matrix =
            Matrix::found(&[adapter("vulkan", "Mesa 22.3.6"), adapter("gl", "4.5 (Core Profile) Mesa [22.3.6]")]);
        let names: Vec<&str> = matrix.configurations.iter().map(|c| c.name.as_str()).collect();
        assert_eq!(names, ["vulkan_llvmpipe_llvm_15_0_6_256_bits", "gl_llvmpipe_llvm_15_0_6_256_bits"]);
        let gl = &matrix.configurations[1];
        assert_eq!((gl.backend.as_str(), gl.adapter.as_str()), ("gl", "llvmpipe (LLVM 15.0.6, 256 bits)"));
        // The driver info is held literally: its brackets are no glob.
        let held = glob::Pattern::new(gl.driver_info.as_deref().unwrap()).unwrap();
        assert!(held.matches("4.5 (Core Profile) Mesa [22.3.6]") && !held.matches("4.5 (Core Profile) Mesa 2"));
        assert!(gl.absent_because().is_none() && gl.env.is_empty());
    }

    #[test]
    fn a_missing_required_file_makes_a_configuration_absent() {
        let text = "[[configuration]]\nname = \"x\"\nabout = \"\"\nbackend = \"gl\"\nadapter = \"x\"\nrequires = [\"/nonexistent/*.json\"]\ninstalls = \"apt-get install x\"\n";
        let matrix = Matrix::parse(text, "test").unwrap();
        let why = matrix.configurations[0].absent_because().unwrap();
        assert!(why.contains("/nonexistent/*.json") && why.contains("apt-get install x"), "{why}");
    }
}
