//! The benchmark's ground truths ([`super`], items 2 and 3 of its specification): the exact
//! static equilibrium, the lowest mode the start excites, the window it sets, and the exact
//! motion.

use super::metrics::Trajectory;
use crate::error::{Error, Result};
use crate::integrators::dissipation::Dissipation;
use crate::integrators::optimization_integrator::OptimizationIntegrator;
use crate::integrators::stopping::Stopping;
use crate::integrators::time_stepper::TimeStepper;
use crate::model::system::{MassSpringSystem, State, Vec3};
use crate::solvers::registry::{SolverId, SolverSpec};
use crate::studies::integrator_study::exact_stages;
use crate::studies::work_precision::{
    rk4_stability_limit, Case, EXACT_STABILITY_FRACTION, SAMPLE_INTERVAL_S,
};

/// The window holds this many periods of the lowest excited mode.
pub const WINDOW_PERIODS: f64 = 3.0;

/// Section 12.2's second window, in periods of the lowest mode: the Backward Euler slopes
/// fitted again over twice the window, since a first-order scheme's error grows with the time
/// it has to accumulate (issue 47: the stiff rope's slope of 0.97 over 1.5 s read 0.74 over
/// 5 s).
pub const SECOND_WINDOW_PERIODS: f64 = 6.0;

/// A mode of the linearised system about the equilibrium, with the coordinate that measures it.
#[derive(Debug, Clone, PartialEq)]
pub struct Mode {
    /// Angular frequency, rad/s.
    pub omega: f64,
    /// The mass-scaled shape: $`\hat\phi_i \sqrt{m_i}`$ per node, so that the modal coordinate
    /// of a displacement $`u`$ is $`q = \sum_i \sqrt{m_i}\,\hat\phi_i \cdot u_i`$ with
    /// $`\hat\phi`$ of unit length over the free coordinates (zero on fixed nodes).
    pub weights: Vec<Vec3>,
}

impl Mode {
    /// The modal coordinate of positions `x` about `equilibrium`, m·kg^½.
    pub fn coordinate(&self, x: &[Vec3], equilibrium: &[Vec3]) -> f64 {
        self.weights
            .iter()
            .zip(x.iter().zip(equilibrium))
            .map(|(w, (x, e))| w.dot(&(x - e)))
            .sum()
    }

    /// The modal velocity of velocities `v`.
    pub fn velocity(&self, v: &[Vec3]) -> f64 {
        self.weights.iter().zip(v).map(|(w, v)| w.dot(v)).sum()
    }

    /// The mode's energy in a state, ½(q̇² + ω²q²), J.
    pub fn energy(&self, state: &State, equilibrium: &[Vec3]) -> f64 {
        let q = self.coordinate(&state.x, equilibrium);
        let qd = self.velocity(&state.v);
        0.5 * (qd * qd + self.omega * self.omega * q * q)
    }
}

/// A start's participation below this fraction of its largest one leaves a mode unexcited
/// (the rope's out-of-plane swings, which its in-plane start never moves).
pub const PARTICIPATION_FLOOR: f64 = 1e-6;

/// The lowest mode of `system` about `equilibrium` that the start excites: the generalised
/// eigenproblem $`K\phi = \omega^2 M\phi`$ over the free coordinates, $`K = -\partial f/\partial x`$
/// at the equilibrium, and of its modes the slowest whose participation
/// $`|\hat\phi^\top M^{1/2}(x_0 - x_{eq})|`$ is at least [`PARTICIPATION_FLOOR`] of the largest.
pub fn lowest_excited_mode(system: &MassSpringSystem, equilibrium: &[Vec3]) -> Result<Mode> {
    let jacobian = system.force_jacobian_dense(equilibrium);
    let free: Vec<usize> = (0..system.len())
        .filter(|&i| !system.nodes()[i].fixed)
        .flat_map(|i| (0..3).map(move |c| 3 * i + c))
        .collect();
    let root_mass: Vec<f64> = free
        .iter()
        .map(|&r| system.nodes()[r / 3].mass.sqrt())
        .collect();
    let k = nalgebra::DMatrix::from_fn(free.len(), free.len(), |r, c| {
        -jacobian[(free[r], free[c])] / (root_mass[r] * root_mass[c])
    });
    let eigen = k.symmetric_eigen();
    let start = system.initial_state().x;
    let scaled_start: Vec<f64> = free
        .iter()
        .zip(&root_mass)
        .map(|(&r, m)| m * (start[r / 3][r % 3] - equilibrium[r / 3][r % 3]))
        .collect();
    let participation: Vec<f64> = (0..free.len())
        .map(|j| {
            eigen
                .eigenvectors
                .column(j)
                .iter()
                .zip(&scaled_start)
                .map(|(a, b)| a * b)
                .sum::<f64>()
                .abs()
        })
        .collect();
    let largest = participation.iter().copied().fold(0.0, f64::max);
    let j = (0..free.len())
        .filter(|&j| {
            participation[j] >= PARTICIPATION_FLOOR * largest && eigen.eigenvalues[j] > 0.0
        })
        .min_by(|&a, &b| eigen.eigenvalues[a].total_cmp(&eigen.eigenvalues[b]))
        .ok_or_else(|| Error::Input("no mode of the scene is excited by its start".into()))?;
    let mut weights = vec![Vec3::zeros(); system.len()];
    for ((&r, m), phi) in free
        .iter()
        .zip(&root_mass)
        .zip(eigen.eigenvectors.column(j).iter())
    {
        weights[r / 3][r % 3] = m * phi;
    }
    Ok(Mode {
        omega: eigen.eigenvalues[j].sqrt(),
        weights,
    })
}

