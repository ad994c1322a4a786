//! Figures 1-15 of the thesis, redrawn from our runs as SVG, each with the CSV of the points
//! it draws and a caption that states every choice the thesis leaves open.
//!
//! Colours follow Table 8: Backward Euler black; XPBD blue, Fast m-s orange, ADMM green,
//! darker for fewer iterations. Published values are hollow markers on dashed lines, ours
//! filled markers on solid lines.

use crate::error::Result;
use crate::experiments::{published_rows, Measured, PublishedRow, SolverKind};
use crate::report::format::{full, sig4};
use crate::report::plot::{svg, Arrow, Axis, Legend, Line, Marker, Panel, Series};
use crate::report::runs::{FigureRuns, BE_SOFT, BE_STIFF, FMS_SOFT_COARSE, STIFF_MIDDLE};
use crate::report::tables::{iteration_count, measured, stiffness_label};
use crate::report::ReportData;
use crate::solver::Run;
use crate::system::Vec3;
use plotters::style::RGBColor;

/// One figure: file stem (`fig05-error-dt-k1e3`), caption, SVG and CSV text.
#[derive(Debug, Clone, PartialEq)]
pub struct Figure {
    pub number: u8,
    pub stem: String,
    pub caption: String,
    pub svg: String,
    pub csv: String,
}

/// Size of one panel, px.
const PANEL: (u32, u32) = (760, 520);
/// Size of one panel of a two-panel figure, px.
const HALF: (u32, u32) = (600, 500);
/// Long series are reduced to this many buckets (min and max of each) before drawing.
const MAX_BUCKETS: usize = 1500;

const BLACK: RGBColor = RGBColor(0, 0, 0);
const GREY: RGBColor = RGBColor(150, 150, 150);
const RED: RGBColor = RGBColor(200, 30, 30);

/// The colour of a solver at its `index`-th iteration count (0 = fewest, darkest).
pub fn colour(solver: SolverKind, index: usize) -> RGBColor {
    let shades: [RGBColor; 3] = match solver {
        SolverKind::BackwardEuler => [BLACK, BLACK, BLACK],
        SolverKind::Xpbd => [
            RGBColor(8, 48, 107),
            RGBColor(33, 113, 181),
            RGBColor(107, 174, 214),
        ],
        SolverKind::FastMassSpring => [
            RGBColor(127, 39, 4),
            RGBColor(217, 72, 1),
            RGBColor(253, 141, 60),
        ],
        SolverKind::AdmmPd => [
            RGBColor(0, 68, 27),
            RGBColor(35, 139, 69),
            RGBColor(116, 196, 118),
        ],
    };
    shades[index.min(2)]
}

fn marker(solver: SolverKind) -> Marker {
    match solver {
        SolverKind::BackwardEuler => Marker::Square,
        SolverKind::Xpbd => Marker::Circle,
        SolverKind::FastMassSpring => Marker::Triangle,
        SolverKind::AdmmPd => Marker::Cross,
    }
}

/// Long-format CSV of named (x, y) series.
fn series_csv(x: &str, y: &str, series: &[(String, Vec<(f64, f64)>)]) -> String {
    let mut out = format!("series,{x},{y}\n");
    for (name, points) in series {
        for &(a, b) in points {
            out += &format!("{name},{},{}\n", full(a), full(b));
        }
    }
    out
}

/// Node positions (x, y) of named shapes as CSV.
fn shapes_csv(shapes: &[(String, Vec<Vec3>)]) -> String {
    let mut out = String::from("series,node,x_m,y_m\n");
    for (name, nodes) in shapes {
        for (i, p) in nodes.iter().enumerate() {
            out += &format!("{name},{i},{},{}\n", full(p.x), full(p.y));
        }
    }
    out
}

/// A series reduced to the minimum and maximum of each of at most `buckets` consecutive
/// runs of samples, in time order, so that peaks survive the reduction.
pub fn decimate(points: &[(f64, f64)], buckets: usize) -> Vec<(f64, f64)> {
    if points.len() <= 2 * buckets {
        return points.to_vec();
    }
    let size = points.len().div_ceil(buckets);
    let mut out = Vec::with_capacity(2 * buckets + 1);
    for chunk in points.chunks(size) {
        let lo = chunk
            .iter()
            .enumerate()
            .min_by(|a, b| a.1 .1.total_cmp(&b.1 .1))
            .map(|(i, _)| i);
        let hi = chunk
            .iter()
            .enumerate()
            .max_by(|a, b| a.1 .1.total_cmp(&b.1 .1))
            .map(|(i, _)| i);
        let (Some(lo), Some(hi)) = (lo, hi) else {
            continue;
        };
        let (first, second) = if lo <= hi { (lo, hi) } else { (hi, lo) };
        out.push(chunk[first]);
        if second != first {
            out.push(chunk[second]);
        }
    }
    if let (Some(last), Some(end)) = (out.last(), points.last()) {
        if last != end {
            out.push(*end);
        }
    }
    out
}

