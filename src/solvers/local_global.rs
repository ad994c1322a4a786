//! The base iterations that [`crate::solvers::chebyshev`] and [`crate::solvers::anderson`] accelerate: one
//! iteration of Liu 2013 (Algorithm 3, [`crate::solvers::fast_mass_spring`]) or of ADMM-PD (Algorithm 4,
//! [`crate::solvers::admm`]) seen as a fixed-point map $`v \leftarrow G(v)`$ on the variable the
//! accelerating papers extrapolate, built from the base solvers' own pieces
//! ([`FastMassSpring::iterate`], [`AdmmIterate`]) so that the base arithmetic exists once.
//!
//! - Liu 2013: $`v = x`$, the positions, and $`G`$ is a local step followed by a global step.
//!   Wang 2015 extrapolates these positions (Projective Dynamics' $`q`$); Peng et al. 2018
//!   accelerate them too, in their local-global solvers, with the incremental potential of
//!   Eq (20) as the merit function. At a fixed point of the local step's projections that potential is exactly the
//!   local-global energy, so [`crate::solvers::backward_euler::incremental_potential`] is it.
//! - ADMM-PD: $`v = (x, \bar u)`$, the positions and the scaled duals, the variable Zhang,
//!   Peng, Ouyang & Deng 2019 (*Accelerating ADMM for Efficient Simulation and Optimization*)
//!   accelerate (their reference code, bldeng/AA-ADMM `Solver.cpp`, extrapolates the pair
//!   `(u, x)`); $`G`$ is one iteration of Algorithm 4 (lines 2.3-2.10): the local step
//!   $`z = z(x, \bar u)`$ with the dual update $`\bar u^+ = \bar u + Dx - z`$ (Eqs 41-42), then
//!   the global step $`x^+ = A^{-1}(M\tilde x + dt^2 D^\top W^\top W(z - \bar u^+))`$ (Eq 40).
//!   The $`z`$ of the local step is a function of $`(x, \bar u)`$, so it needs no place in
//!   the variable. Two merits ([`AdmmMerit`]): Zhang et al.'s primal residual
//!   $`|W(Dx - z)|^2 = |W(\bar u^+ - \bar u)|^2`$, known right after the local step, so that a
//!   rejected iterate costs a local step and no global solve (the default); or the combined
//!   residual after the global step, primal at the new positions plus dual,
//!   $`|W(Dx^+ - z)|^2 + |WD(x^+ - x)|^2`$ (the merit of this crate before issue 22, and the
//!   residual Zhang et al.'s code stops on), for which a rejected iterate has spent its global
//!   solve.
//!
//! A budget of `iterations` global solves (the base solvers' count) gives both bases
//! `iterations` applications of $`G`$. Every step starts from a [`FirstIterate`]
//! ([`crate::integrators::first_iterate`]), the accelerating papers' own being the inertial prediction
//! (Wang 2015's Algorithm 1, AASolver, AA-ADMM); ADMM's $`\bar u`$ starts at 0 (line 2.2).
//! Unaccelerated, both reproduce their base solver's step from the same first iterate bit for
//! bit. On a stage problem of an optimization integrator ([`crate::integrators::optimization_integrator`])
//! both are the same map with $`dt`$ the stage's $`\tau`$, from its pseudo-state.

use std::str::FromStr;

use crate::error::{require_positive, Error, Result};
use crate::integrators::first_iterate::{FirstIterate, StepStart};
use crate::integrators::optimization_integrator::{MinimizingSolver, PerStageStep, StageProblem};
use crate::model::system::{MassSpringSystem, State, Vec3};
use crate::solvers::admm::{default_omega, AdmmIterate};
use crate::solvers::backward_euler::incremental_potential;
use crate::solvers::fast_mass_spring::FastMassSpring;
use crate::solvers::projective::{
    finish_step, node_of_columns, nodes_of_columns, to_columns, GlobalSolve,
};

/// The local-global iteration being accelerated.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default)]
pub enum Base {
    /// Liu 2013's fast mass-spring iteration (Algorithm 3).
    #[default]
    Liu,
    /// ADMM ⊇ Projective Dynamics (Algorithm 4), $`\omega_i = \sqrt{k_i}`$.
    Admm,
}

