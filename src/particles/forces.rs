//! The tutorial's force objects ("Hablemos de fuerzas"): gravity, viscous drag and the damped
//! spring. Each acts on its own set of particles; their parameters are checked by
//! [`Force::validate`] when the object joins a [`super::ParticleSystem`].

use super::{Force, Particles};
use crate::error::{require_finite, require_non_negative, Result};
use crate::model::lanes::{each_spring_force, Lane, SpringForce, SpringInputs};
use crate::model::spring;
use crate::model::system::{MassSpringSystem, Spring, State, Vec3};
use nalgebra::Vector3;

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

    /// Four springs at a time ([`each_spring_force`]), their sums in spring order.
    fn accumulate(&self, system: &MassSpringSystem, state: &State, f: &mut [Vec3]) {
        each_spring_force(system.springs(), &Damped(state), |s, f_a| {
            f[s.a] += f_a;
            f[s.b] -= f_a;
        });
    }
}

/// [`damped_spring_force`] at a state, for [`each_spring_force`].
struct Damped<'a>(&'a State);

impl SpringForce<Spring> for Damped<'_> {
    #[inline(always)]
    fn on_first_end<T: Lane>(&self, spring: &impl SpringInputs<Spring, T>) -> Vector3<T> {
        let ((x_a, x_b), (v_a, v_b)) = (spring.ends(&self.0.x), spring.ends(&self.0.v));
        damped_spring_force(
            &x_a,
            &x_b,
            &v_a,
            &v_b,
            spring.value(|s| s.rest_length),
            spring.value(|s| s.stiffness),
            spring.value(|s| s.damping),
        )
    }
}

/// The tutorial's damped spring, force on particle $`a`$ (particle $`b`$ receives $`f_b = -f_a`$):
/// $`f_a = -\left[k_s(|l| - r) + k_d\,\frac{\dot l\cdot l}{|l|}\right]\frac{l}{|l|}`$ with
/// $`l = x_a - x_b`$, $`\dot l = v_a - v_b`$.
///
/// The elastic part is the thesis's Hooke force, Eq. (3) ([`spring::force`]); the damping part
/// acts along the spring only, so it resists stretching and compression but not rotation. A
/// collapsed spring ($`|l| = 0`$) has no axis and exerts no force.
///
/// Generic over the [`Lane`] type: `f64` is one spring,
/// [`Lanes4`](crate::model::lanes::Lanes4) four.
pub fn damped_spring_force<T: Lane>(
    x_a: &Vector3<T>,
    x_b: &Vector3<T>,
    v_a: &Vector3<T>,
    v_b: &Vector3<T>,
    rest_length: T,
    k_s: T,
    k_d: T,
) -> Vector3<T> {
    let n = spring::constraint_gradient(x_a, x_b);
    let l_dot = v_a - v_b;
    spring::force(x_a, x_b, rest_length, k_s) - n * (k_d * l_dot.dot(&n))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::model::system::Node;

    /// The springs' sum one spring at a time, at `f64`: the oracle of the four-lane one.
    fn one_at_a_time(system: &MassSpringSystem, state: &State) -> Vec<Vec3> {
        let mut f = vec![Vec3::zeros(); system.len()];
        for s in system.springs() {
            let (x, v) = (&state.x, &state.v);
            let f_a = damped_spring_force(
                &x[s.a],
                &x[s.b],
                &v[s.a],
                &v[s.b],
                s.rest_length,
                s.stiffness,
                s.damping,
            );
            f[s.a] += f_a;
            f[s.b] -= f_a;
        }
        f
    }

    /// Four springs at a time give the bits of one at a time: eleven springs (two groups of
    /// four and three left over) with their own rest lengths, stiffnesses and damping, on shared
    /// nodes.
    #[test]
    fn four_springs_at_a_time_give_each_springs_own_bits() {
        let mut nodes: Vec<Node> = (0..7)
            .map(|i| {
                let t = i as f64;
                Node {
                    mass: 1.0 + 0.1 * t,
                    position: Vec3::new(0.37 * t, (1.3 * t).sin(), 0.21 * t * t),
                    velocity: Vec3::new((0.7 * t).cos(), -0.3 * t, 0.11),
                    fixed: false,
                }
            })
            .collect();
        nodes[6].position = nodes[5].position;
        // Node 0 in all four springs of the first group, so that the order of the sums
        // shows in their bits; the collapsed spring (5, 6) in a lane of the second.
        let ends = [
            (0, 1),
            (2, 0),
            (0, 3),
            (4, 0),
            (1, 2),
            (5, 6),
            (3, 4),
            (2, 5),
            (4, 5),
            (6, 0),
            (1, 3),
        ];
        let springs: Vec<Spring> = ends
            .iter()
            .enumerate()
            .map(|(j, &(a, b))| Spring {
                a,
                b,
                rest_length: 0.5 + 0.07 * j as f64,
                stiffness: 1e3 * (1.0 + j as f64),
                damping: 0.3 * j as f64,
            })
            .collect();
        let system = MassSpringSystem::new(nodes, springs, Vec3::zeros()).unwrap();
        let state = system.initial_state();
        let mut f = vec![Vec3::zeros(); system.len()];
        DampedSprings.accumulate(&system, &state, &mut f);
        let bits = |f: &[Vec3]| {
            f.iter()
                .flat_map(|p| p.iter().map(|c| c.to_bits()))
                .collect::<Vec<_>>()
        };
        assert_eq!(bits(&f), bits(&one_at_a_time(&system, &state)));
    }
}
