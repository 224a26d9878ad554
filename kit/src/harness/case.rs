//! A render case: a named experiment with requirements and parameters that ends in one outcome.

use std::collections::BTreeMap;
use std::path::PathBuf;

use anyhow::{Context, Result};
use serde::Serialize;

use super::params::Sweep;
use super::params::{ParamSpec, Params};
use crate::gpu::Gpu;
use crate::shaders::ShaderFile;

/// What a case concluded.
#[derive(Clone, Debug, PartialEq)]
pub enum Outcome {
    Pass,
    /// The evidence is in the case's metrics and images; the text says what differed.
    Fail(String),
    /// The adapter lacks what the case checks; the text names the missing capability.
    NotSupported(String),
}

/// A case, declared as data; `run` reads top to bottom as setup → render → measure → compare.
#[derive(Clone, Copy)]
pub struct Case {
    /// Hierarchical name: `area.subject.aspect`.
    pub name: &'static str,
    pub summary: &'static str,
    /// Device features without which the case is NotSupported.
    pub requires: wgpu::Features,
    pub params: &'static [ParamSpec],
    /// The ranges a sweep may draw parameters from (empty: the case runs at its defaults only).
    pub sweep: &'static [Sweep],
    /// Whole seconds the case takes at its defaults on the slowest configuration of the adapter
    /// matrix (rounded up from its measured wall time, device opening excluded): what its
    /// timeout in a supervised run follows from.
    pub budget_s: u32,
    /// Its verdict rests on a measured time (a ratio of GPU times): it runs with nothing beside
    /// it, in this run (`check --jobs`) or any other fragkit run on the machine (`case_lock`).
    pub timed_verdict: bool,
    /// The shader files its pipelines are built from, from the kit's shader table (with the
    /// module that builds each): one hop from the case to its shaders and technique. A case
    /// whose run builds a file it does not list fails its test (cases/tests/cases.rs).
    pub shaders: &'static [ShaderFile],
    pub run: fn(&mut Ctx) -> Result<Outcome>,
}

#[cfg(test)]
impl Case {
    /// A parameterless case that passes: for the harness's own tests.
    pub(crate) fn passing(name: &'static str) -> Self {
        Self {
            name,
            summary: "",
            requires: wgpu::Features::empty(),
            params: &[],
            sweep: &[],
            budget_s: 1,
            timed_verdict: false,
            shaders: &[],
            run: |_| Ok(Outcome::Pass),
        }
    }
}

/// What a running case can use and record.
pub struct Ctx<'a> {
    pub gpu: &'a Gpu,
    pub params: Params,
    pub(crate) case_name: &'static str,
    pub(crate) metrics: BTreeMap<String, serde_json::Value>,
    pub(crate) evidence_dir: Option<PathBuf>,
    pub(crate) evidence: Vec<PathBuf>,
}

impl<'a> Ctx<'a> {
    pub(crate) fn new(gpu: &'a Gpu, case_name: &'static str, params: Params, evidence_dir: Option<PathBuf>) -> Self {
        Self { gpu, params, case_name, metrics: BTreeMap::new(), evidence_dir, evidence: Vec::new() }
    }

    /// Records a measured quantity for the report.
    pub fn metric(&mut self, name: &str, value: impl Serialize) {
        let value = serde_json::to_value(value).unwrap_or_else(|e| serde_json::Value::String(format!("<{e}>")));
        self.metrics.insert(name.to_owned(), value);
    }

    /// Writes an evidence image (when the run has an output folder) and lists it in the report.
    pub fn evidence_image(&mut self, name: &str, image: &image::RgbaImage) -> Result<()> {
        let Some(dir) = &self.evidence_dir else {
            return Ok(());
        };
        let path = dir.join(format!("{}.{name}.png", self.case_name));
        image.save(&path).with_context(|| format!("writing evidence image {}", path.display()))?;
        self.evidence.push(path);
        Ok(())
    }
}
