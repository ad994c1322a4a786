//! The report's figure style, written once: panels of line and marker series on linear or
//! logarithmic axes, laid out at their final printed size and written as self-contained SVG.
//!
//! Every figure is laid out in points (1/72 in) at its printed size, so a font size of 8 is
//! 8 pt on paper. Legends go outside the axes (right of or below a panel, or below the whole
//! figure); a legend inside the axes is possible only at a corner, and the figure test rejects
//! it when it covers data.
//!
//! [`layout`] computes every text's box, every data mark and every axes rectangle before
//! anything is written; [`Layout::svg`] only draws it, through plotters' SVG backend (the
//! project's drawing backend), on a canvas of [`SVG_UNITS_PER_PT`] integer units per pt, so
//! positions keep two decimals of a point (no whole-pixel stair-steps). The SVG's
//! `width`/`height` state the printed size in millimetres and its viewBox the canvas. The
//! figure test checks the layout (text sizes, overlaps, marks inside their axes) with the
//! glyph-width bound of [`text_width`].

use mass_spring_solvers::error::{Error, Result};
use plotters::backend::{DrawingBackend, SVGBackend};
use plotters::style::text_anchor::{HPos, Pos, VPos};
use plotters::style::{Color, FontTransform, RGBColor, ShapeStyle, TextStyle};
use plotters_backend::{BackendCoord, DrawingErrorKind};

/// Points per millimetre.
pub const PT_PER_MM: f64 = 72.0 / 25.4;
/// Width of a two-panel (full text width) figure, mm.
pub const FULL_WIDTH_MM: f64 = 170.0;
/// Width of a one-column figure, mm.
pub const COLUMN_WIDTH_MM: f64 = 84.0;

/// Tick, legend and label text, pt.
const TEXT_PT: f64 = 8.0;
/// Axis titles, pt.
const TITLE_PT: f64 = 8.5;
/// Panel tags "(a)", pt.
const TAG_PT: f64 = 9.0;
/// Data lines, pt.
const LINE_PT: f64 = 1.2;
/// Axes frame and ticks, pt.
const FRAME_PT: f64 = 0.6;
/// Major grid lines, pt.
const GRID_PT: f64 = 0.35;
/// Marker radius, pt.
const MARKER_PT: f64 = 2.4;
/// Length of a major tick, pt.
const TICK_PT: f64 = 3.0;
/// Legend swatch width, pt.
const SWATCH_PT: f64 = 16.0;
/// Free space kept between data and the axes frame, pt.
const EDGE_PAD_PT: f64 = 6.0;
/// The generic family: the SVG carries no font, and renders alike in browsers and librsvg.
const FONT: &str = "sans-serif";
/// SVG canvas units per pt. plotters' backend draws on integer coordinates; at 100 units per
/// pt every position, stroke width and font size keeps two decimals of a point.
pub const SVG_UNITS_PER_PT: f64 = 100.0;

/// Top of a glyph box above the baseline, em (DejaVu Sans ascent of digits and capitals).
pub const ASCENT_EM: f64 = 0.78;
/// Bottom of a glyph box below the baseline, em (descenders of g, p, y and subscripts).
pub const DESCENT_EM: f64 = 0.26;

/// An upper bound on the advance width of a character, em, by class: the widths of DejaVu
/// Sans (the widest common sans-serif, and librsvg's default here) rounded up. Arial,
/// Helvetica and Liberation Sans are narrower, so a box built from it holds the text.
pub fn glyph_width_em(c: char) -> f64 {
    match c {
        'i' | 'j' | 'l' | 'I' | 'J' | '.' | ',' | ':' | ';' | '\'' | '|' | '!' | '·' => 0.32,
        'f' | 't' | 'r' | '(' | ')' | '[' | ']' | '-' | ' ' | '/' => 0.42,
        '⁰'..='⁹' | '₀'..='₉' | '¹' | '²' | '³' => 0.42,
        // DejaVu's superscript minus is wider than its superscript digits.
        '⁻' => 0.54,
        'm' | 'w' | 'M' | 'W' | '%' | '…' => 1.0,
        'A'..='Z' | '=' | '+' | '×' | '−' | '<' | '>' | '≈' | '≤' | '≥' | '∇' | '∆' | '±' => {
            0.84
        }
        _ => 0.64,
    }
}

/// The width bound of a text at a font size, pt.
pub fn text_width(text: &str, size: f64) -> f64 {
    text.chars().map(glyph_width_em).sum::<f64>() * size
}

/// An sRGB colour.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub struct Rgb(pub u8, pub u8, pub u8);

pub const WHITE: Rgb = Rgb(255, 255, 255);
const FRAME_COLOUR: Rgb = Rgb(60, 60, 60);
const GRID_COLOUR: Rgb = Rgb(222, 222, 222);

/// How a series' points are joined.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Line {
    Solid,
    Dashed,
    Dotted,
    /// Markers only.
    None,
}

impl Line {
    /// The dash pattern, on and off lengths in pt.
    fn dash(self) -> Option<&'static [f64]> {
        match self {
            Line::Dashed => Some(&[4.5, 2.5]),
            Line::Dotted => Some(&[1.2, 2.0]),
            _ => None,
        }
    }
}

/// The marker at each point of a series.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Marker {
    None,
    Circle,
    Triangle,
    Square,
    Cross,
}

/// How a series looks, also in a legend.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Style {
    pub color: Rgb,
    pub line: Line,
    pub marker: Marker,
    /// Filled markers (ours) or hollow (published).
    pub filled: bool,
    /// Line width, pt.
    pub width: f64,
    /// Marker radius, pt.
    pub radius: f64,
}

/// One series of a panel.
#[derive(Debug, Clone, PartialEq)]
pub struct Series {
    /// Legend text; empty for no legend entry.
    pub label: String,
    /// Points in data coordinates; a NaN point breaks the line.
    pub points: Vec<(f64, f64)>,
    pub style: Style,
    /// Draw a marker at every `marker_every`-th point only (1: all).
    pub marker_every: usize,
}

impl Series {
    /// A solid line without markers.
    pub fn line(label: impl Into<String>, points: Vec<(f64, f64)>, color: Rgb) -> Self {
        Self {
            label: label.into(),
            points,
            style: Style {
                color,
                line: Line::Solid,
                marker: Marker::None,
                filled: true,
                width: LINE_PT,
                radius: MARKER_PT,
            },
            marker_every: 1,
        }
    }

    /// Markers only.
    pub fn points(label: impl Into<String>, points: Vec<(f64, f64)>, color: Rgb) -> Self {
        Self::line(label, points, color).with_line(Line::None)
    }

    /// The same series with markers.
    pub fn with_marker(mut self, marker: Marker, filled: bool) -> Self {
        self.style.marker = marker;
        self.style.filled = filled;
        self
    }

    /// The same series with another line kind.
    pub fn with_line(mut self, line: Line) -> Self {
        self.style.line = line;
        self
    }

    /// The same series with a line width `factor` times the standard one.
    pub fn with_weight(mut self, factor: f64) -> Self {
        self.style.width = LINE_PT * factor;
        self
    }

    /// The same series with a marker radius `factor` times the standard one.
    pub fn with_marker_scale(mut self, factor: f64) -> Self {
        self.style.radius = MARKER_PT * factor;
        self
    }

