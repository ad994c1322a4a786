//! The optimization integrators measured on the thesis rope (issue 23): their global order,
//! their numerical damping, and what each minimizing solver costs per step under each.
//!
//! Every measure runs the integrator with its stage problems solved to round-off
//! ([`ConvergedNewton`]), so that what is measured is the integrator's error, not a solver's:
//! - **order** ([`OrderStudy`]): the positions at [`ORDER_TIME_S`] of the rope at
//!   [`ORDER_STIFFNESS`] from its start, against the exact motion (RK4 at a hundredth of its
//!   stability limit, the benchmark's exact motion), as the largest node distance, for each time step of
//!   [`ORDER_DTS`] (halved from 4e-3 to 5e-4 s); the order is the least-squares slope of
//!   $`\log e`$ against $`\log h`$ ([`fitted_slope`]);
//! - **numerical damping** ([`DampingStudy`]): the rope at [`DAMPING_STIFFNESS`] started in its
//!   lowest in-plane mode about the exact equilibrium ([`lowest_mode`], amplitude
//!   [`MODE_AMPLITUDE_M`], at rest), run [`DAMPING_PERIODS`] periods at [`DAMPING_DT`]; the
//!   mode's amplitude $`A = \sqrt{q^2 + (\dot q/\omega)^2}`$ ($`q = \phi^\top M(x - x_{eq})`$)
//!   decays at a rate fitted by least squares to $`\log A(t)`$ over every step, and the
//!   damping per period is $`1 - e^{(r - r_{exact}) T}`$ against the same fit on the exact
//!   undamped motion (RK4 at a hundredth of its limit);
//! - **cost per step** ([`CostRow`]): each minimizing solver under each integrator on the rope
//!   at [`COST_STIFFNESS`], [`COST_DT`], every stage run to [`COST_TOLERANCE_M`] (the stopping
//!   test of [`crate::integrators::stopping`], at most [`COST_CAP`] iterations), for [`COST_TIME_S`]; the
//!   iterations and flops ([`crate::studies::work_precision::logged_flops`]) per time step, and the
//!   solver error it bought: the largest node distance to the same integrator's run with the
//!   stages solved to round-off, over every step; and the same **at matched solver error**:
//!   every stage stopped at its own residual ([`crate::integrators::stopping::Stopping::Residual`],
//!   section 12.8's rule [`step_residual_tolerance`]) for each solver error of
//!   [`COST_TARGETS_M`], so that the costs of the solvers that met a target compare like for
//!   like (the damped pair has no residual stop: its residual would leave the dissipation out).

use crate::error::{Error, Result};
use crate::integrators::dissipation::Dissipation;
use crate::integrators::optimization_integrator::{Integrated, OptimizationIntegrator};
use crate::integrators::stopping::Stopping;
use crate::integrators::time_stepper::TimeStepper;
use crate::model::system::{MassSpringSystem, State, Vec3};
use crate::solvers::converged_stage::ConvergedNewton;
use crate::solvers::registry::{SolverId, SolverSpec};
use crate::studies::beyond::{from_comparison_start, GridScene, CONVERGENCE_DAMPING};
use crate::studies::work_precision::{
    flops_setup, logged_flops, rk4_stability_limit, step_residual_tolerance, whole_steps,
    EXACT_STABILITY_FRACTION, SAMPLE_INTERVAL_S,
};

