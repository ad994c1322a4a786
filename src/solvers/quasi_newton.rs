//! Quasi-Newton with L-BFGS (Liu, Bouaziz & Kavan 2017, "Quasi-Newton Methods for Real-Time
//! Simulation of Hyperelastic Materials", ACM TOG 36(3); reference code
//! ltt1598/Quasi-Newton-Methods-for-Real-time-Simulation-of-Hyperelastic-Materials).
//!
//! The step minimises the incremental potential of thesis Eq 20,
//! ```math
//! g(x) = \frac{1}{2h^2}(x - y)^\top M (x - y) + E(x),
//! ```
//! ([`crate::solvers::backward_euler::incremental_potential`], gravity in $`E`$), whose minimiser is the
//! Backward Euler step. The paper's observation is that Projective Dynamics is a quasi-Newton
//! method whose Hessian approximation is the constant, prefactored
//! $`\nabla^2 g \approx \frac{1}{h^2}M + L`$, $`L`$ the stiffness-weighted Laplacian (for
//! springs, thesis Eq 25). Its L-BFGS loop (Algorithm 2 of the TOG version; the numbering is
//! from secondary evidence, the body was not read) keeps that matrix as the *initial* Hessian
//! $`H_0`$ of L-BFGS and corrects it with the last $`m`$ pairs
//! $`s_i = x_{i+1} - x_i`$, $`t_i = \nabla g(x_{i+1}) - \nabla g(x_i)`$ by the two-loop
//! recursion (written here in Nocedal & Wright's form, with $`t`$ for their $`y`$, which is the
//! inertial prediction here, and $`\rho_i`$ for the inverse curvature):
//! ```math
//! \begin{aligned}
//! q &\leftarrow -\nabla g(x_k)\\
//! \text{for } i = k-1, \dots, k-m:&\quad \rho_i = 1/(t_i^\top s_i),\quad
//!   \zeta_i = \rho_i\,s_i^\top q,\quad q \leftarrow q - \zeta_i t_i\\
//! r &\leftarrow H_0^{-1} q\\
//! \text{for } i = k-m, \dots, k-1:&\quad \eta = \rho_i\,t_i^\top r,\quad
//!   r \leftarrow r + s_i(\zeta_i - \eta)\\
//! d &= r,\qquad x_{k+1} = x_k + \alpha\,d
//! \end{aligned}
//! ```
//! with $`\alpha`$ from a backtracking line search on $`g`$ that starts at 1 and multiplies by
//! $`\beta`$ until the Armijo condition
//! $`g(x_k + \alpha d) \le g(x_k) + \gamma\,\alpha\,\nabla g(x_k)^\top d`$ holds. The first
//! iteration, with no pairs, is one Projective-Dynamics (Liu 2013) local/global iteration when
//! the line search accepts $`\alpha = 1`$ (tested against [`crate::solvers::fast_mass_spring`]). Here
//! $`H_0^{-1}q = h^2 A^{-1}q`$ with $`A = M + h^2 L`$ the matrix of thesis Algorithm 3 line 1.4,
//! prefactored once by [`GlobalSolve`], the fixed nodes eliminated through thesis Eqs 43-47
//! with a zero update on them ([`crate::model::boundary`]).
//!
//! Parameters ([`LbfgsParams`]): the window $`m = 5`$ and the line search's $`\gamma = 0.03`$,
//! $`\beta = 0.5`$ and smallest step $`10^{-5}`$ are the defaults of the authors' code
//! (`AntTweakBarWrapper::DefaultSettings`, and the loop of
//! `linesearchWithPrefetchedEnergyAndGradientComputing`); the initial guess
//! $`x_0 = y + h^2M^{-1}f_{ext}`$ is the paper's inertial prediction. Nothing is carried from
//! one step to the next: the history starts empty every step.
//!
//! What differs from the paper:
//! - A pair with $`t_i^\top s_i`$ not positive beyond round-off is not stored (the standard
//!   safeguard that keeps the L-BFGS matrix positive definite; compressed springs make $`g`$
//!   non-convex).
//! - The line search compares $`g(x_k + \alpha d) - g(x_k)`$ computed term by term
//!   ([`potential_change`]), not as a difference of two totals: near the solution the totals'
//!   round-off (about $`10^{-16}`$ of the gravity term's ~100 J) exceeds the decrease, and the
//!   method would stall above the 1e-9 m the tests ask for.
//! - The authors' code stops iterating once the direction is small relative to the positions;
//!   here the step ends when the direction's largest component is below [`ROUND_OFF_STEP`]
//!   (1e-13 m, the oracle's own tolerance), so that iterations past convergence cost nothing
//!   and move nothing.
//! - When no step of at least $`10^{-5}`$ satisfies the Armijo condition, the authors' code takes
//!   a zero step and goes on; here the step fails with [`Error::NotConverged`], naming the
//!   iteration (it has not happened on the thesis rope's grid of time steps and stiffnesses).
//!
//! Under an optimization integrator ([`crate::integrators::optimization_integrator`]) each stage is the same
//! loop with $`h`$ the stage's $`\tau`$ and $`(x_n, v_n)`$ its pseudo-state; $`A`$ is factored
//! once per distinct $`\tau`$.
//!
//! # Measured on the thesis rope (`tests/newer_solvers.rs`)
//! At dt = 1e-2, k = 1e6, one step from a moving state (10 converged steps from rest), L-BFGS
//! needs 92 iterations for a gap of 1e-6 m to the converged Backward Euler step and 188 for
//! 1e-9 m; its base, Liu 2013 with the same prefactored matrix, needs 1828 for 1e-6 m from the
//! same start (the inertial prediction), 19.9 times more (1582 from $`x_n`$, the start the
//! thesis's tables read Algorithm 3 with). The window matters: 1e-6 m takes 204 iterations with $`m = 2`$, 44 with 10 and 29 with
//! the full 24 unknowns. What slows both is the Laplacian's isotropic stiffness: across a
//! spring's axis $`H_0`$ has $`k`$, the true Hessian $`k(1 - l_0/l)`$, smaller by the strain.