    /// The same series with a marker at every `n`-th point only.
    pub fn with_marker_every(mut self, n: usize) -> Self {
        self.marker_every = n.max(1);
        self
    }
}

/// One axis.
#[derive(Debug, Clone, PartialEq)]
pub struct Axis {
    /// Title with unit, `Δt (s)`.
    pub label: String,
    pub log: bool,
    /// Fixed range; otherwise the data's extent with room for the markers.
    pub range: Option<(f64, f64)>,
}

impl Axis {
    /// A linear axis with an automatic range.
    pub fn linear(label: impl Into<String>) -> Self {
        Self {
            label: label.into(),
            log: false,
            range: None,
        }
    }

    /// A logarithmic axis with an automatic range.
    pub fn log(label: impl Into<String>) -> Self {
        Self {
            label: label.into(),
            log: true,
            range: None,
        }
    }

    /// The same axis with a fixed range.
    pub fn range(mut self, lo: f64, hi: f64) -> Self {
        self.range = Some((lo, hi));
        self
    }
}

/// A corner of the axes.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Corner {
    UpperLeft,
    UpperRight,
    LowerLeft,
    LowerRight,
}

/// Where a panel's legend goes.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum LegendPlace {
    /// Outside the axes, under the x-axis title (the default: a legend to the right would take
    /// the width from the data).
    Below,
    /// Inside the axes at a corner: only where no data is.
    Inside(Corner),
}

/// Horizontal alignment of a label on its anchor.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Align {
    Start,
    Middle,
    End,
}

/// A text placed at a data point, shifted by `offset` pt (x right, y up) from it; the
/// anchor is the text's baseline.
#[derive(Debug, Clone, PartialEq)]
pub struct Label {
    pub at: (f64, f64),
    pub offset: (f64, f64),
    pub align: Align,
    pub text: String,
    pub color: Rgb,
}

/// An arrow between two data points, its head at `to`.
#[derive(Debug, Clone, PartialEq)]
pub struct Arrow {
    pub from: (f64, f64),
    pub to: (f64, f64),
    pub color: Rgb,
}

/// A shaded region between two curves on the same x values (drawn under the data, not a
/// data mark).
#[derive(Debug, Clone, PartialEq)]
pub struct Band {
    pub lower: Vec<(f64, f64)>,
    pub upper: Vec<(f64, f64)>,
    pub color: Rgb,
}

/// One chart.
#[derive(Debug, Clone, PartialEq)]
pub struct Panel {
    pub x: Axis,
    pub y: Axis,
    /// Drawn in order: put the reference last to draw it on top.
    pub series: Vec<Series>,
    pub labels: Vec<Label>,
    pub arrows: Vec<Arrow>,
    pub bands: Vec<Band>,
    pub legend: LegendPlace,
    /// Frame, ticks and axis titles (off for schematic drawings).
    pub frame: bool,
    /// Equal scales on x and y (geometry drawn to scale): the range of the axis with room to
    /// spare grows.
    pub equal_aspect: bool,
    /// A short key after the panel's tag, `(a) XPBD` (not a title: the caption says what is
    /// drawn).
    pub heading: String,
}

impl Panel {
    /// An empty panel.
    pub fn new(x: Axis, y: Axis) -> Self {
        Self {
            x,
            y,
            series: Vec::new(),
            labels: Vec::new(),
            arrows: Vec::new(),
            bands: Vec::new(),
            legend: LegendPlace::Below,
            frame: true,
            equal_aspect: false,
            heading: String::new(),
        }
    }

    /// Adds a text at a data point, shifted by `offset` pt.
    pub fn label(
        &mut self,
        at: (f64, f64),
        offset: (f64, f64),
        align: Align,
        text: impl Into<String>,
        color: Rgb,
    ) {
        self.labels.push(Label {
            at,
            offset,
            align,
            text: text.into(),
            color,
        });
    }
}

/// A legend entry.
#[derive(Debug, Clone, PartialEq)]
pub struct Entry {
    pub label: String,
    pub style: Style,
}

/// A figure: panels in a grid at a printed size, with an optional legend under them.
#[derive(Debug, Clone, PartialEq)]
pub struct Chart {
    pub width_mm: f64,
    pub height_mm: f64,
    pub columns: usize,
    pub panels: Vec<Panel>,
    /// Entries shared by every panel, drawn under the grid.
    pub legend: Vec<Entry>,
}

impl Chart {
    /// Panels side by side at a printed size.
    pub fn new(width_mm: f64, height_mm: f64, panels: Vec<Panel>) -> Self {
        let columns = panels.len().max(1);
        Self {
            width_mm,
            height_mm,
            columns,
            panels,
            legend: Vec::new(),
        }
    }
}

/// An axis-aligned rectangle, pt, y down.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Rect {
    pub x0: f64,
    pub y0: f64,
    pub x1: f64,
    pub y1: f64,
}

impl Rect {
    pub fn intersects(&self, o: &Rect) -> bool {
        self.x0 < o.x1 && o.x0 < self.x1 && self.y0 < o.y1 && o.y0 < self.y1
    }

    /// Whether `o` lies inside, within `tolerance` pt.
    pub fn contains(&self, o: &Rect, tolerance: f64) -> bool {
        o.x0 >= self.x0 - tolerance
            && o.x1 <= self.x1 + tolerance
            && o.y0 >= self.y0 - tolerance
            && o.y1 <= self.y1 + tolerance
    }

    /// Whether the segment a-b crosses or touches the rectangle.
    pub fn meets_segment(&self, a: (f64, f64), b: (f64, f64)) -> bool {
        clip_segment(a, b, self).is_some()
    }
}

/// What a text is.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum TextRole {
    Tick,
    AxisTitle,
    PanelTag,
    Legend,
    /// A direct label or annotation inside the axes.
    Label,
}

/// A laid-out text.
#[derive(Debug, Clone, PartialEq)]
pub struct TextBox {
    pub text: String,
    pub role: TextRole,
    /// Font size, pt at the printed size.
    pub size: f64,
    /// Its box from [`text_width`], [`ASCENT_EM`] and [`DESCENT_EM`].
    pub rect: Rect,
    /// Turned by −90° (a y-axis title): the text runs upwards.
    pub rotated: bool,
    /// Baseline anchor, alignment and colour.
    anchor: (f64, f64),
    align: Align,
    color: Rgb,
}

/// A drawn data item of a panel.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Mark {
    /// A marker's box.
    Point(Rect),
    /// A piece of a line, after clipping to the axes.
    Segment((f64, f64), (f64, f64)),
}

/// A series as drawn: its axes, legend text, style and the points inside its axes, pt.
#[derive(Debug, Clone, PartialEq)]
pub struct DrawnSeries {
    pub panel: usize,
    pub label: String,
    pub style: Style,
    pub points: Vec<(f64, f64)>,
}

/// A laid-out figure: every text box, data mark and axes rectangle, pt, y down.
#[derive(Debug, Clone, PartialEq)]
pub struct Layout {
    pub width_mm: f64,
    pub height_mm: f64,
    /// Axes rectangle of each panel.
    pub axes: Vec<Rect>,
    /// The data ranges of each panel's axes, (x, y), each (low, high): with [`Layout::axes`]
    /// they give the scale of each axis, and so a shape's vertical exaggeration.
    pub ranges: Vec<((f64, f64), (f64, f64))>,
    pub texts: Vec<TextBox>,
    /// (panel index, mark).
    pub marks: Vec<(usize, Mark)>,
    /// The box of every legend (swatches and texts).
    pub legends: Vec<Rect>,
    /// Every series in drawing order (a later one is drawn over an earlier one).
    pub series: Vec<DrawnSeries>,
    /// Every legend entry: (index in `legends`, entry).
    pub legend_entries: Vec<(usize, Entry)>,
    shapes: Vec<Shape>,
}