/// The stiffness of the order study, N/m (the issue: the k = 1e3 rope).
pub const ORDER_STIFFNESS: f64 = 1e3;
/// Where the order study compares positions, s.
pub const ORDER_TIME_S: f64 = 1.0;
/// The order study's time steps, s: 4e-3 halved to 5e-4.
pub const ORDER_DTS: [f64; 4] = [4e-3, 2e-3, 1e-3, 5e-4];
/// The stiffness of the damping study, N/m.
pub const DAMPING_STIFFNESS: f64 = 1e6;
/// The damping study's time step, s.
pub const DAMPING_DT: f64 = 0.01;
/// Periods of the lowest mode the damping study runs.
pub const DAMPING_PERIODS: usize = 10;
/// The lowest mode's amplitude at the start, m ($`\phi^\top M\phi = 1`$ kg).
pub const MODE_AMPLITUDE_M: f64 = 1e-3;
/// The cost study's stiffness (N/m), time step (s), window (s), tolerance (m) and cap.
pub const COST_STIFFNESS: f64 = 1e6;
pub const COST_DT: f64 = 1e-2;
pub const COST_TIME_S: f64 = 0.5;
pub const COST_TOLERANCE_M: f64 = 1e-6;
pub const COST_CAP: usize = 5000;
/// The solver errors (the largest node distance over the run, m) the matched-accuracy costs
/// aim at.
pub const COST_TARGETS_M: [f64; 3] = [1e-4, 1e-6, 1e-8];

/// `integrator` with every stage solved to round-off on `system` at `dt`, with `dissipation`.
pub fn exact_stages(
    system: &MassSpringSystem,
    dt: f64,
    integrator: OptimizationIntegrator,
    dissipation: Dissipation,
) -> Result<Integrated> {
    Integrated::new(
        Box::new(ConvergedNewton::new(system, dt, dissipation)?),
        integrator,
    )
}

/// `steps` steps of `stepper` from `state`.
pub fn run_steps(stepper: &mut dyn TimeStepper, mut state: State, steps: u64) -> Result<State> {
    for _ in 0..steps {
        stepper.step(&mut state)?;
    }
    Ok(state)
}

/// The largest node distance between two position sets, m.
pub fn largest_distance(a: &[Vec3], b: &[Vec3]) -> f64 {
    a.iter()
        .zip(b)
        .map(|(a, b)| (a - b).norm())
        .fold(0.0, f64::max)
}

/// The least-squares slope of $`y`$ against $`x`$.
pub fn least_squares_slope(points: &[(f64, f64)]) -> f64 {
    let n = points.len() as f64;
    let (mx, my) = points
        .iter()
        .fold((0.0, 0.0), |(a, b), (x, y)| (a + x / n, b + y / n));
    let (sxy, sxx) = points.iter().fold((0.0, 0.0), |(a, b), (x, y)| {
        (a + (x - mx) * (y - my), b + (x - mx) * (x - mx))
    });
    sxy / sxx
}

/// The least-squares slope of $`\log y`$ against $`\log x`$.
pub fn fitted_slope(points: &[(f64, f64)]) -> f64 {
    let logs: Vec<(f64, f64)> = points.iter().map(|(x, y)| (x.ln(), y.ln())).collect();
    least_squares_slope(&logs)
}

/// The exact positions of the order study: the rope at [`ORDER_STIFFNESS`] at
/// [`ORDER_TIME_S`], by RK4 at [`EXACT_STABILITY_FRACTION`] of its limit (the benchmark's
/// exact motion, its step rounded down to divide the benchmark's sample interval).
pub fn order_reference() -> Result<Vec<Vec3>> {
    let system = GridScene::Rope.system(ORDER_STIFFNESS)?;
    let per_sample =
        (SAMPLE_INTERVAL_S / (EXACT_STABILITY_FRACTION * rk4_stability_limit(&system))).ceil();
    let h = SAMPLE_INTERVAL_S / per_sample;
    let steps = whole_steps(ORDER_TIME_S, SAMPLE_INTERVAL_S)? * per_sample as u64;
    let mut rk4 = SolverSpec::new(SolverId::Rk4, 1).build(&system, h)?;
    Ok(run_steps(rk4.as_mut(), system.initial_state(), steps)?.x)
}

/// Builds a stepper for a system and a time step (an integrator with its solver).
pub type StepperFor<'a> = dyn Fn(&MassSpringSystem, f64) -> Result<Box<dyn TimeStepper>> + 'a;

/// An integrator's errors against the exact motion and its fitted order (module doc).
#[derive(Debug, Clone, PartialEq)]
pub struct OrderStudy {
    pub integrator: OptimizationIntegrator,
    /// `(dt, largest node distance at ORDER_TIME_S)`, s and m.
    pub errors: Vec<(f64, f64)>,
    /// The least-squares slope of the errors.
    pub order: f64,
}