use crate::error::{Error, Result};
use crate::integrators::first_iterate::{FirstIterate, StepStart};
use crate::integrators::optimization_integrator::{MinimizingSolver, PerStageStep, StageProblem};
use crate::integrators::stopping::Convergence;
use crate::integrators::time_stepper::TimeStepper;
use crate::model::system::{MassSpringSystem, State, Vec3};
use crate::solvers::backward_euler::inertia;
use crate::solvers::projective::{finish_step, node_of_columns, to_columns, GlobalSolve};
use std::collections::VecDeque;

/// A search direction whose largest component is below this, m, ends the step: the iterate has
/// converged to round-off (the converged Backward Euler step's default tolerance).
pub const ROUND_OFF_STEP: f64 = 1e-13;

/// The smallest step length the line search tries (the authors' code).
pub const MIN_STEP_LENGTH: f64 = 1e-5;

/// The parameters of Liu, Bouaziz & Kavan 2017.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct LbfgsParams {
    /// The L-BFGS history window $`m`$, >= 1.
    pub window: usize,
    /// The Armijo sufficient-decrease constant $`\gamma`$, in (0, 1).
    pub gamma: f64,
    /// The backtracking factor $`\beta`$, in (0, 1).
    pub beta: f64,
}

impl Default for LbfgsParams {
    /// $`m = 5`$, $`\gamma = 0.03`$, $`\beta = 0.5`$: the authors' code's defaults.
    fn default() -> Self {
        Self {
            window: 5,
            gamma: 0.03,
            beta: 0.5,
        }
    }
}