/// A drawing primitive, pt.
#[derive(Debug, Clone, PartialEq)]
enum Shape {
    Path {
        points: Vec<(f64, f64)>,
        stroke: Option<(Rgb, f64, Option<&'static [f64]>)>,
        fill: Option<Rgb>,
        closed: bool,
    },
    Circle {
        centre: (f64, f64),
        r: f64,
        stroke: (Rgb, f64),
        fill: Rgb,
    },
    Text(usize),
}

fn plot_error(message: String) -> Error {
    Error::Input(format!("drawing a figure: {message}"))
}

/// A range with a coordinate transform: linear or log10.
#[derive(Debug, Clone, Copy)]
struct Scale {
    log: bool,
    lo: f64,
    hi: f64,
    /// Screen interval, pt; `a` maps `lo`.
    a: f64,
    b: f64,
}

impl Scale {
    fn t(&self, v: f64) -> f64 {
        if self.log {
            v.log10()
        } else {
            v
        }
    }

    fn map(&self, v: f64) -> f64 {
        let (lo, hi) = (self.t(self.lo), self.t(self.hi));
        self.a + (self.t(v) - lo) / (hi - lo) * (self.b - self.a)
    }

    fn valid(&self, v: f64) -> bool {
        v.is_finite() && (!self.log || v > 0.0)
    }
}

/// Data extent of an axis over a panel's series, labels, arrows and bands.
fn extent(panel: &Panel, pick: impl Fn((f64, f64)) -> f64, log: bool) -> Option<(f64, f64)> {
    let points = panel
        .series
        .iter()
        .flat_map(|s| s.points.iter().copied())
        .chain(panel.labels.iter().map(|l| l.at))
        .chain(panel.arrows.iter().flat_map(|a| [a.from, a.to]))
        .chain(
            panel
                .bands
                .iter()
                .flat_map(|b| b.lower.iter().chain(&b.upper).copied()),
        );
    let (lo, hi) = points
        .map(pick)
        .filter(|v| v.is_finite() && (!log || *v > 0.0))
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), v| {
            (lo.min(v), hi.max(v))
        });
    lo.is_finite().then_some((lo, hi))
}

/// An axis range: fixed, or the data's extent padded by 5 % of it and at least `pad_pt` of
/// the `length_pt` the axis is drawn on, so no marker touches the frame.
fn axis_range(axis: &Axis, data: Option<(f64, f64)>, length_pt: f64) -> (f64, f64) {
    if let Some(r) = axis.range {
        return r;
    }
    let Some((lo, hi)) = data else {
        return if axis.log { (0.1, 10.0) } else { (0.0, 1.0) };
    };
    let (tlo, thi) = if axis.log {
        (lo.log10(), hi.log10())
    } else {
        (lo, hi)
    };
    // A single value gets a decade (log), ±10 % of itself, or ±0.5 around zero.
    let span = if thi > tlo {
        thi - tlo
    } else if axis.log || tlo == 0.0 {
        1.0
    } else {
        0.2 * tlo.abs()
    };
    let fraction = (EDGE_PAD_PT / length_pt.max(1.0)).max(0.05);
    // pad = fraction of the padded span: span + 2 pad = span / (1 - 2 fraction).
    let pad = if thi > tlo {
        span * fraction / (1.0 - 2.0 * fraction).max(0.2)
    } else {
        span / 2.0
    };
    let (a, b) = (tlo - pad, thi + pad);
    if axis.log {
        (10f64.powf(a), 10f64.powf(b))
    } else {
        (a, b)
    }
}

const SUPERSCRIPTS: [char; 10] = ['⁰', '¹', '²', '³', '⁴', '⁵', '⁶', '⁷', '⁸', '⁹'];

/// `10⁻³`: a power of ten with a superscript exponent.
pub fn power_of_ten(exponent: i32) -> String {
    let mut s = String::from("10");
    if exponent < 0 {
        s.push('⁻');
    }
    for d in exponent.unsigned_abs().to_string().bytes() {
        s.push(SUPERSCRIPTS[(d - b'0') as usize]);
    }
    s
}

/// Ticks of a range: (value, label, major). Linear: multiples of 1, 2 or 5 × 10ᵏ, at most six.
/// Log: decades (every second or third when there are many), with 2 and 5 labelled when the
/// range spans less than two decades, and unlabelled minor ticks at 2-9 × 10ᵏ.
fn ticks(lo: f64, hi: f64, log: bool) -> Vec<(f64, String, bool)> {
    if !log {
        let span = hi - lo;
        let raw = span / 6.0;
        let k = raw.log10().floor();
        let base = 10f64.powf(k);
        let step = [1.0, 2.0, 5.0, 10.0]
            .into_iter()
            .map(|m| m * base)
            .find(|s| *s >= raw * 0.999)
            .unwrap_or(10.0 * base);
        let decimals = (-(step.log10().floor())).max(0.0) as usize;
        let first = (lo / step - 1e-9).ceil() as i64;
        let last = (hi / step + 1e-9).floor() as i64;
        return (first..=last)
            .map(|i| {
                let v = i as f64 * step;
                let mut s = format!("{v:.decimals$}");
                if s.starts_with('-') && s.trim_start_matches(['-', '0', '.']).is_empty() {
                    s.remove(0);
                }
                (v, s.replace('-', "−"), true)
            })
            .collect();
    }
    let (a, b) = (lo.log10(), hi.log10());
    let first = (a - 1e-9).ceil() as i32;
    let last = (b + 1e-9).floor() as i32;
    let decades = (last - first + 1).max(0);
    let mut out = Vec::new();
    if decades < 2 {
        let digits = |v: f64| {
            let e = v.log10().floor();
            let decimals = (-e).max(0.0) as usize;
            format!("{v:.decimals$}")
        };
        for e in (a.floor() as i32)..=(b.ceil() as i32) {
            for m in [1.0, 2.0, 5.0] {
                let v = m * 10f64.powi(e);
                if v >= lo * (1.0 - 1e-9) && v <= hi * (1.0 + 1e-9) {
                    out.push((v, digits(v), true));
                }
            }
        }
        return out;
    }
    let every = match decades {
        0..=7 => 1,
        8..=13 => 2,
        _ => 3,
    };
    for e in (a.floor() as i32)..=(b.ceil() as i32) {
        let v = 10f64.powi(e);
        if e >= first && e <= last && (e - first) % every == 0 {
            out.push((v, power_of_ten(e), true));
        }
        if every == 1 && decades <= 5 {
            for m in 2..10 {
                let v = m as f64 * 10f64.powi(e);
                if v > lo && v < hi {
                    out.push((v, String::new(), false));
                }
            }
        }
    }
    out
}

