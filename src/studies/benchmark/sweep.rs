//! The benchmark's configurations ([`super`], item 4 of its specification): every solver at
//! its fixed iteration counts over time steps that reach the asymptotic regime, the explicit
//! baselines beside them.

use crate::integrators::optimization_integrator::OptimizationIntegrator;
use crate::integrators::stopping::Stopping;
use crate::solvers::registry::{SolverId, SolverSpec};
use crate::solvers::vbd::LocalHessian;
use crate::studies::beyond::{
    grid_settings, own_first_iterate, takes_first_iterate, GridScene, COMPARISON_START,
};
use crate::studies::work_precision::{step_residual_tolerance, Case};

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

/// The sheet's smaller time steps, s, for Newton under Backward Euler only: where its error
/// reaches its order (on the sheet the other solvers stop at 0.01 s).
pub const SHEET_NEWTON_DTS: [f64; 3] = [0.005, 0.002, 0.001];

/// The long runs of `make report-long` on a case ([`super::Benchmark::compute_long`]): on the
/// sheet, every solver but Newton (in [`configurations`] there) at its first setting under
/// Backward Euler at [`SHEET_NEWTON_DTS`], where the sheet's errors reach their order; none on
/// the rope, whose sweep reaches its asymptotic regime within `make report`.
pub fn long_configurations(case: Case) -> Vec<Configuration> {
    if case.scene != GridScene::Sheet {
        return Vec::new();
    }
    solvers()
        .into_iter()
        .filter(|&id| id != SolverId::BackwardEuler)
        .flat_map(|id| {
            let spec = settings(id)[0];
            SHEET_NEWTON_DTS.map(|dt_s| Configuration { case, spec, dt_s })
        })
        .collect()
}

/// Section 12.2's second window on a case (`make report-long`): Newton under Backward Euler
/// at its first setting over the smallest decade of the case's time steps, run over
/// [`super::truth::SECOND_WINDOW_PERIODS`] periods; on the rope only (the sheet's steps stop
/// at 0.01 s, where its Backward Euler error is not yet of order one).
pub fn second_window_configurations(case: Case) -> Vec<Configuration> {
    if case.scene != GridScene::Rope {
        return Vec::new();
    }
    let steps = dts(case);
    let smallest = steps.iter().copied().fold(f64::INFINITY, f64::min);
    let spec = settings(SolverId::BackwardEuler)[0];
    steps
        .iter()
        .filter(|&&dt| dt <= 10.0 * smallest * (1.0 + 1e-9))
        .map(|&dt_s| Configuration { case, spec, dt_s })
        .collect()
}

/// The solvers of the benchmark: every solver of the grid of section 10 but the damped pair
/// (at zero damping they are Backward Euler and ADMM-PD, and the exact motion is undamped),
/// then the explicit baselines.
pub fn solvers() -> Vec<SolverId> {
    crate::studies::beyond::grid_solvers()
        .into_iter()
        .filter(|id| !matches!(id, SolverId::DampedBackwardEuler | SolverId::DampedAdmm))
        .chain(BASELINES)
        .collect()
}

/// An explicit baseline's linear stability limit on `truth`'s case, s: $`h\,\omega_{max} <
/// 2\sqrt2`$ for RK4 and $`< 2`$ for symplectic Euler, $`\omega_{max}`$ the highest natural
/// frequency of the scene linearised at its start ([`super::truth::CaseTruth::stability_limit`]
/// is RK4's); None for the solvers without one.
pub fn stability_limit(id: SolverId, truth: &super::truth::CaseTruth) -> Option<f64> {
    stability_limit_from_rk4(id, truth.stability_limit)
}

/// [`stability_limit`] from RK4's, `rk4_limit_s` (s).
pub fn stability_limit_from_rk4(id: SolverId, rk4_limit_s: f64) -> Option<f64> {
    match id {
        SolverId::Rk4 => Some(rk4_limit_s),
        SolverId::SymplecticEuler => Some(rk4_limit_s / std::f64::consts::SQRT_2),
        _ => None,
    }
}

/// The largest fraction of its stability limit at which an explicit baseline's configuration
/// is recommended (the headline's, section 12.4's): the last tenth is left as margin.
pub const STABILITY_MARGIN: f64 = 0.9;

/// The explicit baselines drawn on every diagram: the tutorial's RK4 and symplectic Euler.
pub const BASELINES: [SolverId; 2] = [SolverId::Rk4, SolverId::SymplecticEuler];

/// The settings of a solver in the benchmark: its grid settings (the thesis's counts for its
/// four solvers), a single one for a baseline, each step (each stage) starting from the
/// inertial prediction ([`one_start`]).
pub fn settings(id: SolverId) -> Vec<SolverSpec> {
    own_start_settings(id).into_iter().map(one_start).collect()
}

/// The settings of [`settings`] at each solver's own start (its paper's, or the thesis
/// reading's: Fast m-s and Newton from $`x_n`$, VBD's adaptive guess).
pub fn own_start_settings(id: SolverId) -> Vec<SolverSpec> {
    grid_settings(id).unwrap_or_else(|| vec![SolverSpec::new(id, 1)])
}

