//! Plots (PNG): trade-offs of error against time (one line per method through its sweep, a
//! distinct colour and marker per method, the error on a log axis, the Pareto front marked) and
//! histories (one line per series over whole runs: spreads, failing runs, driver changes). Text uses the bundled DejaVu Sans
//! (kit/results/fonts), so no system fonts are needed.

use std::path::Path;

use anyhow::{Context, Result, anyhow};
use fragkit_report::plot_data::{PlotPoint, TradeoffPlot};
use plotters::prelude::*;

static FONT: &[u8] = include_bytes!("../fonts/DejaVuSans.ttf");

fn register_font() -> Result<()> {
    static REGISTERED: std::sync::OnceLock<bool> = std::sync::OnceLock::new();
    let ok = *REGISTERED.get_or_init(|| plotters::style::register_font("sans-serif", FontStyle::Normal, FONT).is_ok());
    if ok { Ok(()) } else { Err(anyhow!("the bundled font could not be registered")) }
}

/// Distinct colours (Tableau 10, then two darker ones); series beyond them repeat a colour with
/// another marker.
const PALETTE: [RGBColor; 12] = [
    RGBColor(31, 119, 180),
    RGBColor(255, 127, 14),
    RGBColor(44, 160, 44),
    RGBColor(214, 39, 40),
    RGBColor(148, 103, 189),
    RGBColor(140, 86, 75),
    RGBColor(227, 119, 194),
    RGBColor(127, 127, 127),
    RGBColor(188, 189, 34),
    RGBColor(23, 190, 207),
    RGBColor(0, 0, 128),
    RGBColor(128, 0, 0),
];

/// Marker shapes, cycled with a period coprime to the palette's.
const MARKERS: usize = 5;

/// The chart of a trade-off plot: linear time, log error.
type TradeoffChart<'a, 'b> =
    ChartContext<'a, BitMapBackend<'b>, Cartesian2d<plotters::coord::types::RangedCoordf64, LogCoord<f64>>>;

/// Draws `points` with marker `shape` (0..MARKERS) in `colour`, labelled `name` in the legend.
fn draw_markers<'a, 'b: 'a>(
    chart: &mut TradeoffChart<'a, 'b>,
    shape: usize,
    name: &str,
    points: &[(f64, f64)],
    colour: RGBColor,
) -> Result<()> {
    let style = colour.filled();
    let error = |e: plotters::drawing::DrawingAreaErrorKind<_>| anyhow!("{e}");
    let anno = match shape % MARKERS {
        0 => {
            let anno = chart.draw_series(points.iter().map(|&at| Circle::new(at, 5, style))).map_err(error)?;
            anno.label(name).legend(move |at| Circle::new(at, 5, style))
        }
        1 => {
            let anno = chart.draw_series(points.iter().map(|&at| TriangleMarker::new(at, 7, style))).map_err(error)?;
            anno.label(name).legend(move |at| TriangleMarker::new(at, 7, style))
        }
        2 => {
            let square = move |at| EmptyElement::at(at) + Rectangle::new([(-5, -5), (5, 5)], style);
            let anno = chart.draw_series(points.iter().map(|&at| square(at))).map_err(error)?;
            anno.label(name).legend(move |at| EmptyElement::at(at) + Rectangle::new([(-5, -5), (5, 5)], style))
        }
        3 => {
            let ring = colour.stroke_width(2);
            let anno = chart.draw_series(points.iter().map(|&at| Circle::new(at, 6, ring))).map_err(error)?;
            anno.label(name).legend(move |at| Circle::new(at, 6, ring))
        }
        _ => {
            let stroke = colour.stroke_width(3);
            let anno = chart.draw_series(points.iter().map(|&at| Cross::new(at, 6, stroke))).map_err(error)?;
            anno.label(name).legend(move |at| Cross::new(at, 6, stroke))
        }
    };
    let _ = anno;
    Ok(())
}

