//! Figures for the examples, drawn with plotters: bifurcation diagrams, scatter plots
//! (Poincaré maps), line plots (phase portraits, with breaks where a curve jumps), heat maps with
//! a colour bar, and multi-line plots with a legend (log-log work-precision diagrams).
//!
//! Every function writes the picture to `path` (PNG for `.png`, SVG for `.svg`) and the data
//! behind it to the same path with the extension `.csv`. Folders are created as needed.
//! Points with a NaN or infinite coordinate (or a non-positive one on a log axis) are not drawn
//! and, in line plots, break the curve.
//!
//! Log axes are drawn by plotting `log10` of the data on a linear axis labelled with powers of
//! ten (`10⁻³`), so all plot kinds share one coordinate type.

use std::fmt;
use std::ops::Range;
use std::path::{Path, PathBuf};
use std::sync::OnceLock;

use plotters::coord::ranged1d::{
    KeyPointHint, KeyPointWeight, NoDefaultFormatting, Ranged, ValueFormatter,
};
use plotters::coord::Shift;
use plotters::prelude::*;
use plotters::style::FontStyle;

use super::csv::CsvWriter;
use super::layout::{around, fit_title, Occupancy, Rect};

/// Something went wrong while drawing or writing a figure.
#[derive(Debug, Clone)]
pub struct PlotError {
    /// The file being written.
    pub path: PathBuf,
    /// What went wrong.
    pub message: String,
}

impl fmt::Display for PlotError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{}: {}", self.path.display(), self.message)
    }
}

impl std::error::Error for PlotError {}

fn perr(path: &Path, e: impl fmt::Display) -> PlotError {
    PlotError {
        path: path.to_path_buf(),
        message: e.to_string(),
    }
}

/// Registers the bundled DejaVu Sans font as "sans-serif" (once). Text in a bitmap panics
/// without a registered font, so every drawing function calls this first.
pub fn ensure_font() -> Result<(), String> {
    static DONE: OnceLock<Result<(), String>> = OnceLock::new();
    DONE.get_or_init(|| {
        plotters::style::register_font(
            "sans-serif",
            FontStyle::Normal,
            include_bytes!("assets/DejaVuSans.ttf"),
        )
        .map_err(|_| "the bundled font DejaVuSans.ttf could not be loaded".to_string())
    })
    .clone()
}

/// Where a legend goes.
pub use plotters::chart::SeriesLabelPosition as LegendPosition;

/// Titles, labels and layout of a figure. Build with [`Figure::new`] and the `with_` methods.
#[derive(Debug, Clone)]
pub struct Figure {
    /// Title above the plot; name the parameters here.
    pub title: String,
    /// Label of the horizontal axis (symbols such as "η" or "x_r" render fine).
    pub x_label: String,
    /// Label of the vertical axis.
    pub y_label: String,
    /// Column name of x in the CSV (default "x").
    pub x_column: String,
    /// Column name of y in the CSV (default "y").
    pub y_column: String,
    /// Picture size in pixels (default 1200 × 800).
    pub size: (u32, u32),
    /// Fixed x range (in data units); default: the data's range plus 3 %.
    pub x_range: Option<(f64, f64)>,
    /// Fixed y range (in data units); default: the data's range plus 3 %.
    pub y_range: Option<(f64, f64)>,
    /// Logarithmic x axis.
    pub log_x: bool,
    /// Logarithmic y axis.
    pub log_y: bool,
    /// Side of the square dot in pixels for point plots; 1 is a single pixel. 0 (default)
    /// chooses from the number of points: 3 below 20 000 points, 2 below 300 000, else 1.
    pub dot: u32,
    /// Opacity of dots (default 0.8); lower it to show density in crowded plots.
    pub dot_alpha: f64,
    /// Draw a marker at each point of a line plot (default false).
    pub markers: bool,
    /// Break a line where one step is longer than this fraction of the plot's diagonal
    /// (in axis-normalised units); `None` (default) never breaks except at NaN points.
    pub max_jump: Option<f64>,
    /// Where the legend goes; `None` (default): the corner where it covers the least data. The
    /// legend lists the non-empty labels.
    pub legend: Option<LegendPosition>,
    /// A note drawn in a box inside the plot, in the corner where it covers the least data
    /// (lines separated by `\n`); e.g. why a panel looks empty.
    pub note: Option<String>,
    /// Vertical reference lines: `(x, label)`, drawn thin and red (e.g. reported bifurcations).
    pub marks: Vec<(f64, String)>,
    /// Marked points: `(x, y, label)`, drawn as a white-ringed black cross with the label
    /// (category maps only; e.g. the start from rest on a basin).
    pub pins: Vec<(f64, f64, String)>,
    /// Curves drawn over a category map: `(label, points)`, a black line on a white edge,
    /// labelled at its last point (e.g. bifurcation curves from a continuation).
    pub overlays: Vec<(String, Vec<(f64, f64)>)>,
}

impl Figure {
    /// A figure with the given title and axis labels, and default layout.
    pub fn new(title: &str, x_label: &str, y_label: &str) -> Self {
        Figure {
            title: title.to_string(),
            x_label: x_label.to_string(),
            y_label: y_label.to_string(),
            x_column: "x".to_string(),
            y_column: "y".to_string(),
            size: (1200, 800),
            x_range: None,
            y_range: None,
            log_x: false,
            log_y: false,
            dot: 0,
            dot_alpha: 0.8,
            markers: false,
            max_jump: None,
            legend: None,
            note: None,
            marks: Vec::new(),
            pins: Vec::new(),
            overlays: Vec::new(),
        }
    }
    /// Sets the CSV column names of x and y.
    pub fn with_columns(mut self, x: &str, y: &str) -> Self {
        self.x_column = x.to_string();
        self.y_column = y.to_string();
        self
    }
    /// Sets the picture size in pixels.
    pub fn with_size(mut self, width: u32, height: u32) -> Self {
        self.size = (width, height);
        self
    }
    /// Fixes the x range.
    pub fn with_x_range(mut self, lo: f64, hi: f64) -> Self {
        self.x_range = Some((lo, hi));
        self
    }
    /// Fixes the y range.
    pub fn with_y_range(mut self, lo: f64, hi: f64) -> Self {
        self.y_range = Some((lo, hi));
        self
    }
    /// Logarithmic axes.
    pub fn with_log(mut self, log_x: bool, log_y: bool) -> Self {
        self.log_x = log_x;
        self.log_y = log_y;
        self
    }
    /// Dot size (pixels; 0 = automatic) and opacity for point plots.
    pub fn with_dots(mut self, side: u32, alpha: f64) -> Self {
        self.dot = side;
        self.dot_alpha = alpha.clamp(0.05, 1.0);
        self
    }
    /// Markers at the points of line plots.
    pub fn with_markers(mut self) -> Self {
        self.markers = true;
        self
    }
    /// Breaks lines at steps longer than `fraction` of the plot diagonal.
    pub fn with_max_jump(mut self, fraction: f64) -> Self {
        self.max_jump = Some(fraction);
        self
    }
    /// Places the legend.
    pub fn with_legend(mut self, position: LegendPosition) -> Self {
        self.legend = Some(position);
        self
    }
    /// Adds a note in a box inside the plot (lines separated by `\n`).
    pub fn with_note(mut self, note: &str) -> Self {
        self.note = Some(note.to_string());
        self
    }
    /// Adds a labelled curve over a category map.
    pub fn with_overlay(mut self, label: &str, points: Vec<(f64, f64)>) -> Self {
        self.overlays.push((label.to_string(), points));
        self
    }
    /// Adds a marked point with a label (category maps).
    pub fn with_pin(mut self, x: f64, y: f64, label: &str) -> Self {
        self.pins.push((x, y, label.to_string()));
        self
    }
    /// Adds a labelled vertical reference line.
    pub fn with_mark(mut self, x: f64, label: &str) -> Self {
        self.marks.push((x, label.to_string()));
        self
    }

