//! The benchmark's configurations ([`super`], item 4 of its specification): every solver at
//! its fixed iteration counts over time steps that reach the asymptotic regime, the explicit
//! baselines beside them.

use super::Case;
use crate::beyond::{grid_settings, GridScene};
use crate::optimization_integrator::OptimizationIntegrator;
use crate::registry::{SolverId, SolverSpec};

/// One configuration: a solver with its settings at a time step, on a case.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Configuration {
    pub case: Case,
    pub spec: SolverSpec,
    pub dt_s: f64,
}

/// The time steps of the rope, s: from the thesis's coarsest down to where Backward Euler's
/// physical error falls at its order (first) over at least a decade; the stiff rope's modes of
/// 26-49 rad/s keep its error near doing nothing above 1e-3 s, so its sweep goes a step
/// further.
pub const ROPE_DTS: [f64; 11] = [
    0.1, 0.05, 0.02, 0.01, 0.005, 0.002, 0.001, 5e-4, 2e-4, 1e-4, 5e-5,
];

/// The time steps of a case, s. The rope at k = 1e3 stops at 1e-4 s, where Backward Euler has
/// fallen at its order for a decade; the sheet's stop at 1e-2 s, where its runs fit the budget
/// of `make report` (a sheet step costs about a hundred rope steps: the soft sheet's runs at
/// 5e-3 s alone took 19 s of one core, a third of the benchmark; the stiff sheet's exact
/// motion alone is 170 000 RK4 steps).
pub fn dts(case: Case) -> &'static [f64] {
    match (case.scene, case.stiffness > 1e3) {
        (GridScene::Rope, false) => &ROPE_DTS[..10],
        (GridScene::Rope, true) => &ROPE_DTS,
        (GridScene::Sheet, false) => &ROPE_DTS[..4],
        (GridScene::Sheet, true) => &ROPE_DTS[..4],
    }
}

/// The solvers of the benchmark: every solver of the grid of section 10 but the damped pair
/// (at zero damping they are Backward Euler and ADMM-PD, and the exact motion is undamped),
/// then the explicit baselines.
pub fn solvers() -> Vec<SolverId> {
    crate::beyond::grid_solvers()
        .into_iter()
        .filter(|id| !matches!(id, SolverId::DampedBackwardEuler | SolverId::DampedAdmm))
        .chain(BASELINES)
        .collect()
}

/// The explicit baselines drawn on every diagram: the tutorial's RK4 and symplectic Euler.
pub const BASELINES: [SolverId; 2] = [SolverId::Rk4, SolverId::SymplecticEuler];

/// The settings of a solver in the benchmark: its grid settings (the thesis's counts for its
/// four solvers), a single one for a baseline.
pub fn settings(id: SolverId) -> Vec<SolverSpec> {
    grid_settings(id).unwrap_or_else(|| vec![SolverSpec::new(id, 1)])
}

/// Below this time step only each solver's first setting runs (its fewest iterations): there
/// a step from the inertial prediction has little left to solve, and the dearer settings would
/// cost most of the budget to add points that lie on the same error.
pub const FINE_DT_S: f64 = 1e-3;

/// The time steps at which the solver error is measured (each needs its method's trajectory
/// solved to round-off at that step): the thesis's three.
pub const SOLVER_ERROR_DTS: [f64; 3] = [0.1, 0.01, 0.001];

/// The optimization integrators the benchmark runs besides Backward Euler (the thesis's).
pub const SECOND_ORDER: [OptimizationIntegrator; 3] = [
    OptimizationIntegrator::ImplicitMidpoint,
    OptimizationIntegrator::Bdf2,
    OptimizationIntegrator::TrBdf2,
];

/// Every configuration of a case, solver by solver, setting by setting, time step by time
/// step: every setting at the steps down to [`FINE_DT_S`], the first one below it; then, on
/// the rope, every minimizing solver's first setting under each of [`SECOND_ORDER`] down to
/// [`FINE_DT_S`], and Newton's (the reference's method) over every step of every case (on the
/// sheet only Newton's: the other solvers under three more integrators would double the
/// benchmark's budget).
pub fn configurations(case: Case) -> Vec<Configuration> {
    let mut out = Vec::new();
    for id in solvers() {
        for (k, spec) in settings(id).into_iter().enumerate() {
            for &dt_s in dts(case) {
                if k == 0 || dt_s >= FINE_DT_S {
                    out.push(Configuration { case, spec, dt_s });
                }
            }
        }
    }
    let minimizing = solvers().into_iter().filter(|id| {
        id.is_minimizing() && (case.scene == GridScene::Rope || *id == SolverId::BackwardEuler)
    });
    for id in minimizing {
        for integrator in SECOND_ORDER {
            let mut spec = settings(id)[0];
            spec.params.integrator = integrator;
            for &dt_s in dts(case) {
                if id == SolverId::BackwardEuler || dt_s >= FINE_DT_S {
                    out.push(Configuration { case, spec, dt_s });
                }
            }
        }
    }
    out
}
