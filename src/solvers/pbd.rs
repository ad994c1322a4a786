//! Position-Based Dynamics, PBD (thesis §2.2, Algorithm 1, Eqs 13-14; Müller et al. 2007).
//!
//! Each spring is a distance constraint $`C_j = |x_1 - x_2| - l_0`$ (Eq 48, the deformation of
//! Eq 1), projected on its own by nonlinear Gauss-Seidel in index order: the scaling $`s_j`$ of
//! Eq 13 ([`s`]) and the correction $`\Delta x = s_j M^{-1}\nabla C_j`$ of Eq 14 ([`delta_x`]).
//! PBD has no physical stiffness: the springs' $`k`$ (N/m) is ignored. Each constraint instead
//! carries a dimensionless **stiffness factor** in $`[0, 1]`$ that multiplies its correction, as
//! the thesis describes after Eq 14 (Müller 2007: "multiply $`\Delta x`$ by $`k`$"); it is not the
//! spring stiffness $`k`$ in N/m, and its effect depends on the time step and the iteration count
//! (§2.2). Müller's iteration-independent variant $`1 - (1 - k)^{1/n}`$ is not used: the thesis
//! does not adopt it.
//!
//! Erratum (Algorithm 1, line 6): as printed, the projection updates $`x`$ ("$`x_{i+1} = x_i +
//! \Delta x`$", $`i`$ doubling as node and iteration index) and the predicted positions $`p`$ never
//! change, so lines 10-11 would undo the solve. The consistent form, Müller's, is used: the
//! projection updates $`p`$, then line 10 sets $`v = (p - x)/dt`$ and line 11 sets $`x = p`$.
//!
//! Fixed nodes have inverse mass $`w = 0`$ (thesis §3.3, after Müller 2007), so Eq 14 never moves
//! them; they are also left out of lines 1-2. With every stiffness factor equal to 1 the method
//! is XPBD with zero compliance (§2.2.1), bit for bit: [`crate::solvers::xpbd::Xpbd::with_compliance`].

use crate::error::{require_positive, Error, Result};
use crate::integrators::stopping::{Convergence, FixedPoint};
use crate::integrators::time_stepper::TimeStepper;
use crate::model::spring;
use crate::model::system::{MassSpringSystem, State, Vec3};
use crate::solvers::xpbd::{generalized_inverse_mass, inverse_denominator};

/// Eq. (13): $`s_j = \dfrac{-C_j(x_i)}{\nabla C_j M^{-1}\nabla C_j^\top}`$, given the constraint's
/// value `c` and its denominator inverted once per spring, `inverse_w`
/// $`= 1/(\nabla C_j M^{-1}\nabla C_j^\top)`$ (Eq 50), by
/// [`crate::solvers::xpbd::inverse_denominator`] with zero compliance: XPBD's Eq 18 at $`\tilde\alpha = 0`$
/// rounds the same way, and a constraint that nothing can move ($`w = 0`$: both ends fixed) gets
/// $`s_j = 0`$.
pub fn s(c: f64, inverse_w: f64) -> f64 {
    -c * inverse_w
}

/// Eq. (14): $`\Delta x = s_j M^{-1}\nabla C_j(x_i)`$ scaled by the constraint's stiffness factor;
/// for a distance constraint $`\Delta x_1 = w_1\nabla_{x_1}C\,s_j`$ and
/// $`\Delta x_2 = -w_2\nabla_{x_1}C\,s_j`$, given `grad` $`= \nabla_{x_1}C`$ (Eq 49).
pub fn delta_x(grad: &Vec3, w1: f64, w2: f64, s: f64, stiffness_factor: f64) -> (Vec3, Vec3) {
    let s = stiffness_factor * s;
    (grad * (w1 * s), -grad * (w2 * s))
}

/// PBD (Algorithm 1) with a fixed number of solver iterations per step.
#[derive(Debug, Clone)]
pub struct Pbd {
    system: MassSpringSystem,
    dt: f64,
    iterations: usize,
    /// Dimensionless factor in [0, 1] per spring (not the stiffness in N/m).
    stiffness_factors: Vec<f64>,
    /// Inverse masses $`w_i`$, 0 for fixed nodes.
    w: Vec<f64>,
    /// Eq (13)'s inverted denominator per spring ([`s`]).
    inverse_w: Vec<f64>,
    /// $`w_i f_{ext}`$ per node, m/s² (0 for fixed nodes).
    external_acceleration: Vec<Vec3>,
    /// Predicted positions $`p`$, the iterate of lines 3-9.
    p: Vec<Vec3>,
    /// When a step stops iterating, and the iterations steps took.
    convergence: Convergence,
    /// Whether the step's sweeps have reached a fixed point.
    fixed_point: FixedPoint,
}