fn text_box(
    text: &str,
    role: TextRole,
    size: f64,
    anchor: (f64, f64),
    align: Align,
    rotated: bool,
    color: Rgb,
) -> TextBox {
    let w = text_width(text, size);
    let start = match align {
        Align::Start => 0.0,
        Align::Middle => -w / 2.0,
        Align::End => -w,
    };
    let (x, y) = anchor;
    let rect = if rotated {
        // Rotated by -90°: the text runs upwards from the anchor.
        Rect {
            x0: x - ASCENT_EM * size,
            x1: x + DESCENT_EM * size,
            y0: y - start - w,
            y1: y - start,
        }
    } else {
        Rect {
            x0: x + start,
            x1: x + start + w,
            y0: y - ASCENT_EM * size,
            y1: y + DESCENT_EM * size,
        }
    };
    TextBox {
        text: text.to_string(),
        role,
        size,
        rect,
        anchor,
        align,
        rotated,
        color,
    }
}

/// Liang-Barsky: the part of segment a-b inside `r`.
fn clip_segment(a: (f64, f64), b: (f64, f64), r: &Rect) -> Option<((f64, f64), (f64, f64))> {
    let (dx, dy) = (b.0 - a.0, b.1 - a.1);
    let (mut t0, mut t1) = (0.0f64, 1.0f64);
    for (p, q) in [
        (-dx, a.0 - r.x0),
        (dx, r.x1 - a.0),
        (-dy, a.1 - r.y0),
        (dy, r.y1 - a.1),
    ] {
        if p == 0.0 {
            if q < 0.0 {
                return None;
            }
        } else {
            let t = q / p;
            if p < 0.0 {
                t0 = t0.max(t);
            } else {
                t1 = t1.min(t);
            }
        }
    }
    (t0 <= t1).then_some((
        (a.0 + t0 * dx, a.1 + t0 * dy),
        (a.0 + t1 * dx, a.1 + t1 * dy),
    ))
}

/// A legend's entries laid out in rows no wider than `max_width`: (entry, x, row) offsets and
/// the block's size.
fn legend_rows(
    entries: &[&Entry],
    max_width: f64,
    one_column: bool,
) -> (Vec<(f64, usize)>, f64, f64) {
    let row_h = TEXT_PT * 1.35;
    let gap = 10.0;
    let mut placed = Vec::new();
    let (mut x, mut row, mut widest) = (0.0f64, 0usize, 0.0f64);
    for e in entries {
        let w = SWATCH_PT + 3.0 + text_width(&e.label, TEXT_PT);
        if x > 0.0 && (one_column || x + w > max_width) {
            row += 1;
            x = 0.0;
        }
        placed.push((x, row));
        x += w + gap;
        widest = widest.max(x - gap);
    }
    let rows = if entries.is_empty() { 0 } else { row + 1 };
    (placed, widest, rows as f64 * row_h)
}

/// The marker outline of `marker` at `c`, radius `r`, as a closed path (None: a circle).
fn marker_path(marker: Marker, c: (f64, f64), r: f64) -> Option<Vec<(f64, f64)>> {
    let (x, y) = c;
    match marker {
        Marker::None | Marker::Circle => None,
        Marker::Square => {
            let h = r * 0.9;
            Some(vec![
                (x - h, y - h),
                (x + h, y - h),
                (x + h, y + h),
                (x - h, y + h),
            ])
        }
        Marker::Triangle => {
            let h = r * 1.15;
            Some(vec![
                (x, y - h),
                (x + h * 0.866, y + h * 0.5),
                (x - h * 0.866, y + h * 0.5),
            ])
        }
        Marker::Cross => Some(vec![(x - r, y - r), (x + r, y + r)]),
    }
}

/// Layout under construction.
struct Builder {
    texts: Vec<TextBox>,
    marks: Vec<(usize, Mark)>,
    legends: Vec<Rect>,
    series: Vec<DrawnSeries>,
    legend_entries: Vec<(usize, Entry)>,
    shapes: Vec<Shape>,
}

impl Builder {
    fn text(&mut self, t: TextBox) -> Rect {
        let rect = t.rect;
        self.texts.push(t);
        self.shapes.push(Shape::Text(self.texts.len() - 1));
        rect
    }

    fn path(
        &mut self,
        points: Vec<(f64, f64)>,
        color: Rgb,
        width: f64,
        dash: Option<&'static [f64]>,
    ) {
        self.shapes.push(Shape::Path {
            points,
            stroke: Some((color, width, dash)),
            fill: None,
            closed: false,
        });
    }

    /// A marker, in a panel (recorded as a data mark) or in a legend.
    fn marker(&mut self, style: &Style, c: (f64, f64), panel: Option<usize>) {
        let r = style.radius;
        let stroke_w = if style.filled { 0.5 } else { 0.9 };
        let fill = if style.filled { style.color } else { WHITE };
        match marker_path(style.marker, c, r) {
            None => self.shapes.push(Shape::Circle {
                centre: c,
                r,
                stroke: (style.color, stroke_w),
                fill,
            }),
            Some(points) if style.marker == Marker::Cross => {
                let (x, y) = c;
                self.path(points, style.color, 1.0, None);
                self.path(vec![(x - r, y + r), (x + r, y - r)], style.color, 1.0, None);
            }
            Some(points) => self.shapes.push(Shape::Path {
                points,
                stroke: Some((style.color, stroke_w, None)),
                fill: Some(fill),
                closed: true,
            }),
        }
        if let Some(p) = panel {
            let h = r * 1.2 + stroke_w / 2.0;
            self.marks.push((
                p,
                Mark::Point(Rect {
                    x0: c.0 - h,
                    x1: c.0 + h,
                    y0: c.1 - h,
                    y1: c.1 + h,
                }),
            ));
        }
    }

    /// A legend block with its top-left corner at `origin`.
    fn legend(&mut self, entries: &[&Entry], origin: (f64, f64), max_width: f64, one_column: bool) {
        if entries.is_empty() {
            return;
        }
        let (placed, w, h) = legend_rows(entries, max_width, one_column);
        let row_h = TEXT_PT * 1.35;
        let legend = self.legends.len();
        for (e, (dx, row)) in entries.iter().zip(placed) {
            self.legend_entries.push((legend, (*e).clone()));
            let x = origin.0 + dx;
            let mid = origin.1 + row as f64 * row_h + row_h / 2.0;
            let s = &e.style;
            if s.line != Line::None {
                // Inset by half the width: the round caps stay inside the swatch.
                let cap = s.width / 2.0;
                self.path(
                    vec![(x + cap, mid), (x + SWATCH_PT - cap, mid)],
                    s.color,
                    s.width,
                    s.line.dash(),
                );
            }
            if s.marker != Marker::None {
                self.marker(s, (x + SWATCH_PT / 2.0, mid), None);
            }
            self.text(text_box(
                &e.label,
                TextRole::Legend,
                TEXT_PT,
                (x + SWATCH_PT + 3.0, mid + 0.3 * TEXT_PT),
                Align::Start,
                false,
                Rgb(0, 0, 0),
            ));
        }
        self.legends.push(Rect {
            x0: origin.0,
            y0: origin.1,
            x1: origin.0 + w,
            y1: origin.1 + h,
        });
    }
}

/// Entries of a panel's labelled series.
fn entries(panel: &Panel) -> Vec<Entry> {
    panel
        .series
        .iter()
        .filter(|s| !s.label.is_empty())
        .map(|s| Entry {
            label: s.label.clone(),
            style: s.style,
        })
        .collect()
}