    fn tx(&self, x: f64) -> f64 {
        if self.log_x {
            x.log10()
        } else {
            x
        }
    }
    fn ty(&self, y: f64) -> f64 {
        if self.log_y {
            y.log10()
        } else {
            y
        }
    }
    /// The point in plot coordinates, if drawable.
    fn map(&self, (x, y): (f64, f64)) -> Option<(f64, f64)> {
        let p = (self.tx(x), self.ty(y));
        (p.0.is_finite() && p.1.is_finite()).then_some(p)
    }
}

/// A named set of points (one colour).
#[derive(Debug, Clone, Default)]
pub struct Series {
    /// Legend label (empty: not in the legend).
    pub label: String,
    /// The points `(x, y)`, in drawing order for lines.
    pub points: Vec<(f64, f64)>,
}

impl Series {
    /// A series with a label and points.
    pub fn new(label: &str, points: Vec<(f64, f64)>) -> Self {
        Series {
            label: label.to_string(),
            points,
        }
    }
}

/// Values on a rectangular grid, for [`heatmap`].
#[derive(Debug, Clone)]
pub struct Grid {
    /// Cell centres along x (increasing).
    pub xs: Vec<f64>,
    /// Cell centres along y (increasing).
    pub ys: Vec<f64>,
    /// Values, row by row: `values[iy * xs.len() + ix]`. NaN cells are drawn grey.
    pub values: Vec<f64>,
    /// Colour scale limits; default: the finite values' range.
    pub z_range: Option<(f64, f64)>,
}

/// Distinguishable colours (the "tab10" palette).
pub const PALETTE: [RGBColor; 10] = [
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
];

/// The colour of series `i`.
pub fn series_colour(i: usize) -> RGBColor {
    PALETTE[i % PALETTE.len()]
}

/// The viridis colour map at `t ∈ [0, 1]` (clamped), interpolated from nine reference colours.
pub fn viridis(t: f64) -> RGBColor {
    const STOPS: [(u8, u8, u8); 9] = [
        (68, 1, 84),
        (72, 40, 120),
        (62, 74, 137),
        (49, 104, 142),
        (38, 130, 142),
        (31, 158, 137),
        (53, 183, 121),
        (109, 205, 89),
        (253, 231, 37),
    ];
    let t = if t.is_finite() {
        t.clamp(0.0, 1.0)
    } else {
        0.0
    };
    let s = t * (STOPS.len() - 1) as f64;
    let i = (s.floor() as usize).min(STOPS.len() - 2);
    let f = s - i as f64;
    let mix = |a: u8, b: u8| (a as f64 + f * (b as f64 - a as f64)).round() as u8;
    let (a, b) = (STOPS[i], STOPS[i + 1]);
    RGBColor(mix(a.0, b.0), mix(a.1, b.1), mix(a.2, b.2))
}

enum Format {
    Png,
    Svg,
}

fn format_of(path: &Path) -> Result<Format, PlotError> {
    match path
        .extension()
        .and_then(|e| e.to_str())
        .map(str::to_ascii_lowercase)
    {
        Some(e) if e == "png" => Ok(Format::Png),
        Some(e) if e == "svg" => Ok(Format::Svg),
        _ => Err(perr(
            path,
            "the figure's file name must end in .png or .svg",
        )),
    }
}

/// Prepares the output: font, folder, format.
fn prepare(path: &Path) -> Result<Format, PlotError> {
    ensure_font().map_err(|e| perr(path, e))?;
    super::csv::ensure_parent(path).map_err(|e| perr(path, e))?;
    format_of(path)
}

/// Runs a generic drawing function on the backend chosen by the file extension.
macro_rules! on_backend {
    ($path:expr, $size:expr, $draw:ident ( $($arg:expr),* )) => {{
        let path: &Path = $path;
        let res = match prepare(path)? {
            Format::Png => {
                let root = BitMapBackend::new(path, $size).into_drawing_area();
                $draw(&root, $($arg),*).and_then(|_| root.present().map_err(|e| e.to_string()))
            }
            Format::Svg => {
                let root = SVGBackend::new(path, $size).into_drawing_area();
                $draw(&root, $($arg),*).and_then(|_| root.present().map_err(|e| e.to_string()))
            }
        };
        res.map_err(|e| perr(path, e))
    }};
}

fn csv_path(path: &Path) -> PathBuf {
    path.with_extension("csv")
}

/// The range of finite values, padded by 3 % (or ±0.5 around a single value).
fn auto_range(values: impl Iterator<Item = f64>, fixed: Option<(f64, f64)>) -> Range<f64> {
    if let Some((a, b)) = fixed
        && a.is_finite()
        && b.is_finite()
        && a < b
    {
        return a..b;
    }
    let (mut lo, mut hi) = (f64::INFINITY, f64::NEG_INFINITY);
    for v in values.filter(|v| v.is_finite()) {
        lo = lo.min(v);
        hi = hi.max(v);
    }
    if !lo.is_finite() {
        return 0.0..1.0;
    }
    if hi - lo <= 1e-12 * (1.0 + lo.abs()) {
        let pad = if lo == 0.0 { 0.5 } else { 0.1 * lo.abs() };
        return lo - pad..hi + pad;
    }
    let pad = 0.03 * (hi - lo);
    lo - pad..hi + pad
}

fn ranges(fig: &Figure, pts: &[(f64, f64)]) -> (Range<f64>, Range<f64>) {
    let fx = fig.x_range.map(|(a, b)| (fig.tx(a), fig.tx(b)));
    let fy = fig.y_range.map(|(a, b)| (fig.ty(a), fig.ty(b)));
    (
        auto_range(pts.iter().map(|p| p.0), fx),
        auto_range(pts.iter().map(|p| p.1), fy),
    )
}

/// Tick label on a log axis: `10ⁿ` at whole powers, the plain number elsewhere.
fn pow10_label(v: f64) -> String {
    if (v - v.round()).abs() < 1e-9 {
        let k = v.round() as i64;
        let sup: String = k
            .to_string()
            .chars()
            .map(|c| match c {
                '-' => '⁻',
                '0' => '⁰',
                '1' => '¹',
                '2' => '²',
                '3' => '³',
                '4' => '⁴',
                '5' => '⁵',
                '6' => '⁶',
                '7' => '⁷',
                '8' => '⁸',
                _ => '⁹',
            })
            .collect();
        format!("10{sup}")
    } else {
        tick_label(10f64.powf(v))
    }
}

/// Tick label on a linear axis: short, without float noise.
fn tick_label(v: f64) -> String {
    let a = v.abs();
    if a == 0.0 {
        "0".to_string()
    } else if !(1e-3..1e5).contains(&a) {
        format!("{v:.1e}")
    } else {
        let s = format!("{v:.4}");
        let s = s.trim_end_matches('0').trim_end_matches('.');
        if s == "-0" {
            "0".to_string()
        } else {
            s.to_string()
        }
    }
}

