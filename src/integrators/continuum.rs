//! The optimization integrators on a continuum system (issue 50, item 4): Backward Euler,
//! implicit midpoint, BDF2 and TR-BDF2 take the continuum's model unchanged, each stage solved
//! by the crate's one projected Newton ([`crate::model::projected_newton`]) to a stated
//! residual.
//!
//! The state is the nodes' displacements u from the rest shape and their velocities v (flat,
//! d numbers a node, as [`ContinuumSystem`] takes them), the masses lumped from the elements'
//! rest measure and density (`docs/fem-scenes.md`). A stage (the module doc of
//! [`crate::integrators::optimization_integrator`]) minimises
//! ```math
//! \Phi(u) = \frac{1}{2\tau^2}\lVert u - \hat y\rVert_M^2 + E(u),\qquad \hat y = u_a + \tau u_0,
//! ```
//! E the potential energy (elastic, minus the work of gravity and the loads), so that
//! −∇Φ = f(u) − M(u − ŷ)/τ² is a force, and its minimiser's velocity is u* = (u − u_a)/τ.
//! Each scheme's pseudo-state $`(u_a, u_0)`$ and its step's end are the springs' formulas,
//! the same functions ([`midpoint_end`], [`bdf2_pseudo`], [`trapezoid_pseudo`],
//! [`tr_bdf2_pseudo`]). No dissipation: the continuum has none yet.
//!
//! Stop: the stage's residual (the largest force component of −∇Φ on a free node) at most
//! the tolerance ([`DEFAULT_TOLERANCE`], 1e-9) times the largest nodal load, or, in a scene
//! without loads (a free, spinning beam), the largest node's weight under standard gravity
//! ([`WEIGHT_GRAVITY`]): a fixed scale, the same at every stage.

use crate::error::{require_positive, Error, Result};
use crate::integrators::optimization_integrator::{
    bdf2_pseudo, midpoint_end, tr_bdf2_coefficients, tr_bdf2_pseudo, trapezoid_pseudo,
    OptimizationIntegrator, GAMMA,
};
use crate::model::continuum::system::ContinuumSystem;
use crate::model::linear::SymmetricMatrix;
use crate::model::projected_newton::{minimise, Objective};

/// The default tolerance of a stage's residual relative to the largest nodal load.
pub const DEFAULT_TOLERANCE: f64 = 1e-9;
/// The gravity that turns the largest mass into the residual's scale where a scene has no
/// loads, m/s².
pub const WEIGHT_GRAVITY: f64 = 9.81;

/// Displacements and velocities, flat, d numbers a node.
#[derive(Debug, Clone, PartialEq)]
pub struct ContinuumState {
    /// m, from the rest shape.
    pub u: Vec<f64>,
    /// m/s.
    pub v: Vec<f64>,
}

impl ContinuumState {
    /// At rest in the system's start (the rest shape, fixed nodes at their own displacement):
    /// fem-scenes.md's release at t = 0.
    pub fn released(system: &ContinuumSystem) -> Self {
        Self {
            u: system.start().to_vec(),
            v: vec![0.0; system.start().len()],
        }
    }

    /// ½ Σ m_i |v_i|², J.
    pub fn kinetic_energy(&self, system: &ContinuumSystem) -> f64 {
        let d = system.dimension();
        self.v
            .iter()
            .enumerate()
            .map(|(k, v)| 0.5 * system.masses()[k / d] * v * v)
            .sum()
    }
}

/// One stage's objective Φ (module doc), ŷ flat over every node.
struct Stage<'a> {
    system: &'a ContinuumSystem,
    prediction: Vec<f64>,
    /// 1/τ².
    inertia: f64,
}

impl Stage<'_> {
    fn mass(&self, k: usize) -> f64 {
        self.system.masses()[k / self.system.dimension()]
    }
}

