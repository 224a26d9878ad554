//! Plots (PNG): error against time (one point per measured configuration, one colour per method,
//! GPU time on x, error on y) and histories (one line per series over runs, marked points). Text uses the bundled DejaVu Sans (kit/fonts), so no system fonts
//! are needed.

use std::path::Path;

use anyhow::{Context, Result, anyhow};
use plotters::prelude::*;

/// One plotted point.
#[derive(Clone, Debug)]
pub struct PlotPoint {
    pub series: String,
    pub x: f64,
    pub y: f64,
}

static FONT: &[u8] = include_bytes!("../fonts/DejaVuSans.ttf");

fn register_font() -> Result<()> {
    static REGISTERED: std::sync::OnceLock<bool> = std::sync::OnceLock::new();
    let ok = *REGISTERED.get_or_init(|| plotters::style::register_font("sans-serif", FontStyle::Normal, FONT).is_ok());
    if ok { Ok(()) } else { Err(anyhow!("the bundled font could not be registered")) }
}

const PALETTE: [RGBColor; 8] = [
    RGBColor(31, 119, 180),
    RGBColor(255, 127, 14),
    RGBColor(44, 160, 44),
    RGBColor(214, 39, 40),
    RGBColor(148, 103, 189),
    RGBColor(140, 86, 75),
    RGBColor(227, 119, 194),
    RGBColor(127, 127, 127),
];

/// The chart every plot draws into: 960×640, white, title and axis labels, the given ranges.
type Chart<'a, 'b> = ChartContext<
    'a,
    BitMapBackend<'b>,
    Cartesian2d<plotters::coord::types::RangedCoordf64, plotters::coord::types::RangedCoordf64>,
>;

/// Sets up a chart, lets `draw` add the series (each with its legend entry), draws the legend and
/// writes the PNG.
fn chart_png(
    path: &Path,
    title: &str,
    (x_label, y_label): (&str, &str),
    (x_range, y_range): (std::ops::Range<f64>, std::ops::Range<f64>),
    draw: impl FnOnce(&mut Chart) -> Result<()>,
) -> Result<()> {
    register_font()?;
    let (width, height) = (960u32, 640u32);
    let mut pixels = vec![0u8; (width * height * 3) as usize];
    {
        let root = BitMapBackend::with_buffer(&mut pixels, (width, height)).into_drawing_area();
        root.fill(&WHITE).map_err(|e| anyhow!("{e}"))?;
        let mut chart = ChartBuilder::on(&root)
            .caption(title, ("sans-serif", 24))
            .margin(16)
            .x_label_area_size(48)
            .y_label_area_size(72)
            .build_cartesian_2d(x_range, y_range)
            .map_err(|e| anyhow!("{e}"))?;
        chart
            .configure_mesh()
            .x_desc(x_label)
            .y_desc(y_label)
            .label_style(("sans-serif", 14))
            .draw()
            .map_err(|e| anyhow!("{e}"))?;
        draw(&mut chart)?;
        chart
            .configure_series_labels()
            .background_style(WHITE.mix(0.85))
            .border_style(BLACK)
            .label_font(("sans-serif", 14))
            .draw()
            .map_err(|e| anyhow!("{e}"))?;
        root.present().map_err(|e| anyhow!("{e}"))?;
    }
    let image = image::RgbImage::from_raw(width, height, pixels).context("plot buffer size")?;
    image.save(path).with_context(|| format!("writing the plot {}", path.display()))
}

/// Writes a scatter plot of `points` to `path` (PNG, 960×640).
pub fn scatter(path: &Path, title: &str, x_label: &str, y_label: &str, points: &[PlotPoint]) -> Result<()> {
    let finite: Vec<&PlotPoint> = points.iter().filter(|p| p.x.is_finite() && p.y.is_finite()).collect();
    let max_x = finite.iter().map(|p| p.x).fold(0.0, f64::max).max(1e-3) * 1.05;
    let max_y = finite.iter().map(|p| p.y).fold(0.0, f64::max).max(1e-3) * 1.1;
    let mut series: Vec<&str> = Vec::new();
    for p in &finite {
        if !series.contains(&p.series.as_str()) {
            series.push(&p.series);
        }
    }
    chart_png(path, title, (x_label, y_label), (0.0..max_x, 0.0..max_y), |chart| {
        for (i, name) in series.iter().enumerate() {
            let colour = PALETTE[i % PALETTE.len()];
            let data: Vec<(f64, f64)> = finite.iter().filter(|p| p.series == *name).map(|p| (p.x, p.y)).collect();
            chart
                .draw_series(data.iter().map(|&(x, y)| Circle::new((x, y), 5, colour.filled())))
                .map_err(|e| anyhow!("{e}"))?
                .label(*name)
                .legend(move |(x, y)| Circle::new((x, y), 5, colour.filled()));
        }
        Ok(())
    })
}

/// One line of a history plot: its points (x, y) and the x of points to mark (a driver change).
#[derive(Clone, Debug)]
pub struct PlotLine {
    pub series: String,
    pub points: Vec<(f64, f64)>,
    pub marked: Vec<f64>,
}

/// Writes a line plot of `lines` to `path` (PNG, 960×640); marked points are drawn as crosses.
pub fn lines(path: &Path, title: &str, x_label: &str, y_label: &str, lines: &[PlotLine]) -> Result<()> {
    let all: Vec<(f64, f64)> =
        lines.iter().flat_map(|l| l.points.iter().copied()).filter(|(x, y)| x.is_finite() && y.is_finite()).collect();
    let (min_x, max_x) = all.iter().fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), &(x, _)| (a.min(x), b.max(x)));
    let (min_x, max_x) = if min_x.is_finite() { (min_x - 0.5, max_x + 0.5) } else { (0.0, 1.0) };
    let max_y = all.iter().map(|&(_, y)| y).fold(0.0, f64::max).max(1e-3) * 1.1;
    chart_png(path, title, (x_label, y_label), (min_x..max_x, 0.0..max_y), |chart| {
        for (i, line) in lines.iter().enumerate() {
            let colour = PALETTE[i % PALETTE.len()];
            let data: Vec<(f64, f64)> =
                line.points.iter().copied().filter(|(x, y)| x.is_finite() && y.is_finite()).collect();
            chart
                .draw_series(LineSeries::new(data.clone(), colour.stroke_width(2)))
                .map_err(|e| anyhow!("{e}"))?
                .label(line.series.as_str())
                .legend(move |(x, y)| PathElement::new(vec![(x, y), (x + 16, y)], colour.stroke_width(2)));
            chart
                .draw_series(data.iter().map(|&(x, y)| Circle::new((x, y), 3, colour.filled())))
                .map_err(|e| anyhow!("{e}"))?;
            let marked = data.iter().filter(|(x, _)| line.marked.contains(x));
            chart
                .draw_series(marked.map(|&(x, y)| Cross::new((x, y), 8, BLACK.stroke_width(2))))
                .map_err(|e| anyhow!("{e}"))?;
        }
        Ok(())
    })
}
