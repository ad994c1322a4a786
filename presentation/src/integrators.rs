//! The optimization-integrators chapter (issue 23): the four integrators side by side on the
//! thesis rope (their measured orders and numerical damping, [`mass_spring_solvers::studies::integrator_study`]) and
//! what each minimizing solver costs per step under each.

use crate::chapter_figure::ChapterFigure;
use crate::data::write_csv;
use crate::format::{full, short, sig, sig4, MarkdownTable};
use crate::output::OutputFile;
use crate::plot::{Axis, Chart, Line, Marker, Panel, Rgb, Series, COLUMN_WIDTH_MM};
use mass_spring_solvers::error::Result;
use mass_spring_solvers::integrators::optimization_integrator::{OptimizationIntegrator, GAMMA};
use mass_spring_solvers::solvers::registry::SolverId;
use mass_spring_solvers::studies::experiments::run_parallel;
use mass_spring_solvers::studies::integrator_study::{
    exact_amplitude_rate, lowest_mode, minimizing_solvers, order_reference, stops_at_residual,
    CostRow, DampingStudy, OrderStudy, COST_CAP, COST_DT, COST_STIFFNESS, COST_TARGETS_M,
    COST_TIME_S, COST_TOLERANCE_M, DAMPING_DT, DAMPING_PERIODS, DAMPING_STIFFNESS,
    MODE_AMPLITUDE_M, ORDER_DTS, ORDER_STIFFNESS, ORDER_TIME_S,
};
use mass_spring_solvers::studies::work_precision::EXACT_STABILITY_FRACTION as REFERENCE_STABILITY_FRACTION;

/// The columns of `data/integrators.csv`.
pub const INTEGRATORS_HEADER: [&str; 4] = ["integrator", "case", "order", "damping_per_period"];

/// The columns of `data/integrator_costs.csv`.
pub const COSTS_HEADER: [&str; 7] = [
    "solver",
    "integrator",
    "target_m",
    "iterations_per_step",
    "flops_per_step",
    "capped_stages",
    "solver_error_m",
];

/// The order study's case in `integrators.csv`.
pub const ORDER_CASE: &str = "rope_k1e3_t1s_order";
/// The damping study's case in `integrators.csv`.
pub const DAMPING_CASE: &str = "rope_k1e6_lowest_mode_dt0.01s";

/// What the chapters before this one say of their tables' runs: the integrator (issue 23,
/// "every table that shows a run says its integrator").
pub const UNDER_BACKWARD_EULER: &str = "Integrator: every minimizing solver in this section's \
     tables runs under Backward Euler, the thesis's (section 13 runs them under the others); PBD, \
     the XPBD family and the tutorial's integrators integrate by their own schemes.";

/// The figure's file stem.
pub const ORDER_FIGURE: &str = "integrator_orders";

/// Everything the chapter shows.
#[derive(Debug, Clone, PartialEq)]
pub struct IntegratorsChapter {
    /// One per integrator, in [`OptimizationIntegrator::ALL`]'s order.
    pub orders: Vec<OrderStudy>,
    /// One per integrator, in the same order.
    pub damping: Vec<DampingStudy>,
    /// Every minimizing solver under every integrator, solvers in registry order: to the
    /// update tolerance, then to each residual target of [`COST_TARGETS_M`] (the solvers that
    /// stop at a residual).
    pub costs: Vec<CostRow>,
}

/// One job of the chapter.
#[derive(Debug, Clone, Copy)]
enum Job {
    Order(OptimizationIntegrator),
    Damping(OptimizationIntegrator),
    Cost(SolverId, OptimizationIntegrator, Option<f64>),
}

/// What a job gives.
enum Outcome {
    Order(OrderStudy),
    Damping(DampingStudy),
    Cost(CostRow),
}

/// The line colour of each integrator (Okabe-Ito).
fn colour(integrator: OptimizationIntegrator) -> Rgb {
    match integrator {
        OptimizationIntegrator::BackwardEuler => Rgb(0, 0, 0),
        OptimizationIntegrator::ImplicitMidpoint => Rgb(0, 114, 178),
        OptimizationIntegrator::Bdf2 => Rgb(230, 159, 0),
        OptimizationIntegrator::TrBdf2 => Rgb(0, 158, 115),
    }
}

