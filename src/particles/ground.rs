//! The tutorial's floor: its pendulum "rebota en el suelo, perdiendo así energía". A
//! horizontal plane with a restitution coefficient, resolved after every step.

use crate::error::{require_finite, Error, Result};
use crate::model::system::{MassSpringSystem, State};

/// The plane $`y = y_0`$, $`y_0`$ = `height`, with restitution `e` $`\in [0, 1]`$.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Ground {
    height: f64,
    restitution: f64,
}

impl Ground {
    /// A floor at `height` m (finite) with restitution `restitution` in [0, 1]
    /// (0: the particle stops on contact; 1: elastic bounce).
    pub fn new(height: f64, restitution: f64) -> Result<Self> {
        require_finite("ground.height", height)?;
        if !(0.0..=1.0).contains(&restitution) {
            return Err(Error::invalid(
                "ground.restitution",
                restitution,
                "a number in [0, 1]",
            ));
        }
        Ok(Self {
            height,
            restitution,
        })
    }

    /// Height of the plane, m.
    pub fn height(&self) -> f64 {
        self.height
    }

    /// Restitution coefficient $`e`$.
    pub fn restitution(&self) -> f64 {
        self.restitution
    }

    /// Collision response: a free particle below the plane is put back on it and, if it is moving
    /// into the plane, its normal velocity is reversed and scaled by $`e`$,
    /// $`v_y \leftarrow -e\,v_y`$ (a drop from $`h`$ rebounds to $`e^2 h`$). The tangential
    /// velocity is kept (a frictionless floor). Anchored particles are left alone.
    pub fn resolve(&self, system: &MassSpringSystem, state: &mut State) {
        for ((node, x), v) in system.nodes().iter().zip(&mut state.x).zip(&mut state.v) {
            if node.fixed || x.y >= self.height {
                continue;
            }
            x.y = self.height;
            if v.y < 0.0 {
                v.y *= -self.restitution;
            }
        }
    }
}
