//! The benchmark's result set as rows ([`super`], item 8 of its specification): one row per
//! run with every metric, the content of `report/data/benchmark.csv`, from which the report's
//! chapters beyond the thesis read everything they show.

use super::run::Outcome;
use super::statics::StaticsOutcome;
use super::Benchmark;
use serde::{Deserialize, Serialize};

/// One run of the benchmark: a dynamics run over its case's window, or a statics run to the
/// thesis's stopping rule. Empty fields mean "does not apply" (or "not measured").
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Row {
    /// `dynamics` or `statics`.
    pub kind: String,
    /// `rope` or `sheet`.
    pub scene: String,
    pub stiffness_n_per_m: f64,
    /// The solver's registry id.
    pub solver: String,
    /// Iterations per step (the cap in a tolerance mode).
    pub iterations: usize,
    /// A minimizing solver's optimization integrator; empty for a solver with its own scheme
    /// (the XPBD family, PBD, the explicit baselines).
    pub integrator: String,
    /// How each step's iterations stop: `count`, or `residual` and each step's tolerance, m.
    pub stopping: String,
    /// The first iterate the configuration asks for ([`crate::integrators::first_iterate::FirstIterate::key`]:
    /// the option set, else the solver's own; `inertia-and-acceleration` for PBD and the XPBD
    /// family, which predict by construction); empty for the explicit baselines.
    pub first_iterate: String,
    /// The start the run actually used, measured as it ran: the largest distance of a step's
    /// first iterate from its inertial prediction, m (0 for the inertial start).
    pub start_distance_m: Option<f64>,
    pub dt_s: f64,
    /// The window of a dynamics run, the statics runs' time cap, s.
    pub window_s: f64,
    /// Floating-point operations of the run.
    pub flops: Option<f64>,
    /// An explicit baseline's time step over its linear stability limit on the case
    /// ([`super::sweep::stability_limit`]); empty for the implicit solvers.
    pub dt_over_stability_limit: Option<f64>,
    /// Iterations a step took, on average.
    pub iterations_mean: Option<f64>,
    /// A tolerance point's target solver error, m ([`super::sweep::SOLVER_ERROR_TARGETS_M`]).
    pub solver_error_target_m: Option<f64>,
    /// In a tolerance mode, the fraction of steps that reached the cap without meeting it.
    pub capped_fraction: Option<f64>,
    /// Physical error against the exact motion: RMS over samples and free nodes, largest node
    /// distance, the RMS over the exact motion's RMS amplitude.
    pub physical_rms_m: Option<f64>,
    pub physical_max_m: Option<f64>,
    pub physical_rel: Option<f64>,
    /// The fraction of the solver-error reference's steps that reached its cap (empty
    /// without a reference); above zero the solver error is left empty.
    pub reference_capped_fraction: Option<f64>,
    /// Solver error against the same method with every step solved to round-off.
    pub solver_rms_m: Option<f64>,
    pub solver_max_m: Option<f64>,
    pub solver_rel: Option<f64>,
    /// The lowest mode's period over the exact motion's, minus one.
    pub phase_error: Option<f64>,
    /// The lowest mode's energy lost per period, and the exact motion's.
    pub energy_decay_per_period: Option<f64>,
    pub exact_energy_decay_per_period: Option<f64>,
    /// Statics: whether the thesis's rule stopped the run, when, how far from the exact
    /// equilibrium (RMS over the free nodes), and its peaks and T/2.
    pub at_rest: Option<bool>,
    pub end_time_s: Option<f64>,
    pub rest_error_rms_m: Option<f64>,
    pub peaks: Option<usize>,
    pub half_period_s: Option<f64>,
    /// Why the run stopped early, empty if it did not.
    pub failure: String,
}

/// The first iterate `spec` asks for, by its key: the option set, else its solver's own; the
/// inertial prediction for PBD and the XPBD family; empty without iterations.
fn configured_start(spec: &crate::solvers::registry::SolverSpec) -> String {
    use crate::integrators::first_iterate::FirstIterate;
    use crate::solvers::registry::SolverId;
    let rule = match spec.id {
        SolverId::Pbd | SolverId::Xpbd | SolverId::XpbdSubsteps => {
            Some(FirstIterate::InertialPrediction)
        }
        id if crate::studies::beyond::takes_first_iterate(id) => spec
            .params
            .first_iterate
            .or(crate::studies::beyond::own_first_iterate(id)),
        _ => None,
    };
    rule.map(|r| r.key().to_string()).unwrap_or_default()
}

