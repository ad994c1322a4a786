//! The benchmark's chapter (work and precision, the thesis's first line of future work, §5):
//! every view of [`mass_spring_solvers::studies::benchmark`]'s one result set, read from its rows (the content of
//! `data/benchmark.csv` and `data/benchmark_truths.csv`) and from nothing else.

use crate::benchmark_views::{of_case, BASELINE_GREY, FAMILIES};
use crate::benchmark_wall::WallTiming;
use crate::chapter_figure::ChapterFigure;
use crate::data::CsvFile;
use crate::format::{full, sig, sig4, MarkdownTable};
use crate::output::OutputFile;
use crate::plot::{
    place_clear_labels, Align, Axis, Chart, Label, Line, Marker, Panel, Rgb, Series, FULL_WIDTH_MM,
};
use crate::style::{colour, family_marker, solver_line};
use mass_spring_solvers::error::Result;
use mass_spring_solvers::integrators::optimization_integrator::OptimizationIntegrator;
use mass_spring_solvers::solvers::registry::SolverId;
use mass_spring_solvers::studies::benchmark::rows::{Row, TruthRow};
use mass_spring_solvers::studies::benchmark::sweep::{solvers, BASELINES, SECOND_ORDER};
use mass_spring_solvers::studies::benchmark::verdicts::{
    winners, Conclusion, Regime, Verdict, DYNAMICS_LEVELS, STATICS_LEVELS_M, THESIS_THREE, TIE,
};
use mass_spring_solvers::studies::benchmark::{Benchmark, Case};
use mass_spring_solvers::studies::beyond::{kendall_tau, GridScene};

/// The chapter's data: the benchmark's rows.
#[derive(Debug, Clone, PartialEq)]
pub struct BenchmarkChapter {
    pub rows: Vec<Row>,
    pub truths: Vec<TruthRow>,
    /// The committed wall-time measurement of `make timing`, if the repository has one.
    pub wall: Option<WallTiming>,
}

/// A CSV of serialisable rows, written with `csv::Writer` (its header from the fields' names).
pub fn rows_csv<T: serde::Serialize>(rows: &[T]) -> String {
    let mut writer = csv::Writer::from_writer(Vec::new());
    for row in rows {
        writer
            .serialize(row)
            .expect("a row of numbers and words serialises");
    }
    String::from_utf8(writer.into_inner().expect("writing to memory cannot fail"))
        .expect("every field is UTF-8")
}

/// A curve of a work-precision panel: a front and how it is drawn.
struct Curve<'a> {
    label: String,
    rows: Vec<&'a Row>,
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

/// The least-squares slope of $`\log_{10} e`$ against $`\log_{10}\Delta t`$ over `points`
/// (dt, error).
pub fn log_slope(points: &[(f64, f64)]) -> Option<f64> {
    if points.len() < 2 {
        return None;
    }
    let n = points.len() as f64;
    let (mut sx, mut sy, mut sxx, mut sxy) = (0.0, 0.0, 0.0, 0.0);
    for &(x, y) in points {
        let (x, y) = (x.log10(), y.log10());
        sx += x;
        sy += y;
        sxx += x * x;
        sxy += x * y;
    }
    Some((n * sxy - sx * sy) / (n * sxx - sx * sx))
}

impl BenchmarkChapter {
    /// The benchmark of every case.
    pub fn compute(progress: &(dyn Fn(usize, usize) + Sync)) -> Result<Self> {
        Self::compute_cases(&Case::ALL, progress)
    }

    /// The benchmark of `cases` only (the tests run a part).
    pub fn compute_cases(cases: &[Case], progress: &(dyn Fn(usize, usize) + Sync)) -> Result<Self> {
        let benchmark = Benchmark::compute(cases, progress)?;
        Ok(Self {
            rows: benchmark.rows(),
            truths: benchmark.truth_rows(),
            wall: None,
        })
    }

    /// The cases the chapter holds, in [`Case::ALL`]'s order.
    pub fn cases(&self) -> Vec<Case> {
        Case::ALL
            .into_iter()
            .filter(|c| {
                self.truths
                    .iter()
                    .any(|t| of_case(&t.scene, t.stiffness_n_per_m, *c))
            })
            .collect()
    }

    /// The truth of a case.
    pub fn truth(&self, case: Case) -> Option<&TruthRow> {
        self.truths
            .iter()
            .find(|t| of_case(&t.scene, t.stiffness_n_per_m, case))
    }

