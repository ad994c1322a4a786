//! The figure test of issue 11, shared by `tests/figures.rs` (synthetic charts) and
//! `tests/report.rs` (the report's figures): from a figure's layout in plot coordinates
//! (points at the printed size) and the glyph-width bound of `plot::text_width`,
//! - the SVG states its printed size in mm and a viewBox of `SVG_UNITS_PER_PT` units per pt,
//!   so sizes below are in pt;
//! - every text is at least 8 pt;
//! - no text box or legend box intersects a data mark (marker or line piece) of any panel;
//! - no two text boxes intersect, no legend box covers a text other than its own, and no two
//!   legends overlap;
//! - every mark lies inside its panel's axes, and every text inside the figure;
//! - no two labelled series of one axes share marker and dash, whatever their colours
//!   (issue 25: line style or marker redundant with colour, so that a reader without colour,
//!   in grey print or with deuteranopia, tells them apart), and no two entries of one legend
//!   share colour, marker and dash (a colour key, such as the parity figure's evidence
//!   classes, names colours);
//! - every legend entry has a visible swatch, and every labelled series a mark of its own
//!   that no later series draws over (a series hidden under another is named with it, not
//!   drawn twice).

use mass_spring_report::plot::{
    DrawnSeries, Layout, Line, Mark, Marker, Rect, Rgb, Style, TextRole, PT_PER_MM,
    SVG_UNITS_PER_PT, WHITE,
};

/// Points closer than this are drawn on top of each other, pt.
const COINCIDENT_PT: f64 = 0.5;

/// What tells a series apart without colour: dash, marker (and its fill, where it has one).
fn encoding(s: &Style) -> (Line, Marker, bool) {
    (s.line, s.marker, s.marker != Marker::None && s.filled)
}

/// What tells a legend entry apart: its colour besides [`encoding`].
fn key_encoding(s: &Style) -> (Rgb, (Line, Marker, bool)) {
    (s.color, encoding(s))
}

/// Whether `over` hides every point of `under`: it passes through each of them and draws
/// at least as much there (a marker of the same shape and size, filled; a solid line as wide).
fn hides(over: &DrawnSeries, under: &DrawnSeries) -> bool {
    let (o, u) = (&over.style, &under.style);
    let marker_hidden =
        u.marker == Marker::None || (o.marker == u.marker && o.radius >= u.radius && o.filled);
    let line_hidden = u.line == Line::None || (o.line == Line::Solid && o.width >= u.width);
    !under.points.is_empty()
        && marker_hidden
        && line_hidden
        && under.points.iter().all(|p| {
            over.points
                .iter()
                .any(|q| (p.0 - q.0).abs() <= COINCIDENT_PT && (p.1 - q.1).abs() <= COINCIDENT_PT)
        })
}

/// The encoding and visibility problems of a figure's series and legends.
fn series_problems(name: &str, layout: &Layout) -> Vec<String> {
    let mut out = Vec::new();
    let labelled: Vec<&DrawnSeries> = layout
        .series
        .iter()
        .filter(|s| !s.label.is_empty())
        .collect();
    for (i, a) in labelled.iter().enumerate() {
        for b in labelled[i + 1..].iter().filter(|b| b.panel == a.panel) {
            if encoding(&a.style) == encoding(&b.style) {
                out.push(format!(
                    "{name}: series {:?} and {:?} of panel {} share marker and dash",
                    a.label,
                    b.label,
                    a.panel + 1
                ));
            }
        }
    }
    for (i, (legend, a)) in layout.legend_entries.iter().enumerate() {
        let visible_line = a.style.line != Line::None && a.style.width > 0.0;
        let visible_marker = a.style.marker != Marker::None && a.style.radius > 0.0;
        if a.style.color == WHITE || !(visible_line || visible_marker) {
            out.push(format!(
                "{name}: legend entry {:?} has no visible mark",
                a.label
            ));
        }
        for (other, b) in &layout.legend_entries[i + 1..] {
            if other == legend
                && a.label != b.label
                && key_encoding(&a.style) == key_encoding(&b.style)
            {
                out.push(format!(
                    "{name}: legend entries {:?} and {:?} share colour, marker and dash",
                    a.label, b.label
                ));
            }
        }
    }
    for (i, a) in layout.series.iter().enumerate() {
        if a.label.is_empty() {
            continue;
        }
        if a.points.is_empty() {
            out.push(format!(
                "{name}: series {:?} is in the legend but draws nothing",
                a.label
            ));
        } else if let Some(b) = layout.series[i + 1..]
            .iter()
            .find(|b| b.panel == a.panel && b.label != a.label && hides(b, a))
        {
            out.push(format!(
                "{name}: series {:?} is hidden under {:?} in panel {}",
                a.label,
                b.label,
                a.panel + 1
            ));
        }
    }
    out
}

/// Smallest text at the printed size, pt.
pub const MIN_TEXT_PT: f64 = 8.0;
/// Slack for round-off on shared edges, pt.
const TOLERANCE_PT: f64 = 0.01;