impl LbfgsParams {
    /// Rejects a zero window and a $`\gamma`$ or $`\beta`$ outside (0, 1).
    pub fn validate(&self) -> Result<()> {
        if self.window == 0 {
            return Err(Error::invalid("window", 0, "an integer >= 1"));
        }
        for (field, value) in [("gamma", self.gamma), ("beta", self.beta)] {
            if !(value > 0.0 && value < 1.0) {
                return Err(Error::invalid(field, value, "a number > 0 and < 1"));
            }
        }
        Ok(())
    }
}

/// This crate's device, not the paper's: $`g(x') - g(x)`$ for the incremental potential of
/// thesis Eq 20, term by term from the differences $`\delta_i = x'_i - x_i`$, which are exact in floating point for
/// nearby points: $`\frac{m_i}{2h^2}\,\delta_i\cdot(\delta_i + 2(x_i - y_i))`$ and
/// $`-m_i\,g\cdot\delta_i`$ per node, and $`\frac{k}{2}\,\Delta l\,(\Delta l + 2(l - l_0))`$ per
/// spring with $`\Delta l = l' - l = \delta q\cdot(q' + q)/(l' + l)`$ and
/// $`\delta q = \delta_a - \delta_b`$; `y` $`= x_n + h v_n`$. In joules. Near a minimiser the
/// first-order terms cancel and the change is the far smaller second-order one; built from the
/// differences, each term keeps its relative precision, so the sum resolves changes down to
/// about $`10^{-16}`$ of the first-order terms instead of $`10^{-16}`$ of the potential.
pub fn potential_change(
    system: &MassSpringSystem,
    y: &[Vec3],
    x: &[Vec3],
    x_new: &[Vec3],
    dt: f64,
) -> f64 {
    let gravity = system.gravity();
    let delta = |i: usize| x_new[i] - x[i];
    let nodes: f64 = system
        .nodes()
        .iter()
        .enumerate()
        .map(|(i, node)| {
            let d = delta(i);
            let inertia = 0.5 * node.mass * d.dot(&(d + 2.0 * (x[i] - y[i]))) / (dt * dt);
            inertia - node.mass * gravity.dot(&d)
        })
        .sum();
    let springs: f64 = system
        .springs()
        .iter()
        .map(|s| {
            let q = x[s.a] - x[s.b];
            let delta_q = delta(s.a) - delta(s.b);
            let q_new = q + delta_q;
            let (l, l_new) = (q.norm(), q_new.norm());
            let delta_l = if l + l_new > 0.0 {
                delta_q.dot(&(q_new + q)) / (l + l_new)
            } else {
                0.0
            };
            0.5 * s.stiffness * delta_l * (delta_l + 2.0 * (l - s.rest_length))
        })
        .sum();
    nodes + springs
}

/// $`\nabla g(x) = \frac{1}{h^2}M(x - y) - F(x)`$ of the incremental potential of thesis
/// Eq 20 (gravity in $`F`$), column-major into `gradient`, zero on the fixed nodes, whose
/// unknowns the solve eliminates; `forces` is scratch, one entry per node.
pub fn potential_gradient(
    system: &MassSpringSystem,
    y: &[Vec3],
    x: &[Vec3],
    dt: f64,
    forces: &mut [Vec3],
    gradient: &mut [f64],
) {
    let n = x.len();
    let h2 = dt * dt;
    system.forces(x, forces);
    for (i, node) in system.nodes().iter().enumerate() {
        let g = node.mass * (x[i] - y[i]) / h2 - forces[i];
        for c in 0..3 {
            gradient[c * n + i] = if node.fixed { 0.0 } else { g[c] };
        }
    }
}

/// One stored L-BFGS pair with its $`\rho_i = 1/(t_i^\top s_i)`$ and the $`\zeta_i`$ of the
/// current two-loop recursion.
#[derive(Debug, Clone)]
struct Pair {
    s: Vec<f64>,
    t: Vec<f64>,
    rho: f64,
    zeta: f64,
}

impl Pair {
    fn zeros(len: usize) -> Self {
        Self {
            s: vec![0.0; len],
            t: vec![0.0; len],
            rho: 0.0,
            zeta: 0.0,
        }
    }