/// A linear axis (in plot coordinates: `log10` of the data on a log axis) with our own tick
/// positions: multiples of 1, 2 or 5 × 10ᵏ computed from integers (so the end ticks are never
/// lost to rounding), whole decades on log axes with minor lines at 2…9 × 10ᵏ.
#[derive(Clone)]
struct Axis {
    lo: f64,
    hi: f64,
    log: bool,
}

/// The nice step (1, 2 or 5 × 10ᵏ) giving at most `max` ticks on `[lo, hi]`.
fn nice_step(lo: f64, hi: f64, max: usize) -> f64 {
    let span = (hi - lo).max(f64::MIN_POSITIVE);
    let max = max.max(2) as f64;
    let mut step = 10f64.powf((span / max).log10().floor());
    for _ in 0..8 {
        for m in [1.0, 2.0, 5.0] {
            let s = step * m;
            if (span / s).floor() + 1.0 <= max {
                return s;
            }
        }
        step *= 10.0;
    }
    span
}

/// Multiples of `step` inside `[lo, hi]`, each computed as `k · step`.
fn multiples(lo: f64, hi: f64, step: f64) -> Vec<f64> {
    let k0 = (lo / step - 1e-9).ceil() as i64;
    let k1 = (hi / step + 1e-9).floor() as i64;
    (k0..=k1.max(k0 - 1)).map(|k| k as f64 * step).collect()
}

impl Ranged for Axis {
    type FormatOption = NoDefaultFormatting;
    type ValueType = f64;

    fn map(&self, v: &f64, limit: (i32, i32)) -> i32 {
        let f = (v - self.lo) / (self.hi - self.lo);
        let px = limit.0 as f64 + f * (limit.1 - limit.0) as f64;
        px.round().clamp(-1e7, 1e7) as i32
    }

    fn key_points<H: KeyPointHint>(&self, hint: H) -> Vec<f64> {
        let bold_max = hint.bold_points().max(2);
        let mut bold = nice_step(self.lo, self.hi, bold_max);
        if self.log && self.hi - self.lo >= 2.0 {
            bold = bold.max(1.0).round();
        }
        if matches!(hint.weight(), KeyPointWeight::Bold) {
            return multiples(self.lo, self.hi, bold);
        }
        if self.log && bold == 1.0 {
            let mut out = Vec::new();
            for k in (self.lo.floor() as i64)..=(self.hi.ceil() as i64) {
                for m in 1..10 {
                    let v = k as f64 + (m as f64).log10();
                    if v >= self.lo && v <= self.hi {
                        out.push(v);
                    }
                }
            }
            return out;
        }
        let minor = if (bold / 10f64.powf(bold.log10().floor()) - 2.0).abs() < 1e-9 {
            bold / 4.0
        } else {
            bold / 5.0
        };
        multiples(self.lo, self.hi, minor)
    }

    fn range(&self) -> Range<f64> {
        self.lo..self.hi
    }
}

impl ValueFormatter<f64> for Axis {
    fn format(value: &f64) -> String {
        tick_label(*value)
    }
    fn format_ext(&self, value: &f64) -> String {
        if self.log {
            pow10_label(*value)
        } else {
            tick_label(*value)
        }
    }
}

type Chart<'a, DB> = ChartContext<'a, DB, Cartesian2d<Axis, Axis>>;

/// Builds the axes, mesh and axis labels (the title is [`fit_title`]'s).
fn axes<'a, DB: DrawingBackend>(
    area: &'a DrawingArea<DB, Shift>,
    fig: &Figure,
    xr: Range<f64>,
    yr: Range<f64>,
) -> Result<Chart<'a, DB>, String> {
    let mut builder = ChartBuilder::on(area);
    builder
        .margin(12)
        .margin_right(28)
        .x_label_area_size(62)
        .y_label_area_size(88);
    let x_axis = Axis {
        lo: xr.start,
        hi: xr.end,
        log: fig.log_x,
    };
    let y_axis = Axis {
        lo: yr.start,
        hi: yr.end,
        log: fig.log_y,
    };
    let mut chart = builder
        .build_cartesian_2d(x_axis, y_axis)
        .map_err(|e| e.to_string())?;
    let xf = |v: &f64| {
        if fig.log_x {
            pow10_label(*v)
        } else {
            tick_label(*v)
        }
    };
    let yf = |v: &f64| {
        if fig.log_y {
            pow10_label(*v)
        } else {
            tick_label(*v)
        }
    };
    chart
        .configure_mesh()
        .x_desc(fig.x_label.as_str())
        .y_desc(fig.y_label.as_str())
        .axis_desc_style(("sans-serif", 24))
        .label_style(("sans-serif", 18))
        .x_label_formatter(&xf)
        .y_label_formatter(&yf)
        .x_labels(12)
        .y_labels(10)
        .bold_line_style(RGBColor(205, 205, 205))
        .light_line_style(RGBColor(238, 238, 238))
        .draw()
        .map_err(|e| e.to_string())?;
    Ok(chart)
}

/// The occupancy grid of a chart's plot area (see [`Occupancy`]).
fn occupancy<DB: DrawingBackend>(chart: &Chart<'_, DB>) -> Occupancy {
    Occupancy::new(chart.plotting_area().get_pixel_range())
}

/// Size of `text` in `font` (pixels), or an estimate if the backend cannot tell.
fn text_size<DB: DrawingBackend>(chart: &Chart<'_, DB>, text: &str, size: u32) -> (u32, u32) {
    let style: TextStyle = ("sans-serif", size).into();
    chart
        .plotting_area()
        .estimate_text_size(text, &style)
        .unwrap_or((text.chars().count() as u32 * size / 2, size))
}

/// Records a series' points (`line`: and the segments between them) on the grid.
fn occupy<DB: DrawingBackend>(
    occ: &mut Occupancy,
    chart: &Chart<'_, DB>,
    pts: &[(f64, f64)],
    line: bool,
) {
    let mut prev: Option<(i32, i32)> = None;
    for p in pts {
        let q = chart.backend_coord(p);
        match prev {
            Some(a) if line => occ.segment(a, q),
            _ => occ.point(q),
        }
        prev = Some(q);
    }
}

/// The marks of `fig` inside the x range, in plot coordinates, with their labels.
fn marks_in_range<'f, DB: DrawingBackend>(
    chart: &Chart<'_, DB>,
    fig: &'f Figure,
) -> Vec<(f64, &'f str)> {
    let xr = chart.x_range();
    fig.marks
        .iter()
        .map(|(x, label)| (fig.tx(*x), label.as_str()))
        .filter(|(x, _)| x.is_finite() && xr.contains(x))
        .collect()
}

const MARK_COLOUR: RGBColor = RGBColor(200, 30, 30);

/// The vertical reference lines of the marks (drawn before the data, which goes over them).
fn draw_mark_lines<DB: DrawingBackend>(
    chart: &mut Chart<'_, DB>,
    fig: &Figure,
) -> Result<(), String> {
    let yr = chart.y_range();
    for (x, _) in marks_in_range(chart, fig) {
        chart
            .draw_series(std::iter::once(PathElement::new(
                vec![(x, yr.start), (x, yr.end)],
                MARK_COLOUR.mix(0.6).stroke_width(1),
            )))
            .map_err(|e| e.to_string())?;
    }
    Ok(())
}