fn base(kind: &str, c: &super::sweep::Configuration, window_s: f64) -> Row {
    Row {
        kind: kind.into(),
        scene: c.case.scene.id().into(),
        stiffness_n_per_m: c.case.stiffness,
        solver: c.spec.id.id().into(),
        iterations: c.spec.iterations,
        integrator: if c.spec.id.is_minimizing() {
            c.spec.params.integrator.key().into()
        } else {
            String::new()
        },
        stopping: c.spec.stopping.id(),
        first_iterate: configured_start(&c.spec),
        start_distance_m: None,
        dt_s: c.dt_s,
        window_s,
        flops: None,
        dt_over_stability_limit: None,
        iterations_mean: None,
        solver_error_target_m: None,
        capped_fraction: None,
        physical_rms_m: None,
        physical_max_m: None,
        physical_rel: None,
        reference_capped_fraction: None,
        solver_rms_m: None,
        solver_max_m: None,
        solver_rel: None,
        phase_error: None,
        energy_decay_per_period: None,
        exact_energy_decay_per_period: None,
        at_rest: None,
        end_time_s: None,
        rest_error_rms_m: None,
        peaks: None,
        half_period_s: None,
        failure: String::new(),
    }
}

impl Row {
    fn dynamics(o: &Outcome, truth: &super::truth::CaseTruth, exact_decay: Option<f64>) -> Self {
        let window_s = truth.window;
        let mut row = base("dynamics", &o.configuration, window_s);
        row.dt_over_stability_limit = super::sweep::stability_limit(o.configuration.spec.id, truth)
            .map(|limit| o.configuration.dt_s / limit);
        row.solver_error_target_m = super::sweep::solver_error_target(&o.configuration, window_s);
        row.flops = Some(o.flops);
        match &o.measured {
            Ok(m) => {
                row.iterations_mean = Some(m.iterations_mean);
                row.capped_fraction = m.capped_fraction;
                row.start_distance_m = m.start_distance_m;
                row.physical_rms_m = Some(m.physical.rms);
                row.physical_max_m = Some(m.physical.max);
                row.physical_rel = Some(m.physical.relative);
                row.reference_capped_fraction = m.reference_capped_fraction;
                row.solver_rms_m = m.solver.map(|e| e.rms);
                row.solver_max_m = m.solver.map(|e| e.max);
                row.solver_rel = m.solver.map(|e| e.relative);
                row.phase_error = m.phase_error;
                row.energy_decay_per_period = m.energy_decay;
                row.exact_energy_decay_per_period = exact_decay;
            }
            Err(e) => row.failure = e.clone(),
        }
        row
    }

    fn statics(s: &StaticsOutcome) -> Self {
        let mut row = base(
            "statics",
            &s.configuration,
            super::statics::STATICS_MAX_TIME_S,
        );
        match &s.failure {
            Some(e) => row.failure = e.clone(),
            None => {
                row.flops = Some(s.flops);
                row.at_rest = Some(s.at_rest);
                row.end_time_s = Some(s.end_time_s);
                row.rest_error_rms_m = Some(s.rest_error_rms_m);
                row.peaks = Some(s.peaks);
                row.half_period_s = s.half_period_s;
                row.start_distance_m = s.start_distance_m;
            }
        }
        row
    }

    /// Whether the run is under the thesis's scheme: Backward Euler for a minimizing solver,
    /// its own for the others.
    pub fn thesis_scheme(&self) -> bool {
        self.integrator.is_empty() || self.integrator == "backward-euler"
    }

    /// Whether its steps ran their fixed iteration count (the thesis's mode), not to a
    /// tolerance.
    pub fn count_mode(&self) -> bool {
        self.stopping == "count"
    }

    /// Whether the run finished (no divergence).
    pub fn finished(&self) -> bool {
        self.failure.is_empty()
    }
}

