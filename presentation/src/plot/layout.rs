//! The layout of a figure ([`layout`]): panels, legends, labels and every mark placed at the
//! figure's printed size, and labels placed where the laid-out figure has room.

use super::axes::*;
use super::laid_out::*;
use super::*;
use mass_spring_solvers::error::Result;

pub(super) fn text_box(
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

/// A legend's entries laid out in rows no wider than `max_width`: (entry, x, row) offsets and
/// the block's size.
pub(super) fn legend_rows(
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
pub(super) fn marker_path(marker: Marker, c: (f64, f64), r: f64) -> Option<Vec<(f64, f64)>> {
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
pub(super) struct Builder {
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
pub(super) fn entries(panel: &Panel) -> Vec<Entry> {
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
        let mut right = TEXT_PT * 1.2;
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
            // An x tick label centred near the frame's right end may stick out past the
            // figure's edge (the cell's right margin plus the figure's outer one): widen the
            // margin by what it would stick out.
            let edge = cx + cell_w + outer;
            let x_scale = Scale::along_x(panel.x.log, xr, &frame);
            let overhang = if panel.frame {
                ticks(xr.0, xr.1, panel.x.log)
                    .iter()
                    .filter(|t| t.2)
                    .map(|t| x_scale.map(t.0) + text_width(&t.1, TEXT_PT) / 2.0 - edge)
                    .fold(0.0, f64::max)
            } else {
                0.0
            };
            if (needed - left).abs() < 0.5 && overhang <= 0.0 {
                break;
            }
            left = needed;
            right += overhang.max(0.0);
        }
        let sx = Scale::along_x(panel.x.log, xr, &frame);
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

pub(super) fn draw_panel(
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
