//! PNG plots with plotters' pure-Rust bitmap backend and an embedded DejaVu
//! font, so no system font or graphics package is needed.

use std::path::Path;
use std::sync::Once;

use floe_friction::spring_slider::Sample;
use plotters::coord::ranged1d::{DefaultFormatting, KeyPointHint, Ranged};
use plotters::coord::types::RangedCoordf64;
use plotters::prelude::*;
use plotters::style::FontStyle;

use crate::ticks::Ticks;
use floe_run::Error;

/// One named line on a chart.
#[derive(Debug, Clone)]
pub struct Line {
    /// Legend text.
    pub label: String,
    /// (x, y) points in drawing order.
    pub points: Vec<(f64, f64)>,
    /// Draw markers at the points instead of joining them.
    pub markers: bool,
    /// Palette entry (default: the line's position on the chart), so that
    /// a fit can share its data's colour.
    pub colour: Option<usize>,
}

impl Line {
    /// A joined line.
    pub fn new(label: impl Into<String>, points: Vec<(f64, f64)>) -> Self {
        Self {
            label: label.into(),
            points,
            markers: false,
            colour: None,
        }
    }

    /// The same line drawn in palette entry `k`.
    pub fn coloured(mut self, k: usize) -> Self {
        self.colour = Some(k);
        self
    }

    /// Points drawn as markers.
    pub fn markers(label: impl Into<String>, points: Vec<(f64, f64)>) -> Self {
        Self {
            label: label.into(),
            points,
            markers: true,
            colour: None,
        }
    }
}

/// Axis titles and chart caption.
#[derive(Debug, Clone, Copy)]
pub struct Axes<'a> {
    /// Caption above the chart.
    pub title: &'a str,
    /// x-axis title.
    pub x: &'a str,
    /// y-axis title.
    pub y: &'a str,
}

/// Registers the embedded DejaVu font (once per process).
pub(crate) fn register_font() {
    static FONT: Once = Once::new();
    FONT.call_once(|| {
        // The bytes are a valid TTF shipped by the `dejavu` crate; failure here
        // would only mean text-less plots, so it is not fatal.
        let _ = plotters::style::register_font(
            "sans-serif",
            FontStyle::Normal,
            dejavu::sans::regular(),
        );
    });
}

/// The width in pixels of `text` in the embedded font at `size` pixels
/// (the sum of the glyphs' advances: the ink never reaches past it).
pub(crate) fn text_width(text: &str, size: f64) -> u32 {
    register_font();
    ("sans-serif", size)
        .into_font()
        .box_size(text)
        .map_or(0, |(w, _)| w)
}

const PALETTE: [RGBColor; 6] = [
    RGBColor(31, 119, 180),
    RGBColor(214, 39, 40),
    RGBColor(44, 160, 44),
    RGBColor(255, 127, 14),
    RGBColor(148, 103, 189),
    RGBColor(23, 190, 207),
];

fn bounds(lines: &[Line]) -> ((f64, f64), (f64, f64)) {
    let pts = lines
        .iter()
        .flat_map(|l| l.points.iter())
        .filter(|(x, y)| x.is_finite() && y.is_finite());
    let (mut x0, mut x1, mut y0, mut y1) = (
        f64::INFINITY,
        f64::NEG_INFINITY,
        f64::INFINITY,
        f64::NEG_INFINITY,
    );
    for &(x, y) in pts {
        x0 = x0.min(x);
        x1 = x1.max(x);
        y0 = y0.min(y);
        y1 = y1.max(y);
    }
    if !x0.is_finite() {
        return ((0.0, 1.0), (0.0, 1.0));
    }
    let pad = |a: f64, b: f64, fraction: f64| {
        let d = if b > a {
            fraction * (b - a)
        } else if a == 0.0 {
            1.0
        } else {
            0.5 * a.abs()
        };
        (a - d, b + d)
    };
    // Markers are drawn whole: room for them at the ends of x too.
    let x = if lines.iter().any(|l| l.markers) {
        pad(x0, x1, 0.03)
    } else {
        (x0, if x1 > x0 { x1 } else { x0 + 1.0 })
    };
    (x, pad(y0, y1, 0.05))
}

/// Font size of tick labels and axis titles, pixels.
const LABEL_FONT: f64 = 14.0;
/// Font size of the legend's labels, pixels.
const LEGEND_FONT: f64 = 14.0;

