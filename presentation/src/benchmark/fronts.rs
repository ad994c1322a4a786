//! Work-precision fronts and their figures, in any cost: counted flops (the report's section
//! 12, [`super::figures`]) or wall time (`make timing`, [`super::wall`]). One case's figure
//! is a panel per family of solvers under Backward Euler and one of Newton under each
//! integrator, each solver's ε-front with its Δt labels, the explicit baselines, doing nothing
//! and the exact motion's floor.

use crate::benchmark::families::{BASELINE_GREY, FAMILIES};
use crate::chapter_figure::ChapterFigure;
use crate::data::CsvFile;
use crate::format::full;
use crate::plot::{
    place_clear_labels, Align, Axis, Chart, Label, Line, Marker, Panel, Rgb, Series, FULL_WIDTH_MM,
};
use crate::style::{colour, family_marker, solver_line};
use mass_spring_solvers::error::Result;
use mass_spring_solvers::integrators::optimization_integrator::OptimizationIntegrator;
use mass_spring_solvers::solvers::registry::SolverId;
use mass_spring_solvers::studies::benchmark::rows::Row;
use mass_spring_solvers::studies::benchmark::sweep::BASELINES;

/// A point of a work-precision front: the configuration that ran, the cost a figure draws
/// (counted flops in the report, wall time in `make timing`) and its relative physical error.
pub trait FrontRow {
    fn solver(&self) -> &str;
    /// The integrator's key, empty for a solver's own scheme.
    fn integrator(&self) -> &str;
    fn iterations(&self) -> usize;
    fn dt_s(&self) -> f64;
    fn cost(&self) -> f64;
    fn error(&self) -> f64;
}

/// The report's rows: their cost is the counted flops (rows without flops or error are never
/// on a front, [`super::BenchmarkChapter::front_under`]).
impl FrontRow for Row {
    fn solver(&self) -> &str {
        &self.solver
    }
    fn integrator(&self) -> &str {
        &self.integrator
    }
    fn iterations(&self) -> usize {
        self.iterations
    }
    fn dt_s(&self) -> f64 {
        self.dt_s
    }
    fn cost(&self) -> f64 {
        self.flops.unwrap_or(f64::NAN)
    }
    fn error(&self) -> f64 {
        self.physical_rel.unwrap_or(f64::NAN)
    }
}

/// A curve of a work-precision panel: a front and how it is drawn.
struct Curve<'a, R> {
    label: String,
    rows: Vec<&'a R>,
    colour: Rgb,
    line: Line,
    marker: Marker,
}

/// The integrators' colours in the Newton panel (Okabe-Ito, black for Backward Euler).
const INTEGRATOR_COLOURS: [Rgb; 4] = [
    Rgb(0, 0, 0),
    Rgb(0, 114, 178),
    Rgb(230, 159, 0),
    Rgb(0, 158, 115),
];

/// The time steps labelled on the work-precision fronts, s: the decades of the grid.
const LABELLED_DTS: [f64; 4] = [0.1, 0.01, 0.001, 0.0001];

/// Where a front's Δt label may go around its point (offset pt, alignment), in order of
/// preference: above, below, right, left.
const DT_LABEL_PLACES: [((f64, f64), Align); 4] = [
    ((0.0, 6.0), Align::Middle),
    ((0.0, -12.0), Align::Middle),
    ((6.0, -3.0), Align::Start),
    ((-6.0, -3.0), Align::End),
];

