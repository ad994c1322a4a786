//! The benchmark's work-precision figures: one per case, a panel per family of solvers, each
//! solver's ε-front with its Δt labels, and their files.

use super::*;
use crate::benchmark::families::{BASELINE_GREY, FAMILIES};
use crate::chapter_figure::ChapterFigure;
use crate::data::CsvFile;
use crate::format::full;
use crate::output::OutputFile;
use crate::plot::{
    place_clear_labels, Align, Axis, Chart, Label, Line, Marker, Panel, Rgb, Series, FULL_WIDTH_MM,
};
use crate::style::{colour, family_marker, solver_line};
use mass_spring_solvers::error::Result;
use mass_spring_solvers::integrators::optimization_integrator::OptimizationIntegrator;
use mass_spring_solvers::solvers::registry::SolverId;
use mass_spring_solvers::studies::benchmark::rows::Row;
use mass_spring_solvers::studies::benchmark::sweep::BASELINES;
use mass_spring_solvers::studies::benchmark::Case;
use mass_spring_solvers::studies::beyond::GridScene;

/// A curve of a work-precision panel: a front and how it is drawn.
pub(super) struct Curve<'a> {
    label: String,
    rows: Vec<&'a Row>,
    colour: Rgb,
    line: Line,
    marker: Marker,
}

/// The integrators' colours in the Newton panel (Okabe-Ito, black for Backward Euler).
pub(super) const INTEGRATOR_COLOURS: [Rgb; 4] = [
    Rgb(0, 0, 0),
    Rgb(0, 114, 178),
    Rgb(230, 159, 0),
    Rgb(0, 158, 115),
];

/// The time steps labelled on the work-precision fronts, s: the decades of the grid.
pub(super) const LABELLED_DTS: [f64; 4] = [0.1, 0.01, 0.001, 0.0001];

/// Where a front's Δt label may go around its point (offset pt, alignment), in order of
/// preference: above, below, right, left.
pub(super) const DT_LABEL_PLACES: [((f64, f64), Align); 4] = [
    ((0.0, 6.0), Align::Middle),
    ((0.0, -12.0), Align::Middle),
    ((6.0, -3.0), Align::Start),
    ((-6.0, -3.0), Align::End),
];

/// The candidate Δt labels of a panel's fronts: each point at a [`LABELLED_DTS`] step, in
/// the curve's colour, with its [`DT_LABEL_PLACES`].
pub(super) fn dt_labels(curves: &[Curve]) -> Vec<Vec<Label>> {
    curves
        .iter()
        .flat_map(|c| {
            c.rows
                .iter()
                .filter(|r| LABELLED_DTS.contains(&r.dt_s))
                .map(move |r| {
                    DT_LABEL_PLACES
                        .iter()
                        .map(|&(offset, align)| Label {
                            at: (r.flops.unwrap(), r.physical_rel.unwrap()),
                            offset,
                            align,
                            text: full(r.dt_s),
                            color: c.colour,
                        })
                        .collect()
                })
        })
        .collect()
}

/// The ε of the work-precision fronts: configurations within 10 % of each other in both cost
/// and error are one point of the front.
pub const FRONT_EPSILON: f64 = 0.1;

/// The ε-Pareto front of (cost, error) points, as indices cheapest first. A point
/// ε-dominates another when it costs at most (1 + ε) times as much and its error is at most
/// (1 + ε) times as large. The front is built in two passes: in order of cost, a point is kept
/// when its error is below the last kept one's divided by (1 + ε); then, from the most
/// expensive down, a kept point is dropped when the next kept one costs at most (1 + ε) times
/// as much (it is as cheap, within ε, and better). Every point left out is ε-dominated by a
/// point of the front, and no point of the front ε-dominates another; with ε = 0 it is the
/// strict front (each point beats every cheaper one).
pub fn epsilon_front(points: &[(f64, f64)], epsilon: f64) -> Vec<usize> {
    let grow = 1.0 + epsilon;
    let mut order: Vec<usize> = (0..points.len()).collect();
    order.sort_by(|&a, &b| {
        points[a]
            .0
            .total_cmp(&points[b].0)
            .then(points[a].1.total_cmp(&points[b].1))
    });
    let mut kept: Vec<usize> = Vec::new();
    for i in order {
        if kept
            .last()
            .is_none_or(|&l| points[i].1 * grow < points[l].1)
        {
            kept.push(i);
        }
    }
    let mut front: Vec<usize> = Vec::new();
    for &i in kept.iter().rev() {
        if front
            .last()
            .is_none_or(|&next| points[next].0 > grow * points[i].0)
        {
            front.push(i);
        }
    }
    front.reverse();
    front
}

