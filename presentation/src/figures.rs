//! Figures 1-15 of the thesis, redrawn from our runs as SVG at their printed size, and the
//! parity figure of the 56 published rows; each with the CSV of the points it draws and a
//! caption that states every choice the thesis leaves open.
//!
//! Colours follow Table 8: Backward Euler black; XPBD blue, Fast m-s orange, ADMM green,
//! darker for fewer iterations. Published values are hollow markers on dashed lines, ours
//! filled markers on solid lines. The style itself (sizes, fonts, legends outside the data)
//! is [`crate::plot`]'s.

use crate::data::CsvFile;
use crate::format::{full, full_opt, sig4};
use crate::inputs::ReportData;
use crate::plot::{
    layout, power_of_ten, Align, Arrow, Axis, Band, Chart, Entry, Layout, Line, Marker, Panel, Rgb,
    Series, Style, COLUMN_WIDTH_MM, FULL_WIDTH_MM,
};
use crate::runs::{
    FigureRuns, BE_SOFT, BE_STIFF, FMS_SOFT_COARSE, SHEET_FIGURE_STIFFNESS, STIFF_MIDDLE,
};
use crate::style::{
    class_colour, coinciding_groups, colour, iteration_marker, solver_line, solver_marker, BLACK,
    BLUE, COINCIDE_DECADES, GREEN, GREY, RED,
};
use crate::tables::{iteration_count, measured, stiffness_label};
use mass_spring_solvers::error::Result;
use mass_spring_solvers::integrators::time_stepper::Run;
use mass_spring_solvers::model::system::Vec3;
use mass_spring_solvers::solvers::registry::SolverId;
use mass_spring_solvers::studies::experiments::{
    peak_tolerance, published_rows, Measured, PublishedRow, HALF_PERIOD_TOLERANCE,
};
use mass_spring_solvers::studies::forensics::Evidence;

/// One figure: file stem (`fig05-error-dt-k1e3`), caption, layout, SVG and CSV text.
#[derive(Debug, Clone, PartialEq)]
pub struct Figure {
    /// The caption's key: the thesis's number, or one of ours (`P1`) that
    /// [`crate::navigation::number_figures`] numbers.
    pub key: String,
    pub stem: String,
    pub caption: String,
    /// Every text box, data mark and axes rectangle, for the figure test.
    pub layout: Layout,
    pub svg: String,
    pub csv: String,
}

impl Figure {
    fn new(
        key: impl ToString,
        stem: impl Into<String>,
        caption: String,
        chart: &Chart,
        csv: String,
    ) -> Result<Self> {
        let layout = layout(chart)?;
        Ok(Self {
            key: key.to_string(),
            stem: stem.into(),
            caption,
            svg: layout.svg(),
            layout,
            csv,
        })
    }
}

/// Long series are reduced to this many buckets (min and max of each) before drawing.
const MAX_BUCKETS: usize = 1500;

/// The class of a published row in the parity figure: its evidence class (issue 8) when the
/// forensic reproduction ran, else "unclassified".
pub fn row_class(data: &ReportData, row: &PublishedRow) -> String {
    data.forensics
        .as_ref()
        .and_then(|f| f.evidence_of(row))
        .map_or_else(
            || "unclassified".to_string(),
            |e| e.evidence.id().to_string(),
        )
}

/// `10³`: a stiffness as a typeset power of ten.
fn stiffness_text(k: f64) -> String {
    let e = k.log10().round();
    if (10f64.powf(e) - k).abs() <= 1e-9 * k {
        power_of_ten(e as i32)
    } else {
        sig4(k)
    }
}

/// Long-format CSV of named (x, y) series.
fn series_csv(x: &'static str, y: &'static str, series: &[(String, Vec<(f64, f64)>)]) -> String {
    let mut out = CsvFile::new(&["series", x, y]);
    for (name, points) in series {
        for &(a, b) in points {
            out.record(vec![name.to_string(), full(a), full(b)]);
        }
    }
    out.text()
}

