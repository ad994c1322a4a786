//! A small declarative layer over plotters' SVG backend: panels of line and marker series
//! on linear or logarithmic axes, with legends, text and arrows. Text is plain SVG `<text>`
//! (no font files), and the same panels always give the same bytes.

use crate::error::{Error, Result};
use crate::report::format::sig;
use plotters::coord::Shift;
use plotters::prelude::*;

/// Font family of every text.
const FONT: &str = "sans-serif";

/// How a series is drawn.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Line {
    Solid,
    Dashed,
    /// Markers only.
    None,
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

/// One series of a panel.
#[derive(Debug, Clone, PartialEq)]
pub struct Series {
    /// Legend text; empty for no legend entry.
    pub label: String,
    pub points: Vec<(f64, f64)>,
    pub color: RGBColor,
    pub line: Line,
    pub marker: Marker,
    /// Filled markers (ours) or hollow (published).
    pub filled: bool,
    /// Marker radius, px.
    pub marker_size: i32,
    pub width: u32,
}

impl Series {
    /// A solid line without markers.
    pub fn line(label: impl Into<String>, points: Vec<(f64, f64)>, color: RGBColor) -> Self {
        Self {
            label: label.into(),
            points,
            color,
            line: Line::Solid,
            marker: Marker::None,
            filled: true,
            marker_size: 4,
            width: 2,
        }
    }

    /// The same series with markers.
    pub fn with_marker(mut self, marker: Marker, filled: bool) -> Self {
        self.marker = marker;
        self.filled = filled;
        self
    }

    /// The same series with another marker radius (px).
    pub fn with_marker_size(mut self, size: i32) -> Self {
        self.marker_size = size;
        self
    }

    /// The same series with another line kind.
    pub fn with_line(mut self, line: Line) -> Self {
        self.line = line;
        self
    }

    /// The same series with another line width.
    pub fn with_width(mut self, width: u32) -> Self {
        self.width = width;
        self
    }
}

/// One axis.
#[derive(Debug, Clone, PartialEq)]
pub struct Axis {
    /// Title with unit, `dt (s)`.
    pub label: String,
    pub log: bool,
    /// Fixed range; automatic (with a margin, or whole decades on a log axis) when `None`.
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

/// Where the legend goes.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Legend {
    UpperRight,
    UpperLeft,
    LowerRight,
    UpperMiddle,
}

/// A text at a data point (its top-left corner).
#[derive(Debug, Clone, PartialEq)]
pub struct Label {
    pub at: (f64, f64),
    pub text: String,
    pub color: RGBColor,
    pub size: u32,
}

/// An arrow between two data points, its head at `to`.
#[derive(Debug, Clone, PartialEq)]
pub struct Arrow {
    pub from: (f64, f64),
    pub to: (f64, f64),
    pub color: RGBColor,
}

/// One chart.
#[derive(Debug, Clone, PartialEq)]
pub struct Panel {
    pub title: String,
    pub x: Axis,
    pub y: Axis,
    pub series: Vec<Series>,
    pub labels: Vec<Label>,
    pub arrows: Vec<Arrow>,
    pub legend: Legend,
    /// Draw the grid and tick labels (off for schematic drawings).
    pub mesh: bool,
}

impl Panel {
    /// An empty panel.
    pub fn new(title: impl Into<String>, x: Axis, y: Axis) -> Self {
        Self {
            title: title.into(),
            x,
            y,
            series: Vec::new(),
            labels: Vec::new(),
            arrows: Vec::new(),
            legend: Legend::UpperRight,
            mesh: true,
        }
    }

    /// Adds a text at a data point.
    pub fn label(&mut self, at: (f64, f64), text: impl Into<String>, color: RGBColor) {
        self.labels.push(Label {
            at,
            text: text.into(),
            color,
            size: 15,
        });
    }
}

fn plot_error(e: impl std::fmt::Display) -> Error {
    Error::Input(format!("drawing a figure: {e}"))
}

/// The range of an axis over the given values.
fn auto_range(axis: &Axis, values: impl Iterator<Item = f64>) -> (f64, f64) {
    if let Some(r) = axis.range {
        return r;
    }
    let (mut lo, mut hi) = values
        .filter(|v| v.is_finite() && (!axis.log || *v > 0.0))
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), v| {
            (lo.min(v), hi.max(v))
        });
    if !lo.is_finite() {
        return if axis.log { (0.1, 10.0) } else { (0.0, 1.0) };
    }
    if axis.log {
        lo = 10f64.powf(lo.log10().floor());
        hi = 10f64.powf(hi.log10().ceil());
        if hi <= lo {
            hi = lo * 10.0;
        }
        (lo, hi)
    } else {
        if hi <= lo {
            let pad = if lo == 0.0 { 1.0 } else { 0.1 * lo.abs() };
            return (lo - pad, hi + pad);
        }
        let pad = 0.05 * (hi - lo);
        (lo - pad, hi + pad)
    }
}