/// `periods` periods of `period` seconds, rounded up to a whole number of samples, s.
pub fn whole_samples(periods: f64, period: f64) -> f64 {
    // Divided by the samples per second rather than multiplied by the interval, so that
    // 48 samples are 4.8 s and not 4.800000000000001 s.
    (periods * period / SAMPLE_INTERVAL_S - 1e-9).ceil() / (1.0 / SAMPLE_INTERVAL_S).round()
}

/// The exact motion is first run over this many periods of the linearised lowest mode, to
/// measure its period: the motion from the taut start swings wide, so its period is longer
/// than the linear one (by 18 % on the soft rope), and the window holds [`WINDOW_PERIODS`] of
/// the measured periods.
pub const SCOUTING_PERIODS: f64 = 4.5;

/// A node this far from where it started, m, counts as divergence (the scenes span 9 m).
pub const DIVERGENCE_DISTANCE_M: f64 = 1e3;

/// Runs `solver` from `state` over `window` seconds and records its [`Trajectory`]; a
/// non-finite state or a node [`DIVERGENCE_DISTANCE_M`] from its start stops it with
/// [`Error::Diverged`].
pub fn record(
    solver: &mut dyn TimeStepper,
    mut state: State,
    window: f64,
    mode: &Mode,
    equilibrium: &[Vec3],
) -> Result<Trajectory> {
    let dt = solver.dt();
    let per_sample = crate::studies::work_precision::steps_per_sample(dt)?;
    let count = (window / SAMPLE_INTERVAL_S).round() as usize;
    let start = state.x.clone();
    let mut t = Trajectory {
        dt,
        samples: Vec::with_capacity(count),
        modal: Vec::with_capacity(count * per_sample as usize),
        modal_energy: Vec::with_capacity(count * per_sample as usize),
    };
    let mut step = 0u64;
    for _ in 0..count {
        for _ in 0..per_sample {
            solver.step(&mut state)?;
            step += 1;
            t.modal.push(mode.coordinate(&state.x, equilibrium));
            t.modal_energy.push(mode.energy(&state, equilibrium));
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
        t.samples.push(state.x.clone());
    }
    Ok(t)
}

/// The ground truths of one case.
#[derive(Debug, Clone, PartialEq)]
pub struct CaseTruth {
    pub case: Case,
    /// The exact static equilibrium.
    pub equilibrium: Vec<Vec3>,
    /// The lowest mode the start excites.
    pub mode: Mode,
    /// The window, s.
    pub window: f64,
    /// RK4's stability limit, s, and the step of the exact motion.
    pub stability_limit: f64,
    pub h: f64,
    /// The exact motion: RK4 at [`EXACT_STABILITY_FRACTION`] of its limit.
    pub exact: Trajectory,
    /// The change of the exact motion's samples when RK4's step is halved from 2h to h
    /// (largest node distance, m): it bounds the error of the 2h motion, about 15 times that
    /// of the exact motion itself (RK4 is of order 4).
    pub halving_gap: f64,
    /// The exact motion's RMS amplitude about the equilibrium over the samples and free
    /// nodes, m: the do-nothing error (the equilibrium held still) and the scale of the
    /// relative errors.
    pub amplitude: f64,
}

impl CaseTruth {
    /// `solver` on the case's `system`, from its start over the window, recorded
    /// ([`record`]): every run measured against this truth.
    pub fn record_window(
        &self,
        solver: &mut dyn TimeStepper,
        system: &MassSpringSystem,
    ) -> Result<Trajectory> {
        record(
            solver,
            system.initial_state(),
            self.window,
            &self.mode,
            &self.equilibrium,
        )
    }

    /// The same truth over `periods` periods of its lowest mode (the measured one) instead of
    /// [`WINDOW_PERIODS`]: the exact motion, its halving gap and its amplitude recomputed over
    /// the new window, the mode and equilibrium kept. Section 12.2's second window, on which
    /// the Backward Euler slopes are fitted again.
    pub fn over_periods(&self, periods: f64) -> Result<Self> {
        let system = self.case.scene.system(self.case.stiffness)?;
        let period = super::metrics::modal_period(&self.exact)
            .ok_or_else(|| Error::Input(format!("{}: no period to extend", self.case.label())))?;
        let window = whole_samples(periods, period);
        let exact_over =
            |fraction: f64| exact_motion(&system, &self.mode, &self.equilibrium, fraction, window);
        let (_, exact) = exact_over(EXACT_STABILITY_FRACTION)?;
        let (_, doubled) = exact_over(2.0 * EXACT_STABILITY_FRACTION)?;
        Ok(Self {
            window,
            halving_gap: super::metrics::largest_distance(&exact.samples, &doubled.samples),
            amplitude: super::metrics::rms_distance_to(&system, &exact.samples, &self.equilibrium),
            exact,
            ..self.clone()
        })
    }

    /// The equilibrium, the mode, the window and the exact motion of a case (and its motion
    /// at twice the step, for the halving gap).
    pub fn compute(case: Case) -> Result<Self> {
        let system = case.scene.system(case.stiffness)?;
        let equilibrium = case.scene.equilibrium(case.stiffness)?;
        let mode = lowest_excited_mode(&system, &equilibrium)?;
        let stability_limit = rk4_stability_limit(&system);
        let exact_over = |fraction: f64, window: f64| {
            exact_motion(&system, &mode, &equilibrium, fraction, window)
        };
        let linear_period = std::f64::consts::TAU / mode.omega;
        let scouting = whole_samples(SCOUTING_PERIODS, linear_period);
        let (h, mut exact) = exact_over(EXACT_STABILITY_FRACTION, scouting)?;
        let period = super::metrics::modal_period(&exact).ok_or_else(|| {
            Error::Input(format!(
                "{}: the exact motion's lowest mode does not oscillate over {scouting} s",
                case.label()
            ))
        })?;
        let window = whole_samples(WINDOW_PERIODS, period).min(scouting);
        exact.truncate(window);
        let (_, doubled) = exact_over(2.0 * EXACT_STABILITY_FRACTION, window)?;
        let halving_gap = super::metrics::largest_distance(&exact.samples, &doubled.samples);
        let amplitude = super::metrics::rms_distance_to(&system, &exact.samples, &equilibrium);
        Ok(Self {
            case,
            equilibrium,
            mode,
            window,
            stability_limit,
            h,
            exact,
            halving_gap,
            amplitude,
        })
    }
}

/// RK4 at `fraction` of its stability limit (the step rounded down to divide the sampling
/// interval) over `window` s from the system's start: its step, s, and its trajectory.
fn exact_motion(
    system: &MassSpringSystem,
    mode: &Mode,
    equilibrium: &[Vec3],
    fraction: f64,
    window: f64,
) -> Result<(f64, Trajectory)> {
    let per_sample = (SAMPLE_INTERVAL_S / (fraction * rk4_stability_limit(system))).ceil();
    let h = SAMPLE_INTERVAL_S / per_sample;
    let mut rk4 = SolverSpec::new(SolverId::Rk4, 1).build(system, h)?;
    Ok((
        h,
        record(
            rk4.as_mut(),
            system.initial_state(),
            window,
            mode,
            equilibrium,
        )?,
    ))
}

/// The form of a solver whose steps are solved to round-off: the ground truth of its solver
/// error. PBD has none: on the rope its only fixed point is the straight rope between the
/// anchors (hard constraints and no compliance), which its iterations approach without
/// reaching, so its solver error is not measured.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Converged {
    /// Every minimising solver: each stage of its integrator solved by Newton to round-off
    /// (a stage that does not converge fails the run: no Newton reference is capped).
    Newton(OptimizationIntegrator),
    /// XPBD iterated until its Eq. (16) residual $`\max_j \lvert C_j(x) + \tilde\alpha_j
    /// \lambda_j\rvert`$ (the constraint row with its compliance term, m) is at most
    /// [`XPBD_REFERENCE_RESIDUAL_M`], or [`XPBD_REFERENCE_CAP`] iterations
    /// ([`XPBD_REFERENCE_CAP_SHEET`] on the sheet).
    Xpbd,
}

