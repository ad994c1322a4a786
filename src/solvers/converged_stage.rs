//! The Newton-solved stage problem: the oracle every minimizing solver is tested against
//! (thesis Eq 20 solved to round-off, [`converged_step`]), for any stage
//! of an optimization integrator ([`crate::integrators::optimization_integrator`]) and any dissipation
//! ([`crate::integrators::dissipation`]), and [`ConvergedNewton`], the same as a [`MinimizingSolver`], with
//! which an integrator's runs have no solver error.
//!
//! The stage minimises $`\frac{1}{2\tau^2}\lVert x - \hat y\rVert_M^2 + U(x) + \Psi(x)`$ from the
//! pseudo-state $`(x_a, u_0)`$, gravity in the potential (the same minimiser as
//! $`\tau^2M^{-1}f_{ext}`$ in $`\hat y`$), by projected Newton (the springs' and the
//! momentum-conserving damping's transverse stiffness clamped at 0, the drag's Hessian
//! smoothed at rest) with a backtracking line search on the objective (the crate's one,
//! [`crate::model::projected_newton::backtrack`], accepting plain descent); the first iterate
//! is $`x_a + \tau u_0`$. Its Hessian rule (always the projected one) and its stop (on the
//! size of the update) are its own: the report's Backward Euler reference and every solver's
//! tests are measured against its steps, bit for bit.

use crate::error::{require_positive, Error, Result};
use crate::integrators::damping::RayleighDamping;
use crate::integrators::dissipation::{Dissipation, StageDissipation};
use crate::integrators::optimization_integrator::{MinimizingSolver, StageProblem};
use crate::integrators::time_stepper::TimeStepper;
use crate::model::boundary::{fixed_node_unknowns, ConstrainedSystem};
use crate::model::projected_newton::backtrack;
use crate::model::spring;
use crate::model::system::{MassSpringSystem, State, Vec3};
use crate::solvers::backward_euler::{
    incremental_potential, inertia, ConvergedStepOptions, ImplicitMatrix,
};
use nalgebra::Matrix3;

/// Halvings of the line search's step ([`backtrack`]): down to 2⁻⁴⁰ ≈ 9.1e-13 of Newton's.
const HALVINGS: usize = 40;

/// [Brown 2018, dissipation potential] (unverified: no body text or reference code found) The
/// stage `problem` from the pseudo-state `state` with `dissipation`, solved to
/// `options.tolerance` by projected Newton with a backtracking line search (module doc); the
/// velocity is $`(x^* - x_a)/\tau`$. A Backward Euler stage without dissipation is
/// [`converged_step`].
///
/// Fails with [`Error::NotConverged`] when the line search stalls (no decrease of the
/// objective down to a step of $`10^{-12}`$ of Newton's) or the objective is not finite.
pub fn converged_stage(
    system: &MassSpringSystem,
    state: &State,
    problem: &StageProblem,
    dissipation: Dissipation,
    options: ConvergedStepOptions,
) -> Result<State> {
    converged_stage_in(
        &mut StageWorkspace::default(),
        system,
        state,
        problem,
        dissipation,
        options,
    )
}

/// What [`converged_stage`] builds for its system before the first Newton iteration, kept by
/// a solver that solves many stages of one system ([`ConvergedNewton`]): the matrix's pattern
/// and slots, and its factorisation with the fixed nodes imposed (built at the first
/// iteration, refactored at every later one, as within one stage).
#[derive(Debug, Clone, Default)]
struct StageWorkspace {
    implicit: Option<ImplicitMatrix>,
    solve: Option<ConstrainedSystem>,
}

