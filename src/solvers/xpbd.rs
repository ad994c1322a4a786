//! Extended Position-Based Dynamics, XPBD (thesis §2.2.1, Algorithm 2, Eqs 15-19; the rope's
//! distance constraints of §3.3, Eqs 48-51; Macklin, Müller & Chentanez 2016).
//!
//! Each spring $`j`$ is a compliant distance constraint $`C_j = |x_1 - x_2| - l_0`$ (Eq 48, the
//! spring's deformation of Eq 1) with compliance $`\alpha_j = 1/k_j`$ (the inverse of the
//! spring's stiffness in N/m). The compliant constraint force of Eq 15,
//! $`\lambda = -\alpha^{-1}C(x)`$, turns the equations of motion into Eq 16,
//! $`M a - \nabla C^\top\lambda = 0`$, $`C(x) + \alpha\lambda = 0`$. Discretised with the
//! time-step-scaled compliance $`\tilde\alpha = \alpha/dt^2`$ and solved by a simplified Newton
//! method, one constraint at a time, they give the linear system of Eq 17 and its solution for
//! a single constraint, Eq 18 ([`delta_lambda`]), and the position update of Eq 19
//! ([`delta_x`]). For the rope's distance constraint the gradient is the unit vector of Eq 49
//! ([`spring::constraint_gradient`]), so $`\nabla C M^{-1}\nabla C^\top = w_1 + w_2`$ (Eq 50,
//! [`generalized_inverse_mass`]) and Eq 19 becomes Eq 51.
//!
//! [`Xpbd::step`] is Algorithm 2 line for line: predict $`\tilde x`$ (line 1), start from it
//! (line 2) with $`\lambda = 0`$ (line 3, every step), sweep the springs Gauss-Seidel style in
//! index order $`0 \to 8`$ for a fixed number of iterations (lines 4-12), and take the velocity
//! from the position change (line 14). The sweep order is part of the method: each projection
//! sees the positions its predecessors in the sweep have already moved. Fixed nodes have inverse
//! mass $`w = 0`$ (thesis §3.3, after Müller 2007), so Eq 51 never moves them; they are also left
//! out of the prediction, so they stay exactly where they are even if a velocity was given.
//!
//! With zero compliance ([`Xpbd::with_compliance`] and `alpha = 0`) Eq 18 is PBD's Eq 13 and
//! the method is PBD with stiffness factor 1 ([`crate::solvers::pbd`]), as §2.2.1 observes.
//!
//! # What XPBD converges to
//!
//! Many iterations do *not* reach the Backward Euler step that minimises Eq 20 (the
//! [`crate::solvers::converged_stage::converged_step`] oracle); they reach a nearby point. Macklin et al.
//! (2016) write the discrete equations of motion as
//! $`g(x,\lambda) = M(x - \tilde x) - \nabla C(x)^\top\lambda = 0`$ and
//! $`h(x,\lambda) = C(x) + \tilde\alpha\lambda = 0`$ (their §3, the discretised Eq 16,
//! [`residuals`]); a solution of both is exactly the minimiser of Eq 20. Their full Newton system
//! needs the Hessian of the constraints in
//! $`K = M - \sum_j \partial^2 C_j/\partial x^2\,\lambda_j`$ and the residual $`g`$ on the
//! right-hand side. XPBD replaces $`K`$ by $`M`$ and assumes $`g = 0`$ (their simplified system),
//! which holds at $`x_0 = \tilde x`$, $`\lambda_0 = 0`$ and stays true only while the constraint
//! gradients do not change. With the simplification, the iteration keeps
//! $`M(x - \tilde x) = \sum_i \nabla C(x_i)^\top\Delta\lambda_i`$, a sum of corrections along the
//! gradients of the *iterates*, while $`g = 0`$ needs $`\nabla C(x)^\top\lambda`$ along the
//! gradient of the *final* point. Its fixed point therefore satisfies $`h = 0`$ (each constraint's
//! own equation, which Eq 18 solves) but not $`g = 0`$: the iterations converge, to a point that
//! differs from the Backward Euler step by an amount of the order of the gradients' rotation during
//! the step times the constraint impulses. More iterations cannot remove it. The test
//! `xpbd_does_not_reach_the_converged_backward_euler_step` measures this gap on the thesis rope
//! (k = 1e6, one step from a moving state): with 100 to 10000 iterations it stays at 2.4e-8 m at
//! dt = 1e-3 (1.3e-5 of the step's displacement) and from 1000 iterations on at 1.4e-4 m at
//! dt = 1e-2 (0.8 %), while $`h`$ falls to round-off and $`g`$ does not.
//!
//! # Symmetry
//!
//! The sweep in index order is not mirror-symmetric: each projection sees the spring before it
//! already corrected and the one after it not yet. On the thesis rope, whose scene and Backward
//! Euler run are symmetric about its middle to round-off, XPBD's two halves differ after 2 s of
//! simulation, the more the fewer the iterations and the larger the step; sweeping 8 → 0
//! instead gives exactly the mirror image. The test `xpbd_index_order_breaks_the_mirror_symmetry`
//! (`tests/xpbd.rs`) measures both.