impl Objective for Stage<'_> {
    fn value_and_magnitude(&self, u: &[f64]) -> (f64, f64) {
        let (energy, magnitude) = self.system.energy_and_magnitude(u);
        let kinetic: f64 = (0..u.len())
            .map(|k| 0.5 * self.inertia * self.mass(k) * (u[k] - self.prediction[k]).powi(2))
            .sum();
        (energy + kinetic, magnitude + kinetic)
    }

    fn descent(&self, u: &[f64]) -> Vec<f64> {
        let mut forces = self.system.forces(u);
        for (k, f) in forces.iter_mut().enumerate() {
            *f -= self.inertia * self.mass(k) * (u[k] - self.prediction[k]);
        }
        self.system.free_part(&forces)
    }

    fn hessian(&self, u: &[f64], projected: bool) -> SymmetricMatrix {
        let mut h = self.system.hessian(u, projected);
        let d = self.system.dimension();
        let free = (0..self.system.node_count()).filter(|&i| !self.system.is_fixed(i));
        for (f, i) in free.enumerate() {
            for c in 0..d {
                h.add(f * d + c, f * d + c, self.inertia * self.system.masses()[i]);
            }
        }
        h
    }

    fn moved(&self, u: &[f64], step: &[f64], alpha: f64) -> Vec<f64> {
        self.system.moved(u, step, alpha)
    }
}

/// What the stages of a run took: Newton iterations and the largest relative residual left.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct StageLog {
    pub stages: usize,
    pub iterations: usize,
    pub largest_residual: f64,
}

/// An optimization integrator on a continuum system, every stage solved by projected Newton.
#[derive(Debug, Clone)]
pub struct ContinuumIntegrator {
    system: ContinuumSystem,
    integrator: OptimizationIntegrator,
    h: f64,
    tolerance: f64,
    /// The residual's scale, N (module doc).
    scale: f64,
    /// BDF2: the state before the last step, and the state the last step produced.
    history: Option<(ContinuumState, ContinuumState)>,
    log: StageLog,
}

impl ContinuumIntegrator {
    /// `integrator` with step `h` (s, > 0) on `system`, its stages solved to `tolerance`
    /// (> 0) of the largest nodal load; every free node needs a positive mass.
    pub fn new(
        system: &ContinuumSystem,
        integrator: OptimizationIntegrator,
        h: f64,
        tolerance: f64,
    ) -> Result<Self> {
        require_positive("dt", h)?;
        require_positive("tolerance", tolerance)?;
        for i in (0..system.node_count()).filter(|&i| !system.is_fixed(i)) {
            require_positive(format!("masses[{i}]"), system.masses()[i])?;
        }
        let largest_mass = system.masses().iter().fold(0.0, |m: f64, &x| m.max(x));
        let scale = match system.largest_load() {
            load if load > 0.0 => load,
            _ => WEIGHT_GRAVITY * largest_mass,
        };
        Ok(Self {
            system: system.clone(),
            integrator,
            h,
            tolerance,
            scale,
            history: None,
            log: StageLog::default(),
        })
    }

    /// The system.
    pub fn system(&self) -> &ContinuumSystem {
        &self.system
    }

    /// The time step, s.
    pub fn dt(&self) -> f64 {
        self.h
    }

    /// What the stages took so far.
    pub fn log(&self) -> StageLog {
        self.log
    }

    /// The stage of step `tau` from the pseudo-state `(u_a, u_0)` (fixed nodes: their own
    /// displacement, no velocity), solved: its minimiser and velocity.
    fn stage(&mut self, anchor: Vec<f64>, velocity: &[f64], tau: f64) -> Result<ContinuumState> {
        let d = self.system.dimension();
        let free = |k: usize| !self.system.is_fixed(k / d);
        let prediction: Vec<f64> = (0..anchor.len())
            .map(|k| {
                if free(k) {
                    anchor[k] + tau * velocity[k]
                } else {
                    anchor[k]
                }
            })
            .collect();
        let stage = Stage {
            system: &self.system,
            prediction: prediction.clone(),
            inertia: 1.0 / (tau * tau),
        };
        let minimum = minimise(
            &stage,
            prediction,
            self.tolerance,
            self.scale,
            &format!("{} stage", self.integrator.label()),
        )?;
        self.log.stages += 1;
        self.log.iterations += minimum.iterations;
        self.log.largest_residual = self.log.largest_residual.max(minimum.relative_residual);
        let v = (0..anchor.len())
            .map(|k| {
                if free(k) {
                    (minimum.u[k] - anchor[k]) / tau
                } else {
                    0.0
                }
            })
            .collect();
        Ok(ContinuumState { u: minimum.u, v })
    }

