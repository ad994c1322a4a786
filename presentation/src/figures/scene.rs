//! Figures 1-4: the scene and its springs, the rope at rest, a spring and the distance
//! constraint.

use super::common::*;

use crate::data::CsvFile;
use crate::format::{full, full_opt};
use crate::inputs::ReportData;
use crate::plot::{Align, Arrow, Axis, Chart, Entry, Line, Marker, Panel, Series, FULL_WIDTH_MM};
use crate::runs::SHEET_FIGURE_STIFFNESS;
use crate::style::{BLACK, BLUE, GREEN, GREY, RED};
use crate::tables::stiffness_label;
use mass_spring_solvers::error::Result;
use mass_spring_solvers::model::system::Vec3;

/// The oblique view of Figure 1: an orthographic projection seen from azimuth 35° and
/// elevation 25°, so that lengths in the picture plane keep their scale. Returns (right, up).
pub(super) fn oblique(p: &Vec3) -> (f64, f64) {
    let (a, e) = (35f64.to_radians(), 25f64.to_radians());
    let right = p.x * a.cos() - p.z * a.sin();
    let depth = p.x * a.sin() + p.z * a.cos();
    (right, p.y * e.cos() + depth * e.sin())
}

/// Figure 1: the sheet of `docs/sheet-scene.md` hanging from two corners, one panel per
/// instant, drawn to scale in an oblique view.
pub(super) fn figure1(data: &ReportData) -> Result<Figure> {
    let sheet = &data.runs.sheet;
    let p = &sheet.params;
    let n = p.nodes_per_side;
    let mut csv = CsvFile::new(&["time_s", "i", "j", "x_m", "y_m", "z_m"]);
    // One common extent for every panel: the same scale throughout.
    let all: Vec<(f64, f64)> = sheet
        .frames
        .iter()
        .flat_map(|(_, x)| x.iter().map(oblique))
        .collect();
    let (x0, x1, y0, y1) = all.iter().fold(
        (
            f64::INFINITY,
            f64::NEG_INFINITY,
            f64::INFINITY,
            f64::NEG_INFINITY,
        ),
        |(a, b, c, d), q| (a.min(q.0), b.max(q.0), c.min(q.1), d.max(q.1)),
    );
    let mut panels = Vec::new();
    for (t, x) in &sheet.frames {
        let mut panel = Panel::new(
            Axis::linear("").range(x0 - 0.5, x1 + 0.5),
            Axis::linear("").range(y0 - 0.5, y1 + 0.5),
        );
        panel.frame = false;
        panel.equal_aspect = true;
        // The grid lines of the net (structural springs), row by row and column by column.
        for line in 0..n {
            let row: Vec<(f64, f64)> = (0..n).map(|j| oblique(&x[p.node(line, j)])).collect();
            let column: Vec<(f64, f64)> = (0..n).map(|i| oblique(&x[p.node(i, line)])).collect();
            panel
                .series
                .push(Series::line("", row, BLUE).with_weight(0.6));
            panel
                .series
                .push(Series::line("", column, BLUE).with_weight(0.6));
        }
        let held: Vec<(f64, f64)> = sheet
            .system
            .nodes()
            .iter()
            .zip(x)
            .filter(|(node, _)| node.fixed)
            .map(|(_, q)| oblique(q))
            .collect();
        panel
            .series
            .push(Series::points("", held, RED).with_marker(Marker::Square, true));
        panel.heading = format!("t = {} s", sig_short(*t));
        for i in 0..n {
            for j in 0..n {
                let q = x[p.node(i, j)];
                csv.record(vec![
                    full(*t),
                    i.to_string(),
                    j.to_string(),
                    full(q.x),
                    full(q.y),
                    full(q.z),
                ]);
            }
        }
        panels.push(panel);
    }
    let mut chart = Chart::new(FULL_WIDTH_MM, 62.0, panels);
    chart.legend = vec![
        Entry {
            label: "structural springs (grid lines)".into(),
            style: Series::line("", Vec::new(), BLUE).with_weight(0.6).style,
        },
        Entry {
            label: "held corners".into(),
            style: Series::points("", Vec::new(), RED)
                .with_marker(Marker::Square, true)
                .style,
        },
    ];
    let spring_count = sheet.system.springs().len();
    Figure::new(
        1,
        "fig01-cloth",
        format!(
            "Figure 1. A cloth simulated with a mass-spring discretisation: the sheet of `docs/sheet-scene.md` \
             ({n} × {n} nodes of {} kg, {} m apart, {spring_count} springs of k = {} N/m: structural springs on \
             the grid edges and shear springs on both diagonals of every cell), held at the two corners of one edge \
             and released flat and at rest, simulated with Backward Euler (Δt = {} s, 5 Newton iterations); panels \
             (a)-({}) at t = {}. Orthographic view from 35° azimuth and 25° elevation, the same scale in every \
             panel and in both directions; only the structural springs are drawn. The sheet swings down about the \
             held edge and stretches under its own weight; with shear springs on both diagonals it stays \
             symmetric and does not sway sideways.",
            sig_short(p.node_mass),
            sig_short(p.spacing),
            stiffness_text(SHEET_FIGURE_STIFFNESS),
            sig_short(sheet.dt),
            (b'a' + sheet.frames.len().saturating_sub(1) as u8) as char,
            sheet.frames.iter().map(|(t, _)| format!("{} s", sig_short(*t))).collect::<Vec<_>>().join(", ")
        ),
        &chart,
        csv.text(),
    )
}