/// The kinetic energy of a run against time, up to `until` seconds.
fn energy_series(run: &Run, until: f64) -> Vec<(f64, f64)> {
    run.kinetic_energy
        .iter()
        .enumerate()
        .map(|(i, &e)| (i as f64 * run.dt, e))
        .take_while(|&(t, _)| t <= until + 0.5 * run.dt)
        .collect()
}

/// Figures 5, 7, 9, 10: rest-state error against dt on log axes, published and ours side by
/// side, one series per solver and iteration count.
fn error_against_dt(
    data: &ReportData,
    number: u8,
    stiffness: f64,
    solvers: &[SolverKind],
) -> Result<Figure> {
    let k = stiffness_label(stiffness);
    let mut published = Panel::new(
        format!("published (thesis), k = {k} N/m"),
        Axis::log("dt (s)").range(5e-4, 0.2),
        Axis::log("rest-state error (m)"),
    );
    let mut ours = Panel::new(
        format!("ours, k = {k} N/m"),
        Axis::log("dt (s)").range(5e-4, 0.2),
        Axis::log("rest-state error (m)"),
    );
    let mut csv_rows = String::from("solver,iterations,dt_s,error_published_m,error_ours_m\n");
    let mut all_y = Vec::new();
    for &solver in solvers {
        for index in 0..3 {
            let Some(iterations) = iteration_count(solver, index) else {
                continue;
            };
            let rows: Vec<&PublishedRow> = published_rows()
                .iter()
                .filter(|r| {
                    r.solver == solver && r.iterations == iterations && r.stiffness == stiffness
                })
                .collect();
            let mut sorted = rows.clone();
            sorted.sort_by(|a, b| a.dt_s.total_cmp(&b.dt_s));
            let pub_points: Vec<(f64, f64)> = sorted
                .iter()
                .filter_map(|r| r.error.map(|e| (r.dt_s, e)))
                .collect();
            let our_points: Vec<(f64, f64)> = sorted
                .iter()
                .filter_map(|r| {
                    measured(&data.results, r)
                        .and_then(|m| m.error_sum)
                        .map(|e| (r.dt_s, e))
                })
                .collect();
            for r in &sorted {
                let m = measured(&data.results, r);
                csv_rows += &format!(
                    "{},{},{},{},{}\n",
                    solver.id(),
                    iterations,
                    full(r.dt_s),
                    r.error.map(full).unwrap_or_default(),
                    m.and_then(|m| m.error_sum).map(full).unwrap_or_default()
                );
            }
            let c = colour(solver, index);
            let label = format!("{} {iterations} it.", solver.abbreviation());
            all_y.extend(pub_points.iter().chain(&our_points).map(|p| p.1));
            published.series.push(
                Series::line(label.clone(), pub_points, c)
                    .with_line(Line::Dashed)
                    .with_marker(marker(solver), false),
            );
            if !our_points.is_empty() {
                ours.series
                    .push(Series::line(label, our_points, c).with_marker(marker(solver), true));
            }
        }
    }
    // One y range for both panels, so that they compare at a glance.
    let (lo, hi) = all_y
        .iter()
        .filter(|v| **v > 0.0)
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), &v| {
            (lo.min(v), hi.max(v))
        });
    if lo.is_finite() {
        // One decade of headroom above the data for the legend.
        let (lo, hi) = (
            10f64.powf(lo.log10().floor()),
            10f64.powf(hi.log10().ceil() + 1.0),
        );
        published.y = published.y.clone().range(lo, hi);
        ours.y = ours.y.clone().range(lo, hi);
    }
    published.legend = Legend::UpperLeft;
    ours.legend = Legend::UpperLeft;
    if ours.series.is_empty() {
        ours.label(
            (1.5e-3, lo.max(1e-12) * 2.0),
            "(not run in this report)",
            GREY,
        );
    }
    let which = if solvers.len() == 3 {
        "all methods"
    } else {
        "the two Projective Dynamics methods"
    };
    let stem = format!(
        "fig{number:02}-error-dt-k{k}{}",
        if solvers.len() == 3 { "" } else { "-pd" }
    );
    Ok(Figure {
        number,
        stem,
        caption: format!(
            "Figure {number}. Rest-state error against dt, k = {k} N/m, {which}: published (left, hollow markers, \
             dashed) and ours (right, filled markers); one series per solver and iteration count. The error is the \
             sum over the nodes of the distance between the final positions and those of our Backward Euler \
             reference of the same stiffness (the thesis's measure, convention 7). Same axes in both panels."
        ),
        svg: svg(&[published, ours], HALF)?,
        csv: csv_rows,
    })
}

fn xy(nodes: &[Vec3]) -> Vec<(f64, f64)> {
    nodes.iter().map(|p| (p.x, p.y)).collect()
}

