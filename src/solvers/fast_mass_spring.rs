//! Liu et al. 2013, *Fast Simulation of Mass-Spring Systems* (thesis §2.3.1 and §3.4,
//! Algorithm 3, Eqs 20-29 and 52-53).
//!
//! Block coordinate descent on Eq (20) with the spring energy rewritten by Eqs (21)-(23):
//! a local step projects every spring onto its rest length (Eq 28), a global step solves the
//! prefactored system $`(M + dt^2 L)\,x = M y + dt^2 f_{ext} + dt^2 J d`$ (Eq 29). The matrices
//! $`M`$, $`L`$, $`J`$ (Eqs 24-26, 52-53) and the factorisation of $`A = M + dt^2 L`$ are built once
//! per scene and time step ([`crate::solvers::projective`], shared with ADMM-PD); fixed nodes enter the
//! factorisation by Eqs 43-47.
//!
//! Errata implemented in consistent form (see `docs/thesis-errata.md`):
//! - Eqs (27), (29): as printed, $`b = M x + dt^2 f_{ext}`$ and $`(M + dt^2 L)x = dt^2 J d - b`$
//!   give the inertia the wrong sign and no velocity. Liu 2013 uses the prediction
//!   $`y = x_n + dt\,v_n`$: the right-hand side is $`M y + dt^2 f_{ext} + dt^2 J d`$.
//! - Algorithm 3 has no velocity update: $`v_{n+1} = (x_{n+1} - x_n)/dt`$ after the loop, as in
//!   Algorithm 4 line 2.11.
//!
//! Algorithm 3 does not say where the iteration starts: an open point, resolved by the shared
//! [`FirstIterate`] of [`crate::integrators::first_iterate`]. The default is $`x_n`$
//! ([`FirstIterate::Previous`]), this crate's reading for the thesis's tables; Liu 2013's
//! $`y = x_n + dt\,v_n`$ ([`FirstIterate::Inertial`]) is the other reading. The report runs
//! both and says which published rows each reproduces (its "interpretation" evidence class).
//! The comparisons beyond the thesis start it, like every solver, from the inertial prediction
//! ([`FirstIterate::InertialPrediction`]). With many iterations the step converges to the
//! Backward Euler step of Eq (20) whatever the start.
//!
//! Under an optimization integrator ([`crate::integrators::optimization_integrator`]) each stage is the same
//! iteration with $`dt`$ the stage's $`\tau`$ and $`(x_n, v_n)`$ its pseudo-state; $`A`$ and
//! $`dt^2 f_{ext}`$ are built once per distinct $`\tau`$.

use crate::error::{require_positive, Error, Result};
use crate::integrators::first_iterate::StepStart;
use crate::integrators::optimization_integrator::{MinimizingSolver, PerStageStep, StageProblem};
use crate::integrators::stopping::{Convergence, FixedPoint};
use crate::integrators::time_stepper::TimeStepper;
use crate::model::lanes::Lane;
use crate::model::system::{MassSpringSystem, State, Vec3};
use crate::solvers::projective::{
    finish_step, incidence_matrix, nodes_of_columns, sphere_scales, to_columns, GlobalSolve,
    SpringGraph, SpringIncidence,
};
use nalgebra::Vector3;

/// Where each step's local/global iteration starts, a point Algorithm 3 leaves open: the
/// crate's one notion of a first iterate.
pub use crate::integrators::first_iterate::FirstIterate;

/// Liu 2013's solver with a fixed number of local/global iterations per step.
#[derive(Debug, Clone)]
pub struct FastMassSpring {
    system: MassSpringSystem,
    dt: f64,
    iterations: usize,
    start: StepStart,
    /// $`J`$ of Eqs (26), (53), stored per spring.
    j: SpringIncidence,
    rest_lengths: Vec<f64>,
    /// The nodes' masses, kg.
    masses: Vec<f64>,
    /// $`A`$ and $`dt^2 f_{ext}`$ of each stage step, the current one's $`dt`$ in `tau`.
    stage_steps: PerStageStep<LiuStageStep>,
    /// The current stage's $`dt`$ ($`\tau`$), s.
    tau: f64,
    // Per-step buffers (column-major, 3n), so that a step allocates nothing.
    x_n: Vec<f64>,
    b: Vec<f64>,
    x: Vec<f64>,
    /// Whether the step's iterations have reached a fixed point.
    fixed_point: FixedPoint,
    /// One $`d_i`$ per spring.
    d: Vec<Vec3>,
    /// Scratch of the local step, one entry per spring.
    scale: Vec<f64>,
    /// When a step stops iterating, and the iterations steps took.
    convergence: Convergence,
}