const SUPERSCRIPTS: [char; 10] = ['⁰', '¹', '²', '³', '⁴', '⁵', '⁶', '⁷', '⁸', '⁹'];

/// A tick label: `10⁻³` for a power of ten on a log axis, else a short decimal.
fn tick(v: f64, log: bool) -> String {
    if log && v > 0.0 {
        let e = v.log10();
        if (e - e.round()).abs() < 1e-9 {
            let e = e.round() as i32;
            let mut s = String::from("10");
            if e < 0 {
                s.push('⁻');
            }
            for d in e.unsigned_abs().to_string().bytes() {
                s.push(SUPERSCRIPTS[(d - b'0') as usize]);
            }
            return s;
        }
        return sig(v, 2);
    }
    if v.abs() < 1e-12 {
        return "0".into();
    }
    let s = format!("{v:.6}");
    let s = s.trim_end_matches('0').trim_end_matches('.');
    s.to_string()
}

fn legend_position(l: Legend) -> SeriesLabelPosition {
    match l {
        Legend::UpperRight => SeriesLabelPosition::UpperRight,
        Legend::UpperLeft => SeriesLabelPosition::UpperLeft,
        Legend::LowerRight => SeriesLabelPosition::LowerRight,
        Legend::UpperMiddle => SeriesLabelPosition::UpperMiddle,
    }
}

/// The chart around a panel's plotting area: caption, margin and label areas.
fn chart_builder<'a, 'b, DB: DrawingBackend>(
    area: &'a DrawingArea<DB, Shift>,
    panel: &'b Panel,
) -> ChartBuilder<'a, 'b, DB> {
    let mut builder = ChartBuilder::on(area);
    builder
        .caption(&panel.title, (FONT, 19))
        .margin(14)
        .x_label_area_size(if panel.mesh { 48 } else { 0 })
        .y_label_area_size(if panel.mesh { 78 } else { 0 });
    builder
}

/// The height, px, at which `panel`, drawn `width` px wide, shows a metre as the same number
/// of pixels along x and y (geometry drawn to scale). Both axes must be linear with fixed
/// ranges.
pub fn height_to_scale(panel: &Panel, width: u32) -> Result<u32> {
    let (Some((x0, x1)), Some((y0, y1)), false, false) =
        (panel.x.range, panel.y.range, panel.x.log, panel.y.log)
    else {
        return Err(Error::Input(format!(
            "drawing \"{}\" to scale needs linear axes with fixed ranges",
            panel.title
        )));
    };
    // The plotting area of a square probe: the label areas and margins are fixed in pixels.
    let mut scratch = String::new();
    let root = SVGBackend::with_string(&mut scratch, (width, width)).into_drawing_area();
    let chart = chart_builder(&root, panel)
        .build_cartesian_2d(x0..x1, y0..y1)
        .map_err(plot_error)?;
    let (px, py) = chart.plotting_area().get_pixel_range();
    let (plot_width, plot_height) = (f64::from(px.end - px.start), py.end - py.start);
    let overhead = width as i32 - plot_height;
    Ok((overhead + (plot_width * (y1 - y0) / (x1 - x0)).round() as i32).max(1) as u32)
}

