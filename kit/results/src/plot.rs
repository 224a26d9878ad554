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

/// Series `i`'s colour: the palette's, repeated past its end.
fn colour(i: usize) -> RGBColor {
    PALETTE[i % PALETTE.len()]
}

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

/// A plot's canvas.
const CANVAS: (u32, u32) = (960, 640);

/// Draws on a white canvas with the kit's font.
fn render(
    draw: impl FnOnce(&DrawingArea<BitMapBackend, plotters::coord::Shift>) -> Result<()>,
) -> Result<image::RgbImage> {
    register_font()?;
    let (width, height) = CANVAS;
    let mut pixels = vec![0u8; (width * height * 3) as usize];
    {
        let root = BitMapBackend::with_buffer(&mut pixels, (width, height)).into_drawing_area();
        root.fill(&WHITE).map_err(|e| anyhow!("{e}"))?;
        draw(&root)?;
        root.present().map_err(|e| anyhow!("{e}"))?;
    }
    image::RgbImage::from_raw(width, height, pixels).context("plot buffer size")
}

/// Draws as [`render`] does and writes the picture to `path` as PNG.
fn png(
    path: &Path,
    draw: impl FnOnce(&DrawingArea<BitMapBackend, plotters::coord::Shift>) -> Result<()>,
) -> Result<()> {
    render(draw)?.save(path).with_context(|| format!("writing the plot {}", path.display()))
}

/// The points a trade-off plot can draw: finite, with an error of 0 or more.
fn drawable(points: &[PlotPoint]) -> Vec<&PlotPoint> {
    points.iter().filter(|p| p.x.is_finite() && p.y.is_finite() && p.y >= 0.0).collect()
}

/// A trade-off plot's axes: time from 0 to 5 % past the slowest point; error on whole decades,
/// from below half the smallest error above 0 (where exact points, error 0, are drawn) to past
/// 1.5 times the largest, at least one decade.
#[derive(Clone, Copy, Debug, PartialEq)]
struct TradeoffAxes {
    max_x: f64,
    floor: f64,
    max_y: f64,
}

impl TradeoffAxes {
    fn of(points: &[&PlotPoint]) -> Self {
        let max_x = points.iter().map(|p| p.x).fold(0.0, f64::max).max(1e-3) * 1.05;
        let smallest = points.iter().map(|p| p.y).filter(|&y| y > 0.0).fold(f64::INFINITY, f64::min);
        let floor = if smallest.is_finite() { 10f64.powf((smallest / 2.0).log10().floor()) } else { 1e-6 };
        let largest = points.iter().map(|p| p.y).fold(floor, f64::max);
        // At least a decade: the largest error is at least twice the floor.
        let max_y = 10f64.powf((largest * 1.5).log10().ceil());
        Self { max_x, floor, max_y }
    }

    /// The error axis' range: the decades, widened by 0.1 % so that points on them are drawn.
    fn error_range(&self) -> std::ops::Range<f64> {
        self.floor * 0.999..self.max_y * 1.001
    }

    /// Where an error is drawn: 0 on the floor.
    fn shown(&self, y: f64) -> f64 {
        y.max(self.floor)
    }

    /// The corner with the fewest points, where the legend goes (ties: upper right first, then
    /// upper left, lower right, lower left).
    fn emptiest_corner(&self, points: &[(f64, f64)]) -> SeriesLabelPosition {
        let (mid_x, mid_y) = (self.max_x / 2.0, (self.floor * self.max_y).sqrt());
        let in_corner = |right: bool, upper: bool| {
            points.iter().filter(|&&(x, y)| (x > mid_x) == right && (self.shown(y) > mid_y) == upper).count()
        };
        [
            (in_corner(true, true), SeriesLabelPosition::UpperRight),
            (in_corner(false, true), SeriesLabelPosition::UpperLeft),
            (in_corner(true, false), SeriesLabelPosition::LowerRight),
            (in_corner(false, false), SeriesLabelPosition::LowerLeft),
        ]
        .into_iter()
        .min_by_key(|(count, _)| *count)
        .map_or(SeriesLabelPosition::UpperRight, |(_, position)| position)
    }
}