/// What Liu's iteration prefactors for one step $`dt`$.
#[derive(Debug, Clone)]
pub struct LiuStageStep {
    /// $`A = M + dt^2 L`$, factored once (Algorithm 3 line 1.4).
    pub a: GlobalSolve,
    /// $`dt^2 f_{ext}`$, column-major.
    pub dt2_f_ext: Vec<f64>,
}

impl LiuStageStep {
    /// Algorithm 3, line 1.4, and $`dt^2 f_{ext}`$.
    fn new(system: &MassSpringSystem, dt: f64) -> Result<Self> {
        let n = system.len();
        let k: Vec<f64> = system.springs().iter().map(|s| s.stiffness).collect();
        let mut dt2_f_ext = vec![0.0; 3 * n];
        let f_ext: Vec<Vec3> = (0..n).map(|i| dt * dt * system.external_force(i)).collect();
        to_columns(&f_ext, &mut dt2_f_ext);
        Ok(Self {
            a: GlobalSolve::new(system, dt, &k)?,
            dt2_f_ext,
        })
    }
}

impl FastMassSpring {
    /// The solver for `system` with time step `dt` (s, > 0) and `iterations` (>= 1)
    /// local/global iterations per step. Algorithm 3, lines 1.1-1.4.
    pub fn new(system: &MassSpringSystem, dt: f64, iterations: usize) -> Result<Self> {
        require_positive("dt", dt)?;
        system.require_undamped_springs()?;
        if iterations == 0 {
            return Err(Error::invalid("iterations", 0, "an integer >= 1"));
        }
        let n = system.len();
        Ok(Self {
            system: system.clone(),
            dt,
            iterations,
            start: StepStart::new(FirstIterate::default()),
            j: incidence_matrix(system),
            rest_lengths: system.springs().iter().map(|s| s.rest_length).collect(),
            masses: system.nodes().iter().map(|node| node.mass).collect(),
            stage_steps: PerStageStep::new(dt, LiuStageStep::new(system, dt)?),
            tau: dt,
            x_n: vec![0.0; 3 * n],
            b: vec![0.0; 3 * n],
            x: vec![0.0; 3 * n],
            fixed_point: FixedPoint::default(),
            d: vec![Vec3::zeros(); system.springs().len()],
            scale: vec![0.0; system.springs().len()],
            convergence: Convergence::default(),
        })
    }

    /// The same solver starting each step's iteration at `first_iterate`.
    pub fn with_first_iterate(mut self, first_iterate: FirstIterate) -> Self {
        self.start = StepStart::new(first_iterate);
        self
    }

    /// Where each step starts.
    pub fn first_iterate(&self) -> FirstIterate {
        self.start.rule()
    }

    /// Local/global iterations per step.
    pub fn iterations(&self) -> usize {
        self.iterations
    }

    /// Whether each step runs its full count of iterations ([`crate::integrators::stopping::Stopping::Count`]),
    /// as a batch of runs does ([`crate::solvers::batch`]).
    pub fn counts_iterations(&self) -> bool {
        self.convergence.stopping() == crate::integrators::stopping::Stopping::Count
    }

    /// $`J`$ of Eqs (26), (53).
    pub fn incidence(&self) -> &SpringIncidence {
        &self.j
    }

    /// What the solver prefactored for its own step $`dt`$.
    pub fn own_step(&self) -> &LiuStageStep {
        self.stage_steps.own()
    }

    /// Algorithm 3 line 2.1 and the first iterate: $`b`$ of Eq (27) for `state`, and the
    /// iterate set where [`FirstIterate`] says (Algorithm 3 is silent; see the module doc).
    /// The accelerated solvers of [`crate::solvers::chebyshev`] and [`crate::solvers::anderson`] start from here.
    pub fn begin_step(&mut self, state: &State) {
        self.begin_stage(state, &StageProblem::backward_euler(self.dt))
            .expect("the solver's own step is prefactored when it is built");
    }

