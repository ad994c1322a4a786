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

mod axes;
mod laid_out;
mod layout;
mod svg;

pub use axes::power_of_ten;
pub use laid_out::*;
pub use layout::{layout, place_clear_labels};

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

#[cfg(test)]
mod tests {
    use super::axes::*;
    use super::layout::*;
    use super::svg::*;
    use super::*;

    /// A log axis over less than two decades labels 1, 2 and 5 of each decade: in digits near
    /// 1 (`0.002`, `5000`), as a power of ten beyond (`2×10⁶`, `10⁷`), never `2000000`.
    /// Negative case: the digits of a value of 10⁴ or more, which the labels of Figures 27-28
    /// read before (`2000000 … 20000000`), appear in no label.
    #[test]
    fn log_ticks_beyond_ten_thousand_are_powers_of_ten() {
        let labels = |lo: f64, hi: f64| -> Vec<String> {
            ticks(lo, hi, true).into_iter().map(|t| t.1).collect()
        };
        assert_eq!(labels(1.5e6, 2.5e7), ["2×10⁶", "5×10⁶", "10⁷", "2×10⁷"]);
        assert_eq!(labels(1.5e3, 6e3), ["2000", "5000"]);
        assert_eq!(labels(1.5e-3, 6e-3), ["0.002", "0.005"]);
        assert!(labels(1.5e6, 2.5e7).iter().all(|l| !l.contains("000")));
    }

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