impl OrderStudy {
    /// `stepper(dt)`'s errors against `exact` over [`ORDER_DTS`] on the order study's rope.
    pub fn of(
        integrator: OptimizationIntegrator,
        exact: &[Vec3],
        stepper: &StepperFor,
    ) -> Result<Self> {
        let system = GridScene::Rope.system(ORDER_STIFFNESS)?;
        let errors = ORDER_DTS
            .iter()
            .map(|&dt| {
                let mut s = stepper(&system, dt)?;
                let end = run_steps(
                    s.as_mut(),
                    system.initial_state(),
                    whole_steps(ORDER_TIME_S, dt)?,
                )?;
                Ok((dt, largest_distance(&end.x, exact)))
            })
            .collect::<Result<Vec<_>>>()?;
        Ok(Self {
            integrator,
            order: fitted_slope(&errors),
            errors,
        })
    }

    /// `integrator` with exact stages.
    pub fn compute(integrator: OptimizationIntegrator, exact: &[Vec3]) -> Result<Self> {
        Self::of(integrator, exact, &|system, dt| {
            Ok(Box::new(exact_stages(
                system,
                dt,
                integrator,
                Dissipation::NONE,
            )?))
        })
    }
}

/// A mode of the rope linearised about its exact equilibrium.
#[derive(Debug, Clone, PartialEq)]
pub struct Mode {
    /// Angular frequency, rad/s.
    pub omega: f64,
    /// Shape, $`\phi^\top M \phi = 1`$ kg, zero on the fixed nodes.
    pub shape: Vec<Vec3>,
    pub equilibrium: Vec<Vec3>,
}

impl Mode {
    /// $`q = \phi^\top M(x - x_{eq})`$ and $`\dot q = \phi^\top M v`$ of `state`.
    pub fn coordinates(&self, system: &MassSpringSystem, state: &State) -> (f64, f64) {
        system
            .nodes()
            .iter()
            .enumerate()
            .fold((0.0, 0.0), |(q, q_dot), (i, n)| {
                (
                    q + n.mass * self.shape[i].dot(&(state.x[i] - self.equilibrium[i])),
                    q_dot + n.mass * self.shape[i].dot(&state.v[i]),
                )
            })
    }

    /// The mode's amplitude in `state`, $`\sqrt{q^2 + (\dot q/\omega)^2}`$, m·kg^½.
    pub fn amplitude(&self, system: &MassSpringSystem, state: &State) -> f64 {
        let (q, q_dot) = self.coordinates(system, state);
        q.hypot(q_dot / self.omega)
    }

    /// The state at rest at $`x_{eq} + a\,\phi`$.
    pub fn displaced(&self, a: f64) -> State {
        State {
            x: self
                .equilibrium
                .iter()
                .zip(&self.shape)
                .map(|(x, p)| x + a * p)
                .collect(),
            v: vec![Vec3::zeros(); self.shape.len()],
        }
    }
}

/// The lowest in-plane mode (x, y) of the rope at `stiffness` about its exact equilibrium:
/// the smallest eigenpair of $`M^{-1/2}KM^{-1/2}`$ with $`K = -\partial F/\partial x`$ there.
pub fn lowest_mode(stiffness: f64) -> Result<Mode> {
    let system = GridScene::Rope.system(stiffness)?;
    let equilibrium = GridScene::Rope.equilibrium(stiffness)?;
    let jacobian = system.force_jacobian_dense(&equilibrium);
    let free: Vec<usize> = (0..system.len())
        .filter(|&i| !system.nodes()[i].fixed)
        .flat_map(|i| (0..2).map(move |c| 3 * i + c))
        .collect();
    let root_mass = |r: usize| system.nodes()[r / 3].mass.sqrt();
    let k = nalgebra::DMatrix::from_fn(free.len(), free.len(), |r, c| {
        -jacobian[(free[r], free[c])] / (root_mass(free[r]) * root_mass(free[c]))
    });
    let eigen = k.symmetric_eigen();
    let lowest = eigen
        .eigenvalues
        .iter()
        .enumerate()
        .min_by(|a, b| a.1.total_cmp(b.1))
        .map(|(i, _)| i)
        .ok_or_else(|| Error::invalid("stiffness", stiffness, "a rope with a free node"))?;
    let mut shape = vec![Vec3::zeros(); system.len()];
    for (r, &unknown) in free.iter().enumerate() {
        // M^{-1/2} times the unit eigenvector: φᵀMφ = 1.
        shape[unknown / 3][unknown % 3] = eigen.eigenvectors[(r, lowest)] / root_mass(unknown);
    }
    Ok(Mode {
        omega: eigen.eigenvalues[lowest].sqrt(),
        shape,
        equilibrium,
    })
}