fn marker(integrator: OptimizationIntegrator) -> Marker {
    match integrator {
        OptimizationIntegrator::BackwardEuler => Marker::Square,
        OptimizationIntegrator::ImplicitMidpoint => Marker::Circle,
        OptimizationIntegrator::Bdf2 => Marker::Triangle,
        OptimizationIntegrator::TrBdf2 => Marker::Cross,
    }
}

impl IntegratorsChapter {
    /// Runs the studies of [`mass_spring_solvers::studies::integrator_study`], in parallel.
    pub fn compute(progress: &(dyn Fn(usize, usize) + Sync)) -> Result<Self> {
        let exact = order_reference()?;
        let mode = lowest_mode(DAMPING_STIFFNESS)?;
        let exact_rate = exact_amplitude_rate(&mode)?;
        let mut jobs: Vec<Job> = OptimizationIntegrator::ALL
            .into_iter()
            .flat_map(|i| [Job::Order(i), Job::Damping(i)])
            .collect();
        for id in minimizing_solvers() {
            jobs.extend(OptimizationIntegrator::ALL.map(|i| Job::Cost(id, i, None)));
        }
        for target in COST_TARGETS_M {
            for id in minimizing_solvers()
                .into_iter()
                .filter(|&id| stops_at_residual(id))
            {
                jobs.extend(OptimizationIntegrator::ALL.map(|i| Job::Cost(id, i, Some(target))));
            }
        }
        let cost = |job: &Job| match job {
            Job::Order(_) => 10.0,
            Job::Damping(_) => 1.0,
            Job::Cost(..) => 0.5,
        };
        let outcomes = run_parallel(
            &jobs,
            cost,
            |job| -> Result<Outcome> {
                Ok(match *job {
                    Job::Order(i) => Outcome::Order(OrderStudy::compute(i, &exact)?),
                    Job::Damping(i) => {
                        Outcome::Damping(DampingStudy::compute(i, &mode, exact_rate)?)
                    }
                    Job::Cost(id, i, target) => Outcome::Cost(CostRow::compute(id, i, target)?),
                })
            },
            progress,
        );
        let mut chapter = Self {
            orders: Vec::new(),
            damping: Vec::new(),
            costs: Vec::new(),
        };
        for outcome in outcomes {
            match outcome? {
                Outcome::Order(o) => chapter.orders.push(o),
                Outcome::Damping(d) => chapter.damping.push(d),
                Outcome::Cost(c) => chapter.costs.push(c),
            }
        }
        Ok(chapter)
    }

    /// The damping study of `integrator`.
    pub fn damping_of(&self, integrator: OptimizationIntegrator) -> Option<&DampingStudy> {
        self.damping.iter().find(|d| d.integrator == integrator)
    }

    /// How many times less than Backward Euler the most damping second-order scheme damps: the
    /// smallest ratio of Backward Euler's damping per period to a second-order scheme's
    /// (infinite for a scheme that damps nothing).
    pub fn least_damping_ratio(&self) -> Option<f64> {
        let be = self
            .damping_of(OptimizationIntegrator::BackwardEuler)?
            .per_period;
        self.damping
            .iter()
            .filter(|d| d.integrator != OptimizationIntegrator::BackwardEuler)
            .map(|d| be / d.per_period.abs())
            .min_by(f64::total_cmp)
    }

    /// The cost row of `solver` under `integrator`, to the update tolerance (`target` None)
    /// or to the residual for `target`.
    pub fn cost(
        &self,
        solver: SolverId,
        integrator: OptimizationIntegrator,
        target: Option<f64>,
    ) -> Option<&CostRow> {
        self.costs
            .iter()
            .find(|c| c.solver == solver && c.integrator == integrator && c.target_m == target)
    }

    /// The cheapest solver in flops per step under `integrator` among those that met the
    /// solver error `target` ([`CostRow::met`]), with its row.
    pub fn cheapest_at(&self, integrator: OptimizationIntegrator, target: f64) -> Option<&CostRow> {
        self.costs
            .iter()
            .filter(|c| c.integrator == integrator && c.target_m == Some(target) && c.met())
            .min_by(|a, b| a.flops_per_step.total_cmp(&b.flops_per_step))
    }

    /// `data/integrators.csv`: the fitted order of each integrator on the order case, and its
    /// damping per period on the damping case (full precision; the other column empty).
    pub fn integrators_csv(&self) -> String {
        let orders = self.orders.iter().map(|o| {
            vec![
                o.integrator.key().to_string(),
                ORDER_CASE.to_string(),
                full(o.order),
                String::new(),
            ]
        });
        let damping = self.damping.iter().map(|d| {
            vec![
                d.integrator.key().to_string(),
                DAMPING_CASE.to_string(),
                String::new(),
                full(d.per_period),
            ]
        });
        write_csv(&INTEGRATORS_HEADER, orders.chain(damping))
    }