/// The residual XPBD's reference aims at, m: four orders below the smallest solver error
/// the chapters read (1e-8 m), some orders above the round-off of a metre-long spring.
pub const XPBD_REFERENCE_RESIDUAL_M: f64 = 1e-12;
/// XPBD's reference's iteration cap per step on the rope: its stiff case at dt = 0.1 s takes
/// about 80 000 sweeps a step to reach [`XPBD_REFERENCE_RESIDUAL_M`]. A step that reaches the
/// cap is counted ([`SolverTruth::capped_fraction`]) and the solver errors measured against a
/// capped reference are not reported.
pub const XPBD_REFERENCE_CAP: usize = 200_000;
/// The cap on the sheet, whose sweeps cost twenty rope sweeps: its stiff case does not
/// converge within it at dt = 0.1 s (its solver errors there are not reported).
pub const XPBD_REFERENCE_CAP_SHEET: usize = 20_000;

impl Converged {
    /// The converged form of `spec`'s solver; None for PBD (above), the XPBD substeps (its
    /// substeps are its time steps) and the explicit baselines (no iteration to converge).
    pub fn of(spec: &SolverSpec) -> Option<Converged> {
        match spec.id {
            SolverId::Xpbd => Some(Converged::Xpbd),
            id if id.is_minimizing() => Some(Converged::Newton(spec.params.integrator)),
            _ => None,
        }
    }

