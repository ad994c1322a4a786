//! ADMM ⊇ Projective Dynamics (Overby et al. 2017; thesis §2.3.2 and §3.5, Algorithm 4,
//! Eqs 30-42 and 54-56).
//!
//! Eq (20) split as in Eqs (34)-(39): $`f(x) = \frac{1}{2dt^2}|x - \tilde x|_M^2`$,
//! $`g(z) = U_*(z)`$ (the springs' Hooke energy), constraint $`W(Dx - z) = 0`$ with the reduction
//! matrix $`D`$ (Eq 54) and the weights $`W = \omega I`$, $`\omega_i = \sqrt{k_i}`$ by default (the
//! "usual" choice of §2.3.2, and the one §3.5 assumes). Each step starts from
//! $`x^0 = \tilde x = x_n + dt\,v_n + dt^2 M^{-1} f_{ext}`$ with the scaled dual $`\bar u = 0`$
//! (lines 2.1-2.2), then iterates, in the order of Algorithm 4: the local step $`z`$ (Eq 41,
//! solved by Eqs 55-56 for Hooke's energy), the dual update $`\bar u`$ (Eq 42), and the global
//! step $`x`$ (Eq 40) with $`A = M + dt^2 D^\top W^\top W D`$ factored once per scene and time step
//! ([`crate::solvers::projective`], shared with Liu 2013; fixed nodes by Eqs 43-47). The velocity is
//! $`(x - x_n)/dt`$ (line 2.11).
//!
//! Errata implemented in consistent form (see `docs/thesis-errata.md`):
//! - Eq (34): the inertial term is $`(x - \tilde x)^\top M (x - \tilde x)`$, as Eq (35) has it
//!   (printed with $`x^n - x^{n+1}`$).
//! - Eq (36): $`g(z) = U_*(z)`$ (printed $`g(x)`$).
//! - Eq (40), last line: $`D^\top W^\top W`$ (printed $`D^\top W W`$; equal for a diagonal $`W`$).
//!
//! Eq (56)'s simplified form $`z = \frac12(p + D_i x + \bar u_i)`$ holds only for
//! $`\omega_i^2 = k_i`$; the general form is used so that any weights stay correct.
//!
//!
//! Under an optimization integrator ([`crate::integrators::optimization_integrator`]) each stage is the same
//! iteration with $`dt`$ the stage's $`\tau`$ and $`(x_n, v_n)`$ its pseudo-state; $`A`$ is
//! factored once per distinct $`\tau`$.
//!
//! The labelled departures that explain the published numbers (start points, carried dual,
//! other weights, fixed-node handling, stale right-hand side) are not here: they are built
//! from this module's building blocks in [`crate::studies::forensics::admm_variants`].

use crate::error::{require_positive, Error, Result};
use crate::integrators::first_iterate::{inertial_prediction, FirstIterate, StepStart};
use crate::integrators::optimization_integrator::{MinimizingSolver, PerStageStep, StageProblem};
use crate::integrators::stopping::Convergence;
use crate::integrators::time_stepper::TimeStepper;
use crate::model::lanes::Lane;
use crate::model::system::{MassSpringSystem, State, Vec3};
use crate::solvers::projective::{
    finish_step, nodes_of_columns, project_on_sphere, reduction_matrix, sphere_scales, to_columns,
    GlobalSolve, SpringGraph, SpringIncidence,
};
use nalgebra::Vector3;

/// The default weights $`\omega_i = \sqrt{k_i}`$ (§2.3.2, Eqs 37-38: $`A = WD`$, $`B = -W`$).
pub fn default_omega(system: &MassSpringSystem) -> Vec<f64> {
    system
        .springs()
        .iter()
        .map(|s| s.stiffness.sqrt())
        .collect()
}

/// Eq. (56): $`z_i = \dfrac{k\,p_i + \omega_i^2\,(D_i x + \bar u_i)}{\omega_i^2 + k}`$, the
/// minimiser of Eq (41) for Hooke's energy given the projection $`p_i`$ of Eq (55);
/// $`\frac12(p_i + D_i x + \bar u_i)`$ when $`\omega_i^2 = k`$. For any lane type
/// ([`crate::model::lanes`]).
#[inline]
pub fn z_update<T: Lane>(p: Vector3<T>, q: Vector3<T>, k: T, omega: T) -> Vector3<T> {
    let omega2 = omega * omega;
    (p * k + q * omega2) / (omega2 + k)
}