use crate::error::{require_non_negative, require_positive, Error, Result};
use crate::integrators::stopping::{Convergence, FixedPoint};
use crate::integrators::time_stepper::TimeStepper;
use crate::model::lanes::{self, Lane};
use crate::model::spring;
use crate::model::system::{MassSpringSystem, State, Vec3};
use crate::solvers::incidence::{Ends, SpringGraph};
use nalgebra::Vector3;

/// Eq. (18): $`\tilde\alpha = \alpha/dt^2`$, the time-step-scaled compliance that Eqs 17-18
/// use (defined under Eq 18); with $`\alpha`$ in m/N it is in 1/kg, the units of $`w = 1/m`$.
pub fn alpha_tilde(alpha: f64, dt: f64) -> f64 {
    alpha / (dt * dt)
}

/// Eq. (50):
/// $`\nabla C\,M^{-1}\nabla C^\top = w_1|\nabla_{x_1}C|^2 + w_2|\nabla_{x_2}C|^2 = w_1 + w_2`$ for
/// a distance constraint, whose gradient (Eq 49) is a unit vector for each node; $`w_i = 1/m_i`$,
/// and 0 for a fixed node.
pub fn generalized_inverse_mass(w1: f64, w2: f64) -> f64 {
    w1 + w2
}

/// Eq. (18)'s denominator inverted, $`1/(\nabla C_j M^{-1} \nabla C_j^\top + \tilde\alpha_j)`$,
/// given `w` $`= \nabla C_j M^{-1}\nabla C_j^\top`$ (Eq 50). It is fixed for a spring within a
/// run, so the solver computes it once and [`delta_lambda`] multiplies by it: a division in the
/// Gauss-Seidel chain costs about as much as the rest of a constraint's update.
///
/// A constraint that nothing can move ($`w = 0`$: both ends fixed) and that has no compliance has
/// a zero denominator; it gets 0, so that its $`\Delta\lambda = 0`$ and it is left alone.
pub fn inverse_denominator(w: f64, alpha_tilde: f64) -> f64 {
    let denominator = w + alpha_tilde;
    if denominator > 0.0 {
        1.0 / denominator
    } else {
        0.0
    }
}

/// Eqs. (17), (18):
/// $`\Delta\lambda = \dfrac{-C_j(x_i) - \tilde\alpha_j\lambda_{ij}}{\nabla C_j M^{-1} \nabla C_j^\top + \tilde\alpha_j}`$,
/// Eq 17 solved for one constraint $`j`$ given its value `c`, its current multiplier `lambda` and
/// the inverted denominator of [`inverse_denominator`].
pub fn delta_lambda<T: Lane>(c: T, alpha_tilde: T, lambda: T, inverse_denominator: T) -> T {
    (-c - alpha_tilde * lambda) * inverse_denominator
}

/// Eqs. (19), (51): $`\Delta x = M^{-1}\nabla C^\top\Delta\lambda`$, for a distance constraint
/// $`\Delta x_1 = w_1\nabla_{x_1}C\,\Delta\lambda`$ and
/// $`\Delta x_2 = w_2\nabla_{x_2}C\,\Delta\lambda = -w_2\nabla_{x_1}C\,\Delta\lambda`$, given
/// `grad` $`= \nabla_{x_1}C`$ (Eq 49).
pub fn delta_x<T: Lane>(
    grad: &Vector3<T>,
    w1: T,
    w2: T,
    delta_lambda: T,
) -> (Vector3<T>, Vector3<T>) {
    (grad * (w1 * delta_lambda), -grad * (w2 * delta_lambda))
}