/// Figures 6 and 8: the rest state of Backward Euler against XPBD at dt = 0.1 s, every
/// iteration count.
fn rest_state_xpbd(data: &ReportData, number: u8, stiffness: f64) -> Result<Figure> {
    let k = stiffness_label(stiffness);
    let mut panel = Panel::new(
        format!("rest state, k = {k} N/m"),
        Axis::linear("x (m)"),
        Axis::linear("y (m)"),
    );
    panel.legend = Legend::UpperMiddle;
    let mut shapes = Vec::new();
    let reference = data.results.rows.iter().find(|m| {
        m.published.solver == SolverKind::BackwardEuler && m.published.stiffness == stiffness
    });
    if let Some(r) = reference {
        panel.series.push(
            Series::line(
                "BE reference (dt 0.001, 5 it.)",
                xy(&r.final_positions),
                BLACK,
            )
            .with_width(3)
            .with_marker(Marker::Square, true),
        );
        shapes.push(("backward_euler".to_string(), r.final_positions.clone()));
    }
    for index in 0..3 {
        let Some(iterations) = iteration_count(SolverKind::Xpbd, index) else {
            continue;
        };
        let row = published_rows().iter().find(|r| {
            r.solver == SolverKind::Xpbd
                && r.stiffness == stiffness
                && r.dt_s == 0.1
                && r.iterations == iterations
        });
        if let Some(m) = row.and_then(|r| measured(&data.results, r)) {
            let label = format!(
                "XPBD dt 0.1, {iterations} it. (error {} m)",
                opt_sig(m.error_sum)
            );
            panel.series.push(
                Series::line(
                    label,
                    xy(&m.final_positions),
                    colour(SolverKind::Xpbd, index),
                )
                .with_marker(Marker::Circle, true),
            );
            shapes.push((
                format!("xpbd_dt0.1_{iterations}it"),
                m.final_positions.clone(),
            ));
        }
    }
    if panel.series.len() < 2 {
        panel.label((0.5, -0.5), "(XPBD not run in this report)", GREY);
    }
    headroom(&mut panel, 0.3);
    Ok(Figure {
        number,
        stem: format!("fig{number:02}-rest-state-xpbd-k{k}"),
        caption: format!(
            "Figure {number}. Rest state of Backward Euler against XPBD, k = {k} N/m. The thesis does not say which \
             XPBD run it shows; we show the coarsest time step, dt = 0.1 s, with each of its iteration counts (1, 20, \
             50), where the difference is visible and shrinks with the iterations. Node positions at the end of each \
             run (the first kinetic-energy peak below 0.001 J)."
        ),
        svg: svg(&[panel], PANEL)?,
        csv: shapes_csv(&shapes),
    })
}

fn opt_sig(x: Option<f64>) -> String {
    x.map_or_else(|| "–".into(), sig4)
}

/// Figure 1: the cloth.
fn figure1(data: &ReportData) -> Result<Figure> {
    let cloth = &data.runs.cloth;
    let mut panel = Panel::new(
        "cloth hanging from two corners, Backward Euler",
        Axis::linear("x (m)"),
        Axis::linear("y (m)"),
    );
    panel.legend = Legend::LowerRight;
    let shades = [
        RGBColor(190, 190, 190),
        RGBColor(100, 140, 200),
        RGBColor(20, 40, 120),
    ];
    let mut csv = String::from("time_s,spring,x_a_m,y_a_m,x_b_m,y_b_m\n");
    for (f, (t, x)) in cloth.frames.iter().enumerate() {
        let color = shades[f.min(2)];
        // Every spring as its own two-point polyline, separated by NaN gaps in one series.
        let mut points = Vec::new();
        for (s, spring) in cloth.system.springs().iter().enumerate() {
            let (a, b) = (x[spring.a], x[spring.b]);
            points.extend([(a.x, a.y), (b.x, b.y), (f64::NAN, f64::NAN)]);
            csv += &format!(
                "{},{s},{},{},{},{}\n",
                full(*t),
                full(a.x),
                full(a.y),
                full(b.x),
                full(b.y)
            );
        }
        for segment in points.split(|p| p.0.is_nan()).filter(|s| !s.is_empty()) {
            panel
                .series
                .push(Series::line("", segment.to_vec(), color).with_width(1));
        }
        if let Some(last) = panel.series.last_mut() {
            last.label = format!("t = {} s", sig_short(*t));
        }
    }
    let pinned: Vec<(f64, f64)> = cloth
        .system
        .nodes()
        .iter()
        .filter(|n| n.fixed)
        .map(|n| (n.position.x, n.position.y))
        .collect();
    panel.series.push(
        Series::line("pinned corners", pinned, RED)
            .with_line(Line::None)
            .with_marker(Marker::Square, true),
    );
    let p = &cloth.params;
    Ok(Figure {
        number: 1,
        stem: "fig01-cloth".into(),
        caption: format!(
            "Figure 1. A cloth simulated with a mass-spring discretisation: the hanging cloth of `particles::scenes` \
             ({}×{} particles of {} kg, {} m apart, a spring of k = {} N/m on every grid edge and one diagonal per \
             quad), pinned at its two top corners and released at rest, simulated with Backward Euler (dt = {} s, 5 \
             Newton iterations); the mesh at t = {}.",
            p.nx,
            p.ny,
            sig_short(p.particle_mass),
            sig_short(p.spacing),
            sig_short(p.stiffness),
            sig_short(cloth.dt),
            cloth.frames.iter().map(|(t, _)| format!("{} s", sig_short(*t))).collect::<Vec<_>>().join(", ")
        ),
        svg: svg(&[panel], PANEL)?,
        csv,
    })
}