/// The least-squares decay rate of `mode`'s amplitude along `steps` steps of `stepper` from
/// `state`, 1/s (negative for a decay).
pub fn amplitude_rate(
    stepper: &mut dyn TimeStepper,
    mode: &Mode,
    mut state: State,
    steps: u64,
) -> Result<f64> {
    let dt = stepper.dt();
    let mut samples = Vec::with_capacity(steps as usize + 1);
    samples.push((0.0, mode.amplitude(stepper.system(), &state).ln()));
    for j in 1..=steps {
        stepper.step(&mut state)?;
        samples.push((j as f64 * dt, mode.amplitude(stepper.system(), &state).ln()));
    }
    Ok(least_squares_slope(&samples))
}

/// An integrator's numerical damping of the rope's lowest mode (module doc).
#[derive(Debug, Clone, PartialEq)]
pub struct DampingStudy {
    pub integrator: OptimizationIntegrator,
    /// The lowest mode's period, s.
    pub period_s: f64,
    /// The amplitude lost per period against the exact motion, a fraction.
    pub per_period: f64,
}

/// The exact motion's amplitude rate on the damping study's mode (RK4 at a hundredth of its
/// stability limit, over the same window), 1/s.
pub fn exact_amplitude_rate(mode: &Mode) -> Result<f64> {
    let system = GridScene::Rope.system(DAMPING_STIFFNESS)?;
    let window = DAMPING_PERIODS as f64 * 2.0 * std::f64::consts::PI / mode.omega;
    let per_step = (DAMPING_DT / (EXACT_STABILITY_FRACTION * rk4_stability_limit(&system))).ceil();
    let h = DAMPING_DT / per_step;
    let mut rk4 = SolverSpec::new(SolverId::Rk4, 1).build(&system, h)?;
    let steps = (window / h).round() as u64;
    amplitude_rate(rk4.as_mut(), mode, mode.displaced(MODE_AMPLITUDE_M), steps)
}

impl DampingStudy {
    /// `stepper` at [`DAMPING_DT`] on `mode`, against `exact_rate`.
    pub fn of(
        integrator: OptimizationIntegrator,
        mode: &Mode,
        exact_rate: f64,
        stepper: &mut dyn TimeStepper,
    ) -> Result<Self> {
        let period_s = 2.0 * std::f64::consts::PI / mode.omega;
        let steps = (DAMPING_PERIODS as f64 * period_s / DAMPING_DT).round() as u64;
        let rate = amplitude_rate(stepper, mode, mode.displaced(MODE_AMPLITUDE_M), steps)?;
        Ok(Self {
            integrator,
            period_s,
            per_period: 1.0 - ((rate - exact_rate) * period_s).exp(),
        })
    }

    /// `integrator` with exact stages.
    pub fn compute(
        integrator: OptimizationIntegrator,
        mode: &Mode,
        exact_rate: f64,
    ) -> Result<Self> {
        let system = GridScene::Rope.system(DAMPING_STIFFNESS)?;
        let mut stepper = exact_stages(&system, DAMPING_DT, integrator, Dissipation::NONE)?;
        Self::of(integrator, mode, exact_rate, &mut stepper)
    }
}