/// The residuals of the discretised Eq 16 at an iterate, in Macklin et al. (2016)'s form.
#[derive(Debug, Clone, PartialEq)]
pub struct Residuals {
    /// $`g_i = m_i(x_i - \tilde x_i) - \sum_j \nabla_{x_i}C_j(x)\,\lambda_j`$ per free node (0 on
    /// fixed nodes, whose equation of motion is replaced by the constraint that fixes them), N·s².
    pub g: Vec<Vec3>,
    /// $`h_j = C_j(x) + \tilde\alpha_j\lambda_j`$ per spring, m.
    pub h: Vec<f64>,
}

/// Eq. (16): $`M a - \nabla C^\top\lambda = 0`$, $`C(x) + \alpha\lambda = 0`$, discretised with
/// $`a = (x - \tilde x)/dt^2`$ and the multiplier in impulse units as
/// $`g = M(x - \tilde x) - \nabla C(x)^\top\lambda`$ and $`h = C(x) + \tilde\alpha\lambda`$
/// (Macklin et al. 2016, §3). Both vanish exactly at the minimiser of Eq 20; XPBD drives
/// $`h`$ to zero but not $`g`$ (see the module documentation).
pub fn residuals(
    system: &MassSpringSystem,
    x: &[Vec3],
    x_tilde: &[Vec3],
    lambda: &[f64],
    alpha_tilde: &[f64],
) -> Residuals {
    let mut g: Vec<Vec3> = system
        .nodes()
        .iter()
        .zip(x.iter().zip(x_tilde))
        .map(|(node, (x, x_tilde))| node.mass * (x - x_tilde))
        .collect();
    let h = system
        .springs()
        .iter()
        .zip(lambda.iter().zip(alpha_tilde))
        .map(|(s, (&lambda, &alpha_tilde))| {
            let grad = spring::constraint_gradient(&x[s.a], &x[s.b]);
            g[s.a] -= grad * lambda;
            g[s.b] += grad * lambda;
            spring::constraint(&x[s.a], &x[s.b], s.rest_length) + alpha_tilde * lambda
        })
        .collect();
    for (g, node) in g.iter_mut().zip(system.nodes()) {
        if node.fixed {
            *g = Vec3::zeros();
        }
    }
    Residuals { g, h }
}

/// The largest $`|h_j| = |C_j(x) + \tilde\alpha_j\lambda_j|`$ over the springs, m: the part of
/// Eq 16's residual that XPBD drives to zero ([`residuals`]), read by the residual stopping mode
/// ([`crate::integrators::stopping::Stopping::Residual`]). Empty `alpha_tilde` and `lambda` mean zero
/// compliance, PBD's $`|C_j(x)|`$. A spring between two fixed nodes is left out: nothing can
/// move it ([`inverse_denominator`]).
pub fn constraint_residual(
    system: &MassSpringSystem,
    x: &[Vec3],
    alpha_tilde: &[f64],
    lambda: &[f64],
) -> f64 {
    let nodes = system.nodes();
    system
        .springs()
        .iter()
        .enumerate()
        .filter(|(_, s)| !(nodes[s.a].fixed && nodes[s.b].fixed))
        .map(|(j, s)| {
            let compliance_term = match (alpha_tilde.get(j), lambda.get(j)) {
                (Some(a), Some(l)) => a * l,
                _ => 0.0,
            };
            (spring::constraint(&x[s.a], &x[s.b], s.rest_length) + compliance_term).abs()
        })
        .fold(0.0, f64::max)
}

/// How the compliance of each spring is chosen.
#[derive(Debug, Clone, Copy, PartialEq)]
enum Compliance {
    /// $`\alpha_j = 1/k_j`$ from the springs (the thesis's method).
    FromStiffness,
    /// The same $`\alpha`$ for every spring, the springs' stiffness ignored.
    Uniform(f64),
}

/// What a run of Algorithm 2 fixes before its first step, one value per lane ([`Lane`]: `f64`
/// for one run, a vector for a batch, [`crate::solvers::batch`]).
#[derive(Debug, Clone)]
pub struct Coefficients<T> {
    /// Time step, s.
    pub dt: T,
    /// $`l_0`$ per spring, m.
    pub rest_length: Vec<T>,
    /// $`\tilde\alpha_j = \alpha_j/dt^2`$ per spring.
    pub alpha_tilde: Vec<T>,
    /// Eq (18)'s inverted denominator per spring ([`inverse_denominator`]).
    pub inverse_denominator: Vec<T>,
    /// Inverse masses $`w_i`$, 0 for fixed nodes.
    pub w: Vec<T>,
    /// $`M^{-1}f_{ext}`$ per node, m/s² (0 for fixed nodes).
    pub external_acceleration: Vec<Vector3<T>>,
}