impl Pbd {
    /// PBD for `system` with time step `dt` (s, > 0), `iterations` (>= 1) solver iterations per
    /// step, and the same dimensionless `stiffness_factor` in [0, 1] for every constraint.
    pub fn new(
        system: &MassSpringSystem,
        dt: f64,
        iterations: usize,
        stiffness_factor: f64,
    ) -> Result<Self> {
        require_factor("stiffness_factor", stiffness_factor)?;
        let factors = vec![stiffness_factor; system.springs().len()];
        Self::with_stiffness_factors(system, dt, iterations, &factors)
    }

    /// PBD with one dimensionless stiffness factor in [0, 1] per spring, in spring order.
    pub fn with_stiffness_factors(
        system: &MassSpringSystem,
        dt: f64,
        iterations: usize,
        stiffness_factors: &[f64],
    ) -> Result<Self> {
        require_positive("dt", dt)?;
        system.require_undamped_springs()?;
        if iterations == 0 {
            return Err(Error::invalid("iterations", 0, "an integer >= 1"));
        }
        if stiffness_factors.len() != system.springs().len() {
            return Err(Error::invalid(
                "stiffness_factors.len()",
                stiffness_factors.len(),
                &format!("the number of springs, {}", system.springs().len()),
            ));
        }
        for (j, &factor) in stiffness_factors.iter().enumerate() {
            require_factor(format!("stiffness_factors[{j}]"), factor)?;
        }
        let w = system.inverse_masses();
        let external_acceleration = (0..system.len())
            .map(|i| w[i] * system.external_force(i))
            .collect();
        let inverse_w = system
            .springs()
            .iter()
            .map(|s| inverse_denominator(generalized_inverse_mass(w[s.a], w[s.b]), 0.0))
            .collect();
        Ok(Self {
            system: system.clone(),
            dt,
            iterations,
            stiffness_factors: stiffness_factors.to_vec(),
            w,
            inverse_w,
            external_acceleration,
            p: vec![Vec3::zeros(); system.len()],
            convergence: Convergence::default(),
            fixed_point: FixedPoint::default(),
        })
    }

    /// The stiffness factor of each spring.
    pub fn stiffness_factors(&self) -> &[f64] {
        &self.stiffness_factors
    }
}

/// Checks a dimensionless stiffness factor: in [0, 1].
pub fn require_factor(field: impl Into<String>, factor: f64) -> Result<f64> {
    if (0.0..=1.0).contains(&factor) {
        Ok(factor)
    } else {
        Err(Error::invalid(
            field,
            factor,
            "a dimensionless factor in [0, 1] (not the stiffness in N/m)",
        ))
    }
}

impl TimeStepper for Pbd {
    fn name(&self) -> String {
        let first = self.stiffness_factors.first().copied().unwrap_or(1.0);
        if self.stiffness_factors.iter().all(|&f| f == first) {
            format!(
                "PBD ({}, stiffness factor {first})",
                self.convergence
                    .iterations_label(self.iterations, "iterations")
            )
        } else {
            format!(
                "PBD ({}, stiffness factor per spring)",
                self.convergence
                    .iterations_label(self.iterations, "iterations")
            )
        }
    }

    fn dt(&self) -> f64 {
        self.dt
    }

    fn system(&self) -> &MassSpringSystem {
        &self.system
    }

    fn convergence(&mut self) -> Option<&mut Convergence> {
        Some(&mut self.convergence)
    }