fn shrink(r: &Rect) -> Rect {
    Rect {
        x0: r.x0 + TOLERANCE_PT,
        y0: r.y0 + TOLERANCE_PT,
        x1: r.x1 - TOLERANCE_PT,
        y1: r.y1 - TOLERANCE_PT,
    }
}

fn hits(r: &Rect, mark: &Mark) -> bool {
    let r = shrink(r);
    match mark {
        Mark::Point(m) => r.intersects(m),
        Mark::Segment(a, b) => r.meets_segment(*a, *b),
    }
}

/// The SVG's stated size: `width="Wmm" height="Hmm" viewBox="0 0 w h"`.
fn stated_size(svg: &str) -> Option<(f64, f64, f64, f64)> {
    let attr = |name: &str| -> Option<&str> {
        let start = svg.find(&format!(" {name}=\""))? + name.len() + 3;
        let end = svg[start..].find('"')? + start;
        Some(&svg[start..end])
    };
    let mm = |v: &str| v.strip_suffix("mm")?.parse::<f64>().ok();
    let view: Vec<f64> = attr("viewBox")?
        .split(' ')
        .filter_map(|v| v.parse().ok())
        .collect();
    Some((
        mm(attr("width")?)?,
        mm(attr("height")?)?,
        *view.get(2)?,
        *view.get(3)?,
    ))
}

/// Everything wrong with a figure; empty when it passes.
pub fn problems(name: &str, layout: &Layout, svg: &str) -> Vec<String> {
    let mut out = Vec::new();
    match stated_size(svg) {
        // The viewBox is whole canvas units: within half a unit of the stated size.
        Some((w, h, vw, vh))
            if (w * PT_PER_MM - vw / SVG_UNITS_PER_PT).abs() <= 0.005
                && (h * PT_PER_MM - vh / SVG_UNITS_PER_PT).abs() <= 0.005
                && (w - layout.width_mm).abs() <= 0.005
                && (h - layout.height_mm).abs() <= 0.005 => {}
        other => out.push(format!(
            "{name}: the SVG does not state its printed size in mm with a viewBox of \
             {SVG_UNITS_PER_PT} units per pt: {other:?}"
        )),
    }
    let page = Rect {
        x0: 0.0,
        y0: 0.0,
        x1: layout.width_mm * PT_PER_MM,
        y1: layout.height_mm * PT_PER_MM,
    };
    for t in &layout.texts {
        if t.size < MIN_TEXT_PT {
            out.push(format!(
                "{name}: text {:?} is {} pt, under {MIN_TEXT_PT} pt",
                t.text, t.size
            ));
        }
        if !page.contains(&t.rect, TOLERANCE_PT) {
            out.push(format!(
                "{name}: text {:?} leaves the figure: {:?}",
                t.text, t.rect
            ));
        }
    }
    for (panel, mark) in &layout.marks {
        let axes = &layout.axes[*panel];
        let inside = match mark {
            Mark::Point(r) => axes.contains(r, TOLERANCE_PT),
            Mark::Segment(a, b) => [a, b].iter().all(|p| {
                axes.contains(
                    &Rect {
                        x0: p.0,
                        y0: p.1,
                        x1: p.0,
                        y1: p.1,
                    },
                    TOLERANCE_PT,
                )
            }),
        };
        if !inside {
            out.push(format!(
                "{name}: a mark of panel {} lies outside its axes: {mark:?}",
                panel + 1
            ));
        }
    }
    let boxes = layout
        .texts
        .iter()
        .map(|t| (format!("text {:?}", t.text), t.rect))
        .chain(
            layout
                .legends
                .iter()
                .enumerate()
                .map(|(i, r)| (format!("legend {}", i + 1), *r)),
        );
    for (what, rect) in boxes {
        if let Some((panel, mark)) = layout.marks.iter().find(|(_, m)| hits(&rect, m)) {
            out.push(format!(
                "{name}: {what} covers a data mark of panel {}: {mark:?}",
                panel + 1
            ));
        }
    }
    // A legend's own texts are inside its box; every other text, and other legends, stay out.
    for (i, legend) in layout.legends.iter().enumerate() {
        for t in layout.texts.iter().filter(|t| t.role != TextRole::Legend) {
            if shrink(legend).intersects(&t.rect) {
                out.push(format!("{name}: legend {} covers text {:?}", i + 1, t.text));
            }
        }
        for other in &layout.legends[i + 1..] {
            if shrink(legend).intersects(other) {
                out.push(format!("{name}: legends {} and another overlap", i + 1));
            }
        }
    }
    for (i, a) in layout.texts.iter().enumerate() {
        for b in &layout.texts[i + 1..] {
            if shrink(&a.rect).intersects(&b.rect) {
                out.push(format!(
                    "{name}: texts {:?} and {:?} overlap",
                    a.text, b.text
                ));
            }
        }
    }
    out.extend(series_problems(name, layout));
    out
}