impl Base {
    /// Every base, in a fixed order.
    pub const ALL: [Base; 2] = [Base::Liu, Base::Admm];

    /// The command-line name: `liu` or `admm`.
    pub fn name(self) -> &'static str {
        match self {
            Base::Liu => "liu",
            Base::Admm => "admm",
        }
    }

    /// The name in prose.
    pub fn label(self) -> &'static str {
        match self {
            Base::Liu => "Liu 2013",
            Base::Admm => "ADMM-PD",
        }
    }
}

impl FromStr for Base {
    type Err = Error;

    fn from_str(s: &str) -> Result<Self> {
        Base::ALL
            .into_iter()
            .find(|b| b.name() == s)
            .ok_or_else(|| Error::invalid("base", s, "liu or admm"))
    }
}

/// [Zhang 2019, primal-residual safeguard] Checked against bldeng/AA-ADMM `Solver.cpp`: the merit of an ADMM
/// iterate $`(x, \bar u)`$ that a safeguard compares (module doc).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default)]
pub enum AdmmMerit {
    /// Zhang et al. 2019's primal residual $`|W(Dx - z)|^2`$, checked after the local step.
    #[default]
    PrimalResidual,
    /// The combined residual after the global step, $`|W(Dx^+ - z)|^2 + |WD(x^+ - x)|^2`$.
    CombinedResidual,
}

impl AdmmMerit {
    /// Both merits.
    pub const ALL: [AdmmMerit; 2] = [AdmmMerit::PrimalResidual, AdmmMerit::CombinedResidual];

    /// The name on the command line.
    pub fn key(self) -> &'static str {
        match self {
            AdmmMerit::PrimalResidual => "primal-residual",
            AdmmMerit::CombinedResidual => "combined-residual",
        }
    }

    /// Whether a rejected iterate has spent its global solve.
    pub fn rejection_costs_a_solve(self) -> bool {
        self == AdmmMerit::CombinedResidual
    }
}

impl FromStr for AdmmMerit {
    type Err = Error;

    fn from_str(s: &str) -> Result<Self> {
        AdmmMerit::ALL
            .into_iter()
            .find(|m| m.key() == s)
            .ok_or_else(|| Error::invalid("safeguard", s, "primal-residual or combined-residual"))
    }
}

/// What [`LocalGlobal::apply`] did, with the merit of the variable it was given.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Merit {
    /// $`v \leftarrow G(v)`$ was applied.
    Applied(f64),
    /// The merit was above the threshold; $`v`$ is unchanged.
    Rejected(f64),
}

/// The base solver's machinery.
#[derive(Debug, Clone)]
enum Iteration {
    Liu {
        solver: Box<FastMassSpring>,
        /// $`y = x_n + dt\,v_n`$, for the incremental potential.
        y: Vec<Vec3>,
        /// The positions of the iterate as nodes, for the incremental potential.
        x: Vec<Vec3>,
    },
    Admm {
        /// $`A = M + dt^2 D^\top W^\top W D`$ of each stage step, factored once (Algorithm 4
        /// line 1.5).
        a: Box<PerStageStep<GlobalSolve>>,
        iterate: Box<AdmmIterate>,
        start: StepStart,
        merit: AdmmMerit,
        /// The positions and duals the variable held before $`G`$ (for the residuals).
        x_before: Vec<f64>,
        u_before: Vec<Vec3>,
    },
}

/// One base iteration as a map $`v \leftarrow G(v)`$, with its merit function (module doc).
#[derive(Debug, Clone)]
pub struct LocalGlobal {
    system: MassSpringSystem,
    dt: f64,
    /// The current stage's $`dt`$ ($`\tau`$), s.
    tau: f64,
    base: Base,
    iteration: Iteration,
    /// The variable $`v`$: column-major positions (Liu), or those then $`\bar u`$, three
    /// coordinates per spring (ADMM).
    v: Vec<f64>,
    /// Global solves since [`LocalGlobal::begin`].
    solves: usize,
}

