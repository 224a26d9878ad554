//! `fragkit report oit`: RMSE and FLIP against the exact composite versus GPU time, for every
//! method × sample count × accumulated frames × post-filter, as JSON, markdown and a PNG plot.

use std::path::Path;

use anyhow::{Context, Result};
use serde::Serialize;

use super::pictures::available_methods;
use super::reference::{exact_image, rmse};
use super::run::{Accumulation, run_method};
use super::scene::QuadScene;
use crate::caps::{common_sample_counts, matches_standard};
use crate::gpu::Gpu;
use crate::image_compare::flip_mean;
use crate::probe::sample_positions::measure;
use crate::tonemap::ldr_to_display;
use fragkit_report::AdapterDescription;
use fragkit_report::plot_data::{PlotPoint, TradeoffPlot};

#[derive(Clone, Debug)]
pub struct OitSweep {
    pub size: (u32, u32),
    pub frame_counts: Vec<u32>,
    pub seed: u32,
}

impl Default for OitSweep {
    fn default() -> Self {
        Self { size: (128, 128), frame_counts: vec![1, 4, 16, 64], seed: 1 }
    }
}

#[derive(Clone, Debug, Serialize)]
pub struct OitReportRow {
    pub scene: String,
    pub method: String,
    pub samples: u32,
    pub frames: u32,
    pub filtered: bool,
    pub gpu_ms: f64,
    pub rmse: f64,
    pub flip: f64,
    /// Depth peeling: layers peeled.
    pub layers: Option<u32>,
}

/// Sample counts at which a target really renders that many samples at the standard positions.
fn real_counts(gpu: &Gpu) -> Vec<(u32, Vec<[f32; 2]>)> {
    common_sample_counts(gpu)
        .into_iter()
        .filter_map(|n| {
            let measured = measure(gpu, n).ok()?;
            let positions = measured.agreed().filter(|p| matches_standard(n, p))?;
            Some((n, positions.iter().filter_map(|s| s.mid()).collect()))
        })
        .collect()
}

pub fn run_sweep(
    gpu: &Gpu,
    scene: &QuadScene,
    sweep: &OitSweep,
    mut progress: impl FnMut(&OitReportRow),
) -> Result<Vec<OitReportRow>> {
    let mut rows = Vec::new();
    for (samples, positions) in real_counts(gpu) {
        let exact = exact_image(scene, sweep.size, &positions);
        let exact_shown = ldr_to_display(sweep.size.0, sweep.size.1, &exact)?;
        let (methods, _) = available_methods(gpu, scene, samples.max(2));
        for method in methods {
            // Single-sampled methods run once, at 1x; coverage methods at every real count above 1.
            let coverage_method = method.is_stochastic() || method == super::run::Method::PlainCoverage;
            if coverage_method == (samples == 1) {
                continue;
            }
            let settings: Vec<(u32, bool)> = if method.is_stochastic() {
                sweep.frame_counts.iter().flat_map(|&f| [(f, false), (f, true)]).collect()
            } else {
                vec![(1, false)]
            };
            for (frames, filtered) in settings {
                let result = run_method(
                    gpu,
                    scene,
                    sweep.size,
                    samples,
                    &method,
                    Accumulation { frames, seed: sweep.seed, filtered },
                )?;
                let shown = ldr_to_display(sweep.size.0, sweep.size.1, &result.image)?;
                let row = OitReportRow {
                    scene: scene.name.clone(),
                    method: method.name().into(),
                    samples,
                    frames,
                    filtered,
                    gpu_ms: result.gpu_ms,
                    rmse: rmse(&result.image, &exact),
                    flip: f64::from(flip_mean(&shown, &exact_shown)?),
                    layers: result.layers,
                };
                progress(&row);
                rows.push(row);
            }
        }
    }
    Ok(rows)
}

/// Writes `oit_report.json` and `oit_report.md` into `dir`; returns the trade-off plot
/// `oit_report.png` for the results tools to draw.
pub fn write_report(dir: &Path, adapter: &AdapterDescription, rows: &[OitReportRow]) -> Result<TradeoffPlot> {
    std::fs::create_dir_all(dir).with_context(|| format!("creating {}", dir.display()))?;
    let json = serde_json::json!({"adapter": adapter, "rows": rows});
    std::fs::write(dir.join("oit_report.json"), serde_json::to_string_pretty(&json)?)
        .context("writing oit_report.json")?;
    let mut markdown = format!(
        "# OIT: error against GPU time\n\nAdapter: {} ({}). Reference: the exact composite at this adapter's sample \
         positions. GPU time: every pass of every accumulated frame.\n\n\
         | scene | method | samples | frames | filtered | GPU ms | RMSE | FLIP | layers |\n|---|---|---:|---:|---|---:|---:|---:|---:|\n",
        adapter.name, adapter.backend
    );
    for r in rows {
        markdown.push_str(&format!(
            "| {} | {} | {} | {} | {} | {:.2} | {:.5} | {:.4} | {} |\n",
            r.scene,
            r.method,
            r.samples,
            r.frames,
            r.filtered,
            r.gpu_ms,
            r.rmse,
            r.flip,
            r.layers.map_or("-".into(), |l| l.to_string())
        ));
    }
    std::fs::write(dir.join("oit_report.md"), markdown).context("writing oit_report.md")?;
    // One line per method (and sample count, filter) through its accumulated frames.
    let points: Vec<PlotPoint> = rows
        .iter()
        .map(|r| PlotPoint {
            series: format!("{} {}x{}", r.method, r.samples, if r.filtered { " +filter" } else { "" }),
            step: f64::from(r.frames),
            x: r.gpu_ms,
            y: r.rmse,
        })
        .collect();
    Ok(TradeoffPlot {
        path: dir.join("oit_report.png"),
        title: format!("OIT error vs GPU time — {}", adapter.name),
        x_label: "GPU time (ms); lines join the frames accumulated".to_owned(),
        y_label: "RMSE vs exact composite".to_owned(),
        points,
    })
}
