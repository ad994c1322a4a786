//! The tutorial's particle system (seed 004, "Simulación física. Métodos numéricos", after
//! Baraff and Witkin's SIGGRAPH course notes; formulas in `docs/tutorial-formulas.md`).
//!
//! One model serves the thesis and the tutorial: the particles and springs are the nodes and
//! springs of a [`MassSpringSystem`] (an anchored particle is a fixed node), the phase space is
//! a [`State`] and the tutorial's per-particle "force accumulator" is the force array that
//! [`ParticleSystem::accumulate_forces`] fills at every derivative evaluation. What the
//! tutorial adds:
//!
//! - force objects applied to sets of particles ([`Force`]; [`forces::Gravity`],
//!   [`forces::Drag`], [`forces::DampedSprings`]);
//! - the first-order form $`x' = v`$, $`v' = f/m`$ ([`ParticleSystem::derivative`]), advanced by
//!   explicit Euler, symplectic Euler or RK4 ([`integrators`]), each a
//!   [`crate::integrators::time_stepper::TimeStepper`] driven by [`crate::integrators::time_stepper::simulate`] like the thesis's
//!   solvers;
//! - a ground plane with restitution ([`ground::Ground`]);
//! - beyond the tutorial, the adaptive Dormand-Prince 5(4) integrator it promises for "another
//!   article" ([`adaptive`]);
//! - its two scenes, a cloth dropped from 10 m and a pendulum that bounces on the floor, and a
//!   cloth hanging from two pinned corners for the thesis's solvers ([`scenes`]).

pub mod adaptive;
pub mod forces;
pub mod ground;
pub mod integrators;
pub mod scene_file;
pub mod scenes;

pub use adaptive::{AdaptiveStats, AdaptiveStepper};
pub use forces::{DampedSprings, Drag, Gravity};
pub use ground::Ground;
pub use integrators::{Integrator, ParticleStepper};

use crate::error::{Error, Result};
use crate::model::system::{MassSpringSystem, State, Vec3};

/// A set of particles a force object acts on.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum Particles {
    /// Every particle of the system.
    All,
    /// The listed particle indices.
    Only(Vec<usize>),
}

impl Particles {
    /// Rejects an empty list or an index outside the system, naming `field`.
    pub fn validate(&self, field: &str, system: &MassSpringSystem) -> Result<()> {
        match self {
            Particles::All => Ok(()),
            Particles::Only(indices) if indices.is_empty() => Err(Error::invalid(
                field,
                "[]",
                "a non-empty list of particle indices",
            )),
            Particles::Only(indices) => {
                for (k, &i) in indices.iter().enumerate() {
                    if i >= system.len() {
                        return Err(Error::invalid(
                            format!("{field}[{k}]"),
                            i,
                            &format!("a particle index in 0..{}", system.len()),
                        ));
                    }
                }
                Ok(())
            }
        }
    }

    /// The indices of the set in a system of `n` particles.
    pub fn indices(&self, n: usize) -> Box<dyn Iterator<Item = usize> + '_> {
        match self {
            Particles::All => Box::new(0..n),
            Particles::Only(indices) => Box::new(indices.iter().copied()),
        }
    }
}

/// A force object: adds its force on each particle it acts on to the accumulator `f`.
pub trait Force: std::fmt::Debug {
    /// A short name with the force's parameters.
    fn name(&self) -> String;
    /// Rejects a force that does not fit `system` (a particle or spring index out of range).
    fn validate(&self, system: &MassSpringSystem) -> Result<()>;
    /// Adds this force, evaluated at `state`, to `f` (one entry per particle).
    fn accumulate(&self, system: &MassSpringSystem, state: &State, f: &mut [Vec3]);
}

/// Particles, springs, force objects and an optional ground: what the tutorial calls a
/// particle system (the time step lives in the integrator).
#[derive(Debug)]
pub struct ParticleSystem {
    system: MassSpringSystem,
    forces: Vec<Box<dyn Force>>,
    ground: Option<Ground>,
}

impl ParticleSystem {
    /// A particle system with exactly the force objects `forces` (validated against `system`).
    ///
    /// The force objects are the only forces applied: `system.gravity()` is not added (it only
    /// enters the energy scale of [`crate::integrators::time_stepper::simulate`]'s divergence guard, beside the
    /// springs' energy scale).
    pub fn new(system: MassSpringSystem, forces: Vec<Box<dyn Force>>) -> Result<Self> {
        forces.into_iter().try_fold(
            Self {
                system,
                forces: Vec::new(),
                ground: None,
            },
            Self::with_force,
        )
    }

    /// The system's own forces as objects: its gravity on every particle and its springs,
    /// damped by each spring's `damping`. With zero damping the accumulated force equals
    /// [`MassSpringSystem::forces`] on every free particle.
    pub fn from_system(system: MassSpringSystem) -> Self {
        let gravity = Gravity {
            g: system.gravity(),
            particles: Particles::All,
        };
        Self {
            system,
            forces: vec![Box::new(gravity), Box::new(DampedSprings)],
            ground: None,
        }
    }

    /// Adds a force object after checking it fits the system.
    pub fn with_force(mut self, force: Box<dyn Force>) -> Result<Self> {
        force.validate(&self.system)?;
        self.forces.push(force);
        Ok(self)
    }

    /// Adds (or replaces) the ground plane.
    pub fn with_ground(mut self, ground: Ground) -> Self {
        self.ground = Some(ground);
        self
    }

    /// The particles and springs.
    pub fn system(&self) -> &MassSpringSystem {
        &self.system
    }

    /// The force objects, in the order they are applied.
    pub fn forces(&self) -> &[Box<dyn Force>] {
        &self.forces
    }

    /// The ground plane, if any.
    pub fn ground(&self) -> Option<&Ground> {
        self.ground.as_ref()
    }

    /// The force accumulator: clears `f`, then lets every force object add its share.
    pub fn accumulate_forces(&self, state: &State, f: &mut [Vec3]) {
        f.fill(Vec3::zeros());
        for force in &self.forces {
            force.accumulate(&self.system, state, f);
        }
    }

    /// The first-order form of Newton's law, $`x' = v`$, $`v' = f/m`$, at `state`, written to
    /// `derivative` (its `x` holds $`x'`$, its `v` holds $`v'`$); `f` is the accumulator's storage.
    /// Anchored particles have zero derivative, so they never move.
    pub fn derivative(&self, state: &State, f: &mut [Vec3], derivative: &mut State) {
        self.accumulate_forces(state, f);
        for (i, node) in self.system.nodes().iter().enumerate() {
            if node.fixed {
                derivative.x[i] = Vec3::zeros();
                derivative.v[i] = Vec3::zeros();
            } else {
                derivative.x[i] = state.v[i];
                derivative.v[i] = f[i] / node.mass;
            }
        }
    }

    /// Resolves ground contacts after a step (nothing without a ground).
    pub fn resolve_contacts(&self, state: &mut State) {
        if let Some(ground) = &self.ground {
            ground.resolve(&self.system, state);
        }
    }

    /// Total linear momentum $`\sum_i m_i v_i`$, kg·m/s.
    pub fn momentum(&self, state: &State) -> Vec3 {
        self.system
            .nodes()
            .iter()
            .zip(&state.v)
            .map(|(node, v)| node.mass * v)
            .sum()
    }
}
