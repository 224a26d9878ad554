//! The command line that reproduces one case run, as a shell runs it: the case and its
//! parameters, and what chose and shaped the adapter — the matrix configuration the run was, the
//! variables of the driver stack set in this process (Mesa's, the Vulkan loader's, GLVND's and
//! EGL's, wgpu's), and the selection flags. A line that drops them meets another driver, or the
//! same driver in another state: `fragkit check CASE --backend gl` on plain llvmpipe passes where
//! the run that printed it crashed on zink over 4-lane lavapipe.

use std::collections::BTreeMap;

use super::case::Case;
use crate::gpu::AdapterSelector;

/// Variables read by the drivers and loaders the kit runs on, by exact name.
const DRIVER_VARIABLES: &[&str] = &[
    "GALLIUM_DRIVER",
    "LIBGL_ALWAYS_SOFTWARE",
    "LIBGL_DRIVERS_PATH",
    "EGL_PLATFORM",
    "__GLX_VENDOR_LIBRARY_NAME",
    "__EGL_VENDOR_LIBRARY_FILENAMES",
    "__EGL_VENDOR_LIBRARY_DIRS",
    // wgpu's GL backend picks its EGL platform by these.
    "DISPLAY",
    "WAYLAND_DISPLAY",
];

/// Families of variables read by them, by prefix: llvmpipe and gallivm, Mesa, zink, softpipe,
/// the Vulkan loader and layers, SwiftShader, Mesa's hardware drivers, wgpu.
const DRIVER_PREFIXES: &[&str] = &[
    "LP_",
    "GALLIVM_",
    "GALLIUM_",
    "MESA_",
    "ZINK_",
    "SOFTPIPE_",
    "VK_",
    "SWIFTSHADER_",
    "RADV_",
    "ANV_",
    "NIR_",
    "WGPU_",
];

/// Whether the driver stack reads `name`.
pub fn is_driver_variable(name: &str) -> bool {
    DRIVER_VARIABLES.contains(&name) || DRIVER_PREFIXES.iter().any(|prefix| name.starts_with(prefix))
}

/// How to run one case again where it ran.
#[derive(Clone, Debug, PartialEq)]
pub struct Reproduction {
    /// The suite's way to run one case: `fragkit check`.
    command: String,
    /// Driver-stack variables the run had that the flags do not set, in name order.
    environment: Vec<(String, String)>,
    /// How the adapter was chosen: `--matrix NAME`, or the selection flags; `--validation`.
    flags: Vec<String>,
    /// Whether the line names the backend of the adapter the run opened (`--backend B`): a run
    /// that chose none may have had wgpu fall back to another.
    names_backend: bool,
}

impl Reproduction {
    /// The run of this process: its driver-stack variables and the selector's flags.
    pub fn of_process(command: &str, selector: &AdapterSelector) -> Self {
        Self::new(command, selector, std::env::vars())
    }

    /// The run of a process with environment `variables`.
    pub fn new(
        command: &str,
        selector: &AdapterSelector,
        variables: impl IntoIterator<Item = (String, String)>,
    ) -> Self {
        let environment: BTreeMap<String, String> =
            variables.into_iter().filter(|(name, _)| is_driver_variable(name)).collect();
        let mut flags = Vec::new();
        for (flag, value) in [("--adapter", &selector.adapter_name), ("--driver-info", &selector.driver_info)] {
            if let Some(value) = value {
                flags.extend([flag.to_owned(), value.clone()]);
            }
        }
        if selector.validation {
            flags.push("--validation".to_owned());
        }
        Self { command: command.to_owned(), environment: environment.into_iter().collect(), flags, names_backend: true }
    }

    /// The same run as configuration `name` of the adapter matrix (`matrix_flags`: `--matrix
    /// NAME`, and `--adapters-file FILE` where the matrix is not the built-in one), which sets
    /// `configuration_environment` itself and chooses the adapter: those variables and the
    /// selection flags leave the line.
    pub fn as_configuration(
        mut self,
        matrix_flags: &[String],
        configuration_environment: &BTreeMap<String, String>,
    ) -> Self {
        self.environment.retain(|(name, value)| configuration_environment.get(name) != Some(value));
        let validation = self.flags.iter().any(|f| f == "--validation");
        self.flags = matrix_flags.to_vec();
        if validation {
            self.flags.push("--validation".to_owned());
        }
        self.names_backend = false;
        self
    }

    /// The line that runs `case` with `overrides` again on the adapter of `backend`.
    pub fn line(&self, case: &Case, overrides: &BTreeMap<String, String>, backend: &str) -> String {
        let mut words: Vec<String> =
            self.environment.iter().map(|(name, value)| format!("{name}={}", quoted(value))).collect();
        words.push(self.command.clone());
        words.push(quoted(case.name));
        for (key, value) in overrides {
            words.extend(["--set".to_owned(), quoted(&format!("{key}={value}"))]);
        }
        if self.names_backend {
            words.extend(["--backend".to_owned(), quoted(backend)]);
        }
        words.extend(self.flags.iter().map(|flag| quoted(flag)));
        words.join(" ")
    }
}