/// What a step of Algorithm 2 works on besides the positions and velocities.
#[derive(Debug, Clone)]
pub struct Scratch<T> {
    /// Multipliers $`\lambda_j`$ of the current step.
    pub lambda: Vec<T>,
    /// $`x^n`$, kept for line 14.
    pub x_n: Vec<Vector3<T>>,
    /// $`\tilde x`$ of the current step, kept for [`residuals`].
    pub x_tilde: Vec<Vector3<T>>,
}

impl<T: Lane> Scratch<T> {
    /// Zeros for `springs` springs and `nodes` nodes.
    pub fn new(springs: usize, nodes: usize) -> Self {
        Self {
            lambda: vec![T::zero(); springs],
            x_n: vec![Vector3::zeros(); nodes],
            x_tilde: vec![Vector3::zeros(); nodes],
        }
    }
}

// region: step
impl<T: Lane> Coefficients<T> {
    /// Algorithm 2, lines 1-3: $`x_0 = \tilde x = x^n + dt\,v^n + dt^2 M^{-1}f_{ext}`$ (free
    /// nodes only), $`\lambda = 0`$.
    pub fn predict(&self, x: &mut [Vector3<T>], v: &[Vector3<T>], scratch: &mut Scratch<T>) {
        let dt = self.dt;
        scratch.x_n.copy_from_slice(x);
        // Grouped as dt·(vⁿ + dt·M⁻¹f_ext), the order in which PBD's lines 1-2 round, so that
        // zero compliance is PBD bit for bit.
        for (i, x) in x.iter_mut().enumerate() {
            let moved = *x + (v[i] + self.external_acceleration[i] * dt) * dt;
            *x = lanes::select(self.w[i].simd_gt(T::zero()), moved, *x);
        }
        scratch.x_tilde.copy_from_slice(x);
        scratch.lambda.fill(T::zero());
    }

    /// Algorithm 2, lines 5-11: one Gauss-Seidel sweep over the springs of `graph` in index
    /// order (on the batches' [`crate::solvers::incidence::Chain`] every index a constant).
    #[inline]
    pub fn sweep<G: SpringGraph>(&self, graph: &G, x: &mut [Vector3<T>], lambda: &mut [T]) {
        let x = &mut x[..graph.nodes()];
        for (j, lambda_j) in lambda[..graph.springs()].iter_mut().enumerate() {
            self.project(j, graph.ends(j), x, lambda_j);
        }
    }

    /// Algorithm 2, lines 6-9 for spring `j` between nodes `a` and `b`: its constraint's
    /// $`\Delta\lambda`$ and the position update it makes. A sweep is this for every spring
    /// in index order ([`Self::sweep`]); the batches' rope makes the same projections in
    /// another order that keeps what each one sees ([`crate::solvers::batch::xpbd`]).
    #[inline(always)]
    pub fn project(
        &self,
        j: usize,
        (a, b): (usize, usize),
        x: &mut [Vector3<T>],
        lambda_j: &mut T,
    ) {
        let (w1, w2) = (self.w[a], self.w[b]);
        // Eqs 48-49.
        let c = spring::constraint(&x[a], &x[b], self.rest_length[j]);
        let grad = spring::constraint_gradient(&x[a], &x[b]);
        // Line 6, Eqs 18 and 50.
        let delta_lambda = delta_lambda(
            c,
            self.alpha_tilde[j],
            *lambda_j,
            self.inverse_denominator[j],
        );
        // Line 7, Eqs 19 and 51.
        let (delta_x1, delta_x2) = delta_x(&grad, w1, w2, delta_lambda);
        // Lines 8-9.
        *lambda_j += delta_lambda;
        x[a] += delta_x1;
        x[b] += delta_x2;
    }

    /// Algorithm 2, lines 13-14: $`x^{n+1} = x_i`$ (already in place),
    /// $`v^{n+1} = (x^{n+1} - x^n)/dt`$.
    pub fn velocities(&self, x: &[Vector3<T>], v: &mut [Vector3<T>], scratch: &Scratch<T>) {
        for ((v, x), x_n) in v.iter_mut().zip(x).zip(&scratch.x_n) {
            *v = (x - x_n) / self.dt;
        }
    }
}
// endregion: step