/// A short decimal (`0.25`, `1`, `0.001`) for captions.
fn sig_short(x: f64) -> String {
    let s = sig4(x);
    if s.contains('.') && !s.contains('e') {
        s.trim_end_matches('0').trim_end_matches('.').to_string()
    } else {
        s
    }
}

/// Figure 2: our rest state and the analytic one, both stiffnesses.
fn figure2(data: &ReportData) -> Result<Figure> {
    let mut panels = Vec::new();
    let mut shapes = Vec::new();
    for stiffness in [1e3, 1e6] {
        let k = stiffness_label(stiffness);
        let mut panel = Panel::new(
            format!("k = {k} N/m"),
            Axis::linear("x (m)"),
            Axis::linear("y (m)"),
        );
        panel.legend = Legend::UpperMiddle;
        if let Some(r) = reference(data, stiffness) {
            panel.series.push(
                Series::line(
                    "Newton rest state (BE reference)",
                    xy(&r.final_positions),
                    BLACK,
                )
                .with_marker(Marker::Circle, true),
            );
            shapes.push((format!("backward_euler_k{k}"), r.final_positions.clone()));
        }
        match data.catenary.analytic(stiffness) {
            Some(nodes) => {
                panel.series.push(
                    Series::line("exact discrete catenary", xy(nodes), RED)
                        .with_line(Line::Dashed)
                        .with_marker(Marker::Square, false)
                        .with_marker_size(7),
                );
                shapes.push((format!("analytic_k{k}"), nodes.to_vec()));
            }
            None => panel.label((2.0, 0.0), "(analytic catenary pending)", GREY),
        }
        panels.push(panel);
    }
    Ok(Figure {
        number: 2,
        stem: "fig02-catenary".into(),
        caption: "Figure 2. The catenary discretised with 10 nodes: the rest state our Backward Euler reference comes \
                  to (filled circles) and the exact static equilibrium of the discrete elastic chain (hollow squares), \
                  for both stiffnesses. The vertical scales differ: the lowest node hangs about 1.47 m below the \
                  anchors at k = 1e3 and 0.143 m at k = 1e6."
            .into(),
        svg: svg(&panels, HALF)?,
        csv: shapes_csv(&shapes),
    })
}

fn reference(data: &ReportData, stiffness: f64) -> Option<&Measured> {
    data.results.rows.iter().find(|m| {
        m.published.solver == SolverKind::BackwardEuler && m.published.stiffness == stiffness
    })
}

