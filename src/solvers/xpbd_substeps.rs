//! XPBD with substeps (Macklin, Storey, Lu, Terdiman, Chentanez, Jeschke & Müller 2019, "Small
//! Steps in Physics Simulation", SCA 2019).
//!
//! The paper's Algorithm 1 splits each step of $`\Delta t`$ into $`n`$ substeps of
//! $`h = \Delta t/n`$ and gives each substep a single constraint-solver iteration:
//! ```math
//! \begin{aligned}
//! &\textbf{for } n \text{ substeps:}\\
//! &\quad v \leftarrow v + h\,M^{-1}f_{ext},\qquad p \leftarrow x,\qquad x \leftarrow x + h\,v\\
//! &\quad \text{one sweep over the constraints (XPBD, } \lambda = 0
//!   \text{ at the start of the substep)}\\
//! &\quad v \leftarrow (x - p)/h
//! \end{aligned}
//! ```
//! On the rope the sweep is the thesis's XPBD projection (Eqs 18-19 and 48-51, [`crate::solvers::xpbd`]):
//! each spring is a compliant distance constraint with $`\alpha_j = 1/k_j`$, now scaled by the
//! substep, $`\tilde\alpha_j = \alpha_j/h^2`$. A substep is therefore exactly one step of the
//! thesis's Algorithm 2 with time step $`h`$ and one iteration (prediction, $`\lambda = 0`$, one
//! Gauss-Seidel sweep, velocity from the position change), and [`XpbdSubsteps`] runs $`n`$ of
//! them through [`Xpbd`] itself rather than a copy of its loop. Nothing is carried from one
//! step to the next.
//!
//! The paper's argument is that the substep is the better place to spend a constraint
//! projection: XPBD's error has one part from the unfinished solve and one from the time
//! discretisation, and a smaller $`h`$ shrinks both, because the constraints move less within a
//! substep, so one projection leaves less unsolved. With one iteration per substep the scheme
//! converges to the exact motion as $`h \to 0`$ at first order, like the symplectic Euler it is
//! built on.
//!
//! Two options of the paper, off by default (the report's runs use the defaults, and say so):
//! - **Constraint damping** (§4.1, Eq. 8, [`XpbdSubstepsParams::constraint_damping`]
//!   $`\beta_j`$, N·s/m): with $`\tilde\beta = \Delta t_s^2\beta`$ and
//!   $`\gamma = \tilde\alpha\tilde\beta/\Delta t_s`$, each multiplier increment becomes
//!   $`\Delta\lambda = (-C - \tilde\alpha\lambda - \gamma\nabla C(x - x^n)) /
//!   ((1 + \gamma)\nabla C M^{-1}\nabla C^\top + \tilde\alpha)`$ ([`damped_delta_lambda`];
//!   the $`\tilde\alpha\lambda`$ term is 0 with one iteration, which is Eq. 8 as printed).
//!   It is the XPBD form of the dissipation $`\frac12\beta\dot C^2`$: a spring force
//!   $`-(kC + \beta\dot C)\nabla C`$, tested on a free spring against the damped
//!   oscillator's closed form.
//! - **The sweep** ([`Sweep`]): Gauss-Seidel over the springs in index order, the thesis's
//!   (default), or a Jacobi sweep, every spring's correction computed from the same positions
//!   and then added (the paper's 3D runs use a parallel Jacobi iteration; it names
//!   Gauss-Seidel as working too).
//!
//! With either option a substep is computed here ([`XpbdSubsteps::step`]), with the thesis's
//! equations of [`crate::solvers::xpbd`]; without them through [`Xpbd`] itself. Collisions (the paper
//! collects them once per step) do not arise on the rope.
//! [`XpbdSubstepsParams::iterations_per_substep`] (1 in Algorithm 1) is kept as a parameter
//! because the paper weighs substeps against iterations; with more than one, each substep is
//! Algorithm 2 with that many iterations.
//!
//! # What XPBD with substeps converges to (measured, `tests/newer_solvers.rs`)
//! Not the Backward Euler step: each substep is an XPBD step, whose fixed point is not the
//! minimiser of Eq 20 (see [`crate::solvers::xpbd`]); as the substeps grow the motion tends to the exact
//! motion of the undamped rope, which Backward Euler's numerical damping leaves. Against RK4
//! with a 2000-fold finer step:
//! - k = 1e3, 0.1 s from rest (10 steps of 1e-2): the gap halves with every doubling of the
//!   substeps, order 1.000 from 2 to 64 substeps (4.9e-3 m with 1 substep, 7.7e-5 m with 64).
//! - k = 1e6, one step of 1e-2 from a moving state: order 1.03 from 256 to 512 substeps, after
//!   a pre-asymptotic range where $`h\sqrt{k/m}`$ is not small.
//! - At equal cost (n sweeps, same case): one step of n substeps against one step of n
//!   iterations, gap to the exact motion 1.18e-3 m for both at n = 1, then 3.4e-4 against
//!   9.8e-4 m at n = 10 and 2.0e-5 against 5.1e-4 m at n = 50 (26 times closer). The
//!   iterations stall at XPBD's own fixed point, 4.9e-4 m from the exact motion; the substeps
//!   keep going. Their gap to the Backward Euler step stops at 4.8e-4 m instead.
//! - The last substep's compliance-weighted residual $`\max_j|C_j + \tilde\alpha_j\lambda_j|`$
//!   (one sweep leaves each spring disturbed by its neighbour's later projection) falls at
//!   second order in $`h`$: 8.4e-6 m at 64 substeps, 1.3e-7 m at 512; with 500 iterations per
//!   substep it is 4e-19 m.

