//! Figures 5-10: the rest-state error against Δt per solver, and the rest states of XPBD
//! beside the reference, to scale.

use super::common::*;

use crate::data::CsvFile;
use crate::format::{full, full_opt};
use crate::inputs::ReportData;
use crate::plot::{
    Align, Axis, Chart, Entry, Marker, Panel, Series, COLUMN_WIDTH_MM, FULL_WIDTH_MM,
};
use crate::style::{coinciding_groups, colour, iteration_marker, BLACK, COINCIDE_DECADES, GREY};
use crate::tables::{iteration_count, measured, stiffness_label};
use mass_spring_solvers::error::Result;
use mass_spring_solvers::model::system::Vec3;
use mass_spring_solvers::solvers::registry::SolverId;
use mass_spring_solvers::studies::experiments::{published_rows, PublishedRow};

/// How far Figures 5, 7, 9 and 10 shift the marks of the first and third iteration counts
/// along Δt (left and right; the second stays), decades.
pub const DODGE_DECADES: f64 = 0.06;

/// Figures 5, 7, 9, 10: rest-state error against Δt on log axes, one panel per solver,
/// published (hollow, dashed) and ours (filled, solid) on the same axes.
pub(super) fn error_against_dt(
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
                // Each iteration count's marks shifted along Δt by its own small factor, so
                // that counts with the same error at a step do not hide one another.
                let dodge = 10f64.powf(DODGE_DECADES * (index as f64 - 1.0));
                s.points = series[index]
                    .iter()
                    .map(|&(dt, e)| (dt * dodge, e))
                    .collect();
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
    // Figures 9 and 10 are the thesis's own figures of the Projective Dynamics pair: the same
    // series as panels (b)-(c) of Figures 5 and 7, which the caption says.
    let which = if solvers.len() == 3 {
        "XPBD (a), Fast m-s (b) and ADMM (c)".to_string()
    } else {
        format!(
            "the two Projective Dynamics methods, Fast m-s (a) and ADMM (b), as the thesis draws them apart \
             (the same series as Figure {}(b)-(c), repeated)",
            if stiffness == 1e3 { 5 } else { 7 }
        )
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
             panel; the fewest iterations' marks are shifted {} decade left along Δt and the most iterations' \
             as far right, so that equal errors do not hide one another (the data file holds the true \
             Δt).{merged}",
            stiffness_text(stiffness),
            crate::tables::summed_over_free_nodes(),
            DODGE_DECADES,
        ),
        &chart,
        csv_rows.text(),
    )
}

/// The panel of Figure 6 or 8 and the shapes it draws: the rest state of Backward Euler
/// against XPBD at Δt = 0.1 s, every iteration count.
pub(super) fn rest_state_panel(
    data: &ReportData,
    stiffness: f64,
) -> (Panel, Vec<(String, Vec<Vec3>)>) {
    let mut panel = Panel::new(Axis::linear("x (m)"), Axis::linear("y (m)"));
    let mut shapes = Vec::new();
    let mut reference_series = None;
    if let Some(r) = reference(data, stiffness) {
        reference_series = Some(
            Series::line(
                "Newton reference (Δt = 0.001 s, 5 it.)",
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
                .with_marker(iteration_marker(index), true)
                // The most iterations' marks smaller, drawn last: where two runs come to the
                // same rest state, the other's mark shows around them.
                .with_marker_scale(if index == 2 { 0.55 } else { 1.0 }),
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
    // The reference underneath, its hollow squares larger than the XPBD marks: a run that
    // comes to the reference's rest state shows its own mark inside the square (drawn on top,
    // the squares hid the 20- and 50-iteration runs).
    if let Some(r) = reference_series {
        panel.series.insert(0, r);
    }
    (panel, shapes)
}

/// Figures 6 (k = 10³) and 8 (k = 10⁶), twins drawn to scale and at one scale: both panels
/// take the union of their data ranges, so that the same metre is as long in both.
pub(super) fn rest_states_xpbd(data: &ReportData) -> Result<[Figure; 2]> {
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
                    "Figure {number}. Rest state of Newton under Backward Euler (hollow squares) against XPBD, k = {} N/m, \
                     drawn to scale (the same metre on both axes) and at the scale of its twin, Figure {twin}. \
                     The thesis does not say which XPBD run it shows; we show the coarsest time step, Δt = 0.1 s, \
                     with each of its iteration counts (1, 20, 50), where the difference is visible and shrinks \
                     with the iterations. Node positions at the end of each run (the first kinetic-energy peak \
                     below 0.001 J). The reference is drawn underneath and the 50-iteration marks smaller, \
                     so that runs at the same rest state show each mark inside the other.",
                    stiffness_text(stiffness)
                ),
                &Chart::new(COLUMN_WIDTH_MM, 82.0, vec![panel]),
                shapes_csv(&shapes),
            )
    });
    Ok([six?, eight?])
}