/// A zigzag between two points, for drawing a spring.
fn zigzag(a: (f64, f64), b: (f64, f64), turns: usize, amplitude: f64) -> Vec<(f64, f64)> {
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

/// Figure 3: the rope's nodes and springs.
fn figure3() -> Result<Figure> {
    let rope = crate::scene::RopeParams::thesis(1e3);
    let nodes: Vec<(f64, f64)> = (0..rope.nodes)
        .map(|i| {
            let p = rope.anchor_left
                + (rope.anchor_right - rope.anchor_left) * (i as f64 / (rope.nodes - 1) as f64);
            (p.x, p.y)
        })
        .collect();
    let mut panel = Panel::new(
        "the thesis rope: 10 nodes, 9 springs",
        Axis::linear("x (m)").range(-0.6, 9.6),
        Axis::linear("y (m)").range(-1.2, 1.0),
    );
    panel.mesh = false;
    let blue = RGBColor(33, 113, 181);
    let mut csv = String::from("element,index,x_a_m,y_a_m,x_b_m,y_b_m\n");
    for (i, w) in nodes.windows(2).enumerate() {
        let label = if i == 0 {
            "spring: k, rest length l0 = 1 m"
        } else {
            ""
        };
        panel
            .series
            .push(Series::line(label, zigzag(w[0], w[1], 3, 0.12), blue).with_width(2));
        csv += &format!(
            "spring,{i},{},{},{},{}\n",
            full(w[0].0),
            full(w[0].1),
            full(w[1].0),
            full(w[1].1)
        );
    }
    let last = nodes.len() - 1;
    let free: Vec<(f64, f64)> = nodes[1..last].to_vec();
    panel.series.push(
        Series::line("free node, m = 1 kg", free, BLACK)
            .with_line(Line::None)
            .with_marker(Marker::Circle, true),
    );
    panel.series.push(
        Series::line("fixed node (anchor)", vec![nodes[0], nodes[last]], RED)
            .with_line(Line::None)
            .with_marker(Marker::Square, true),
    );
    for (i, &(x, y)) in nodes.iter().enumerate() {
        panel.label((x - 0.12, y - 0.2), format!("x{i}"), BLACK);
        csv += &format!("node,{i},{},{},,\n", full(x), full(y));
    }
    panel.label((-0.45, 0.42), "(0, 0) m", GREY);
    panel.label((8.4, 0.42), "(9, 0) m", GREY);
    panel.arrows.push(Arrow {
        from: (4.5, -0.55),
        to: (4.5, -1.05),
        color: GREY,
    });
    panel.label((4.65, -0.7), "g = 9.81 m/s²", GREY);
    panel.legend = Legend::UpperMiddle;
    Ok(Figure {
        number: 3,
        stem: "fig03-rope-structure".into(),
        caption: "Figure 3. The internal structure of the rope: one spring between each pair of consecutive nodes \
                  (10 nodes of 1 kg, 9 springs of rest length 1 m); nodes 0 and 9 are fixed at (0, 0) and (9, 0) m, \
                  and the rope starts straight, taut and at rest."
            .into(),
        svg: svg(&[panel], (900, 360))?,
        csv,
    })
}

/// Figure 4: the distance constraint and its gradient.
fn figure4() -> Result<Figure> {
    let x1: (f64, f64) = (0.0, 0.0);
    let x2: (f64, f64) = (1.6, 0.9);
    let l0 = 1.0;
    let (dx, dy) = (x1.0 - x2.0, x1.1 - x2.1);
    let d = (dx * dx + dy * dy).sqrt();
    let n = (dx / d, dy / d);
    let c = d - l0;
    let mut left = Panel::new(
        "C = |x1 - x2| - l0 and its gradient",
        Axis::linear("x (m)").range(-1.2, 2.8),
        Axis::linear("y (m)").range(-1.0, 1.8),
    );
    left.legend = Legend::LowerRight;
    left.series.push(
        Series::line("current length |x1 - x2|", vec![x1, x2], BLACK)
            .with_marker(Marker::Circle, true),
    );
    // The rest length and C drawn beside the spring, on its lower side.
    let side = (0.1 * n.1, -0.1 * n.0);
    let side = if side.1 > 0.0 {
        (-side.0, -side.1)
    } else {
        side
    };
    let rest = vec![
        (x2.0 + side.0, x2.1 + side.1),
        (x2.0 + side.0 + l0 * n.0, x2.1 + side.1 + l0 * n.1),
    ];
    left.series.push(
        Series::line("rest length l0 = 1 m", rest.clone(), RGBColor(33, 113, 181)).with_width(4),
    );
    let stretch = vec![(rest[1].0, rest[1].1), (x1.0 + side.0, x1.1 + side.1)];
    left.series
        .push(Series::line(format!("C = {} m", sig_short(c)), stretch.clone(), RED).with_width(4));
    let g1 = (x1.0 + 0.8 * n.0, x1.1 + 0.8 * n.1);
    let g2 = (x2.0 - 0.8 * n.0, x2.1 - 0.8 * n.1);
    left.arrows.push(Arrow {
        from: x1,
        to: g1,
        color: RGBColor(35, 139, 69),
    });
    left.arrows.push(Arrow {
        from: x2,
        to: g2,
        color: RGBColor(35, 139, 69),
    });
    left.label((x1.0 - 0.3, x1.1 + 0.22), "x1", BLACK);
    left.label((x2.0 - 0.3, x2.1 + 0.22), "x2", BLACK);
    left.label(
        (g1.0 - 0.2, g1.1 - 0.12),
        "∇x1 C = (x1 - x2)/|x1 - x2|",
        RGBColor(35, 139, 69),
    );
    left.label(
        (g2.0 - 0.55, g2.1 + 0.35),
        "∇x2 C = -∇x1 C",
        RGBColor(35, 139, 69),
    );
    let mut right = Panel::new(
        "C against the spring's length",
        Axis::linear("length |x1 - x2| (m)").range(0.0, 2.0),
        Axis::linear("C (m)").range(-1.1, 1.1),
    );
    right.legend = Legend::LowerRight;
    right.series.push(Series::line(
        "C = |x1 - x2| - l0 (slope |∇C| = 1)",
        vec![(0.0, -l0), (2.0, 2.0 - l0)],
        RED,
    ));
    right.series.push(
        Series::line("this spring", vec![(d, c)], BLACK)
            .with_line(Line::None)
            .with_marker(Marker::Circle, true),
    );
    right.series.push(
        Series::line("rest length l0", vec![(l0, 0.0)], RGBColor(33, 113, 181))
            .with_line(Line::None)
            .with_marker(Marker::Square, true),
    );
    right.label((1.05, -0.05), "rest: C = 0", GREY);
    right.label((0.05, -0.1), "compressed: C < 0", GREY);
    right.label((1.05, 0.95), "stretched: C > 0", GREY);
    let csv = format!(
        "quantity,x,y\nx1,{},{}\nx2,{},{}\ngrad_x1_C,{},{}\ngrad_x2_C,{},{}\nlength_m,{},\nrest_length_m,{},\nC_m,{},\n",
        full(x1.0), full(x1.1), full(x2.0), full(x2.1), full(n.0), full(n.1), full(-n.0), full(-n.1), full(d), full(l0), full(c)
    );
    Ok(Figure {
        number: 4,
        stem: "fig04-distance-constraint".into(),
        caption: "Figure 4. The distance constraint C = |x1 - x2| - l0 of a spring (Eqs 1, 48) and its gradient (Eq 49): \
                  unit vectors along the spring, opposite at the two ends, pointing where C grows. Left: a stretched \
                  spring; right: C against the spring's length."
            .into(),
        svg: svg(&[left, right], HALF)?,
        csv,
    })
}

/// The peaks of a run inside a window, for markers.
fn peaks_until(run: &Run, until: f64) -> Vec<(f64, f64)> {
    run.peaks
        .iter()
        .filter(|p| p.time_exact <= until)
        .map(|p| (p.time_exact, p.energy))
        .collect()
}

/// Figure 11: two periods of the reference's kinetic energy, k = 1e6.
fn figure11(runs: &FigureRuns) -> Result<Figure> {
    let mut panel = Panel::new(
        "Backward Euler, k = 1e6 N/m, dt = 0.001 s",
        Axis::linear("time (s)"),
        Axis::linear("kinetic energy (J)"),
    );
    let mut csv_series = Vec::new();
    let mut caption_extra = String::new();
    if let Some((_, run)) = runs.get(BE_STIFF) {
        // Two periods T = 4 half-periods: up to the fifth kinetic-energy peak.
        let until = run.peaks.get(4).map_or(1.0, |p| p.time_exact) + 0.02;
        let ke = energy_series(run, until);
        let peaks = peaks_until(run, until);
        if peaks.len() > 1 {
            let intervals: Vec<String> = peaks.windows(2).map(|w| sig4(w[1].0 - w[0].0)).collect();
            caption_extra = format!(
                " Intervals between peaks 1 to 5: {} s (the thesis's T/2 is their mean over the whole run).",
                intervals.join(", ")
            );
        }
        for (i, &(t, e)) in peaks.iter().enumerate() {
            panel.label((t - 0.012, e + 0.35), format!("{}", i + 1), BLACK);
        }
        panel
            .series
            .push(Series::line("kinetic energy", ke.clone(), BLACK));
        panel.series.push(
            Series::line("peaks", peaks.clone(), RED)
                .with_line(Line::None)
                .with_marker(Marker::Circle, true),
        );
        csv_series.push(("kinetic_energy_J".to_string(), ke));
        csv_series.push(("peak_J".to_string(), peaks));
    }
    Ok(Figure {
        number: 11,
        stem: "fig11-kinetic-energy-reference".into(),
        caption: format!(
            "Figure 11. Two periods of the kinetic energy of Backward Euler (dt = 0.001 s, 5 Newton iterations), \
             k = 1e6 N/m, from the release at rest: the kinetic energy peaks twice per period of the rope, so two \
             periods span peaks 1 to 5.{caption_extra}"
        ),
        svg: svg(&[panel], PANEL)?,
        csv: series_csv("time_s", "value", &csv_series),
    })
}

/// The five instants of Figure 12: release, first peak, first minimum after it, second
/// peak, second minimum (sample indices).
pub fn five_instants(kinetic_energy: &[f64]) -> Vec<usize> {
    let mut instants = vec![0];
    let mut want_peak = true;
    for i in 1..kinetic_energy.len().saturating_sub(1) {
        let (a, b, c) = (
            kinetic_energy[i - 1],
            kinetic_energy[i],
            kinetic_energy[i + 1],
        );
        let hit = if want_peak {
            a < b && b >= c
        } else {
            a > b && b <= c
        };
        if hit {
            instants.push(i);
            want_peak = !want_peak;
            if instants.len() == 5 {
                break;
            }
        }
    }
    instants
}

/// Figure 12: the kinetic energy over one period with five marked instants, and the rope at
/// those instants.
fn figure12(runs: &FigureRuns) -> Result<Figure> {
    let mut energy = Panel::new(
        "kinetic energy, k = 1e3 N/m",
        Axis::linear("time (s)"),
        Axis::linear("kinetic energy (J)"),
    );
    let mut rope = Panel::new(
        "the rope at the marked instants",
        Axis::linear("x (m)"),
        Axis::linear("y (m)"),
    );
    energy.legend = Legend::UpperRight;
    rope.legend = Legend::LowerRight;
    let mut csv = String::from("instant,time_s,kinetic_energy_J,node,x_m,y_m\n");
    let palette = [
        GREY,
        RGBColor(217, 72, 1),
        RGBColor(35, 139, 69),
        RGBColor(33, 113, 181),
        RGBColor(120, 40, 160),
    ];
    rope.y = rope.y.clone().range(-3.6, 0.3);
    if let Some((_, run)) = runs.get(BE_SOFT) {
        let instants = five_instants(&run.kinetic_energy);
        let top = run
            .kinetic_energy
            .iter()
            .take(instants.last().map_or(0, |&i| i + 1))
            .fold(0.0, |m: f64, &e| m.max(e));
        let end = instants.last().map_or(1.0, |&i| i as f64 * run.dt) + 0.05;
        energy.series.push(Series::line(
            "kinetic energy",
            energy_series(run, end),
            BLACK,
        ));
        for (n, &i) in instants.iter().enumerate() {
            let t = i as f64 * run.dt;
            let e = run.kinetic_energy[i];
            let c = palette[n % palette.len()];
            energy.series.push(
                Series::line("", vec![(t, e)], c)
                    .with_line(Line::None)
                    .with_marker(Marker::Circle, true),
            );
            energy.label((t - 0.012, e + 0.09 * top), format!("{}", n + 1), c);
            if let Some((_, state)) = run.positions.get(i) {
                let what = match n {
                    0 => "release",
                    1 | 3 => "peak",
                    _ => "turning point",
                };
                rope.series.push(
                    Series::line(
                        format!("{}: t = {} s, {what}", n + 1, sig_short(t)),
                        xy(&state.x),
                        c,
                    )
                    .with_marker(Marker::Circle, true),
                );
                for (node, p) in state.x.iter().enumerate() {
                    csv += &format!(
                        "{},{},{},{node},{},{}\n",
                        n + 1,
                        full(t),
                        full(e),
                        full(p.x),
                        full(p.y)
                    );
                }
            }
        }
    }
    Ok(Figure {
        number: 12,
        stem: "fig12-energy-and-motion".into(),
        caption: "Figure 12. The kinetic energy over one period and the rope's motion, Backward Euler reference, \
                  k = 1e3 N/m (the softer rope, whose motion is visible at scale). The thesis's five instants are \
                  not given; we mark 1 the release (straight rope at rest), 2 the first kinetic-energy peak (the rope \
                  passes its equilibrium going down), 3 the next minimum (lowest turning point), 4 the second peak \
                  (equilibrium going up) and 5 the next minimum (highest turning point): one full period."
            .into(),
        svg: svg(&[energy, rope], HALF)?,
        csv,
    })
}

/// Sets a linear y range with `fraction` of the data's span free above the curves, for the
/// legend.
fn headroom(panel: &mut Panel, fraction: f64) {
    let (lo, hi) = panel
        .series
        .iter()
        .flat_map(|s| s.points.iter().map(|p| p.1))
        .filter(|y| y.is_finite())
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), y| {
            (lo.min(y), hi.max(y))
        });
    if lo < hi {
        let span = hi - lo;
        panel.y = panel
            .y
            .clone()
            .range(lo - 0.05 * span, hi + fraction * span);
    }
}

