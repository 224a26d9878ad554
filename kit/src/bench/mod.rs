//! Performance measurements: each technique against its baseline, timed side by side in one
//! run. `cargo bench` (criterion, for developers) and `fragkit bench` (from the binary, recorded
//! in the results database) both call this code: a [`Bench`] names its variants and times one
//! frame of a variant; [`measure`] runs rounds — every variant once per round, back to back, so
//! the machine's drift cancels in the per-round ratios — and summarises them.

pub mod cbr;
pub mod cps;
pub mod oit;
pub mod stencil;

use std::collections::BTreeMap;

use anyhow::{Result, bail};
use serde::Serialize;

use crate::gpu::Gpu;
use fragkit_report::AdapterDescription;
use fragkit_report::noise::median;
use fragkit_report::noise::{MedianInterval, median_interval};
use fragkit_report::report::{CaseRecord, ReportedOutcome};

/// Confidence sought for the interval of a median speed-up.
const SPEEDUP_CONFIDENCE: f64 = 0.95;

/// One timed frame of a variant.
#[derive(Clone, Debug, Default)]
pub struct Sample {
    pub gpu_ms: f64,
    /// Where the time went (e.g. CPS: build, lighting, composite), in milliseconds.
    pub parts: Vec<(&'static str, f64)>,
    /// Counts the frame measured (e.g. shaded texels); the same every round.
    pub counts: Vec<(&'static str, u64)>,
}

impl Sample {
    pub fn gpu_ms(gpu_ms: f64) -> Self {
        Self { gpu_ms, ..Default::default() }
    }
}

/// A set of variants, each timed against its baseline.
pub trait Bench {
    /// The scene and size, e.g. `cps_640x360_200_lights`.
    fn name(&self) -> String;
    fn variants(&self) -> Vec<String>;
    /// The variant `variant`'s speed-up is measured against: one that does the same work but
    /// for what the technique saves.
    fn baseline(&self, variant: usize) -> usize;
    /// Renders one frame of `variant` and times it.
    fn run(&mut self, gpu: &Gpu, variant: usize) -> Result<Sample>;
    /// Metrics derived from a variant's medians and the baseline's (e.g. CPS's ideal speed-up),
    /// and a sentence saying where the time goes; none by default.
    fn explain(
        &self,
        _variant: &VariantSummary,
        _baseline: &VariantSummary,
    ) -> (BTreeMap<String, f64>, Option<String>) {
        (BTreeMap::new(), None)
    }
}

/// The benches `fragkit bench` offers, by technique.
pub const TECHNIQUES: [&str; 4] = ["cps", "oit", "cbr", "kit"];

/// The bench of `technique` (one of [`TECHNIQUES`]) at its default scene.
pub fn for_technique(gpu: &Gpu, technique: &str) -> Result<Box<dyn Bench>> {
    Ok(match technique {
        "cps" => Box::new(cps::CpsBench::new(gpu)?),
        "oit" => Box::new(oit::OitBench::new(gpu)?),
        "cbr" => Box::new(cbr::CbrBench::new(gpu)?),
        "kit" => Box::new(stencil::EarlyRejectionBench::new(gpu)?),
        other => bail!("unknown bench {other:?}; expected one of {}", TECHNIQUES.join(", ")),
    })
}

/// A variant's rounds, summarised.
#[derive(Clone, Debug, Serialize)]
pub struct VariantSummary {
    pub name: String,
    /// GPU time of every round, in order.
    pub gpu_ms: Vec<f64>,
    pub median_ms: f64,
    /// The variant this one's speed-up is measured against.
    pub baseline: String,
    /// Median over the rounds of baseline / this variant (1 for a baseline).
    pub speedup: f64,
    /// Where the median per-round speed-up lies, from the rounds' order statistics (no
    /// distribution assumed): how far one invocation's figure can be trusted.
    pub speedup_interval: MedianInterval,
    /// Median of each part over the rounds.
    pub parts: BTreeMap<String, f64>,
    pub counts: BTreeMap<String, u64>,
    /// What [`Bench::explain`] derived.
    pub derived: BTreeMap<String, f64>,
    pub explanation: Option<String>,
}

#[derive(Clone, Debug, Serialize)]
pub struct BenchResult {
    pub technique: String,
    pub bench: String,
    pub adapter: AdapterDescription,
    pub rounds: usize,
    pub variants: Vec<VariantSummary>,
    /// Wall time of the measured rounds, in milliseconds.
    pub wall_ms: f64,
}

/// Runs `rounds` rounds of every variant (after one untimed warm-up round: pipelines compile on
/// first use) and summarises them.
pub fn measure(gpu: &Gpu, technique: &str, bench: &mut dyn Bench, rounds: usize) -> Result<BenchResult> {
    if rounds == 0 {
        bail!("a bench needs at least one round");
    }
    let variants = bench.variants();
    for variant in 0..variants.len() {
        bench.run(gpu, variant)?;
    }
    let started = std::time::Instant::now();
    let mut samples: Vec<Vec<Sample>> = vec![Vec::with_capacity(rounds); variants.len()];
    for _ in 0..rounds {
        for (variant, samples) in samples.iter_mut().enumerate() {
            samples.push(bench.run(gpu, variant)?);
        }
    }
    let wall_ms = started.elapsed().as_secs_f64() * 1e3;
    let baselines: Vec<usize> = (0..variants.len()).map(|v| bench.baseline(v)).collect();
    let mut summaries: Vec<VariantSummary> = variants
        .iter()
        .zip(&samples)
        .zip(&baselines)
        .map(|((name, own), &baseline)| {
            let gpu_ms: Vec<f64> = own.iter().map(|s| s.gpu_ms).collect();
            let ratios: Vec<f64> = samples[baseline].iter().zip(own).map(|(b, s)| b.gpu_ms / s.gpu_ms).collect();
            let speedup_interval =
                median_interval(&ratios, SPEEDUP_CONFIDENCE).expect("a bench runs at least one round");
            let mut parts = BTreeMap::new();
            for (part, _) in &own[0].parts {
                let values =
                    own.iter().map(|s| s.parts.iter().find(|(p, _)| p == part).map_or(0.0, |(_, ms)| *ms)).collect();
                parts.insert((*part).to_owned(), median(values));
            }
            VariantSummary {
                name: name.clone(),
                median_ms: median(gpu_ms.clone()),
                gpu_ms,
                baseline: variants[baseline].clone(),
                speedup: median(ratios),
                speedup_interval,
                parts,
                counts: own[0].counts.iter().map(|(c, n)| ((*c).to_owned(), *n)).collect(),
                derived: BTreeMap::new(),
                explanation: None,
            }
        })
        .collect();
    let unexplained = summaries.clone();
    for (summary, &baseline) in summaries.iter_mut().zip(&baselines) {
        (summary.derived, summary.explanation) = bench.explain(summary, &unexplained[baseline]);
    }
    Ok(BenchResult {
        technique: technique.to_owned(),
        bench: bench.name(),
        adapter: gpu.description.clone(),
        rounds,
        variants: summaries,
        wall_ms,
    })
}

impl BenchResult {
    /// Lines for a person: each variant's median time and speed-up, and where its time goes.
    pub fn lines(&self) -> Vec<String> {
        let mut lines = vec![format!(
            "{} {} on {} ({}), medians of {} rounds:",
            self.technique, self.bench, self.adapter.name, self.adapter.backend, self.rounds
        )];
        for v in &self.variants {
            let parts: Vec<String> = v.parts.iter().map(|(p, ms)| format!("{p} {ms:.2}")).collect();
            let parts = if parts.is_empty() { String::new() } else { format!(" ({})", parts.join(", ")) };
            let speedup = if v.baseline == v.name {
                "baseline".to_owned()
            } else {
                let MedianInterval { low, high, coverage } = v.speedup_interval;
                // One round's ratio is the median itself, held by no interval.
                let interval = if coverage > 0.0 {
                    format!("{low:.2}–{high:.2}x, {:.0} % interval", 100.0 * coverage)
                } else {
                    "one round: no interval".to_owned()
                };
                format!("{:.2}x over {} ({interval})", v.speedup, v.baseline)
            };
            lines.push(format!("  {:<28} {:>9.2} ms{parts}  {speedup}", v.name, v.median_ms));
            if let Some(explanation) = &v.explanation {
                lines.push(format!("  {:<28} {explanation}", ""));
            }
        }
        lines
    }

    /// One record per variant, named `bench.<technique>.<bench>.<variant>`, for the results
    /// database and `fragkit compare`: GPU time the median with every round kept, the speed-up,
    /// parts, counts and derived figures as metrics.
    pub fn records(&self) -> Vec<CaseRecord> {
        let per_variant = self.wall_ms / self.variants.len() as f64;
        self.variants
            .iter()
            .map(|v| {
                let mut metrics = BTreeMap::from([
                    ("speedup".to_owned(), serde_json::json!(v.speedup)),
                    ("speedup_interval".to_owned(), serde_json::json!(v.speedup_interval)),
                    ("rounds".to_owned(), serde_json::json!(self.rounds)),
                ]);
                for (name, value) in v.parts.iter().chain(&v.derived) {
                    metrics.insert(name.clone(), serde_json::json!(value));
                }
                for (name, value) in &v.counts {
                    metrics.insert(name.clone(), serde_json::json!(value));
                }
                CaseRecord {
                    name: format!("bench.{}.{}.{}", self.technique, self.bench, v.name),
                    outcome: ReportedOutcome::Pass,
                    reason: format!("{:.2}x over {}", v.speedup, v.baseline),
                    params: BTreeMap::new(),
                    metrics,
                    gpu_ms: Some(v.median_ms),
                    gpu_ms_repeats: v.gpu_ms.clone(),
                    wall_ms: per_variant,
                    evidence: Vec::new(),
                    attempts: 1,
                    diagnostics: Vec::new(),
                }
            })
            .collect()
    }
}

/// Benches that time whole passes need timestamp queries.
pub fn require_timestamps(gpu: &Gpu, bench: &str) -> Result<()> {
    if !gpu.has(wgpu::Features::TIMESTAMP_QUERY) {
        bail!(
            "the {bench} bench times passes with timestamp queries, which {} ({}) does not offer",
            gpu.description.name,
            gpu.description.backend
        );
    }
    Ok(())
}
