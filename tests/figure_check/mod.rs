//! The figure test of issue 11, shared by `tests/figures.rs` (synthetic charts) and
//! `tests/report.rs` (the report's figures): from a figure's layout in plot coordinates
//! (points at the printed size) and the glyph-width bound of `plot::text_width`,
//! - the SVG states its printed size in mm and a viewBox of `SVG_UNITS_PER_PT` units per pt,
//!   so sizes below are in pt;
//! - every text is at least 8 pt;
//! - no text box or legend box intersects a data mark (marker or line piece) of any panel;
//! - no two text boxes intersect, no legend box covers a text other than its own, and no two
//!   legends overlap;
//! - every mark lies inside its panel's axes, and every text inside the figure.

use mass_spring_solvers::report::plot::{
    Layout, Mark, Rect, TextRole, PT_PER_MM, SVG_UNITS_PER_PT,
};

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
    out
}