/// XPBD (Algorithm 2) with a fixed number of solver iterations per step.
#[derive(Debug, Clone)]
pub struct Xpbd {
    system: MassSpringSystem,
    iterations: usize,
    compliance: Compliance,
    coefficients: Coefficients<f64>,
    scratch: Scratch<f64>,
    /// The springs' ends, for the sweep.
    graph: Ends,
    /// When a step stops iterating, and the iterations steps took.
    convergence: Convergence,
    /// Whether the step's sweeps have reached a fixed point.
    fixed_point: FixedPoint,
}

impl Xpbd {
    /// The thesis's XPBD for `system` with time step `dt` (s, > 0) and `iterations` (>= 1)
    /// solver iterations per step; every spring's compliance is $`\alpha_j = 1/k_j`$, so every
    /// spring needs $`k_j > 0`$.
    pub fn new(system: &MassSpringSystem, dt: f64, iterations: usize) -> Result<Self> {
        system.require_positive_stiffness()?;
        Self::build(system, dt, iterations, Compliance::FromStiffness)
    }

    /// XPBD with the same compliance `alpha` (m/N, >= 0) for every spring, ignoring the springs'
    /// stiffness. `alpha = 0` makes every spring infinitely stiff: the method is then PBD with
    /// stiffness factor 1 (§2.2.1).
    pub fn with_compliance(
        system: &MassSpringSystem,
        dt: f64,
        iterations: usize,
        alpha: f64,
    ) -> Result<Self> {
        require_non_negative("alpha", alpha)?;
        Self::build(system, dt, iterations, Compliance::Uniform(alpha))
    }

    fn build(
        system: &MassSpringSystem,
        dt: f64,
        iterations: usize,
        compliance: Compliance,
    ) -> Result<Self> {
        require_positive("dt", dt)?;
        system.require_undamped_springs()?;
        if iterations == 0 {
            return Err(Error::invalid("iterations", 0, "an integer >= 1"));
        }
        let alpha_tilde: Vec<f64> = system
            .springs()
            .iter()
            .map(|s| {
                let alpha = match compliance {
                    Compliance::FromStiffness => 1.0 / s.stiffness,
                    Compliance::Uniform(alpha) => alpha,
                };
                self::alpha_tilde(alpha, dt)
            })
            .collect();
        let w = system.inverse_masses();
        let inverse_denominator = system
            .springs()
            .iter()
            .zip(&alpha_tilde)
            .map(|(s, &a)| self::inverse_denominator(generalized_inverse_mass(w[s.a], w[s.b]), a))
            .collect();
        let external_acceleration = (0..system.len())
            .map(|i| w[i] * system.external_force(i))
            .collect();
        Ok(Self {
            system: system.clone(),
            iterations,
            compliance,
            coefficients: Coefficients {
                dt,
                rest_length: system.springs().iter().map(|s| s.rest_length).collect(),
                alpha_tilde,
                inverse_denominator,
                w,
                external_acceleration,
            },
            scratch: Scratch::new(system.springs().len(), system.len()),
            graph: Ends::of(system),
            convergence: Convergence::default(),
            fixed_point: FixedPoint::default(),
        })
    }

    /// What the run fixes before its first step.
    pub fn coefficients(&self) -> &Coefficients<f64> {
        &self.coefficients
    }

    /// Whether each step runs its full count of iterations ([`crate::integrators::stopping::Stopping::Count`]),
    /// as a batch of runs does ([`crate::solvers::batch`]).
    pub fn counts_iterations(&self) -> bool {
        self.convergence.stopping() == crate::integrators::stopping::Stopping::Count
    }

    /// Solver iterations per step.
    pub fn iterations(&self) -> usize {
        self.iterations
    }

    /// $`\tilde\alpha_j`$ per spring.
    pub fn alpha_tilde(&self) -> &[f64] {
        &self.coefficients.alpha_tilde
    }

    /// The multipliers $`\lambda_j`$ at the end of the last step.
    pub fn lambda(&self) -> &[f64] {
        &self.scratch.lambda
    }

    /// The prediction $`\tilde x`$ of the last step.
    pub fn prediction(&self) -> &[Vec3] {
        &self.scratch.x_tilde
    }
}

impl TimeStepper for Xpbd {
    fn name(&self) -> String {
        match self.compliance {
            Compliance::FromStiffness => format!(
                "XPBD ({})",
                self.convergence
                    .iterations_label(self.iterations, "iterations")
            ),
            Compliance::Uniform(alpha) => {
                format!(
                    "XPBD ({}, alpha = {alpha:e} m/N)",
                    self.convergence
                        .iterations_label(self.iterations, "iterations")
                )
            }
        }
    }

