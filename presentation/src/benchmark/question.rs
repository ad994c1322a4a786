//! The thesis's question on the benchmark (section 12): the cells of statics and dynamics, the
//! verdict on each conclusion of §4.4 and §5, and the chapter's section.

use super::*;
use crate::chapter_figure::ChapterFigure;
use crate::format::{full, sig, sig4, MarkdownTable};
use mass_spring_solvers::solvers::registry::SolverId;
use mass_spring_solvers::studies::benchmark::rows::Row;
use mass_spring_solvers::studies::benchmark::sweep::{solvers, BASELINES, SECOND_ORDER};
use mass_spring_solvers::studies::benchmark::verdicts::{
    winners, Conclusion, Regime, Verdict, DYNAMICS_LEVELS, STATICS_LEVELS_M, THESIS_THREE, TIE,
};
use mass_spring_solvers::studies::benchmark::Case;
use mass_spring_solvers::studies::beyond::GridScene;

impl BenchmarkChapter {
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

/// `1.2e6 (dt 0.01 s, 20 it.)`.
pub(super) fn cost_cell(row: Option<&Row>) -> String {
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