/// Each series (in order of first appearance) and its line: its points in step order, errors as
/// `axes` shows them.
fn series_lines<'a>(points: &[&'a PlotPoint], axes: &TradeoffAxes) -> Vec<(&'a str, Vec<(f64, f64)>)> {
    let mut names: Vec<&str> = Vec::new();
    for p in points {
        if !names.contains(&p.series.as_str()) {
            names.push(&p.series);
        }
    }
    names
        .into_iter()
        .map(|name| {
            let mut data: Vec<(f64, f64, f64)> =
                points.iter().filter(|p| p.series == name).map(|p| (p.step, p.x, axes.shown(p.y))).collect();
            data.sort_by(|a, b| a.0.total_cmp(&b.0));
            (name, data.iter().map(|&(_, x, y)| (x, y)).collect())
        })
        .collect()
}

/// Writes a trade-off plot of `points` to `path` (PNG, 960×640): time on x (linear), error on y
/// (log: errors span decades; an error of 0 — exact — is drawn on the axis floor), one line per
/// series through its points in step order with a distinct colour and marker, and the Pareto
/// front (no point both faster and more exact) as a dashed black line.
pub fn tradeoff(plot: &TradeoffPlot) -> Result<()> {
    let TradeoffPlot { path, title, x_label, y_label, points } = plot;
    let finite = drawable(points);
    let axes = TradeoffAxes::of(&finite);
    let lines = series_lines(&finite, &axes);
    png(path, |root| {
        let mut chart = ChartBuilder::on(root)
            .caption(title, ("sans-serif", 22))
            .margin(16)
            .x_label_area_size(48)
            .y_label_area_size(80)
            .build_cartesian_2d(0.0..axes.max_x, axes.error_range().log_scale())
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
        for (i, (name, line)) in lines.iter().enumerate() {
            // Segment by segment: plotters' joins of a thick path that turns back overshoot.
            chart
                .draw_series(line.windows(2).map(|pair| PathElement::new(pair.to_vec(), colour(i).stroke_width(2))))
                .map_err(|e| anyhow!("{e}"))?;
            draw_markers(&mut chart, i, name, line, colour(i))?;
        }
        let drawn: Vec<(f64, f64)> = finite.iter().map(|p| (p.x, axes.shown(p.y))).collect();
        let front = pareto_front(&drawn);
        chart
            .draw_series(DashedLineSeries::new(front, 6, 4, BLACK.stroke_width(1)))
            .map_err(|e| anyhow!("{e}"))?
            .label("Pareto front")
            .legend(|(x, y)| PathElement::new(vec![(x - 8, y), (x + 8, y)], BLACK.stroke_width(1)));
        // The legend goes in the corner with the fewest points.
        let corner = axes.emptiest_corner(&drawn);
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

/// A history plot's axes: the runs from the first to the last (0 to 1 where there are none), and
/// values from 0 to a top that keeps the data in the lower part, below the legend's rows (one per
/// series and two for the marks, 8 % each, at most 45 % in all).
#[derive(Clone, Copy, Debug, PartialEq)]
struct HistoryAxes {
    first: i64,
    last: i64,
    y_max: f64,
}

impl HistoryAxes {
    fn of(series: &[HistorySeries]) -> Self {
        let points = || series.iter().flat_map(|s| s.points.iter());
        let (first, last) = points().fold((i64::MAX, i64::MIN), |(a, b), p| (a.min(p.run), b.max(p.run)));
        let (first, last) = if first <= last { (first, last) } else { (0, 1) };
        let top =
            points().map(|p| p.spread.map_or(p.value, |(_, high)| high.max(p.value))).fold(0.0, f64::max).max(1e-3);
        let entries = series.len() + 2;
        Self { first, last, y_max: top / (1.0 - (0.08 * entries as f64).min(0.45)) }
    }

    /// The run axis: half a run beyond the first and the last, so that their points are inside.
    fn run_range(&self) -> std::ops::Range<f64> {
        (self.first as f64 - 0.5)..(self.last as f64 + 0.5)
    }

    /// Ticks on the run axis: one a run, at most 25.
    fn x_labels(&self) -> usize {
        let runs = (self.last - self.first + 1) as usize;
        runs.min(24) + 1
    }
}

/// A run axis tick's label: whole run ids only.
fn run_label(x: &f64) -> String {
    if x.fract().abs() < 1e-9 { format!("{x:.0}") } else { String::new() }
}

/// Where a mark's glyph sits in its legend row: the middle of the 16 px a series' line takes.
fn mark_in_legend((x, y): (i32, i32)) -> (i32, i32) {
    (x + 8, y)
}

/// The (run, value) points of runs that carry a mark.
type MarkedRuns = Vec<(f64, f64)>;

/// The points of runs where a case run failed, and of runs whose driver changed.
fn marked_runs(series: &[HistorySeries]) -> (MarkedRuns, MarkedRuns) {
    let points = || series.iter().flat_map(|s| s.points.iter());
    let at = |p: &RunPoint| (p.run as f64, p.value);
    (points().filter(|p| p.failed).map(at).collect(), points().filter(|p| p.driver_changed).map(at).collect())
}

/// Writes a history plot to `path` (PNG, 960×640): a line per series over whole run ids (ticks
/// only at integers), each run's spread as a bar, failing runs ringed in red, driver changes
/// crossed; the legend in headroom above the data, with entries for the marks that occur.
pub fn history(path: &Path, title: &str, y_label: &str, series: &[HistorySeries]) -> Result<()> {
    let axes = HistoryAxes::of(series);
    png(path, |root| {
        let mut chart = ChartBuilder::on(root)
            .caption(title, ("sans-serif", 22))
            .margin(16)
            .x_label_area_size(48)
            .y_label_area_size(72)
            .build_cartesian_2d(axes.run_range(), 0.0..axes.y_max)
            .map_err(|e| anyhow!("{e}"))?;
        chart
            .configure_mesh()
            .x_desc("run")
            .y_desc(y_label)
            .x_labels(axes.x_labels())
            .x_label_formatter(&run_label)
            .label_style(("sans-serif", 14))
            .draw()
            .map_err(|e| anyhow!("{e}"))?;
        for (i, line) in series.iter().enumerate() {
            let colour = colour(i);
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
        let (failed, changed) = marked_runs(series);
        if !failed.is_empty() {
            chart
                .draw_series(failed.iter().map(|&(x, y)| Circle::new((x, y), 8, RED.stroke_width(2))))
                .map_err(|e| anyhow!("{e}"))?
                .label("a case run failed")
                .legend(|at| Circle::new(mark_in_legend(at), 5, RED.stroke_width(2)));
        }
        if !changed.is_empty() {
            chart
                .draw_series(changed.iter().map(|&(x, y)| Cross::new((x, y), 8, BLACK.stroke_width(2))))
                .map_err(|e| anyhow!("{e}"))?
                .label("driver changed")
                .legend(|at| Cross::new(mark_in_legend(at), 5, BLACK.stroke_width(2)));
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

    fn point(series: &str, step: f64, x: f64, y: f64) -> PlotPoint {
        PlotPoint { series: series.into(), step, x, y }
    }

    #[test]
    fn a_tradeoff_draws_finite_points_on_whole_decades_with_exact_ones_on_the_floor() {
        let points = [
            point("a", 2.0, 4.0, 0.5),
            point("b", 1.0, 10.0, 0.03),
            point("a", 1.0, 2.0, 0.0),
            point("a", 3.0, f64::NAN, 0.1),
            point("b", 2.0, 3.0, f64::INFINITY),
            point("b", 3.0, 1.0, -0.1),
        ];
        let finite = drawable(&points);
        assert_eq!(finite.len(), 3);
        let axes = TradeoffAxes::of(&finite);
        // 5 % past the slowest; the floor below half the smallest error (0.015: 0.01), the top
        // past 1.5 times the largest (0.75: 1).
        assert_eq!(axes, TradeoffAxes { max_x: 10.5, floor: 0.01, max_y: 1.0 });
        assert_eq!((axes.shown(0.0), axes.shown(0.02)), (0.01, 0.02));
        assert_eq!(axes.error_range(), 0.01 * 0.999..1.001);
        // Series in order of first appearance, each line in step order.
        assert_eq!(series_lines(&finite, &axes), [("a", vec![(2.0, 0.01), (4.0, 0.5)]), ("b", vec![(10.0, 0.03)])]);
        // Only exact points (or none): a decade above the default floor.
        let exact = [point("a", 1.0, 0.0, 0.0)];
        assert_eq!(TradeoffAxes::of(&drawable(&exact)), TradeoffAxes { max_x: 1e-3 * 1.05, floor: 1e-6, max_y: 1e-5 });
        // An error of 0.06: floor 0.01 (half is 0.03), top 0.1 (1.5 times is 0.09).
        let one = [point("a", 1.0, 1.0, 0.06)];
        assert_eq!(TradeoffAxes::of(&drawable(&one)), TradeoffAxes { max_x: 1.05, floor: 0.01, max_y: 0.1 });
        // An error of 0.015: half of it lies a decade lower, so the floor does too.
        let low = [point("a", 1.0, 1.0, 0.015)];
        assert_eq!(TradeoffAxes::of(&drawable(&low)).floor, 0.001);
    }

    #[test]
    fn the_legend_takes_the_corner_with_the_fewest_points() {
        let axes = TradeoffAxes { max_x: 10.0, floor: 0.01, max_y: 100.0 };
        // The middle: x 5, error 1 (the log axis' centre).
        let (left, right, low, high) = (1.0, 9.0, 0.1, 10.0);
        let position = |points: &[(f64, f64)]| format!("{:?}", axes.emptiest_corner(points));
        let corner = |expected: SeriesLabelPosition| format!("{expected:?}");
        assert_eq!(position(&[]), corner(SeriesLabelPosition::UpperRight));
        assert_eq!(position(&[(right, high)]), corner(SeriesLabelPosition::UpperLeft));
        assert_eq!(position(&[(right, high), (left, high)]), corner(SeriesLabelPosition::LowerRight));
        assert_eq!(position(&[(right, high), (left, high), (right, low)]), corner(SeriesLabelPosition::LowerLeft));
        assert_eq!(position(&[(left, low), (left, high), (right, low)]), corner(SeriesLabelPosition::UpperRight));
        // An exact point (error 0) counts where it is drawn, on the floor: low.
        assert_eq!(
            position(&[(right, high), (left, high), (left, 0.0), (left, 0.0)]),
            corner(SeriesLabelPosition::LowerRight)
        );
        // The middle itself counts as left and low: with one point in each other corner, the
        // upper right is the first of the emptiest.
        assert_eq!(
            position(&[(5.0, 1.0), (right, high), (right, low), (left, high)]),
            corner(SeriesLabelPosition::UpperRight)
        );
    }

    #[test]
    fn colours_repeat_past_the_palette_and_each_of_five_markers_differs() {
        assert_eq!((colour(0), colour(11), colour(12), colour(13)), (PALETTE[0], PALETTE[11], PALETTE[0], PALETTE[1]));
        // One marker of each shape in the plot's right half and its legend entry in the left: the
        // pixels of its colour, the marker's (each from its top-left corner) — and the legend
        // shows the very same glyph.
        let drawn = |shape: usize| {
            let image = render(|root| {
                let mut chart = ChartBuilder::on(root)
                    .build_cartesian_2d(0.0..2.0, (0.1..10.0).log_scale())
                    .map_err(|e| anyhow!("{e}"))?;
                draw_markers(&mut chart, shape, "m", &[(1.5, 1.0)], PALETTE[0])?;
                chart
                    .configure_series_labels()
                    .position(SeriesLabelPosition::UpperLeft)
                    .draw()
                    .map_err(|e| anyhow!("{e}"))
            })
            .unwrap();
            let pixels: Vec<(u32, u32)> =
                image.enumerate_pixels().filter(|(_, _, p)| p.0 == [31, 119, 180]).map(|(x, y, _)| (x, y)).collect();
            let from_corner = |half: Vec<(u32, u32)>| {
                let (x0, y0) = (half.iter().map(|p| p.0).min().unwrap(), half.iter().map(|p| p.1).min().unwrap());
                let mut glyph: Vec<(u32, u32)> = half.iter().map(|&(x, y)| (x - x0, y - y0)).collect();
                glyph.sort_unstable();
                glyph
            };
            let (legend, marker): (Vec<_>, Vec<_>) = pixels.into_iter().partition(|p| p.0 < CANVAS.0 / 2);
            let (legend, marker) = (from_corner(legend), from_corner(marker));
            assert_eq!(legend, marker, "marker {shape}: the legend shows another glyph");
            marker
        };
        let shapes: Vec<Vec<(u32, u32)>> = (0..=MARKERS).map(drawn).collect();
        assert!(shapes.iter().all(|pixels| !pixels.is_empty()));
        for i in 0..MARKERS {
            for j in 0..i {
                assert_ne!(shapes[i], shapes[j], "markers {j} and {i} look alike");
            }
        }
        assert_eq!(shapes[MARKERS], shapes[0], "the sixth series takes the first marker again");
    }

    fn run_point(run: i64, value: f64, spread: Option<(f64, f64)>, failed: bool, driver_changed: bool) -> RunPoint {
        RunPoint { run, value, spread, failed, driver_changed }
    }

    #[test]
    fn a_history_spans_its_runs_and_leaves_headroom_for_one_legend_row_a_series_and_two_marks() {
        let series = |points: Vec<RunPoint>| HistorySeries { name: "s".into(), points };
        let one = [
            series(vec![run_point(7, 2.0, Some((1.0, 4.0)), false, false)]),
            series(vec![run_point(3, 5.0, None, false, false)]),
        ];
        // Four rows of 8 %: the top at 5 / 0.68.
        assert_eq!(HistoryAxes::of(&one), HistoryAxes { first: 3, last: 7, y_max: 5.0 / (1.0 - 0.08 * 4.0) });
        // A spread's high end counts; the headroom stops at 45 %.
        let many: Vec<HistorySeries> =
            (0..6).map(|i| series(vec![run_point(i, 1.0, Some((0.5, 2.0)), false, false)])).collect();
        assert_eq!(HistoryAxes::of(&many), HistoryAxes { first: 0, last: 5, y_max: 2.0 / 0.55 });
        // No runs: runs 0 to 1 and a small top.
        assert_eq!(HistoryAxes::of(&[]), HistoryAxes { first: 0, last: 1, y_max: 1e-3 / (1.0 - 0.16) });
        assert_eq!(HistoryAxes::of(&one).x_labels(), 6);
        assert_eq!(HistoryAxes::of(&one).run_range(), 2.5..7.5);
        assert_eq!(HistoryAxes { first: 1, last: 40, y_max: 1.0 }.x_labels(), 25);
        assert_eq!(
            (run_label(&3.0), run_label(&3.5), run_label(&-2.0)),
            ("3".to_owned(), String::new(), "-2".to_owned())
        );
        // A tick a billionth off a run is no run's (1e-9's fraction is exactly 1e-9).
        assert_eq!((run_label(&1e-9), run_label(&0.5e-9)), (String::new(), "0".to_owned()));
        let marked = [series(vec![
            run_point(1, 1.0, None, true, false),
            run_point(2, 3.0, None, false, true),
            run_point(4, 2.0, None, true, true),
        ])];
        assert_eq!(marked_runs(&marked), (vec![(1.0, 1.0), (4.0, 2.0)], vec![(2.0, 3.0), (4.0, 2.0)]));
    }

    #[test]
    fn a_history_legend_has_a_row_for_each_mark_that_occurs_and_no_other() {
        let path = std::env::temp_dir().join(format!("fragkit-history-marks-{}.png", std::process::id()));
        let dark = |failed: bool, driver_changed: bool| {
            let points = vec![run_point(1, 1.0, None, false, false), run_point(2, 1.0, None, failed, driver_changed)];
            history(&path, "t", "ms", &[HistorySeries { name: "s".into(), points }]).unwrap();
            let image = image::open(&path).unwrap().to_rgb8();
            image.pixels().filter(|p| p.0.iter().all(|&c| c < 60)).count()
        };
        let (none, failed, changed, both) =
            (dark(false, false), dark(true, false), dark(false, true), dark(true, true));
        assert!(none < failed && none < changed && failed < both && changed < both, "{none} {failed} {changed} {both}");
        std::fs::remove_file(&path).ok();
    }

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
