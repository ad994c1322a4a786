//! The SVG of a laid-out figure ([`Layout::svg`]), drawn through plotters' SVG backend on a
//! canvas of [`SVG_UNITS_PER_PT`](super::SVG_UNITS_PER_PT) integer units per point.

use super::laid_out::*;
use super::*;
use plotters::backend::{DrawingBackend, SVGBackend};
use plotters::style::text_anchor::{HPos, Pos, VPos};
use plotters::style::{Color, FontTransform, RGBColor, ShapeStyle, TextStyle};
use plotters_backend::{BackendCoord, DrawingErrorKind};

/// A size with two decimals, without a trailing `.00`.
pub(super) fn num(v: f64) -> String {
    let s = format!("{v:.2}");
    let s = s.trim_end_matches('0').trim_end_matches('.');
    if s == "-0" {
        "0".into()
    } else {
        s.to_string()
    }
}

/// A length in canvas units.
pub(super) fn units(pt: f64) -> i32 {
    (pt * SVG_UNITS_PER_PT).round() as i32
}

pub(super) fn canvas(p: (f64, f64)) -> BackendCoord {
    (units(p.0), units(p.1))
}

pub(super) fn colour(c: Rgb) -> RGBColor {
    RGBColor(c.0, c.1, c.2)
}

pub(super) fn stroke_style(c: Rgb, width_pt: f64) -> ShapeStyle {
    colour(c).stroke_width(units(width_pt).max(0) as u32)
}

/// plotters' SVG backend writes a text style's size divided by 1.24 as the `font-size`; the
/// style size whose quotient is exactly `size` units, so the attribute reads `800`, not
/// `799.9999999999999`.
pub(super) fn plotters_font_size(size: f64) -> f64 {
    let guess = size * 1.24;
    (-4i64..=4)
        .map(|k| f64::from_bits(guess.to_bits().wrapping_add_signed(k)))
        .find(|s| s / 1.24 == size)
        .unwrap_or(guess)
}

/// The pieces of a polyline drawn by a dash pattern (on, off, on, … lengths, pt), as SVG's
/// `stroke-dasharray` draws it: the pattern runs on across vertices, so a dash can turn a
/// corner.
pub(super) fn dash_runs(points: &[(f64, f64)], pattern: &[f64]) -> Vec<Vec<(f64, f64)>> {
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