/// Eq. (41): $`z_i = \arg\min_{z_i} U_i(z_i) + \frac12|W_i(D_i x - z_i + \bar u_i)|^2`$ for
/// $`U_i(z) = \frac12 k(|z| - l_0)^2`$, with $`q = D_i x + \bar u_i`$: the minimiser lies on $`q`$'s
/// ray, so it is Eq (56) applied to the projection $`p_i = l_0\,q/|q|`$ of Eq (55).
#[inline]
pub fn z_minimisation<T: Lane>(q: Vector3<T>, l0: T, k: T, omega: T) -> Vector3<T> {
    let p = project_on_sphere(q, l0);
    z_update(p, q, k, omega)
}

/// Eq. (42): $`\bar u_i \leftarrow \bar u_i + D_i x - z_i`$.
#[inline]
pub fn dual_update<T: Lane>(u_bar: Vector3<T>, d_x: Vector3<T>, z: Vector3<T>) -> Vector3<T> {
    u_bar + d_x - z
}

/// Each spring's data in Algorithm 4's local step, one value per spring.
#[derive(Debug, Clone, Copy)]
pub struct LocalStepSprings<'a, T> {
    /// $`l_{0,i}`$.
    pub rest_lengths: &'a [T],
    /// $`k_i`$.
    pub stiffness: &'a [T],
    /// $`\omega_i`$, the diagonal of $`W`$.
    pub omega: &'a [T],
}

/// Lines 2.4-2.7: for every spring, $`z_i`$ (Eq 41 by Eqs 55-56), then $`\bar u_i`$ (Eq 42),
/// from the column-major iterate `x`. [`z_minimisation`]'s arithmetic, with every spring's
/// square root and division of Eq (55) gathered in one pass over `scale` (scratch, one per
/// spring; `z` holds $`D_i x`$ until its update), as Liu's local step gathers its own
/// ([`crate::solvers::fast_mass_spring::spring_directions`]): the same operations on the same
/// operands, so the same bits, several springs' at a time.
#[inline]
pub fn local_step_of<T: Lane, G: SpringGraph>(
    d: &SpringIncidence<T, G>,
    x: &[T],
    springs: LocalStepSprings<T>,
    scale: &mut [T],
    z: &mut [Vector3<T>],
    u_bar: &mut [Vector3<T>],
) {
    // The loops run over the graph's springs and nodes (every index known where the code is
    // compiled for a `Chain`).
    let s = d.springs();
    let x = &x[..3 * d.nodes()];
    let (scale, z, u_bar) = (&mut scale[..s], &mut z[..s], &mut u_bar[..s]);
    // D_i x, and |q|² for Eq (41)'s q = D_i x + ū_i.
    for (i, ((d_x, u_bar), r)) in z
        .iter_mut()
        .zip(u_bar.iter())
        .zip(scale.iter_mut())
        .enumerate()
    {
        *d_x = d.apply_row(i, x);
        *r = (*d_x + *u_bar).norm_squared();
    }
    // Eq (55): l_0/|q| for every spring.
    sphere_scales(scale, &springs.rest_lengths[..s]);
    // Eq (56) on the projection p = q l_0/|q|, then Eq (42).
    let per_spring = scale
        .iter()
        .zip(&springs.stiffness[..s])
        .zip(&springs.omega[..s]);
    for ((z, u_bar), ((&r, &k), &omega)) in z.iter_mut().zip(u_bar.iter_mut()).zip(per_spring) {
        let d_x = *z;
        let q = d_x + *u_bar;
        *z = z_update(q * r, q, k, omega);
        *u_bar = dual_update(*u_bar, d_x, *z);
    }
}

/// Eq. (40)'s right-hand side $`M\tilde x + dt^2 D^\top W^\top W (z - \bar u)`$, formed in `x`
/// (`dt2_omega2`: $`dt^2\omega_i^2`$ per spring).
#[inline]
pub fn global_rhs_of<T: Lane, G: SpringGraph>(
    d: &SpringIncidence<T, G>,
    m_x_tilde: &[T],
    z: &[Vector3<T>],
    u_bar: &[Vector3<T>],
    dt2_omega2: &[T],
    x: &mut [T],
) {
    d.b_plus_transposed(m_x_tilde, |i| (z[i] - u_bar[i]) * dt2_omega2[i], x);
}