/// The marks' labels (drawn after the data): near the top of each line, right of it or left,
/// in the first of six rows where it covers no other label and the least data.
fn draw_mark_labels<DB: DrawingBackend>(
    chart: &mut Chart<'_, DB>,
    fig: &Figure,
    occ: &mut Occupancy,
) -> Result<(), String> {
    let yr = chart.y_range();
    for (x, label) in marks_in_range(chart, fig) {
        let (w, h) = text_size(chart, label, 16);
        let (w, h) = (w as i32, h as i32);
        let top = chart.backend_coord(&(x, yr.end));
        let candidates: Vec<Rect> = (0..6)
            .flat_map(|row| {
                let y = top.1 + 4 + row * (h + 4);
                [
                    (top.0 + 4, y, top.0 + 4 + w, y + h),
                    (top.0 - 4 - w, y, top.0 - 4, y + h),
                ]
            })
            .collect();
        let r = candidates[occ.place(&candidates)];
        chart
            .draw_series(std::iter::once(
                EmptyElement::at((x, yr.end))
                    + Text::new(
                        label.to_string(),
                        (r.0 - top.0, r.1 - top.1),
                        ("sans-serif", 16).into_font().color(&MARK_COLOUR),
                    ),
            ))
            .map_err(|e| e.to_string())?;
    }
    Ok(())
}

/// The figure's note, in a white box in the corner where it covers the least data.
fn draw_note<DB: DrawingBackend>(
    chart: &mut Chart<'_, DB>,
    fig: &Figure,
    occ: &mut Occupancy,
) -> Result<(), String> {
    let Some(note) = &fig.note else {
        return Ok(());
    };
    let lines: Vec<&str> = note.lines().collect();
    let sizes: Vec<(u32, u32)> = lines.iter().map(|l| text_size(chart, l, 19)).collect();
    let w = sizes.iter().map(|s| s.0).max().unwrap_or(0) as i32 + 20;
    let line_h = sizes.iter().map(|s| s.1).max().unwrap_or(19) as i32 + 6;
    let h = line_h * lines.len() as i32 + 14;
    let corner = occ.legend_corner((w, h), 12);
    let (px, py) = chart.plotting_area().get_pixel_range();
    let left = match corner {
        LegendPosition::UpperLeft | LegendPosition::LowerLeft => px.start + 12,
        _ => px.end - 12 - w,
    };
    let top = match corner {
        LegendPosition::UpperLeft | LegendPosition::UpperRight => py.start + 12,
        _ => py.end - 12 - h,
    };
    let area = chart.plotting_area();
    let (bx, by) = (left - px.start, top - py.start);
    let root = area.strip_coord_spec();
    root.draw(&Rectangle::new(
        [(bx, by), (bx + w, by + h)],
        WHITE.mix(0.92).filled(),
    ))
    .map_err(|e| e.to_string())?;
    root.draw(&Rectangle::new(
        [(bx, by), (bx + w, by + h)],
        RGBColor(120, 120, 120),
    ))
    .map_err(|e| e.to_string())?;
    for (k, l) in lines.iter().enumerate() {
        let y = by + 8 + k as i32 * line_h;
        root.draw(&Text::new(l.to_string(), (bx + 10, y), ("sans-serif", 19)))
            .map_err(|e| e.to_string())?;
    }
    Ok(())
}

fn draw_dots<DB: DrawingBackend>(
    chart: &mut Chart<'_, DB>,
    pts: &[(f64, f64)],
    colour: RGBColor,
    side: u32,
    alpha: f64,
) -> Result<(), String> {
    let style = colour.mix(alpha);
    if side <= 1 {
        chart
            .draw_series(pts.iter().map(|&p| Pixel::new(p, style)))
            .map_err(|e| e.to_string())?;
    } else {
        let s = side as i32;
        let (a, b) = (-(s / 2), s - s / 2);
        chart
            .draw_series(
                pts.iter().map(|&p| {
                    EmptyElement::at(p) + Rectangle::new([(a, a), (b, b)], style.filled())
                }),
            )
            .map_err(|e| e.to_string())?;
    }
    Ok(())
}

/// The legend of the labelled series: where `fig.legend` says, else in the corner where it
/// covers the least data and no label.
fn draw_legend<'a, DB: DrawingBackend + 'a>(
    chart: &mut Chart<'a, DB>,
    fig: &Figure,
    labels: &[&str],
    occ: &mut Occupancy,
) -> Result<(), String> {
    let labels: Vec<&str> = labels.iter().copied().filter(|l| !l.is_empty()).collect();
    let position = match &fig.legend {
        Some(p) => p.clone(),
        None => {
            let sizes: Vec<(u32, u32)> = labels.iter().map(|l| text_size(chart, l, 19)).collect();
            let w = sizes.iter().map(|s| s.0).max().unwrap_or(0) as i32 + 60;
            let h = sizes.iter().map(|s| s.1 as i32 + 7).sum::<i32>() + 24;
            occ.legend_corner((w, h), 12)
        }
    };
    chart
        .configure_series_labels()
        .position(position)
        .background_style(WHITE.mix(0.9))
        .border_style(RGBColor(150, 150, 150))
        .label_font(("sans-serif", 19))
        .margin(12)
        .draw()
        .map_err(|e| e.to_string())
}

fn draw_points_chart<DB: DrawingBackend>(
    root: &DrawingArea<DB, Shift>,
    fig: &Figure,
    series: &[Vec<(f64, f64)>],
    labels: &[&str],
    single_colour: Option<RGBColor>,
) -> Result<(), String> {
    root.fill(&WHITE).map_err(|e| e.to_string())?;
    let all: Vec<(f64, f64)> = series.iter().flatten().copied().collect();
    let (xr, yr) = ranges(fig, &all);
    let area = fit_title(&root.margin(6, 0, 0, 0), &fig.title)?;
    let mut chart = axes(&area, fig, xr, yr)?;
    let mut occ = occupancy(&chart);
    draw_mark_lines(&mut chart, fig)?;
    occupy(&mut occ, &chart, &all, false);
    let side = match fig.dot {
        0 if all.len() < 20_000 => 3,
        0 if all.len() < 300_000 => 2,
        0 => 1,
        s => s,
    };
    for (i, pts) in series.iter().enumerate() {
        let colour = single_colour.unwrap_or_else(|| series_colour(i));
        draw_dots(&mut chart, pts, colour, side, fig.dot_alpha)?;
        let label = labels.get(i).copied().unwrap_or("");
        if !label.is_empty() {
            // An empty series carries the legend entry (dots have no legend of their own).
            chart
                .draw_series(std::iter::empty::<Circle<(f64, f64), i32>>())
                .map_err(|e| e.to_string())?
                .label(label)
                .legend(move |(x, y)| {
                    Rectangle::new([(x, y - 5), (x + 10, y + 5)], colour.filled())
                });
        }
    }
    draw_mark_labels(&mut chart, fig, &mut occ)?;
    if labels.iter().any(|l| !l.is_empty()) {
        draw_legend(&mut chart, fig, labels, &mut occ)?;
    }
    draw_note(&mut chart, fig, &mut occ)
}

