//! The work-precision chapter (issue 14, the thesis's first line of future work, §5): every
//! solver's error against its counted floating-point operations on the rope at both
//! stiffnesses and on the 10 × 10 sheet, the cheapest configuration of each solver that
//! reaches a physical error, and the thesis's question answered with the cost counted.

use crate::beyond::GridScene;
use crate::error::Result;
use crate::registry::{SolverId, SolverSpec};
use crate::report::figures::{colour, solver_line};
use crate::report::format::{full, sig4, MarkdownTable};
use crate::report::output::OutputFile;
use crate::report::plot::{Axis, Chart, Marker, Panel, Series, FULL_WIDTH_MM};
use crate::report::ChapterFigure;
use crate::work_precision::{
    cheapest, flops_per_iteration, flops_per_step_overhead, flops_setup, most_accurate_within,
    pareto_front, sweep, sweep_of, sweep_solvers, Case, CaseReference, ErrorKind, Point,
    PointResult, ERROR_LEVELS_M, REFERENCE_STABILITY_FRACTION, SAMPLE_INTERVAL_S, TOLERANCES_M,
    TOLERANCE_CAP, WINDOW_S,
};

/// The header of `data/work_precision.csv` (issue 14, step 5).
pub const CSV_HEADER: &str =
    "solver,scene,stiffness,dt_s,tolerance,iterations_mean,error_kind,error,flops";

/// The solver-error level of the section's second table, m.
pub const SOLVER_ERROR_LEVEL_M: f64 = 1e-6;

/// The budgets, in flops, at which the solvers are compared for accuracy.
pub const BUDGETS: [f64; 4] = [1e6, 1e7, 1e8, 1e9];

/// The thesis's verdict (§4.4 and §5): Projective Dynamics, ADMM first, for the rest state;
/// XPBD for the motion ("XPBD para el caso dinámico").
pub const THESIS_VERDICT: [(ErrorKind, SolverId); 2] = [
    (ErrorKind::Rest, SolverId::AdmmPd),
    (ErrorKind::Physical, SolverId::Xpbd),
];

/// The thesis's three approximations, whose ranking Tables 8-12 give.
pub const THESIS_THREE: [SolverId; 3] =
    [SolverId::Xpbd, SolverId::FastMassSpring, SolverId::AdmmPd];

/// For each verdict of [`THESIS_VERDICT`]: in how many (case, budget) cells of [`Case::ALL`] ×
/// [`BUDGETS`] its solver is the most accurate of [`THESIS_THREE`] within the budget, and in
/// how many cells any of the three has a configuration within it.
pub fn verdict(results: &[PointResult]) -> [(usize, usize); 2] {
    THESIS_VERDICT.map(|(kind, id)| {
        let winners: Vec<SolverId> = Case::ALL
            .into_iter()
            .flat_map(|case| {
                BUDGETS.into_iter().filter_map(move |budget| {
                    most_accurate_within(results, case, kind, budget, &THESIS_THREE)
                        .map(|r| r.point.spec.id)
                })
            })
            .collect();
        (winners.iter().filter(|&&w| w == id).count(), winners.len())
    })
}

/// The solvers most often the most accurate in the error of `kind` on `case` over the
/// [`BUDGETS`] (every sweep solver competing), in registry order (more than one on a tie),
/// with that count; None if no solver has a configuration within any budget.
pub fn most_frequent_winner(
    results: &[PointResult],
    case: Case,
    kind: ErrorKind,
) -> Option<(Vec<SolverId>, usize)> {
    let winners: Vec<SolverId> = BUDGETS
        .into_iter()
        .filter_map(|budget| {
            most_accurate_within(results, case, kind, budget, &sweep_solvers())
                .map(|r| r.point.spec.id)
        })
        .collect();
    most_frequent(&winners)
}