/// Width of the widest tick label of an axis range, pt.
fn tick_width(lo: f64, hi: f64, log: bool) -> f64 {
    ticks(lo, hi, log)
        .iter()
        .map(|t| text_width(&t.1, TEXT_PT))
        .fold(0.0, f64::max)
}

/// The ranges of a panel drawn on an axes box of `w` × `h` pt.
fn ranges(panel: &Panel, w: f64, h: f64) -> ((f64, f64), (f64, f64)) {
    let xr = axis_range(&panel.x, extent(panel, |p| p.0, panel.x.log), w);
    let yr = axis_range(&panel.y, extent(panel, |p| p.1, panel.y.log), h);
    if !panel.equal_aspect || panel.x.log || panel.y.log {
        return (xr, yr);
    }
    let (sx, sy) = (w / (xr.1 - xr.0), h / (yr.1 - yr.0));
    if sx > sy {
        let half = w / sy / 2.0;
        let c = (xr.0 + xr.1) / 2.0;
        ((c - half, c + half), yr)
    } else {
        let half = h / sx / 2.0;
        let c = (yr.0 + yr.1) / 2.0;
        (xr, (c - half, c + half))
    }
}

/// Lays out a chart at its printed size.
pub fn layout(chart: &Chart) -> Result<Layout> {
    if chart.panels.is_empty() || chart.columns == 0 {
        return Err(plot_error(
            "a chart needs at least one panel and one column".into(),
        ));
    }
    let width = chart.width_mm * PT_PER_MM;
    let height = chart.height_mm * PT_PER_MM;
    let mut b = Builder {
        texts: Vec::new(),
        marks: Vec::new(),
        legends: Vec::new(),
        series: Vec::new(),
        legend_entries: Vec::new(),
        shapes: Vec::new(),
    };
    let outer = 4.0;
    let shared: Vec<&Entry> = chart.legend.iter().collect();
    let (_, _, shared_h) = legend_rows(&shared, width - 2.0 * outer, false);
    let grid_h = height - shared_h - if shared_h > 0.0 { outer + 2.0 } else { 0.0 };
    let rows = chart.panels.len().div_ceil(chart.columns);
    let cell_w = (width - 2.0 * outer) / chart.columns as f64;
    let cell_h = (grid_h - outer) / rows as f64;
    let tags = chart.panels.len() > 1;
    // Legends under the panels take the same height in every panel, so that all axes of a
    // row have the same height and compare at a glance.
    let below_h = chart
        .panels
        .iter()
        .filter(|p| p.legend == LegendPlace::Below)
        .map(|p| {
            let own = entries(p);
            let refs: Vec<&Entry> = own.iter().collect();
            if refs.is_empty() {
                0.0
            } else {
                legend_rows(&refs, cell_w - 8.0, false).2 + 3.0
            }
        })
        .fold(0.0, f64::max);
    let mut axes = Vec::new();
    let mut ranges_drawn = Vec::new();
    for (index, panel) in chart.panels.iter().enumerate() {
        let cx = outer + (index % chart.columns) as f64 * cell_w;
        let cy = outer + (index / chart.columns) as f64 * cell_h;
        let own: Vec<Entry> = entries(panel);
        let own_refs: Vec<&Entry> = own.iter().collect();
        let top = if tags || !panel.heading.is_empty() {
            TAG_PT * 1.4
        } else {
            TEXT_PT * 0.6
        };
        let right = TEXT_PT * 1.2;
        let bottom_axis = if panel.frame {
            TICK_PT + 2.0 + TEXT_PT * 1.1 + 3.0 + TITLE_PT * 1.1
        } else {
            2.0
        };
        // The y tick labels depend on the range, and the range (equal aspect) on the box.
        let mut left = if panel.frame { 30.0 } else { 2.0 };
        let mut frame = Rect {
            x0: 0.0,
            y0: 0.0,
            x1: 0.0,
            y1: 0.0,
        };
        let mut xr = (0.0, 1.0);
        let mut yr = (0.0, 1.0);
        for _ in 0..3 {
            let w = cell_w - left - right;
            let h = cell_h - top - bottom_axis - below_h;
            if w < 20.0 || h < 10.0 {
                return Err(plot_error(format!(
                    "panel {} does not fit in {} × {} mm",
                    index + 1,
                    chart.width_mm,
                    chart.height_mm
                )));
            }
            (xr, yr) = ranges(panel, w, h);
            frame = Rect {
                x0: cx + left,
                y0: cy + top,
                x1: cx + left + w,
                y1: cy + top + h,
            };
            let needed = if panel.frame {
                tick_width(yr.0, yr.1, panel.y.log) + TICK_PT + 3.0 + TITLE_PT * 1.3 + 2.0
            } else {
                2.0
            };
            if (needed - left).abs() < 0.5 {
                break;
            }
            left = needed;
        }
        let sx = Scale {
            log: panel.x.log,
            lo: xr.0,
            hi: xr.1,
            a: frame.x0,
            b: frame.x1,
        };
        let sy = Scale {
            log: panel.y.log,
            lo: yr.0,
            hi: yr.1,
            a: frame.y1,
            b: frame.y0,
        };
        draw_panel(&mut b, index, panel, &frame, &sx, &sy)?;
        ranges_drawn.push((xr, yr));
        if tags || !panel.heading.is_empty() {
            let tag = if tags {
                format!("({}) {}", (b'a' + index as u8) as char, panel.heading)
            } else {
                panel.heading.clone()
            };
            b.text(text_box(
                tag.trim_end(),
                TextRole::PanelTag,
                TAG_PT,
                (cx + 1.0, cy + TAG_PT * 0.9),
                Align::Start,
                false,
                Rgb(0, 0, 0),
            ));
        }
        match panel.legend {
            LegendPlace::Below => b.legend(
                &own_refs,
                (cx + 4.0, frame.y1 + bottom_axis + 1.0),
                cell_w - 8.0,
                false,
            ),
            LegendPlace::Inside(corner) => {
                let (_, w, h) = legend_rows(&own_refs, f64::INFINITY, true);
                let inset = 4.0;
                let x = match corner {
                    Corner::UpperLeft | Corner::LowerLeft => frame.x0 + inset,
                    _ => frame.x1 - inset - w,
                };
                let y = match corner {
                    Corner::UpperLeft | Corner::UpperRight => frame.y0 + inset,
                    _ => frame.y1 - inset - h,
                };
                b.legend(&own_refs, (x, y), f64::INFINITY, true);
            }
        }
        axes.push(frame);
    }
    if !shared.is_empty() {
        let (_, w, _) = legend_rows(&shared, width - 2.0 * outer, false);
        b.legend(
            &shared,
            ((width - w) / 2.0, grid_h + 2.0),
            width - 2.0 * outer,
            false,
        );
    }
    Ok(Layout {
        width_mm: chart.width_mm,
        height_mm: chart.height_mm,
        axes,
        ranges: ranges_drawn,
        texts: b.texts,
        marks: b.marks,
        legends: b.legends,
        series: b.series,
        legend_entries: b.legend_entries,
        shapes: b.shapes,
    })
}