    /// The finished dynamics rows of a case at fixed iteration counts (the tolerance points
    /// have their own view, [`crate::benchmark_tolerance`]).
    pub fn dynamics(&self, case: Case) -> Vec<&Row> {
        self.rows
            .iter()
            .filter(|r| r.kind == "dynamics" && r.finished() && r.count_mode())
            .filter(|r| of_case(&r.scene, r.stiffness_n_per_m, case))
            .collect()
    }

    /// The statics rows of a case.
    pub fn statics(&self, case: Case) -> Vec<&Row> {
        self.rows
            .iter()
            .filter(|r| r.kind == "statics")
            .filter(|r| of_case(&r.scene, r.stiffness_n_per_m, case))
            .collect()
    }

    /// A solver's work-precision front on a case under the thesis's scheme: the
    /// [`epsilon_front`] of its configurations (every setting and time step) in flops and
    /// relative physical error, cheapest first.
    pub fn front(&self, case: Case, solver: SolverId) -> Vec<&Row> {
        let integrator = if solver.is_minimizing() {
            OptimizationIntegrator::BackwardEuler.key()
        } else {
            ""
        };
        self.front_under(case, solver, integrator)
    }

    /// [`BenchmarkChapter::front`] under an integrator (its key; empty for a solver's own
    /// scheme).
    pub fn front_under(&self, case: Case, solver: SolverId, integrator: &str) -> Vec<&Row> {
        let rows: Vec<&Row> = self
            .dynamics(case)
            .into_iter()
            .filter(|r| r.solver == solver.id() && r.integrator == integrator)
            .filter(|r| r.flops.is_some() && r.physical_rel.is_some())
            .collect();
        let points: Vec<(f64, f64)> = rows
            .iter()
            .map(|r| (r.flops.unwrap(), r.physical_rel.unwrap()))
            .collect();
        epsilon_front(&points, FRONT_EPSILON)
            .into_iter()
            .map(|i| rows[i])
            .collect()
    }

    /// A solver's relative physical error against dt on a case at its first setting, under
    /// the thesis's scheme.
    pub fn convergence(&self, case: Case, solver: SolverId) -> Vec<(f64, f64)> {
        let integrator = if solver.is_minimizing() {
            OptimizationIntegrator::BackwardEuler.key()
        } else {
            ""
        };
        self.convergence_under(case, solver, integrator)
    }

    /// [`BenchmarkChapter::convergence`] under an integrator (its key).
    pub fn convergence_under(
        &self,
        case: Case,
        solver: SolverId,
        integrator: &str,
    ) -> Vec<(f64, f64)> {
        let mut points: Vec<(f64, f64)> = self
            .dynamics(case)
            .into_iter()
            .filter(|r| r.solver == solver.id() && r.iterations == first_setting(solver))
            .filter(|r| r.integrator == integrator)
            .filter_map(|r| Some((r.dt_s, r.physical_rel?)))
            .collect();
        points.sort_by(|a, b| a.0.total_cmp(&b.0));
        points
    }

    /// The fitted slope of a solver's relative physical error over the smallest decade of dt
    /// of a case, with the decade's ends.
    pub fn smallest_decade_slope(&self, case: Case, solver: SolverId) -> Option<(f64, f64, f64)> {
        decade_slope(&self.convergence(case, solver))
    }
}

/// The fitted slope over the smallest decade of dt of (dt, error) points sorted by dt, with
/// the decade's ends.
pub fn decade_slope(points: &[(f64, f64)]) -> Option<(f64, f64, f64)> {
    let smallest = points.first()?.0;
    let decade: Vec<(f64, f64)> = points
        .iter()
        .copied()
        .filter(|(dt, _)| *dt <= 10.0 * smallest * (1.0 + 1e-9))
        .collect();
    Some((log_slope(&decade)?, smallest, decade.last()?.0))
}

