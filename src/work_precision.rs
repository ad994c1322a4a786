//! The timing study the thesis left for later (§5, its first line of future work): accuracy
//! against work, as the work-precision diagrams of the SciML benchmarks draw it.
//!
//! **The exact motion.** The undamped motion of a scene from rest over [`WINDOW_S`], by the
//! tutorial's RK4 ([`SolverId::Rk4`] through the registry) at a step a hundredth of its
//! stability limit $`\omega h < 2\sqrt2`$ (with $`\omega`$ the highest natural frequency of the
//! start state, [`rk4_stability_limit`]), kept at the sample times only
//! ($`t_j = j \cdot`$ [`SAMPLE_INTERVAL_S`]). Its convergence is shown by halving the step
//! from twice it to it ([`CaseReference::halving_gap`], `tests/work_precision.rs`): the
//! change bounds the error of the coarser motion, and the error of the finer one is about a
//! fifteenth of it (order 4).
//!
//! **The three errors** of a run at step $`dt`$, each the per-node distance summed (thesis
//! convention 7) with its largest node distance beside it:
//!
//! - physical, $`e_{phys} = \max_j \sum_i |x_i(t_j) - x^{exact}_i(t_j)|`$, the worst sample of
//!   the window;
//! - rest, $`e_{rest} = \sum_i |x_i(T) - x^{eq}_i|`$ at the window's end $`T`$ = [`WINDOW_S`],
//!   against the exact static equilibrium ([`GridScene::equilibrium`]);
//! - solver, $`e_{solv} = \max_j \sum_i |x_i(t_j) - x^{BE}_i(t_j)|`$, against the trajectory of
//!   repeated converged Backward Euler steps ([`converged_step`]) at the same $`dt`$.
//!
//! **The configurations**: each solver at its fixed iteration counts (the thesis's mode) and,
//! for every solver whose steps iterate, run to each of [`TOLERANCES_M`] ([`crate::stopping`]:
//! a step stops at the first iterate that moves no node by more than the tolerance, capped at
//! [`TOLERANCE_CAP`]), over the time steps of [`Case::dts`].
//!
//! **The cost** in floating-point operations, by a model per operation ([`flops_setup`],
//! [`flops_per_step_overhead`], [`flops_of_iteration`], [`flops_of_extra`]), applied to the
//! iterations each step took ([`logged_flops`]): a run costs setup
//! $`+ \sum_{steps}(`$overhead $`+ \sum_{j < m}`$ iteration $`j)`$ with $`m`$ the step's
//! iterations, plus its logged extra work.

use crate::backward_euler::{converged_step, ConvergedStepOptions};
use crate::beyond::{grid_settings, GridScene};
use crate::error::{require_positive, Error, Result};
use crate::experiments::run_parallel;
use crate::linear::SymmetricMatrix;
use crate::local_global::AdmmMerit;
use crate::metrics::{rest_error_max, rest_error_sum};
use crate::registry::{SolverId, SolverSpec};
use crate::solver::TimeStepper;
use crate::stopping::IterationLog;
use crate::system::{MassSpringSystem, State, Vec3};

/// The window of the physical error, s (issue 14: "over the first 5 s").
pub const WINDOW_S: f64 = 5.0;

/// The interval between the samples of the window, s: a multiple of every swept time step.
pub const SAMPLE_INTERVAL_S: f64 = 0.1;

/// The time steps swept, s.
pub const SWEEP_DTS: [f64; 7] = [0.1, 0.05, 0.02, 0.01, 0.005, 0.002, 0.001];

/// The exact motion's step as a fraction of RK4's stability limit.
pub const REFERENCE_STABILITY_FRACTION: f64 = 0.01;

/// A node this far from where it started, m, counts as divergence (the scenes span 9 m).
pub const DIVERGENCE_DISTANCE_M: f64 = 1e3;

/// The physical-error levels of the cheapest-configuration table, m.
pub const ERROR_LEVELS_M: [f64; 3] = [1e-1, 1e-2, 1e-3];

/// The tolerances of the sweep's runs to a tolerance ([`crate::stopping`]), m.
pub const TOLERANCES_M: [f64; 3] = [1e-2, 1e-4, 1e-6];

/// The iteration cap of a step run to a tolerance: above the thesis's largest count (70), and
/// small enough that the capped runs of the slow iterations fit the chapter's budget.
pub const TOLERANCE_CAP: usize = 100;

/// A scene at a stiffness: what one work-precision diagram is drawn for.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Case {
    pub scene: GridScene,
    pub stiffness: f64,
}

impl Case {
    /// The diagrams: the rope and the 10 × 10 sheet at both stiffnesses of the thesis.
    pub const ALL: [Case; 4] = [
        Case {
            scene: GridScene::Rope,
            stiffness: 1e3,
        },
        Case {
            scene: GridScene::Rope,
            stiffness: 1e6,
        },
        Case {
            scene: GridScene::Sheet,
            stiffness: 1e3,
        },
        Case {
            scene: GridScene::Sheet,
            stiffness: 1e6,
        },
    ];

    /// The time steps swept on this case: the soft sheet's stop at 0.005 s and the stiff
    /// sheet's at 0.01 s, where the runs of every solver, its exact motion's 491 000 RK4 steps
    /// and the converged Backward Euler trajectories still fit the chapter's budget.
    pub fn dts(self) -> &'static [f64] {
        match (self.scene, self.stiffness > 1e3) {
            (GridScene::Rope, _) => &SWEEP_DTS,
            (GridScene::Sheet, false) => &SWEEP_DTS[..5],
            (GridScene::Sheet, true) => &SWEEP_DTS[..4],
        }
    }

    /// The time steps of the runs to a tolerance: every other one of [`Case::dts`], from the
    /// coarsest (the tolerance multiplies the configurations by three).
    pub fn tolerance_dts(self) -> impl Iterator<Item = f64> {
        self.dts().iter().copied().step_by(2)
    }

    /// `rope, k = 1e3 N/m`.
    pub fn label(self) -> String {
        format!("{}, k = {:e} N/m", self.scene.id(), self.stiffness)
    }
}

/// The number of samples in the window.
pub fn sample_count() -> usize {
    (WINDOW_S / SAMPLE_INTERVAL_S).round() as usize
}