/// The points no other point beats in both time and error, by increasing time.
pub fn pareto_front(points: &[(f64, f64)]) -> Vec<(f64, f64)> {
    let mut sorted: Vec<(f64, f64)> = points.to_vec();
    sorted.sort_by(|a, b| a.0.total_cmp(&b.0).then(a.1.total_cmp(&b.1)));
    let mut front: Vec<(f64, f64)> = Vec::new();
    for p in sorted {
        if front.last().is_none_or(|last| p.1 < last.1) {
            front.push(p);
        }
    }
    front
}

/// Draws on a white 960×640 canvas with the kit's font and writes it to `path` as PNG.
fn png(
    path: &Path,
    draw: impl FnOnce(&DrawingArea<BitMapBackend, plotters::coord::Shift>) -> Result<()>,
) -> Result<()> {
    register_font()?;
    let (width, height) = (960u32, 640u32);
    let mut pixels = vec![0u8; (width * height * 3) as usize];
    {
        let root = BitMapBackend::with_buffer(&mut pixels, (width, height)).into_drawing_area();
        root.fill(&WHITE).map_err(|e| anyhow!("{e}"))?;
        draw(&root)?;
        root.present().map_err(|e| anyhow!("{e}"))?;
    }
    let image = image::RgbImage::from_raw(width, height, pixels).context("plot buffer size")?;
    image.save(path).with_context(|| format!("writing the plot {}", path.display()))
}

/// Writes a trade-off plot of `points` to `path` (PNG, 960×640): time on x (linear), error on y
/// (log: errors span decades; an error of 0 — exact — is drawn on the axis floor), one line per
/// series through its points in step order with a distinct colour and marker, and the Pareto
/// front (no point both faster and more exact) as a dashed black line.
pub fn tradeoff(plot: &TradeoffPlot) -> Result<()> {
    let TradeoffPlot { path, title, x_label, y_label, points } = plot;
    let finite: Vec<&PlotPoint> = points.iter().filter(|p| p.x.is_finite() && p.y.is_finite() && p.y >= 0.0).collect();
    let max_x = finite.iter().map(|p| p.x).fold(0.0, f64::max).max(1e-3) * 1.05;
    let smallest = finite.iter().map(|p| p.y).filter(|&y| y > 0.0).fold(f64::INFINITY, f64::min);
    // Whole decades, so that the log axis has labelled ticks at both ends.
    let floor = if smallest.is_finite() { 10f64.powf((smallest / 2.0).log10().floor()) } else { 1e-6 };
    let largest = finite.iter().map(|p| p.y).fold(floor, f64::max);
    let max_y = 10f64.powf((largest * 1.5).log10().ceil()).max(floor * 10.0);
    let shown = |y: f64| y.max(floor);
    let mut series: Vec<&str> = Vec::new();
    for p in &finite {
        if !series.contains(&p.series.as_str()) {
            series.push(&p.series);
        }
    }
    png(path, |root| {
        let mut chart = ChartBuilder::on(root)
            .caption(title, ("sans-serif", 22))
            .margin(16)
            .x_label_area_size(48)
            .y_label_area_size(80)
            .build_cartesian_2d(0.0..max_x, (floor * 0.999..max_y * 1.001).log_scale())
            .map_err(|e| anyhow!("{e}"))?;
        chart
            .configure_mesh()
            .x_desc(x_label)
            .y_desc(format!("{y_label} (log; 0 drawn at the floor)"))
            .y_labels(12)
            .y_label_formatter(&|y| format!("{y:.0e}"))
            .label_style(("sans-serif", 14))
            .draw()
            .map_err(|e| anyhow!("{e}"))?;
        for (i, name) in series.iter().enumerate() {
            let colour = PALETTE[i % PALETTE.len()];
            let mut data: Vec<(f64, f64, f64)> =
                finite.iter().filter(|p| p.series == *name).map(|p| (p.step, p.x, shown(p.y))).collect();
            data.sort_by(|a, b| a.0.total_cmp(&b.0));
            let line: Vec<(f64, f64)> = data.iter().map(|&(_, x, y)| (x, y)).collect();
            // Segment by segment: plotters' joins of a thick path that turns back overshoot.
            chart
                .draw_series(line.windows(2).map(|pair| PathElement::new(pair.to_vec(), colour.stroke_width(2))))
                .map_err(|e| anyhow!("{e}"))?;
            draw_markers(&mut chart, i, name, &line, colour)?;
        }
        let front = pareto_front(&finite.iter().map(|p| (p.x, shown(p.y))).collect::<Vec<_>>());
        chart
            .draw_series(DashedLineSeries::new(front, 6, 4, BLACK.stroke_width(1)))
            .map_err(|e| anyhow!("{e}"))?
            .label("Pareto front")
            .legend(|(x, y)| PathElement::new(vec![(x - 8, y), (x + 8, y)], BLACK.stroke_width(1)));
        // The legend goes in the corner with the fewest points.
        let (mid_x, mid_y) = (max_x / 2.0, (floor * max_y).sqrt());
        let in_corner = |right: bool, upper: bool| {
            finite.iter().filter(|p| (p.x > mid_x) == right && (shown(p.y) > mid_y) == upper).count()
        };
        let corner = [
            (in_corner(true, true), SeriesLabelPosition::UpperRight),
            (in_corner(false, true), SeriesLabelPosition::UpperLeft),
            (in_corner(true, false), SeriesLabelPosition::LowerRight),
            (in_corner(false, false), SeriesLabelPosition::LowerLeft),
        ]
        .into_iter()
        .min_by_key(|(count, _)| *count)
        .map_or(SeriesLabelPosition::UpperRight, |(_, position)| position);
        chart
            .configure_series_labels()
            .position(corner)
            .background_style(WHITE.mix(0.85))
            .border_style(BLACK)
            .label_font(("sans-serif", 13))
            .draw()
            .map_err(|e| anyhow!("{e}"))
    })
}