impl Benchmark {
    /// Every run as a row: the dynamics runs case by case in the sweep's order, then the
    /// statics runs.
    pub fn rows(&self) -> Vec<Row> {
        // The exact motion's decay once per case, not once per run: its modal fit over the
        // whole window was most of the benchmark's CPU time outside the runs.
        let exact_decays: Vec<Option<f64>> = self
            .truths
            .iter()
            .map(|t| {
                super::metrics::modal_period(&t.exact)
                    .and_then(|p| super::metrics::energy_decay_per_period(&t.exact, p))
            })
            .collect();
        let mut rows: Vec<Row> = self
            .outcomes
            .iter()
            .map(|o| {
                let case = o.configuration.case;
                let i = self
                    .truths
                    .iter()
                    .position(|t| t.case == case)
                    .expect("every run's case has a truth");
                Row::dynamics(o, &self.truths[i], exact_decays[i])
            })
            .collect();
        rows.extend(self.statics.iter().map(Row::statics));
        rows
    }

    /// The own-start variant's runs as rows ([`super::sweep::own_start_configurations`]), the
    /// content of `report/data/benchmark_own_start.csv`.
    pub fn own_start_rows(&self) -> Vec<Row> {
        self.own_start
            .iter()
            .map(|o| {
                let truth = self
                    .truth(o.configuration.case)
                    .expect("every run's case has a truth");
                let exact_decay = super::metrics::modal_period(&truth.exact)
                    .and_then(|p| super::metrics::energy_decay_per_period(&truth.exact, p));
                Row::dynamics(o, truth, exact_decay)
            })
            .collect()
    }
}

/// One case's ground truths, the content of `report/data/benchmark_truths.csv`.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct TruthRow {
    pub scene: String,
    pub stiffness_n_per_m: f64,
    /// The lowest excited mode of the linearised system, rad/s.
    pub linear_omega_rad_per_s: f64,
    /// The lowest mode's period in the exact motion, s.
    pub exact_period_s: f64,
    /// The window, s.
    pub window_s: f64,
    /// RK4's stability limit and the exact motion's step, s.
    pub rk4_stability_limit_s: f64,
    pub rk4_step_s: f64,
    /// The largest node distance between the exact motions at 2h and h, m.
    pub halving_gap_m: f64,
    /// The exact motion's RMS amplitude about the equilibrium (the do-nothing error), m.
    pub amplitude_rms_m: f64,
    /// The lowest mode's energy lost per period in the exact motion.
    pub exact_energy_decay_per_period: Option<f64>,
}

impl Benchmark {
    /// Every case's truths as a row.
    pub fn truth_rows(&self) -> Vec<TruthRow> {
        self.truths
            .iter()
            .map(|t| {
                let period = super::metrics::modal_period(&t.exact);
                TruthRow {
                    scene: t.case.scene.id().into(),
                    stiffness_n_per_m: t.case.stiffness,
                    linear_omega_rad_per_s: t.mode.omega,
                    exact_period_s: period.unwrap_or(f64::NAN),
                    window_s: t.window,
                    rk4_stability_limit_s: t.stability_limit,
                    rk4_step_s: t.h,
                    halving_gap_m: t.halving_gap,
                    amplitude_rms_m: t.amplitude,
                    exact_energy_decay_per_period: period
                        .and_then(|p| super::metrics::energy_decay_per_period(&t.exact, p)),
                }
            })
            .collect()
    }
}

/// One solver-error reference: a converged method at one time step on a case, with whether it
/// converged; the content of `report/data/benchmark_references.csv`.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct ReferenceRow {
    pub scene: String,
    pub stiffness_n_per_m: f64,
    /// [`super::truth::Converged::id`].
    pub method: String,
    pub dt_s: f64,
    /// The fraction of its steps that reached the iteration cap without meeting the residual.
    pub capped_fraction: f64,
    /// The residual it aims at and the largest one a step ended at, m (XPBD's; empty for
    /// Newton's, whose stages converge or fail the run).
    pub target_residual_m: Option<f64>,
    pub largest_end_residual_m: Option<f64>,
}

impl Benchmark {
    /// Every solver-error reference as a row.
    pub fn reference_rows(&self) -> Vec<ReferenceRow> {
        self.solver_truths
            .iter()
            .map(|(case, dt, t)| ReferenceRow {
                scene: case.scene.id().into(),
                stiffness_n_per_m: case.stiffness,
                method: t.method.id(),
                dt_s: *dt,
                capped_fraction: t.capped_fraction,
                target_residual_m: t
                    .largest_end_residual_m
                    .map(|_| super::truth::XPBD_REFERENCE_RESIDUAL_M),
                largest_end_residual_m: t.largest_end_residual_m,
            })
            .collect()
    }
}