use crate::error::{require_positive, require_within, Error, Result};
use crate::integrators::time_stepper::TimeStepper;
use crate::model::spring;
use crate::model::system::{MassSpringSystem, State, Vec3};
use crate::solvers::xpbd::{delta_x, generalized_inverse_mass, inverse_denominator, Xpbd};

/// The largest constraint damping, in N·s/m: the scene files' bound on spring damping
/// (`LIMITS.damping`).
pub const MAX_CONSTRAINT_DAMPING: f64 = 1e9;

/// The order of a constraint pass.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum Sweep {
    /// One spring after the other, in index order, each seeing its predecessors' corrections.
    #[default]
    GaussSeidel,
    /// Every spring's correction from the same positions, added after the pass.
    Jacobi,
}

impl Sweep {
    /// Both sweeps.
    pub const ALL: [Sweep; 2] = [Sweep::GaussSeidel, Sweep::Jacobi];

    /// The name on the command line.
    pub fn key(self) -> &'static str {
        match self {
            Sweep::GaussSeidel => "gauss-seidel",
            Sweep::Jacobi => "jacobi",
        }
    }
}

impl std::str::FromStr for Sweep {
    type Err = Error;

    fn from_str(s: &str) -> Result<Self> {
        Sweep::ALL
            .into_iter()
            .find(|w| w.key() == s)
            .ok_or_else(|| Error::invalid("sweep", s, "gauss-seidel or jacobi"))
    }
}

/// The parameters of Macklin et al. 2019 besides the substep count.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct XpbdSubstepsParams {
    /// Constraint-solver iterations per substep, >= 1 (Algorithm 1 of the paper: 1).
    pub iterations_per_substep: usize,
    /// The constraint damping $`\beta`$ of §4.1, N·s/m, >= 0 (0: none).
    pub constraint_damping: f64,
    /// The order of each constraint pass.
    pub sweep: Sweep,
}

impl Default for XpbdSubstepsParams {
    /// The paper's Algorithm 1: one iteration per substep, no damping, and the thesis's
    /// Gauss-Seidel sweep.
    fn default() -> Self {
        Self {
            iterations_per_substep: 1,
            constraint_damping: 0.0,
            sweep: Sweep::GaussSeidel,
        }
    }
}

impl XpbdSubstepsParams {
    /// Rejects a zero iteration count and a damping outside `0..=MAX_CONSTRAINT_DAMPING`.
    pub fn validate(&self) -> Result<()> {
        if self.iterations_per_substep == 0 {
            return Err(Error::invalid(
                "iterations_per_substep",
                0,
                "an integer >= 1",
            ));
        }
        require_within(
            "constraint_damping",
            self.constraint_damping,
            0.0,
            MAX_CONSTRAINT_DAMPING,
            "N·s/m",
        )?;
        Ok(())
    }

