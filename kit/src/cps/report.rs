//! `fragkit report cps`: error against GPU time over LOD policy × top level × light count ×
//! composite mode, with full-resolution deferred shading as the reference and the naive
//! alternative (every level lit in full, then composited) beside CPS. Written as JSON, a
//! markdown table and a PNG plot.

use std::path::Path;

use anyhow::{Context, Result};
use serde::Serialize;

use super::reference::seam_error;
use super::renderer::{CpsFrame, CpsRenderer};
use super::{CompositeMode, CpsConfig, LodPolicy};
use crate::deferred::DeferredInputs;
use crate::deferred::lighting::FullResolution;
use crate::gpu::Gpu;
use crate::image_compare::{compare, flip_mean};
use crate::query::GpuTimer;
use crate::readback::read_texture;
use crate::scene::corridor::corridor;
use crate::tonemap::to_display;
use fragkit_report::AdapterDescription;
use fragkit_report::noise::median;
use fragkit_report::plot_data::{PlotPoint, TradeoffPlot};

/// What to sweep.
#[derive(Clone, Debug)]
pub struct CpsSweep {
    pub size: (u32, u32),
    pub light_counts: Vec<u32>,
    pub max_levels: Vec<u32>,
    pub policies: Vec<LodPolicy>,
    /// Timed repeats per configuration; the median is reported.
    pub repeats: u32,
    pub seed: u32,
}

impl Default for CpsSweep {
    fn default() -> Self {
        Self {
            size: (320, 180),
            light_counts: vec![1, 16, 64, 200],
            max_levels: vec![2, 4, 6],
            policies: vec![LodPolicy::foveated(), LodPolicy::content()],
            repeats: 3,
            seed: 1,
        }
    }
}

/// One measured configuration.
#[derive(Clone, Debug, Serialize)]
pub struct CpsReportRow {
    /// `fullres`, `cps` or `naive`.
    pub method: String,
    pub policy: String,
    pub max_level: u32,
    pub lights: u32,
    pub composite: String,
    /// Median GPU time of the lighting work (G-buffer excluded, the same for every method).
    pub gpu_ms: f64,
    /// Of which building the LOD-present and stencil pyramids.
    pub pyramid_ms: f64,
    /// Of which the composite pass.
    pub composite_ms: f64,
    pub psnr_db: f64,
    pub flip: f64,
    /// Colour steps across level boundaries against full resolution's (see `seam_error`).
    pub seam_error: f64,
    /// Texels lit, all levels together (full resolution: every pixel).
    pub shaded_texels: u64,
}

fn texels_of(values: &[f32]) -> Vec<[f32; 4]> {
    values.chunks_exact(4).map(|c| [c[0], c[1], c[2], c[3]]).collect()
}

/// The sweep's scene with `lights` and full resolution's image of it: displayed, and its HDR
/// texels.
struct SweepReference {
    inputs: DeferredInputs,
    shown: image::RgbaImage,
    texels: Vec<[f32; 4]>,
}

impl SweepReference {
    /// Renders full resolution once (untimed; for the report, its warm-up).
    fn new(gpu: &Gpu, sweep: &CpsSweep, lights: u32, fullres: &FullResolution) -> Result<Self> {
        let inputs = DeferredInputs::new(gpu, &corridor(sweep.seed, lights), sweep.size)?;
        fullres.render(gpu, &inputs, &mut GpuTimer::new(gpu, 1))?;
        let hdr = read_texture(gpu, &fullres.target, wgpu::TextureAspect::All, 0)?.as_f16();
        Ok(Self { inputs, shown: to_display(sweep.size.0, sweep.size.1, &hdr)?, texels: texels_of(&hdr) })
    }

    fn frame(&self) -> CpsFrame<'_> {
        CpsFrame { gbuffer: &self.inputs.gbuffer, lights: &self.inputs.lights, eye: self.inputs.eye }
    }
}

/// A rendered composite's error against full resolution.
#[derive(Clone, Copy, Debug)]
pub struct Quality {
    pub psnr_db: f64,
    pub flip: f64,
    /// Colour steps across level boundaries against full resolution's (see `seam_error`).
    pub seam_error: f64,
}

fn quality(gpu: &Gpu, renderer: &CpsRenderer, reference: &SweepReference) -> Result<Quality> {
    let screen = renderer.plan.screen;
    let hdr = renderer.read_image(gpu)?;
    let shown = to_display(screen.0, screen.1, &hdr)?;
    let (difference, _) = compare(&shown, &reference.shown, 0)?;
    let lod = renderer.read_lod(gpu)?;
    Ok(Quality {
        psnr_db: difference.psnr_db,
        flip: f64::from(flip_mean(&shown, &reference.shown)?),
        seam_error: seam_error(screen, &lod, &texels_of(&hdr), &reference.texels),
    })
}

/// One composite's quality on one configuration of the sweep.
#[derive(Clone, Debug)]
pub struct CompositeQuality {
    pub policy: String,
    pub max_level: u32,
    pub lights: u32,
    pub composite: CompositeMode,
    pub quality: Quality,
}

