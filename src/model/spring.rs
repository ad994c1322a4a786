//! A Hookean spring as constraint, energy, force and force Jacobian (thesis §2.1, Eqs 1-4),
//! and the distance constraint's gradient (§3.3, Eq 49).
//!
//! Following the phys-sim-book layout: one file for the one energy, exposing its value,
//! gradient (as the force) and Hessian (as the force Jacobian). All functions take the two
//! end points $`x_1, x_2`$; the quantities for $`x_2`$ follow by symmetry
//! ($`F_2 = -F_1`$, $`\partial F_1/\partial x_2 = -\partial F_1/\partial x_1`$).

use crate::model::lanes::{self, Lane};
use crate::model::Vec3;
use nalgebra::{Matrix3, Vector3};

/// Eqs. (1), (48): $`C = |x_1 - x_2| - l_0`$, the spring's deformation, and the distance
/// constraint that XPBD drives to zero. Generic over the [`Lane`] type so that a batch of
/// runs evaluates it once for all its lanes ([`crate::model::lanes`]); `f64` is one run.
pub fn constraint<T: Lane>(x1: &Vector3<T>, x2: &Vector3<T>, l0: T) -> T {
    (x1 - x2).norm() - l0
}

/// Eq. (49): $`\nabla_{x_1} C = (x_1 - x_2)/|x_1 - x_2|`$, the unit vector along the spring
/// ($`\nabla_{x_2} C`$ is its negative). A zero-length spring has no direction; the zero
/// vector is returned so that a projection leaves it alone (per lane: a lane's collapsed
/// spring does not disturb the others').
pub fn constraint_gradient<T: Lane>(x1: &Vector3<T>, x2: &Vector3<T>) -> Vector3<T> {
    let d = x1 - x2;
    let l = d.norm();
    lanes::select(l.simd_gt(T::zero()), d / l, Vector3::zeros())
}

/// Springs as arrays, one value per spring: at `f64` one run's, in lanes ([`crate::model::lanes`])
/// one per lane, their ends shared (Backward Euler's step, [`crate::solvers::backward_euler`]).
#[derive(Debug, Clone, Copy)]
pub struct SpringArrays<'a, T> {
    /// Each spring's two nodes, a then b.
    pub ends: &'a [(usize, usize)],
    /// $`l_0`$.
    pub rest_lengths: &'a [T],
    /// $`k`$.
    pub stiffness: &'a [T],
}

/// Eq. (2): $`E = \frac12 k\,C^\top C`$, Hooke's energy.
pub fn energy(x1: &Vec3, x2: &Vec3, l0: f64, k: f64) -> f64 {
    let c = constraint(x1, x2, l0);
    0.5 * k * c * c
}

/// Eq. (3): $`F_1 = -\partial E/\partial x_1 = -k\,C\,\nabla_{x_1}C`$, the force on $`x_1`$
/// (the force on $`x_2`$ is $`-F_1`$).
///
/// Generic over the [`Lane`] type like Eq. (1): `f64` is one spring, [`lanes::Lanes4`] four
/// ([`lanes::each_spring_force`]: the system's forces and the tutorial's damped springs); the
/// product is the same either way (IEEE multiplication commutes).
pub fn force<T: Lane>(x1: &Vector3<T>, x2: &Vector3<T>, l0: T, k: T) -> Vector3<T> {
    constraint_gradient(x1, x2) * (-k * constraint(x1, x2, l0))
}

/// Eq. (4): $`\partial F_1/\partial x_1 = -\partial^2 E/\partial x_1^2
/// = -k\left[\hat n\hat n^\top + (1 - l_0/l)(I - \hat n\hat n^\top)\right]`$.
///
/// Erratum (sign convention): the thesis calls $`-\partial^2E/\partial x^2`$ "the Hessian"; it is
/// the force Jacobian $`dF/dx`$ that Eq. (12) uses, the negative of the energy Hessian. Under
/// compression ($`l < l_0`$) the transverse term is positive and the block is indefinite. The other
/// blocks are
/// $`\partial F_1/\partial x_2 = \partial F_2/\partial x_1 = -\partial F_1/\partial x_1`$ and
/// $`\partial F_2/\partial x_2 = \partial F_1/\partial x_1`$.
pub fn force_jacobian(x1: &Vec3, x2: &Vec3, l0: f64, k: f64) -> Matrix3<f64> {
    force_jacobian_of(x1, x2, l0, k)
}

/// Eq. (4): [`force_jacobian`] for any [`Lane`] type (Backward Euler's batched runs), in
/// each lane, a lane's collapsed spring its own.
pub fn force_jacobian_of<T: Lane>(x1: &Vector3<T>, x2: &Vector3<T>, l0: T, k: T) -> Matrix3<T> {
    jacobian_with_transverse(x1, x2, l0, k, |t| t)
}

