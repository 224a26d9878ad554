//! The data of a trade-off plot (error against time), as a technique's report describes it; the
//! results crate draws it.

use std::path::PathBuf;

/// One measured configuration of a trade-off plot.
#[derive(Clone, Debug)]
pub struct PlotPoint {
    /// The method: one line, colour and marker.
    pub series: String,
    /// Where the configuration lies in the method's sweep (frames, level, sequence): the line
    /// joins a method's points in this order.
    pub step: f64,
    pub x: f64,
    pub y: f64,
}

/// A trade-off plot to draw: where, its labels, and its points.
#[must_use = "a report's plot is written only when drawn (fragkit_results::plot::tradeoff)"]
#[derive(Clone, Debug)]
pub struct TradeoffPlot {
    pub path: PathBuf,
    pub title: String,
    pub x_label: String,
    pub y_label: String,
    pub points: Vec<PlotPoint>,
}