/// The iteration of Algorithm 4 within one step (lines 2.1-2.10): its iterate, its auxiliary
/// and dual variables and the per-spring data they need. [`AdmmPd`] and the forensic variants
/// of `crate::studies::forensics::admm_variants` step through it; its buffers are column-major (3n) or
/// one `Vec3` per spring, so that a step allocates nothing.
#[derive(Debug, Clone)]
pub struct AdmmIterate {
    /// $`D`$ of Eq (54), stored per spring.
    d: SpringIncidence,
    /// $`\omega_i`$, the diagonal of $`W`$.
    omega: Vec<f64>,
    /// The springs' rest lengths and stiffnesses.
    rest_lengths: Vec<f64>,
    stiffness: Vec<f64>,
    /// Scratch of the local step, one value per spring.
    scale: Vec<f64>,
    /// $`dt^2\,\omega_i^2`$, the factor of $`D_i^\top`$ in Eq (40)'s right-hand side.
    dt2_omega2: Vec<f64>,
    /// The positions $`x_n`$ at the start of the step; the fixed nodes keep them.
    pub x_n: Vec<f64>,
    /// $`\tilde x`$.
    pub x_tilde: Vec<f64>,
    /// $`M\tilde x`$.
    m_x_tilde: Vec<f64>,
    /// The iterate $`x`$.
    pub x: Vec<f64>,
    /// $`z`$, one per spring.
    pub z: Vec<Vec3>,
    /// The scaled dual $`\bar u`$, one per spring.
    pub u_bar: Vec<Vec3>,
}

impl AdmmIterate {
    /// Buffers for `system` with the weights `omega` (one per spring) and time step `dt`.
    pub fn new(system: &MassSpringSystem, dt: f64, omega: Vec<f64>) -> Self {
        let (n, s) = (system.len(), system.springs().len());
        Self {
            d: reduction_matrix(system),
            dt2_omega2: omega.iter().map(|w| dt * dt * (w * w)).collect(),
            omega,
            rest_lengths: system.springs().iter().map(|s| s.rest_length).collect(),
            stiffness: system.springs().iter().map(|s| s.stiffness).collect(),
            scale: vec![0.0; s],
            x_n: vec![0.0; 3 * n],
            x_tilde: vec![0.0; 3 * n],
            m_x_tilde: vec![0.0; 3 * n],
            x: vec![0.0; 3 * n],
            z: vec![Vec3::zeros(); s],
            u_bar: vec![Vec3::zeros(); s],
        }
    }

    /// The weights $`\omega_i`$.
    pub fn omega(&self) -> &[f64] {
        &self.omega
    }

    /// $`D`$ of Eq (54).
    pub fn reduction(&self) -> &SpringIncidence {
        &self.d
    }

    /// The global step's factors $`dt^2\omega_i^2`$.
    pub fn dt2_omega2(&self) -> &[f64] {
        &self.dt2_omega2
    }

    /// The global step's factors $`dt^2\omega_i^2`$ for another time step `dt` (a stage's
    /// $`\tau`$).
    pub fn set_step(&mut self, dt: f64) {
        for (f, w) in self.dt2_omega2.iter_mut().zip(&self.omega) {
            *f = dt * dt * (w * w);
        }
    }

    /// Line 2.1: $`x_n`$, and $`\tilde x = x_n + dt\,v_n + dt^2 M^{-1} f_{ext}`$ (Eq 35's
    /// $`\tilde x`$) with $`M\tilde x`$ for Eq (40). Fixed nodes predict their own position:
    /// they never move.
    pub fn predict(&mut self, system: &MassSpringSystem, state: &State, dt: f64) {
        to_columns(&state.x, &mut self.x_n);
        let n = state.x.len();
        for (i, node) in system.nodes().iter().enumerate() {
            let x = inertial_prediction(system, state, dt, i);
            for c in 0..3 {
                self.x_tilde[c * n + i] = x[c];
                self.m_x_tilde[c * n + i] = node.mass * x[c];
            }
        }
    }

