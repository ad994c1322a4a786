//! The base iterations that [`crate::chebyshev`] and [`crate::anderson`] accelerate: one
//! iteration of Liu 2013 (Algorithm 3, [`crate::fast_mass_spring`]) or of ADMM-PD (Algorithm 4,
//! [`crate::admm`]) seen as a fixed-point map $`v \leftarrow G(v)`$ on the variable the
//! accelerating papers extrapolate, built from the base solvers' own pieces
//! ([`FastMassSpring::iterate`], [`AdmmIterate`]) so that the base arithmetic exists once.
//!
//! - Liu 2013: $`v = x`$, the positions, and $`G`$ is a local step followed by a global step.
//!   Wang 2015 extrapolates these positions (Projective Dynamics' $`q`$); Peng et al. 2018
//!   accelerate them too, in their local-global solvers, with the incremental potential of
//!   Eq (20) as the merit function. At a fixed point of the local step's projections that potential is exactly the
//!   local-global energy, so [`crate::backward_euler::incremental_potential`] is it.
//! - ADMM-PD: $`v = (z, \bar u)`$, the auxiliary and scaled dual variables. The positions are a
//!   function of them ($`x = A^{-1}(M\tilde x + dt^2 D^\top W^\top W(z - \bar u))`$, Eq 40), so
//!   ADMM is a fixed-point iteration on $`(z, \bar u)`$, the variable Peng et al. 2018
//!   accelerate in their ADMM discussion (and Zhang, Peng, Ouyang, Deng 2019, *Accelerating
//!   ADMM for Efficient Simulation and Optimization*, prove ADMM a fixed-point iteration of
//!   the second primal variable and the dual); $`G`$ is Algorithm 4's global step followed
//!   by its local step and dual update (the same iteration as lines 2.3-2.10, read from the
//!   global step on). The merit
//!   is Peng et al.'s combined residual, primal plus dual:
//!   $`r = |W(Dx - z^+)|^2 + |W(z^+ - z)|^2`$, with $`x`$ the global step's output and $`z^+`$
//!   the local step's; the primal part is $`|W(\bar u^+ - \bar u)|^2`$ by Eq (42).
//!
//! A budget of `iterations` global solves (the base solvers' count) gives Liu `iterations`
//! applications of $`G`$ and ADMM `iterations - 1`: ADMM's step starts with a local step
//! from $`\tilde x`$ (no solve) and ends with the global step that turns $`(z, \bar u)`$ into
//! positions. Unaccelerated, both reproduce their base solver's step bit for bit.

use std::str::FromStr;

use crate::admm::{default_omega, AdmmIterate};
use crate::backward_euler::incremental_potential;
use crate::error::{require_positive, Error, Result};
use crate::fast_mass_spring::FastMassSpring;
use crate::projective::{finish_step, node_of_columns, nodes_of_columns, GlobalSolve};
use crate::system::{MassSpringSystem, State, Vec3};

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
        /// $`A = M + dt^2 D^\top W^\top W D`$, factored once (Algorithm 4 line 1.5).
        a: Box<GlobalSolve>,
        iterate: Box<AdmmIterate>,
    },
}

/// One base iteration as a map $`v \leftarrow G(v)`$, with its merit function (module doc).
#[derive(Debug, Clone)]
pub struct LocalGlobal {
    system: MassSpringSystem,
    dt: f64,
    base: Base,
    iteration: Iteration,
    /// The variable $`v`$: column-major positions (Liu), or $`z`$ then $`\bar u`$, three
    /// coordinates per spring (ADMM).
    v: Vec<f64>,
    /// Global solves since [`LocalGlobal::begin`].
    solves: usize,
}