/// Figure 2: our rest state and the analytic one, both stiffnesses, each panel to scale.
pub(super) fn figure2(data: &ReportData) -> Result<Figure> {
    let mut panels = Vec::new();
    let mut shapes = Vec::new();
    for stiffness in [1e3, 1e6] {
        let k = stiffness_label(stiffness);
        let mut panel = Panel::new(
            Axis::linear("x (m)"),
            Axis::linear(format!("y (m), k = {} N/m", stiffness_text(stiffness))),
        );
        panel.equal_aspect = true;
        let reference_series = reference(data, stiffness).map(|r| {
            shapes.push((format!("backward_euler_k{k}"), r.final_positions.clone()));
            Series::line("", xy(&r.final_positions), BLACK).with_marker(Marker::Circle, true)
        });
        match data.catenary.analytic(stiffness) {
            Some(nodes) => {
                panel.series.push(
                    Series::line("", xy(nodes), RED)
                        .with_line(Line::Dashed)
                        .with_marker(Marker::Square, false)
                        .with_marker_scale(1.6),
                );
                shapes.push((format!("analytic_k{k}"), nodes.to_vec()));
            }
            None => panel.label(
                (4.5, 0.0),
                (0.0, 10.0),
                Align::Middle,
                "(analytic catenary pending)",
                GREY,
            ),
        }
        // Our rest state on top of the exact one.
        panel.series.extend(reference_series);
        panels.push(panel);
    }
    let mut chart = Chart::new(FULL_WIDTH_MM, 100.0, panels);
    chart.columns = 1;
    chart.legend = vec![
        Entry {
            label: "Newton rest state (BE reference)".into(),
            style: Series::line("", Vec::new(), BLACK)
                .with_marker(Marker::Circle, true)
                .style,
        },
        Entry {
            label: "exact discrete catenary".into(),
            style: Series::line("", Vec::new(), RED)
                .with_line(Line::Dashed)
                .with_marker(Marker::Square, false)
                .with_marker_scale(1.6)
                .style,
        },
    ];
    let sag = |k: f64| {
        reference(data, k).map_or("–".to_string(), |r| {
            sig_short(-r.final_positions.iter().map(|p| p.y).fold(0.0, f64::min))
        })
    };
    Figure::new(
        2,
        "fig02-catenary",
        format!(
            "Figure 2. The catenary discretised with 10 nodes: the rest state our Backward Euler reference comes to \
             (filled circles) and the exact static equilibrium of the discrete elastic chain (hollow squares), \
             k = 10³ N/m (a) and 10⁶ N/m (b), each drawn to scale: the lowest node hangs {} m below the anchors at \
             k = 10³ N/m and {} m at 10⁶ N/m.",
            sag(1e3),
            sag(1e6)
        ),
        &chart,
        shapes_csv(&shapes),
    )
}