impl BenchmarkChapter {
    /// The cheapest configuration of any solver that reaches a relative physical error of
    /// `level` on a case.
    pub fn cheapest_overall(&self, case: Case, level: f64) -> Option<&Row> {
        self.dynamics(case)
            .into_iter()
            .filter(|r| r.physical_rel.is_some_and(|e| e <= level) && r.flops.is_some())
            .min_by(|a, b| a.flops.unwrap().total_cmp(&b.flops.unwrap()))
    }
}

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
fn dt_labels(curves: &[Curve]) -> Vec<Vec<Label>> {
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
        for curve in curves.into_iter().chain(baselines) {
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
            let points: Vec<(f64, f64)> = curve
                .rows
                .iter()
                .map(|r| (r.flops.unwrap(), r.physical_rel.unwrap()))
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
        }
        panel
    }

    /// The figures and the data files.
    pub fn files(&self, figures: &[ChapterFigure]) -> Vec<OutputFile> {
        let mut files: Vec<OutputFile> = figures
            .iter()
            .flat_map(|f| crate::chapter_figure::figure_files(f.stem, &f.svg, &f.csv))
            .collect();
        files.push(OutputFile::text("data/benchmark.csv", rows_csv(&self.rows)));
        files.push(OutputFile::text(
            "data/benchmark_truths.csv",
            rows_csv(&self.truths),
        ));
        files
    }

    /// The rope cells of a regime: (case, level, winners among the thesis's three, costs).
    pub fn thesis_cells(&self, regime: Regime) -> Vec<ThesisCell> {
        let mut cells = Vec::new();
        for case in self
            .cases()
            .into_iter()
            .filter(|c| c.scene == GridScene::Rope)
        {
            let rows = match regime {
                Regime::Dynamics => self.dynamics(case),
                Regime::Statics => self.statics(case),
            };
            for &level in regime.levels() {
                let (winners, costs) = winners(&rows, regime, level, &THESIS_THREE);
                cells.push(ThesisCell {
                    case,
                    regime,
                    level,
                    winners,
                    costs,
                });
            }
        }
        cells
    }

    /// Each of the thesis's conclusions decided from its regimes' rope cells.
    pub fn verdicts(&self) -> Vec<(Conclusion, Verdict)> {
        Conclusion::ALL
            .into_iter()
            .map(|c| {
                let cells: Vec<Vec<SolverId>> = c
                    .regimes()
                    .iter()
                    .flat_map(|&r| self.thesis_cells(r))
                    .map(|cell| cell.winners)
                    .collect();
                (c, c.decide(&cells))
            })
            .collect()
    }
}

/// A cell of the thesis's question.
#[derive(Debug, Clone, PartialEq)]
pub struct ThesisCell {
    pub case: Case,
    pub regime: Regime,
    pub level: f64,
    pub winners: Vec<SolverId>,
    pub costs: Vec<(SolverId, Option<f64>)>,
}