    /// `data/integrator_costs.csv`: every cost row, full precision.
    pub fn costs_csv(&self) -> String {
        write_csv(
            &COSTS_HEADER,
            self.costs.iter().map(|c| {
                vec![
                    c.solver.id().to_string(),
                    c.integrator.key().to_string(),
                    c.target_m.map_or(String::new(), full),
                    full(c.iterations_per_step),
                    full(c.flops_per_step),
                    c.capped.to_string(),
                    full(c.solver_error_m),
                ]
            }),
        )
    }

    /// The order figure: each integrator's error at t = 1 s against dt, log-log.
    pub fn figures(&self) -> Result<Vec<ChapterFigure>> {
        let mut panel = Panel::new(
            Axis::log("time step h (s)"),
            Axis::log("largest node error at t = 1 s (m)"),
        );
        let mut records = Vec::new();
        for o in &self.orders {
            let i = o.integrator;
            for &(dt, e) in &o.errors {
                records.push(vec![i.key().to_string(), full(dt), full(e)]);
            }
            panel.series.push(
                Series::line(
                    format!("{} (fitted order {})", i.label(), sig(o.order, 3)),
                    o.errors.clone(),
                    colour(i),
                )
                .with_marker(marker(i), true)
                .with_line(if i == OptimizationIntegrator::BackwardEuler {
                    Line::Solid
                } else {
                    Line::Dashed
                }),
            );
        }
        // Slope guides from one point below every error at the smallest step: a first-order
        // and a second-order line, to read each integrator's order off its slope.
        let points = || self.orders.iter().flat_map(|o| o.errors.iter().copied());
        let (dt_lo, dt_hi) = points().fold((f64::INFINITY, 0.0f64), |(lo, hi), (dt, _)| {
            (lo.min(dt), hi.max(dt))
        });
        let e_lo = points().map(|(_, e)| e).fold(f64::INFINITY, f64::min) / 3.0;
        if dt_lo < dt_hi && e_lo.is_finite() {
            for (order, line) in [(1, Line::Dotted), (2, Line::Dashed)] {
                let guide = [dt_lo, dt_hi]
                    .map(|dt| (dt, e_lo * (dt / dt_lo).powi(order)))
                    .to_vec();
                panel.series.push(
                    Series::line(format!("slope {order}"), guide, crate::style::GREY)
                        .with_weight(0.6)
                        .with_line(line),
                );
            }
        }
        let csv = write_csv(&["integrator", "dt_s", "error_m"], records);
        Ok(vec![ChapterFigure::new(
            ORDER_FIGURE,
            &Chart::new(COLUMN_WIDTH_MM, 80.0, vec![panel]),
            csv,
        )?])
    }

    /// The cost table of every solver with rows for `target` (None: the update tolerance),
    /// one column per integrator: iterations, flops and solver error per step, "†" where a
    /// target was not met, the capped stages named.
    fn cost_table(&self, target: Option<f64>) -> String {
        let mut header = vec!["solver".to_string()];
        header.extend(
            OptimizationIntegrator::ALL.map(|i| format!("{}: it. / flops / error (m)", i.label())),
        );
        let header: Vec<&str> = header.iter().map(String::as_str).collect();
        let mut t = MarkdownTable::new(&header);
        for id in minimizing_solvers() {
            if OptimizationIntegrator::ALL
                .iter()
                .all(|&i| self.cost(id, i, target).is_none())
            {
                continue;
            }
            let mut row = vec![SolverId::display_name(id).to_string()];
            for i in OptimizationIntegrator::ALL {
                row.push(self.cost(id, i, target).map_or("–".into(), |c| {
                    format!(
                        "{} / {} / {}{}{}",
                        sig(c.iterations_per_step, 3),
                        sig(c.flops_per_step, 3),
                        sig(c.solver_error_m, 2),
                        if c.capped > 0 {
                            format!(" ({} capped)", c.capped)
                        } else {
                            String::new()
                        },
                        if target.is_some() && !c.met() {
                            " †"
                        } else {
                            ""
                        }
                    )
                }));
            }
            t.row(row);
        }
        t.render()
    }