/// Node positions (x, y) of named shapes as CSV.
fn shapes_csv(shapes: &[(String, Vec<Vec3>)]) -> String {
    let mut out = CsvFile::new(&["series", "node", "x_m", "y_m"]);
    for (name, nodes) in shapes {
        for (i, p) in nodes.iter().enumerate() {
            out.record(vec![name.to_string(), i.to_string(), full(p.x), full(p.y)]);
        }
    }
    out.text()
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

/// "20 ≈ 50 it." for a group of iteration counts.
fn group_label(iterations: &[usize], group: &[usize]) -> String {
    let counts: Vec<String> = group.iter().map(|&i| iterations[i].to_string()).collect();
    format!("{} it.", counts.join(" ≈ "))
}

/// The look of one error series: published hollow and dashed, ours filled and solid.
fn error_style(index: usize, color: Rgb, published: bool) -> Series {
    let s = Series::line("", Vec::new(), color).with_marker(iteration_marker(index), !published);
    if published {
        s.with_line(Line::Dashed)
    } else {
        s
    }
}

/// Figures 5, 7, 9, 10: rest-state error against Δt on log axes, one panel per solver,
/// published (hollow, dashed) and ours (filled, solid) on the same axes.
fn error_against_dt(
    data: &ReportData,
    number: u8,
    stiffness: f64,
    solvers: &[SolverId],
) -> Result<Figure> {
    let k = stiffness_label(stiffness);
    let mut csv_rows = CsvFile::new(&[
        "solver",
        "iterations",
        "dt_s",
        "error_published_m",
        "error_ours_m",
    ]);
    // Per solver: iteration counts, published series, our series.
    let mut per_solver = Vec::new();
    for &solver in solvers {
        let (mut counts, mut published, mut ours) = (Vec::new(), Vec::new(), Vec::new());
        for index in 0..3 {
            let Some(iterations) = iteration_count(solver, index) else {
                continue;
            };
            let mut rows: Vec<&PublishedRow> = published_rows()
                .iter()
                .filter(|r| {
                    r.solver == solver && r.iterations == iterations && r.stiffness == stiffness
                })
                .collect();
            rows.sort_by(|a, b| a.dt_s.total_cmp(&b.dt_s));
            let mut p = Vec::new();
            let mut o = Vec::new();
            for r in &rows {
                let ours_error = measured(&data.results, r).and_then(|m| m.error_sum);
                csv_rows.record(vec![
                    solver.id().to_string(),
                    iterations.to_string(),
                    full(r.dt_s),
                    full_opt(r.error),
                    full_opt(ours_error),
                ]);
                p.extend(r.error.map(|e| (r.dt_s, e)));
                o.extend(ours_error.map(|e| (r.dt_s, e)));
            }
            counts.push(iterations);
            published.push(p);
            ours.push(o);
        }
        per_solver.push((solver, counts, published, ours));
    }
    // One y range for every panel, so that they compare at a glance.
    let (lo, hi) = per_solver
        .iter()
        .flat_map(|(_, _, p, o)| p.iter().chain(o).flatten().map(|q| q.1))
        .filter(|v| *v > 0.0)
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), v| {
            (lo.min(v), hi.max(v))
        });
    let y_range = if lo.is_finite() {
        (10f64.powf(lo.log10() - 0.4), 10f64.powf(hi.log10() + 0.4))
    } else {
        (1e-9, 10.0)
    };
    let mut panels = Vec::new();
    let mut merged = Vec::new();
    for (solver, counts, published, ours) in &per_solver {
        let mut panel = Panel::new(
            Axis::log("Δt (s)").range(6e-4, 0.17),
            Axis::log("rest-state error (m)").range(y_range.0, y_range.1),
        );
        panel.heading = solver.display_name().to_string();
        let pub_groups = coinciding_groups(published);
        let our_groups = if ours.iter().all(|o| o.is_empty()) {
            pub_groups.clone()
        } else {
            coinciding_groups(ours)
        };
        let same = pub_groups == our_groups;
        for (source, groups, series) in [
            ("published", &pub_groups, published),
            ("ours", &our_groups, ours),
        ] {
            let is_published = source == "published";
            for g in groups {
                let index = g[0];
                let mut s = error_style(index, colour(*solver, index), is_published);
                s.points = series[index].clone();
                let label = group_label(counts, g);
                if g.len() > 1 {
                    merged.push(format!("{} {source} {label}", solver.display_name()));
                }
                // Where both sources group alike, one entry (ours' look) names the colour.
                s.label = match (same, is_published) {
                    (true, true) => String::new(),
                    (true, false) => label,
                    (false, _) => format!("{source} {label}"),
                };
                if !s.points.is_empty() {
                    panel.series.push(s);
                }
            }
        }
        if ours.iter().all(|o| o.is_empty()) {
            panel.label(
                (1e-2, y_range.0),
                (0.0, 8.0),
                Align::Middle,
                "(ours not run in this report)",
                GREY,
            );
        }
        panels.push(panel);
    }
    let mut chart = Chart::new(FULL_WIDTH_MM, 78.0, panels);
    chart.legend = vec![
        Entry {
            label: "published (thesis)".into(),
            style: error_style(0, GREY, true).style,
        },
        Entry {
            label: "ours".into(),
            style: error_style(0, GREY, false).style,
        },
    ];
    let which = if solvers.len() == 3 {
        "XPBD (a), Fast m-s (b) and ADMM (c)"
    } else {
        "the two Projective Dynamics methods, Fast m-s (a) and ADMM (b)"
    };
    let merged = if merged.is_empty() {
        String::new()
    } else {
        format!(
            " Series closer than {} decade at every point are drawn once and named together: {}",
            COINCIDE_DECADES,
            merged.join("; ")
        )
    };
    let stem = format!(
        "fig{number:02}-error-dt-k{k}{}",
        if solvers.len() == 3 { "" } else { "-pd" }
    );
    Figure::new(
        number,
        stem,
        format!(
            "Figure {number}. Rest-state error against Δt, k = {} N/m, one panel per solver: {which}. Published \
             values hollow on dashed lines, ours filled on solid lines, one colour and marker per iteration count \
             (darker for fewer). The error is the distance between the final positions and those of our \
             Backward Euler reference of the same stiffness, {} (the thesis's measure). Same axes in every \
             panel.{merged}",
            stiffness_text(stiffness),
            crate::tables::summed_over_free_nodes()
        ),
        &chart,
        csv_rows.text(),
    )
}