    /// Makes this the pair of an iteration from `x` to `x_new` (column-major $`s`$); false when
    /// its curvature $`t^\top s`$ is not positive beyond round-off, and the pair is not kept.
    fn set(&mut self, x: &[Vec3], x_new: &[Vec3], gradient: &[f64], gradient_new: &[f64]) -> bool {
        let n = x.len();
        for (i, (x_new, x)) in x_new.iter().zip(x).enumerate() {
            for c in 0..3 {
                self.s[c * n + i] = x_new[c] - x[c];
            }
        }
        for (t, (a, b)) in self.t.iter_mut().zip(gradient_new.iter().zip(gradient)) {
            *t = a - b;
        }
        let curvature = dot(&self.t, &self.s);
        self.rho = 1.0 / curvature;
        curvature > 1e-12 * dot(&self.s, &self.s).sqrt() * dot(&self.t, &self.t).sqrt()
    }
}

fn dot(a: &[f64], b: &[f64]) -> f64 {
    a.iter().zip(b).map(|(a, b)| a * b).sum()
}

/// L-BFGS on the incremental potential with the Projective-Dynamics matrix as initial Hessian
/// (Liu, Bouaziz & Kavan 2017), `iterations` L-BFGS iterations per step.
#[derive(Debug, Clone)]
pub struct Lbfgs {
    system: MassSpringSystem,
    dt: f64,
    iterations: usize,
    params: LbfgsParams,
    /// $`A = M + h^2 L`$ of each stage step with the fixed nodes imposed, factored once:
    /// $`H_0 = A/h^2`$.
    global: PerStageStep<GlobalSolve>,
    /// The current stage's $`h`$ ($`\tau`$), s.
    tau: f64,
    /// Zeros in the layout of the global solve: the update of the fixed nodes.
    zeros: Vec<f64>,
    forces: Vec<Vec3>,
    /// The step length $`\alpha`$ of each iteration of the last step.
    step_lengths: Vec<f64>,
    /// Where each step starts: the inertial prediction, the authors' code's, by default.
    start: StepStart,
    /// When a step stops iterating, and the iterations steps took, with the line-search
    /// trials after each iteration's first as their extra work.
    convergence: Convergence,
}

impl Lbfgs {
    /// L-BFGS for `system` with time step `dt` (s, > 0), `iterations` (>= 1) L-BFGS iterations
    /// per step and the paper's `params`.
    pub fn new(
        system: &MassSpringSystem,
        dt: f64,
        iterations: usize,
        params: LbfgsParams,
    ) -> Result<Self> {
        params.validate()?;
        if iterations == 0 {
            return Err(Error::invalid("iterations", 0, "an integer >= 1"));
        }
        let stiffness: Vec<f64> = system.springs().iter().map(|s| s.stiffness).collect();
        let global = GlobalSolve::new(system, dt, &stiffness)?;
        let n = system.len();
        Ok(Self {
            system: system.clone(),
            dt,
            iterations,
            params,
            global: PerStageStep::new(dt, global),
            tau: dt,
            zeros: vec![0.0; 3 * n],
            forces: vec![Vec3::zeros(); n],
            step_lengths: Vec::new(),
            start: StepStart::new(FirstIterate::InertialPrediction),
            convergence: Convergence::default(),
        })
    }

    /// The same solver starting each step at `first_iterate` ([`crate::integrators::first_iterate`]).
    pub fn with_first_iterate(mut self, first_iterate: FirstIterate) -> Self {
        self.start = StepStart::new(first_iterate);
        self
    }

    /// The step length $`\alpha`$ the line search accepted at each iteration of the last step
    /// (fewer than the iterations when the step ended at round-off).
    pub fn step_lengths(&self) -> &[f64] {
        &self.step_lengths
    }

    /// $`\nabla g(x)`$ ([`potential_gradient`]) with the solver's force buffer.
    fn gradient(&mut self, x: &[Vec3], y: &[Vec3], gradient: &mut [f64]) {
        potential_gradient(&self.system, y, x, self.tau, &mut self.forces, gradient);
    }