/// Steps of `dt` between two samples; an error unless `dt` divides [`SAMPLE_INTERVAL_S`].
pub fn steps_per_sample(dt: f64) -> Result<u64> {
    whole_steps(SAMPLE_INTERVAL_S, dt)
}

/// Steps of `dt` in `time` (s); an error unless `dt` is positive and divides it.
pub fn whole_steps(time: f64, dt: f64) -> Result<u64> {
    let dt = require_positive("dt", dt)?;
    let ratio = time / dt;
    if ratio.round() >= 1.0 && (ratio - ratio.round()).abs() < 1e-9 * ratio {
        Ok(ratio.round() as u64)
    } else {
        Err(Error::invalid(
            "dt",
            dt,
            &format!("{time} s divided by a whole number"),
        ))
    }
}

/// The highest natural frequency $`\omega_{max}`$ of `system` linearised at its start, rad/s:
/// the square root of the largest eigenvalue of $`M^{-1/2} K M^{-1/2}`$ over the free nodes,
/// $`K = -\partial f/\partial x`$.
pub fn highest_frequency(system: &MassSpringSystem) -> f64 {
    let x = system.initial_state().x;
    let jacobian = system.force_jacobian_dense(&x);
    let free: Vec<usize> = (0..system.len())
        .filter(|&i| !system.nodes()[i].fixed)
        .flat_map(|i| (0..3).map(move |c| 3 * i + c))
        .collect();
    let scale: Vec<f64> = free
        .iter()
        .map(|&r| 1.0 / system.nodes()[r / 3].mass.sqrt())
        .collect();
    let k = nalgebra::DMatrix::from_fn(free.len(), free.len(), |r, c| {
        -jacobian[(free[r], free[c])] * scale[r] * scale[c]
    });
    let largest = k
        .symmetric_eigenvalues()
        .iter()
        .copied()
        .fold(0.0, f64::max);
    largest.sqrt()
}

/// RK4's stability limit on `system`, s: $`h < 2\sqrt2/\omega_{max}`$.
pub fn rk4_stability_limit(system: &MassSpringSystem) -> f64 {
    2.0 * std::f64::consts::SQRT_2 / highest_frequency(system)
}

/// Runs `solver` from `state` over the window and keeps the positions at every sample time;
/// a non-finite state or a node [`DIVERGENCE_DISTANCE_M`] from its start stops it with
/// [`Error::Diverged`], saying when.
pub fn sample_trajectory(solver: &mut dyn TimeStepper, state: State) -> Result<Vec<Vec<Vec3>>> {
    sample_trajectory_to(solver, state, sample_count())
}

/// [`sample_trajectory`] over the first `samples` samples.
fn sample_trajectory_to(
    solver: &mut dyn TimeStepper,
    mut state: State,
    count: usize,
) -> Result<Vec<Vec<Vec3>>> {
    let dt = solver.dt();
    let per_sample = steps_per_sample(dt)?;
    let start = state.x.clone();
    let mut samples = Vec::with_capacity(count);
    let mut step = 0u64;
    for _ in 0..count {
        for _ in 0..per_sample {
            solver.step(&mut state)?;
            step += 1;
        }
        let far = state
            .x
            .iter()
            .zip(&start)
            .any(|(x, x0)| (x - x0).norm() > DIVERGENCE_DISTANCE_M);
        if !state.is_finite() || far {
            return Err(Error::Diverged {
                solver: solver.name(),
                step,
                time: step as f64 * dt,
                reason: format!(
                    "a node non-finite or more than {DIVERGENCE_DISTANCE_M} m from its start"
                ),
            });
        }
        samples.push(state.x.clone());
    }
    Ok(samples)
}

/// The exact undamped motion of a case, at the sample times.
#[derive(Debug, Clone, PartialEq)]
pub struct ExactMotion {
    pub case: Case,
    /// RK4's step, s.
    pub h: f64,
    /// RK4's stability limit on the case, s.
    pub stability_limit: f64,
    /// The positions at $`t_j = j \cdot`$ [`SAMPLE_INTERVAL_S`], $`j = 1 \dots`$.
    pub samples: Vec<Vec<Vec3>>,
    /// The exact static equilibrium.
    pub equilibrium: Vec<Vec3>,
}

impl ExactMotion {
    /// RK4 at `fraction` of its stability limit, the step rounded down to divide
    /// [`SAMPLE_INTERVAL_S`].
    pub fn compute(case: Case, fraction: f64) -> Result<Self> {
        Self::compute_samples(case, fraction, sample_count())
    }

    /// [`ExactMotion::compute`] over the first `samples` samples of the window only (the
    /// tests check the stiff sheet's convergence over a part of it).
    pub fn compute_samples(case: Case, fraction: f64, samples: usize) -> Result<Self> {
        let fraction = require_positive("fraction", fraction)?;
        if fraction > 1.0 {
            return Err(Error::invalid("fraction", fraction, "(0, 1]"));
        }
        let system = case.scene.system(case.stiffness)?;
        let stability_limit = rk4_stability_limit(&system);
        let per_sample = (SAMPLE_INTERVAL_S / (fraction * stability_limit)).ceil();
        let h = SAMPLE_INTERVAL_S / per_sample;
        let mut rk4 = SolverSpec::new(SolverId::Rk4, 1).build(&system, h)?;
        Ok(Self {
            case,
            h,
            stability_limit,
            samples: sample_trajectory_to(rk4.as_mut(), system.initial_state(), samples)?,
            equilibrium: case.scene.equilibrium(case.stiffness)?,
        })
    }

    /// RK4 steps over its samples.
    pub fn steps(&self) -> u64 {
        (self.samples.len() as f64 * SAMPLE_INTERVAL_S / self.h).round() as u64
    }
}

/// The converged Backward Euler trajectory of `system` at `dt` (repeated [`converged_step`]),
/// at the sample times.
pub fn backward_euler_trajectory(system: &MassSpringSystem, dt: f64) -> Result<Vec<Vec<Vec3>>> {
    let per_sample = steps_per_sample(dt)?;
    let mut state = system.initial_state();
    let mut samples = Vec::with_capacity(sample_count());
    for _ in 0..sample_count() {
        for _ in 0..per_sample {
            state = converged_step(system, &state, dt, ConvergedStepOptions::default())?;
        }
        samples.push(state.x.clone());
    }
    Ok(samples)
}