impl BenchmarkChapter {
    /// The work-precision figures, one per case: a panel per family of solvers under the
    /// thesis's scheme and a panel of Newton under each integrator, with the baselines and the
    /// do-nothing line on each.
    pub fn figures(&self) -> Result<Vec<ChapterFigure>> {
        self.cases()
            .into_iter()
            .map(|case| {
                let mut csv = CsvFile::new(&[
                    "solver",
                    "integrator",
                    "iterations",
                    "dt_s",
                    "flops",
                    "physical_rel",
                    "panel",
                ]);
                let mut panels = Vec::new();
                let mut labels = Vec::new();
                for (name, family) in FAMILIES {
                    let curves: Vec<Curve> = family
                        .iter()
                        .map(|&id| Curve {
                            label: id.info().display_name.to_string(),
                            rows: self.front(case, id),
                            colour: colour(id, 0),
                            line: solver_line(id),
                            marker: family_marker(id),
                        })
                        .collect();
                    labels.push(dt_labels(&curves));
                    panels.push(self.work_panel(case, name, curves, &mut csv));
                }
                let newton: Vec<Curve> = OptimizationIntegrator::ALL
                    .iter()
                    .enumerate()
                    .map(|(k, &integrator)| Curve {
                        label: format!("Newton, {}", integrator.label()),
                        rows: self.front_under(case, SolverId::BackwardEuler, integrator.key()),
                        colour: INTEGRATOR_COLOURS[k],
                        line: [Line::Solid, Line::Dashed, Line::Dotted, Line::Solid][k],
                        marker: [
                            Marker::Square,
                            Marker::Circle,
                            Marker::Triangle,
                            Marker::Cross,
                        ][k],
                    })
                    .collect();
                labels.push(dt_labels(&newton));
                panels.push(self.work_panel(
                    case,
                    "Newton under each integrator",
                    newton,
                    &mut csv,
                ));
                let mut chart = Chart::new(FULL_WIDTH_MM, 250.0, panels);
                chart.columns = 1;
                for (panel, candidates) in labels.into_iter().enumerate() {
                    place_clear_labels(&mut chart, panel, candidates)?;
                }
                ChapterFigure::new(stem(case), &chart, csv.text())
            })
            .collect()
    }

    /// Whether a work-precision figure of `case` draws any explicit baseline (none is drawn
    /// where every one is unstable at every time step, the stiff sheet).
    pub fn baselines_drawn(&self, case: Case) -> bool {
        BASELINES.iter().any(|&id| !self.front(case, id).is_empty())
    }