    /// [Brown 2018, dissipation potential] (unverified: no body text or reference code found) The mass-proportional damping's term joins the
    /// inertial one: $`\frac{1}{2h^2}|x - \tilde x|_M^2 + \frac{\alpha}{2h}|x - x_n|_M^2`$ is, up to
    /// a constant, $`\frac{1 + \alpha h}{2h^2}|x - \hat x|_M^2`$ with
    /// $`\hat x = (\tilde x + \alpha h\,x_n)/(1 + \alpha h)`$. Replaces $`\tilde x`$ (after
    /// [`Self::predict`]) by $`\hat x`$, given `alpha_h` $`= \alpha h`$.
    pub fn damp_prediction(&mut self, system: &MassSpringSystem, alpha_h: f64) {
        let n = system.len();
        for (i, node) in system.nodes().iter().enumerate() {
            for c in 0..3 {
                let r = c * n + i;
                let x_hat = (self.x_tilde[r] + alpha_h * self.x_n[r]) / (1.0 + alpha_h);
                self.x_tilde[r] = x_hat;
                self.m_x_tilde[r] = node.mass * x_hat;
            }
        }
    }

    /// Lines 2.4-2.7: for every spring, $`z_i`$ (Eq 41 by Eqs 55-56), then $`\bar u_i`$
    /// (Eq 42), from the current iterate $`x`$.
    pub fn local_step(&mut self) {
        let springs = LocalStepSprings {
            rest_lengths: &self.rest_lengths,
            stiffness: &self.stiffness,
            omega: &self.omega,
        };
        local_step_of(
            &self.d,
            &self.x,
            springs,
            &mut self.scale,
            &mut self.z,
            &mut self.u_bar,
        );
    }

    /// The combined residual after a global step from `x_before` to the iterate $`x^+`$, with
    /// the $`z`$ of the local step before it: primal $`|W(Dx^+ - z)|^2`$ plus dual
    /// $`|WD(x^+ - x_{before})|^2`$ (Zhang et al. 2019's code's `comb_residual`, weighted).
    pub fn combined_residual(&self, x_before: &[f64]) -> f64 {
        let mut change = vec![0.0; x_before.len()];
        for ((d, x), x0) in change.iter_mut().zip(&self.x).zip(x_before) {
            *d = x - x0;
        }
        self.z
            .iter()
            .zip(&self.omega)
            .enumerate()
            .map(|(i, (z, &w))| {
                let primal = w * (self.d.apply_row(i, &self.x) - z);
                let dual = w * self.d.apply_row(i, &change);
                primal.norm_squared() + dual.norm_squared()
            })
            .sum()
    }

    /// Eq. (40): $`(M + dt^2 D^\top W^\top W D)\,x = M\tilde x + dt^2 D^\top W^\top W (z - \bar u)`$;
    /// forms the right-hand side in $`x`$, for the prefactored solve of the step.
    pub fn global_rhs(&mut self) {
        global_rhs_of(
            &self.d,
            &self.m_x_tilde,
            &self.z,
            &self.u_bar,
            &self.dt2_omega2,
            &mut self.x,
        );
    }
}

/// ADMM-PD (Algorithm 4 as printed) with a fixed number of iterations per step.
#[derive(Debug, Clone)]
pub struct AdmmPd {
    system: MassSpringSystem,
    dt: f64,
    iterations: usize,
    /// $`A = M + dt^2 D^\top W^\top W D`$ of each stage step, factored once (line 1.5).
    a: PerStageStep<GlobalSolve>,
    /// The current stage's $`dt`$ ($`\tau`$), s.
    tau: f64,
    iterate: AdmmIterate,
    /// Where each step starts: $`x^0 = \tilde x`$ (line 2.1) by default.
    start: StepStart,
    /// When a step stops iterating, and the iterations steps took.
    convergence: Convergence,
}

