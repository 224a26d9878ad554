//! `fragkit report cbr`: full resolution, checkerboarding (forward and deferred, ASO and CSO, on
//! every path this adapter has) and a half-resolution bilinear upscale, on a static sequence and
//! moving ones: PSNR and FLIP of the last frame against full resolution, against the median GPU
//! time of a frame. Written as JSON, a markdown table and a PNG plot.

use std::path::Path;

use anyhow::{Context, Result};
use serde::Serialize;

use super::measure::{measure_against, read_hdr};
use super::plan::Shading;
use super::reconstruct::Detection;
use super::renderer::{Checkerboard, CheckerboardConfig, FullResolutionScene, HalfResolutionUpscale};
use super::sampling::{CheckerboardPath, Orientation};
use super::scene::{CheckerboardScene, Motion, textured_corridor};
use crate::gpu::Gpu;
use fragkit_report::AdapterDescription;
use fragkit_report::noise::median;
use fragkit_report::plot_data::{PlotPoint, TradeoffPlot};

#[derive(Clone, Debug)]
pub struct CbrSweep {
    pub size: (u32, u32),
    pub lights: u32,
    /// Frames a sequence runs; the first is warm-up, the last is measured.
    pub frames: u32,
    pub motions: Vec<Motion>,
    pub paths: Vec<CheckerboardPath>,
    pub seed: u32,
}

impl CbrSweep {
    /// The defaults on `gpu`: every path it has (offset passes everywhere, 2x where measured).
    pub fn for_adapter(gpu: &Gpu) -> Self {
        let mut paths = vec![CheckerboardPath::OffsetPasses];
        if CheckerboardPath::for_adapter(gpu) == CheckerboardPath::Msaa2x {
            paths.push(CheckerboardPath::Msaa2x);
        }
        Self {
            size: (320, 180),
            lights: 64,
            frames: 6,
            motions: vec![
                Motion::Static,
                Motion::Pan(glam::Vec2::new(2.0, 0.0)),
                Motion::Strafe(0.1),
                Motion::Object(0.15),
            ],
            paths,
            seed: 5,
        }
    }
}

#[derive(Clone, Debug, Serialize)]
pub struct CbrReportRow {
    pub sequence: String,
    /// `fullres`, `cbr` or `half_upscale`.
    pub method: String,
    pub path: String,
    pub shading: String,
    pub detection: String,
    /// Median GPU time of a frame after the first.
    pub gpu_ms: f64,
    pub psnr_db: f64,
    pub flip: f64,
}

/// Renders `frames` frames with `render`, timing all but the first; the median.
fn timed_frames(frames: u32, mut render: impl FnMut(u32) -> Result<f64>) -> Result<f64> {
    let mut times = Vec::new();
    for frame in 0..frames.max(2) {
        let ms = render(frame)?;
        if frame > 0 {
            times.push(ms);
        }
    }
    Ok(median(times))
}

fn row(sequence: &str, method: &str, gpu_ms: f64, error: (f64, f64)) -> CbrReportRow {
    CbrReportRow {
        sequence: sequence.to_owned(),
        method: method.to_owned(),
        path: "-".into(),
        shading: "-".into(),
        detection: "-".into(),
        gpu_ms,
        psnr_db: error.0,
        flip: error.1,
    }
}

fn sequence_rows(gpu: &Gpu, sweep: &CbrSweep, scene: &CheckerboardScene, sequence: &str) -> Result<Vec<CbrReportRow>> {
    let (screen, frames) = (sweep.size, sweep.frames.max(2));
    let mut fullres = FullResolutionScene::new(gpu, scene, screen)?;
    let fullres_ms = timed_frames(frames, |f| fullres.render(gpu, f))?;
    let reference = read_hdr(gpu, fullres.output())?;
    let error_of = |image: &[f32]| -> Result<(f64, f64)> {
        let (error, _) = measure_against(screen, image, &reference, 0)?;
        Ok((error.psnr_db, error.flip))
    };
    let mut rows = vec![CbrReportRow {
        path: Orientation::Upright.name().into(),
        shading: Shading::Forward.name().into(),
        ..row(sequence, "fullres", fullres_ms, (f64::INFINITY, 0.0))
    }];
    // Each checkerboarding's baseline is full resolution shaded the same way (deferred: the same
    // G-buffer and lighting at every pixel, so that its speed-up is not credited with deferred
    // shading's) and rasterised as its views are (turned for the offset passes).
    let others = [
        (Shading::Forward, Orientation::Turned),
        (Shading::Deferred, Orientation::Upright),
        (Shading::Deferred, Orientation::Turned),
    ];
    for (shading, orientation) in others {
        let mut frame = FullResolutionScene::shaded(gpu, scene, screen, shading, orientation)?;
        let ms = timed_frames(frames, |f| frame.render(gpu, f))?;
        rows.push(CbrReportRow {
            path: orientation.name().into(),
            shading: shading.name().into(),
            ..row(sequence, "fullres", ms, error_of(&read_hdr(gpu, frame.output())?)?)
        });
    }

    let mut upscale = HalfResolutionUpscale::new(gpu, scene, screen)?;
    let upscale_ms = timed_frames(frames, |f| upscale.render(gpu, f))?;
    rows.push(row(sequence, "half_upscale", upscale_ms, error_of(&read_hdr(gpu, &upscale.output)?)?));

    for &path in &sweep.paths {
        for shading in Shading::ALL {
            for detection in [Detection::Aso, Detection::DEFAULT_CSO] {
                let config = CheckerboardConfig { detection, ..CheckerboardConfig::new(screen, path, shading) };
                let mut checkerboard = Checkerboard::new(gpu, scene, config)?;
                let ms = timed_frames(frames, |f| Ok(checkerboard.render(gpu, f)?.gpu_ms))?;
                let error = error_of(&read_hdr(gpu, &checkerboard.reconstruction.colour)?)?;
                rows.push(CbrReportRow {
                    path: path.name().into(),
                    shading: shading.name().into(),
                    detection: detection.name().into(),
                    ..row(sequence, "cbr", ms, error)
                });
            }
        }
    }
    Ok(rows)
}