/// The candidate Δt labels of a panel's fronts: each point at a [`LABELLED_DTS`] step, in
/// the curve's colour, with its [`DT_LABEL_PLACES`].
fn dt_labels<R: FrontRow>(curves: &[Curve<R>]) -> Vec<Vec<Label>> {
    curves
        .iter()
        .flat_map(|c| {
            c.rows
                .iter()
                .filter(|r| LABELLED_DTS.contains(&r.dt_s()))
                .map(move |r| {
                    DT_LABEL_PLACES
                        .iter()
                        .map(|&(offset, align)| Label {
                            at: (r.cost(), r.error()),
                            offset,
                            align,
                            text: full(r.dt_s()),
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

/// A case's work-precision figure in one cost: a panel per family of solvers under Backward
/// Euler (the thesis's scheme; XPBD, PBD and the explicit baselines under their own) and a
/// panel of Newton under each integrator, with the baselines, doing nothing and the exact
/// motion's `floor` on each. `front(solver, integrator key)` gives a solver's front, cheapest
/// first; the figure's data records every point drawn, its cost in the column `cost_column`.
pub fn work_figure<'a, R: FrontRow + 'a>(
    stem: &'static str,
    (cost_axis, cost_column): (&str, &'static str),
    floor: Option<f64>,
    front: impl Fn(SolverId, &str) -> Vec<&'a R>,
) -> Result<ChapterFigure> {
    let mut csv = CsvFile::new(&[
        "solver",
        "integrator",
        "iterations",
        "dt_s",
        cost_column,
        "physical_rel",
        "panel",
    ]);
    let own_scheme = |id: SolverId| {
        if id.is_minimizing() {
            OptimizationIntegrator::BackwardEuler.key()
        } else {
            ""
        }
    };
    let baselines = || -> Vec<Curve<R>> {
        BASELINES
            .iter()
            .map(|&id| Curve {
                label: id.info().display_name.to_string(),
                rows: front(id, ""),
                colour: BASELINE_GREY,
                line: if id == SolverId::Rk4 {
                    Line::Dashed
                } else {
                    Line::Dotted
                },
                marker: Marker::Cross,
            })
            .collect()
    };
    let mut panels = Vec::new();
    let mut labels = Vec::new();
    for (name, family) in FAMILIES {
        let curves: Vec<Curve<R>> = family
            .iter()
            .map(|&id| Curve {
                label: id.info().display_name.to_string(),
                rows: front(id, own_scheme(id)),
                colour: colour(id, 0),
                line: solver_line(id),
                marker: family_marker(id),
            })
            .collect();
        labels.push(dt_labels(&curves));
        panels.push(work_panel(
            name,
            cost_axis,
            curves,
            baselines(),
            floor,
            &mut csv,
        ));
    }
    let newton: Vec<Curve<R>> = OptimizationIntegrator::ALL
        .iter()
        .enumerate()
        .map(|(k, &integrator)| Curve {
            label: format!("Newton, {}", integrator.label()),
            rows: front(SolverId::BackwardEuler, integrator.key()),
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
    panels.push(work_panel(
        "Newton under each integrator",
        cost_axis,
        newton,
        baselines(),
        floor,
        &mut csv,
    ));
    let mut chart = Chart::new(FULL_WIDTH_MM, 250.0, panels);
    chart.columns = 1;
    for (panel, candidates) in labels.into_iter().enumerate() {
        place_clear_labels(&mut chart, panel, candidates)?;
    }
    ChapterFigure::new(stem, &chart, csv.text())
}

/// The caption of a [`work_figure`] after its number: what it draws, by `cost` (e.g. "the
/// counted flops over the window"), on the case `label`, whose explicit baselines are drawn
/// if `baselines` (none is where every one is unstable at every time step).
pub fn work_figure_caption(label: &str, cost: &str, baselines: bool) -> String {
    format!(
        "Work and precision, {label}: (a)-(c) Backward Euler only (the minimizing solvers \
         under it; XPBD, PBD and the explicit baselines under their own schemes), (d) Newton \
         under each of the four integrators (the other solvers' costs under them are in \
         section 12.4). Each solver's ε-front (ε = {eps}: a configuration is left out when \
         another of its own costs at most {grow} times as much with at most {grow} times its \
         error) of the relative physical error against {cost} (relative error: the RMS \
         physical error per free node over the exact motion's RMS amplitude), by family; the \
         numbers beside a front are the time step Δt (s) of its points at 0.1, 0.01, 0.001 \
         and 0.0001 s, in its colour, where there is room; grey: {baselines}doing nothing (the \
         equilibrium held still, error 1) and, dashed where a front comes within a factor 100 of it, the exact motion's floor (its halving gap over its amplitude, about 15 \
         times its own error): a point below it measures the truth, not the run, and is drawn \
         on it. A front marked ≈ has another's errors step for step: the same computation at \
         another cost.",
        eps = full(FRONT_EPSILON),
        grow = full(1.0 + FRONT_EPSILON),
        baselines = if baselines {
            "the explicit baselines (RK4 dashed, symplectic Euler dotted), "
        } else {
            "(the explicit baselines are unstable at every time step here, so none is drawn) "
        },
    )
}

/// How far above the exact motion's floor a front's least error may lie for the floor to be
/// drawn.
const FLOOR_DRAWN_WITHIN: f64 = 100.0;

/// One panel of a work-precision figure: `curves`, then `baselines`, doing nothing and the
/// exact motion's `floor`; each drawn point a record of `csv`.
fn work_panel<R: FrontRow>(
    name: &str,
    cost_axis: &str,
    curves: Vec<Curve<R>>,
    baselines: Vec<Curve<R>>,
    floor: Option<f64>,
    csv: &mut CsvFile,
) -> Panel {
    let mut panel = Panel::new(Axis::log(cost_axis), Axis::log("relative error"));
    panel.heading = name.into();
    let (mut lowest, mut highest) = (f64::INFINITY, 0.0f64);
    let mut seen: Vec<(String, Vec<(f64, f64)>)> = Vec::new();
    // The floor is drawn (and cuts the range) only where a front comes within
    // FLOOR_DRAWN_WITHIN of it: far below every point it would only squeeze the fronts.
    let least_error = curves
        .iter()
        .chain(&baselines)
        .flat_map(|c| c.rows.iter().map(|r| r.error()))
        .fold(f64::INFINITY, f64::min);
    let floor = floor.filter(|&f| least_error <= FLOOR_DRAWN_WITHIN * f);
    for mut curve in curves.into_iter().chain(baselines) {
        for r in &curve.rows {
            csv.record(vec![
                r.solver().to_string(),
                r.integrator().to_string(),
                r.iterations().to_string(),
                full(r.dt_s()),
                full(r.cost()),
                full(r.error()),
                name.into(),
            ]);
            lowest = lowest.min(r.cost());
            highest = highest.max(r.cost());
        }
        // A front whose errors are another's of this panel, step for step (the same
        // computation at another cost: one iteration from the same start), is named so.
        let errors: Vec<(f64, f64)> = curve.rows.iter().map(|r| (r.dt_s(), r.error())).collect();
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
            .map(|r| (r.cost(), floor.map_or(r.error(), |f| r.error().max(f))))
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

/// Whether two fronts' (dt, error) points are the same to round-off, step for step.
fn same_errors(a: &[(f64, f64)], b: &[(f64, f64)]) -> bool {
    a.len() == b.len()
        && a.iter()
            .zip(b)
            .all(|(x, y)| x.0 == y.0 && (x.1 - y.1).abs() <= 1e-9 * x.1.abs().max(y.1.abs()))
}