/// The quality of each of `composites` on every light count × policy × top level of `sweep`
/// (untimed): what `cps.composite.seam_free_sweep` checks over the report's own sweep.
pub fn composite_quality(gpu: &Gpu, sweep: &CpsSweep, composites: &[CompositeMode]) -> Result<Vec<CompositeQuality>> {
    let fullres = FullResolution::new(gpu, sweep.size);
    let mut rows = Vec::new();
    for &lights in &sweep.light_counts {
        let reference = SweepReference::new(gpu, sweep, lights, &fullres)?;
        let frame = reference.frame();
        for policy in &sweep.policies {
            for &max_level in &sweep.max_levels {
                for &composite in composites {
                    let renderer =
                        CpsRenderer::new(gpu, sweep.size, CpsConfig::new(max_level, policy.clone(), composite))?;
                    renderer.render(gpu, &frame)?;
                    rows.push(CompositeQuality {
                        policy: policy.name().into(),
                        max_level,
                        lights,
                        composite,
                        quality: quality(gpu, &renderer, &reference)?,
                    });
                }
            }
        }
    }
    Ok(rows)
}

/// Renders one CPS configuration `repeats` times after a warm-up; its row.
fn measure_cps(
    gpu: &Gpu,
    sweep: &CpsSweep,
    config: CpsConfig,
    reference: &SweepReference,
    lights: u32,
) -> Result<CpsReportRow> {
    let frame = reference.frame();
    let renderer = CpsRenderer::new(gpu, sweep.size, config.clone())?;
    renderer.render(gpu, &frame)?;
    let mut times = Vec::new();
    let mut pyramid_times = Vec::new();
    let mut composite_times = Vec::new();
    let mut shaded = 0;
    for _ in 0..sweep.repeats.max(1) {
        let output = renderer.render(gpu, &frame)?;
        times.push(output.gpu_ms(""));
        pyramid_times.push(output.gpu_ms("pyramid"));
        composite_times.push(output.gpu_ms("composite"));
        shaded = output.shaded_texels.iter().sum();
    }
    let quality = quality(gpu, &renderer, reference)?;
    Ok(CpsReportRow {
        method: if config.shade_every_texel { "naive" } else { "cps" }.into(),
        policy: config.policy.name().into(),
        max_level: config.max_level,
        lights,
        composite: config.composite.name().into(),
        gpu_ms: median(times),
        pyramid_ms: median(pyramid_times),
        composite_ms: median(composite_times),
        psnr_db: quality.psnr_db,
        flip: quality.flip,
        seam_error: quality.seam_error,
        shaded_texels: shaded,
    })
}

/// Runs the sweep; one row per configuration, full resolution first for each light count.
pub fn run_sweep(gpu: &Gpu, sweep: &CpsSweep, mut progress: impl FnMut(&CpsReportRow)) -> Result<Vec<CpsReportRow>> {
    let mut rows = Vec::new();
    let fullres = FullResolution::new(gpu, sweep.size);
    for &lights in &sweep.light_counts {
        // One untimed warm-up (which also makes the reference), then the repeats.
        let reference = SweepReference::new(gpu, sweep, lights, &fullres)?;
        let mut times = Vec::new();
        for _ in 0..sweep.repeats.max(1) {
            let mut timer = GpuTimer::new(gpu, 1);
            fullres.render(gpu, &reference.inputs, &mut timer)?;
            times.push(timer.read(gpu)?.iter().map(|t| t.ms).sum::<f64>());
        }
        let row = CpsReportRow {
            method: "fullres".into(),
            policy: "-".into(),
            max_level: 0,
            lights,
            composite: "-".into(),
            gpu_ms: median(times),
            pyramid_ms: 0.0,
            composite_ms: 0.0,
            psnr_db: f64::INFINITY,
            flip: 0.0,
            seam_error: 0.0,
            shaded_texels: u64::from(sweep.size.0 * sweep.size.1),
        };
        progress(&row);
        rows.push(row);
        for policy in &sweep.policies {
            for &max_level in &sweep.max_levels {
                let configs = CompositeMode::ALL
                    .into_iter()
                    .map(|mode| CpsConfig::new(max_level, policy.clone(), mode))
                    .chain(std::iter::once(CpsConfig::new(max_level, policy.clone(), CompositeMode::Nearest).naive()));
                for config in configs {
                    let row = measure_cps(gpu, sweep, config, &reference, lights)?;
                    progress(&row);
                    rows.push(row);
                }
            }
        }
    }
    Ok(rows)
}

