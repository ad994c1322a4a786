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
//! On the rope the sweep is the thesis's XPBD projection (Eqs 18-19 and 48-51, [`crate::xpbd`]):
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
//! What differs from the paper: nothing in the substep itself; collisions (the paper collects
//! them once per step) do not arise on the rope. [`XpbdSubstepsParams::iterations_per_substep`]
//! (1 in Algorithm 1) is kept as a parameter because the paper weighs substeps against
//! iterations; with more than one, each substep is Algorithm 2 with that many iterations.
//!
//! # What XPBD with substeps converges to (measured, `tests/newer_solvers.rs`)
//! Not the Backward Euler step: each substep is an XPBD step, whose fixed point is not the
//! minimiser of Eq 20 (see [`crate::xpbd`]); as the substeps grow the motion tends to the exact
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

use crate::error::{require_positive, Error, Result};
use crate::solver::TimeStepper;
use crate::system::{MassSpringSystem, State};
use crate::xpbd::Xpbd;

/// The parameters of Macklin et al. 2019 besides the substep count.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct XpbdSubstepsParams {
    /// Constraint-solver iterations per substep, >= 1 (Algorithm 1 of the paper: 1).
    pub iterations_per_substep: usize,
}

impl Default for XpbdSubstepsParams {
    /// The paper's Algorithm 1: one iteration per substep.
    fn default() -> Self {
        Self {
            iterations_per_substep: 1,
        }
    }
}

impl XpbdSubstepsParams {
    /// Rejects a zero iteration count.
    pub fn validate(&self) -> Result<()> {
        if self.iterations_per_substep == 0 {
            return Err(Error::invalid(
                "iterations_per_substep",
                0,
                "an integer >= 1",
            ));
        }
        Ok(())
    }
}

/// XPBD with `substeps` substeps of $`dt/n`$ per step of $`dt`$ (Macklin et al. 2019).
#[derive(Debug, Clone)]
pub struct XpbdSubsteps {
    dt: f64,
    substeps: usize,
    params: XpbdSubstepsParams,
    /// The thesis's XPBD at the substep's time step $`h = dt/n`$.
    substep: Xpbd,
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
        let substep = Xpbd::new(system, dt / substeps as f64, params.iterations_per_substep)?;
        Ok(Self {
            dt,
            substeps,
            params,
            substep,
        })
    }

    /// Substeps per step.
    pub fn substeps(&self) -> usize {
        self.substeps
    }

    /// The XPBD solver of one substep: its $`\tilde\alpha`$, and after a step the multipliers
    /// and prediction of the last substep (for [`crate::xpbd::residuals`]).
    pub fn substep_solver(&self) -> &Xpbd {
        &self.substep
    }
}

impl TimeStepper for XpbdSubsteps {
    fn name(&self) -> String {
        format!(
            "XPBD substeps ({} substeps, {} iteration(s) per substep)",
            self.substeps, self.params.iterations_per_substep
        )
    }

    fn dt(&self) -> f64 {
        self.dt
    }

    fn system(&self) -> &MassSpringSystem {
        self.substep.system()
    }

    /// [Macklin 2019, Alg. 1] $`n`$ substeps of $`h = \Delta t/n`$, each a prediction, one
    /// constraint sweep with $`\lambda`$ reset, and $`v = (x - p)/h`$.
    // region: step
    fn step(&mut self, state: &mut State) -> Result<()> {
        for _ in 0..self.substeps {
            self.substep.step(state)?;
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