/// A bifurcation diagram: `points` are `(parameter, value)` pairs, drawn as small dark dots.
///
/// Meant for up to hundreds of thousands of points; the dot size adapts to the number of
/// points unless set with `fig.with_dots`. Writes `path` and the CSV (`fig.x_column`, `fig.y_column`).
pub fn bifurcation(
    path: impl AsRef<Path>,
    fig: &Figure,
    points: &[(f64, f64)],
) -> Result<(), PlotError> {
    let path = path.as_ref();
    let mapped: Vec<(f64, f64)> = points.iter().filter_map(|&p| fig.map(p)).collect();
    on_backend!(
        path,
        fig.size,
        draw_points_chart(fig, &[mapped], &[""], Some(RGBColor(20, 20, 70)))
    )?;
    let mut w = CsvWriter::create(csv_path(path), &[&fig.x_column, &fig.y_column])
        .map_err(|e| perr(path, e))?;
    for &(x, y) in points {
        w.row(&[x, y]).map_err(|e| perr(path, e))?;
    }
    w.finish().map_err(|e| perr(path, e))
}

/// A scatter plot (a Poincaré map): one colour per series, legend for labelled series.
/// Writes `path` and the CSV (`series`, `fig.x_column`, `fig.y_column`).
pub fn scatter(path: impl AsRef<Path>, fig: &Figure, series: &[Series]) -> Result<(), PlotError> {
    let path = path.as_ref();
    let mapped: Vec<Vec<(f64, f64)>> = series
        .iter()
        .map(|s| s.points.iter().filter_map(|&p| fig.map(p)).collect())
        .collect();
    let labels: Vec<&str> = series.iter().map(|s| s.label.as_str()).collect();
    on_backend!(
        path,
        fig.size,
        draw_points_chart(fig, &mapped, &labels, None)
    )?;
    write_series_csv(path, fig, series)
}

fn write_series_csv(path: &Path, fig: &Figure, series: &[Series]) -> Result<(), PlotError> {
    let mut w = CsvWriter::create(csv_path(path), &["series", &fig.x_column, &fig.y_column])
        .map_err(|e| perr(path, e))?;
    for s in series {
        for &(x, y) in &s.points {
            w.record(&[
                s.label.clone(),
                super::csv::fmt_f64(x),
                super::csv::fmt_f64(y),
            ])
            .map_err(|e| perr(path, e))?;
        }
    }
    w.finish().map_err(|e| perr(path, e))
}

/// Splits a polyline (already in plot coordinates, `None` = undrawable point) into pieces at
/// undrawable points and at steps longer than `max_jump` of the normalised diagonal. Points
/// closer than `min_step` (normalised) to the last kept point are skipped, except the last
/// point of each piece, so dense curves are not drawn as a pile of tiny thick segments.
fn split_curve(
    pts: &[Option<(f64, f64)>],
    max_jump: Option<f64>,
    min_step: f64,
    xr: &Range<f64>,
    yr: &Range<f64>,
) -> Vec<Vec<(f64, f64)>> {
    let (w, h) = (xr.end - xr.start, yr.end - yr.start);
    let dist = |a: (f64, f64), b: (f64, f64)| {
        let dx = (a.0 - b.0) / w;
        let dy = (a.1 - b.1) / h;
        (dx * dx + dy * dy).sqrt()
    };
    let mut pieces = Vec::new();
    let mut cur: Vec<(f64, f64)> = Vec::new();
    // The previous point, if it was skipped (not yet in `cur`).
    let mut pending: Option<(f64, f64)> = None;
    let mut prev: Option<(f64, f64)> = None;
    let close = |cur: &mut Vec<(f64, f64)>,
                 pending: &mut Option<(f64, f64)>,
                 pieces: &mut Vec<Vec<(f64, f64)>>| {
        cur.extend(pending.take());
        if !cur.is_empty() {
            pieces.push(std::mem::take(cur));
        }
    };
    for p in pts {
        let Some(q) = *p else {
            close(&mut cur, &mut pending, &mut pieces);
            prev = None;
            continue;
        };
        if let Some(pr) = prev
            && max_jump.is_some_and(|limit| dist(q, pr) > limit * std::f64::consts::SQRT_2)
        {
            close(&mut cur, &mut pending, &mut pieces);
        }
        prev = Some(q);
        match cur.last() {
            Some(&last) if dist(q, last) < min_step => pending = Some(q),
            _ => {
                pending = None;
                cur.push(q);
            }
        }
    }
    close(&mut cur, &mut pending, &mut pieces);
    pieces
}

fn draw_lines_chart<DB: DrawingBackend>(
    root: &DrawingArea<DB, Shift>,
    fig: &Figure,
    series: &[Series],
) -> Result<(), String> {
    root.fill(&WHITE).map_err(|e| e.to_string())?;
    let mapped: Vec<Vec<Option<(f64, f64)>>> = series
        .iter()
        .map(|s| s.points.iter().map(|&p| fig.map(p)).collect())
        .collect();
    let all: Vec<(f64, f64)> = mapped.iter().flatten().flatten().copied().collect();
    let (xr, yr) = ranges(fig, &all);
    let area = fit_title(&root.margin(6, 0, 0, 0), &fig.title)?;
    let mut chart = axes(&area, fig, xr.clone(), yr.clone())?;
    let mut occ = occupancy(&chart);
    draw_mark_lines(&mut chart, fig)?;
    for (i, (s, pts)) in series.iter().zip(&mapped).enumerate() {
        let colour = series_colour(i);
        let style = colour.stroke_width(2);
        let min_step = 1.5 / f64::from(fig.size.0.max(fig.size.1).max(1));
        let pieces = split_curve(pts, fig.max_jump, min_step, &xr, &yr);
        let mut labelled = s.label.is_empty();
        for piece in pieces {
            occupy(&mut occ, &chart, &piece, true);
            let ann = chart
                .draw_series(LineSeries::new(piece.iter().copied(), style))
                .map_err(|e| e.to_string())?;
            if !labelled {
                labelled = true;
                let marker = fig.markers;
                ann.label(s.label.as_str()).legend(move |(x, y)| {
                    let line =
                        PathElement::new(vec![(x - 4, y), (x + 20, y)], colour.stroke_width(3));
                    let dot = Circle::new((x + 8, y), if marker { 4 } else { 0 }, colour.filled());
                    EmptyElement::at((0, 0)) + line + dot
                });
            }
            if fig.markers {
                chart
                    .draw_series(piece.iter().map(|&p| Circle::new(p, 4, colour.filled())))
                    .map_err(|e| e.to_string())?;
            }
        }
    }
    draw_mark_labels(&mut chart, fig, &mut occ)?;
    if series.iter().any(|s| !s.label.is_empty()) {
        let labels: Vec<&str> = series.iter().map(|s| s.label.as_str()).collect();
        draw_legend(&mut chart, fig, &labels, &mut occ)?;
    }
    draw_note(&mut chart, fig, &mut occ)
}

/// A line plot: each series is a polyline (a phase portrait, a time history), broken at
/// NaN points and, if `fig.max_jump` is set, where the curve jumps. With `fig.with_markers()`
/// and `fig.with_log(true, true)` this is a work-precision diagram. Labelled series get a
/// legend. Writes `path` and the CSV (`series`, `fig.x_column`, `fig.y_column`).
pub fn lines(path: impl AsRef<Path>, fig: &Figure, series: &[Series]) -> Result<(), PlotError> {
    let path = path.as_ref();
    on_backend!(path, fig.size, draw_lines_chart(fig, series))?;
    write_series_csv(path, fig, series)
}