/// An error over the window: the summed node distance (convention 7) and the largest node
/// distance, each at its worst sample, m.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct WindowError {
    pub sum: f64,
    pub max: f64,
}

impl WindowError {
    /// $`\max_j \sum_i |x_i(t_j) - y_i(t_j)|`$ and $`\max_j \max_i |x_i(t_j) - y_i(t_j)|`$.
    pub fn between(x: &[Vec<Vec3>], y: &[Vec<Vec3>]) -> Self {
        x.iter()
            .zip(y)
            .fold(WindowError { sum: 0.0, max: 0.0 }, |e, (x, y)| {
                WindowError {
                    sum: e.sum.max(rest_error_sum(x, y)),
                    max: e.max.max(rest_error_max(x, y)),
                }
            })
    }

    /// The error of one state (the rest error at the window's end).
    pub fn at(x: &[Vec3], y: &[Vec3]) -> Self {
        WindowError {
            sum: rest_error_sum(x, y),
            max: rest_error_max(x, y),
        }
    }
}

/// The kind of an error, as `work_precision.csv` names it.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum ErrorKind {
    Physical,
    Rest,
    Solver,
}

impl ErrorKind {
    pub const ALL: [ErrorKind; 3] = [ErrorKind::Physical, ErrorKind::Rest, ErrorKind::Solver];

    pub fn id(self) -> &'static str {
        match self {
            ErrorKind::Physical => "physical",
            ErrorKind::Rest => "rest",
            ErrorKind::Solver => "solver",
        }
    }
}

/// One configuration of the sweep: a solver with its iteration count, or its tolerance and
/// cap ([`SolverSpec::stopping`]), at a time step.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Point {
    pub case: Case,
    pub spec: SolverSpec,
    pub dt_s: f64,
}

/// A configuration's outcome.
#[derive(Debug, Clone, PartialEq)]
pub struct PointResult {
    pub point: Point,
    /// Floating-point operations of the whole window: counted from the iterations its steps
    /// took ([`logged_flops`]) for an iterative solver that finished, else the model's
    /// [`run_flops`].
    pub flops: f64,
    /// The iterations its steps took; None for a solver without iterations or a run that
    /// stopped.
    pub log: Option<IterationLog>,
    /// The three errors, or why the run stopped.
    pub errors: std::result::Result<[WindowError; 3], String>,
}

impl PointResult {
    /// The error of `kind` (summed node distance), if the run finished.
    pub fn error(&self, kind: ErrorKind) -> Option<f64> {
        self.errors.as_ref().ok().map(|e| e[kind as usize].sum)
    }

    /// Iterations per step: the mean the log recorded, else the fixed count.
    pub fn iterations_mean(&self) -> f64 {
        self.log
            .as_ref()
            .and_then(IterationLog::mean_iterations)
            .unwrap_or(self.point.spec.iterations as f64)
    }
}

/// The solvers of the sweep: every solver of the grid of section 10 but the damped pair
/// (at zero damping they are Backward Euler and ADMM-PD; the exact motion is undamped).
pub fn sweep_solvers() -> Vec<SolverId> {
    crate::beyond::grid_solvers()
        .into_iter()
        .filter(|id| !matches!(id, SolverId::DampedBackwardEuler | SolverId::DampedAdmm))
        .collect()
}

/// Every configuration of a case: each sweep solver at the iteration counts of its grid
/// settings (the thesis's counts for its four) at every time step of the case and, where its
/// steps can stop at a tolerance, at each of [`TOLERANCES_M`] with the cap [`TOLERANCE_CAP`]
/// at the steps of [`Case::tolerance_dts`].
pub fn sweep_points(case: Case) -> Vec<Point> {
    let mut points = Vec::new();
    for id in sweep_solvers() {
        for spec in grid_settings(id).expect("a grid solver has settings") {
            for &dt_s in case.dts() {
                points.push(Point { case, spec, dt_s });
            }
        }
        if id.stops_at_tolerance() {
            for tolerance in TOLERANCES_M {
                let spec = SolverSpec::new(id, TOLERANCE_CAP)
                    .to_tolerance(tolerance)
                    .expect("the sweep's tolerances are positive");
                for dt_s in case.tolerance_dts() {
                    points.push(Point { case, spec, dt_s });
                }
            }
        }
    }
    points
}

/// The references of one case: the exact motion and the converged Backward Euler trajectory
/// at each swept step.
#[derive(Debug, Clone, PartialEq)]
pub struct CaseReference {
    pub exact: ExactMotion,
    /// The change of the exact motion when RK4's step is halved from $`2h`$ to its $`h`$: an
    /// estimate of the error of the $`2h`$ motion, and so, RK4 being of order 4, about 15
    /// times the error of the exact motion itself (Richardson).
    pub halving_gap: WindowError,
    /// (dt, trajectory) for every dt of [`Case::dts`].
    pub backward_euler: Vec<(f64, Vec<Vec<Vec3>>)>,
}

impl CaseReference {
    pub fn compute(case: Case) -> Result<Self> {
        Ok(references_of(&[case])?.remove(0))
    }
}

/// The references of `cases`, each of its parts a parallel job (in one job the stiff sheet's
/// two exact motions, 14 s of one core, would run in series).
fn references_of(cases: &[Case]) -> Result<Vec<CaseReference>> {
    #[derive(Clone, Copy)]
    enum Part {
        Exact(Case, f64),
        BackwardEuler(Case, f64),
    }
    enum Done {
        Exact(ExactMotion),
        BackwardEuler(Vec<Vec<Vec3>>),
    }
    let mut parts = Vec::new();
    for &case in cases {
        parts.push(Part::Exact(case, REFERENCE_STABILITY_FRACTION));
        parts.push(Part::Exact(case, 2.0 * REFERENCE_STABILITY_FRACTION));
        parts.extend(case.dts().iter().map(|&dt| Part::BackwardEuler(case, dt)));
    }
    // The exact motions first, the stiffer and the finer first; their cost grows as the
    // stability limit shrinks, about as the square root of the stiffness.
    let cost = |part: &Part| match *part {
        Part::Exact(case, fraction) => 1e3 * case.stiffness.sqrt() / fraction,
        Part::BackwardEuler(case, dt) => case.stiffness.sqrt() / dt,
    };
    let done = run_parallel(
        &parts,
        cost,
        |part| -> Result<Done> {
            Ok(match *part {
                Part::Exact(case, fraction) => Done::Exact(ExactMotion::compute(case, fraction)?),
                Part::BackwardEuler(case, dt) => {
                    let system = case.scene.system(case.stiffness)?;
                    Done::BackwardEuler(backward_euler_trajectory(&system, dt)?)
                }
            })
        },
        &|_, _| {},
    );
    let mut done = done.into_iter();
    cases
        .iter()
        .map(|case| {
            let mut next = || done.next().expect("a result per part");
            let (Done::Exact(exact), Done::Exact(doubled)) = (next()?, next()?) else {
                unreachable!("each case's parts start with its two exact motions")
            };
            let backward_euler = case
                .dts()
                .iter()
                .map(|&dt| match next()? {
                    Done::BackwardEuler(trajectory) => Ok((dt, trajectory)),
                    Done::Exact(_) => unreachable!("then a trajectory per time step"),
                })
                .collect::<Result<_>>()?;
            Ok(CaseReference {
                halving_gap: WindowError::between(&exact.samples, &doubled.samples),
                exact,
                backward_euler,
            })
        })
        .collect()
}