    /// `newton backward-euler`, `xpbd`.
    pub fn id(self) -> String {
        match self {
            Converged::Newton(i) => format!("newton {}", i.key()),
            Converged::Xpbd => "xpbd".into(),
        }
    }

    /// Its solver at step `dt` on `case`'s `system`.
    pub fn solver(
        self,
        case: Case,
        system: &MassSpringSystem,
        dt: f64,
    ) -> Result<Box<dyn TimeStepper>> {
        match self {
            Converged::Newton(integrator) => Ok(Box::new(exact_stages(
                system,
                dt,
                integrator,
                Dissipation::NONE,
            )?)),
            Converged::Xpbd => {
                let cap = match case.scene {
                    crate::studies::beyond::GridScene::Rope => XPBD_REFERENCE_CAP,
                    crate::studies::beyond::GridScene::Sheet => XPBD_REFERENCE_CAP_SHEET,
                };
                let mut spec = SolverSpec::new(SolverId::Xpbd, cap);
                spec.stopping = Stopping::residual(XPBD_REFERENCE_RESIDUAL_M)?;
                spec.build(system, dt)
            }
        }
    }
}

/// A converged method's trajectory at one step over a case's window.
#[derive(Debug, Clone, PartialEq)]
pub struct SolverTruth {
    pub method: Converged,
    pub trajectory: Trajectory,
    /// The fraction of its steps that reached the iteration cap without meeting the residual
    /// (0 for Newton's, whose stages converge or fail the run).
    pub capped_fraction: f64,
    /// The largest residual a step ended at, m (XPBD's; None for Newton's).
    pub largest_end_residual_m: Option<f64>,
}

impl SolverTruth {
    /// `method` at step `dt` over `truth`'s window.
    pub fn compute(method: Converged, dt: f64, truth: &CaseTruth) -> Result<Self> {
        let system = truth.case.scene.system(truth.case.stiffness)?;
        let mut solver = method.solver(truth.case, &system, dt)?;
        let trajectory = truth.record_window(solver.as_mut(), &system)?;
        let log = solver.iteration_log().filter(|_| method == Converged::Xpbd);
        Ok(Self {
            method,
            trajectory,
            capped_fraction: log.map_or(0.0, |l| l.capped as f64 / l.steps().max(1) as f64),
            largest_end_residual_m: log.map(|l| l.largest_end_residual_m),
        })
    }
}