    /// Makes `tau` the current stage step, factoring its matrix if new.
    fn select(&mut self, tau: f64) -> Result<()> {
        let system = &self.system;
        self.global.select(tau, |tau| {
            let stiffness: Vec<f64> = system.springs().iter().map(|s| s.stiffness).collect();
            GlobalSolve::new(system, tau, &stiffness)
        })?;
        self.tau = tau;
        Ok(())
    }

    /// [Liu 2017, Alg. 2] (unverified: the TOG version's numbering, from secondary evidence; checked against ltt1598 `simulation.cpp`) The two-loop recursion: $`d = -H^{-1}\nabla g`$ with
    /// $`H_0^{-1} q = h^2 A^{-1} q`$ and the stored pairs, oldest first in `history`.
    fn direction(&self, gradient: &[f64], history: &mut VecDeque<Pair>, d: &mut [f64]) {
        for (v, g) in d.iter_mut().zip(gradient) {
            *v = -g;
        }
        for pair in history.iter_mut().rev() {
            pair.zeta = pair.rho * dot(&pair.s, d);
            for (q, t) in d.iter_mut().zip(&pair.t) {
                *q -= pair.zeta * t;
            }
        }
        let h2 = self.tau * self.tau;
        for q in d.iter_mut() {
            *q *= h2;
        }
        self.global.current().solve(d, &self.zeros);
        for pair in history.iter() {
            let eta = pair.rho * dot(&pair.t, d);
            for (r, s) in d.iter_mut().zip(&pair.s) {
                *r += s * (pair.zeta - eta);
            }
        }
    }

    /// [Liu 2017, Alg. 2] (unverified: the TOG version's numbering, from secondary evidence; checked against ltt1598 `simulation.cpp`) Backtracking from $`\alpha = 1`$ by $`\beta`$ until
    /// $`g(x + \alpha d) - g(x) \le \gamma\,\alpha\,\nabla g^\top d`$; returns $`\alpha`$ with
    /// the accepted point in `trial`, or `None` below [`MIN_STEP_LENGTH`].
    fn line_search(
        &self,
        x: &[Vec3],
        y: &[Vec3],
        d: &[f64],
        slope: f64,
        trial: &mut [Vec3],
    ) -> Option<(f64, u64)> {
        let n = x.len();
        let mut alpha = 1.0;
        let mut trials = 0;
        while alpha >= MIN_STEP_LENGTH {
            trials += 1;
            for (i, (trial, x)) in trial.iter_mut().zip(x).enumerate() {
                *trial = x + alpha * node_of_columns(d, n, i);
            }
            let change = potential_change(&self.system, y, x, trial, self.tau);
            if change <= self.params.gamma * alpha * slope {
                return Some((alpha, trials));
            }
            alpha *= self.params.beta;
        }
        None
    }
}