/// Runs one configuration and measures its three errors against `reference`.
pub fn run_point(point: &Point, reference: &CaseReference) -> Result<PointResult> {
    let system = point.case.scene.system(point.case.stiffness)?;
    let mut solver = point.spec.build_send(&system, point.dt_s)?;
    let trajectory = sample_trajectory(solver.as_mut(), system.initial_state());
    let log = match (&trajectory, solver.iteration_log()) {
        (Ok(_), Some(log)) => Some(log.clone()),
        _ => None,
    };
    let flops = match &log {
        Some(log) => logged_flops(&point.spec, &system, log),
        None => run_flops(&point.spec, &system, point.dt_s)?,
    };
    let errors = match trajectory {
        Ok(samples) => {
            let be = &reference
                .backward_euler
                .iter()
                .find(|(dt, _)| *dt == point.dt_s)
                .expect("a Backward Euler trajectory at each dt of the case")
                .1;
            let last = samples.last().expect("the window has samples");
            Ok([
                WindowError::between(&samples, &reference.exact.samples),
                WindowError::at(last, &reference.exact.equilibrium),
                WindowError::between(&samples, be),
            ])
        }
        Err(e) => Err(e.to_string()),
    };
    Ok(PointResult {
        point: *point,
        flops,
        log,
        errors,
    })
}

/// The sweep of every case: the references first (one job per case), then every
/// configuration (the dearest first, by [`run_flops`]).
pub fn sweep(
    progress: &(dyn Fn(usize, usize) + Sync),
) -> Result<(Vec<CaseReference>, Vec<PointResult>)> {
    let points: Vec<Point> = Case::ALL.into_iter().flat_map(sweep_points).collect();
    sweep_of(&points, progress)
}

/// [`sweep`] of `points` only, with the references of their cases (the tests run a part).
pub fn sweep_of(
    points: &[Point],
    progress: &(dyn Fn(usize, usize) + Sync),
) -> Result<(Vec<CaseReference>, Vec<PointResult>)> {
    let cases: Vec<Case> = Case::ALL
        .into_iter()
        .filter(|c| points.iter().any(|p| p.case == *c))
        .collect();
    let references = references_of(&cases)?;
    let cost = |p: &Point| {
        p.case
            .scene
            .system(p.case.stiffness)
            .and_then(|s| run_flops(&p.spec, &s, p.dt_s))
            .unwrap_or(0.0)
    };
    let results = run_parallel(
        points,
        cost,
        |p| {
            let i = cases
                .iter()
                .position(|c| *c == p.case)
                .expect("every point's case has a reference");
            run_point(p, &references[i])
        },
        progress,
    )
    .into_iter()
    .collect::<Result<Vec<_>>>()?;
    Ok((references, results))
}

/// The cheapest finished configuration of `id` on `case` whose error of `kind` is at most
/// `level`; None if no configuration reaches it.
pub fn cheapest(
    results: &[PointResult],
    case: Case,
    id: SolverId,
    kind: ErrorKind,
    level: f64,
) -> Option<&PointResult> {
    cheapest_by(
        results
            .iter()
            .filter(|r| r.point.case == case && r.point.spec.id == id),
        |r| r.flops,
        |r| r.error(kind),
        level,
    )
}

/// The configurations of `id` on `case` that no other of its configurations beats in both
/// cost and the error of `kind` (its work-precision curve), cheapest first.
pub fn pareto_front(
    results: &[PointResult],
    case: Case,
    id: SolverId,
    kind: ErrorKind,
) -> Vec<&PointResult> {
    pareto_front_by(
        results
            .iter()
            .filter(|r| r.point.case == case && r.point.spec.id == id),
        |r| r.flops,
        |r| r.error(kind),
    )
}

/// The most accurate finished configuration in the error of `kind` among `solvers` on `case`
/// that costs at most `budget` flops.
pub fn most_accurate_within<'a>(
    results: &'a [PointResult],
    case: Case,
    kind: ErrorKind,
    budget: f64,
    solvers: &[SolverId],
) -> Option<&'a PointResult> {
    most_accurate_within_by(
        results
            .iter()
            .filter(|r| r.point.case == case && solvers.contains(&r.point.spec.id)),
        |r| r.flops,
        |r| r.error(kind),
        budget,
    )
}

/// The cheapest of `rows` by `cost` whose `error` is at most `level` (the first of equal
/// cost); None if none reaches it.
pub fn cheapest_by<'a, T>(
    rows: impl IntoIterator<Item = &'a T>,
    cost: impl Fn(&T) -> f64,
    error: impl Fn(&T) -> Option<f64>,
    level: f64,
) -> Option<&'a T> {
    rows.into_iter()
        .filter(|r| error(r).is_some_and(|e| e <= level))
        .min_by(|a, b| cost(a).total_cmp(&cost(b)))
}