fn draw_panel(
    b: &mut Builder,
    index: usize,
    panel: &Panel,
    frame: &Rect,
    sx: &Scale,
    sy: &Scale,
) -> Result<()> {
    let to_pt = |p: (f64, f64)| (sx.map(p.0), sy.map(p.1));
    let valid = |p: &(f64, f64)| sx.valid(p.0) && sy.valid(p.1);
    if panel.frame {
        for (v, text, major) in ticks(sx.lo, sx.hi, sx.log) {
            let x = sx.map(v);
            if major {
                b.path(
                    vec![(x, frame.y0), (x, frame.y1)],
                    GRID_COLOUR,
                    GRID_PT,
                    None,
                );
                b.text(text_box(
                    &text,
                    TextRole::Tick,
                    TEXT_PT,
                    (x, frame.y1 + TICK_PT + 2.0 + ASCENT_EM * TEXT_PT),
                    Align::Middle,
                    false,
                    FRAME_COLOUR,
                ));
            }
            let len = if major { TICK_PT } else { TICK_PT * 0.6 };
            b.path(
                vec![(x, frame.y1), (x, frame.y1 + len)],
                FRAME_COLOUR,
                FRAME_PT,
                None,
            );
        }
        let mut widest = 0.0f64;
        for (v, text, major) in ticks(sy.lo, sy.hi, sy.log) {
            let y = sy.map(v);
            if major {
                b.path(
                    vec![(frame.x0, y), (frame.x1, y)],
                    GRID_COLOUR,
                    GRID_PT,
                    None,
                );
                let r = b.text(text_box(
                    &text,
                    TextRole::Tick,
                    TEXT_PT,
                    (frame.x0 - TICK_PT - 2.0, y + 0.3 * TEXT_PT),
                    Align::End,
                    false,
                    FRAME_COLOUR,
                ));
                widest = widest.max(r.x1 - r.x0);
            }
            let len = if major { TICK_PT } else { TICK_PT * 0.6 };
            b.path(
                vec![(frame.x0 - len, y), (frame.x0, y)],
                FRAME_COLOUR,
                FRAME_PT,
                None,
            );
        }
        b.text(text_box(
            &panel.x.label,
            TextRole::AxisTitle,
            TITLE_PT,
            (
                (frame.x0 + frame.x1) / 2.0,
                frame.y1 + TICK_PT + 2.0 + TEXT_PT * 1.1 + 3.0 + ASCENT_EM * TITLE_PT,
            ),
            Align::Middle,
            false,
            Rgb(0, 0, 0),
        ));
        b.text(text_box(
            &panel.y.label,
            TextRole::AxisTitle,
            TITLE_PT,
            (
                frame.x0 - TICK_PT - 2.0 - widest - 3.0 - DESCENT_EM * TITLE_PT,
                (frame.y0 + frame.y1) / 2.0,
            ),
            Align::Middle,
            true,
            Rgb(0, 0, 0),
        ));
    }
    for band in &panel.bands {
        let mut points: Vec<(f64, f64)> = band
            .lower
            .iter()
            .filter(|p| valid(p))
            .map(|&p| to_pt(p))
            .collect();
        points.extend(
            band.upper
                .iter()
                .rev()
                .filter(|p| valid(p))
                .map(|&p| to_pt(p)),
        );
        let points = points
            .into_iter()
            .map(|(x, y)| (x.clamp(frame.x0, frame.x1), y.clamp(frame.y0, frame.y1)))
            .collect();
        b.shapes.push(Shape::Path {
            points,
            stroke: None,
            fill: Some(band.color),
            closed: true,
        });
    }
    for s in &panel.series {
        b.series.push(DrawnSeries {
            panel: index,
            label: s.label.clone(),
            style: s.style,
            points: s
                .points
                .iter()
                .filter(|p| valid(p))
                .map(|&p| to_pt(p))
                .filter(|c| {
                    c.0 >= frame.x0 && c.0 <= frame.x1 && c.1 >= frame.y0 && c.1 <= frame.y1
                })
                .collect(),
        });
        if s.style.line != Line::None {
            let mut run: Vec<(f64, f64)> = Vec::new();
            let flush = |run: &mut Vec<(f64, f64)>, b: &mut Builder| {
                if run.len() > 1 {
                    b.path(
                        std::mem::take(run),
                        s.style.color,
                        s.style.width,
                        s.style.line.dash(),
                    );
                }
                run.clear();
            };
            for w in s.points.windows(2) {
                let (p, q) = (w[0], w[1]);
                if !valid(&p) || !valid(&q) {
                    flush(&mut run, b);
                    continue;
                }
                let Some((a, c)) = clip_segment(to_pt(p), to_pt(q), frame) else {
                    flush(&mut run, b);
                    continue;
                };
                if run
                    .last()
                    .is_none_or(|l| (l.0 - a.0).abs() > 1e-9 || (l.1 - a.1).abs() > 1e-9)
                {
                    flush(&mut run, b);
                    run.push(a);
                }
                run.push(c);
                b.marks.push((index, Mark::Segment(a, c)));
            }
            flush(&mut run, b);
        }
        if s.style.marker != Marker::None {
            for p in s.points.iter().step_by(s.marker_every).filter(|p| valid(p)) {
                let c = to_pt(*p);
                if c.0 >= frame.x0 && c.0 <= frame.x1 && c.1 >= frame.y0 && c.1 <= frame.y1 {
                    b.marker(&s.style, c, Some(index));
                }
            }
        }
    }
    for a in &panel.arrows {
        let (p, q) = (to_pt(a.from), to_pt(a.to));
        let (dx, dy) = (q.0 - p.0, q.1 - p.1);
        let len = (dx * dx + dy * dy).sqrt().max(1e-9);
        let (ux, uy) = (dx / len, dy / len);
        let head = 5.0;
        let base = (q.0 - ux * head, q.1 - uy * head);
        b.path(vec![p, base], a.color, LINE_PT, None);
        b.shapes.push(Shape::Path {
            points: vec![
                q,
                (base.0 - uy * head * 0.4, base.1 + ux * head * 0.4),
                (base.0 + uy * head * 0.4, base.1 - ux * head * 0.4),
            ],
            stroke: None,
            fill: Some(a.color),
            closed: true,
        });
        b.marks.push((index, Mark::Segment(p, q)));
    }
    for l in &panel.labels {
        let (x, y) = to_pt(l.at);
        b.text(text_box(
            &l.text,
            TextRole::Label,
            TEXT_PT,
            (x + l.offset.0, y - l.offset.1),
            l.align,
            false,
            l.color,
        ));
    }
    if panel.frame {
        b.shapes.push(Shape::Path {
            points: vec![
                (frame.x0, frame.y0),
                (frame.x1, frame.y0),
                (frame.x1, frame.y1),
                (frame.x0, frame.y1),
            ],
            stroke: Some((FRAME_COLOUR, FRAME_PT, None)),
            fill: None,
            closed: true,
        });
    }
    Ok(())
}

/// A size with two decimals, without a trailing `.00`.
fn num(v: f64) -> String {
    let s = format!("{v:.2}");
    let s = s.trim_end_matches('0').trim_end_matches('.');
    if s == "-0" {
        "0".into()
    } else {
        s.to_string()
    }
}

/// A length in canvas units.
fn units(pt: f64) -> i32 {
    (pt * SVG_UNITS_PER_PT).round() as i32
}

fn canvas(p: (f64, f64)) -> BackendCoord {
    (units(p.0), units(p.1))
}