    fn dt(&self) -> f64 {
        self.coefficients.dt
    }

    fn system(&self) -> &MassSpringSystem {
        &self.system
    }

    fn convergence(&mut self) -> Option<&mut Convergence> {
        Some(&mut self.convergence)
    }

    /// Algorithm 2. The iterate $`x_i`$ lives in `state.x`.
    // region: step
    fn step(&mut self, state: &mut State) -> Result<()> {
        let x = &mut state.x;
        // Lines 1-3.
        self.coefficients.predict(x, &state.v, &mut self.scratch);
        self.convergence.begin_from(
            &self.system,
            &self.scratch.x_n,
            &state.v,
            self.coefficients.dt,
            x.iter().copied(),
        );
        // Lines 4-12: Gauss-Seidel over the springs in index order, stopping early only in the
        // tolerance mode; at a fixed point the sweeps left are not computed ([`FixedPoint`]:
        // a sweep reads nothing that changes but x and λ).
        self.fixed_point.begin_step();
        for _ in 0..self.iterations {
            if !self.fixed_point.reached() {
                let lambda = &mut self.scratch.lambda;
                self.fixed_point.keep(x, lambda);
                self.coefficients.sweep(&self.graph, x, lambda);
                self.fixed_point.compare(x, lambda);
            }
            let converged = if self.convergence.wants_value() {
                let r = constraint_residual(
                    &self.system,
                    x,
                    &self.coefficients.alpha_tilde,
                    &self.scratch.lambda,
                );
                self.convergence.converged_value(r)
            } else {
                self.convergence.converged(x.iter().copied())
            };
            if converged {
                break;
            }
        }
        self.convergence.end_step(0);
        // Lines 13-14.
        self.coefficients.velocities(x, &mut state.v, &self.scratch);
        Ok(())
    }
    // endregion: step
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::model::scene::thesis_rope;

    #[test]
    fn rejects_bad_parameters() {
        let rope = thesis_rope(1e3).unwrap();
        let field = |e: Error| match e {
            Error::InvalidParameter { field, .. } => field,
            other => panic!("{other}"),
        };
        assert_eq!(field(Xpbd::new(&rope, 0.0, 1).unwrap_err()), "dt");
        assert_eq!(field(Xpbd::new(&rope, f64::NAN, 1).unwrap_err()), "dt");
        assert_eq!(field(Xpbd::new(&rope, 0.01, 0).unwrap_err()), "iterations");
        assert_eq!(
            field(Xpbd::with_compliance(&rope, 0.01, 1, -1.0).unwrap_err()),
            "alpha"
        );
        let slack = rope.with_stiffness(0.0).unwrap();
        assert_eq!(
            field(Xpbd::new(&slack, 0.01, 1).unwrap_err()),
            "springs[0].stiffness"
        );
        // Zero stiffness is fine when the compliance is given explicitly.
        assert!(Xpbd::with_compliance(&slack, 0.01, 1, 0.0).is_ok());
    }

    /// Eqs 18-19 and 50 against hand-computed values, in exactly representable numbers.
    #[test]
    fn single_constraint_matches_closed_form() {
        let k = 4.0;
        let dt = 0.5;
        let c = 0.3;
        let w = 0.5;
        let at = alpha_tilde(1.0 / k, dt);
        assert_eq!(at, 1.0);
        // (−0.3 − 1·0)/(0.5 + 1)
        let inverse = inverse_denominator(w, at);
        assert!((delta_lambda(c, at, 0.0, inverse) + 0.2).abs() < 1e-15);
        // With λ = −C/α̃ the constraint's equation h = C + α̃λ holds and nothing changes.
        assert_eq!(delta_lambda(c, at, -c / at, inverse), 0.0);
        assert_eq!(inverse_denominator(0.0, 0.0), 0.0);
        assert_eq!(
            delta_lambda(c, 0.0, 0.0, inverse_denominator(0.0, 0.0)),
            0.0
        );
        let (a, b) = delta_x(&Vec3::new(0.6, 0.8, 0.0), 1.0, 0.0, -0.5);
        assert_eq!(a, Vec3::new(-0.3, -0.4, 0.0));
        assert_eq!(b, Vec3::zeros());
        assert_eq!(generalized_inverse_mass(1.0, 0.0), 1.0);
    }
}