    /// Algorithm 1 with its erratum: the projection moves $`p`$.
    // region: step
    fn step(&mut self, state: &mut State) -> Result<()> {
        let dt = self.dt;
        let p = &mut self.p;
        // Lines 1-2 (the velocity's update kept for after the start is measured against
        // xₙ + h vₙ + h² M⁻¹f_ext; the same operations in the same order).
        for (i, p) in p.iter_mut().enumerate() {
            *p = state.x[i];
            if self.w[i] > 0.0 {
                *p += dt * (state.v[i] + dt * self.external_acceleration[i]);
            }
        }
        self.convergence
            .begin_from(&self.system, &state.x, &state.v, dt, p.iter().copied());
        for (v, (&w, &a)) in state
            .v
            .iter_mut()
            .zip(self.w.iter().zip(&self.external_acceleration))
        {
            if w > 0.0 {
                *v += dt * a;
            }
        }
        // Lines 3-9: Gauss-Seidel over the springs in index order, stopping early only in the
        // tolerance mode; at a fixed point the sweeps left are not computed ([`FixedPoint`]:
        // a sweep reads nothing that changes but p).
        self.fixed_point.begin_step();
        for _ in 0..self.iterations {
            if !self.fixed_point.reached() {
                self.fixed_point.keep(p, &[]);
                for (j, s) in self.system.springs().iter().enumerate() {
                    let (w1, w2) = (self.w[s.a], self.w[s.b]);
                    let c = spring::constraint(&p[s.a], &p[s.b], s.rest_length);
                    let grad = spring::constraint_gradient(&p[s.a], &p[s.b]);
                    // Line 5, Eqs 13-14.
                    let s_j = self::s(c, self.inverse_w[j]);
                    let stiffness_factor = self.stiffness_factors[j];
                    let (delta_x1, delta_x2) = delta_x(&grad, w1, w2, s_j, stiffness_factor);
                    // Line 6 (erratum: on p).
                    p[s.a] += delta_x1;
                    p[s.b] += delta_x2;
                }
                self.fixed_point.compare(p, &[]);
            }
            let converged = if self.convergence.wants_value() {
                // PBD's constraints are XPBD's with zero compliance.
                let r = crate::solvers::xpbd::constraint_residual(&self.system, p, &[], &[]);
                self.convergence.converged_value(r)
            } else {
                self.convergence.converged(p.iter().copied())
            };
            if converged {
                break;
            }
        }
        self.convergence.end_step(0);
        // Lines 10-11.
        for ((x, v), p) in state.x.iter_mut().zip(state.v.iter_mut()).zip(p.iter()) {
            *v = (p - *x) / dt;
            *x = *p;
        }
        Ok(())
    }
    // endregion: step
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::model::scene::thesis_rope;

    #[test]
    fn rejects_bad_parameters() {
        let rope = thesis_rope(1e3).unwrap();
        let field = |e: Error| match e {
            Error::InvalidParameter { field, .. } => field,
            other => panic!("{other}"),
        };
        assert_eq!(field(Pbd::new(&rope, -0.1, 1, 1.0).unwrap_err()), "dt");
        assert_eq!(
            field(Pbd::new(&rope, 0.01, 0, 1.0).unwrap_err()),
            "iterations"
        );
        for bad in [1000.0, -0.5, f64::NAN] {
            assert_eq!(
                field(Pbd::new(&rope, 0.01, 1, bad).unwrap_err()),
                "stiffness_factor"
            );
        }
        let mut factors = vec![0.5; 9];
        factors[4] = 1.5;
        assert_eq!(
            field(Pbd::with_stiffness_factors(&rope, 0.01, 1, &factors).unwrap_err()),
            "stiffness_factors[4]"
        );
        assert_eq!(
            field(Pbd::with_stiffness_factors(&rope, 0.01, 1, &[1.0; 3]).unwrap_err()),
            "stiffness_factors.len()"
        );
    }

    /// One projection of one spring with factor 1 restores the rest length exactly, and a
    /// factor of 1/2 removes half the deformation when the masses are equal.
    #[test]
    fn projection_restores_the_rest_length() {
        let (x1, x2) = (Vec3::new(0.0, 0.0, 0.0), Vec3::new(3.0, 4.0, 0.0));
        let c = spring::constraint(&x1, &x2, 2.0);
        let grad = spring::constraint_gradient(&x1, &x2);
        let s_j = s(
            c,
            inverse_denominator(generalized_inverse_mass(1.0, 1.0), 0.0),
        );
        let (d1, d2) = delta_x(&grad, 1.0, 1.0, s_j, 1.0);
        assert!(spring::constraint(&(x1 + d1), &(x2 + d2), 2.0).abs() < 1e-15);
        let (d1, d2) = delta_x(&grad, 1.0, 1.0, s_j, 0.5);
        assert!((spring::constraint(&(x1 + d1), &(x2 + d2), 2.0) - 0.5 * c).abs() < 1e-15);
        assert_eq!(s(c, inverse_denominator(0.0, 0.0)), 0.0);
    }
}