    /// One panel of a work-precision figure: `curves`, then the baselines and doing nothing;
    /// each drawn point a record of `csv`.
    fn work_panel(&self, case: Case, name: &str, curves: Vec<Curve>, csv: &mut CsvFile) -> Panel {
        let mut panel = Panel::new(
            Axis::log("flops over the window"),
            Axis::log("relative error"),
        );
        panel.heading = name.into();
        let baselines = BASELINES.iter().map(|&id| Curve {
            label: id.info().display_name.to_string(),
            rows: self.front(case, id),
            colour: BASELINE_GREY,
            line: if id == SolverId::Rk4 {
                Line::Dashed
            } else {
                Line::Dotted
            },
            marker: Marker::Cross,
        });
        let (mut lowest, mut highest) = (f64::INFINITY, 0.0f64);
        let floor = self.truth_floor(case);
        let mut seen: Vec<(String, Vec<(f64, f64)>)> = Vec::new();
        for mut curve in curves.into_iter().chain(baselines) {
            for r in &curve.rows {
                csv.record(vec![
                    r.solver.clone(),
                    r.integrator.clone(),
                    r.iterations.to_string(),
                    full(r.dt_s),
                    full(r.flops.unwrap()),
                    full(r.physical_rel.unwrap()),
                    name.into(),
                ]);
                lowest = lowest.min(r.flops.unwrap());
                highest = highest.max(r.flops.unwrap());
            }
            // A front whose errors are another's of this panel, step for step (the same
            // computation at another cost: one iteration from the same start), is named so.
            let errors: Vec<(f64, f64)> = curve
                .rows
                .iter()
                .map(|r| (r.dt_s, r.physical_rel.unwrap()))
                .collect();
            if let Some((twin, _)) = seen.iter().find(|(_, e)| same_errors(e, &errors)) {
                curve.label = format!("{} (≈ {twin}'s errors)", curve.label);
            } else if !errors.is_empty() {
                seen.push((curve.label.clone(), errors));
            }
            // Below the exact motion's own floor an error measures the truth, not the run: such
            // points are drawn on the floor.
            let points: Vec<(f64, f64)> = curve
                .rows
                .iter()
                .map(|r| {
                    let e = r.physical_rel.unwrap();
                    (r.flops.unwrap(), floor.map_or(e, |f| e.max(f)))
                })
                .collect();
            if !points.is_empty() {
                panel.series.push(
                    Series::line(curve.label, points, curve.colour)
                        .with_line(curve.line)
                        .with_marker(curve.marker, curve.colour != BASELINE_GREY),
                );
            }
        }
        if lowest.is_finite() {
            panel.series.push(
                Series::line(
                    "doing nothing",
                    vec![(lowest, 1.0), (highest, 1.0)],
                    BASELINE_GREY,
                )
                .with_line(Line::Solid)
                .with_weight(0.6),
            );
            if let Some(f) = floor {
                panel.series.push(
                    Series::line(
                        "the exact motion's floor (points below drawn on it)",
                        vec![(lowest, f), (highest, f)],
                        BASELINE_GREY,
                    )
                    .with_line(Line::Dashed)
                    .with_weight(0.6),
                );
            }
        }
        panel
    }

    /// The exact motion's own error on a case, relative to its amplitude, as the figures cut
    /// at it: its halving gap (the change when RK4's step is halved, which bounds the coarser
    /// motion's error and is about 15 times the exact motion's own), over the amplitude.
    pub fn truth_floor(&self, case: Case) -> Option<f64> {
        let truth = self.truth(case)?;
        Some(truth.halving_gap_m / truth.amplitude_rms_m)
    }

    /// The figures and the data files.
    pub fn files(&self, figures: &[ChapterFigure]) -> Vec<OutputFile> {
        let mut files: Vec<OutputFile> = figures
            .iter()
            .flat_map(|f| crate::chapter_figure::figure_files(f.stem, &f.svg, &f.csv))
            .collect();
        files.push(OutputFile::text("data/benchmark.csv", rows_csv(&self.rows)));
        files.push(OutputFile::text(
            "data/benchmark_references.csv",
            rows_csv(&self.references),
        ));
        if !self.protocol.is_empty() {
            files.push(OutputFile::text(
                "data/benchmark_thesis_protocol.csv",
                rows_csv(&self.protocol),
            ));
        }
        files.push(OutputFile::text(
            "data/benchmark_own_start.csv",
            rows_csv(&self.own_start),
        ));
        files.push(OutputFile::text(
            "data/benchmark_truths.csv",
            rows_csv(&self.truths),
        ));
        files
    }
}

/// Whether two fronts' (dt, error) points are the same to round-off, step for step.
fn same_errors(a: &[(f64, f64)], b: &[(f64, f64)]) -> bool {
    a.len() == b.len()
        && a.iter()
            .zip(b)
            .all(|(x, y)| x.0 == y.0 && (x.1 - y.1).abs() <= 1e-9 * x.1.abs().max(y.1.abs()))
}

/// The figure's file stem of a case.
pub fn stem(case: Case) -> &'static str {
    match (case.scene, case.stiffness == 1e3) {
        (GridScene::Rope, true) => "benchmark_rope_k1e3",
        (GridScene::Rope, false) => "benchmark_rope_k1e6",
        (GridScene::Sheet, true) => "benchmark_sheet_k1e3",
        (GridScene::Sheet, false) => "benchmark_sheet_k1e6",
    }
}