/// The rows that no other beats in both `cost` and `error` (a work-precision curve), cheapest
/// first; rows without an error aside.
pub fn pareto_front_by<'a, T>(
    rows: impl IntoIterator<Item = &'a T>,
    cost: impl Fn(&T) -> f64,
    error: impl Fn(&T) -> Option<f64>,
) -> Vec<&'a T> {
    let mut finished: Vec<(&T, f64)> = rows
        .into_iter()
        .filter_map(|r| error(r).map(|e| (r, e)))
        .collect();
    finished.sort_by(|a, b| cost(a.0).total_cmp(&cost(b.0)).then(a.1.total_cmp(&b.1)));
    let mut front: Vec<(&T, f64)> = Vec::new();
    for (r, e) in finished {
        if front.last().is_none_or(|best| e < best.1) {
            front.push((r, e));
        }
    }
    front.into_iter().map(|(r, _)| r).collect()
}

/// The most accurate of `rows` by `error` whose `cost` is at most `budget` (the cheaper of
/// equal error).
pub fn most_accurate_within_by<'a, T>(
    rows: impl IntoIterator<Item = &'a T>,
    cost: impl Fn(&T) -> f64,
    error: impl Fn(&T) -> Option<f64>,
    budget: f64,
) -> Option<&'a T> {
    rows.into_iter()
        .filter(|r| cost(r) <= budget)
        .filter_map(|r| error(r).map(|e| (r, e)))
        .min_by(|a, b| a.1.total_cmp(&b.1).then(cost(a.0).total_cmp(&cost(b.0))))
        .map(|(r, _)| r)
}

// The flop model. One flop is one addition, subtraction, multiplication, division or square
// root of f64s; copies, comparisons and index arithmetic are free.

/// A spring's elastic force (Eq. 3) added to its two nodes: $`d = x_b - x_a`$ 3,
/// $`|d|`$ 5 + 1 (square root), $`k(|d| - l_0)/|d|`$ 3, times $`d`$ 3, added to both nodes 6.
pub const FLOPS_SPRING_FORCE: f64 = 21.0;

/// A spring's force Jacobian (Eq. 4), a 3 × 3 block:
/// $`k\,(1 - l_0/|d|)\,I + k\,(l_0/|d|)\,\hat d\hat d^\top`$ with $`\hat d`$ from the force's
/// $`d, |d|`$: $`\hat d`$ 3, the two scalars 4, the six distinct products of the outer
/// product 6 and their scaling 6, the diagonal 3.
pub const FLOPS_SPRING_JACOBIAN_BLOCK: f64 = 22.0;

/// The block added into the four blocks of Backward Euler's matrix, 36 more.
pub const FLOPS_SPRING_JACOBIAN: f64 = FLOPS_SPRING_JACOBIAN_BLOCK + 36.0;

/// A spring seen from one node in VBD's vertex step: its force added to that node only
/// ([`FLOPS_SPRING_FORCE`] less 3) and its block subtracted from the node's 3 × 3 Hessian,
/// [`FLOPS_SPRING_JACOBIAN_BLOCK`] + 9.
pub const FLOPS_SPRING_VERTEX_VISIT: f64 =
    FLOPS_SPRING_FORCE - 3.0 + FLOPS_SPRING_JACOBIAN_BLOCK + 9.0;

/// A spring's energy $`\frac k2(|d| - l_0)^2`$: 3 + 6 + 3.
pub const FLOPS_SPRING_ENERGY: f64 = 12.0;

/// One node's terms of the incremental potential (Eq. 20), $`\frac{m}{2h^2}|x - y|^2 - m\,g\cdot
/// x`$: 3 + 5 + 2, and 6 for gravity's.
pub const FLOPS_NODE_POTENTIAL: f64 = 16.0;

/// One spring's term of L-BFGS's potential change between two points
/// ([`crate::quasi_newton::potential_change`]): $`q`$ 3, $`\delta q`$ 9, $`q'`$ 3, the two
/// lengths 12, $`\Delta l = \delta q\cdot(q' + q)/(l' + l)`$ 10, the energy change
/// $`\frac k2\Delta l(\Delta l + 2(l - l_0))`$ 6 and its sum 1.
pub const FLOPS_SPRING_POTENTIAL_CHANGE: f64 = 44.0;

/// One node's term of the same change: the displacement 3, the inertia term
/// $`\frac m2\,\delta\cdot(\delta + 2(x - y))/h^2`$ 3 + 3 + 3 + 5 + 4, gravity's 6, their
/// difference and sum 2.
pub const FLOPS_NODE_POTENTIAL_CHANGE: f64 = 29.0;

/// Liu 2013's local step for one spring, $`d_j = l_0\,(x_b - x_a)/|x_b - x_a|`$:
/// 3 + 6 + 1 (division) + 3.
pub const FLOPS_SPRING_PROJECTION: f64 = 13.0;

/// One spring's term $`k\,J d`$ of the global step's right-hand side: 3 products, added to
/// two nodes, 6.
pub const FLOPS_SPRING_RHS: f64 = 9.0;

/// One spring's constraint projection in PBD and XPBD (Eqs 13-19, 48-51): $`C = |d| - l_0`$
/// 3 + 6 + 1, $`\nabla C = d/|d|`$ 4, the multiplier $`\Delta\lambda = (-C - \tilde\alpha
/// \lambda)/(w_1 + w_2 + \tilde\alpha)`$ 6, the two corrections $`\pm w\,\Delta\lambda\,\nabla
/// C`$ 8 and their addition 6, $`\lambda \mathrel{+}= \Delta\lambda`$ 1. PBD has no
/// $`\lambda`$ and a scale by its stiffness factor instead: the same 36 less 3 plus 1.
pub const FLOPS_CONSTRAINT_PROJECTION: f64 = 36.0;

/// One vertex of VBD: the inertia term's force and Hessian diagonal, $`m/h^2 (x - y)`$,
/// 3 + 3 + 1; the 3 × 3 solve by Cholesky, 3 square roots and 10 for the factor, 12 for the
/// two substitutions; the update 3. (The springs' forces and blocks are counted per visit,
/// [`FLOPS_SPRING_VERTEX_VISIT`], and a Hessian that is not positive definite, factored again
/// after its projection, is not counted.)
pub const FLOPS_VERTEX_SOLVE: f64 = 7.0 + 13.0 + 12.0 + 3.0;