    /// Whether a substep is the thesis's XPBD step (no option of the paper's in use).
    fn is_plain(&self) -> bool {
        self.constraint_damping == 0.0 && self.sweep == Sweep::GaussSeidel
    }
}

/// [Macklin 2019, Eq. 8] The damped multiplier increment of one constraint:
/// $`\Delta\lambda = (-C - \tilde\alpha\lambda - \gamma\,\nabla C(x - x^n)) /
/// ((1 + \gamma)\,w + \tilde\alpha)`$, given its value `c`, `alpha_tilde`, its multiplier
/// `lambda`, $`\gamma`$, `c_change` $`= \nabla C(x - x^n)`$ and the inverted denominator
/// `inverse_denominator` $`= 1/((1 + \gamma)\,w + \tilde\alpha)`$ with
/// $`w = \nabla C M^{-1}\nabla C^\top`$ ([`crate::solvers::xpbd::inverse_denominator`] of
/// $`(1 + \gamma)\,w`$, computed once per spring: 0 for a constraint nothing can move and
/// without compliance). With $`\gamma = 0`$ it is Eq 18 ([`crate::solvers::xpbd::delta_lambda`]).
pub fn damped_delta_lambda(
    c: f64,
    alpha_tilde: f64,
    lambda: f64,
    inverse_denominator: f64,
    gamma: f64,
    c_change: f64,
) -> f64 {
    (-c - alpha_tilde * lambda - gamma * c_change) * inverse_denominator
}

/// XPBD with `substeps` substeps of $`dt/n`$ per step of $`dt`$ (Macklin et al. 2019).
#[derive(Debug, Clone)]
pub struct XpbdSubsteps {
    dt: f64,
    substeps: usize,
    params: XpbdSubstepsParams,
    /// The thesis's XPBD at the substep's time step $`h = dt/n`$.
    substep: Xpbd,
    /// $`\gamma_j = \tilde\alpha_j\tilde\beta/h`$ per spring.
    gamma: Vec<f64>,
    /// The inverted denominator of [`damped_delta_lambda`] per spring.
    inverse_denominator: Vec<f64>,
    /// $`w_i = 1/m_i`$ (0 for a fixed node).
    w: Vec<f64>,
    // Per-substep buffers of the optioned substep: x^n, the multipliers and a Jacobi pass's
    // corrections.
    x_n: Vec<Vec3>,
    lambda: Vec<f64>,
    corrections: Vec<Vec3>,
}

impl XpbdSubsteps {
    /// XPBD for `system` with time step `dt` (s, > 0) split into `substeps` (>= 1) substeps;
    /// every spring needs $`k_j > 0`$ (its compliance is $`1/k_j`$).
    pub fn new(
        system: &MassSpringSystem,
        dt: f64,
        substeps: usize,
        params: XpbdSubstepsParams,
    ) -> Result<Self> {
        params.validate()?;
        if substeps == 0 {
            return Err(Error::invalid("substeps", 0, "an integer >= 1"));
        }
        require_positive("dt", dt)?;
        let h = dt / substeps as f64;
        let substep = Xpbd::new(system, h, params.iterations_per_substep)?;
        let beta_tilde = h * h * params.constraint_damping;
        let gamma: Vec<f64> = substep
            .alpha_tilde()
            .iter()
            .map(|alpha_tilde| alpha_tilde * beta_tilde / h)
            .collect();
        let w = system.inverse_masses();
        let inverse_denominator = system
            .springs()
            .iter()
            .zip(gamma.iter().zip(substep.alpha_tilde()))
            .map(|(s, (&gamma, &alpha_tilde))| {
                let w = generalized_inverse_mass(w[s.a], w[s.b]);
                inverse_denominator((1.0 + gamma) * w, alpha_tilde)
            })
            .collect();
        let (n, s) = (system.len(), system.springs().len());
        Ok(Self {
            dt,
            substeps,
            params,
            substep,
            gamma,
            inverse_denominator,
            w,
            x_n: vec![Vec3::zeros(); n],
            lambda: vec![0.0; s],
            corrections: vec![Vec3::zeros(); n],
        })
    }

    /// Substeps per step.
    pub fn substeps(&self) -> usize {
        self.substeps
    }