    /// The figure's files, `data/integrators.csv` and `data/integrator_costs.csv`.
    pub fn files(&self, figures: &[ChapterFigure]) -> Vec<OutputFile> {
        let mut files = crate::chapter_figure::chapter_figure_files(figures);
        files.push(OutputFile::text(
            "data/integrators.csv",
            self.integrators_csv(),
        ));
        files.push(OutputFile::text(
            "data/integrator_costs.csv",
            self.costs_csv(),
        ));
        files
    }

    /// The chapter's section of `REPORT.md`, headed `## {number}.`.
    pub fn section(&self, number: u32, figures: &[ChapterFigure]) -> String {
        let mut md = format!(
            "## {number}. Optimization integrators: every minimizing solver under four schemes\n\n"
        );
        md += "Every implicit solver here minimises thesis Eq 20, and Backward Euler fixes its \
               prediction and its weight, with them its first-order numerical damping: the \
               floor every implicit solver lands on in section 12. An optimization integrator \
               (Brown et al. 2018's term) turns each step into one or more stage problems of the \
               same form, minimise ½‖x − ŷ‖²_M + c h² U(x) (+ c h² τ D((x − x_a)/τ) with a \
               dissipation function D, τ = √c h), with every explicit force folded into ŷ, and \
               the solver never knows which integrator asks (`src/integrators/optimization_integrator.rs`: \
               `MinimizingSolver::solve`). Brown et al.'s body is not available here: the stage \
               problems are derived from the standard coefficients of each scheme and \
               transcribed in that module's documentation. Under Backward Euler each solver's \
               stage is its printed step, bit for bit (the thesis's tables run through it).\n\n";
        let mut t = MarkdownTable::new(&[
            "integrator",
            "order",
            "stages per step",
            "c",
            "distinct τ/h (one factorisation each)",
            "notes",
        ]);
        let tau = |i: OptimizationIntegrator| {
            i.stage_steps(1.0)
                .iter()
                .map(|t| sig4(*t))
                .collect::<Vec<_>>()
                .join(", ")
        };
        for (i, stages, c, notes) in [
            (
                OptimizationIntegrator::BackwardEuler,
                "1",
                "1".to_string(),
                "the thesis's scheme",
            ),
            (
                OptimizationIntegrator::ImplicitMidpoint,
                "1",
                "1/4".to_string(),
                "over the midpoint z; x_{n+1} = 2z − x_n; symplectic",
            ),
            (
                OptimizationIntegrator::Bdf2,
                "1",
                "4/9".to_string(),
                "two-step; its first step (and any step from a state it did not produce) is one \
                 TR-BDF2 step, hence its second τ",
            ),
            (
                OptimizationIntegrator::TrBdf2,
                "2",
                format!("γ²/4 = {} (both stages)", sig4(GAMMA * GAMMA / 4.0)),
                "γ = 2 − √2: trapezoid to t + γh, then BDF2 over x_n, x_γ, x_{n+1}",
            ),
        ] {
            t.row(vec![
                i.label().into(),
                i.order().to_string(),
                stages.into(),
                c,
                tau(i),
                notes.into(),
            ]);
        }
        md += &t.render();
        md += "\n";

        md += &format!("### {number}.1 Orders\n\n");
        let order_of = |i| {
            self.orders
                .iter()
                .find(|o| o.integrator == i)
                .map_or("–".to_string(), |o| sig(o.order, 4))
        };
        md += &format!(
            "The positions of the rope at k = {:e} N/m at t = {} s from its start, every stage \
             solved to round-off (Newton, `src/solvers/converged_stage.rs`), against the exact motion \
             (RK4 at {} of its stability limit), as the largest node distance, for h = {} s \
             (Figure I1). The least-squares slopes, against the targets the issue fixed before the run \
             (1 ± 0.1 for Backward Euler, 2 ± 0.1 for the others, \
             `tests/optimization_integrators.rs`), are: Backward Euler {}, implicit midpoint {}, \
             BDF2 {}, TR-BDF2 {}.\n\n",
            ORDER_STIFFNESS,
            short(ORDER_TIME_S),
            full(REFERENCE_STABILITY_FRACTION),
            ORDER_DTS.map(full).join(", "),
            order_of(OptimizationIntegrator::BackwardEuler),
            order_of(OptimizationIntegrator::ImplicitMidpoint),
            order_of(OptimizationIntegrator::Bdf2),
            order_of(OptimizationIntegrator::TrBdf2),
        );
        for f in figures {
            md += &format!(
                "![Figure I1](figures/{stem}.svg)\n\n*Figure I1. The error at t = {} s \
                 of each integrator against its time step, on the k = {:e} N/m rope, stages \
                 solved to round-off; grey, below the points, guides of slope 1 (dotted) and 2 \
                 (dashed).* Data: [`data/{stem}.csv`](data/{stem}.csv).\n\n",
                short(ORDER_TIME_S),
                ORDER_STIFFNESS,
                stem = f.stem
            );
        }

        md += &format!("### {number}.2 Numerical damping\n\n");
        let period = self.damping.first().map_or(f64::NAN, |d| d.period_s);
        md += &format!(
            "The rope at k = {:e} N/m started at rest in its lowest in-plane mode about the exact \
             equilibrium (period {} s, amplitude {} m), {} periods at h = {} s, stages solved \
             to round-off: the amplitude lost per period against the exact undamped motion \
             (RK4 at {} of its limit), from a least-squares fit of the log of the modal \
             amplitude √(q² + (q̇/ω)²) over every step.\n\n",
            DAMPING_STIFFNESS,
            sig4(period),
            short(MODE_AMPLITUDE_M),
            DAMPING_PERIODS,
            short(DAMPING_DT),
            full(REFERENCE_STABILITY_FRACTION),
        );
        let be = self
            .damping_of(OptimizationIntegrator::BackwardEuler)
            .map(|d| d.per_period);
        let mut t = MarkdownTable::new(&[
            "integrator",
            "fitted order",
            "amplitude lost per period",
            "Backward Euler's over it",
        ]);
        for d in &self.damping {
            t.row(vec![
                d.integrator.label().into(),
                order_of(d.integrator),
                sig4(d.per_period),
                be.map_or("–".into(), |be| sig4(be / d.per_period.abs())),
            ]);
        }
        md += &t.render();
        md += &format!(
            "\nBackward Euler takes {} of the mode's amplitude each period; every second-order \
             scheme damps at least {} times less (the issue's bar: 10). The midpoint, symplectic, \
             damps nothing: its value is the residue of the fit, below 1e-4.\n\n",
            be.map_or("–".into(), sig4),
            self.least_damping_ratio().map_or("–".into(), |r| sig(r, 3)),
        );

        md += &format!("### {number}.3 Each minimizing solver's cost per step\n\n");
        md += &format!(
            "Every minimizing solver under every integrator on the rope at k = {:e} N/m, h = {} s, \
             from rest for {} s, each stage run to {:e} m (the stopping test of \
             `src/integrators/stopping.rs`, at most {} iterations): the iterations and the floating-point \
             operations (the cost model of section 12, setup apart) per time step, every stage \
             counted, and the solver error they bought, the largest node distance over the \
             steps to the same integrator's run with its stages solved to round-off. The damped \
             pair runs with Rayleigh damping α = {} 1/s, β = {} s (two of the grid settings of \
             section 10.1) against the damped stages.\n\n",
            COST_STIFFNESS,
            short(COST_DT),
            short(COST_TIME_S),
            COST_TOLERANCE_M,
            COST_CAP,
            short(mass_spring_solvers::studies::beyond::CONVERGENCE_DAMPING.alpha),
            short(mass_spring_solvers::studies::beyond::CONVERGENCE_DAMPING.beta),
        );
        md += &self.cost_table(None);
        let (least, most) = self
            .costs
            .iter()
            .filter(|c| c.target_m.is_none())
            .map(|c| c.solver_error_m)
            .fold((f64::INFINITY, 0.0_f64), |(lo, hi), e| {
                (lo.min(e), hi.max(e))
            });
        md += &format!(
            "\nThe solver errors these costs bought run from {} m to {} m, so a cost per step here \
             is not a cost at matched accuracy: a tolerance on the update is not the same accuracy \
             for every solver.\n\n",
            sig(least, 2),
            sig(most, 2)
        );
        md += &format!(
            "**To at most a solver error ε.** The same runs with every stage stopped at its own \
             residual instead, as section 12.8 stops them, and every solver from one start, the \
             inertial prediction (the runs above start where each solver's own default does: \
             Newton and Fast m-s from x_n, VBD its adaptive guess): for a solver error ε, here the \
             largest node distance over the run (section 12.8's is an RMS, met within 10 ×), each \
             stage's residual at most ε h / T = ε / {} (T = {} s), at most {} iterations; the \
             damped pair has no residual stop (its residual would leave the dissipation out) and \
             is not here. A cell met its target when no stage reached the cap and the solver error \
             it got is at most ε; \"†\" marks one that did not (its cost is not at that \
             accuracy). A cell that met it may be far more accurate than ε: the comparison is of \
             costs to at most ε, not at equal errors.\n\n",
            short(COST_TIME_S / COST_DT),
            short(COST_TIME_S),
            COST_CAP,
        );
        for target in COST_TARGETS_M {
            md += &format!("**ε = {target:e} m**\n\n");
            md += &self.cost_table(Some(target));
            md += "\n";
        }
        let mut t = MarkdownTable::new(
            &std::iter::once("integrator".to_string())
                .chain(COST_TARGETS_M.map(|t| {
                    format!("cheapest to at most {t:e} m (flops per step, error reached)")
                }))
                .collect::<Vec<_>>()
                .iter()
                .map(String::as_str)
                .collect::<Vec<_>>(),
        );
        for i in OptimizationIntegrator::ALL {
            let mut row = vec![i.label().to_string()];
            row.extend(COST_TARGETS_M.map(|target| {
                self.cheapest_at(i, target)
                    .map_or("none met it".into(), |c| {
                        format!(
                            "{} ({}, {} m)",
                            SolverId::display_name(c.solver),
                            sig(c.flops_per_step, 3),
                            sig(c.solver_error_m, 2)
                        )
                    })
            }));
            t.row(row);
        }
        let matched: Vec<&CostRow> = self.costs.iter().filter(|c| c.target_m.is_some()).collect();
        md += &format!(
            "{} of the {} cells met their target ({} of {} under Backward Euler); where one did \
             not, a stage residual of ε h / T did not keep that solver's error within ε under that \
             integrator. The rule bounds a step's error by its residual and adds the steps' \
             errors, which holds under Backward Euler; under the second-order integrators a \
             step combines its stages and the previous steps (the midpoint's x_n+1 = 2z − x_n, \
             BDF2's history), which can amplify a stage's error, and no per-integrator factor was \
             fitted here, so those columns compare fewer solvers. ",
            matched.iter().filter(|c| c.met()).count(),
            matched.len(),
            matched
                .iter()
                .filter(|c| c.met() && c.integrator == OptimizationIntegrator::BackwardEuler)
                .count(),
            matched
                .iter()
                .filter(|c| c.integrator == OptimizationIntegrator::BackwardEuler)
                .count()
        );
        md += &format!(
            "The cheapest per step among the solvers that met each target, under each \
             integrator:\n\n{}\nData: [`data/integrator_costs.csv`](data/integrator_costs.csv) \
             (`{}`; `target_m` empty for the update tolerance) and \
             [`data/integrators.csv`](data/integrators.csv) (`{}`).\n\n",
            t.render(),
            COSTS_HEADER.join(","),
            INTEGRATORS_HEADER.join(","),
        );

        md += &format!("### {number}.4 Dissipation functions\n\n");
        md += "The stage objective takes a dissipation function D(x, v) in it, not a force \
               added after the solve (`src/integrators/dissipation.rs`): classical Rayleigh damping, power-law \
               drag D = c|v|^(p+1)/(p+1) with 0 < p < 1 (Newton takes its quadratic \
               majorizer's curvature, since its own Hessian is unbounded at rest and Newton \
               two-cycles there), and a momentum-conserving Rayleigh damping of this crate's own \
               design (Brown et al. announce one whose formulation we cannot read): Rayleigh \
               damping of the springs' rates of stretching only, whose stage term is a spring of \
               the anchor's length, central and so angular-momentum conserving under the \
               implicit midpoint rule. Newton (`damped_backward_euler`) and the damped ADMM-PD \
               (`damped_admm`, the drag a proximal block on the nodes) take all three under \
               every integrator (`--rayleigh-form`, `--drag`, `--drag-exponent`). \
               `tests/optimization_integrators.rs` checks Rayleigh damping in TR-BDF2 against \
               the damped oscillator's closed form (order 2), a mass under drag against its \
               closed-form stopping time and distance (orders 1 and 2 for Backward Euler and \
               TR-BDF2), and a free rotating rope's angular momentum under the midpoint (kept to \
               round-off with the momentum-conserving form, lost with the classical one), each \
               with the case that fails it.\n\n";
        md
    }
}