    /// [`Self::begin_step`] for a stage problem from its pseudo-state `stage`, with the
    /// matrix of its $`\tau`$ (built if new).
    pub fn begin_stage(&mut self, stage: &State, problem: &StageProblem) -> Result<()> {
        let system = &self.system;
        self.stage_steps
            .select(problem.tau, |tau| LiuStageStep::new(system, tau))?;
        self.tau = problem.tau;
        to_columns(&stage.x, &mut self.x_n);
        self.inertial_rhs(stage);
        let x0 = self.start.first_iterate(&self.system, stage, problem);
        to_columns(x0, &mut self.x);
        Ok(())
    }

    /// The current stage's $`dt`$, s.
    pub fn stage_step(&self) -> f64 {
        self.tau
    }

    /// Algorithm 3 lines 2.2-2.8 once: the local step, then the global step, from the current
    /// iterate.
    pub fn iterate(&mut self) {
        self.local_step();
        self.global_step();
    }

    /// The current iterate $`x`$, column-major (all x, all y, all z).
    pub fn positions(&self) -> &[f64] {
        &self.x
    }

    /// The current iterate, to be replaced (by an accelerated iterate). Fixed nodes must keep
    /// their positions; the global step restores them anyway.
    pub fn positions_mut(&mut self) -> &mut [f64] {
        &mut self.x
    }

    /// Eq. (27): consistent form $`b = M y + dt^2 f_{ext}`$ with $`y = x_n + dt\,v_n`$
    /// (printed: $`b = M x + f_{ext}\,dt^2`$, subtracted in Eq 29).
    fn inertial_rhs(&mut self, state: &State) {
        let dt2_f_ext = &self.stage_steps.current().dt2_f_ext;
        inertial_rhs(
            &state.x,
            &state.v,
            &self.masses,
            self.tau,
            dt2_f_ext,
            &mut self.b,
        );
    }

    /// Eq. (28): $`d_i = l_0\,(x_1 - x_2)/|x_1 - x_2|`$ for every spring, at the current
    /// iterate (the local step, lines 2.3-2.5). Public for the timing study, which times the
    /// two halves of an iteration apart after a step.
    pub fn local_step(&mut self) {
        spring_directions(
            &self.j,
            &self.x,
            &self.rest_lengths,
            &mut self.d,
            &mut self.scale,
        );
    }

    /// Eq. (29): consistent form $`(M + dt^2 L)\,x = b + dt^2 J d`$, solved with the
    /// prefactored $`A`$ for the three coordinates at once; fixed nodes stay at $`x_n`$.
    pub fn global_step(&mut self) {
        global_rhs(&self.j, &self.b, &self.d, self.tau * self.tau, &mut self.x);
        self.stage_steps.current().a.solve(&mut self.x, &self.x_n);
    }
}

// The arithmetic of a step, generic over the lane type ([`crate::model::lanes`]): at `f64` it is
// [`FastMassSpring`]'s, in lanes a batch's ([`crate::solvers::batch::liu`]).

/// Eq. (27): consistent form $`b = M y + dt^2 f_{ext}`$ with $`y = x_n + dt\,v_n`$, from the
/// positions `x`, velocities `v` and `masses` of the nodes, column-major.
pub fn inertial_rhs<T: Lane>(
    x: &[Vector3<T>],
    v: &[Vector3<T>],
    masses: &[T],
    dt: T,
    dt2_f_ext: &[T],
    b: &mut [T],
) {
    let n = x.len();
    for (i, ((x, v), &mass)) in x.iter().zip(v).zip(masses).enumerate() {
        let y = x + v * dt;
        for c in 0..3 {
            b[c * n + i] = mass * y[c] + dt2_f_ext[c * n + i];
        }
    }
}

/// How many springs [`spring_directions`] takes through its three passes at a time: each
/// block's differences and factors are still in the L1 cache when the next pass reads them,
/// and each spring gets the same operations in the same order, so the same bits. The 100 × 100
/// sheet's 39,402 springs a pass at a time went through L2: the local step 110-116 µs, in
/// blocks of 64 springs 99-105 µs (least of 4 to 6 runs pinned to one core, `timing --point
/// fast_mass_spring 100`; 32 the same, 16 and 256 slower). ADMM-PD's local step
/// ([`crate::solvers::admm::local_step_of`]) in blocks of 64 was slower (182 against 171 µs,
/// least of 8 alternating runs), and runs a pass at a time.
pub const SPRING_BLOCK: usize = 64;

