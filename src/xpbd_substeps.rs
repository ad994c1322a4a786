//! XPBD with substeps (Macklin, Storey, Lu, Terdiman, Chentanez, Jeschke & Müller 2019, "Small
//! Steps in Physics Simulation", SCA 2019).
//!
//! The paper's Algorithm 1 splits each step of $`\Delta t`$ into $`n`$ substeps of
//! $`h = \Delta t/n`$ and gives each substep a single constraint-solver iteration:
//! ```math
//! \begin{aligned}
//! &\textbf{for } n \text{ substeps:}\\
//! &\quad v \leftarrow v + h\,M^{-1}f_{ext},\qquad p \leftarrow x,\qquad x \leftarrow x + h\,v\\
//! &\quad \text{one sweep over the constraints (XPBD, } \lambda = 0\text{ at the start of the substep)}\\
//! &\quad v \leftarrow (x - p)/h
//! \end{aligned}
//! ```
//! On the rope the sweep is the thesis's XPBD projection (Eqs 18-19 and 48-51, [`crate::xpbd`]):
//! each spring is a compliant distance constraint with $`\alpha_j = 1/k_j`$, now scaled by the
//! substep, $`\tilde\alpha_j = \alpha_j/h^2`$. A substep is therefore exactly one step of the
//! thesis's Algorithm 2 with time step $`h`$ and one iteration (prediction, $`\lambda = 0`$, one
//! Gauss-Seidel sweep, velocity from the position change), and [`XpbdSubsteps`] runs $`n`$ of
//! them through [`Xpbd`] itself rather than a copy of its loop.
//!
//! The paper's argument is that the substep is the better place to spend a constraint
//! projection: XPBD's error has one part from the unfinished solve and one from the time
//! discretisation, and a smaller $`h`$ shrinks both, because the constraints move less within a
//! substep, so one projection leaves less unsolved. With one iteration per substep the scheme converges to the exact motion as
//! $`h \to 0`$ like the symplectic Euler it is built on, at first order. `tests/xpbd_substeps.rs`
//! measures that order against RK4 and compares one step of $`n`$ substeps with one step of
//! $`n`$ iterations at equal cost ($`n`$ sweeps).
//!
//! What differs from the paper: nothing in the substep itself; collisions (the paper collects
//! them once per step) do not arise on the rope. [`XpbdSubstepsParams::iterations_per_substep`]
//! (1 in Algorithm 1) is kept as a parameter because the paper discusses the trade-off of
//! substeps against iterations; with more than one, the substep is Algorithm 2 with that many
//! iterations.
//!
//! # What XPBD with substeps converges to
//!
//! Not the Backward Euler step: each substep is an XPBD step, whose fixed point is not the
//! minimiser of Eq 20 (see [`crate::xpbd`]), and with many substeps the motion approaches the
//! exact motion of the undamped system instead, which Backward Euler's numerical damping leaves.

use crate::error::{Error, Result};
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
        crate::error::require_positive("dt", dt)?;
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
        Ok(())
    }
    // endregion: step
}