/// The node whose height Figure 13 follows: the middle free node (the lowest at rest).
pub const FIGURE13_NODE: usize = 4;

/// Figure 13: the rope's motion over time, Backward Euler against Fast m-s.
fn figure13(runs: &FigureRuns) -> Result<Figure> {
    let mut panel = Panel::new(
        "k = 1e3 N/m: height of node 4",
        Axis::linear("time (s)"),
        Axis::linear("y of node 4 (m)"),
    );
    panel.legend = Legend::UpperRight;
    let fms = runs.get(FMS_SOFT_COARSE);
    let window = fms
        .map_or(10.0, |(_, r)| r.end_time().max(10.0))
        .min(crate::report::runs::SOFT_START_S);
    let mut csv_series = Vec::new();
    let height = |run: &Run| -> Vec<(f64, f64)> {
        run.positions
            .iter()
            .filter(|(t, _)| *t <= window + 1e-9)
            .map(|(t, s)| (*t, s.x[FIGURE13_NODE].y))
            .collect()
    };
    if let Some((_, run)) = runs.get(BE_SOFT) {
        let y = height(run);
        panel.series.push(
            Series::line(
                "Backward Euler (dt 0.001 s, 5 it.)",
                decimate(&y, MAX_BUCKETS),
                BLACK,
            )
            .with_width(1),
        );
        csv_series.push(("backward_euler".to_string(), decimate(&y, MAX_BUCKETS)));
    }
    let mut extra = String::new();
    match fms {
        Some((spec, run)) => {
            let y = height(run);
            panel.series.push(
                Series::line(
                    format!("Fast m-s (dt 0.1 s, {} it.)", spec.iterations),
                    y.clone(),
                    colour(SolverKind::FastMassSpring, 0),
                )
                .with_width(3)
                .with_marker(Marker::Triangle, true),
            );
            csv_series.push(("fast_mass_spring".to_string(), y));
            extra = format!(" The Fast m-s run stops at t = {} s.", sig4(run.end_time()));
        }
        None => panel.label((0.5, -2.6), "(Fast m-s not run in this report)", GREY),
    }
    headroom(&mut panel, 0.3);
    Ok(Figure {
        number: 13,
        stem: "fig13-motion-be-vs-fms".into(),
        caption: format!(
            "Figure 13. The rope's motion over time, Backward Euler against Fast m-s (k = 1e3 N/m, dt = 0.1 s, 1 \
             iteration). The thesis does not say what it plots; we plot the height of node 4, a middle node and the \
             lowest at rest, which shows the bounces directly: the reference oscillates about its rest height while \
             one Liu iteration per step creeps down with hardly a bounce.{extra} The window is the Fast m-s run, at \
             least 10 s."
        ),
        svg: svg(&[panel], PANEL)?,
        csv: series_csv("time_s", "y_m", &csv_series),
    })
}