/// Cell edges from cell centres (midpoints, extended by half a cell at the ends).
fn edges(c: &[f64]) -> Vec<f64> {
    match c.len() {
        0 => Vec::new(),
        1 => vec![c[0] - 0.5, c[0] + 0.5],
        n => {
            let mut e = Vec::with_capacity(n + 1);
            e.push(c[0] - 0.5 * (c[1] - c[0]));
            for i in 0..n - 1 {
                e.push(0.5 * (c[i] + c[i + 1]));
            }
            e.push(c[n - 1] + 0.5 * (c[n - 1] - c[n - 2]));
            e
        }
    }
}

fn draw_heatmap_chart<DB: DrawingBackend>(
    root: &DrawingArea<DB, Shift>,
    fig: &Figure,
    grid: &Grid,
    zr: Range<f64>,
    bar_label: &str,
) -> Result<(), String> {
    root.fill(&WHITE).map_err(|e| e.to_string())?;
    let body = fit_title(&root.margin(6, 0, 0, 0), &fig.title)?;
    let (w, _) = body.dim_in_pixel();
    let (main, bar) = body.split_horizontally(w.saturating_sub(170));
    let (ex, ey) = (edges(&grid.xs), edges(&grid.ys));
    let xr = auto_range(
        ex.iter().copied(),
        fig.x_range.or(Some((ex[0], ex[ex.len() - 1]))),
    );
    let yr = auto_range(
        ey.iter().copied(),
        fig.y_range.or(Some((ey[0], ey[ey.len() - 1]))),
    );
    let mut chart = axes(&main, fig, xr, yr)?;
    let mut occ = occupancy(&chart);
    draw_mark_lines(&mut chart, fig)?;
    draw_mark_labels(&mut chart, fig, &mut occ)?;
    let nx = grid.xs.len();
    let colour = |v: f64| {
        if v.is_finite() {
            viridis((v - zr.start) / (zr.end - zr.start))
        } else {
            RGBColor(200, 200, 200)
        }
    };
    chart
        .draw_series((0..grid.ys.len()).flat_map(|iy| {
            let (ex, ey) = (&ex, &ey);
            (0..nx).map(move |ix| {
                let v = grid.values[iy * nx + ix];
                Rectangle::new(
                    [(ex[ix], ey[iy]), (ex[ix + 1], ey[iy + 1])],
                    colour(v).filled(),
                )
            })
        }))
        .map_err(|e| e.to_string())?;
    // Colour bar, aligned with the plot area (same top margin and bottom label area).
    let mut cb = ChartBuilder::on(&bar)
        .margin(12)
        .margin_left(8)
        .x_label_area_size(62)
        .right_y_label_area_size(95)
        .build_cartesian_2d(
            Axis {
                lo: 0.0,
                hi: 1.0,
                log: false,
            },
            Axis {
                lo: zr.start,
                hi: zr.end,
                log: false,
            },
        )
        .map_err(|e| e.to_string())?;
    let steps = 256;
    let dz = (zr.end - zr.start) / steps as f64;
    cb.draw_series((0..steps).map(|k| {
        let z0 = zr.start + k as f64 * dz;
        Rectangle::new([(0.0, z0), (1.0, z0 + dz)], colour(z0 + 0.5 * dz).filled())
    }))
    .map_err(|e| e.to_string())?;
    // The mesh draws only the axis and its title; ticks and labels are ours, so that they
    // sit clear of the bar.
    let blank = |_: &f64| String::new();
    cb.configure_mesh()
        .disable_x_mesh()
        .disable_y_mesh()
        .disable_x_axis()
        .y_desc(bar_label)
        .y_label_formatter(&blank)
        .axis_desc_style(("sans-serif", 22))
        .y_labels(2)
        .draw()
        .map_err(|e| e.to_string())?;
    let font = ("sans-serif", 18).into_font();
    for v in multiples(zr.start, zr.end, nice_step(zr.start, zr.end, 8)) {
        let (px, py) = cb.backend_coord(&(1.0, v));
        root.draw(&PathElement::new(vec![(px, py), (px + 7, py)], BLACK))
            .map_err(|e| e.to_string())?;
        root.draw(&Text::new(tick_label(v), (px + 11, py - 9), font.clone()))
            .map_err(|e| e.to_string())?;
    }
    Ok(())
}

/// A heat map of `grid` with a colour bar labelled `bar_label` (viridis; NaN cells grey).
/// Linear axes only. Writes `path` and the CSV (`fig.x_column`, `fig.y_column`, `value`).
pub fn heatmap(
    path: impl AsRef<Path>,
    fig: &Figure,
    grid: &Grid,
    bar_label: &str,
) -> Result<(), PlotError> {
    let path = path.as_ref();
    let (nx, ny) = (grid.xs.len(), grid.ys.len());
    if nx == 0 || ny == 0 || grid.values.len() != nx * ny {
        return Err(perr(
            path,
            format!(
                "grid has {nx} × {ny} cells but {} values",
                grid.values.len()
            ),
        ));
    }
    // The colour bar spans exactly the finite values (no padding) unless a range is given.
    let zr = match grid.z_range {
        Some((a, b)) if a.is_finite() && b.is_finite() && a < b => a..b,
        _ => {
            let finite = grid.values.iter().copied().filter(|v| v.is_finite());
            let lo = finite.clone().fold(f64::INFINITY, f64::min);
            let hi = finite.fold(f64::NEG_INFINITY, f64::max);
            if !lo.is_finite() {
                0.0..1.0
            } else if hi > lo {
                lo..hi
            } else {
                lo - 0.5..hi + 0.5
            }
        }
    };
    on_backend!(path, fig.size, draw_heatmap_chart(fig, grid, zr, bar_label))?;
    let mut w = CsvWriter::create(csv_path(path), &[&fig.x_column, &fig.y_column, "value"])
        .map_err(|e| perr(path, e))?;
    for iy in 0..ny {
        for ix in 0..nx {
            w.row(&[grid.xs[ix], grid.ys[iy], grid.values[iy * nx + ix]])
                .map_err(|e| perr(path, e))?;
        }
    }
    w.finish().map_err(|e| perr(path, e))
}

/// One category of a [`category_map`]: its legend text and colour.
#[derive(Debug, Clone)]
pub struct Category {
    /// Legend text.
    pub label: String,
    /// Fill colour.
    pub colour: RGBColor,
}

/// Cells of a rectangular grid, each in one category of a [`category_map`] (or none).
#[derive(Debug, Clone)]
pub struct CategoryGrid {
    /// Cell centres along x (increasing).
    pub xs: Vec<f64>,
    /// Cell centres along y (increasing).
    pub ys: Vec<f64>,
    /// Category index of each cell, row by row (`cells[iy * xs.len() + ix]`); `None` is drawn
    /// light grey.
    pub cells: Vec<Option<usize>>,
}