/// Draws one panel on `area`. A macro instead of a generic function because plotters'
/// linear and logarithmic coordinates are different types with the same interface.
macro_rules! draw_panel {
    ($area:expr, $panel:expr, $xr:expr, $yr:expr, $ranges:expr) => {{
        let panel: &Panel = $panel;
        let (x0, x1, y0, y1) = $ranges;
        let mut chart = chart_builder($area, panel)
            .build_cartesian_2d($xr, $yr)
            .map_err(plot_error)?;
        if panel.mesh {
            let x_log = panel.x.log;
            let y_log = panel.y.log;
            let xf = move |v: &f64| tick(*v, x_log);
            let yf = move |v: &f64| tick(*v, y_log);
            chart
                .configure_mesh()
                .x_desc(panel.x.label.as_str())
                .y_desc(panel.y.label.as_str())
                .x_label_formatter(&xf)
                .y_label_formatter(&yf)
                .label_style((FONT, 14))
                .axis_desc_style((FONT, 16))
                .max_light_lines(4)
                .light_line_style(RGBColor(238, 238, 238))
                .bold_line_style(RGBColor(205, 205, 205))
                .draw()
                .map_err(plot_error)?;
        }
        let mut labelled = false;
        for s in &panel.series {
            let color = s.color;
            let style = ShapeStyle::from(color).stroke_width(s.width);
            let points: Vec<(f64, f64)> = s
                .points
                .iter()
                .copied()
                .filter(|&(x, y)| {
                    x.is_finite() && y.is_finite() && (!panel.x.log || x > 0.0) && (!panel.y.log || y > 0.0)
                })
                .collect();
            let mut drew_line = false;
            match s.line {
                Line::Solid => {
                    let anno = chart
                        .draw_series(LineSeries::new(points.iter().copied(), style))
                        .map_err(plot_error)?;
                    if !s.label.is_empty() && s.marker == Marker::None {
                        anno.label(s.label.as_str())
                            .legend(move |(x, y)| PathElement::new(vec![(x, y), (x + 24, y)], style));
                        labelled = true;
                    }
                    drew_line = true;
                }
                Line::Dashed => {
                    let anno = chart
                        .draw_series(DashedLineSeries::new(points.iter().copied(), 7, 5, style))
                        .map_err(plot_error)?;
                    if !s.label.is_empty() && s.marker == Marker::None {
                        anno.label(s.label.as_str()).legend(move |(x, y)| {
                            EmptyElement::at((x, y))
                                + PathElement::new(vec![(0, 0), (8, 0)], style)
                                + PathElement::new(vec![(14, 0), (24, 0)], style)
                        });
                        labelled = true;
                    }
                    drew_line = true;
                }
                Line::None => {}
            }
            if s.marker != Marker::None {
                let ms = if s.filled {
                    ShapeStyle::from(color).filled()
                } else {
                    ShapeStyle::from(color).stroke_width(2)
                };
                let line: Vec<(i32, i32)> = match (drew_line, s.line) {
                    (false, _) => vec![],
                    (true, Line::Dashed) => vec![(0, 0), (7, 0)],
                    (true, _) => vec![(0, 0), (24, 0)],
                };
                let label = s.label.as_str();
                let r = s.marker_size;
                // The marker is built twice: at data points and in the legend's pixel space.
                macro_rules! markers {
                    ($p:ident => $make:expr) => {{
                        let anno = chart
                            .draw_series(points.iter().map(|&$p| $make))
                            .map_err(plot_error)?;
                        if !label.is_empty() {
                            anno.label(label).legend(move |(x, y)| {
                                let $p = (12, 0);
                                EmptyElement::at((x, y)) + PathElement::new(line.clone(), style) + $make
                            });
                            labelled = true;
                        }
                    }};
                }
                match s.marker {
                    Marker::Circle | Marker::None => markers!(p => Circle::new(p, r, ms)),
                    Marker::Triangle => markers!(p => TriangleMarker::new(p, r + 1, ms)),
                    Marker::Cross => markers!(p => Cross::new(p, r, ms)),
                    Marker::Square => markers!(p => EmptyElement::at(p) + Rectangle::new([(-r, -r), (r, r)], ms)),
                }
            }
        }
        for l in &panel.labels {
            chart
                .draw_series(std::iter::once(Text::new(
                    l.text.clone(),
                    l.at,
                    (FONT, l.size).into_font().color(&l.color),
                )))
                .map_err(plot_error)?;
        }
        if !panel.arrows.is_empty() {
            let (px, py) = chart.plotting_area().get_pixel_range();
            let sx = (px.end - px.start) as f64 / (x1 - x0);
            let sy = (py.end - py.start) as f64 / (y1 - y0);
            for a in &panel.arrows {
                let style = ShapeStyle::from(a.color).stroke_width(2);
                // The head in pixel space (y grows downwards), mapped back to data.
                let (dx, dy) = ((a.to.0 - a.from.0) * sx, -(a.to.1 - a.from.1) * sy);
                let len = (dx * dx + dy * dy).sqrt().max(1e-9);
                let (ux, uy) = (dx / len, dy / len);
                let head = |angle: f64| {
                    let (c, s) = (angle.cos(), angle.sin());
                    let (hx, hy) = (-(ux * c - uy * s) * 12.0, -(ux * s + uy * c) * 12.0);
                    (a.to.0 + hx / sx, a.to.1 - hy / sy)
                };
                chart
                    .draw_series(std::iter::once(PathElement::new(vec![a.from, a.to], style)))
                    .map_err(plot_error)?;
                chart
                    .draw_series(std::iter::once(Polygon::new(
                        vec![a.to, head(0.4), head(-0.4)],
                        ShapeStyle::from(a.color).filled(),
                    )))
                    .map_err(plot_error)?;
            }
        }
        if labelled {
            chart
                .configure_series_labels()
                .position(legend_position(panel.legend))
                .label_font((FONT, 14))
                .background_style(WHITE.mix(0.9))
                .border_style(RGBColor(120, 120, 120))
                .margin(10)
                .draw()
                .map_err(plot_error)?;
        }
    }};
}