impl AdmmPd {
    /// Algorithm 4, lines 1.1-1.5, with $`\omega_i = \sqrt{k_i}`$. Needs every stiffness > 0,
    /// `dt` > 0 and `iterations` >= 1.
    pub fn new(system: &MassSpringSystem, dt: f64, iterations: usize) -> Result<Self> {
        require_positive("dt", dt)?;
        system.require_positive_stiffness()?;
        system.require_undamped_springs()?;
        if iterations == 0 {
            return Err(Error::invalid("iterations", 0, "an integer >= 1"));
        }
        let omega = default_omega(system);
        let omega2: Vec<f64> = omega.iter().map(|w| w * w).collect();
        Ok(Self {
            system: system.clone(),
            dt,
            iterations,
            a: PerStageStep::new(dt, GlobalSolve::new(system, dt, &omega2)?),
            tau: dt,
            iterate: AdmmIterate::new(system, dt, omega),
            start: StepStart::new(FirstIterate::InertialPrediction),
            convergence: Convergence::default(),
        })
    }

    /// The same solver starting each step at `first_iterate` ([`crate::integrators::first_iterate`]); the
    /// default, the inertial prediction, is line 2.1's $`x^0 = \tilde x`$ bit for bit.
    pub fn with_first_iterate(mut self, first_iterate: FirstIterate) -> Self {
        self.start = StepStart::new(first_iterate);
        self
    }

    /// Iterations per step.
    pub fn iterations(&self) -> usize {
        self.iterations
    }

    /// Where each step starts.
    pub fn first_iterate(&self) -> FirstIterate {
        self.start.rule()
    }

    /// Whether each step runs its full count of iterations ([`crate::integrators::stopping::Stopping::Count`]),
    /// as a batch of runs does ([`crate::solvers::batch`]).
    pub fn counts_iterations(&self) -> bool {
        self.convergence.stopping() == crate::integrators::stopping::Stopping::Count
    }

    /// The iteration's per-spring data ($`D`$, $`dt^2\omega_i^2`$) at the solver's own step.
    pub fn iterate_data(&self) -> &AdmmIterate {
        &self.iterate
    }

    /// $`A`$ of the solver's own step, prefactored (line 1.5).
    pub fn own_step(&self) -> &GlobalSolve {
        self.a.own()
    }

    /// Lines 2.4-2.7 at the current iterate: $`z`$ and $`\bar u`$ (Eqs 41-42).
    pub fn local_step(&mut self) {
        self.iterate.local_step();
    }

    /// The global step at the current iterate: Eq (40)'s right-hand side and the prefactored
    /// solve.
    pub fn global_step(&mut self) {
        self.iterate.global_rhs();
        self.a
            .current()
            .solve(&mut self.iterate.x, &self.iterate.x_n);
    }

    /// Makes `tau` the current stage step: its matrix (factored if new) and factors.
    fn select(&mut self, tau: f64) -> Result<()> {
        let (system, omega) = (&self.system, self.iterate.omega());
        self.a.select(tau, |tau| {
            let omega2: Vec<f64> = omega.iter().map(|w| w * w).collect();
            GlobalSolve::new(system, tau, &omega2)
        })?;
        if tau != self.tau {
            self.tau = tau;
            self.iterate.set_step(tau);
        }
        Ok(())
    }
}

impl TimeStepper for AdmmPd {
    fn name(&self) -> String {
        format!(
            "ADMM-PD ({})",
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

impl MinimizingSolver for AdmmPd {
    /// Algorithm 4, run-time part.
    // region: step
    fn solve(&mut self, problem: &StageProblem, state: &mut State) -> Result<()> {
        let dt = problem.tau;
        self.select(dt)?;
        let it = &mut self.iterate;
        // 2.1: x̃, and x⁰ = x̃ (or another first iterate).
        it.predict(&self.system, state, dt);
        to_columns(
            self.start.first_iterate(&self.system, state, problem),
            &mut it.x,
        );
        // 2.2: ū = 0 every step.
        it.u_bar.fill(Vec3::zeros());
        self.convergence
            .begin_stage(&self.system, state, problem.tau, nodes_of_columns(&it.x));
        // 2.3-2.10, stopping early only in the tolerance mode.
        for _ in 0..self.iterations {
            self.local_step();
            self.global_step();
            if self
                .convergence
                .converged(nodes_of_columns(&self.iterate.x))
            {
                break;
            }
        }
        self.convergence.end_step(0);
        // 2.11
        finish_step(state, &self.iterate.x, dt);
        Ok(())
    }
    // endregion: step

    fn prepare(&mut self, tau: f64) -> Result<()> {
        self.select(tau)
    }
}