/// A zigzag between two points, for drawing a spring.
pub(super) fn zigzag(
    a: (f64, f64),
    b: (f64, f64),
    turns: usize,
    amplitude: f64,
) -> Vec<(f64, f64)> {
    let (dx, dy) = (b.0 - a.0, b.1 - a.1);
    let len = (dx * dx + dy * dy).sqrt();
    let (nx, ny) = (-dy / len, dx / len);
    let lead = 0.2;
    let mut points = vec![a, (a.0 + lead * dx, a.1 + lead * dy)];
    let n = 2 * turns;
    for i in 0..n {
        let s = lead + (1.0 - 2.0 * lead) * (i as f64 + 0.5) / n as f64;
        let side = if i % 2 == 0 { amplitude } else { -amplitude };
        points.push((a.0 + s * dx + side * nx, a.1 + s * dy + side * ny));
    }
    points.extend([(a.0 + (1.0 - lead) * dx, a.1 + (1.0 - lead) * dy), b]);
    points
}

/// Figure 3: the rope's nodes and springs, to scale.
pub(super) fn figure3() -> Result<Figure> {
    let rope = mass_spring_solvers::model::scene::RopeParams::thesis(1e3);
    let nodes: Vec<(f64, f64)> = (0..rope.nodes)
        .map(|i| {
            let p = rope.anchor_left
                + (rope.anchor_right - rope.anchor_left) * (i as f64 / (rope.nodes - 1) as f64);
            (p.x, p.y)
        })
        .collect();
    let mut panel = Panel::new(
        Axis::linear("x (m)").range(-1.7, 10.7),
        Axis::linear("y (m)").range(-1.2, 0.7),
    );
    panel.frame = false;
    panel.equal_aspect = true;
    let mut csv = CsvFile::new(&["element", "index", "x_a_m", "y_a_m", "x_b_m", "y_b_m"]);
    for (i, w) in nodes.windows(2).enumerate() {
        let label = if i == 0 {
            "spring: stiffness k, rest length l₀ = 1 m"
        } else {
            ""
        };
        panel
            .series
            .push(Series::line(label, zigzag(w[0], w[1], 3, 0.12), BLUE).with_weight(0.8));
        csv.record(vec![
            "spring".to_string(),
            i.to_string(),
            full(w[0].0),
            full(w[0].1),
            full(w[1].0),
            full(w[1].1),
        ]);
    }
    let last = nodes.len() - 1;
    panel.series.push(
        Series::points("free node, m = 1 kg", nodes[1..last].to_vec(), BLACK)
            .with_marker(Marker::Circle, true),
    );
    panel.series.push(
        Series::points("fixed node (anchor)", vec![nodes[0], nodes[last]], RED)
            .with_marker(Marker::Square, true)
            .with_marker_scale(1.2),
    );
    for (i, &(x, y)) in nodes.iter().enumerate() {
        panel.label(
            (x, y),
            (0.0, -13.0),
            Align::Middle,
            format!("x{}", subscript(i)),
            BLACK,
        );
        csv.record(vec![
            "node".to_string(),
            i.to_string(),
            full(x),
            full(y),
            String::new(),
            String::new(),
        ]);
    }
    panel.label(nodes[0], (-5.0, 4.0), Align::End, "(0, 0) m", GREY);
    panel.label(nodes[last], (5.0, 4.0), Align::Start, "(9, 0) m", GREY);
    panel.arrows.push(Arrow {
        from: (4.5, -0.55),
        to: (4.5, -1.15),
        color: GREY,
    });
    panel.label(
        (4.5, -0.85),
        (5.0, -3.0),
        Align::Start,
        "g = 9.81 m/s²",
        GREY,
    );
    Figure::new(
        3,
        "fig03-rope-structure",
        "Figure 3. The internal structure of the rope, to scale: one spring between each pair of consecutive nodes \
         (10 nodes of 1 kg, 9 springs of rest length 1 m); nodes 0 and 9 are fixed at (0, 0) and (9, 0) m, and the \
         rope starts straight, taut and at rest."
            .into(),
        &Chart::new(FULL_WIDTH_MM, 45.0, vec![panel]),
        csv.text(),
    )
}