/// The solvers that occur most often in `winners`, in registry order (more than one on a
/// tie), with their count; None for no winner.
pub fn most_frequent(winners: &[SolverId]) -> Option<(Vec<SolverId>, usize)> {
    let counts: Vec<(SolverId, usize)> = sweep_solvers()
        .into_iter()
        .map(|id| (id, winners.iter().filter(|&&w| w == id).count()))
        .collect();
    let most = counts.iter().map(|&(_, n)| n).max().filter(|&n| n > 0)?;
    let ids = counts
        .into_iter()
        .filter(|&(_, n)| n == most)
        .map(|(id, _)| id)
        .collect();
    Some((ids, most))
}

/// `` `a` `` or `` `a`, `b` and `c` ``.
pub fn solver_list(ids: &[SolverId]) -> String {
    let names: Vec<String> = ids.iter().map(|id| format!("`{id}`")).collect();
    match names.split_last() {
        Some((last, rest)) if !rest.is_empty() => format!("{} and {last}", rest.join(", ")),
        _ => names.concat(),
    }
}

/// Every result of the chapter.
#[derive(Debug, Clone, PartialEq)]
pub struct WorkPrecisionChapter {
    /// The references of each case of [`Case::ALL`], in its order.
    pub references: Vec<CaseReference>,
    /// Every configuration of the sweep.
    pub results: Vec<PointResult>,
}

/// `work_precision.csv`: one row per finished configuration and error kind; a run that
/// diverged has no row (the section lists it).
pub fn csv(results: &[PointResult]) -> String {
    let mut out = format!("{CSV_HEADER}\n");
    for r in results {
        for kind in ErrorKind::ALL {
            if let Some(error) = r.error(kind) {
                out += &format!(
                    "{},{},{},{},{},{},{},{},{}\n",
                    r.point.spec.id,
                    r.point.case.scene.id(),
                    full(r.point.case.stiffness),
                    full(r.point.dt_s),
                    tolerance_cell(&r.point),
                    full(r.iterations_mean()),
                    kind.id(),
                    full(error),
                    full(r.flops)
                );
            }
        }
    }
    out
}

/// `dt = 0.01 s, 70 it.`, or for a run to a tolerance `dt = 0.01 s, to 1e-4 m (12.3 it.)`
/// with the mean iterations per step.
pub fn configuration(r: &PointResult) -> String {
    configuration_of(&r.point, r.iterations_mean())
}

/// [`configuration`] of `point`, whose steps took `iterations_mean` iterations on average.
pub fn configuration_of(point: &Point, iterations_mean: f64) -> String {
    let dt = full(point.dt_s);
    match point.spec.stopping.tolerance_m() {
        None => format!("dt = {dt} s, {} it.", point.spec.iterations),
        Some(t) => format!("dt = {dt} s, to {t:e} m ({iterations_mean:.1} it.)"),
    }
}

/// A CSV's tolerance cell: the tolerance, m, or empty for a fixed iteration count.
pub fn tolerance_cell(point: &Point) -> String {
    point
        .spec
        .stopping
        .tolerance_m()
        .map_or(String::new(), full)
}

/// The `i`-th solver's work-precision curve in a figure: its front's (cost, error) points, in
/// the registry's colour and line style, with the `i`-th of four markers.
pub fn front_series(i: usize, id: SolverId, points: Vec<(f64, f64)>) -> Series {
    const MARKERS: [Marker; 4] = [
        Marker::Circle,
        Marker::Square,
        Marker::Triangle,
        Marker::Cross,
    ];
    Series::line(id.info().abbreviation, points, colour(id, 0))
        .with_marker(MARKERS[i % MARKERS.len()], i % 2 == 0)
        .with_line(solver_line(id))
}

/// The figure's file stem of a case (also of its wall-time figure in `make timing`).
pub fn stem(case: Case) -> &'static str {
    match (case.scene, case.stiffness == 1e3) {
        (GridScene::Rope, true) => "work_precision_rope_k1e3",
        (GridScene::Rope, false) => "work_precision_rope_k1e6",
        (GridScene::Sheet, true) => "work_precision_sheet_k1e3",
        (GridScene::Sheet, false) => "work_precision_sheet_k1e6",
    }
}