/// The three composites side by side, row by row of the sweep: seam error, FLIP and the composite
/// pass's time; and where seam-free is not at or below 4-neighbour, which of them it loses.
fn composites_side_by_side(rows: &[CpsReportRow]) -> String {
    let mut lines = Vec::new();
    let mut losses = 0;
    for sf in rows.iter().filter(|r| r.method == "cps" && r.composite == "seam_free") {
        let of = |composite: &str| {
            rows.iter().find(|r| {
                r.method == "cps"
                    && r.composite == composite
                    && (r.policy.as_str(), r.max_level, r.lights) == (sf.policy.as_str(), sf.max_level, sf.lights)
            })
        };
        let (Some(fn4), Some(nearest)) = (of("four_neighbour"), of("nearest")) else {
            continue;
        };
        let mut lost = Vec::new();
        if sf.seam_error > fn4.seam_error {
            lost.push("seam error");
        }
        if sf.flip > fn4.flip {
            lost.push("FLIP");
        }
        if !lost.is_empty() {
            losses += 1;
        }
        let verdict =
            if lost.is_empty() { "at or below".to_owned() } else { format!("worse in {}", lost.join(" and ")) };
        lines.push(format!(
            "| {} | {} | {} | {:.5} / {:.5} / {:.5} | {:.4} / {:.4} / {:.4} | {:.2} / {:.2} / {:.2} | {verdict} |",
            sf.policy,
            sf.max_level,
            sf.lights,
            sf.seam_error,
            fn4.seam_error,
            nearest.seam_error,
            sf.flip,
            fn4.flip,
            nearest.flip,
            sf.composite_ms,
            fn4.composite_ms,
            nearest.composite_ms
        ));
    }
    format!(
        "\n## The three composites\n\nSeam-free is linear over the three shading samples around each pixel, each \
         where it was lit: shading linear in screen position comes out exact whatever the levels \
         (`cps.composite.linear_precision`), so a level boundary adds no step the shading does not have. \
         It is meant to be at or below the original 4-neighbour interpolation in seam error and FLIP; \
         here it is at or below in {} of {} rows.\n\n\
         | policy | top level | lights | seam error (seam-free / 4-neighbour / nearest) | FLIP (same order) | composite ms (same order) | seam-free vs 4-neighbour |\n\
         |---|---:|---:|---:|---:|---:|---|\n{}\n",
        lines.len() - losses,
        lines.len(),
        lines.join("\n")
    )
}

/// Writes `cps_report.json` and `cps_report.md` into `dir`; returns the trade-off plot
/// `cps_report.png` for the results tools to draw.
pub fn write_report(dir: &Path, adapter: &AdapterDescription, rows: &[CpsReportRow]) -> Result<TradeoffPlot> {
    std::fs::create_dir_all(dir).with_context(|| format!("creating {}", dir.display()))?;
    let json = serde_json::json!({"adapter": adapter, "rows": rows});
    std::fs::write(dir.join("cps_report.json"), serde_json::to_string_pretty(&json)?)
        .context("writing cps_report.json")?;

    let mut markdown = format!(
        "# CPS: error against GPU time\n\nAdapter: {} ({}). Reference: full-resolution deferred shading. \
         GPU time: lighting work only (the G-buffer is the same for every method), median of repeats.\n\n\
         | lights | method | policy | max level | composite | GPU ms | pyramids ms | composite ms | speed-up | PSNR dB | FLIP | seam error | texels lit |\n\
         |---:|---|---|---:|---|---:|---:|---:|---:|---:|---:|---:|---:|\n",
        adapter.name, adapter.backend
    );
    for row in rows {
        let fullres_ms =
            rows.iter().find(|r| r.method == "fullres" && r.lights == row.lights).map_or(f64::NAN, |r| r.gpu_ms);
        markdown.push_str(&format!(
            "| {} | {} | {} | {} | {} | {:.2} | {:.2} | {:.2} | {:.2}x | {:.2} | {:.4} | {:.5} | {} |\n",
            row.lights,
            row.method,
            row.policy,
            row.max_level,
            row.composite,
            row.gpu_ms,
            row.pyramid_ms,
            row.composite_ms,
            fullres_ms / row.gpu_ms,
            row.psnr_db,
            row.flip,
            row.seam_error,
            row.shaded_texels
        ));
    }
    markdown.push_str(&composites_side_by_side(rows));
    std::fs::write(dir.join("cps_report.md"), markdown).context("writing cps_report.md")?;

    // One line per method through its top levels, at the sweep's largest light count (the
    // table has every count).
    let lights = rows.iter().map(|r| r.lights).max().unwrap_or(0);
    let points: Vec<PlotPoint> = rows
        .iter()
        .filter(|r| r.lights == lights)
        .map(|r| PlotPoint {
            series: match r.method.as_str() {
                "fullres" => "full resolution".to_owned(),
                method => format!("{method} {} ({})", r.composite, r.policy),
            },
            step: f64::from(r.max_level),
            x: r.gpu_ms,
            y: r.flip,
        })
        .collect();
    Ok(TradeoffPlot {
        path: dir.join("cps_report.png"),
        title: format!("CPS error vs GPU time — {}, {lights} lights", adapter.name),
        x_label: "GPU time of the lighting work (ms); lines join the top levels".to_owned(),
        y_label: "mean FLIP vs full resolution".to_owned(),
        points,
    })
}