/// Figure 4: the distance constraint and its gradient.
pub(super) fn figure4() -> Result<Figure> {
    let x1: (f64, f64) = (0.0, 0.0);
    let x2: (f64, f64) = (1.6, 0.9);
    let l0 = 1.0;
    let (dx, dy) = (x1.0 - x2.0, x1.1 - x2.1);
    let d = (dx * dx + dy * dy).sqrt();
    let n = (dx / d, dy / d);
    let c = d - l0;
    let mut left = Panel::new(
        Axis::linear("x (m)").range(-1.3, 2.9),
        Axis::linear("y (m)").range(-1.0, 1.9),
    );
    left.equal_aspect = true;
    left.series.push(
        Series::line("current length |x₁ − x₂|", vec![x1, x2], BLACK)
            .with_marker(Marker::Circle, true),
    );
    // The rest length and C drawn beside the spring, on its lower side.
    let side = (0.12 * n.1, -0.12 * n.0);
    let side = if side.1 > 0.0 {
        (-side.0, -side.1)
    } else {
        side
    };
    let rest = vec![
        (x2.0 + side.0, x2.1 + side.1),
        (x2.0 + side.0 + l0 * n.0, x2.1 + side.1 + l0 * n.1),
    ];
    left.series
        .push(Series::line("rest length l₀ = 1 m", rest.clone(), BLUE).with_weight(2.0));
    left.series.push(
        Series::line(
            format!("C = {} m", sig_short(c)),
            vec![rest[1], (x1.0 + side.0, x1.1 + side.1)],
            RED,
        )
        .with_weight(2.0)
        .with_line(Line::Dashed),
    );
    // The gradients are unit vectors: arrows 1 m long on this to-scale drawing.
    let g1 = (x1.0 + n.0, x1.1 + n.1);
    let g2 = (x2.0 - n.0, x2.1 - n.1);
    for (from, to) in [(x1, g1), (x2, g2)] {
        left.arrows.push(Arrow {
            from,
            to,
            color: GREEN,
        });
    }
    // Up and to the left of each end: away from the spring, the arrows and the C lines.
    left.label(x1, (-4.0, 4.0), Align::End, "x₁", BLACK);
    left.label(x2, (-4.0, 4.0), Align::End, "x₂", BLACK);
    left.label(g1, (0.0, -12.0), Align::Middle, "∇ₓ₁C", GREEN);
    left.label(g2, (0.0, 6.0), Align::Middle, "∇ₓ₂C = −∇ₓ₁C", GREEN);
    let mut right = Panel::new(
        Axis::linear("length |x₁ − x₂| (m)").range(0.0, 2.0),
        Axis::linear("C (m)").range(-1.1, 1.1),
    );
    right.series.push(Series::line(
        "C = |x₁ − x₂| − l₀ (slope |∇C| = 1)",
        vec![(0.0, -l0), (2.0, 2.0 - l0)],
        RED,
    ));
    right
        .series
        .push(Series::points("this spring", vec![(d, c)], BLACK).with_marker(Marker::Circle, true));
    right.series.push(
        Series::points("rest length l₀", vec![(l0, 0.0)], BLUE).with_marker(Marker::Square, true),
    );
    right.label((l0, 0.0), (6.0, -3.0), Align::Start, "rest: C = 0", GREY);
    right.label(
        (0.5, -0.5),
        (6.0, -6.0),
        Align::Start,
        "compressed: C < 0",
        GREY,
    );
    right.label(
        (1.5, 0.5),
        (-6.0, 6.0),
        Align::End,
        "stretched: C > 0",
        GREY,
    );
    let mut csv = CsvFile::new(&["quantity", "x_m", "y_m"]);
    for (quantity, x, y) in [
        ("x1", x1.0, Some(x1.1)),
        ("x2", x2.0, Some(x2.1)),
        ("grad_x1_c", n.0, Some(n.1)),
        ("grad_x2_c", -n.0, Some(-n.1)),
        ("length", d, None),
        ("rest_length", l0, None),
        ("c", c, None),
    ] {
        csv.record(vec![quantity.into(), full(x), full_opt(y)]);
    }
    Figure::new(
        4,
        "fig04-distance-constraint",
        "Figure 4. The distance constraint C = |x₁ − x₂| − l₀ of a spring (Eqs 1, 48) and its gradient (Eq 49), \
         drawn to scale: (a) a stretched spring with the gradients at its ends, unit vectors (1 m long here) along \
         the spring, opposite at the two ends, pointing where C grows; (b) C against the spring's length."
            .into(),
        &Chart::new(FULL_WIDTH_MM, 75.0, vec![left, right]),
        csv.text(),
    )
}