/// The pattern of the matrix a solver factors: unknowns per node (`block`) over the spring
/// graph of every node (fixed nodes included, as [`crate::boundary`] keeps them).
fn spring_graph_matrix(system: &MassSpringSystem, block: usize) -> SymmetricMatrix {
    let edges: Vec<(usize, usize)> = system.springs().iter().map(|s| (s.a, s.b)).collect();
    SymmetricMatrix::from_node_graph(system.len(), block, &edges)
}

/// The non-zeros below the diagonal of the banded $`LDL^\top`$ factor of a matrix of
/// dimension $`n`$ and half-bandwidth $`p`$: $`\sum_i \min(i, p)`$.
pub fn factor_nnz(n: usize, p: usize) -> usize {
    (0..n).map(|i| i.min(p)).sum()
}

/// The crate's banded $`LDL^\top`$ ([`crate::linear::BandedLdlt`]) of dimension $`n`$ and
/// half-bandwidth $`p`$: row $`i`$ takes $`\sum_{m<p}(2m + 1) = p^2`$ for its $`p`$ entries
/// of $`L`$, $`2p`$ for $`d_i`$ and 1 for $`1/d_i`$, on every row (the factor pads the first
/// rows with zeros): $`n\,(p + 1)^2`$.
pub fn flops_factorization(n: usize, p: usize) -> f64 {
    (n * (p + 1) * (p + 1)) as f64
}

/// One solve with that factor for `rhs` right-hand sides: the two triangular solves
/// $`2 \cdot nnz`$ each and the diagonal $`2n`$ (a product by $`1/d_i`$ and a subtraction),
/// per right-hand side.
pub fn flops_solve(n: usize, p: usize, rhs: usize) -> f64 {
    (rhs * (4 * factor_nnz(n, p) + 2 * n)) as f64
}

/// The global solve of Liu 2013 and ADMM-PD: one node-graph matrix, three right-hand sides.
fn flops_global_solve(system: &MassSpringSystem) -> f64 {
    let a = spring_graph_matrix(system, 1);
    flops_solve(a.dim(), a.bandwidth(), 3)
}

/// [`flops_global_solve`]'s factorisation, once per run (dt and the stiffness are fixed).
fn flops_global_factorization(system: &MassSpringSystem) -> f64 {
    let a = spring_graph_matrix(system, 1);
    flops_factorization(a.dim(), a.bandwidth())
}

/// Floating-point operations before the first step: the factorisation of the global matrix
/// for the solvers that prefactor it (Liu 2013, ADMM-PD, their accelerations, L-BFGS), 0 for
/// the others.
pub fn flops_setup(spec: &SolverSpec, system: &MassSpringSystem) -> f64 {
    match spec.id {
        SolverId::FastMassSpring
        | SolverId::AdmmPd
        | SolverId::ChebyshevLiu
        | SolverId::ChebyshevAdmm
        | SolverId::AndersonLiu
        | SolverId::AndersonAdmm
        | SolverId::DampedAdmm
        | SolverId::Lbfgs => flops_global_factorization(system),
        _ => 0.0,
    }
}

/// Floating-point operations of a step outside its iterations, on $`n`$ nodes: the
/// prediction $`y = x + h\,v + h^2 M^{-1} f_{ext}`$, 4 per coordinate, and the velocity
/// $`v = (x - x_n)/h`$, 2 per coordinate, for every solver that iterates on positions; the
/// right-hand side's inertia $`M y/h^2`$, 1 more per coordinate, for the global-solve
/// solvers, and L-BFGS's first gradient ($`s`$ forces + $`4c`$); none for Backward Euler
/// (all inside its Newton iteration); the tutorial's integrators and XPBD's substeps count all
/// their work per iteration.
pub fn flops_per_step_overhead(spec: &SolverSpec, system: &MassSpringSystem) -> f64 {
    let coordinates = 3.0 * system.len() as f64;
    match spec.id {
        SolverId::Lbfgs => {
            7.0 * coordinates
                + system.springs().len() as f64 * FLOPS_SPRING_FORCE
                + 4.0 * coordinates
        }
        SolverId::BackwardEuler | SolverId::DampedBackwardEuler | SolverId::XpbdSubsteps => 0.0,
        SolverId::ExplicitEuler | SolverId::SymplecticEuler | SolverId::Rk4 | SolverId::Rk45 => 0.0,
        SolverId::Pbd | SolverId::Xpbd | SolverId::Vbd => 6.0 * coordinates,
        _ => 7.0 * coordinates,
    }
}