fn draw_one(area: &DrawingArea<SVGBackend<'_>, Shift>, panel: &Panel) -> Result<()> {
    let xs = panel
        .series
        .iter()
        .flat_map(|s| s.points.iter().map(|p| p.0));
    let ys = panel
        .series
        .iter()
        .flat_map(|s| s.points.iter().map(|p| p.1));
    let (x0, x1) = auto_range(&panel.x, xs);
    let (y0, y1) = auto_range(&panel.y, ys);
    match (panel.x.log, panel.y.log) {
        (false, false) => draw_panel!(area, panel, x0..x1, y0..y1, (x0, x1, y0, y1)),
        (true, false) => draw_panel!(area, panel, (x0..x1).log_scale(), y0..y1, (x0, x1, y0, y1)),
        (false, true) => draw_panel!(area, panel, x0..x1, (y0..y1).log_scale(), (x0, x1, y0, y1)),
        (true, true) => draw_panel!(
            area,
            panel,
            (x0..x1).log_scale(),
            (y0..y1).log_scale(),
            (x0, x1, y0, y1)
        ),
    }
    Ok(())
}

/// An SVG document of `panels` side by side, each `panel_size` pixels.
pub fn svg(panels: &[Panel], panel_size: (u32, u32)) -> Result<String> {
    let mut out = String::new();
    {
        let width = panel_size.0 * panels.len().max(1) as u32;
        let root = SVGBackend::with_string(&mut out, (width, panel_size.1)).into_drawing_area();
        root.fill(&WHITE).map_err(plot_error)?;
        let areas = root.split_evenly((1, panels.len().max(1)));
        for (area, panel) in areas.iter().zip(panels) {
            draw_one(area, panel)?;
        }
        root.present().map_err(plot_error)?;
    }
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn ticks() {
        assert_eq!(tick(0.001, true), "10⁻³");
        assert_eq!(tick(100.0, true), "10²");
        assert_eq!(tick(0.5, false), "0.5");
        assert_eq!(tick(2.0, false), "2");
        assert_eq!(tick(-1e-15, false), "0");
    }

    #[test]
    fn an_svg_is_deterministic() {
        let mut p = Panel::new("t", Axis::log("dt (s)"), Axis::linear("E (J)"));
        p.series.push(
            Series::line("a", vec![(0.001, 1.0), (0.1, 2.0)], RGBColor(0, 0, 0))
                .with_marker(Marker::Triangle, false),
        );
        p.arrows.push(Arrow {
            from: (0.01, 1.0),
            to: (0.02, 1.5),
            color: RGBColor(200, 0, 0),
        });
        let a = svg(&[p.clone(), p.clone()], (400, 300)).unwrap();
        let b = svg(&[p.clone(), p], (400, 300)).unwrap();
        assert_eq!(a, b);
        assert!(a.contains("<text") && a.contains("dt (s)"));
    }

    #[test]
    fn geometry_to_scale_has_equal_pixels_per_unit() {
        for (mesh, x_range, y_range) in [(true, 4.0, 1.0), (false, 2.0, 3.0)] {
            let mut p = Panel::new(
                "t",
                Axis::linear("x (m)").range(0.0, x_range),
                Axis::linear("y (m)").range(0.0, y_range),
            );
            p.mesh = mesh;
            let height = height_to_scale(&p, 800).unwrap();
            let mut out = String::new();
            let root = SVGBackend::with_string(&mut out, (800, height)).into_drawing_area();
            let chart = chart_builder(&root, &p)
                .build_cartesian_2d(0.0..x_range, 0.0..y_range)
                .unwrap();
            let (px, py) = chart.plotting_area().get_pixel_range();
            let per_x = f64::from(px.end - px.start) / x_range;
            let per_y = f64::from(py.end - py.start) / y_range;
            assert!(
                (per_x - per_y).abs() <= 1.0 / y_range,
                "{per_x} vs {per_y} px/m"
            );
        }
        let log = Panel::new("t", Axis::log("x").range(1.0, 10.0), Axis::linear("y"));
        assert!(height_to_scale(&log, 800).is_err());
    }
}
