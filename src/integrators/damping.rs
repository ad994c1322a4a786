//! Rayleigh damping as a dissipation potential of the optimisation integrators (Brown, Overby,
//! Forootaninia, Narain 2018, "Accurate Dissipative Forces in Optimization Integrators", ACM
//! Trans. Graph. 37(6), art. 282), one of the dissipation functions of [`crate::integrators::dissipation`]
//! (whose stage term the damped Backward Euler step, its converged oracle
//! ([`crate::solvers::backward_euler`]) and the damped ADMM-PD ([`crate::solvers::damped_admm`]) minimise).
//!
//! The paper writes a dissipative force as minus the velocity gradient of a Rayleigh
//! dissipation function $`\mathcal D(x, v) \ge 0`$, convex in $`v`$:
//! $`f_d = -\partial\mathcal D/\partial v`$. Rayleigh damping, mass- and stiffness-proportional,
//! is the quadratic
//! ```math
//! \mathcal D(x, v) = \tfrac12\,v^\top(\alpha M + \beta K(x))\,v,\qquad f_d = -(\alpha M + \beta K(x))\,v,
//! ```
//! with $`K(x) = \nabla^2 E_{el}(x)`$ the Hessian of the elastic energy, the tangent stiffness,
//! at the current positions. Backward Euler with the position argument of $`\mathcal D`$ held at
//! the start of the step ($`x_n`$, first order like the integrator itself) is again a
//! minimisation: the incremental potential of the thesis's Eq (20) gains $`h\,\mathcal D`$,
//! ```math
//! \Phi(x) = \frac{1}{2h^2}(x - y)^\top M (x - y) + E(x) + h\,\mathcal D\!\left(x_n, \frac{x - x_n}{h}\right),
//! ```
//! whose stationarity $`M(v_{n+1} - v_n)/h = F(x_{n+1}) - (\alpha M + \beta K(x_n))\,v_{n+1}`$ is
//! Backward Euler with the damping force taken at the end-of-step velocity. For the springs,
//! $`K = \sum_i D_i^\top H_i D_i`$ with $`H_i`$ the 3×3 Hessian of spring $`i`$'s energy in its
//! vector $`d_i = x_{a_i} - x_{b_i}`$, so
//! ```math
//! h\,\mathcal D = \frac{\alpha}{2h}\,|x - x_n|_M^2 + \frac{\beta}{2h}\sum_i (d_i - d_{n,i})^\top H_i(x_n)\,(d_i - d_{n,i}).
//! ```
//!
//! Choices, stated because the paper's text was not at hand when this was written (its
//! equation numbers are therefore not quoted; the tags below name the paper and the section's
//! subject):
//! - The position argument of $`\mathcal D`$ (the $`K`$ of the stiffness term) is held at
//!   $`x_n`$ for the whole step, so the damping term is quadratic in $`x`$ and its gradient is
//!   exactly a force; the velocity argument is the end-of-step one.
//! - $`H_i`$ is projected to the positive semidefinite cone (the transverse factor
//!   $`1 - l_0/l`$ clamped at 0, [`crate::model::spring::force_jacobian_definite`]) so that
//!   $`\mathcal D \ge 0`$: a compressed spring's indefinite Hessian would otherwise feed energy
//!   in. On a stretched or unstressed rope it is the exact Hessian.
//! - $`K`$ is the tangent stiffness at the current positions, which turns with the rope: the
//!   stiffness-proportional force of a rigid motion of an unstressed rope is then zero. A
//!   stiffness frozen at the rest configuration would damp rigid rotation.
//! - The mass-proportional term damps every motion, rigid motion included ($`-\alpha M v`$, a
//!   drag against the still frame); [`crate::integrators::dissipation`] has this crate's momentum-conserving
//!   variant, which damps relative motion only.
//!
//! The modal damping ratio of this model is the classical $`\zeta = \alpha/(2\omega) +
//! \beta\omega/2`$ for a mode $`K\phi = \omega^2 M\phi`$ (tested in `tests/damping.rs`).

use crate::error::{Error, Result};
use crate::model::spring;
use crate::model::system::{MassSpringSystem, Vec3};
use nalgebra::Matrix3;

/// Rayleigh damping $`D = \alpha M + \beta K`$.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct RayleighDamping {
    /// Mass-proportional coefficient $`\alpha`$, 1/s.
    pub alpha: f64,
    /// Stiffness-proportional coefficient $`\beta`$, s.
    pub beta: f64,
}

impl Default for RayleighDamping {
    /// No damping: the thesis's model. The paper gives no values for this scene; a ratio
    /// $`\zeta`$ at a frequency $`\omega`$ is reached with $`\alpha = 2\zeta\omega`$ or
    /// $`\beta = 2\zeta/\omega`$.
    fn default() -> Self {
        Self::NONE
    }
}

impl RayleighDamping {
    /// $`\alpha = \beta = 0`$.
    pub const NONE: Self = Self {
        alpha: 0.0,
        beta: 0.0,
    };

    /// Both coefficients finite and >= 0.
    pub fn validate(&self) -> Result<()> {
        for (field, value, unit) in [("alpha", self.alpha, "1/s"), ("beta", self.beta, "s")] {
            if !(value.is_finite() && value >= 0.0) {
                return Err(Error::invalid(
                    field,
                    value,
                    &format!("a finite number >= 0, in {unit}"),
                ));
            }
        }
        Ok(())
    }

    /// True when both coefficients are 0.
    pub fn is_none(&self) -> bool {
        self.alpha == 0.0 && self.beta == 0.0
    }

    /// The damping ratio of a mode of angular frequency `omega` (rad/s):
    /// $`\zeta = \alpha/(2\omega) + \beta\omega/2`$.
    pub fn modal_ratio(&self, omega: f64) -> f64 {
        self.alpha / (2.0 * omega) + self.beta * omega / 2.0
    }
}

/// [Brown 2018, Rayleigh damping] (unverified: no body text or reference code found) $`H_i = \nabla^2_{d} E_i`$, spring `i`'s energy Hessian in its
/// vector $`d = x_a - x_b`$, projected to the positive semidefinite cone: $`-\partial F_a/\partial
/// x_a`$ of Eq (4) with the transverse factor clamped at 0.
pub fn spring_hessian(system: &MassSpringSystem, x: &[Vec3], i: usize) -> Matrix3<f64> {
    let s = &system.springs()[i];
    -spring::force_jacobian_definite(&x[s.a], &x[s.b], s.rest_length, s.stiffness)
}

/// [Brown 2018, Rayleigh damping] (unverified: no body text or reference code found) $`f_d = -(\alpha M + \beta K(x))\,v`$, the damping force on
/// every node at positions `x` and velocities `v`, with $`K(x)`$ the tangent stiffness at `x`
/// ([`spring_hessian`]). Fixed nodes get 0.
pub fn rayleigh_force(
    system: &MassSpringSystem,
    damping: RayleighDamping,
    x: &[Vec3],
    v: &[Vec3],
) -> Vec<Vec3> {
    let mut f: Vec<Vec3> = system
        .nodes()
        .iter()
        .zip(v)
        .map(|(node, v)| -damping.alpha * node.mass * v)
        .collect();
    for (i, s) in system.springs().iter().enumerate() {
        let f_a = -damping.beta * (spring_hessian(system, x, i) * (v[s.a] - v[s.b]));
        f[s.a] += f_a;
        f[s.b] -= f_a;
    }
    for (f, node) in f.iter_mut().zip(system.nodes()) {
        if node.fixed {
            *f = Vec3::zeros();
        }
    }
    f
}