impl LocalGlobal {
    /// The base iteration of `base` for `system` with time step `dt` (s, > 0).
    pub fn new(system: &MassSpringSystem, dt: f64, base: Base) -> Result<Self> {
        let n = system.len();
        let s = system.springs().len();
        let (iteration, v) = match base {
            Base::Liu => (
                Iteration::Liu {
                    solver: Box::new(FastMassSpring::new(system, dt, 1)?),
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
                        a: Box::new(GlobalSolve::new(system, dt, &omega2)?),
                        iterate: Box::new(AdmmIterate::new(system, dt, omega)),
                    },
                    vec![0.0; 6 * s],
                )
            }
        };
        Ok(Self {
            system: system.clone(),
            dt,
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

    /// Applications of $`G`$ that a budget of `iterations` global solves allows (module doc).
    pub fn applications(&self, iterations: usize) -> usize {
        match self.base {
            Base::Liu => iterations,
            Base::Admm => iterations.saturating_sub(1),
        }
    }

    /// Global solves since [`LocalGlobal::begin`].
    pub fn solves(&self) -> usize {
        self.solves
    }

    /// The first variable of a step from `state`: Liu's first iterate (Algorithm 3, line 2.1
    /// and [`crate::fast_mass_spring::FirstIterate::Previous`]); for ADMM, $`\tilde x`$ and
    /// $`\bar u = 0`$ (lines 2.1-2.2) followed by the first local step (lines 2.4-2.7).
    pub fn begin(&mut self, state: &State) {
        self.solves = 0;
        match &mut self.iteration {
            Iteration::Liu { solver, y, .. } => {
                solver.begin_step(state);
                for ((y, x), v) in y.iter_mut().zip(&state.x).zip(&state.v) {
                    *y = x + self.dt * v;
                }
                self.v.copy_from_slice(solver.positions());
            }
            Iteration::Admm { iterate, .. } => {
                iterate.predict(&self.system, state, self.dt);
                iterate.x.copy_from_slice(&iterate.x_tilde);
                iterate.u_bar.fill(Vec3::zeros());
                iterate.local_step(&self.system);
                store_admm(iterate, &mut self.v);
            }
        }
    }

    /// The variable $`v`$ (layout in the field's doc).
    pub fn variable(&self) -> &[f64] {
        &self.v
    }

    /// The positions of the latest iterate, as nodes: the variable itself for Liu; for ADMM,
    /// whose variable is $`(z, \bar u)`$, the output of the latest global step ($`\tilde x`$
    /// before the first).
    pub fn positions(&self) -> impl Iterator<Item = Vec3> + '_ {
        nodes_of_columns(match &self.iteration {
            Iteration::Liu { .. } => &self.v,
            Iteration::Admm { iterate, .. } => &iterate.x,
        })
    }

    /// Replaces the variable (by an extrapolated one).
    pub fn set_variable(&mut self, v: &[f64]) {
        self.v.copy_from_slice(v);
    }

    /// $`v \leftarrow G(v)`$ if the merit of the current $`v`$ is at most `threshold`;
    /// otherwise $`v`$ is left unchanged. Either way the merit is returned. Liu's merit (the incremental
    /// potential) costs no solve, so a rejected Liu iterate costs none; ADMM's combined residual
    /// needs $`G(v)`$ itself, so a rejected ADMM iterate has spent a global solve.
    pub fn apply(&mut self, threshold: f64) -> Merit {
        match &mut self.iteration {
            Iteration::Liu { solver, y, x } => {
                let n = x.len();
                for (i, x) in x.iter_mut().enumerate() {
                    *x = node_of_columns(&self.v, n, i);
                }
                let merit = incremental_potential(&self.system, y, x, self.dt);
                if merit > threshold {
                    return Merit::Rejected(merit);
                }
                solver.positions_mut().copy_from_slice(&self.v);
                solver.iterate();
                self.solves += 1;
                self.v.copy_from_slice(solver.positions());
                Merit::Applied(merit)
            }
            Iteration::Admm { a, iterate } => {
                load_admm(&self.v, iterate);
                // 2.8-2.9, then the next iteration's 2.4-2.7.
                iterate.global_rhs();
                a.solve(&mut iterate.x, &iterate.x_n);
                self.solves += 1;
                iterate.local_step(&self.system);
                let s = iterate.z.len();
                let mut merit = 0.0;
                for (i, &omega) in iterate.omega().iter().enumerate() {
                    let z = Vec3::new(self.v[3 * i], self.v[3 * i + 1], self.v[3 * i + 2]);
                    let j = 3 * (s + i);
                    let u_bar = Vec3::new(self.v[j], self.v[j + 1], self.v[j + 2]);
                    let primal = omega * (iterate.u_bar[i] - u_bar);
                    let dual = omega * (iterate.z[i] - z);
                    merit += primal.norm_squared() + dual.norm_squared();
                }
                if merit > threshold {
                    return Merit::Rejected(merit);
                }
                store_admm(iterate, &mut self.v);
                Merit::Applied(merit)
            }
        }
    }

    /// Ends the step: the positions of the variable (for ADMM one more global step, Algorithm 4
    /// lines 2.8-2.9), then $`v_{n+1} = (x_{n+1} - x_n)/dt`$ (line 2.11). A non-finite iterate
    /// is an error naming the base, and `state` is left as it was.
    pub fn finish(&mut self, state: &mut State) -> Result<()> {
        let x = match &mut self.iteration {
            Iteration::Liu { .. } => &self.v,
            Iteration::Admm { a, iterate } => {
                load_admm(&self.v, iterate);
                iterate.global_rhs();
                a.solve(&mut iterate.x, &iterate.x_n);
                self.solves += 1;
                &iterate.x
            }
        };
        if !x.iter().all(|c| c.is_finite()) {
            return Err(Error::NotConverged {
                what: format!("accelerated {}", self.base.label()),
                detail: format!(
                    "the positions are no longer finite after {} global solves",
                    self.solves
                ),
            });
        }
        finish_step(state, x, self.dt);
        Ok(())
    }
}

/// $`(z, \bar u)`$ of `iterate` into the variable.
fn store_admm(iterate: &AdmmIterate, v: &mut [f64]) {
    let s = iterate.z.len();
    for (i, (z, u_bar)) in iterate.z.iter().zip(&iterate.u_bar).enumerate() {
        v[3 * i..3 * i + 3].copy_from_slice(z.as_slice());
        v[3 * (s + i)..3 * (s + i) + 3].copy_from_slice(u_bar.as_slice());
    }
}

/// The variable into $`(z, \bar u)`$ of `iterate`.
fn load_admm(v: &[f64], iterate: &mut AdmmIterate) {
    let s = iterate.z.len();
    for (i, (z, u_bar)) in iterate
        .z
        .iter_mut()
        .zip(iterate.u_bar.iter_mut())
        .enumerate()
    {
        *z = Vec3::from_column_slice(&v[3 * i..3 * i + 3]);
        *u_bar = Vec3::from_column_slice(&v[3 * (s + i)..3 * (s + i) + 3]);
    }
}