/// An axis of a chart for plotters: a linear range whose mesh lines are
/// [`Ticks`] (bold) and the values between them (light).
pub(crate) struct TickAxis {
    linear: RangedCoordf64,
    bold: Vec<f64>,
    light: Vec<f64>,
}

impl TickAxis {
    /// The axis over `[lo, hi]` with about `target` ticks, and the ticks
    /// (for the labels and the title).
    pub(crate) fn over(lo: f64, hi: f64, target: usize) -> (Self, Ticks) {
        let ticks = Ticks::over(lo, hi, target);
        let axis = Self {
            linear: (lo..hi).into(),
            bold: ticks.values.clone(),
            light: ticks.light_values(lo, hi),
        };
        (axis, ticks)
    }
}

impl Ranged for TickAxis {
    type FormatOption = DefaultFormatting;
    type ValueType = f64;

    fn map(&self, value: &f64, limit: (i32, i32)) -> i32 {
        self.linear.map(value, limit)
    }

    fn key_points<Hint: KeyPointHint>(&self, hint: Hint) -> Vec<f64> {
        if hint.weight().allow_light_points() {
            self.light.clone()
        } else {
            self.bold.clone()
        }
    }

    fn range(&self) -> std::ops::Range<f64> {
        self.linear.range()
    }
}

/// The margin right of a chart: at least `least`, and room for the half
/// of the last x label that reaches past the plot's right edge.
pub(crate) fn right_margin(x: &Ticks, least: u32) -> u32 {
    let last = x.labels.last().map_or(0, |l| text_width(l, LABEL_FONT));
    least.max(last / 2 + 4)
}

/// The width of the area left of a chart that its y labels (right-aligned
/// at plotters' 10 pixels from the axis) and its rotated title need.
pub(crate) fn y_label_area(ticks: &Ticks) -> u32 {
    let widest = ticks
        .labels
        .iter()
        .map(|l| text_width(l, LABEL_FONT))
        .max()
        .unwrap_or(0);
    widest + 10 + LABEL_FONT as u32 + 10
}

type Area<'a> = DrawingArea<BitMapBackend<'a>, plotters::coord::Shift>;

/// The corner of the chart whose legend-sized box covers the fewest data
/// points (upper right first on a tie): the legend is drawn there, not
/// over the data. The box is estimated from the labels' widths against
/// the plotting area's size in pixels, `x` and `y` its ranges.
fn legend_corner(
    lines: &[Line],
    (x, y): ((f64, f64), (f64, f64)),
    (width, height): (u32, u32),
) -> SeriesLabelPosition {
    let labelled = lines.iter().filter(|l| !l.label.is_empty());
    let widest = labelled
        .clone()
        .map(|l| text_width(&l.label, LEGEND_FONT))
        .max()
        .unwrap_or(0);
    // The legend's frame: a sample line, the label and margins, one row
    // per label.
    let box_w = f64::from(widest + 50) / f64::from(width.max(1));
    let box_h = 22.0 * labelled.count() as f64 / f64::from(height.max(1));
    let corners = [
        (SeriesLabelPosition::UpperRight, true, true),
        (SeriesLabelPosition::UpperLeft, false, true),
        (SeriesLabelPosition::LowerRight, true, false),
        (SeriesLabelPosition::LowerLeft, false, false),
    ];
    let covered = |right: bool, upper: bool| {
        lines
            .iter()
            .flat_map(|l| l.points.iter())
            .filter(|(px, py)| {
                let fx = (px - x.0) / (x.1 - x.0);
                let fy = (py - y.0) / (y.1 - y.0);
                let in_x = if right {
                    fx >= 1.0 - box_w
                } else {
                    fx <= box_w
                };
                let in_y = if upper {
                    fy >= 1.0 - box_h
                } else {
                    fy <= box_h
                };
                in_x && in_y
            })
            .count()
    };
    let mut best = (usize::MAX, SeriesLabelPosition::UpperRight);
    for (corner, right, upper) in corners {
        let n = covered(right, upper);
        if n < best.0 {
            best = (n, corner);
        }
    }
    best.1
}