fn xy(nodes: &[Vec3]) -> Vec<(f64, f64)> {
    nodes.iter().map(|p| (p.x, p.y)).collect()
}

fn opt_sig(x: Option<f64>) -> String {
    x.map_or_else(|| "–".into(), sig4)
}

/// The panel of Figure 6 or 8 and the shapes it draws: the rest state of Backward Euler
/// against XPBD at Δt = 0.1 s, every iteration count.
fn rest_state_panel(data: &ReportData, stiffness: f64) -> (Panel, Vec<(String, Vec<Vec3>)>) {
    let mut panel = Panel::new(Axis::linear("x (m)"), Axis::linear("y (m)"));
    let mut shapes = Vec::new();
    let mut reference_series = None;
    if let Some(r) = reference(data, stiffness) {
        reference_series = Some(
            Series::line(
                "BE reference (Δt = 0.001 s, 5 it.)",
                xy(&r.final_positions),
                BLACK,
            )
            .with_weight(0.8)
            .with_marker(Marker::Square, false)
            .with_marker_scale(1.3),
        );
        shapes.push(("backward_euler".to_string(), r.final_positions.clone()));
    }
    for index in 0..3 {
        let Some(iterations) = iteration_count(SolverId::Xpbd, index) else {
            continue;
        };
        let row = published_rows().iter().find(|r| {
            r.solver == SolverId::Xpbd
                && r.stiffness == stiffness
                && r.dt_s == 0.1
                && r.iterations == iterations
        });
        if let Some(m) = row.and_then(|r| measured(&data.results, r)) {
            panel.series.push(
                Series::line(
                    format!(
                        "XPBD Δt = 0.1 s, {iterations} it. (error {} m)",
                        opt_sig(m.error_sum)
                    ),
                    xy(&m.final_positions),
                    colour(SolverId::Xpbd, index),
                )
                .with_marker(iteration_marker(index), true),
            );
            shapes.push((
                format!("xpbd_dt0.1_{iterations}it"),
                m.final_positions.clone(),
            ));
        }
    }
    if panel.series.is_empty() {
        panel.label(
            (4.5, 0.0),
            (0.0, -12.0),
            Align::Middle,
            "(XPBD not run in this report)",
            GREY,
        );
    }
    // The reference on top.
    panel.series.extend(reference_series);
    (panel, shapes)
}

/// The data extent of a panel's series on one axis (finite values only).
fn series_extent(panel: &Panel, pick: fn(&(f64, f64)) -> f64) -> (f64, f64) {
    panel
        .series
        .iter()
        .flat_map(|s| s.points.iter().map(pick))
        .filter(|v| v.is_finite())
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), v| {
            (lo.min(v), hi.max(v))
        })
}

/// Figures 6 (k = 10³) and 8 (k = 10⁶), twins drawn to scale and at one scale: both panels
/// take the union of their data ranges, so that the same metre is as long in both.
fn rest_states_xpbd(data: &ReportData) -> Result<[Figure; 2]> {
    let twins = [(6, 1e3, 8), (8, 1e6, 6)].map(|(number, stiffness, twin)| {
        let (panel, shapes) = rest_state_panel(data, stiffness);
        (number, stiffness, twin, panel, shapes)
    });
    let union = |pick: fn(&(f64, f64)) -> f64| {
        twins
            .iter()
            .map(|t| series_extent(&t.3, pick))
            .fold((f64::INFINITY, f64::NEG_INFINITY), |a, b| {
                (a.0.min(b.0), a.1.max(b.1))
            })
    };
    let (x, y) = (union(|p| p.0), union(|p| p.1));
    let [six, eight] = twins.map(|(number, stiffness, twin, mut panel, shapes)| {
            panel.equal_aspect = true;
            if x.0 < x.1 && y.0 < y.1 {
                let pad = 0.04 * (x.1 - x.0);
                panel.x = panel.x.clone().range(x.0 - pad, x.1 + pad);
                panel.y = panel.y.clone().range(y.0 - pad, y.1 + pad);
            }
            Figure::new(
                number,
                format!("fig{number:02}-rest-state-xpbd-k{}", stiffness_label(stiffness)),
                format!(
                    "Figure {number}. Rest state of Backward Euler (hollow squares) against XPBD, k = {} N/m, \
                     drawn to scale (the same metre on both axes) and at the scale of its twin, Figure {twin}. \
                     The thesis does not say which XPBD run it shows; we show the coarsest time step, Δt = 0.1 s, \
                     with each of its iteration counts (1, 20, 50), where the difference is visible and shrinks \
                     with the iterations. Node positions at the end of each run (the first kinetic-energy peak \
                     below 0.001 J).",
                    stiffness_text(stiffness)
                ),
                &Chart::new(COLUMN_WIDTH_MM, 82.0, vec![panel]),
                shapes_csv(&shapes),
            )
    });
    Ok([six?, eight?])
}