    /// The XPBD solver of one substep: its $`\tilde\alpha`$, and after a step of the default
    /// options the multipliers and prediction of the last substep (for
    /// [`crate::solvers::xpbd::residuals`]).
    pub fn substep_solver(&self) -> &Xpbd {
        &self.substep
    }

    /// One substep of `h` with the paper's options (module doc): the prediction (Algorithm 1
    /// line 4), $`\lambda = 0`$, the passes of [`damped_delta_lambda`] in the chosen order
    /// (lines 5-10), and $`v = (x - x^n)/h`$ (line 11).
    fn optioned_substep(&mut self, state: &mut State) {
        let h = self.dt / self.substeps as f64;
        let system = self.substep.system();
        let g = system.gravity();
        self.x_n.copy_from_slice(&state.x);
        for ((x, v), &w) in state.x.iter_mut().zip(&state.v).zip(&self.w) {
            if w > 0.0 {
                *x += h * (v + h * g);
            }
        }
        self.lambda.fill(0.0);
        let alpha_tilde = self.substep.alpha_tilde();
        for _ in 0..self.params.iterations_per_substep {
            self.corrections.fill(Vec3::zeros());
            for (j, s) in system.springs().iter().enumerate() {
                let x = &state.x;
                let (w1, w2) = (self.w[s.a], self.w[s.b]);
                let c = spring::constraint(&x[s.a], &x[s.b], s.rest_length);
                let grad = spring::constraint_gradient(&x[s.a], &x[s.b]);
                let c_change = grad.dot(&((x[s.a] - self.x_n[s.a]) - (x[s.b] - self.x_n[s.b])));
                let delta_lambda = damped_delta_lambda(
                    c,
                    alpha_tilde[j],
                    self.lambda[j],
                    self.inverse_denominator[j],
                    self.gamma[j],
                    c_change,
                );
                let (delta_x1, delta_x2) = delta_x(&grad, w1, w2, delta_lambda);
                self.lambda[j] += delta_lambda;
                let moved = match self.params.sweep {
                    Sweep::GaussSeidel => &mut state.x,
                    Sweep::Jacobi => &mut self.corrections,
                };
                moved[s.a] += delta_x1;
                moved[s.b] += delta_x2;
            }
            if self.params.sweep == Sweep::Jacobi {
                for (x, d) in state.x.iter_mut().zip(&self.corrections) {
                    *x += d;
                }
            }
        }
        for ((v, x), x_n) in state.v.iter_mut().zip(&state.x).zip(&self.x_n) {
            *v = (x - x_n) / h;
        }
    }
}

impl TimeStepper for XpbdSubsteps {
    fn name(&self) -> String {
        format!(
            "XPBD substeps ({} substeps, {} iteration(s) per substep{}{})",
            self.substeps,
            self.params.iterations_per_substep,
            match self.params.constraint_damping {
                0.0 => String::new(),
                beta => format!(", constraint damping {beta} N·s/m"),
            },
            match self.params.sweep {
                Sweep::GaussSeidel => "",
                Sweep::Jacobi => ", Jacobi sweep",
            }
        )
    }

    fn dt(&self) -> f64 {
        self.dt
    }

    fn system(&self) -> &MassSpringSystem {
        self.substep.system()
    }

    /// The substeps' start, each from its own prediction (measured by the substep solver's
    /// log; the optioned substep does not measure it).
    fn start_distance_m(&mut self) -> Option<f64> {
        if self.params.is_plain() {
            self.substep.start_distance_m()
        } else {
            None
        }
    }

    /// [Macklin 2019, Alg. 1] $`n`$ substeps of $`h = \Delta t/n`$, each a prediction, one
    /// constraint sweep with $`\lambda`$ reset, and $`v = (x - p)/h`$.
    // region: step
    fn step(&mut self, state: &mut State) -> Result<()> {
        for _ in 0..self.substeps {
            if self.params.is_plain() {
                self.substep.step(state)?;
            } else {
                self.optioned_substep(state);
            }
        }
        if !state.is_finite() {
            return Err(Error::NotConverged {
                what: "XPBD substeps".into(),
                detail: "the state is no longer finite".into(),
            });
        }
        Ok(())
    }
    // endregion: step
}
