//! The inertial prediction $`y = x_n + h v_n + h^2 M^{-1} f_{ext}`$ of a step (or stage), node
//! by node: the start that [`super::first_iterate`] names (c) and against which
//! [`super::stopping::Convergence::begin_from`] measures every run's actual start.

use crate::model::lanes::Lane;
use crate::model::system::{MassSpringSystem, Vec3};
use nalgebra::Vector3;

/// $`h^2 m_i^{-1} f_{ext,i}`$, the last term of node `i`'s inertial prediction.
pub fn pull(system: &MassSpringSystem, h: f64, i: usize) -> Vec3 {
    h * h / system.nodes()[i].mass * system.external_force(i)
}

/// (c) The inertial prediction of a free node, $`x_n + h v_n + h^2 m^{-1} f_{ext}`$, for any
/// lane type, `pull` being the last term ([`pull`]).
#[inline]
pub fn predicted<T: Lane>(x: Vector3<T>, v: Vector3<T>, h: T, pull: Vector3<T>) -> Vector3<T> {
    x + v * h + pull
}

/// [`super::first_iterate::inertial_prediction`] of node `i` from the positions `x` and velocities `v` (a stage's
/// pseudo-state $`(x_a, u_0)`$ with `dt` its $`\tau`$).
#[inline]
pub fn inertial_prediction_from(
    system: &MassSpringSystem,
    x: &[Vec3],
    v: &[Vec3],
    dt: f64,
    i: usize,
) -> Vec3 {
    if system.nodes()[i].fixed {
        x[i]
    } else {
        predicted(x[i], v[i], dt, pull(system, dt, i))
    }
}