fn draw_category_chart<DB: DrawingBackend>(
    root: &DrawingArea<DB, Shift>,
    fig: &Figure,
    grid: &CategoryGrid,
    legend: &[Category],
) -> Result<(), String> {
    root.fill(&WHITE).map_err(|e| e.to_string())?;
    let body = fit_title(&root.margin(6, 0, 0, 0), &fig.title)?;
    let (w, _) = body.dim_in_pixel();
    // Wide enough for the longest legend line (about 10 px a character at this size).
    let longest = legend
        .iter()
        .map(|l| l.label.chars().count())
        .max()
        .unwrap_or(0) as u32;
    let panel = (60 + 10 * longest).clamp(160, w / 2);
    let (main, side) = body.split_horizontally(w.saturating_sub(panel));
    let (ex, ey) = (edges(&grid.xs), edges(&grid.ys));
    let xr = auto_range(
        ex.iter().copied(),
        fig.x_range.or(Some((ex[0], ex[ex.len() - 1]))),
    );
    let yr = auto_range(
        ey.iter().copied(),
        fig.y_range.or(Some((ey[0], ey[ey.len() - 1]))),
    );
    let mut chart = axes(&main, fig, xr, yr)?;
    let mut occ = occupancy(&chart);
    draw_mark_lines(&mut chart, fig)?;
    draw_mark_labels(&mut chart, fig, &mut occ)?;
    let nx = grid.xs.len();
    let none = RGBColor(225, 225, 225);
    let colour = |c: Option<usize>| c.and_then(|k| legend.get(k)).map_or(none, |l| l.colour);
    chart
        .draw_series((0..grid.ys.len()).flat_map(|iy| {
            let (ex, ey) = (&ex, &ey);
            (0..nx).map(move |ix| {
                Rectangle::new(
                    [(ex[ix], ey[iy]), (ex[ix + 1], ey[iy + 1])],
                    colour(grid.cells[iy * nx + ix]).filled(),
                )
            })
        }))
        .map_err(|e| e.to_string())?;
    for (label, pts) in &fig.overlays {
        let pts: Vec<(f64, f64)> = pts
            .iter()
            .copied()
            .filter(|p| p.0.is_finite() && p.1.is_finite())
            .collect();
        chart
            .draw_series(LineSeries::new(pts.iter().copied(), WHITE.stroke_width(6)))
            .map_err(|e| e.to_string())?;
        chart
            .draw_series(LineSeries::new(pts.iter().copied(), BLACK.stroke_width(3)))
            .map_err(|e| e.to_string())?;
        if let Some(&last) = pts.last() {
            chart
                .draw_series(std::iter::once(
                    EmptyElement::at(last)
                        + Text::new(
                            label.clone(),
                            (-10, -26),
                            ("sans-serif", 18).into_font().color(&BLACK),
                        ),
                ))
                .map_err(|e| e.to_string())?;
        }
    }
    for (x, y, label) in &fig.pins {
        if !(x.is_finite() && y.is_finite()) {
            continue;
        }
        let cross = |colour: RGBColor, width: u32, r: i32| {
            EmptyElement::at((*x, *y))
                + PathElement::new(vec![(-r, -r), (r, r)], colour.stroke_width(width))
                + PathElement::new(vec![(-r, r), (r, -r)], colour.stroke_width(width))
        };
        chart
            .draw_series([cross(WHITE, 5, 8), cross(BLACK, 2, 7)])
            .map_err(|e| e.to_string())?;
        chart
            .draw_series(std::iter::once(
                EmptyElement::at((*x, *y))
                    + Text::new(
                        label.clone(),
                        (10, -22),
                        ("sans-serif", 18).into_font().color(&BLACK),
                    ),
            ))
            .map_err(|e| e.to_string())?;
    }
    // The legend: a colour box and the text, one line per category.
    let font = ("sans-serif", 18).into_font();
    let mut y = 30;
    for l in legend {
        side.draw(&Rectangle::new([(8, y), (30, y + 20)], l.colour.filled()))
            .map_err(|e| e.to_string())?;
        side.draw(&Rectangle::new(
            [(8, y), (30, y + 20)],
            BLACK.stroke_width(1),
        ))
        .map_err(|e| e.to_string())?;
        side.draw(&Text::new(l.label.clone(), (38, y + 1), font.clone()))
            .map_err(|e| e.to_string())?;
        y += 30;
    }
    Ok(())
}

/// A map of categories on a grid (basins of attraction, periods over two parameters), with a
/// legend on the right. Linear axes only. Writes `path` and the CSV (`fig.x_column`,
/// `fig.y_column`, `category` (the index, empty for none), `label`).
pub fn category_map(
    path: impl AsRef<Path>,
    fig: &Figure,
    grid: &CategoryGrid,
    legend: &[Category],
) -> Result<(), PlotError> {
    let path = path.as_ref();
    let (nx, ny) = (grid.xs.len(), grid.ys.len());
    if nx == 0 || ny == 0 || grid.cells.len() != nx * ny {
        return Err(perr(
            path,
            format!("grid has {nx} × {ny} cells but {} values", grid.cells.len()),
        ));
    }
    on_backend!(path, fig.size, draw_category_chart(fig, grid, legend))?;
    let mut w = CsvWriter::create(
        csv_path(path),
        &[&fig.x_column, &fig.y_column, "category", "label"],
    )
    .map_err(|e| perr(path, e))?;
    for iy in 0..ny {
        for ix in 0..nx {
            let c = grid.cells[iy * nx + ix];
            let label = c
                .and_then(|k| legend.get(k))
                .map_or("", |l| l.label.as_str());
            w.record(&[
                super::csv::fmt_f64(grid.xs[ix]),
                super::csv::fmt_f64(grid.ys[iy]),
                c.map_or(String::new(), |k| k.to_string()),
                label.to_string(),
            ])
            .map_err(|e| perr(path, e))?;
        }
    }
    w.finish().map_err(|e| perr(path, e))
}

/// Two panels sharing the x axis, one above the other: a line plot (`top`, `series`) over a
/// bifurcation diagram (`bottom`, `points` as small dark dots), e.g. the largest Lyapunov
/// exponent over the diagram it explains. The picture is `top.size` wide and the two panels'
/// heights tall. Writes `path` and the CSVs of the panels (`<stem>_top.csv`: `series`,
/// `top.x_column`, `top.y_column`; `<stem>_bottom.csv`: `bottom.x_column`, `bottom.y_column`).
pub fn lines_over_points(
    path: impl AsRef<Path>,
    top: &Figure,
    series: &[Series],
    bottom: &Figure,
    points: &[(f64, f64)],
) -> Result<(), PlotError> {
    let path = path.as_ref();
    let size = (top.size.0, top.size.1 + bottom.size.1);
    let mapped: Vec<(f64, f64)> = points.iter().filter_map(|&p| bottom.map(p)).collect();
    let split = top.size.1;
    on_backend!(
        path,
        size,
        draw_stacked(top, series, bottom, &mapped, split)
    )?;
    let stem = path
        .file_stem()
        .map_or("figure".into(), |s| s.to_string_lossy().into_owned());
    write_series_csv(&path.with_file_name(format!("{stem}_top.png")), top, series)?;
    let bottom_csv = path.with_file_name(format!("{stem}_bottom.csv"));
    let mut w = CsvWriter::create(&bottom_csv, &[&bottom.x_column, &bottom.y_column])
        .map_err(|e| perr(path, e))?;
    for &(x, y) in points {
        w.row(&[x, y]).map_err(|e| perr(path, e))?;
    }
    w.finish().map_err(|e| perr(path, e))
}