/// [`converged_stage`] in `workspace`, which must have been used for `system` only.
fn converged_stage_in(
    workspace: &mut StageWorkspace,
    system: &MassSpringSystem,
    state: &State,
    problem: &StageProblem,
    dissipation: Dissipation,
    options: ConvergedStepOptions,
) -> Result<State> {
    let dt = problem.tau;
    require_positive("dt", dt)?;
    dissipation.validate()?;
    system.require_undamped_springs()?;
    let n = system.len();
    let y = inertia(state, dt);
    let mut x: Vec<Vec3> = system
        .nodes()
        .iter()
        .enumerate()
        .map(|(i, node)| if node.fixed { state.x[i] } else { y[i] })
        .collect();
    let fixed = fixed_node_unknowns(system, 3);
    let mut dissipation = StageDissipation::new(system, dissipation);
    dissipation.start(system, &state.x, problem.frozen_positions(state), dt);
    let objective =
        |x: &[Vec3]| incremental_potential(system, &y, x, dt) + dissipation.potential(system, x);
    let implicit = workspace
        .implicit
        .get_or_insert_with(|| ImplicitMatrix::new(system));
    let solve = &mut workspace.solve;
    let mut forces = vec![Vec3::zeros(); n];
    let zeros = vec![0.0; 3 * n];
    let mut jacobians = vec![Matrix3::zeros(); system.springs().len()];
    for iteration in 0..options.max_iterations {
        for (jac, s) in jacobians.iter_mut().zip(system.springs()) {
            *jac = spring::force_jacobian_definite(&x[s.a], &x[s.b], s.rest_length, s.stiffness);
        }
        implicit.assemble(system, dt, &jacobians, &dissipation, &x, true);
        match solve {
            Some(solve) => solve.refactor(&mut implicit.matrix)?,
            None => *solve = Some(ConstrainedSystem::new(&mut implicit.matrix, &fixed)?),
        }
        // (M − dt²K̃) Δx = −dt²·∇Φ = dt²F(x) − M(x − y), F including the damping force.
        system.forces(&x, &mut forces);
        dissipation.add_force(system, &x, &mut forces);
        let mut dx: Vec<f64> = (0..3 * n)
            .map(|r| {
                let (i, c) = (r / 3, r % 3);
                dt * dt * forces[i][c] - system.nodes()[i].mass * (x[i][c] - y[i][c])
            })
            .collect();
        solve.as_ref().expect("factored").solve(&mut dx, &zeros, 1);
        let step_norm = dx.iter().fold(0.0_f64, |m, d| m.max(d.abs()));
        let trial = |alpha: f64| -> Vec<Vec3> {
            x.iter()
                .enumerate()
                .map(|(i, xi)| xi + alpha * Vec3::new(dx[3 * i], dx[3 * i + 1], dx[3 * i + 2]))
                .collect()
        };
        // Near the solution the potential's differences drown in round-off: take full steps.
        let mut alpha = 1.0;
        if step_norm > 1e-8 {
            let phi0 = objective(&x);
            // Plain descent, false for a NaN potential too.
            alpha =
                backtrack(HALVINGS, |alpha| objective(&trial(alpha)) <= phi0).ok_or_else(|| {
                    Error::NotConverged {
                        what: "converged Newton stage".into(),
                        detail: format!(
                        "the line search stalled at Newton iteration {}: the potential {phi0:e} \
                         does not decrease along the Newton step ({step_norm:e} m) down to a \
                         fraction {:e} of it",
                        iteration + 1,
                        0.5_f64.powi(HALVINGS as i32)
                    ),
                    }
                })?;
        }
        x = trial(alpha);
        if alpha * step_norm <= options.tolerance {
            let v = x
                .iter()
                .zip(&state.x)
                .map(|(x1, x0)| (x1 - x0) / dt)
                .collect();
            return Ok(State { x, v });
        }
        if iteration + 1 == options.max_iterations {
            return Err(Error::NotConverged {
                what: "converged Newton stage".into(),
                detail: format!(
                    "largest update {:e} m after {} iterations (tolerance {:e} m)",
                    alpha * step_norm,
                    options.max_iterations,
                    options.tolerance
                ),
            });
        }
    }
    Err(Error::invalid("max_iterations", 0, "an integer >= 1"))
}

/// [`converged_stage`] as a minimizing solver: every stage solved to round-off.
#[derive(Debug, Clone)]
pub struct ConvergedNewton {
    system: MassSpringSystem,
    dt: f64,
    dissipation: Dissipation,
    options: ConvergedStepOptions,
    /// The matrix and factorisation of its stages, built once.
    workspace: StageWorkspace,
}

impl ConvergedNewton {
    /// The oracle for `system` with time step `dt` (s, > 0) and `dissipation`.
    pub fn new(system: &MassSpringSystem, dt: f64, dissipation: Dissipation) -> Result<Self> {
        require_positive("dt", dt)?;
        dissipation.validate()?;
        system.require_undamped_springs()?;
        Ok(Self {
            system: system.clone(),
            dt,
            dissipation,
            options: ConvergedStepOptions::default(),
            workspace: StageWorkspace::default(),
        })
    }
}

impl TimeStepper for ConvergedNewton {
    fn name(&self) -> String {
        "converged Newton".into()
    }

    fn dt(&self) -> f64 {
        self.dt
    }

    fn system(&self) -> &MassSpringSystem {
        &self.system
    }

    fn step(&mut self, state: &mut State) -> Result<()> {
        self.solve(&StageProblem::backward_euler(self.dt), state)
    }
}

impl MinimizingSolver for ConvergedNewton {
    fn solve(&mut self, problem: &StageProblem, stage: &mut State) -> Result<()> {
        *stage = converged_stage_in(
            &mut self.workspace,
            &self.system,
            stage,
            problem,
            self.dissipation,
            self.options,
        )?;
        Ok(())
    }

    fn dissipation(&self) -> Option<&Dissipation> {
        (!self.dissipation.is_none()).then_some(&self.dissipation)
    }
}