fn colour(c: Rgb) -> RGBColor {
    RGBColor(c.0, c.1, c.2)
}

fn stroke_style(c: Rgb, width_pt: f64) -> ShapeStyle {
    colour(c).stroke_width(units(width_pt).max(0) as u32)
}

/// plotters' SVG backend writes a text style's size divided by 1.24 as the `font-size`; the
/// style size whose quotient is exactly `size` units, so the attribute reads `800`, not
/// `799.9999999999999`.
fn plotters_font_size(size: f64) -> f64 {
    let guess = size * 1.24;
    (-4i64..=4)
        .map(|k| f64::from_bits(guess.to_bits().wrapping_add_signed(k)))
        .find(|s| s / 1.24 == size)
        .unwrap_or(guess)
}

/// The pieces of a polyline drawn by a dash pattern (on, off, on, … lengths, pt), as SVG's
/// `stroke-dasharray` draws it: the pattern runs on across vertices, so a dash can turn a
/// corner.
fn dash_runs(points: &[(f64, f64)], pattern: &[f64]) -> Vec<Vec<(f64, f64)>> {
    let mut runs = Vec::new();
    let Some(&first) = points.first() else {
        return runs;
    };
    let mut current = vec![first];
    let (mut element, mut on) = (0, true);
    let mut left = pattern[0];
    for w in points.windows(2) {
        let (a, b) = (w[0], w[1]);
        let len = (b.0 - a.0).hypot(b.1 - a.1);
        if len == 0.0 {
            continue;
        }
        let mut done = 0.0;
        while len - done > left {
            done += left;
            let p = (
                a.0 + (b.0 - a.0) * done / len,
                a.1 + (b.1 - a.1) * done / len,
            );
            if on {
                current.push(p);
                runs.push(std::mem::take(&mut current));
            } else {
                current = vec![p];
            }
            on = !on;
            element = (element + 1) % pattern.len();
            left = pattern[element];
        }
        left -= len - done;
        if on {
            current.push(b);
        }
    }
    if on && current.len() > 1 {
        runs.push(current);
    }
    runs
}

type DrawResult = std::result::Result<(), DrawingErrorKind<std::io::Error>>;

/// Adds to panel `panel` of `chart` each label of `candidates` (a list of alternative
/// placements, tried in order) at the first placement whose text lies inside the panel's axes
/// and clear of every data mark, other text and legend of the figure; a label with no clear
/// placement is left out. Direct labels on a crowded panel, with the room checked on the
/// laid-out figure rather than guessed. Labels are placed panel by panel, so the panel's own
/// label is the last one laid out.
pub fn place_clear_labels(
    chart: &mut Chart,
    panel: usize,
    candidates: Vec<Vec<Label>>,
) -> Result<()> {
    for alternatives in candidates {
        for label in alternatives {
            chart.panels[panel].labels.push(label);
            let l = layout(chart)?;
            let placed = l.texts.iter().rposition(|t| t.role == TextRole::Label);
            let clear = placed.is_some_and(|i| {
                let r = l.texts[i].rect;
                l.axes[panel].contains(&r, 0.0)
                    && l.marks.iter().all(|(_, m)| match m {
                        Mark::Point(p) => !r.intersects(p),
                        Mark::Segment(a, b) => !r.meets_segment(*a, *b),
                    })
                    && l.legends.iter().all(|g| !r.intersects(g))
                    && l.texts
                        .iter()
                        .enumerate()
                        .all(|(j, t)| j == i || !r.intersects(&t.rect))
            });
            if clear {
                break;
            }
            chart.panels[panel].labels.pop();
        }
    }
    Ok(())
}

impl Layout {
    /// The SVG document, written by plotters' SVG backend on a canvas of
    /// [`SVG_UNITS_PER_PT`] units per pt: `width`/`height` state the printed size in mm, the
    /// viewBox the canvas.
    pub fn svg(&self) -> String {
        let size = (
            units(self.width_mm * PT_PER_MM),
            units(self.height_mm * PT_PER_MM),
        );
        let mut drawn = String::new();
        {
            let mut backend = SVGBackend::with_string(&mut drawn, (size.0 as u32, size.1 as u32));
            // The backend appends to a String; only its file target can fail.
            self.draw(&mut backend)
                .and_then(|()| backend.present())
                .expect("plotters' SVG backend writing to a String does not fail");
        }
        // plotters' root states the canvas in pixels; the printed size goes there instead.
        let body = drawn.split_once('\n').map_or("", |(_, body)| body);
        format!(
            "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"{}mm\" height=\"{}mm\" \
             viewBox=\"0 0 {} {}\" font-family=\"{FONT}\" stroke-linecap=\"round\" \
             stroke-linejoin=\"round\">\n{body}",
            num(self.width_mm),
            num(self.height_mm),
            size.0,
            size.1
        )
    }

    fn draw(&self, backend: &mut SVGBackend) -> DrawResult {
        let (w, h) = backend.get_size();
        backend.draw_rect((0, 0), (w as i32, h as i32), &colour(WHITE), true)?;
        for shape in &self.shapes {
            match shape {
                Shape::Path {
                    points,
                    stroke,
                    fill,
                    closed,
                } => {
                    if let Some(fill) = fill {
                        backend.fill_polygon(points.iter().map(|&p| canvas(p)), &colour(*fill))?;
                    }
                    let Some((c, width, dash)) = stroke else {
                        continue;
                    };
                    let mut outline = points.clone();
                    if *closed {
                        outline.extend(points.first());
                    }
                    let runs = match dash {
                        Some(pattern) => dash_runs(&outline, pattern),
                        None => vec![outline],
                    };
                    for run in runs {
                        backend
                            .draw_path(run.into_iter().map(canvas), &stroke_style(*c, *width))?;
                    }
                }
                Shape::Circle {
                    centre,
                    r,
                    stroke,
                    fill,
                } => {
                    let (c, r) = (canvas(*centre), units(*r).max(0) as u32);
                    backend.draw_circle(c, r, &colour(*fill), true)?;
                    backend.draw_circle(c, r, &stroke_style(stroke.0, stroke.1), false)?;
                }
                Shape::Text(i) => self.draw_text(backend, &self.texts[*i])?,
            }
        }
        Ok(())
    }