/// Floating-point operations of iteration `j` (from 0) of a step of `spec` on `system`
/// ($`n`$ nodes, $`s`$ springs, $`c = 3n`$ coordinates, $`G`$ the global solve of
/// [`flops_solve`] with three right-hand sides). Anderson's columns and L-BFGS's pairs restart
/// every step, so iteration $`j`$ has $`k = \min(j, m)`$ of them (window $`m`$); every other
/// solver's iterations cost the same:
///
/// | solver | one iteration |
/// |---|---|
/// | Backward Euler (Newton) | $`s`$ (force + Jacobian) + $`9c`$ (the matrix $`M - h^2K`$ and right-hand side) + the factorisation and one solve of the $`c \times c`$ matrix + $`2c`$ (update) |
/// | PBD, XPBD | $`s`$ constraint projections ([`FLOPS_CONSTRAINT_PROJECTION`]) |
/// | XPBD substeps | one XPBD sweep + the prediction and velocity, $`6c`$ |
/// | Liu 2013 | $`s`$ (projection + right-hand side) + $`c`$ + $`G`$ |
/// | ADMM-PD | $`s`$ ($`Dx`$ 3, $`Dx + \bar u`$ 3, projection, $`\bar u \mathrel{+}= Dx - z`$ 6, $`W^2(z - \bar u)`$ 6, right-hand side 6) + $`c`$ + $`G`$ |
/// | Chebyshev | its base's + $`\omega`$ 4 + the extrapolation, 6 per coordinate |
/// | Anderson, $`k`$ columns | its base's + the residual $`c`$ + from the second iteration on the new column (the two differences $`2c`$, its norm $`2c + 1`$ and scaling $`c`$, its Gram row $`2kc`$) + the right-hand side $`2kc`$ + the $`k \times k`$ SVD, $`21k^3`$ (Golub and Van Loan's count with both bases), and its solve $`2k^2`$ + the combination $`2kc + k`$ + the safeguard's merit ($`s`$ spring energies + [`FLOPS_NODE_POTENTIAL`] per node: Liu's incremental potential; ADMM's residual, [`flops_admm_merit`]) |
/// | L-BFGS, $`k`$ pairs | the two-loop recursion $`8kc + 3k`$ and the initial-Hessian solve $`G + c`$ + the slope $`2c`$ + one line-search trial (the point $`2c`$ and the potential's change, [`FLOPS_SPRING_POTENTIAL_CHANGE`] per spring and [`FLOPS_NODE_POTENTIAL_CHANGE`] per node) + the new gradient ($`s`$ forces + $`4c`$) + the new pair $`4c + 1`$ |
/// | VBD | each spring from each of its free nodes ([`FLOPS_SPRING_VERTEX_VISIT`]) + a vertex solve per free node ([`FLOPS_VERTEX_SOLVE`]) |
/// | tutorial integrators | 1, 1 and 4 force evaluations ($`s`$ forces + $`c`$) + 4, 4 and 20 per coordinate |
/// | Dormand-Prince 5(4), a step tried | 6 force evaluations (the seventh is the next step's first) + 42 per coordinate for the stages' sums and 14 for the error estimate |
///
/// An L-BFGS iteration counts one line-search trial; the further trials of a backtracking
/// search, and Anderson's rejected extrapolations, are the solver's logged extra work
/// ([`flops_of_extra`], counted by [`logged_flops`] from the run). An L-BFGS step that ends
/// at a direction below round-off ([`crate::quasi_newton::ROUND_OFF_STEP`]) is logged with
/// that last iteration counted in full (an upper bound by its line search and gradient).
pub fn flops_of_iteration(spec: &SolverSpec, system: &MassSpringSystem, j: usize) -> f64 {
    let n = system.len() as f64;
    let s = system.springs().len() as f64;
    let c = 3.0 * n;
    let forces = s * FLOPS_SPRING_FORCE + c;
    let energy = s * FLOPS_SPRING_ENERGY + n * FLOPS_NODE_POTENTIAL;
    let liu = s * (FLOPS_SPRING_PROJECTION + FLOPS_SPRING_RHS) + c + flops_global_solve(system);
    let admm = s * (3.0 + 3.0 + FLOPS_SPRING_PROJECTION + 6.0 + 6.0 + 6.0)
        + c
        + flops_global_solve(system);
    let anderson = |base: f64, merit: f64| {
        let k = j.min(spec.params.window) as f64;
        let new_column = if j > 0 {
            6.0 * c + 1.0 + 2.0 * k * c
        } else {
            0.0
        };
        base + c
            + new_column
            + 2.0 * k * c
            + 21.0 * k * k * k
            + 2.0 * k * k
            + 2.0 * k * c
            + k
            + merit
    };
    let chebyshev = |base: f64| base + 4.0 + 6.0 * c;
    match spec.id {
        SolverId::BackwardEuler | SolverId::DampedBackwardEuler => {
            let a = spring_graph_matrix(system, 3);
            s * (FLOPS_SPRING_FORCE + FLOPS_SPRING_JACOBIAN)
                + 9.0 * c
                + flops_factorization(a.dim(), a.bandwidth())
                + flops_solve(a.dim(), a.bandwidth(), 1)
                + 2.0 * c
        }
        SolverId::Pbd => s * (FLOPS_CONSTRAINT_PROJECTION - 2.0),
        SolverId::Xpbd => s * FLOPS_CONSTRAINT_PROJECTION,
        SolverId::XpbdSubsteps => s * FLOPS_CONSTRAINT_PROJECTION + 6.0 * c,
        SolverId::FastMassSpring => liu,
        SolverId::AdmmPd | SolverId::DampedAdmm => admm,
        SolverId::ChebyshevLiu => chebyshev(liu),
        SolverId::ChebyshevAdmm => chebyshev(admm),
        SolverId::AndersonLiu => anderson(liu, energy),
        SolverId::AndersonAdmm => anderson(admm, flops_admm_merit(spec, system)),
        SolverId::Lbfgs => {
            let k = j.min(spec.params.history) as f64;
            let direction = 8.0 * k * c + 3.0 * k + flops_global_solve(system) + c;
            let trial =
                2.0 * c + s * FLOPS_SPRING_POTENTIAL_CHANGE + n * FLOPS_NODE_POTENTIAL_CHANGE;
            let gradient = s * FLOPS_SPRING_FORCE + 4.0 * c;
            direction + 2.0 * c + trial + gradient + 4.0 * c + 1.0
        }
        SolverId::Vbd => {
            let free = |i: usize| f64::from(u8::from(!system.nodes()[i].fixed));
            let visits: f64 = system
                .springs()
                .iter()
                .map(|sp| free(sp.a) + free(sp.b))
                .sum();
            let vertices: f64 = (0..system.len()).map(free).sum();
            visits * FLOPS_SPRING_VERTEX_VISIT + vertices * FLOPS_VERTEX_SOLVE
        }
        SolverId::ExplicitEuler | SolverId::SymplecticEuler => forces + 4.0 * c,
        SolverId::Rk4 => 4.0 * forces + 20.0 * c,
        SolverId::Rk45 => 6.0 * forces + 56.0 * c,
    }
}

/// An iteration once the window is full ([`flops_of_iteration`] from iteration $`m`$ on).
pub fn flops_per_iteration(spec: &SolverSpec, system: &MassSpringSystem) -> f64 {
    flops_of_iteration(spec, system, usize::MAX)
}

/// A step: the overhead and each of its iterations.
pub fn flops_per_step(spec: &SolverSpec, system: &MassSpringSystem) -> f64 {
    flops_per_step_overhead(spec, system)
        + (0..spec.iterations)
            .map(|j| flops_of_iteration(spec, system, j))
            .sum::<f64>()
}

/// Floating-point operations of a run of `spec` over the window at `dt`: setup + steps ×
/// [`flops_per_step`].
pub fn run_flops(spec: &SolverSpec, system: &MassSpringSystem, dt: f64) -> Result<f64> {
    let steps = steps_per_sample(dt)? as f64 * sample_count() as f64;
    Ok(flops_setup(spec, system) + steps * flops_per_step(spec, system))
}

/// A node's share of the tolerance test ([`crate::stopping::Convergence::converged`]): the
/// difference 3, its squared norm 5 and the square root 1.
pub const FLOPS_TOLERANCE_TEST_PER_NODE: f64 = 9.0;