/// One run's point in a history plot.
#[derive(Clone, Debug)]
pub struct RunPoint {
    pub run: i64,
    pub value: f64,
    /// The lowest and highest value behind it (repeats, case runs): drawn as an error bar.
    pub spread: Option<(f64, f64)>,
    /// A case run of it failed: drawn as a red ring.
    pub failed: bool,
    /// Its driver differs from the series' previous run: drawn as a cross.
    pub driver_changed: bool,
}

/// One series (adapter) of a history plot.
#[derive(Clone, Debug)]
pub struct HistorySeries {
    pub name: String,
    pub points: Vec<RunPoint>,
}

/// Writes a history plot to `path` (PNG, 960×640): a line per series over whole run ids (ticks
/// only at integers), each run's spread as a bar, failing runs ringed in red, driver changes
/// crossed; the legend in headroom above the data, with entries for the marks that occur.
pub fn history(path: &Path, title: &str, y_label: &str, series: &[HistorySeries]) -> Result<()> {
    let points = || series.iter().flat_map(|s| s.points.iter());
    let (first, last) = points().fold((i64::MAX, i64::MIN), |(a, b), p| (a.min(p.run), b.max(p.run)));
    let (first, last) = if first <= last { (first, last) } else { (0, 1) };
    let top = points().map(|p| p.spread.map_or(p.value, |(_, high)| high.max(p.value))).fold(0.0, f64::max).max(1e-3);
    // Headroom for the legend: the data stays in the lower 70 %.
    let entries = series.len() + 2;
    let y_max = top / (1.0 - (0.08 * entries as f64).min(0.45));
    let x_range = (first as f64 - 0.5)..(last as f64 + 0.5);
    register_font()?;
    png(path, |root| {
        let mut chart = ChartBuilder::on(root)
            .caption(title, ("sans-serif", 22))
            .margin(16)
            .x_label_area_size(48)
            .y_label_area_size(72)
            .build_cartesian_2d(x_range, 0.0..y_max)
            .map_err(|e| anyhow!("{e}"))?;
        let runs = (last - first + 1) as usize;
        chart
            .configure_mesh()
            .x_desc("run")
            .y_desc(y_label)
            .x_labels(runs.min(24) + 1)
            .x_label_formatter(&|x| if x.fract().abs() < 1e-9 { format!("{x:.0}") } else { String::new() })
            .label_style(("sans-serif", 14))
            .draw()
            .map_err(|e| anyhow!("{e}"))?;
        for (i, line) in series.iter().enumerate() {
            let colour = PALETTE[i % PALETTE.len()];
            let data: Vec<(f64, f64)> = line.points.iter().map(|p| (p.run as f64, p.value)).collect();
            chart
                .draw_series(LineSeries::new(data.clone(), colour.stroke_width(2)))
                .map_err(|e| anyhow!("{e}"))?
                .label(line.name.as_str())
                .legend(move |(x, y)| PathElement::new(vec![(x, y), (x + 16, y)], colour.stroke_width(2)));
            chart
                .draw_series(line.points.iter().filter_map(|p| {
                    let x = p.run as f64;
                    p.spread.map(|(low, high)| PathElement::new(vec![(x, low), (x, high)], colour.stroke_width(3)))
                }))
                .map_err(|e| anyhow!("{e}"))?;
            chart
                .draw_series(data.iter().map(|&(x, y)| Circle::new((x, y), 3, colour.filled())))
                .map_err(|e| anyhow!("{e}"))?;
        }
        let failed: Vec<(f64, f64)> = points().filter(|p| p.failed).map(|p| (p.run as f64, p.value)).collect();
        if !failed.is_empty() {
            chart
                .draw_series(failed.iter().map(|&(x, y)| Circle::new((x, y), 8, RED.stroke_width(2))))
                .map_err(|e| anyhow!("{e}"))?
                .label("a case run failed")
                .legend(|(x, y)| Circle::new((x + 8, y), 5, RED.stroke_width(2)));
        }
        let changed: Vec<(f64, f64)> = points().filter(|p| p.driver_changed).map(|p| (p.run as f64, p.value)).collect();
        if !changed.is_empty() {
            chart
                .draw_series(changed.iter().map(|&(x, y)| Cross::new((x, y), 8, BLACK.stroke_width(2))))
                .map_err(|e| anyhow!("{e}"))?
                .label("driver changed")
                .legend(|(x, y)| Cross::new((x + 8, y), 5, BLACK.stroke_width(2)));
        }
        chart
            .configure_series_labels()
            .position(SeriesLabelPosition::UpperLeft)
            .background_style(WHITE.mix(0.9))
            .border_style(BLACK)
            .label_font(("sans-serif", 14))
            .draw()
            .map_err(|e| anyhow!("{e}"))
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_pareto_front_keeps_only_points_nothing_beats_in_both() {
        let points = [(3.0, 0.1), (1.0, 0.5), (2.0, 0.2), (2.5, 0.3), (4.0, 0.1), (5.0, 0.01)];
        assert_eq!(pareto_front(&points), [(1.0, 0.5), (2.0, 0.2), (3.0, 0.1), (5.0, 0.01)]);
    }

    #[test]
    fn a_history_plot_draws_spreads_failures_and_driver_changes() {
        let path = std::env::temp_dir().join(format!("fragkit-history-{}.png", std::process::id()));
        let point = |run, value, failed, driver_changed| RunPoint {
            run,
            value,
            spread: Some((value * 0.9, value * 1.2)),
            failed,
            driver_changed,
        };
        let series = [HistorySeries {
            name: "gpu (vulkan)".into(),
            points: vec![point(3, 1.0, false, false), point(4, 1.1, true, false), point(7, 0.9, false, true)],
        }];
        history(&path, "test", "gpu_ms", &series).unwrap();
        assert!(std::fs::read(&path).unwrap().starts_with(b"\x89PNG"));
    }

    #[test]
    fn a_tradeoff_plot_draws_lines_markers_and_exact_points() {
        let path = std::env::temp_dir().join(format!("fragkit-tradeoff-{}.png", std::process::id()));
        let point = |series: &str, step: f64, x: f64, y: f64| PlotPoint { series: series.into(), step, x, y };
        let points = [
            point("a", 2.0, 9.3, 0.0358),
            point("a", 4.0, 14.5, 0.03586),
            point("a", 6.0, 11.8, 0.03586),
            point("exact", 0.0, 14.0, 0.0),
        ];
        tradeoff(&TradeoffPlot {
            path: path.clone(),
            title: "test".into(),
            x_label: "time (ms)".into(),
            y_label: "error".into(),
            points: points.to_vec(),
        })
        .unwrap();
        assert!(std::fs::read(&path).unwrap().starts_with(b"\x89PNG"));
    }
}