/// Figures 14 and 15: kinetic energy against time, k = 1e6, dt = 0.01, middle iteration
/// counts; Figure 15 is cut at the time Fast m-s comes to rest.
fn kinetic_energy_middle(runs: &FigureRuns, number: u8) -> Result<Figure> {
    let fms_end = runs.get(STIFF_MIDDLE[1].1).map(|(_, r)| r.end_time());
    let cut = if number == 15 {
        fms_end.or(Some(2.0))
    } else {
        None
    };
    let mut panel = Panel::new(
        "k = 1e6 N/m, dt = 0.01 s (reference dt = 0.001 s)",
        Axis::linear("time (s)"),
        Axis::linear("kinetic energy (J)"),
    );
    let mut csv_series = Vec::new();
    let mut add = |label: String, key: &str, run: &Run, color: RGBColor| {
        let until = cut.unwrap_or(run.end_time());
        let ke = energy_series(run, until);
        let ke = decimate(&ke, MAX_BUCKETS);
        // The reference thin, the solvers thicker, so the short runs stand out.
        let width = if run.dt < 0.01 { 1 } else { 2 };
        let s = Series::line(label, ke.clone(), color).with_width(width);
        panel.series.push(s);
        csv_series.push((key.to_string(), ke));
    };
    if let Some((_, run)) = runs.get(BE_STIFF) {
        add(
            "Backward Euler (reference)".into(),
            "backward_euler",
            run,
            BLACK,
        );
    }
    let mut present = Vec::new();
    for (solver, key) in STIFF_MIDDLE {
        if let Some((spec, run)) = runs.get(key) {
            add(
                format!("{} {} it.", solver.abbreviation(), spec.iterations),
                solver.id(),
                run,
                colour(solver, 1),
            );
            present.push(format!(
                "{} {} iterations (ends at {} s)",
                solver.abbreviation(),
                spec.iterations,
                sig4(run.end_time())
            ));
        }
    }
    if present.is_empty() {
        panel.label(
            (0.3, 5.0),
            "(XPBD, Fast m-s and ADMM not run in this report)",
            GREY,
        );
    }
    let first_peaks: Vec<String> =
        std::iter::once(runs.get(BE_STIFF).map(|(_, r)| ("BE".to_string(), r)))
            .flatten()
            .chain(STIFF_MIDDLE.iter().filter_map(|(s, key)| {
                runs.get(key)
                    .map(|(_, r)| (s.abbreviation().to_string(), r))
            }))
            .filter_map(|(name, r)| {
                r.peaks
                    .first()
                    .map(|p| format!("{name} {} J", sig4(p.energy)))
            })
            .collect();
    let what = if number == 14 {
        "over each whole run".to_string()
    } else {
        format!(
            "cut at t = {} s, when Fast m-s comes to rest",
            cut.map_or("–".into(), sig4)
        )
    };
    Ok(Figure {
        number,
        stem: format!("fig{number}-kinetic-energy-k1e6-dt0.01{}", if number == 15 { "-cut" } else { "" }),
        caption: format!(
            "Figure {number}. Kinetic energy against time, k = 1e6 N/m, dt = 0.01 s, the middle iteration count of \
             each solver ({}), with the Backward Euler reference (dt = 0.001 s), {what}. First peaks: {}. The \
             thesis: the reference peaks at about 6 J and XPBD's first peak exceeds 8 J.",
            if present.is_empty() { "not run".to_string() } else { present.join("; ") },
            if first_peaks.is_empty() { "–".to_string() } else { first_peaks.join(", ") }
        ),
        svg: svg(&[panel], PANEL)?,
        csv: series_csv("time_s", "kinetic_energy_J", &csv_series),
    })
}

/// Figures 1-15, in order.
pub fn all(data: &ReportData) -> Result<Vec<Figure>> {
    let pd = [SolverKind::FastMassSpring, SolverKind::AdmmPd];
    let all3 = [
        SolverKind::Xpbd,
        SolverKind::FastMassSpring,
        SolverKind::AdmmPd,
    ];
    Ok(vec![
        figure1(data)?,
        figure2(data)?,
        figure3()?,
        figure4()?,
        error_against_dt(data, 5, 1e3, &all3)?,
        rest_state_xpbd(data, 6, 1e3)?,
        error_against_dt(data, 7, 1e6, &all3)?,
        rest_state_xpbd(data, 8, 1e6)?,
        error_against_dt(data, 9, 1e3, &pd)?,
        error_against_dt(data, 10, 1e6, &pd)?,
        figure11(&data.runs)?,
        figure12(&data.runs)?,
        figure13(&data.runs)?,
        kinetic_energy_middle(&data.runs, 14)?,
        kinetic_energy_middle(&data.runs, 15)?,
    ])
}