/// `spec` starting every step from the inertial prediction $`y = x_n + h v_n + h^2 M^{-1}
/// f_{ext}`$, the benchmark's one start, where its own start is another (Fast m-s, Newton,
/// VBD); PBD, XPBD and its substeps start there by construction, the explicit baselines do
/// not iterate. Each run measures the start it used ([`super::run::Measurement::start_distance_m`]).
pub fn one_start(mut spec: SolverSpec) -> SolverSpec {
    if has_own_start(spec.id) {
        spec.params.first_iterate = Some(COMPARISON_START);
    }
    spec.params.hessian = newton_hessian(spec.id, spec.params.hessian);
    spec
}

/// Newton's Hessian in the benchmark: projected where Eq. (4)'s matrix is not positive
/// definite (compressed springs under the second-order integrators' large steps), so that its
/// runs complete; the other solvers keep theirs.
pub fn newton_hessian(id: SolverId, own: LocalHessian) -> LocalHessian {
    if id == SolverId::BackwardEuler {
        LocalHessian::Projected
    } else {
        own
    }
}

/// Whether `id`'s own start is not the benchmark's: the solvers of the own-start variant.
pub fn has_own_start(id: SolverId) -> bool {
    takes_first_iterate(id) && own_first_iterate(id).is_some_and(|own| own != COMPARISON_START)
}

/// The own-start variant of a case ([`super`], item 1): every solver whose own start is not
/// the inertial prediction ([`has_own_start`]), at each of its settings under Backward Euler
/// over the case's time steps as [`configurations`] runs them, from its own start; the rope
/// only (on the sheet these runs would add a fifth of the benchmark's budget).
pub fn own_start_configurations(case: Case) -> Vec<Configuration> {
    let mut out = Vec::new();
    if case.scene != GridScene::Rope {
        return out;
    }
    for id in solvers().into_iter().filter(|&id| has_own_start(id)) {
        for (k, mut spec) in own_start_settings(id).into_iter().enumerate() {
            spec.params.hessian = newton_hessian(id, spec.params.hessian);
            for &dt_s in dts(case) {
                if k == 0 || dt_s >= FINE_DT_S {
                    out.push(Configuration { case, spec, dt_s });
                }
            }
        }
    }
    out
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
    if case.scene == GridScene::Sheet {
        let spec = settings(SolverId::BackwardEuler)[0];
        for &dt_s in &SHEET_NEWTON_DTS {
            out.push(Configuration { case, spec, dt_s });
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

/// The solver errors the tolerance points aim at, m: the RMS per node, over the window, of
/// the distance to the same method solved to round-off.
pub const SOLVER_ERROR_TARGETS_M: [f64; 3] = [1e-4, 1e-6, 1e-8];

/// The iteration cap of a tolerance point's steps.
pub const TOLERANCE_CAP: usize = 200;

/// The tolerance points of a case whose window is `window` s: every solver that stops at a
/// tolerance, under the thesis's scheme, aiming at each of [`SOLVER_ERROR_TARGETS_M`] at the
/// time steps where the solver error is measured ([`SOLVER_ERROR_DTS`]), each step stopping at
/// its own residual ([`crate::integrators::stopping::Stopping::Residual`], [`crate::studies::work_precision::step_residual_tolerance`]) or
/// at [`TOLERANCE_CAP`] iterations; not PBD, which has no converged trajectory to measure a
/// solver error against ([`super::truth::Converged`]). None on the stiff sheet: tried there,
/// 52 of its 60 points reached the cap in some step, and they cost 4.0e10 flops, twice every
/// other tolerance point together.
pub fn tolerance_configurations(case: Case, window: f64) -> Vec<Configuration> {
    let mut out = Vec::new();
    if case.scene == GridScene::Sheet && case.stiffness > 1e3 {
        return out;
    }
    let solvers = solvers()
        .into_iter()
        .filter(|id| id.stops_at_tolerance() && *id != SolverId::Pbd);
    for id in solvers {
        for target in SOLVER_ERROR_TARGETS_M {
            for &dt_s in dts(case).iter().filter(|dt| SOLVER_ERROR_DTS.contains(dt)) {
                let spec = SolverSpec {
                    iterations: TOLERANCE_CAP,
                    stopping: Stopping::Residual(step_residual_tolerance(target, dt_s, window)),
                    ..settings(id)[0]
                };
                out.push(Configuration { case, spec, dt_s });
            }
        }
    }
    out
}

/// The solver error a configuration aims at, m, if it is a tolerance point of a case whose
/// window is `window` s.
pub fn solver_error_target(c: &Configuration, window: f64) -> Option<f64> {
    let Stopping::Residual(tolerance) = c.spec.stopping else {
        return None;
    };
    SOLVER_ERROR_TARGETS_M
        .into_iter()
        .find(|&t| step_residual_tolerance(t, c.dt_s, window) == tolerance)
}