/// Runs the sweep: per sequence, full resolution first.
pub fn run_sweep(gpu: &Gpu, sweep: &CbrSweep, mut progress: impl FnMut(&str)) -> Result<Vec<CbrReportRow>> {
    let mut rows = Vec::new();
    for &motion in &sweep.motions {
        let sequence = motion.name();
        progress(&sequence);
        let scene = textured_corridor(sweep.seed, sweep.lights, motion);
        rows.extend(sequence_rows(gpu, sweep, &scene, &sequence)?);
    }
    Ok(rows)
}

/// Writes `cbr_report.json` and `cbr_report.md` into `dir`; returns the trade-off plot
/// `cbr_report.png` for the results tools to draw.
pub fn write_report(
    dir: &Path,
    adapter: &AdapterDescription,
    sweep: &CbrSweep,
    rows: &[CbrReportRow],
) -> Result<TradeoffPlot> {
    std::fs::create_dir_all(dir).with_context(|| format!("creating {}", dir.display()))?;
    let json = serde_json::json!({
        "adapter": adapter,
        "size": sweep.size,
        "lights": sweep.lights,
        "frames": sweep.frames,
        "rows": rows,
    });
    std::fs::write(dir.join("cbr_report.json"), serde_json::to_string_pretty(&json)?)
        .context("writing cbr_report.json")?;

    let mut markdown = format!(
        "# CBR: error against GPU time\n\nAdapter: {} ({}). {}x{}, {} lights, {} frames a sequence; the last \
         frame is compared with full resolution (display-referred PSNR, mean FLIP); GPU time is the median \
         frame after the first; each speed-up is over full resolution shaded the same way (forward or \
         deferred) and rasterised as the checkerboard's views are (path column: turned a quarter for the \
         offset passes, then turned back; upright for the 2x path and the upscale).\n\n\
         | sequence | method | path | shading | detection | GPU ms | speed-up | PSNR dB | FLIP |\n\
         |---|---|---|---|---|---:|---:|---:|---:|\n",
        adapter.name, adapter.backend, sweep.size.0, sweep.size.1, sweep.lights, sweep.frames
    );
    for row in rows {
        // The baseline shaded the same way (forward for the upscale, which renders forward).
        let shading = if row.method == "half_upscale" { Shading::Forward.name() } else { row.shading.as_str() };
        // ... and rasterised as its views are: turned for the offset passes, else upright.
        let path =
            [CheckerboardPath::OffsetPasses, CheckerboardPath::Msaa2x].into_iter().find(|p| p.name() == row.path);
        let orientation = path.map_or(Orientation::Upright, CheckerboardPath::orientation).name();
        let fullres = rows
            .iter()
            .find(|r| {
                r.method == "fullres" && r.sequence == row.sequence && r.shading == shading && r.path == orientation
            })
            .map_or(f64::NAN, |r| r.gpu_ms);
        markdown.push_str(&format!(
            "| {} | {} | {} | {} | {} | {:.3} | {:.2}x | {:.2} | {:.4} |\n",
            row.sequence,
            row.method,
            row.path,
            row.shading,
            row.detection,
            row.gpu_ms,
            fullres / row.gpu_ms,
            row.psnr_db,
            row.flip
        ));
    }
    std::fs::write(dir.join("cbr_report.md"), markdown).context("writing cbr_report.md")?;

    // One line per method through the sequences, in the sweep's order.
    let step = |sequence: &str| sweep.motions.iter().position(|m| m.name() == sequence).unwrap_or(0) as f64;
    let points: Vec<PlotPoint> = rows
        .iter()
        .map(|r| PlotPoint {
            series: match r.method.as_str() {
                "cbr" => format!("cbr {} {} {}", r.path, r.shading, r.detection),
                "fullres" => format!("full resolution {} {}", r.shading, r.path),
                other => other.replace('_', " "),
            },
            step: step(&r.sequence),
            x: r.gpu_ms,
            y: r.flip,
        })
        .collect();
    let order: Vec<String> = sweep.motions.iter().map(|m| m.name()).collect();
    Ok(TradeoffPlot {
        path: dir.join("cbr_report.png"),
        title: format!("CBR error vs GPU time — {}", adapter.name),
        x_label: format!("GPU time per frame (ms); lines join the sequences {}", order.join(" → ")),
        y_label: "mean FLIP vs full resolution".to_owned(),
        points,
    })
}