/// What a minimizing solver costs per time step under an integrator (module doc).
#[derive(Debug, Clone, PartialEq)]
pub struct CostRow {
    pub solver: SolverId,
    pub integrator: OptimizationIntegrator,
    /// Iterations (the solver's own unit) per time step, every stage's.
    pub iterations_per_step: f64,
    /// Floating-point operations per time step, setup apart.
    pub flops_per_step: f64,
    /// Stages that reached the cap unconverged.
    pub capped: u64,
    /// The largest node distance to the run with exact stages, m.
    pub solver_error_m: f64,
    /// None: every stage stopped at [`COST_TOLERANCE_M`] on the update; a target ε: every
    /// stage stopped at its residual ε Δt / T ([`step_residual_tolerance`]).
    pub target_m: Option<f64>,
}

impl CostRow {
    /// Whether it met its target: every stage converged and the solver error at most it.
    pub fn met(&self) -> bool {
        self.target_m
            .is_some_and(|t| self.capped == 0 && self.solver_error_m <= t)
    }
}

/// The damped solvers of the cost study (with [`CONVERGENCE_DAMPING`]).
fn is_damped(id: SolverId) -> bool {
    matches!(id, SolverId::DampedBackwardEuler | SolverId::DampedAdmm)
}

/// Whether `id` can stop its stages at a residual (the matched-accuracy costs): every
/// minimizing solver but the damped pair.
pub fn stops_at_residual(id: SolverId) -> bool {
    !is_damped(id)
}

/// The minimizing solvers, in registry order.
pub fn minimizing_solvers() -> Vec<SolverId> {
    SolverId::ALL
        .into_iter()
        .filter(|id| id.is_minimizing())
        .collect()
}

/// The spec of `id` in the cost study: to [`COST_TOLERANCE_M`] on the update from its own
/// start, or with `target` to its residual for that solver error from the comparisons' one
/// start (the inertial prediction, [`from_comparison_start`]), capped at [`COST_CAP`]; the
/// damped solvers with the convergence study's Rayleigh damping.
pub fn cost_spec(
    id: SolverId,
    integrator: OptimizationIntegrator,
    target: Option<f64>,
) -> Result<SolverSpec> {
    let mut spec = match target {
        None => SolverSpec::new(id, COST_CAP).to_tolerance(COST_TOLERANCE_M)?,
        Some(t) => from_comparison_start(SolverSpec {
            stopping: Stopping::residual(step_residual_tolerance(t, COST_DT, COST_TIME_S))?,
            ..SolverSpec::new(id, COST_CAP)
        }),
    };
    spec.params.integrator = integrator;
    if is_damped(id) {
        spec.params.damping = CONVERGENCE_DAMPING;
    }
    Ok(spec)
}

impl CostRow {
    /// `id` under `integrator`, to the update tolerance or, with `target`, to its residual
    /// (module doc).
    pub fn compute(
        id: SolverId,
        integrator: OptimizationIntegrator,
        target: Option<f64>,
    ) -> Result<Self> {
        let system = GridScene::Rope.system(COST_STIFFNESS)?;
        let spec = cost_spec(id, integrator, target)?;
        let steps = whole_steps(COST_TIME_S, COST_DT)?;
        let mut solver = spec.build(&system, COST_DT)?;
        let mut exact = exact_stages(&system, COST_DT, integrator, spec.params.dissipation())?;
        let (mut state, mut oracle) = (system.initial_state(), system.initial_state());
        let mut solver_error_m = 0.0_f64;
        for _ in 0..steps {
            solver.step(&mut state)?;
            exact.step(&mut oracle)?;
            solver_error_m = solver_error_m.max(largest_distance(&state.x, &oracle.x));
        }
        let log = solver
            .iteration_log()
            .cloned()
            .ok_or_else(|| Error::invalid("solver", id, "a solver with iterations"))?;
        let flops = logged_flops(&spec, &system, &log) - flops_setup(&spec, &system);
        Ok(Self {
            solver: id,
            integrator,
            iterations_per_step: log.iterations() as f64 / steps as f64,
            flops_per_step: flops / steps as f64,
            capped: log.capped,
            solver_error_m,
            target_m: target,
        })
    }
}