    /// A text with its baseline on the layout's anchor. plotters' backend has no baseline
    /// alignment: `VPos::Top` shifts the text down by `dy="0.76em"` (font-independent, unlike
    /// the `ex` of `Center` and `Bottom`), so the anchor is drawn 0.76 em above the baseline,
    /// across the text's own direction when it is rotated.
    fn draw_text(&self, backend: &mut SVGBackend, t: &TextBox) -> DrawResult {
        const TOP_DY_EM: f64 = 0.76;
        let (x, y) = t.anchor;
        let shift = TOP_DY_EM * t.size;
        let (at, transform) = if t.rotated {
            ((x - shift, y), FontTransform::Rotate270)
        } else {
            ((x, y - shift), FontTransform::None)
        };
        let h_pos = match t.align {
            Align::Start => HPos::Left,
            Align::Middle => HPos::Center,
            Align::End => HPos::Right,
        };
        let rgb = colour(t.color);
        let style = TextStyle::from((FONT, plotters_font_size(t.size * SVG_UNITS_PER_PT)))
            .color(&rgb)
            .pos(Pos::new(h_pos, VPos::Top))
            .transform(transform);
        backend.draw_text(&t.text, &style, canvas(at))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn log_ticks_are_superscript_decades() {
        let t = ticks(1e-4, 0.2, true);
        let labels: Vec<&str> = t.iter().filter(|t| t.2).map(|t| t.1.as_str()).collect();
        assert_eq!(labels, ["10⁻⁴", "10⁻³", "10⁻²", "10⁻¹"]);
    }

    #[test]
    fn linear_ticks_have_no_float_noise() {
        let labels: Vec<String> = ticks(-0.45, 0.5, false).into_iter().map(|t| t.1).collect();
        // One number of decimals per axis, zero included, and a true minus sign.
        assert_eq!(labels, ["−0.4", "−0.2", "0.0", "0.2", "0.4"]);
    }

    #[test]
    fn clipping_keeps_the_inside_part() {
        let r = Rect {
            x0: 0.0,
            y0: 0.0,
            x1: 10.0,
            y1: 10.0,
        };
        assert_eq!(
            clip_segment((-5.0, 5.0), (5.0, 5.0), &r),
            Some(((0.0, 5.0), (5.0, 5.0)))
        );
        assert_eq!(clip_segment((-5.0, -5.0), (-1.0, 20.0), &r), None);
    }

    #[test]
    fn an_svg_is_deterministic_and_states_its_size() {
        let mut p = Panel::new(Axis::log("Δt (s)"), Axis::linear("E (J)"));
        p.series.push(
            Series::line("a", vec![(0.001, 1.0), (0.1, 2.0)], Rgb(0, 0, 0))
                .with_marker(Marker::Triangle, false),
        );
        p.arrows.push(Arrow {
            from: (0.01, 1.0),
            to: (0.02, 1.5),
            color: Rgb(200, 0, 0),
        });
        let chart = Chart::new(FULL_WIDTH_MM, 60.0, vec![p.clone(), p]);
        let a = layout(&chart).unwrap().svg();
        assert_eq!(a, layout(&chart).unwrap().svg());
        // 170 mm = 481.89 pt, 60 mm = 170.08 pt, at 100 units per pt.
        assert!(a.starts_with(
            "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"170mm\" height=\"60mm\" \
             viewBox=\"0 0 48189 17008\" font-family=\"sans-serif\""
        ));
        assert!(a.contains("\n(b)\n</text>") && a.contains("Δt (s)"));
        assert!(a.ends_with("</svg>\n"));
    }

    /// The value of attribute `name` in an element's text.
    fn attr<'a>(element: &'a str, name: &str) -> &'a str {
        let start = element.find(&format!(" {name}=\"")).unwrap() + name.len() + 3;
        let end = element[start..].find('"').unwrap() + start;
        &element[start..end]
    }

    #[test]
    fn svg_texts_have_their_baseline_on_the_layout_anchor() {
        let mut p = Panel::new(Axis::log("Δt (s)"), Axis::linear("E (J)"));
        p.series.push(Series::line(
            "a & b",
            vec![(0.001, 1.0), (0.1, 2.0)],
            Rgb(0, 0, 0),
        ));
        p.label((0.01, 1.5), (2.0, 3.0), Align::End, "peak", Rgb(200, 0, 0));
        let l = layout(&Chart::new(FULL_WIDTH_MM, 60.0, vec![p.clone(), p])).unwrap();
        let svg = l.svg();
        let elements: Vec<&str> = svg.split("<text").skip(1).collect();
        assert_eq!(elements.len(), l.texts.len());
        assert!(l.texts.iter().any(|t| t.rotated));
        for (e, t) in elements.iter().zip(&l.texts) {
            let number = |name| attr(e, name).parse::<f64>().unwrap();
            // The font size is the layout's, exactly, in canvas units.
            assert_eq!(attr(e, "font-size"), num(t.size * SVG_UNITS_PER_PT));
            let (x, y) = (number("x"), number("y"));
            // plotters shifts the text by `dy` across its direction; the baseline ends there.
            let dy = attr(e, "dy")
                .strip_suffix("em")
                .unwrap()
                .parse::<f64>()
                .unwrap()
                * t.size
                * SVG_UNITS_PER_PT;
            let baseline = if t.rotated {
                assert_eq!(attr(e, "transform"), format!("rotate(270, {x}, {y})"));
                (x + dy, y)
            } else {
                assert!(!e.contains("transform="));
                (x, y + dy)
            };
            let anchor = (t.anchor.0 * SVG_UNITS_PER_PT, t.anchor.1 * SVG_UNITS_PER_PT);
            assert!(
                (baseline.0 - anchor.0).abs() <= 0.5 && (baseline.1 - anchor.1).abs() <= 0.5,
                "{:?}: baseline {baseline:?}, layout {anchor:?}",
                t.text
            );
            let expected = match t.align {
                Align::Start => "start",
                Align::Middle => "middle",
                Align::End => "end",
            };
            assert_eq!(attr(e, "text-anchor"), expected, "{:?}", t.text);
            let content = e.split_once(">\n").unwrap().1;
            assert_eq!(
                content.split_once("\n</text>").unwrap().0,
                t.text.replace('&', "&amp;")
            );
        }
    }

    #[test]
    fn dashes_follow_the_pattern_across_corners() {
        // A 5 pt leg right, then 10 pt down: 15 pt of path.
        let path = [(0.0, 0.0), (5.0, 0.0), (5.0, 10.0)];
        assert_eq!(
            dash_runs(&path, &[4.5, 2.5]),
            [
                vec![(0.0, 0.0), (4.5, 0.0)],
                vec![(5.0, 2.0), (5.0, 6.5)],
                vec![(5.0, 9.0), (5.0, 10.0)],
            ]
        );
        // A dash longer than the first leg turns the corner.
        assert_eq!(
            dash_runs(&path, &[6.0, 1.0]),
            [
                vec![(0.0, 0.0), (5.0, 0.0), (5.0, 1.0)],
                vec![(5.0, 2.0), (5.0, 8.0)],
                vec![(5.0, 9.0), (5.0, 10.0)],
            ]
        );
    }

    #[test]
    fn markers_keep_hollow_and_filled_apart() {
        let mut p = Panel::new(Axis::linear("x"), Axis::linear("y"));
        p.series.push(
            Series::points("ours", vec![(0.0, 0.0)], Rgb(10, 20, 30))
                .with_marker(Marker::Circle, true),
        );
        p.series.push(
            Series::points("published", vec![(1.0, 1.0)], Rgb(10, 20, 30))
                .with_marker(Marker::Square, false),
        );
        let svg = layout(&Chart::new(COLUMN_WIDTH_MM, 60.0, vec![p]))
            .unwrap()
            .svg();
        // Filled circle: a disc in the colour, then its outline (r = 2.4 pt).
        assert!(svg.contains("r=\"240\" opacity=\"1\" fill=\"#0A141E\" stroke=\"none\""));
        assert!(svg.contains(
            "r=\"240\" opacity=\"1\" fill=\"none\" stroke=\"#0A141E\" stroke-width=\"50\""
        ));
        // Hollow square: a white polygon under a 0.9 pt outline.
        assert!(svg.contains("<polygon opacity=\"1\" fill=\"#FFFFFF\""));
        assert!(svg.contains("stroke=\"#0A141E\" stroke-width=\"90\""));
    }
}