/// The merit of one Anderson-ADMM iterate: Zhang et al.'s primal residual
/// $`|W(\bar u^+ - \bar u)|^2`$, 11 per spring (difference 3, weight 3, squared norm 5); or
/// the combined residual, per spring $`Dx^+ - z`$ 6, $`D\,\delta x`$ 3, the two weights 6 and
/// squared norms 10, with the difference $`\delta x`$, $`c`$.
pub fn flops_admm_merit(spec: &SolverSpec, system: &MassSpringSystem) -> f64 {
    let s = system.springs().len() as f64;
    match spec.params.safeguard {
        AdmmMerit::PrimalResidual => 11.0 * s,
        AdmmMerit::CombinedResidual => 25.0 * s + 3.0 * system.len() as f64,
    }
}

/// The work [`IterationLog::extra`] counts, one unit of it: an L-BFGS line-search trial after
/// the first (the trial point and the potential's change, as in [`flops_of_iteration`]); an
/// Anderson extrapolation the safeguard rejected, beyond the logged iterations (whose
/// combinations produced it): for Liu its merit ($`s`$ spring energies and
/// [`FLOPS_NODE_POTENTIAL`] per node); for ADMM with the primal residual the local step and
/// the merit spent on it before the rejection, and no solve; with the combined residual
/// nothing more, the rejected iterate's local step, solve and merit being a logged iteration.
pub fn flops_of_extra(spec: &SolverSpec, system: &MassSpringSystem) -> f64 {
    let n = system.len() as f64;
    let s = system.springs().len() as f64;
    let c = 3.0 * n;
    match spec.id {
        SolverId::Lbfgs => {
            2.0 * c + s * FLOPS_SPRING_POTENTIAL_CHANGE + n * FLOPS_NODE_POTENTIAL_CHANGE
        }
        SolverId::AndersonLiu => s * FLOPS_SPRING_ENERGY + n * FLOPS_NODE_POTENTIAL,
        SolverId::AndersonAdmm => match spec.params.safeguard {
            AdmmMerit::PrimalResidual => {
                s * (12.0 + FLOPS_SPRING_PROJECTION) + flops_admm_merit(spec, system)
            }
            AdmmMerit::CombinedResidual => 0.0,
        },
        _ => 0.0,
    }
}

/// Floating-point operations of a run whose steps took the iterations of `log`: setup
/// $`+ \sum_m N_m\,(`$overhead $`+ \sum_{j<m}`$ iteration $`j)`$, with $`N_m`$ the steps of
/// $`m`$ iterations, + the tolerance test of every iteration in the tolerance mode + the
/// extra work ([`flops_of_extra`]). In the count mode, and without early ends or extra work,
/// it is [`run_flops`].
pub fn logged_flops(spec: &SolverSpec, system: &MassSpringSystem, log: &IterationLog) -> f64 {
    let overhead = flops_per_step_overhead(spec, system);
    let mut step_of = 0.0;
    let mut iterations = 0.0;
    let mut total = flops_setup(spec, system);
    for (m, &steps) in log.steps_by_iterations.iter().enumerate() {
        if m > 0 {
            step_of += flops_of_iteration(spec, system, m - 1);
        }
        iterations += (m as u64 * steps) as f64;
        total += steps as f64 * (overhead + step_of);
    }
    if spec.stopping.tolerance_m().is_some() {
        total += iterations * FLOPS_TOLERANCE_TEST_PER_NODE * system.len() as f64;
    }
    total + log.extra as f64 * flops_of_extra(spec, system)
}

/// Repeats of a wall-clock measurement (issue 14: the minimum of at least 5).
pub const WALL_REPEATS: usize = 5;

/// A point whose repeats spread by more than this (largest over smallest, less 1) is flagged.
pub const WALL_SPREAD_FLAG: f64 = 0.2;

/// The wall-clock time of a configuration per simulated second over its repeats, s/s.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct WallTime {
    pub min: f64,
    pub max: f64,
    pub repeats: usize,
}

impl WallTime {
    /// Largest over smallest, less 1.
    pub fn spread(&self) -> f64 {
        self.max / self.min - 1.0
    }

    /// Whether the repeats spread by more than [`WALL_SPREAD_FLAG`].
    pub fn flagged(&self) -> bool {
        self.spread() > WALL_SPREAD_FLAG
    }
}

/// Runs `point` over the window `repeats` times on the calling thread (solver built and run,
/// the errors not measured) and times each run.
pub fn wall_time(point: &Point, repeats: usize) -> Result<WallTime> {
    if repeats == 0 {
        return Err(Error::invalid("repeats", repeats, "an integer >= 1"));
    }
    let system = point.case.scene.system(point.case.stiffness)?;
    let mut times = Vec::with_capacity(repeats);
    for _ in 0..repeats {
        let start = std::time::Instant::now();
        let mut solver = point.spec.build_send(&system, point.dt_s)?;
        std::hint::black_box(sample_trajectory(solver.as_mut(), system.initial_state())?);
        times.push(start.elapsed().as_secs_f64() / WINDOW_S);
    }
    Ok(WallTime {
        min: times.iter().copied().fold(f64::INFINITY, f64::min),
        max: times.iter().copied().fold(0.0, f64::max),
        repeats,
    })
}

/// The header of `work_precision_wall.csv`: the key columns of `work_precision.csv`, the
/// minimum wall time per simulated second and the repeats' spread.
pub const WALL_CSV_HEADER: &str =
    "solver,scene,stiffness,dt_s,tolerance,iterations_mean,wall_s_per_sim_s,spread";

/// `work_precision_wall.csv`, one row per measured configuration.
pub fn wall_csv(rows: &[(Point, f64, WallTime)]) -> String {
    let mut out = format!("{WALL_CSV_HEADER}\n");
    for (p, iterations_mean, t) in rows {
        out += &format!(
            "{},{},{:?},{:?},{},{:?},{:e},{:.4}\n",
            p.spec.id,
            p.case.scene.id(),
            p.case.stiffness,
            p.dt_s,
            p.spec
                .stopping
                .tolerance_m()
                .map_or(String::new(), |t| format!("{t:?}")),
            iterations_mean,
            t.min,
            t.spread()
        );
    }
    out
}