    /// Per free coordinate `f(k)`, fixed ones as in `state` (displacement, no velocity).
    fn pseudo(
        &self,
        state: &ContinuumState,
        f: impl Fn(usize) -> (f64, f64),
    ) -> (Vec<f64>, Vec<f64>) {
        let d = self.system.dimension();
        (0..state.u.len())
            .map(|k| {
                if self.system.is_fixed(k / d) {
                    (state.u[k], 0.0)
                } else {
                    f(k)
                }
            })
            .unzip()
    }

    /// The TR-BDF2 step: the trapezoidal stage, then the BDF2 stage.
    fn tr_bdf2(&mut self, state: &ContinuumState) -> Result<ContinuumState> {
        let tau = GAMMA * self.h / 2.0;
        let forces = self.system.forces(&state.u);
        let d = self.system.dimension();
        let masses = self.system.masses();
        let (anchor, velocity) = self.pseudo(state, |k| {
            trapezoid_pseudo(state.u[k], state.v[k], forces[k], tau, masses[k / d])
        });
        let gamma = self.stage(anchor, &velocity, tau)?;
        let (a, b, _) = tr_bdf2_coefficients();
        let (anchor, velocity) = self.pseudo(state, |k| {
            (
                tr_bdf2_pseudo(gamma.u[k], state.u[k], (a, b)),
                tr_bdf2_pseudo(gamma.v[k], state.v[k], (a, b)),
            )
        });
        self.stage(anchor, &velocity, tau)
    }

    /// Advances `state` by one step.
    pub fn step(&mut self, state: &mut ContinuumState) -> Result<()> {
        if state.u.len() != self.system.start().len() || state.v.len() != state.u.len() {
            return Err(Error::invalid(
                "state",
                format!("{} and {} numbers", state.u.len(), state.v.len()),
                &format!("{} each (d a node)", self.system.start().len()),
            ));
        }
        let next = match self.integrator {
            OptimizationIntegrator::BackwardEuler => {
                self.stage(state.u.clone(), &state.v.clone(), self.h)?
            }
            OptimizationIntegrator::ImplicitMidpoint => {
                let mid = self.stage(state.u.clone(), &state.v.clone(), self.h / 2.0)?;
                let (u, v) = self.pseudo(state, |k| {
                    (
                        midpoint_end(mid.u[k], state.u[k]),
                        midpoint_end(mid.v[k], state.v[k]),
                    )
                });
                ContinuumState { u, v }
            }
            OptimizationIntegrator::TrBdf2 => self.tr_bdf2(state)?,
            OptimizationIntegrator::Bdf2 => match self.history.take() {
                // x_n the state the last step produced: BDF2 from it and x_{n−1}.
                Some((previous, last)) if last == *state => {
                    let (anchor, velocity) = self.pseudo(state, |k| {
                        (
                            bdf2_pseudo(state.u[k], previous.u[k]),
                            bdf2_pseudo(state.v[k], previous.v[k]),
                        )
                    });
                    self.stage(anchor, &velocity, 2.0 * self.h / 3.0)?
                }
                // A first step, or from a state it did not produce: one TR-BDF2 step.
                _ => self.tr_bdf2(state)?,
            },
        };
        if self.integrator == OptimizationIntegrator::Bdf2 {
            self.history = Some((state.clone(), next.clone()));
        }
        *state = next;
        Ok(())
    }
}