impl WorkPrecisionChapter {
    /// The exact motions, the converged Backward Euler trajectories and every configuration.
    pub fn compute(progress: &(dyn Fn(usize, usize) + Sync)) -> Result<Self> {
        let (references, results) = sweep(progress)?;
        Ok(Self {
            references,
            results,
        })
    }

    /// The chapter with only `points` of the sweep run (the tests run a part of it).
    pub fn compute_points(
        points: &[Point],
        progress: &(dyn Fn(usize, usize) + Sync),
    ) -> Result<Self> {
        let (references, results) = sweep_of(points, progress)?;
        Ok(Self {
            references,
            results,
        })
    }

    fn of(&self, case: Case) -> impl Iterator<Item = &PointResult> {
        self.results.iter().filter(move |r| r.point.case == case)
    }

    /// One figure per case: the physical error against the flops, log-log, each solver's
    /// work-precision curve (its configurations that no other of its own beats in both).
    pub fn figures(&self) -> Result<Vec<ChapterFigure>> {
        Case::ALL
            .into_iter()
            .map(|case| {
                let mut panel = Panel::new(
                    Axis::log("floating-point operations over 5 s"),
                    Axis::log("physical error (m)"),
                );
                let mut csv = String::from(
                    "solver,tolerance_m,iterations_mean,dt_s,flops,physical_error_m\n",
                );
                for (i, id) in sweep_solvers().into_iter().enumerate() {
                    let front = pareto_front(&self.results, case, id, ErrorKind::Physical);
                    for r in &front {
                        csv += &format!(
                            "{id},{},{},{},{},{}\n",
                            tolerance_cell(&r.point),
                            full(r.iterations_mean()),
                            full(r.point.dt_s),
                            full(r.flops),
                            full(r.error(ErrorKind::Physical).expect("the front has errors"))
                        );
                    }
                    let points = front
                        .iter()
                        .map(|r| (r.flops, r.error(ErrorKind::Physical).unwrap()))
                        .collect();
                    panel.series.push(front_series(i, id, points));
                }
                ChapterFigure::new(
                    stem(case),
                    &Chart::new(FULL_WIDTH_MM, 90.0, vec![panel]),
                    csv,
                )
            })
            .collect()
    }

    /// The figures and `data/work_precision.csv`.
    pub fn files(&self, figures: &[ChapterFigure]) -> Vec<OutputFile> {
        let mut files: Vec<OutputFile> = figures
            .iter()
            .flat_map(|f| crate::report::figure_files(f.stem, &f.svg, &f.csv))
            .collect();
        files.push(OutputFile::text(
            "data/work_precision.csv",
            csv(&self.results),
        ));
        files
    }

    /// The smallest physical error of the sweep on `case`, m.
    pub fn smallest_physical_error(&self, case: Case) -> Option<f64> {
        self.of(case)
            .filter_map(|r| r.error(ErrorKind::Physical))
            .min_by(f64::total_cmp)
    }