/// Eq. (20): $`x^{n+1} = \arg\min_x \frac{1}{2dt^2}(x - y)^\top M (x - y) + E(x)`$, solved to
/// `options.tolerance` by projected Newton with a backtracking line search; then
/// $`v^{n+1} = (x^{n+1} - x^n)/dt`$.
///
/// Erratum: the thesis prints $`(x^n - y)`$ in the inertial term, which does not depend on $`x`$;
/// the minimised variable is $`x`$. Gravity enters through $`E`$ (its potential), which is the
/// same minimiser as putting $`dt^2 M^{-1} f_{ext}`$ into $`y`$. The Hessian uses the projected
/// spring Jacobian ([`spring::force_jacobian_definite`]) so every direction descends; at a
/// stretched-rope solution it equals the exact one and convergence is quadratic.
///
/// Fails with [`Error::NotConverged`] when the line search stalls (no decrease of the
/// potential down to a step of $`10^{-12}`$ of Newton's) or the potential is not finite, rather
/// than take the stalled step as converged.
pub fn converged_step(
    system: &MassSpringSystem,
    state: &State,
    dt: f64,
    options: ConvergedStepOptions,
) -> Result<State> {
    damped_converged_step(system, state, dt, RayleighDamping::NONE, options)
}

/// [Brown 2018, dissipation potential] (unverified: no body text or reference code found) [`converged_step`] with Rayleigh damping: projected
/// Newton on $`\Phi(x) + h\,\mathcal D(x_n, (x - x_n)/h)`$ ([`crate::integrators::damping`]), the oracle of
/// the damped solvers. With $`\alpha = \beta = 0`$ it is [`converged_step`].
pub fn damped_converged_step(
    system: &MassSpringSystem,
    state: &State,
    dt: f64,
    damping: RayleighDamping,
    options: ConvergedStepOptions,
) -> Result<State> {
    require_positive("dt", dt)?;
    converged_stage(
        system,
        state,
        &StageProblem::backward_euler(dt),
        Dissipation::rayleigh(damping),
        options,
    )
}

/// The static equilibrium $`F(x) = 0`$ of a system, by a proximal-point iteration: converged
/// steps of `dt_s` seconds from rest, repeated until the positions stop moving (`tolerance`, m).
///
/// Each step minimises $`\frac{1}{2dt^2}|x - x_k|^2_M + E(x)`$, whose fixed points are exactly the
/// minimisers of $`E`$; the inertial term regularises the start (a straight rope has no
/// transverse stiffness). Used to check the analytic catenary.
pub fn static_equilibrium(
    system: &MassSpringSystem,
    dt_s: f64,
    tolerance: f64,
) -> Result<Vec<Vec3>> {
    let mut state = system.initial_state();
    state.v.fill(Vec3::zeros());
    for _ in 0..10_000 {
        let next = converged_step(system, &state, dt_s, ConvergedStepOptions::default())?;
        let moved = next
            .x
            .iter()
            .zip(&state.x)
            .map(|(a, b)| (a - b).amax())
            .fold(0.0, f64::max);
        state.x = next.x;
        if moved <= tolerance {
            return Ok(state.x);
        }
    }
    Err(Error::NotConverged {
        what: "static equilibrium".into(),
        detail: format!("positions still move more than {tolerance:e} m after 10000 steps"),
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::integrators::time_stepper::TimeStepper;
    use crate::model::scene::{thesis_rope, SheetParams};

    /// Every bit of a state.
    fn bits(state: &State) -> Vec<u64> {
        state
            .x
            .iter()
            .chain(&state.v)
            .flat_map(|p| p.iter().map(|c| c.to_bits()))
            .collect()
    }

    /// [`ConvergedNewton`] keeps its matrix and factorisation from stage to stage
    /// ([`StageWorkspace`]); its steps have the bits of [`converged_stage`] built afresh at
    /// every step, on the rope and on the sheet, with and without damping. Fails if a stage's
    /// first iteration takes the kept factorisation as it is (the last stage's matrix) instead
    /// of refactoring it.
    #[test]
    fn kept_workspace_steps_have_the_bits_of_fresh_ones() {
        let damping = Dissipation::rayleigh(RayleighDamping {
            alpha: 0.5,
            beta: 0.002,
        });
        let systems = [
            thesis_rope(1e3).unwrap(),
            SheetParams::spec(4, 1e3).build().unwrap(),
        ];
        for system in &systems {
            for dissipation in [Dissipation::rayleigh(RayleighDamping::NONE), damping] {
                let dt = 0.01;
                let mut kept = ConvergedNewton::new(system, dt, dissipation).unwrap();
                let (mut a, mut b) = (system.initial_state(), system.initial_state());
                for _ in 0..20 {
                    kept.step(&mut a).unwrap();
                    b = converged_stage(
                        system,
                        &b,
                        &StageProblem::backward_euler(dt),
                        dissipation,
                        ConvergedStepOptions::default(),
                    )
                    .unwrap();
                    assert_eq!(bits(&a), bits(&b));
                }
            }
        }
    }
}
