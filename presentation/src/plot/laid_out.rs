//! What a layout holds: every text's box, every data mark and every axes rectangle of a
//! figure at its printed size, in points, before anything is drawn.

use super::*;

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
    pub(super) anchor: (f64, f64),
    pub(super) align: Align,
    pub(super) color: Rgb,
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
    pub(super) shapes: Vec<Shape>,
}

/// A drawing primitive, pt.
#[derive(Debug, Clone, PartialEq)]
pub(super) enum Shape {
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

/// Liang-Barsky: the part of segment a-b inside `r`.
pub(super) fn clip_segment(
    a: (f64, f64),
    b: (f64, f64),
    r: &Rect,
) -> Option<((f64, f64), (f64, f64))> {
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
