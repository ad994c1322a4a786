//! The tutorial's force objects ("Hablemos de fuerzas"): gravity, viscous drag and the damped
//! spring. Each acts on its own set of particles; their parameters are checked by
//! [`Force::validate`] when the object joins a [`super::ParticleSystem`].

use super::{Force, Particles};
use crate::error::{require_finite, require_non_negative, Result};
use crate::model::spring;
use crate::model::system::{MassSpringSystem, Spring, State, Vec3};

/// Gravity on a set of particles: $`f_i = m_i\,g`$. A system may hold several, each on its own
/// set of particles.
#[derive(Debug, Clone, PartialEq)]
pub struct Gravity {
    /// Acceleration, m/s² (finite).
    pub g: Vec3,
    pub particles: Particles,
}

impl Force for Gravity {
    fn name(&self) -> String {
        format!("gravity {:?} m/s²", self.g.as_slice())
    }

    fn validate(&self, system: &MassSpringSystem) -> Result<()> {
        for c in 0..3 {
            require_finite(format!("gravity.g[{c}]"), self.g[c])?;
        }
        self.particles.validate("gravity.particles", system)
    }

    fn accumulate(&self, system: &MassSpringSystem, _state: &State, f: &mut [Vec3]) {
        for i in self.particles.indices(system.len()) {
            f[i] += system.nodes()[i].mass * self.g;
        }
    }
}

/// The tutorial's ideal viscous drag ("fricción") on a set of particles: $`f_i = -k_f\,v_i`$.
#[derive(Debug, Clone, PartialEq)]
pub struct Drag {
    /// Drag coefficient $`k_f`$, N·s/m (>= 0).
    pub k_f: f64,
    pub particles: Particles,
}

impl Force for Drag {
    fn name(&self) -> String {
        format!("drag k_f = {} N·s/m", self.k_f)
    }

    fn validate(&self, system: &MassSpringSystem) -> Result<()> {
        require_non_negative("drag.k_f", self.k_f)?;
        self.particles.validate("drag.particles", system)
    }

    fn accumulate(&self, system: &MassSpringSystem, state: &State, f: &mut [Vec3]) {
        for i in self.particles.indices(system.len()) {
            f[i] -= self.k_f * state.v[i];
        }
    }
}

/// Every spring of the system as the tutorial's damped spring ([`damped_spring_force`]),
/// with each spring's own rest length $`r`$, stiffness $`k_s`$ and damping $`k_d`$.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct DampedSprings;

impl Force for DampedSprings {
    fn name(&self) -> String {
        "damped springs".into()
    }

    fn validate(&self, _system: &MassSpringSystem) -> Result<()> {
        // The springs were validated with the system.
        Ok(())
    }

    /// A few springs' forces at a time, then their sums in spring order: each spring's
    /// square root and divisions run beside the others' instead of after the sums of the
    /// spring before (the sums' order, so their bits, unchanged).
    fn accumulate(&self, system: &MassSpringSystem, state: &State, f: &mut [Vec3]) {
        const AT_ONCE: usize = 8;
        for springs in system.springs().chunks(AT_ONCE) {
            let mut forces = [Vec3::zeros(); AT_ONCE];
            for (f_a, s) in forces.iter_mut().zip(springs) {
                *f_a = damped_spring_force(s, &state.x, &state.v);
            }
            for (f_a, s) in forces.iter().zip(springs) {
                f[s.a] += f_a;
                f[s.b] -= f_a;
            }
        }
    }
}

/// The tutorial's damped spring, force on particle $`a`$ (particle $`b`$ receives $`f_b = -f_a`$):
/// $`f_a = -\left[k_s(|l| - r) + k_d\,\frac{\dot l\cdot l}{|l|}\right]\frac{l}{|l|}`$ with
/// $`l = x_a - x_b`$, $`\dot l = v_a - v_b`$.
///
/// The elastic part is the thesis's Hooke force, Eq. (3) ([`spring::force`]); the damping part
/// acts along the spring only, so it resists stretching and compression but not rotation. A
/// collapsed spring ($`|l| = 0`$) has no axis and exerts no force.
pub fn damped_spring_force(s: &Spring, x: &[Vec3], v: &[Vec3]) -> Vec3 {
    let (x_a, x_b) = (&x[s.a], &x[s.b]);
    let n = spring::constraint_gradient(x_a, x_b);
    let l_dot = v[s.a] - v[s.b];
    spring::force(x_a, x_b, s.rest_length, s.stiffness) - s.damping * l_dot.dot(&n) * n
}