impl LocalGlobal {
    /// The base iteration of `base` for `system` with time step `dt` (s, > 0), each step
    /// starting at `first_iterate`; `merit` is ADMM's (Liu's is its energy).
    pub fn new(
        system: &MassSpringSystem,
        dt: f64,
        base: Base,
        first_iterate: FirstIterate,
        merit: AdmmMerit,
    ) -> Result<Self> {
        let n = system.len();
        let s = system.springs().len();
        let (iteration, v) = match base {
            Base::Liu => (
                Iteration::Liu {
                    solver: Box::new(
                        FastMassSpring::new(system, dt, 1)?.with_first_iterate(first_iterate),
                    ),
                    y: vec![Vec3::zeros(); n],
                    x: vec![Vec3::zeros(); n],
                },
                vec![0.0; 3 * n],
            ),
            Base::Admm => {
                // The checks of AdmmPd::new: the weights are square roots of the stiffnesses.
                require_positive("dt", dt)?;
                system.require_positive_stiffness()?;
                let omega = default_omega(system);
                let omega2: Vec<f64> = omega.iter().map(|w| w * w).collect();
                (
                    Iteration::Admm {
                        a: Box::new(PerStageStep::new(
                            dt,
                            GlobalSolve::new(system, dt, &omega2)?,
                        )),
                        iterate: Box::new(AdmmIterate::new(system, dt, omega)),
                        start: StepStart::new(first_iterate),
                        merit,
                        x_before: vec![0.0; 3 * n],
                        u_before: vec![Vec3::zeros(); s],
                    },
                    vec![0.0; 3 * n + 3 * s],
                )
            }
        };
        Ok(Self {
            system: system.clone(),
            dt,
            tau: dt,
            base,
            iteration,
            v,
            solves: 0,
        })
    }

    /// The base iteration.
    pub fn base(&self) -> Base {
        self.base
    }

    /// The system.
    pub fn system(&self) -> &MassSpringSystem {
        &self.system
    }

    /// The time step, s.
    pub fn dt(&self) -> f64 {
        self.dt
    }

    /// Global solves since [`LocalGlobal::begin`].
    pub fn solves(&self) -> usize {
        self.solves
    }

    /// The first variable of a step from `state`: Liu's first iterate (Algorithm 3, line 2.1
    /// and [`FastMassSpring::begin_step`]); for ADMM, $`\tilde x`$ (line 2.1), the first
    /// iterate and $`\bar u = 0`$ (line 2.2).
    pub fn begin(&mut self, state: &State) {
        self.begin_stage(state, &StageProblem::backward_euler(self.dt))
            .expect("the iteration's own step is prefactored when it is built");
    }

    /// [`Self::begin`] for a stage problem from its pseudo-state `stage`, with the matrix of
    /// its $`\tau`$ (factored if new).
    pub fn begin_stage(&mut self, stage: &State, problem: &StageProblem) -> Result<()> {
        self.solves = 0;
        let dt = problem.tau;
        self.prepare(dt)?;
        match &mut self.iteration {
            Iteration::Liu { solver, y, .. } => {
                solver.begin_stage(stage, problem)?;
                for ((y, x), v) in y.iter_mut().zip(&stage.x).zip(&stage.v) {
                    *y = x + dt * v;
                }
                solver.positions_into(&mut self.v);
            }
            Iteration::Admm { iterate, start, .. } => {
                iterate.predict(&self.system, stage, dt);
                let n = iterate.x.len();
                to_columns(
                    start.first_iterate(&self.system, stage, problem),
                    &mut self.v[..n],
                );
                self.v[n..].fill(0.0);
            }
        }
        Ok(())
    }

    /// Makes `tau` the current stage step, prefactoring its matrices if new.
    pub fn prepare(&mut self, tau: f64) -> Result<()> {
        let system = &self.system;
        match &mut self.iteration {
            Iteration::Liu { solver, .. } => solver.prepare(tau)?,
            Iteration::Admm { a, iterate, .. } => {
                let omega = iterate.omega();
                a.select(tau, |tau| {
                    let omega2: Vec<f64> = omega.iter().map(|w| w * w).collect();
                    GlobalSolve::new(system, tau, &omega2)
                })?;
                if tau != self.tau {
                    iterate.set_step(tau);
                }
            }
        }
        self.tau = tau;
        Ok(())
    }

    /// The variable $`v`$ (layout in the field's doc).
    pub fn variable(&self) -> &[f64] {
        &self.v
    }