/// Eq. (28): $`d_i = l_0\,(x_1 - x_2)/|x_1 - x_2|`$ for every spring of `j` at the
/// column-major iterate `x` (`scale`: scratch, one entry per spring), with the arithmetic of
/// [`crate::solvers::projective::project_on_sphere`]: each spring's difference and its
/// squared length in one pass, then every square root and division at once
/// ([`sphere_scales`], several springs at a time in SIMD registers), then the scaling, the
/// three passes block by block ([`SPRING_BLOCK`] springs; on the 100 × 100 sheet the pass over the
/// differences apart cost 14 % of the local step). The loops run over the graph's springs and
/// nodes, so that on a [`crate::solvers::projective::Chain`] every index is known where the
/// code is compiled.
#[inline]
pub fn spring_directions<T: Lane, G: SpringGraph>(
    j: &SpringIncidence<T, G>,
    x: &[T],
    rest_lengths: &[T],
    d: &mut [Vector3<T>],
    scale: &mut [T],
) {
    let x = &x[..3 * j.nodes()];
    let springs = j.springs();
    let blocks = d[..springs]
        .chunks_mut(SPRING_BLOCK)
        .zip(scale[..springs].chunks_mut(SPRING_BLOCK));
    for (start, (d, scale)) in (0..springs).step_by(SPRING_BLOCK).zip(blocks) {
        for (k, (d, r)) in d.iter_mut().zip(scale.iter_mut()).enumerate() {
            *d = j.difference(start + k, x);
            *r = d.norm_squared();
        }
        sphere_scales(scale, &rest_lengths[start..start + scale.len()]);
        for (d, &r) in d.iter_mut().zip(scale.iter()) {
            *d *= r;
        }
    }
}

/// Eq. (29), the right-hand side of the consistent form: $`x \leftarrow b + dt^2 J d`$.
#[inline]
pub fn global_rhs<T: Lane, G: SpringGraph>(
    j: &SpringIncidence<T, G>,
    b: &[T],
    d: &[Vector3<T>],
    dt2: T,
    x: &mut [T],
) {
    j.b_plus_transposed(b, |i| d[i] * dt2, x);
}

impl TimeStepper for FastMassSpring {
    fn name(&self) -> String {
        format!(
            "Fast mass-spring (Liu 2013, {})",
            self.convergence
                .iterations_label(self.iterations, "iterations")
        )
    }

    fn dt(&self) -> f64 {
        self.dt
    }

    fn system(&self) -> &MassSpringSystem {
        &self.system
    }

    fn convergence(&mut self) -> Option<&mut Convergence> {
        Some(&mut self.convergence)
    }

    fn step(&mut self, state: &mut State) -> Result<()> {
        self.solve(&StageProblem::backward_euler(self.dt), state)
    }
}

impl MinimizingSolver for FastMassSpring {
    /// Algorithm 3, run-time part.
    // region: step
    fn solve(&mut self, problem: &StageProblem, state: &mut State) -> Result<()> {
        // 2.1 and the first iterate.
        self.begin_stage(state, problem)?;
        self.convergence
            .begin_stage(state, problem.tau, nodes_of_columns(&self.x));
        // 2.2-2.8, stopping early only in the tolerance mode; at a fixed point the iterations
        // left are not computed ([`FixedPoint`]: an iteration reads nothing of the solver's
        // but its iterate and the step's b and A, and its result is known).
        self.fixed_point.begin_step();
        for _ in 0..self.iterations {
            if !self.fixed_point.reached() {
                self.fixed_point.keep(&[], &self.x);
                self.iterate();
                self.fixed_point.compare(&[], &self.x);
            }
            if self.convergence.converged(nodes_of_columns(&self.x)) {
                break;
            }
        }
        self.convergence.end_step(0);
        // Erratum: Algorithm 3 omits the velocity update.
        finish_step(state, &self.x, problem.tau);
        Ok(())
    }
    // endregion: step

    fn prepare(&mut self, tau: f64) -> Result<()> {
        let system = &self.system;
        self.stage_steps
            .select(tau, |tau| LiuStageStep::new(system, tau))
            .map(|_| ())
    }
}