/// `text` as one shell word: as it is where every character is plain, else single-quoted.
fn quoted(text: &str) -> String {
    let plain = |c: char| c.is_ascii_alphanumeric() || "_-.,/:=+@%".contains(c);
    if !text.is_empty() && text.chars().all(plain) {
        text.to_owned()
    } else {
        format!("'{}'", text.replace('\'', r"'\''"))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::harness::Outcome;

    const CASE: Case = Case {
        name: "kit.example",
        summary: "",
        requires: wgpu::Features::empty(),
        params: &[],
        sweep: &[],
        budget_s: 1,
        timed_verdict: false,
        shaders: &[],
        run: |_| Ok(Outcome::Pass),
    };

    fn variables(pairs: &[(&str, &str)]) -> Vec<(String, String)> {
        pairs.iter().map(|(k, v)| ((*k).to_owned(), (*v).to_owned())).collect()
    }

    #[test]
    fn driver_variables_are_the_stacks_and_nothing_else() {
        for name in [
            "GALLIUM_DRIVER",
            "LP_NATIVE_VECTOR_WIDTH",
            "MESA_GL_VERSION_OVERRIDE",
            "VK_ICD_FILENAMES",
            "VK_DRIVER_FILES",
            "LIBGL_ALWAYS_SOFTWARE",
            "WGPU_BACKEND",
            "ZINK_DEBUG",
            "GALLIVM_PERF",
            "DISPLAY",
        ] {
            assert!(is_driver_variable(name), "{name}");
        }
        for name in ["PATH", "HOME", "XDG_RUNTIME_DIR", "CARGO", "RUST_LOG", "LANG", "VKX", "LP", "MY_LP_THING"] {
            assert!(!is_driver_variable(name), "{name}");
        }
    }

    /// The variables that shaped the driver, the case, each `--set`, the backend the run opened and
    /// the selection flags; values a shell would split or expand quoted.
    #[test]
    fn a_line_carries_the_driver_environment_the_parameters_and_the_selection() {
        let selector = AdapterSelector {
            backend: None,
            adapter_name: Some("llvmpipe".into()),
            driver_info: Some("OpenGL ES 3.0*".into()),
            validation: true,
        };
        let environment = variables(&[
            ("PATH", "/usr/bin"),
            ("LP_NATIVE_VECTOR_WIDTH", "128"),
            ("GALLIUM_DRIVER", "zink"),
            ("MESA_DEBUG", "it's"),
            ("HOME", "/root"),
        ]);
        let reproduction = Reproduction::new("fragkit check", &selector, environment);
        let overrides =
            BTreeMap::from([("size".to_owned(), "64x48".to_owned()), ("scene".to_owned(), "a b".to_owned())]);
        assert_eq!(
            reproduction.line(&CASE, &overrides, "gl"),
            "GALLIUM_DRIVER=zink LP_NATIVE_VECTOR_WIDTH=128 MESA_DEBUG='it'\\''s' fragkit check kit.example \
             --set 'scene=a b' --set size=64x48 --backend gl --adapter llvmpipe --driver-info 'OpenGL ES 3.0*' --validation"
        );
        let plain = Reproduction::new("suite", &AdapterSelector::default(), variables(&[("HOME", "/root")]));
        assert_eq!(plain.line(&CASE, &BTreeMap::new(), "vulkan"), "suite kit.example --backend vulkan");
    }

    /// As a matrix configuration the line names it: its own variables and the selection leave
    /// the line (the configuration sets and makes them), anything else set stays, and so does
    /// `--validation`.
    #[test]
    fn a_configurations_line_names_it_and_keeps_what_it_does_not_set() {
        let selector = AdapterSelector {
            backend: Some("gl".into()),
            adapter_name: Some("llvmpipe".into()),
            validation: true,
            ..Default::default()
        };
        let environment =
            variables(&[("GALLIUM_DRIVER", "zink"), ("LP_NATIVE_VECTOR_WIDTH", "128"), ("MESA_DEBUG", "1")]);
        let configuration = BTreeMap::from([
            ("GALLIUM_DRIVER".to_owned(), "zink".to_owned()),
            ("LP_NATIVE_VECTOR_WIDTH".to_owned(), "256".to_owned()),
        ]);
        let reproduction = Reproduction::new("fragkit check", &selector, environment)
            .as_configuration(&["--matrix".to_owned(), "zink".to_owned()], &configuration);
        assert_eq!(
            reproduction.line(&CASE, &BTreeMap::new(), "gl"),
            "LP_NATIVE_VECTOR_WIDTH=128 MESA_DEBUG=1 fragkit check kit.example --matrix zink --validation"
        );
        // Without validation, none is added: the selection's other flags do not stand for it.
        let selector = AdapterSelector { validation: false, ..selector };
        let reproduction = Reproduction::new("fragkit check", &selector, variables(&[("HOME", "/root")]))
            .as_configuration(&["--matrix".to_owned(), "zink".to_owned()], &configuration);
        assert_eq!(reproduction.line(&CASE, &BTreeMap::new(), "gl"), "fragkit check kit.example --matrix zink");
    }

    #[test]
    fn words_are_quoted_only_where_a_shell_would_change_them() {
        assert_eq!(quoted("kit.msaa.sample_mask"), "kit.msaa.sample_mask");
        assert_eq!(
            quoted("/usr/share/vulkan/icd.d/lvp_icd.x86_64.json"),
            "/usr/share/vulkan/icd.d/lvp_icd.x86_64.json"
        );
        assert_eq!(quoted(""), "''");
        assert_eq!(quoted("a b"), "'a b'");
        assert_eq!(quoted("$HOME"), "'$HOME'");
        assert_eq!(quoted("*"), "'*'");
        assert_eq!(quoted("it's"), "'it'\\''s'");
    }
}