/// Eq. (4) projected to the negative semidefinite cone: the transverse factor
/// $`1 - l_0/l`$ is clamped at 0, so $`-\partial F/\partial x`$ is positive semidefinite even under
/// compression (projected Newton, used by the converged step's descent direction).
pub fn force_jacobian_definite(x1: &Vec3, x2: &Vec3, l0: f64, k: f64) -> Matrix3<f64> {
    jacobian_with_transverse(x1, x2, l0, k, |t| t.max(0.0))
}

/// Per lane, Eq. (4) with `transverse` applied to its factor $`1 - l_0/l`$; a collapsed
/// spring has no axis, and its stiffness acts equally in every direction ($`-kI`$). Both are
/// computed and the lane's chosen (at `f64`, a branch's result).
#[inline(always)]
fn jacobian_with_transverse<T: Lane>(
    x1: &Vector3<T>,
    x2: &Vector3<T>,
    l0: T,
    k: T,
    transverse: impl Fn(T) -> T,
) -> Matrix3<T> {
    let d = x1 - x2;
    let l = d.norm();
    // Scalar times matrix, written matrix times scalar (the same products) for a generic lane.
    let collapsed = Matrix3::identity() * -k;
    let n = d / l;
    let nn = n * n.transpose();
    let one = T::splat(1.0);
    let stretched = (nn + (Matrix3::identity() - nn) * transverse(one - l0 / l)) * -k;
    let axis = l.simd_ne(T::zero());
    Matrix3::from_fn(|r, c| stretched[(r, c)].select(axis, collapsed[(r, c)]))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn sample() -> (Vec3, Vec3) {
        (Vec3::new(0.3, -0.7, 0.2), Vec3::new(1.1, 0.4, -0.5))
    }

    /// Central differences of Eq (2) reproduce Eq (3) for both a stretched and a compressed spring.
    #[test]
    fn force_is_minus_energy_gradient() {
        let (x1, x2) = sample();
        for l0 in [0.5, 2.5] {
            let k = 7.0;
            let f = force(&x1, &x2, l0, k);
            let h = 1e-6;
            for c in 0..3 {
                let mut p = x1;
                let mut m = x1;
                p[c] += h;
                m[c] -= h;
                let grad = (energy(&p, &x2, l0, k) - energy(&m, &x2, l0, k)) / (2.0 * h);
                assert!(
                    (f[c] + grad).abs() < 1e-7,
                    "l0={l0} c={c}: {} vs {}",
                    f[c],
                    -grad
                );
            }
        }
    }

    /// Central differences of Eq (3) reproduce Eq (4), including the sign: dF/dx, not the Hessian.
    #[test]
    fn force_jacobian_is_force_derivative() {
        let (x1, x2) = sample();
        for l0 in [0.5, 2.5] {
            let k = 7.0;
            let jac = force_jacobian(&x1, &x2, l0, k);
            let h = 1e-6;
            for c in 0..3 {
                let mut p = x1;
                let mut m = x1;
                p[c] += h;
                m[c] -= h;
                let col = (force(&p, &x2, l0, k) - force(&m, &x2, l0, k)) / (2.0 * h);
                for r in 0..3 {
                    assert!((jac[(r, c)] - col[r]).abs() < 1e-6, "l0={l0} ({r},{c})");
                }
                // dF1/dx2 = -dF1/dx1
                let mut p2 = x2;
                let mut m2 = x2;
                p2[c] += h;
                m2[c] -= h;
                let col2 = (force(&x1, &p2, l0, k) - force(&x1, &m2, l0, k)) / (2.0 * h);
                for r in 0..3 {
                    assert!((-jac[(r, c)] - col2[r]).abs() < 1e-6);
                }
            }
        }
    }

    /// Under tension the force Jacobian is negative semidefinite; under compression it is
    /// indefinite, and the projected form is not.
    #[test]
    fn compression_makes_the_jacobian_indefinite() {
        let (x1, x2) = sample();
        let l = (x1 - x2).norm();
        let eig = |m: Matrix3<f64>| m.symmetric_eigenvalues();
        assert!(eig(force_jacobian(&x1, &x2, 0.5 * l, 3.0))
            .iter()
            .all(|&e| e <= 1e-12));
        assert!(eig(force_jacobian(&x1, &x2, 2.0 * l, 3.0))
            .iter()
            .any(|&e| e > 0.1));
        assert!(eig(force_jacobian_definite(&x1, &x2, 2.0 * l, 3.0))
            .iter()
            .all(|&e| e <= 1e-12));
    }

    #[test]
    fn constraint_and_gradient() {
        let x1 = Vec3::new(3.0, 4.0, 0.0);
        let x2 = Vec3::zeros();
        assert_eq!(constraint(&x1, &x2, 2.0), 3.0);
        assert_eq!(constraint_gradient(&x1, &x2), Vec3::new(0.6, 0.8, 0.0));
        assert_eq!(constraint_gradient(&x2, &x2), Vec3::zeros());
    }
}