impl TimeStepper for Lbfgs {
    fn name(&self) -> String {
        format!(
            "L-BFGS ({}, window {}, gamma {}, beta {})",
            self.convergence
                .iterations_label(self.iterations, "iterations"),
            self.params.window,
            self.params.gamma,
            self.params.beta
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

impl MinimizingSolver for Lbfgs {
    /// [Liu 2017, Alg. 2] (unverified: the TOG version's numbering, from secondary evidence; checked against ltt1598 `simulation.cpp`) From the inertial prediction, `iterations` L-BFGS iterations with the
    /// Projective-Dynamics matrix as $`H_0`$ and the Armijo line search; then
    /// $`v = (x - x_n)/h`$.
    // region: step
    fn solve(&mut self, problem: &StageProblem, state: &mut State) -> Result<()> {
        self.select(problem.tau)?;
        let (dt, n) = (problem.tau, state.x.len());
        // y = xⁿ + h·vⁿ of Eq 20 (gravity is in E); x₀ = y + h²M⁻¹f_ext by default, the
        // authors' code's start.
        let y = inertia(state, dt);
        let mut x = self
            .start
            .first_iterate(&self.system, state, problem)
            .to_vec();
        let mut gradient = vec![0.0; 3 * n];
        self.gradient(&x, &y, &mut gradient);
        let mut history: VecDeque<Pair> = VecDeque::with_capacity(self.params.window);
        // Scratch: the direction, the trial point, the next gradient, the next pair.
        let (mut d, mut x_new, mut gradient_new) = (vec![0.0; 3 * n], x.clone(), gradient.clone());
        let mut spare = Pair::zeros(3 * n);
        self.step_lengths.clear();
        self.convergence
            .begin_stage(&self.system, state, problem.tau, x.iter().copied());
        let mut extra_trials = 0;
        // Stopping early in the tolerance mode, or at a direction below round-off.
        for iteration in 0..self.iterations {
            self.direction(&gradient, &mut history, &mut d);
            let slope = dot(&gradient, &d);
            let largest = d.iter().fold(0.0_f64, |m, v| m.max(v.abs()));
            if largest < ROUND_OFF_STEP {
                self.convergence.stalled();
                break;
            }
            let Some((alpha, trials)) = self.line_search(&x, &y, &d, slope, &mut x_new) else {
                return Err(Error::NotConverged {
                    what: "L-BFGS line search".into(),
                    detail: format!(
                        "no step >= {MIN_STEP_LENGTH:e} decreases the potential at iteration {} \
                         (direction {largest:e} m, slope {slope:e} J)",
                        iteration + 1
                    ),
                });
            };
            self.step_lengths.push(alpha);
            extra_trials += trials - 1;
            self.gradient(&x_new, &y, &mut gradient_new);
            if spare.set(&x, &x_new, &gradient, &gradient_new) {
                let oldest = if history.len() == self.params.window {
                    history.pop_front()
                } else {
                    None
                };
                let recycled = oldest.unwrap_or_else(|| Pair::zeros(3 * n));
                history.push_back(std::mem::replace(&mut spare, recycled));
            }
            std::mem::swap(&mut x, &mut x_new);
            std::mem::swap(&mut gradient, &mut gradient_new);
            if self.convergence.converged(x.iter().copied()) {
                break;
            }
        }
        self.convergence.end_step(extra_trials);
        if !x.iter().all(|p| p.iter().all(|c| c.is_finite())) {
            return Err(Error::NotConverged {
                what: "L-BFGS".into(),
                detail: "the iterate is no longer finite".into(),
            });
        }
        let mut columns = vec![0.0; 3 * n];
        to_columns(&x, &mut columns);
        finish_step(state, &columns, dt);
        Ok(())
    }
    // endregion: step

    fn prepare(&mut self, tau: f64) -> Result<()> {
        self.select(tau)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::model::scene::thesis_rope;
    use crate::solvers::backward_euler::incremental_potential;

    /// The term-by-term difference equals the difference of the totals where the totals are
    /// precise (a large change).
    #[test]
    fn potential_change_matches_the_difference_of_totals() {
        let rope = thesis_rope(1e3).unwrap();
        let x: Vec<Vec3> = rope.nodes().iter().map(|n| n.position).collect();
        let y: Vec<Vec3> = x.iter().map(|p| p + Vec3::new(0.01, -0.02, 0.0)).collect();
        let x_new: Vec<Vec3> = x
            .iter()
            .enumerate()
            .map(|(i, p)| p + Vec3::new(0.0, -0.05 * (i as f64).sin(), 0.01))
            .collect();
        let dt = 1e-2;
        let exact =
            incremental_potential(&rope, &y, &x_new, dt) - incremental_potential(&rope, &y, &x, dt);
        let change = potential_change(&rope, &y, &x, &x_new, dt);
        assert!(
            (change - exact).abs() < 1e-10 * exact.abs(),
            "{change} vs {exact}"
        );
    }
}