fn first_setting(solver: SolverId) -> usize {
    mass_spring_solvers::studies::benchmark::sweep::settings(solver)[0].iterations
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

/// `1.2e6 (dt 0.01 s, 20 it.)`.
fn cost_cell(row: Option<&Row>) -> String {
    match row {
        None => "not reached".into(),
        Some(r) => format!(
            "{} (dt {} s, {} it.)",
            sig(r.flops.unwrap_or(f64::NAN), 2),
            full(r.dt_s),
            r.iterations
        ),
    }
}

/// The Spanish text of the thesis's conclusions (§4.4 and §5), with a translation.
pub const THESIS_QUOTES: [(&str, &str, &str); 4] = [
    (
        "§4.4.1",
        "En conclusión, desde una perspectiva estática, donde no importe el desarrollo dinámico la \
         mejor solución siempre vendrá de Projective Dynamics en relación con PBD. Dentro de esta \
         familia de métodos, no existe una gran diferencia.",
        "In conclusion, from a static point of view, where the dynamics do not matter, the best \
         solution will always come from Projective Dynamics rather than PBD. Within this family \
         there is no great difference.",
    ),
    (
        "§4.4.2",
        "En suma, no existe un método que destaque por encima del resto en el comportamiento \
         dinámico. Sí quedan patentes las deficiencias de Fast Simulation of Mass-Spring Systems.",
        "In short, no method stands out above the rest in the dynamic behaviour. The \
         shortcomings of Fast Simulation of Mass-Spring Systems are plain.",
    ),
    (
        "§5",
        "En cuanto a la simulación estática, los algoritmos más favorables han sido los basados en \
         Projective Dynamics, teniendo ADMM preferencia, dada su mayor versatilidad. Al \
         contrario, en las simulaciones dinámicas, no ha habido un claro método que se destaque \
         con respecto a los demás, [...] pero sí que se ha de destacar que Liu ofrece resultados \
         peores que ADMM y XPBD, por lo que se descarta como método viable para el ámbito \
         dinámico.",
        "As for static simulation, the most favourable algorithms have been those based on \
         Projective Dynamics, ADMM being preferred for its greater versatility. In dynamic \
         simulations, on the contrary, no method has clearly stood out from the others, [...] \
         but Liu gives worse results than ADMM and XPBD, so it is ruled out as a viable method \
         for dynamics.",
    ),
    (
        "§5",
        "Por lo tanto, podemos concluir que, dependiendo del tipo de simulación a realizar, los \
         métodos más apropiados serían XPBD para el caso dinámico y ADMM para simulaciones tanto \
         estáticas como dinámicas.",
        "We can therefore conclude that, depending on the kind of simulation, the most suitable \
         methods would be XPBD for dynamics and ADMM for both static and dynamic simulations.",
    ),
];

impl BenchmarkChapter {
    /// The chapter's section of `REPORT.md`, headed `## {number}.`.
    pub fn section(&self, number: u32, figures: &[ChapterFigure]) -> String {
        let mut md = format!(
            "## {number}. The benchmark: work and precision, the timing study the thesis left for later (§5)\n\n"
        );
        md += "One protocol, `mass_spring_solvers::studies::benchmark` (its module documentation is the specification), behind this \
               chapter and the views of sections 10 and 11: the thesis rope and the 10 × 10 sheet, each at \
               k = 1e3 and 1e6 N/m, from the thesis's start; one window per case, three periods of the \
               lowest mode the start excites; every solver at its fixed iteration counts over time steps \
               from 0.1 s down into its asymptotic regime, each step starting from the inertial prediction, \
               under the thesis's Backward Euler and, for every minimizing solver, under the second-order \
               optimization integrators of section 13 (implicit midpoint, BDF2, TR-BDF2; section 12.2); \
               the explicit baselines (RK4, symplectic Euler) on every diagram. Errors are per node over the \
               free nodes: the RMS over samples (every 0.1 s) and free nodes of the distance to the exact \
               motion (**physical**), to the same method with every step solved to round-off (**solver**), \
               each also divided by the exact motion's RMS amplitude about the equilibrium, so that 1 is the \
               error of doing nothing (the equilibrium held still); the lowest mode's **phase error** (its \
               period against the exact motion's) and **amplitude error** (its energy lost per period), the \
               thesis's two dynamic metrics made independent of where a window cuts a run. Cost: counted \
               floating-point operations. Beside the fixed counts, tolerance points ask each iterative \
               solver for a solver error and compare what it achieved (section 12.8). Every number of this chapter and of sections 10-11's benchmark \
               views is in [`data/benchmark.csv`](data/benchmark.csv), one row per run, and \
               [`data/benchmark_truths.csv`](data/benchmark_truths.csv).\n\n";

        md += &format!("### {number}.1 The ground truths\n\n");
        md += "The exact motion is the tutorial's RK4 at a hundredth of its stability limit; its convergence is \
               shown by halving its step from twice that to it (the change bounds the error of the coarser \
               motion; RK4 being of order 4, the exact motion's own is about a fifteenth of it). The window is \
               three periods of the lowest mode as the exact motion swings it (longer than the linear period: \
               the start is far from the equilibrium).\n\n";
        let mut t = MarkdownTable::new(&[
            "case",
            ">linear period (s)",
            ">exact period (s)",
            ">window (s)",
            ">RK4 step (s)",
            ">halving changes it by (m)",
            ">exact amplitude, RMS (m)",
            ">its modal energy lost per period",
        ]);
        for case in self.cases() {
            let tr = self.truth(case).expect("a truth per case");
            t.row(vec![
                case.label(),
                sig4(std::f64::consts::TAU / tr.linear_omega_rad_per_s),
                sig4(tr.exact_period_s),
                full(tr.window_s),
                sig(tr.rk4_step_s, 3),
                sig(tr.halving_gap_m, 2),
                sig4(tr.amplitude_rms_m),
                tr.exact_energy_decay_per_period
                    .map_or("–".into(), |d| sig(d, 2)),
            ]);
        }
        md += &t.render();
        md += "\nThe exact motion loses energy from its lowest mode because the motion is not linear: the mode \
               exchanges it with the others. A run's amplitude error is its loss beside this one.\n\n";

        md += &format!("### {number}.2 The errors converge\n\n");
        let mut t = MarkdownTable::new(&[
            "case",
            "solver",
            ">smallest decade of dt (s)",
            ">fitted slope of the physical error",
            ">relative error at its smallest dt",
        ]);
        for case in self.cases() {
            let mut lines: Vec<(String, Vec<(f64, f64)>)> = vec![
                (
                    "Newton, Backward Euler".into(),
                    self.convergence(case, SolverId::BackwardEuler),
                ),
                (
                    SolverId::SymplecticEuler.info().display_name.into(),
                    self.convergence(case, SolverId::SymplecticEuler),
                ),
            ];
            for integrator in SECOND_ORDER {
                lines.push((
                    format!("Newton, {}", integrator.label()),
                    self.convergence_under(case, SolverId::BackwardEuler, integrator.key()),
                ));
            }
            for (name, points) in lines {
                if let Some((slope, lo, hi)) = decade_slope(&points) {
                    t.row(vec![
                        case.label(),
                        name,
                        format!("{} – {}", full(lo), full(hi)),
                        sig(slope, 3),
                        points.first().map_or("–".into(), |p| sig(p.1, 3)),
                    ]);
                }
            }
        }
        md += &t.render();
        md += "\nBackward Euler is first order: its relative physical error falls in proportion to dt once dt is \
               small beside the periods of the modes that carry the motion (on the stiff rope, modes of 26-49 \
               rad/s hold its error near doing nothing above 1e-3 s).\n\n";

        md += &format!("### {number}.3 Work-precision diagrams\n\n");
        let cited: Vec<String> = self
            .cases()
            .into_iter()
            .zip(1..=figures.len())
            .map(|(case, n)| format!("Figure W{n} the {}", case.label()))
            .collect();
        md += &format!(
            "The work-precision diagrams ({}) show, for each case, what each solver's accuracy \
             costs: a solver whose front lies lower and further left reaches an error for fewer \
             flops.\n\n",
            cited.join("; ")
        );
        for (n, (case, f)) in self.cases().into_iter().zip(figures).enumerate() {
            md += &format!(
                "![Figure W{0}](figures/{stem}.svg)\n\n*Figure W{0}. Work and precision, {label}: each solver's ε-front \
                 (ε = {eps}: a configuration is left out when another of its own costs at most {grow} times \
                 as much with at most {grow} times its error) of the relative physical error against the \
                 counted flops over the window (relative error: the RMS physical error per free node over the \
                 exact motion's RMS amplitude), by family; the numbers beside a front are the time step Δt (s) \
                 of its points at 0.1, 0.01, 0.001 and 0.0001 s, in its colour, where there is room; grey: the explicit baselines (RK4 dashed, \
                 symplectic Euler dotted) and doing nothing (the equilibrium held still, error 1).* Data: \
                 [`data/{stem}.csv`](data/{stem}.csv).\n\n",
                n + 1,
                stem = f.stem,
                label = case.label(),
                eps = full(FRONT_EPSILON),
                grow = full(1.0 + FRONT_EPSILON)
            );
        }

        md += &format!("### {number}.4 The cheapest configuration at each accuracy\n\n");
        md += "Per case and relative physical error, each solver's cheapest configuration that reaches it (flops, \
               then its time step and iterations).\n\n";
        for case in self.cases() {
            let rows = self.dynamics(case);
            let mut t = MarkdownTable::new(&["solver", ">10 %", ">1 %", ">0.1 %"]);
            for id in solvers() {
                let cells: Vec<String> = DYNAMICS_LEVELS
                    .iter()
                    .map(|&level| {
                        cost_cell(
                            rows.iter()
                                .filter(|r| r.solver == id.id())
                                .filter(|r| r.physical_rel.is_some_and(|e| e <= level))
                                .min_by(|a, b| {
                                    a.flops
                                        .unwrap_or(f64::INFINITY)
                                        .total_cmp(&b.flops.unwrap_or(f64::INFINITY))
                                })
                                .copied(),
                        )
                    })
                    .collect();
                let mut cells_row = vec![id.info().display_name.to_string()];
                cells_row.extend(cells);
                t.row(cells_row);
            }
            md += &format!("**{}**\n\n", case.label());
            md += &t.render();
            md += "\n";
        }

        md += &format!("### {number}.5 Statics: the cost of coming to rest\n\n");
        md += &format!(
            "The rope run by the thesis's own rule (the first kinetic-energy peak below 1e-3 J ends the run) \
             at dt = 0.1 and 0.01 s, every setting, up to {} s: the cost to the stop of each solver's \
             cheapest configuration that comes to rest within an RMS distance per free node of the exact \
             equilibrium.\n\n",
            full(mass_spring_solvers::studies::benchmark::statics::STATICS_MAX_TIME_S)
        );
        for case in self
            .cases()
            .into_iter()
            .filter(|c| c.scene == GridScene::Rope)
        {
            let rows = self.statics(case);
            let headers: Vec<String> = STATICS_LEVELS_M
                .iter()
                .map(|l| format!(">within {l:e} m"))
                .collect();
            let mut header = vec!["solver"];
            header.extend(headers.iter().map(String::as_str));
            let mut t = MarkdownTable::new(&header);
            for id in solvers().into_iter().filter(|id| !BASELINES.contains(id)) {
                let mut cells = vec![id.info().display_name.to_string()];
                for &level in &STATICS_LEVELS_M {
                    cells.push(cost_cell(
                        rows.iter()
                            .filter(|r| r.solver == id.id())
                            .filter(|r| Regime::Statics.accuracy(r).is_some_and(|a| a <= level))
                            .min_by(|a, b| {
                                a.flops
                                    .unwrap_or(f64::INFINITY)
                                    .total_cmp(&b.flops.unwrap_or(f64::INFINITY))
                            })
                            .copied(),
                    ));
                }
                t.row(cells);
            }
            md += &format!("**{}**\n\n", case.label());
            md += &t.render();
            md += "\n";
        }

        md += &format!("### {number}.6 The thesis's question, as it asks it\n\n");
        for (where_, es, en) in THESIS_QUOTES {
            md += &format!("> {es} ({where_})\n>\n> *{en}*\n\n");
        }
        md += &format!(
            "Decided on the rope, the thesis's scene, among its three solvers at matched cost: a cell is a \
             stiffness and an accuracy (dynamics: a relative physical error of 10 %, 1 % or 0.1 %; statics: \
             an RMS rest distance of 1e-2, 1e-3 or 1e-4 m per node), its winners the solvers within {} % \
             of the cheapest (ties).\n\n",
            full(100.0 * TIE)
        );
        let mut t = MarkdownTable::new(&["cell", "XPBD", "Fast m-s", "ADMM", "winners"]);
        for regime in [Regime::Statics, Regime::Dynamics] {
            for cell in self.thesis_cells(regime) {
                let level = match regime {
                    Regime::Dynamics => format!("dynamics, {} %", full(100.0 * cell.level)),
                    Regime::Statics => format!("statics, {:e} m", cell.level),
                };
                let mut cells = vec![format!("{}, {level}", cell.case.label())];
                for (_, cost) in &cell.costs {
                    cells.push(cost.map_or("not reached".into(), |c| sig(c, 2)));
                }
                cells.push(if cell.winners.is_empty() {
                    "none reaches it".into()
                } else {
                    cell.winners
                        .iter()
                        .map(|s| s.info().display_name)
                        .collect::<Vec<_>>()
                        .join(", ")
                });
                t.row(cells);
            }
        }
        md += &t.render();
        md += "\n";
        let mut t = MarkdownTable::new(&["conclusion", "verdict", "criterion"]);
        for (c, v) in self.verdicts() {
            t.row(vec![c.label().into(), v.id().into(), c.criterion().into()]);
        }
        md += &t.render();
        md += "\n";
        md +=
            &crate::benchmark_wall::section(&format!("{number}.7"), self.wall.as_ref(), &self.rows);
        md += &crate::benchmark_tolerance::section(&format!("{number}.8"), &self.rows);
        md
    }
}

/// The time steps of the per-solver views of sections 10 and 11: the thesis's.
pub const VIEW_DTS: [f64; 3] = [0.1, 0.01, 0.001];

/// The time step of the views' phase, amplitude and solver-error columns, s.
pub const VIEW_DETAIL_DT: f64 = 0.01;

impl BenchmarkChapter {
    /// The dynamics row of a solver at a setting and time step on a case.
    pub fn row(&self, case: Case, solver: SolverId, iterations: usize, dt_s: f64) -> Option<&Row> {
        self.rows.iter().find(|r| {
            r.kind == "dynamics"
                && r.thesis_scheme()
                && r.count_mode()
                && of_case(&r.scene, r.stiffness_n_per_m, case)
                && r.solver == solver.id()
                && r.iterations == iterations
                && r.dt_s == dt_s
        })
    }

    /// The benchmark on one scene at the thesis's time steps, every solver and setting: the
    /// relative physical error at each of [`VIEW_DTS`], and at [`VIEW_DETAIL_DT`] the phase,
    /// amplitude and solver errors (the views of sections 10.2 and 11.2).
    pub fn scene_view(&self, case: Case) -> MarkdownTable {
        let detail = full(VIEW_DETAIL_DT);
        let headers = [
            "solver".to_string(),
            ">setting".to_string(),
            format!(">error, dt {}", full(VIEW_DTS[0])),
            format!(">error, dt {}", full(VIEW_DTS[1])),
            format!(">error, dt {}", full(VIEW_DTS[2])),
            format!(">phase, dt {detail}"),
            format!(">energy lost per period, dt {detail}"),
            format!(">solver error, dt {detail}"),
        ];
        let header: Vec<&str> = headers.iter().map(String::as_str).collect();
        let mut t = MarkdownTable::new(&header);
        let percent =
            |x: Option<f64>| x.map_or("–".to_string(), |x| format!("{} %", sig(100.0 * x, 2)));
        for id in solvers() {
            for spec in mass_spring_solvers::studies::benchmark::sweep::settings(id) {
                let at = |dt: f64| self.row(case, id, spec.iterations, dt);
                let error = |dt: f64| match at(dt) {
                    None => "–".to_string(),
                    Some(r) if !r.finished() => "diverged".to_string(),
                    Some(r) => percent(r.physical_rel),
                };
                let d = at(VIEW_DETAIL_DT).filter(|r| r.finished());
                t.row(vec![
                    id.info().display_name.into(),
                    mass_spring_solvers::studies::beyond::setting_label(&spec),
                    error(VIEW_DTS[0]),
                    error(VIEW_DTS[1]),
                    error(VIEW_DTS[2]),
                    percent(d.and_then(|r| r.phase_error)),
                    percent(d.and_then(|r| r.energy_decay_per_period)),
                    percent(d.and_then(|r| r.solver_rel)),
                ]);
            }
        }
        t
    }

    /// The view's opening sentence: the window, the truths, the metrics.
    pub fn scene_view_intro(&self, scene: GridScene, number: u32) -> String {
        let windows: Vec<String> = self
            .cases()
            .into_iter()
            .filter(|c| c.scene == scene)
            .filter_map(|c| {
                self.truth(c)
                    .map(|t| format!("{} s at k = {:e} N/m", full(t.window_s), c.stiffness))
            })
            .collect();
        format!(
            "The benchmark of section {number}, this scene's part: every solver, setting and time step of \
             the thesis's grid runs from the thesis's start over the case's window ({}), three periods of \
             the lowest mode. Errors are relative, the RMS per free node of the distance to the exact motion \
             over the exact motion's RMS amplitude (1 is doing nothing); phase error: the lowest mode's \
             period against the exact motion's; energy lost per period: the lowest mode's (the exact \
             motion's own loss is in section {number}.1); solver error: against the same method with every \
             step solved to round-off. Peaks and T/2 are not shown: over a window they count the window, \
             not the solver.\n\n",
            windows.join(", ")
        )
    }
}

/// Resamples of the ranking cells for τ's interval.
pub const BOOTSTRAP_RESAMPLES: usize = 2000;

/// One cell of the rankings' comparison: the solvers ordered by their relative physical error
/// at one stiffness, time step and setting index, on the rope and on the sheet.
#[derive(Debug, Clone, PartialEq)]
pub struct RankingCell {
    pub stiffness: f64,
    pub dt_s: f64,
    pub setting: usize,
    pub rope: Vec<SolverId>,
    pub sheet: Vec<SolverId>,
    pub tau: Option<f64>,
}

/// Errors within this relative spread are the same to round-off: a cell where every solver's
/// error agrees so closely ranks nothing.
pub const ROUND_OFF_SPREAD: f64 = 1e-9;

impl BenchmarkChapter {
    /// The solvers ranked on a case at one time step and setting index, best first; None when
    /// every error agrees to round-off (or fewer than two solvers finished).
    fn ranking(
        &self,
        case: Case,
        dt_s: f64,
        setting: usize,
        ranked: &[SolverId],
    ) -> Option<Vec<SolverId>> {
        let mut errors: Vec<(SolverId, f64)> = ranked
            .iter()
            .filter_map(|&id| {
                let spec = mass_spring_solvers::studies::benchmark::sweep::settings(id)
                    .get(setting)
                    .copied()?;
                let e = self.row(case, id, spec.iterations, dt_s)?.physical_rel?;
                Some((id, e))
            })
            .collect();
        errors.sort_by(|a, b| a.1.total_cmp(&b.1));
        let (lo, hi) = (errors.first()?.1, errors.last()?.1);
        (errors.len() >= 2 && hi - lo > ROUND_OFF_SPREAD * hi)
            .then(|| errors.into_iter().map(|(id, _)| id).collect())
    }

    /// The rope's and the sheet's rankings, cell by cell (stiffness × the thesis's time steps
    /// × the three settings), the solvers with three settings only.
    pub fn rankings(&self) -> Vec<RankingCell> {
        let ranked: Vec<SolverId> = solvers()
            .into_iter()
            .filter(|id| mass_spring_solvers::studies::benchmark::sweep::settings(*id).len() == 3)
            .collect();
        let mut cells = Vec::new();
        for stiffness in mass_spring_solvers::model::scene::THESIS_STIFFNESSES {
            let rope = Case {
                scene: GridScene::Rope,
                stiffness,
            };
            let sheet = Case {
                scene: GridScene::Sheet,
                stiffness,
            };
            for dt_s in VIEW_DTS {
                for setting in 0..3 {
                    if let (Some(r), Some(s)) = (
                        self.ranking(rope, dt_s, setting, &ranked),
                        self.ranking(sheet, dt_s, setting, &ranked),
                    ) {
                        let tau = kendall_tau(&r, &s);
                        cells.push(RankingCell {
                            stiffness,
                            dt_s,
                            setting,
                            rope: r,
                            sheet: s,
                            tau,
                        });
                    }
                }
            }
        }
        cells
    }
}

/// The mean of `taus` and its bootstrap interval (the 2.5 and 97.5 percentiles of the mean
/// over [`BOOTSTRAP_RESAMPLES`] resamples of the cells with replacement, drawn by a fixed
/// xorshift generator so the report is byte-identical).
pub fn mean_with_interval(taus: &[f64]) -> Option<(f64, f64, f64)> {
    if taus.is_empty() {
        return None;
    }
    let mean = |v: &[f64]| v.iter().sum::<f64>() / v.len() as f64;
    let mut state: u64 = 0x9E37_79B9_7F4A_7C15;
    let mut next = || {
        state ^= state << 13;
        state ^= state >> 7;
        state ^= state << 17;
        state
    };
    let mut means: Vec<f64> = (0..BOOTSTRAP_RESAMPLES)
        .map(|_| {
            let sample: Vec<f64> = (0..taus.len())
                .map(|_| taus[(next() % taus.len() as u64) as usize])
                .collect();
            mean(&sample)
        })
        .collect();
    means.sort_by(f64::total_cmp);
    let at = |q: f64| means[((q * (means.len() - 1) as f64).round() as usize).min(means.len() - 1)];
    Some((mean(taus), at(0.025), at(0.975)))
}

#[cfg(test)]
mod tests {
    use super::epsilon_front;

    /// Whether `a` ε-dominates `b`.
    fn dominates(a: (f64, f64), b: (f64, f64), epsilon: f64) -> bool {
        a.0 <= (1.0 + epsilon) * b.0 && a.1 <= (1.0 + epsilon) * b.1
    }

    #[test]
    fn the_epsilon_front_covers_every_point_and_no_point_of_it_dominates_another() {
        // Costs 1 to 12 with a plateau, near-duplicates and points off the front.
        let points = [
            (1.0, 1.0),
            (1.05, 0.5),  // 5 % dearer, twice as good: replaces (1, 1)
            (2.0, 0.49),  // 2 % better only: left out, covered by (1.05, 0.5)
            (3.0, 0.2),   // kept
            (3.2, 0.19),  // 5 % better: left out
            (6.0, 0.05),  // kept
            (5.0, 0.3),   // worse than a cheaper point
            (12.0, 0.01), // kept
        ];
        let front = epsilon_front(&points, 0.1);
        assert_eq!(front, vec![1, 3, 5, 7]);
        for (i, &p) in points.iter().enumerate() {
            if !front.contains(&i) {
                assert!(front.iter().any(|&f| dominates(points[f], p, 0.1)), "{i}");
            }
        }
        for &a in &front {
            for &b in front.iter().filter(|&&b| b != a) {
                assert!(!dominates(points[a], points[b], 0.1), "{a} over {b}");
            }
        }
        // The strict front keeps every improvement, however small (the failing case of the
        // ε-front's purpose: near-duplicates drawn as separate points).
        assert_eq!(epsilon_front(&points, 0.0), vec![0, 1, 2, 3, 4, 5, 7]);
    }
}