/// The oblique view of Figure 1: an orthographic projection seen from azimuth 35° and
/// elevation 25°, so that lengths in the picture plane keep their scale. Returns (right, up).
fn oblique(p: &Vec3) -> (f64, f64) {
    let (a, e) = (35f64.to_radians(), 25f64.to_radians());
    let right = p.x * a.cos() - p.z * a.sin();
    let depth = p.x * a.sin() + p.z * a.cos();
    (right, p.y * e.cos() + depth * e.sin())
}

/// Figure 1: the sheet of `docs/sheet-scene.md` hanging from two corners, one panel per
/// instant, drawn to scale in an oblique view.
fn figure1(data: &ReportData) -> Result<Figure> {
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
fn figure2(data: &ReportData) -> Result<Figure> {
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

fn reference(data: &ReportData, stiffness: f64) -> Option<&Measured> {
    data.results.rows.iter().find(|m| {
        m.published.solver == SolverId::BackwardEuler && m.published.stiffness == stiffness
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

/// Figure 3: the rope's nodes and springs, to scale.
fn figure3() -> Result<Figure> {
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

/// `₁₂`: an index as subscript digits.
fn subscript(i: usize) -> String {
    i.to_string()
        .bytes()
        .map(|d| char::from_u32(0x2080 + (d - b'0') as u32).unwrap_or('?'))
        .collect()
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

/// The peaks of a run inside a window, for markers.
fn peaks_until(run: &Run, until: f64) -> Vec<(f64, f64)> {
    run.peaks
        .iter()
        .filter(|p| p.time_exact <= until)
        .map(|p| (p.time_exact, p.energy))
        .collect()
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

/// Figure 11: two periods of the reference's kinetic energy, k = 10⁶.
fn figure11(runs: &FigureRuns) -> Result<Figure> {
    let mut panel = Panel::new(Axis::linear("time (s)"), Axis::linear("kinetic energy (J)"));
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
        for (i, &p) in peaks.iter().enumerate() {
            panel.label(p, (0.0, 6.0), Align::Middle, format!("{}", i + 1), BLACK);
        }
        panel
            .series
            .push(Series::line("kinetic energy", ke.clone(), BLACK));
        panel
            .series
            .push(Series::points("peaks", peaks.clone(), RED).with_marker(Marker::Circle, true));
        csv_series.push(("kinetic_energy_j".to_string(), ke));
        csv_series.push(("peak_j".to_string(), peaks));
    }
    headroom(&mut panel, 0.12);
    Figure::new(
        11,
        "fig11-kinetic-energy-reference",
        format!(
            "Figure 11. Two periods of the kinetic energy of Backward Euler (Δt = 0.001 s, 5 Newton iterations), \
             k = 10⁶ N/m, from the release at rest: the kinetic energy peaks twice per period of the rope, so two \
             periods span peaks 1 to 5.{caption_extra}"
        ),
        &Chart::new(COLUMN_WIDTH_MM, 66.0, vec![panel]),
        series_csv("time_s", "value_j", &csv_series),
    )
}

/// Figure 12: the kinetic energy over one period with five marked instants, and the rope at
/// those instants.
fn figure12(runs: &FigureRuns) -> Result<Figure> {
    let mut energy = Panel::new(Axis::linear("time (s)"), Axis::linear("kinetic energy (J)"));
    let mut rope = Panel::new(
        Axis::linear("x (m)"),
        Axis::linear("y (m)").range(-3.6, 0.3),
    );
    rope.equal_aspect = true;
    let mut csv = CsvFile::new(&[
        "instant",
        "time_s",
        "kinetic_energy_j",
        "node",
        "x_m",
        "y_m",
    ]);
    let palette = [GREY, Rgb(217, 72, 1), GREEN, BLUE, Rgb(120, 40, 160)];
    if let Some((_, run)) = runs.get(BE_SOFT) {
        let instants = five_instants(&run.kinetic_energy);
        let end = instants.last().map_or(1.0, |&i| i as f64 * run.dt) + 0.05;
        energy
            .series
            .push(Series::line("", energy_series(run, end), BLACK));
        for (n, &i) in instants.iter().enumerate() {
            let t = i as f64 * run.dt;
            let e = run.kinetic_energy[i];
            let c = palette[n % palette.len()];
            // A marker of its own besides the colour, for grey print and colour-blind readers.
            let (marker, filled) = [
                (Marker::Circle, true),
                (Marker::Triangle, true),
                (Marker::Square, true),
                (Marker::Cross, true),
                (Marker::Circle, false),
            ][n % 5];
            energy
                .series
                .push(Series::points("", vec![(t, e)], c).with_marker(marker, filled));
            // Peaks labelled above, minima (the curve rises on both sides) below.
            let offset = if n % 2 == 1 { 6.0 } else { -12.0 };
            energy.label(
                (t, e),
                (0.0, offset),
                Align::Middle,
                format!("{}", n + 1),
                c,
            );
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
                    .with_marker(marker, filled)
                    .with_marker_scale(0.8),
                );
                for (node, p) in state.x.iter().enumerate() {
                    csv.record(vec![
                        (n + 1).to_string(),
                        full(t),
                        full(e),
                        node.to_string(),
                        full(p.x),
                        full(p.y),
                    ]);
                }
            }
        }
        headroom(&mut energy, 0.12);
        let (lo, hi) = energy.y.range.unwrap_or((0.0, 1.0));
        // Room under the minima for their labels.
        energy.y = energy.y.clone().range(lo - 0.12 * (hi - lo), hi);
    }
    Figure::new(
        12,
        "fig12-energy-and-motion",
        "Figure 12. The kinetic energy over one period (a) and the rope's motion (b, drawn to scale: the same metre on both axes), Backward Euler reference, \
         k = 10³ N/m (the softer rope, whose motion is visible at scale). The thesis's five instants are not given; \
         we mark 1 the release (straight rope at rest), 2 the first kinetic-energy peak (the rope passes its \
         equilibrium going down), 3 the next minimum (lowest turning point), 4 the second peak (equilibrium going \
         up) and 5 the next minimum (highest turning point): one full period."
            .into(),
        &Chart::new(FULL_WIDTH_MM, 80.0, vec![energy, rope]),
        csv.text(),
    )
}

/// Sets a linear y range with `fraction` of the data's span free above the curves, for
/// direct labels.
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
/// The window of Figure 13, s: four periods of the reference, where its bounces still read.
pub const FIGURE13_WINDOW_S: f64 = 10.0;
/// Figure 13 marks every this many Fast m-s steps (the line joins every step).
const FIGURE13_MARKER_EVERY: usize = 5;

/// Figure 13: the rope's motion over the first seconds, Backward Euler against Fast m-s.
fn figure13(runs: &FigureRuns) -> Result<Figure> {
    let mut panel = Panel::new(
        Axis::linear("time (s)"),
        Axis::linear(format!("y of node x{} (m)", subscript(FIGURE13_NODE))),
    );
    let fms = runs.get(FMS_SOFT_COARSE);
    let mut csv_series = Vec::new();
    let height = |run: &Run| -> Vec<(f64, f64)> {
        run.positions
            .iter()
            .filter(|(t, _)| *t <= FIGURE13_WINDOW_S + 1e-9)
            .map(|(t, s)| (*t, s.x[FIGURE13_NODE].y))
            .collect()
    };
    let mut extra = String::new();
    match fms {
        Some((spec, run)) => {
            let y = height(run);
            panel.series.push(
                Series::line(
                    format!("Fast m-s (Δt = 0.1 s, {} it.)", spec.iterations),
                    y.clone(),
                    colour(SolverId::FastMassSpring, 0),
                )
                .with_weight(1.5)
                .with_marker(Marker::Triangle, true)
                .with_marker_every(FIGURE13_MARKER_EVERY),
            );
            csv_series.push(("fast_mass_spring".to_string(), y));
            extra = format!(" The Fast m-s run stops at t = {} s.", sig4(run.end_time()));
        }
        None => panel.label(
            (5.0, -2.6),
            (0.0, 0.0),
            Align::Middle,
            "(Fast m-s not run in this report)",
            GREY,
        ),
    }
    if let Some((_, run)) = runs.get(BE_SOFT) {
        let y = decimate(&height(run), MAX_BUCKETS);
        panel.series.push(
            Series::line("Backward Euler (Δt = 0.001 s, 5 it.)", y.clone(), BLACK).with_weight(0.8),
        );
        csv_series.insert(0, ("backward_euler".to_string(), y));
    }
    Figure::new(
        13,
        "fig13-motion-be-vs-fms",
        format!(
            "Figure 13. The rope's motion over the first {} s, Backward Euler against Fast m-s (k = 10³ N/m, \
             Δt = 0.1 s, 1 iteration). The thesis does not say what it plots; we plot the height of node 4, a middle \
             node and the lowest at rest, which shows the bounces directly: the reference oscillates about its rest \
             height while one Fast m-s iteration per step creeps down with hardly a bounce. Markers every {} Fast m-s \
             steps.{extra}",
            sig_short(FIGURE13_WINDOW_S),
            FIGURE13_MARKER_EVERY
        ),
        &Chart::new(FULL_WIDTH_MM, 62.0, vec![panel]),
        series_csv("time_s", "y_m", &csv_series),
    )
}

/// Figure 14: the kinetic-energy peaks against time on a log axis, k = 10⁶, Δt = 0.01, middle
/// iteration counts (damping rates are slopes); Figure 15: the kinetic energy itself, cut at
/// the time Fast m-s comes to rest.
fn kinetic_energy_middle(runs: &FigureRuns, number: u8) -> Result<Figure> {
    let envelope = number == 14;
    let fms_end = runs.get(STIFF_MIDDLE[1].1).map(|(_, r)| r.end_time());
    let cut = if envelope {
        None
    } else {
        fms_end.or(Some(2.0))
    };
    let mut panel = if envelope {
        Panel::new(
            Axis::linear("time (s)"),
            Axis::log("kinetic-energy peaks (J)"),
        )
    } else {
        Panel::new(Axis::linear("time (s)"), Axis::linear("kinetic energy (J)"))
    };
    let mut csv_series = Vec::new();
    let mut drawn = Vec::new();
    let mut add = |label: String, key: &str, run: &Run, color: Rgb, line: Line, marker: Marker| {
        let until = cut.unwrap_or(run.end_time());
        let points = if envelope {
            run.peaks.iter().map(|p| (p.time_exact, p.energy)).collect()
        } else {
            decimate(&energy_series(run, until), MAX_BUCKETS)
        };
        // The reference thin, the solvers thicker, so the short runs stand out.
        let weight = if run.dt < 0.01 { 0.8 } else { 1.4 };
        // A marker for each solver besides its dash (the reference is solid like XPBD, the
        // threshold dotted like ADMM): a dozen on a dense curve, one per peak on the envelope.
        let every = if envelope {
            1
        } else {
            (points.len() / 12).max(1)
        };
        drawn.push(
            Series::line(label, points.clone(), color)
                .with_weight(weight)
                .with_line(line)
                .with_marker(marker, true)
                .with_marker_every(every),
        );
        csv_series.push((key.to_string(), points));
    };
    let mut present = Vec::new();
    for ((solver, key), marker) in
        STIFF_MIDDLE
            .into_iter()
            .zip([Marker::Circle, Marker::Triangle, Marker::Square])
    {
        if let Some((spec, run)) = runs.get(key) {
            add(
                format!("{} {} it.", solver.display_name(), spec.iterations),
                solver.id(),
                run,
                colour(solver, 1),
                solver_line(solver),
                marker,
            );
            present.push(format!(
                "{} {} iterations (ends at {} s)",
                solver.display_name(),
                spec.iterations,
                sig4(run.end_time())
            ));
        }
    }
    if let Some((_, run)) = runs.get(BE_STIFF) {
        add(
            "Backward Euler (reference)".into(),
            "backward_euler",
            run,
            BLACK,
            Line::Solid,
            Marker::None,
        );
        // The reference first in the data, last (on top) in the drawing.
        csv_series.rotate_right(1);
    }
    panel.series = drawn;
    if envelope {
        panel.series.push(
            Series::line(
                "stopping threshold",
                vec![
                    (0.0, mass_spring_solvers::model::metrics::STOP_THRESHOLD_J),
                    (
                        panel_end(&panel.series),
                        mass_spring_solvers::model::metrics::STOP_THRESHOLD_J,
                    ),
                ],
                GREY,
            )
            .with_line(Line::Dotted),
        );
    }
    if present.is_empty() {
        panel.label(
            (0.3, 5.0),
            (0.0, 0.0),
            Align::Start,
            "(XPBD, Fast m-s and ADMM not run in this report)",
            GREY,
        );
    }
    let first_peaks: Vec<String> = std::iter::once(
        runs.get(BE_STIFF)
            .map(|(_, r)| (SolverId::BackwardEuler.display_name().to_string(), r)),
    )
    .flatten()
    .chain(STIFF_MIDDLE.iter().filter_map(|(s, key)| {
        runs.get(key)
            .map(|(_, r)| (s.display_name().to_string(), r))
    }))
    .filter_map(|(name, r)| {
        r.peaks
            .first()
            .map(|p| format!("{name} {} J", sig4(p.energy)))
    })
    .collect();
    let what = if envelope {
        "the kinetic energy at each of its peaks (the envelope of the oscillation) over each whole run, on a \
         logarithmic axis, so that a constant damping rate is a straight line; the dotted line is the stopping \
         threshold, 0.001 J"
            .to_string()
    } else {
        format!(
            "the kinetic energy itself, cut at t = {} s, when Fast m-s comes to rest",
            cut.map_or("–".into(), sig4)
        )
    };
    Figure::new(
        number,
        format!("fig{number}-kinetic-energy-k1e6-dt0.01{}", if envelope { "" } else { "-cut" }),
        format!(
            "Figure {number}. Kinetic energy against time, k = 10⁶ N/m, Δt = 0.01 s, the middle iteration count of \
             each solver ({}; XPBD solid with circles, Fast m-s dashed with triangles, ADMM dotted with squares), with the Backward Euler reference \
             (Δt = 0.001 s, thin black): {what}. First peaks: {}. The \
             thesis: the reference peaks at about 6 J and XPBD's first peak exceeds 8 J.",
            if present.is_empty() { "not run".to_string() } else { present.join("; ") },
            if first_peaks.is_empty() { "–".to_string() } else { first_peaks.join(", ") }
        ),
        &Chart::new(FULL_WIDTH_MM, 66.0, vec![panel]),
        series_csv("time_s", "kinetic_energy_j", &csv_series),
    )
}

/// The last x of a panel's series.
fn panel_end(series: &[Series]) -> f64 {
    series
        .iter()
        .flat_map(|s| s.points.iter().map(|p| p.0))
        .fold(1.0, f64::max)
}

/// The marks of one class and solver in a parity panel: (class, solver, (published, ours)).
type ParityGroup = (String, SolverId, Vec<(f64, f64)>);

/// One row of the parity figure: the published numbers, ours (faithful configuration) and
/// the row's class.
struct ParityRow<'a> {
    published: &'a PublishedRow,
    ours: &'a Measured,
    class: String,
}

/// Points (published, ours) of one quantity, grouped by class and solver in order of first
/// appearance; rows where either side is missing or not positive are left out.
fn parity_points(
    rows: &[ParityRow],
    pick: impl Fn(&ParityRow) -> Option<(f64, f64)>,
) -> (Vec<ParityGroup>, usize) {
    let mut groups: Vec<ParityGroup> = Vec::new();
    let mut count = 0;
    for r in rows {
        let Some(p) = pick(r).filter(|p| p.0 > 0.0 && p.1 > 0.0) else {
            continue;
        };
        count += 1;
        let solver = r.published.solver;
        match groups.iter_mut().find(|g| g.0 == r.class && g.1 == solver) {
            Some(g) => g.2.push(p),
            None => groups.push((r.class.clone(), solver, vec![p])),
        }
    }
    (groups, count)
}

/// Log-spaced samples over a panel's extent, for the diagonal and the bands.
fn log_samples(lo: f64, hi: f64) -> Vec<f64> {
    let (a, b) = (lo.log10(), hi.log10());
    (0..=120)
        .map(|i| 10f64.powf(a + (b - a) * i as f64 / 120.0))
        .collect()
}

/// A parity panel: ours against published, y = x, an optional reproduction band
/// `band(x) -> (lower, upper)`.
fn parity_panel(
    quantity: &str,
    unit: &str,
    groups: &[ParityGroup],
    band: Option<&dyn Fn(f64) -> (f64, f64)>,
) -> Panel {
    let (lo, hi) = groups
        .iter()
        .flat_map(|g| g.2.iter().flat_map(|p| [p.0, p.1]))
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), v| {
            (lo.min(v), hi.max(v))
        });
    // Room for the markers at both ends: 6 % of the span and 0.1 decade.
    let (lo, hi) = if lo.is_finite() {
        let pad = 10f64.powf(0.06 * (hi / lo).log10() + 0.1);
        (lo / pad, hi * pad)
    } else {
        (0.1, 10.0)
    };
    let mut panel = Panel::new(
        Axis::log(format!("published {quantity}{unit}")).range(lo, hi),
        Axis::log(format!("ours{unit}")).range(lo, hi),
    );
    let xs = log_samples(lo, hi);
    if let Some(band) = band {
        let (lower, upper): (Vec<_>, Vec<_>) = xs
            .iter()
            .map(|&x| {
                let (l, u) = band(x);
                ((x, l.max(lo)), (x, u.min(hi)))
            })
            .unzip();
        panel.bands.push(Band {
            lower,
            upper,
            color: Rgb(215, 215, 215),
        });
    }
    panel.series.push(
        Series::line("", vec![(lo, lo), (hi, hi)], GREY)
            .with_weight(0.6)
            .with_line(Line::Dashed),
    );
    for (class, solver, points) in groups {
        panel.series.push(
            Series::points("", points.clone(), class_colour(class))
                .with_marker(solver_marker(*solver), true),
        );
    }
    panel
}

/// The parity figure: ours against published for all 56 rows, one panel each for the peak
/// count, T/2 and the rest-state error, marks coloured by the row's class.
fn parity(data: &ReportData) -> Result<Figure> {
    let rows: Vec<ParityRow> = published_rows()
        .iter()
        .filter_map(|p| {
            measured(&data.results, p).map(|ours| ParityRow {
                published: p,
                ours,
                class: row_class(data, p),
            })
        })
        .collect();
    let mut csv = CsvFile::new(&[
        "table",
        "solver",
        "dt_s",
        "iterations",
        "stiffness_n_per_m",
        "class",
        "peaks_published",
        "peaks_ours",
        "half_period_published_s",
        "half_period_ours_s",
        "error_published_m",
        "error_ours_m",
    ]);
    for r in &rows {
        let p = r.published;
        csv.record(vec![
            p.table.to_string(),
            p.solver.id().to_string(),
            full(p.dt_s),
            p.iterations.to_string(),
            full(p.stiffness),
            r.class.to_string(),
            p.ke_peaks.to_string(),
            r.ours.peaks.to_string(),
            full(p.half_period_s),
            full_opt(r.ours.half_period_thesis),
            full_opt(p.error),
            full_opt(r.ours.error_sum),
        ]);
    }
    let (peaks, n_peaks) = parity_points(&rows, |r| {
        Some((r.published.ke_peaks as f64, r.ours.peaks as f64))
    });
    let (half, n_half) = parity_points(&rows, |r| {
        r.ours
            .half_period_thesis
            .map(|t| (r.published.half_period_s, t))
    });
    let (error, n_error) = parity_points(&rows, |r| r.published.error.zip(r.ours.error_sum));
    let peak_band = |x: f64| {
        let tol = peak_tolerance(x.round() as usize) as f64;
        (x - tol, x + tol)
    };
    let period_band = |x: f64| {
        (
            x * (1.0 - HALF_PERIOD_TOLERANCE),
            x * (1.0 + HALF_PERIOD_TOLERANCE),
        )
    };
    let panels = vec![
        parity_panel("peak count", "", &peaks, Some(&peak_band)),
        parity_panel("T/2", " (s)", &half, Some(&period_band)),
        parity_panel("rest-state error", " (m)", &error, None),
    ];
    let mut chart = Chart::new(FULL_WIDTH_MM, 80.0, panels);
    let mut classes: Vec<String> = rows.iter().map(|r| r.class.clone()).collect();
    // Strongest class first, as in the forensic chapter.
    classes.sort_by_key(|c| Evidence::ALL.iter().position(|e| e.id() == c));
    classes.dedup();
    for class in &classes {
        chart.legend.push(Entry {
            label: class.clone(),
            style: Series::points("", Vec::new(), class_colour(class))
                .with_marker(Marker::Circle, true)
                .style,
        });
    }
    for solver in SolverId::THESIS_TABLES {
        chart.legend.push(Entry {
            label: solver.display_name().to_string(),
            style: Series::points("", Vec::new(), GREY)
                .with_marker(solver_marker(solver), false)
                .style,
        });
    }
    chart.legend.push(Entry {
        label: "ours = published".into(),
        style: Series::line("", Vec::new(), GREY)
            .with_weight(0.6)
            .with_line(Line::Dashed)
            .style,
    });
    chart.legend.push(Entry {
        label: "reproduction band".into(),
        style: Style {
            color: Rgb(215, 215, 215),
            line: Line::Solid,
            marker: Marker::None,
            filled: true,
            width: 6.0,
            radius: 0.0,
        },
    });
    Figure::new(
        PARITY_FIGURE,
        "parity",
        format!(
            "Figure {PARITY_FIGURE}. Ours against published for every row, log-log: (a) the kinetic-energy peak count \
             ({n_peaks} rows), (b) T/2 under the thesis convention ({n_half} rows) and (c) the rest-state error \
             ({n_error} solver rows; Table 1 has none). Ours are the faithful configuration's numbers; the dashed \
             line is ours = published and the grey band the reproduction rule (peaks within max(1, round(0.005 × \
             published)), T/2 within {} %); the rest-state error has no rule. Colour: the row's evidence class of \
             section 6 ({}), which names the configuration that reproduces it while the mark stays at the faithful \
             numbers; marker: the solver. Rows where a side is missing or zero are left out.",
            sig_short(100.0 * HALF_PERIOD_TOLERANCE),
            classes.join(", ")
        ),
        &chart,
        csv.text(),
    )
}

/// The parity figure's key (it is not the thesis's).
pub const PARITY_FIGURE: &str = "P1";

/// Figures 1-15 and the parity figure, in order.
pub fn all(data: &ReportData) -> Result<Vec<Figure>> {
    let pd = [SolverId::FastMassSpring, SolverId::AdmmPd];
    let all3 = [SolverId::Xpbd, SolverId::FastMassSpring, SolverId::AdmmPd];
    let [six, eight] = rest_states_xpbd(data)?;
    Ok(vec![
        figure1(data)?,
        figure2(data)?,
        figure3()?,
        figure4()?,
        error_against_dt(data, 5, 1e3, &all3)?,
        six,
        error_against_dt(data, 7, 1e6, &all3)?,
        eight,
        error_against_dt(data, 9, 1e3, &pd)?,
        error_against_dt(data, 10, 1e6, &pd)?,
        figure11(&data.runs)?,
        figure12(&data.runs)?,
        figure13(&data.runs)?,
        kinetic_energy_middle(&data.runs, 14)?,
        kinetic_energy_middle(&data.runs, 15)?,
        parity(data)?,
    ])
}