fn draw_stacked<DB: DrawingBackend>(
    root: &DrawingArea<DB, Shift>,
    top: &Figure,
    series: &[Series],
    bottom: &Figure,
    points: &[(f64, f64)],
    split: u32,
) -> Result<(), String> {
    let (upper, lower) = root.split_vertically(split);
    draw_lines_chart(&upper, top, series)?;
    draw_points_chart(
        &lower,
        bottom,
        &[points.to_vec()],
        &[""],
        Some(RGBColor(20, 20, 70)),
    )
}

/// A continued branch for [`branches`]: pieces of curve, each stable (drawn solid) or not
/// (dashed), in one colour.
#[derive(Debug, Clone)]
pub struct BranchCurve {
    /// Legend text (empty: not in the legend).
    pub label: String,
    /// Colour.
    pub colour: RGBColor,
    /// The pieces: points and whether the orbit is stable there.
    pub pieces: Vec<(Vec<(f64, f64)>, bool)>,
}

fn draw_branches_chart<DB: DrawingBackend>(
    root: &DrawingArea<DB, Shift>,
    fig: &Figure,
    background: &[(f64, f64)],
    curves: &[BranchCurve],
    points: &[(f64, f64, String)],
) -> Result<(), String> {
    root.fill(&WHITE).map_err(|e| e.to_string())?;
    let all: Vec<(f64, f64)> = background
        .iter()
        .copied()
        .chain(
            curves
                .iter()
                .flat_map(|c| c.pieces.iter().flat_map(|p| p.0.iter().copied())),
        )
        .collect();
    let (xr, yr) = ranges(fig, &all);
    let area = fit_title(&root.margin(6, 0, 0, 0), &fig.title)?;
    let mut chart = axes(&area, fig, xr, yr)?;
    let mut occ = occupancy(&chart);
    draw_mark_lines(&mut chart, fig)?;
    draw_dots(&mut chart, background, RGBColor(90, 90, 90), 2, 0.7)?;
    occupy(&mut occ, &chart, background, false);
    for c in curves {
        let colour = c.colour;
        for (piece, stable) in &c.pieces {
            occupy(&mut occ, &chart, piece, true);
            let style = colour.stroke_width(3);
            if *stable {
                chart
                    .draw_series(LineSeries::new(piece.iter().copied(), style))
                    .map_err(|e| e.to_string())?;
            } else {
                chart
                    .draw_series(DashedLineSeries::new(piece.iter().copied(), 8, 6, style))
                    .map_err(|e| e.to_string())?;
            }
        }
        if !c.label.is_empty() {
            chart
                .draw_series(std::iter::empty::<Circle<(f64, f64), i32>>())
                .map_err(|e| e.to_string())?
                .label(c.label.as_str())
                .legend(move |(x, y)| {
                    PathElement::new(vec![(x, y), (x + 18, y)], colour.stroke_width(3))
                });
        }
    }
    draw_point_labels(&mut chart, points, &mut occ)?;
    draw_mark_labels(&mut chart, fig, &mut occ)?;
    if curves.iter().any(|c| !c.label.is_empty()) {
        let labels: Vec<&str> = curves.iter().map(|c| c.label.as_str()).collect();
        draw_legend(&mut chart, fig, &labels, &mut occ)?;
    }
    draw_note(&mut chart, fig, &mut occ)
}

/// Special points: a ring each, and a label placed clear of the other labels and, as far as
/// possible, of the curves. A label repeated within 24 pixels (the same point found from two
/// branches, or twice at the bracket's two ends) is drawn once.
fn draw_point_labels<DB: DrawingBackend>(
    chart: &mut Chart<'_, DB>,
    points: &[(f64, f64, String)],
    occ: &mut Occupancy,
) -> Result<(), String> {
    let mut kept: Vec<((i32, i32), &str)> = Vec::new();
    let (xr, yr) = (chart.x_range(), chart.y_range());
    for (x, y, label) in points {
        // Points beyond the axes (a branch continued past the range) are not drawn.
        if !(xr.contains(x) && yr.contains(y)) {
            continue;
        }
        let at = chart.backend_coord(&(*x, *y));
        let near = |(p, l): &((i32, i32), &str)| {
            l == label && (p.0 - at.0).abs() < 24 && (p.1 - at.1).abs() < 24
        };
        if !kept.iter().any(near) {
            kept.push((at, label.as_str()));
        }
    }
    // The rings first, so that no label covers one.
    for &(at, _) in &kept {
        occ.label((at.0 - 7, at.1 - 7, at.0 + 7, at.1 + 7));
    }
    let area = chart.plotting_area().strip_coord_spec();
    let (px, py) = chart.plotting_area().get_pixel_range();
    for &(at, label) in &kept {
        let (bx, by) = (at.0 - px.start, at.1 - py.start);
        area.draw(&Circle::new((bx, by), 6, BLACK.stroke_width(2)))
            .map_err(|e| e.to_string())?;
        let size = text_size(chart, label, 16);
        let candidates = around(at, size, 6);
        let r = candidates[occ.place(&candidates)];
        area.draw(&Text::new(
            label.to_string(),
            (r.0 - px.start, r.1 - py.start),
            ("sans-serif", 16),
        ))
        .map_err(|e| e.to_string())?;
    }
    Ok(())
}

/// Continued branches (stable solid, unstable dashed) over a brute-force diagram drawn as grey
/// dots, with labelled special points. Writes `path` and the CSV of the branches (`branch`,
/// `stable`, `fig.x_column`, `fig.y_column`).
pub fn branches(
    path: impl AsRef<Path>,
    fig: &Figure,
    background: &[(f64, f64)],
    curves: &[BranchCurve],
    points: &[(f64, f64, String)],
) -> Result<(), PlotError> {
    let path = path.as_ref();
    on_backend!(
        path,
        fig.size,
        draw_branches_chart(fig, background, curves, points)
    )?;
    let mut w = CsvWriter::create(
        csv_path(path),
        &["branch", "stable", &fig.x_column, &fig.y_column],
    )
    .map_err(|e| perr(path, e))?;
    for (i, c) in curves.iter().enumerate() {
        for (piece, stable) in &c.pieces {
            for &(x, y) in piece {
                w.record(&[
                    if c.label.is_empty() {
                        i.to_string()
                    } else {
                        c.label.clone()
                    },
                    stable.to_string(),
                    super::csv::fmt_f64(x),
                    super::csv::fmt_f64(y),
                ])
                .map_err(|e| perr(path, e))?;
            }
        }
    }
    w.finish().map_err(|e| perr(path, e))
}

/// The symbol of a parameter for a figure (Unicode, as `docs/model.md` writes it) from its
/// ASCII name in flags, CSV columns and JSON (`SweepParameter::symbol`): `"eta"` → `"η"`,
/// `"nu1"` → `"ν₁"`, `"ex"` → `"eₓ"`, ...; unknown names are returned as they are.
pub fn symbol(ascii: &str) -> &str {
    match ascii {
        "eta" => "η",
        "nu1" => "ν₁",
        "nu2" => "ν₂",
        "beta" => "β",
        "phi0" => "φ₀",
        "ex" => "eₓ",
        // Unicode has no subscript y.
        "ey" => "e_y",
        "Dx" => "Dₓ",
        "x0" => "x₀ (rotor, units of the gap γ)",
        "y0" => "y₀ (rotor, units of the gap γ)",
        "vx0" => "x₀′ = dx/dτ at τ = 0",
        other => other,
    }
}