fn draw_chart(area: &Area, axes: Axes, lines: &[Line]) -> Result<(), String> {
    let (x, y) = bounds(lines);
    let (width, height) = area.dim_in_pixel();
    let targets = ((width / 90).max(2) as usize, (height / 60).max(2) as usize);
    let (xr, xt) = TickAxis::over(x.0, x.1, targets.0);
    let (yr, yt) = TickAxis::over(y.0, y.1, targets.1);
    let mut chart = ChartBuilder::on(area)
        .caption(axes.title, ("sans-serif", 20))
        .margin(12)
        .margin_right(right_margin(&xt, 12))
        .x_label_area_size(45)
        .y_label_area_size(y_label_area(&yt))
        .build_cartesian_2d(xr, yr)
        .map_err(|e| e.to_string())?;
    chart
        .configure_mesh()
        .x_desc(xt.title(axes.x))
        .y_desc(yt.title(axes.y))
        .x_label_formatter(&|v| xt.label_of(*v))
        .y_label_formatter(&|v| yt.label_of(*v))
        .label_style(("sans-serif", LABEL_FONT))
        .axis_desc_style(("sans-serif", LABEL_FONT))
        .draw()
        .map_err(|e| e.to_string())?;
    for (i, line) in lines.iter().enumerate() {
        let color = PALETTE[line.colour.unwrap_or(i) % PALETTE.len()];
        let pts = line
            .points
            .iter()
            .copied()
            .filter(|(x, y)| x.is_finite() && y.is_finite());
        let series = if line.markers {
            chart
                .draw_series(pts.map(|p| Circle::new(p, 4, color.filled())))
                .map_err(|e| e.to_string())?
        } else {
            chart
                .draw_series(LineSeries::new(pts, color.stroke_width(2)))
                .map_err(|e| e.to_string())?
        };
        // The legend shows what the chart draws: a dot for markers.
        match (line.label.is_empty(), line.markers) {
            (true, _) => {}
            (false, true) => {
                series
                    .label(line.label.clone())
                    .legend(move |(x, y)| Circle::new((x + 10, y), 4, color.filled()));
            }
            (false, false) => {
                series.label(line.label.clone()).legend(move |(x, y)| {
                    PathElement::new(vec![(x, y), (x + 20, y)], color.stroke_width(2))
                });
            }
        }
    }
    if lines.iter().any(|l| !l.label.is_empty()) {
        let corner = legend_corner(lines, (x, y), chart.plotting_area().dim_in_pixel());
        chart
            .configure_series_labels()
            .background_style(WHITE.mix(0.85))
            .border_style(BLACK)
            .label_font(("sans-serif", LEGEND_FONT))
            .position(corner)
            .draw()
            .map_err(|e| e.to_string())?;
    }
    Ok(())
}

/// Draws panels side by side into one PNG, each `(axes, lines)`.
pub fn panels(path: &Path, panels: &[(Axes, Vec<Line>)]) -> Result<(), Error> {
    grid(path, 1, panels)
}

/// Draws panels in `rows` rows (filled row by row) into one PNG.
pub fn grid(path: &Path, rows: usize, panels: &[(Axes, Vec<Line>)]) -> Result<(), Error> {
    register_font();
    let err = |message: String| Error::Plot {
        path: path.to_path_buf(),
        message,
    };
    let rows = rows.max(1);
    let cols = panels.len().div_ceil(rows).max(1);
    let root = BitMapBackend::new(path, (620 * cols as u32, 460 * rows as u32)).into_drawing_area();
    root.fill(&WHITE).map_err(|e| err(e.to_string()))?;
    let areas = root.split_evenly((rows, cols));
    for (area, (axes, lines)) in areas.iter().zip(panels) {
        draw_chart(area, *axes, lines).map_err(err)?;
    }
    root.present().map_err(|e| err(e.to_string()))
}

/// The spring-slider figure: friction against load-point displacement and
/// against time.
pub fn friction_figure(path: &Path, title: &str, samples: &[Sample]) -> Result<(), Error> {
    let by_displacement: Vec<_> = samples
        .iter()
        .map(|s| (s.load_point_m * 1e3, s.mu))
        .collect();
    let by_time: Vec<_> = samples.iter().map(|s| (s.t_s, s.mu)).collect();
    panels(
        path,
        &[
            (
                Axes {
                    title,
                    x: "load-point displacement (mm)",
                    y: "friction coefficient mu",
                },
                vec![Line::new("", by_displacement)],
            ),
            (
                Axes {
                    title,
                    x: "time (s)",
                    y: "friction coefficient mu",
                },
                vec![Line::new("", by_time)],
            ),
        ],
    )
}