    /// The chapter's section of `REPORT.md`, headed `## {number}.`.
    pub fn section(&self, number: u32, figures: &[ChapterFigure]) -> String {
        let mut md = format!(
            "## {number}. Work and precision: the timing study the thesis left for later (§5)\n\n"
        );
        md += &format!(
            "The thesis fixes its iteration counts by hand and never counts work. Here every \
             solver runs the rope and the 10 × 10 sheet, each at k = 1e3 and 1e6 N/m, from \
             rest for {w} s, at every time step of the sweep, at the iteration counts of \
             section 10 (a fixed count per step) and, for every solver whose steps iterate, to \
             each tolerance of {tols} m (a step stops at the first iterate that moved no node by \
             more than the tolerance, capped at {cap} iterations: one measure for every solver, \
             our interpretation where the papers run fixed counts, argued in `src/stopping.rs`), \
             and each run gets three errors, each the per-node distance summed (convention 7) \
             with its largest node distance in the library: **physical**, the worst over the \
             samples t = {si}, {s2}, …, {w} s of the gap to the exact undamped motion; **rest**, \
             the gap at t = {w} s to the exact static equilibrium (a run still swinging at {w} s \
             is far from it, so this error rewards numerical damping); **solver**, the worst \
             gap over the same samples to the trajectory of converged Backward Euler steps at the \
             same time step (zero for an exact implicit Euler). The damped pair is left out (at \
             zero damping it is Backward Euler and ADMM-PD; the exact motion is undamped).\n\n",
            w = full(WINDOW_S),
            tols = TOLERANCES_M.map(full).join(", "),
            cap = TOLERANCE_CAP,
            si = full(SAMPLE_INTERVAL_S),
            s2 = full(2.0 * SAMPLE_INTERVAL_S),
        );
        md += crate::report::integrators::UNDER_BACKWARD_EULER;
        md += "\n\n";

        md += &format!("### {number}.1 The exact motion\n\n");
        md += &format!(
            "The tutorial's RK4 at {} of its stability limit ωh < 2√2, with ω the highest \
             natural frequency of the start state, the step rounded down to divide the sample \
             interval. Its convergence: the change of the trajectory when RK4's step is halved \
             from twice this step to it, which estimates the error of the coarser motion; RK4 \
             being of order 4, the exact motion's own error is about a fifteenth of it (the test \
             `tests/work_precision.rs` bounds the change and measures the order).\n\n",
            full(REFERENCE_STABILITY_FRACTION)
        );
        let mut t = MarkdownTable::new(&[
            "case",
            "stability limit (s)",
            "RK4 step (s)",
            "steps",
            "flops",
            "halving from 2h to h changes it by (m)",
            "smallest physical error of the sweep (m)",
        ]);
        for reference in &self.references {
            let e = &reference.exact;
            let system = e
                .case
                .scene
                .system(e.case.stiffness)
                .expect("the case's system built for its reference");
            let flops =
                e.steps() as f64 * flops_per_iteration(&SolverSpec::new(SolverId::Rk4, 1), &system);
            t.row(vec![
                e.case.label(),
                sig4(e.stability_limit),
                sig4(e.h),
                e.steps().to_string(),
                sig4(flops),
                sig4(reference.halving_gap.sum),
                self.smallest_physical_error(e.case)
                    .map_or("–".into(), sig4),
            ]);
        }
        md += &t.render();
        md += "\n";

        md += &format!("### {number}.2 The cost model\n\n");
        md += "Every count is floating-point operations (an addition, multiplication, division \
               or square root), from each operation's arithmetic as \
               `work_precision::flops_per_iteration` documents it: a solve with a factor of nnz \
               non-zeros below the diagonal costs 4·nnz + 2n per right-hand side (two triangular \
               solves and the diagonal), the banded factorisation n(p + 1)², a spring projection \
               13, an XPBD constraint projection 36, a spring force 21 and its Jacobian 58 with \
               its assembly. A run costs setup + Σ over its steps of (overhead + the count of \
               each iteration the step took), from the iterations each step logged \
               (`work_precision::logged_flops`); Anderson's columns and L-BFGS's pairs restart \
               every step, so their first iterations cost less than the full-window iteration \
               shown here. A line search's trials after the first and Anderson's rejected \
               extrapolations are logged and counted (`work_precision::flops_of_extra`); the \
               tolerance test costs 9 per node and iteration. On each scene:\n\n";
        let mut t = MarkdownTable::new(&[
            "solver",
            "rope setup",
            "rope per step",
            "rope per iteration (full window)",
            "sheet setup",
            "sheet per step",
            "sheet per iteration (full window)",
        ]);
        let rope = GridScene::Rope.system(1e3).expect("the thesis rope builds");
        let sheet = GridScene::Sheet.system(1e3).expect("the sheet builds");
        for id in sweep_solvers() {
            let spec = SolverSpec::new(id, 1);
            let mut row = vec![format!("`{id}`")];
            for system in [&rope, &sheet] {
                row.push(sig4(flops_setup(&spec, system)));
                row.push(sig4(flops_per_step_overhead(&spec, system)));
                row.push(sig4(flops_per_iteration(&spec, system)));
            }
            t.row(row);
        }
        md += &t.render();
        md += "\n";

        md += &format!("### {number}.3 Work-precision diagrams\n\n");
        for (case, f) in Case::ALL.iter().zip(figures) {
            md += &format!(
                "![{s}](figures/{s}.svg)\n\n*Physical error against floating-point operations, \
                 {label}: each solver's configurations that none of its own beats in both \
                 (time steps {dts} s × its iteration counts and tolerances).* Data: [`data/{s}.csv`](data/{s}.csv), \
                 every configuration in [`data/work_precision.csv`](data/work_precision.csv).\n\n",
                s = f.stem,
                label = case.label(),
                dts = case.dts().iter().map(|&d| full(d)).collect::<Vec<_>>().join(", "),
            );
        }
        let diverged: Vec<String> = self
            .results
            .iter()
            .filter(|r| r.errors.is_err())
            .map(|r| {
                format!(
                    "`{}` {} ({})",
                    r.point.spec.id,
                    configuration(r),
                    r.point.case.label()
                )
            })
            .collect();
        md += &format!(
            "Runs that did not finish the window: {}.\n\n",
            if diverged.is_empty() {
                "none".to_string()
            } else {
                diverged.join("; ")
            }
        );

        md +=
            &format!("### {number}.4 The cheapest configuration that reaches a physical error\n\n");
        for case in Case::ALL {
            md += &format!("**{}**\n\n", case.label());
            let mut header = vec!["solver".to_string()];
            header.extend(ERROR_LEVELS_M.iter().map(|l| format!("≤ {} m", full(*l))));
            header.push("smallest reached (m)".into());
            let mut t = MarkdownTable::new(&header);
            for id in sweep_solvers() {
                let mut row = vec![format!("`{id}`")];
                for level in ERROR_LEVELS_M {
                    row.push(
                        cheapest(&self.results, case, id, ErrorKind::Physical, level)
                            .map_or("not reached".into(), |r| {
                                format!("{} flops ({})", sig4(r.flops), configuration(r))
                            }),
                    );
                }
                let best = pareto_front(&self.results, case, id, ErrorKind::Physical);
                row.push(best.last().map_or("–".into(), |r| {
                    format!(
                        "{} ({} flops)",
                        sig4(r.error(ErrorKind::Physical).unwrap()),
                        sig4(r.flops)
                    )
                }));
                t.row(row);
            }
            md += &t.render();
            md += "\n";
        }

        md += &format!(
            "Beside them, the solver error: the cheapest configuration of each solver within \
             {} m of the converged Backward Euler trajectory at its own time step (how much work \
             it takes to be implicit Euler; the XPBD family and PBD converge elsewhere).\n\n",
            full(SOLVER_ERROR_LEVEL_M)
        );
        let mut header = vec!["solver".to_string()];
        header.extend(Case::ALL.iter().map(|c| c.label()));
        let mut t = MarkdownTable::new(&header);
        for id in sweep_solvers() {
            let mut row = vec![format!("`{id}`")];
            for case in Case::ALL {
                row.push(
                    cheapest(
                        &self.results,
                        case,
                        id,
                        ErrorKind::Solver,
                        SOLVER_ERROR_LEVEL_M,
                    )
                    .map_or("not reached".into(), |r| {
                        format!("{} flops ({})", sig4(r.flops), configuration(r))
                    }),
                );
            }
            t.row(row);
        }
        md += &t.render();
        md += "\n";

        md += &format!("### {number}.5 The thesis's question, with the cost counted\n\n");
        md += "At each budget, the solver whose most accurate configuration within it has the \
               smallest error, among every solver and among the thesis's three approximations \
               (XPBD, Liu 2013, ADMM-PD):\n\n";
        let mut t = MarkdownTable::new(&[
            "case",
            "error",
            "budget (flops)",
            "most accurate, all solvers",
            "most accurate of the thesis's three",
        ]);
        let name = |r: Option<&PointResult>, kind: ErrorKind| {
            r.map_or("none within budget".into(), |r| {
                format!(
                    "`{}` {} ({})",
                    r.point.spec.id,
                    sig4(r.error(kind).unwrap()),
                    configuration(r)
                )
            })
        };
        for case in Case::ALL {
            for (kind, _) in THESIS_VERDICT {
                for budget in BUDGETS {
                    t.row(vec![
                        case.label(),
                        kind.id().into(),
                        sig4(budget),
                        name(
                            most_accurate_within(
                                &self.results,
                                case,
                                kind,
                                budget,
                                &sweep_solvers(),
                            ),
                            kind,
                        ),
                        name(
                            most_accurate_within(&self.results, case, kind, budget, &THESIS_THREE),
                            kind,
                        ),
                    ]);
                }
            }
        }
        md += &t.render();
        md += "\n";
        let [(rest_holds, rest_cells), (physical_holds, physical_cells)] = verdict(&self.results);
        md +=
            &format!(
            "The thesis concludes (§4.4, §5) that ADMM-PD is the best of its three for the rest \
             state and XPBD for the motion. Counted in flops, ADMM-PD is the most accurate of the \
             three for the rest state in {rest_holds} of {rest_cells} (case, budget) cells with \
             a configuration within the budget, and XPBD for the physical error in \
             {physical_holds} of {physical_cells}. The most accuracy per flop in the physical \
             error, over every solver: {}.\n\n",
            Case::ALL
                .into_iter()
                .map(|case| match most_frequent_winner(&self.results, case, ErrorKind::Physical) {
                    Some((ids, n)) if ids.len() == 1 => format!(
                        "on the {}, `{}` (the most accurate at {n} of {} budgets)",
                        case.label(),
                        ids[0],
                        BUDGETS.len()
                    ),
                    Some((ids, n)) => format!(
                        "on the {}, no single solver: {} are each the most accurate at {n} of \
                         {} budgets",
                        case.label(),
                        solver_list(&ids),
                        BUDGETS.len()
                    ),
                    None => format!("on the {}, no solver within the budgets", case.label()),
                })
                .collect::<Vec<_>>()
                .join("; ")
        );

        md += &format!("### {number}.6 Iterations to a tolerance\n\n");
        md += &format!(
            "What the runs to a tolerance took at dt = {dt} s: the mean iterations per step, \
             the share of steps that reached the cap of {TOLERANCE_CAP} unconverged, and the \
             physical error. A tolerance on the change of x stops a slowly contracting iteration \
             (Liu 2013 and ADMM-PD on stiff springs) far from its fixed point, which the error \
             column shows.\n\n",
            dt = full(TOLERANCE_TABLE_DT_S)
        );
        for case in Case::ALL {
            md += &format!("**{}**\n\n", case.label());
            let mut header = vec!["solver".to_string()];
            header.extend(TOLERANCES_M.iter().map(|t| format!("to {} m", full(*t))));
            let mut t = MarkdownTable::new(&header);
            for id in sweep_solvers()
                .into_iter()
                .filter(|id| id.stops_at_tolerance())
            {
                let mut row = vec![format!("`{id}`")];
                for tolerance in TOLERANCES_M {
                    let r = self.of(case).find(|r| {
                        r.point.spec.id == id
                            && r.point.dt_s == TOLERANCE_TABLE_DT_S
                            && r.point.spec.stopping.tolerance_m() == Some(tolerance)
                    });
                    row.push(match r {
                        Some(r) => match (&r.log, r.error(ErrorKind::Physical)) {
                            (Some(log), Some(e)) => format!(
                                "{:.1} it., {} % capped, {} m",
                                r.iterations_mean(),
                                sig4(100.0 * log.capped as f64 / log.steps() as f64),
                                sig4(e)
                            ),
                            _ => "did not finish".into(),
                        },
                        None => "–".into(),
                    });
                }
                t.row(row);
            }
            md += &t.render();
            md += "\n";
        }
        md
    }
}

/// The time step of the section's table of runs to a tolerance, s.
pub const TOLERANCE_TABLE_DT_S: f64 = 0.02;