    /// The positions of the variable, as nodes.
    pub fn positions(&self) -> impl Iterator<Item = Vec3> + '_ {
        nodes_of_columns(&self.v[..3 * self.system.len()])
    }

    /// Replaces the variable (by an extrapolated one).
    pub fn set_variable(&mut self, v: &[f64]) {
        self.v.copy_from_slice(v);
    }

    /// $`v \leftarrow G(v)`$ if the merit of the current $`v`$ is at most `threshold`;
    /// otherwise $`v`$ is left unchanged. Either way the merit is returned. Liu's merit (the
    /// incremental potential) and ADMM's primal residual cost no solve, so such a rejected
    /// iterate costs none (ADMM's, a local step); ADMM's combined residual needs the global
    /// step, so an iterate it rejects has spent a solve.
    pub fn apply(&mut self, threshold: f64) -> Merit {
        match &mut self.iteration {
            Iteration::Liu { solver, y, x } => {
                let n = x.len();
                for (i, x) in x.iter_mut().enumerate() {
                    *x = node_of_columns(&self.v, n, i);
                }
                let merit = incremental_potential(&self.system, y, x, self.tau);
                if merit > threshold {
                    return Merit::Rejected(merit);
                }
                solver.set_positions(&self.v);
                solver.iterate();
                self.solves += 1;
                solver.positions_into(&mut self.v);
                Merit::Applied(merit)
            }
            Iteration::Admm {
                a,
                iterate,
                merit: rule,
                x_before,
                u_before,
                ..
            } => {
                load_admm(&self.v, iterate);
                x_before.copy_from_slice(&iterate.x);
                u_before.copy_from_slice(&iterate.u_bar);
                // 2.4-2.7: z and ū⁺ = ū + Dx − z, so that ū⁺ − ū is the primal residual.
                iterate.local_step();
                let weighted = |iterate: &AdmmIterate, i: usize, r: Vec3| {
                    (iterate.omega()[i] * r).norm_squared()
                };
                let primal: f64 = (0..u_before.len())
                    .map(|i| weighted(iterate, i, iterate.u_bar[i] - u_before[i]))
                    .sum();
                if *rule == AdmmMerit::PrimalResidual && primal > threshold {
                    return Merit::Rejected(primal);
                }
                // 2.8-2.9.
                iterate.global_rhs();
                a.current().solve(&mut iterate.x, &iterate.x_n);
                self.solves += 1;
                let merit = match rule {
                    AdmmMerit::PrimalResidual => primal,
                    AdmmMerit::CombinedResidual => iterate.combined_residual(x_before),
                };
                if merit > threshold {
                    return Merit::Rejected(merit);
                }
                store_admm(iterate, &mut self.v);
                Merit::Applied(merit)
            }
        }
    }

    /// Ends the step: $`v_{n+1} = (x_{n+1} - x_n)/dt`$ from the variable's positions
    /// (Algorithm 3's erratum, Algorithm 4 line 2.11). A non-finite iterate is an error naming
    /// the base, and `state` is left as it was.
    pub fn finish(&mut self, state: &mut State) -> Result<()> {
        let x = &self.v[..3 * self.system.len()];
        if !x.iter().all(|c| c.is_finite()) {
            return Err(Error::NotConverged {
                what: format!("accelerated {}", self.base.label()),
                detail: format!(
                    "the positions are no longer finite after {} global solves",
                    self.solves
                ),
            });
        }
        finish_step(state, x, self.tau);
        Ok(())
    }
}

/// $`(x, \bar u)`$ of `iterate` into the variable.
fn store_admm(iterate: &AdmmIterate, v: &mut [f64]) {
    let n = iterate.x.len();
    v[..n].copy_from_slice(&iterate.x);
    for (i, u_bar) in iterate.u_bar.iter().enumerate() {
        v[n + 3 * i..n + 3 * i + 3].copy_from_slice(u_bar.as_slice());
    }
}

/// The variable into $`(x, \bar u)`$ of `iterate`.
fn load_admm(v: &[f64], iterate: &mut AdmmIterate) {
    let n = iterate.x.len();
    iterate.x.copy_from_slice(&v[..n]);
    for (i, u_bar) in iterate.u_bar.iter_mut().enumerate() {
        *u_bar = Vec3::from_column_slice(&v[n + 3 * i..n + 3 * i + 3]);
    }
}
