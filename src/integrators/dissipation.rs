//! Dissipation functions $`\mathcal D(x, v)`$ and their term in a stage's objective (Brown,
//! Overby, Forootaninia & Narain 2018, "Accurate Dissipative Forces in Optimization
//! Integrators": the subject of its abstract; its body is not available here, `docs/papers.md`).
//!
//! A dissipative force is minus the velocity gradient of a dissipation function,
//! $`f_d = -\partial\mathcal D/\partial v`$, with $`\mathcal D \ge 0`$ convex in $`v`$. A
//! stage of an optimization integrator ([`crate::integrators::optimization_integrator`]) with velocity
//! $`u(x) = (x - x_a)/\tau`$ minimises (scaled by $`1/\tau^2`$, the form of thesis Eq 20)
//! ```math
//! \Phi(x) = \frac{1}{2\tau^2}\lVert x - \hat y\rVert_M^2 + U(x) + \Psi(x),\qquad
//! \Psi(x) = \tau\,\mathcal D\!\left(x_D, \frac{x - x_a}{\tau}\right),
//! ```
//! whose stationarity $`M(u - u_0) = \tau\,(F(x) + f_d(x_D, u))`$ is the stage's implicit
//! equation with the damping force at the stage's end velocity: $`\nabla_x\Psi =
//! \partial\mathcal D/\partial v`$. The term is in the minimised objective, not a force added
//! after the solve. [`Dissipation`] is the interface (its value, its force, its stage term
//! [`StageDissipation`] with gradient and Hessian), a sum of three functions:
//! - **Rayleigh damping** ([`crate::integrators::damping`]), $`\mathcal D = \frac12 v^\top(\alpha M + \beta
//!   K(x))v`$, the position argument frozen at the stage's start $`x_D`$, so that $`\Psi`$ is
//!   quadratic: $`\frac{\alpha}{2\tau}\lVert x - x_a\rVert_M^2 + \frac{\beta}{2\tau}\sum_i(d_i -
//!   d_{a,i})^\top H_i(x_D)(d_i - d_{a,i})`$, $`d_i`$ spring $`i`$'s vector.
//! - **Power-law drag**, $`\mathcal D = \sum_i \frac{c}{p+1}|v_i|^{p+1}`$ with $`0 < p < 1`$
//!   ([`PowerLawDrag`]): $`f_d = -c|v|^{p-1}v`$, a force that stops a free mass in finite time
//!   ($`t^* = \frac{m\,v_0^{1-p}}{(1-p)c}`$ after $`d^* = \frac{m\,v_0^{2-p}}{(2-p)c}`$). It
//!   is $`C^1`$ but its Hessian $`c|v|^{p-1}(I + (p-1)\hat v\hat v^\top)`$ is unbounded at
//!   $`v = 0`$, and Newton with it does not converge there: on $`|v|^{p-1}v`$ its step maps
//!   $`v`$ to $`(1 - 1/p)\,v`$, for $`p = 1/2`$ to $`-v`$, a two-cycle (measured: the converged
//!   step stalled at updates of 1e-10 m). Newton here takes instead the curvature of the
//!   drag's quadratic majorizer at the iterate, $`c\,s^{p-1} I`$ with
//!   $`s = \sqrt{|v|^2 + \varepsilon^2}`$ ($`\varepsilon`$ = [`DRAG_SMOOTHING`] guards
//!   $`v = 0`$): $`|v|^{p+1}`$ is a concave function of $`|v|^2`$, so the quadratic of that
//!   curvature through the iterate lies above it, and a step on the drag alone is the
//!   majorize-minimize step $`v \leftarrow m u_0/(m + \tau c|v|^{p-1})`$, which decreases the
//!   objective and never crosses $`v = 0`$. With the exact gradient and a backtracking line
//!   search on the exact objective (convex in the drag), the minimiser is the exact one.
//! - **Momentum-conserving Rayleigh damping**, *this crate's own design* (the paper's abstract
//!   announces a momentum-conserving modification of any dissipation function, whose
//!   formulation we cannot read; [`RayleighForm::MomentumConserving`]): Rayleigh damping
//!   restricted to relative motion,
//!   $`\mathcal D = \frac12\sum_s (\alpha\,\mu_s + \beta\,k_s)\,\dot l_s^2`$ with
//!   $`\dot l_s = \hat d_s\cdot(v_{a_s} - v_{b_s})`$ and $`\mu_s`$ the reduced mass of spring $`s`$'s ends (a fixed end counts as infinitely
//!   heavy) and $`\dot l_s`$ its rate of stretching. For an unstressed spring the $`\beta`$ part
//!   is Rayleigh's $`\frac\beta2 v^\top Kv`$ exactly; the $`\alpha`$ part damps a two-mass
//!   spring's stretching at the rate $`\alpha`$ of mass-proportional damping, and no rigid
//!   motion at all. Its stage term differences the lengths,
//!   $`\Psi = \sum_s \frac{\alpha\mu_s + \beta k_s}{2\tau}(l_s(x) - l_s(x_a))^2`$: a spring of
//!   stiffness $`(\alpha\mu_s + \beta k_s)/\tau`$ and rest length $`l_s(x_a)`$, whose forces are
//!   central, along $`x_{a_s} - x_{b_s}`$ at the iterate. Central forces at the midpoint keep
//!   the implicit midpoint rule's angular momentum exactly (tested: to round-off), where
//!   mass-proportional damping, $`-\alpha M u`$, takes it away.

use crate::error::{require_within, Error, Result};
use crate::integrators::damping::{spring_hessian, RayleighDamping};
use crate::model::spring;
use crate::model::system::{MassSpringSystem, Vec3};
use nalgebra::Matrix3;

/// The velocity scale $`\varepsilon`$, m/s, that keeps the drag's curvature in Newton finite at
/// rest (module doc): $`|v|^{p-1}`$ becomes $`(|v|^2 + \varepsilon^2)^{(p-1)/2}`$.
pub const DRAG_SMOOTHING: f64 = 1e-12;

/// The largest power-law drag coefficient, in N·(s/m)^p: the scene files' bound on spring
/// damping and drag (`LIMITS.damping`, 1e9 N·s/m), past which a step's forces overflow.
pub const MAX_DRAG: f64 = 1e9;

/// The unit of the power-law drag coefficient.
pub const DRAG_UNIT: &str = "N·(s/m)^p";

/// Power-law drag $`\mathcal D = \sum_i \frac{c}{p+1}|v_i|^{p+1}`$ on every free node.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PowerLawDrag {
    /// $`c \ge 0`$, in N·(s/m)^p; 0: no drag.
    pub coefficient: f64,
    /// $`p \in (0, 1)`$.
    pub exponent: f64,
}

impl PowerLawDrag {
    /// No drag (with $`p = 1/2`$ for when a coefficient is set).
    pub const NONE: Self = Self {
        coefficient: 0.0,
        exponent: 0.5,
    };

    /// $`0 \le c \le`$ [`MAX_DRAG`], $`0 < p < 1`$.
    pub fn validate(&self) -> Result<()> {
        require_within("drag", self.coefficient, 0.0, MAX_DRAG, DRAG_UNIT)?;
        if !(self.exponent > 0.0 && self.exponent < 1.0) {
            return Err(Error::invalid(
                "drag_exponent",
                self.exponent,
                "a number > 0 and < 1",
            ));
        }
        Ok(())
    }

    /// The closed-form motion of a free mass `m` (kg) from speed `v0` (m/s): the time, s, and
    /// the distance, m, to its stop (module doc).
    pub fn stop(&self, m: f64, v0: f64) -> (f64, f64) {
        let (c, p) = (self.coefficient, self.exponent);
        (
            m * v0.powf(1.0 - p) / ((1.0 - p) * c),
            m * v0.powf(2.0 - p) / ((2.0 - p) * c),
        )
    }
}

/// Which Rayleigh damping: the classical, or the momentum-conserving variant (module doc).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default)]
pub enum RayleighForm {
    /// $`\frac12 v^\top(\alpha M + \beta K)v`$ ([`crate::integrators::damping`]).
    #[default]
    Classical,
    /// This crate's variant on the springs' rates of stretching.
    MomentumConserving,
}

impl RayleighForm {
    /// Both forms.
    pub const ALL: [RayleighForm; 2] = [RayleighForm::Classical, RayleighForm::MomentumConserving];

    /// The name on the command line.
    pub fn key(self) -> &'static str {
        match self {
            RayleighForm::Classical => "classical",
            RayleighForm::MomentumConserving => "momentum-conserving",
        }
    }
}

impl std::str::FromStr for RayleighForm {
    type Err = Error;

    fn from_str(s: &str) -> Result<Self> {
        RayleighForm::ALL
            .into_iter()
            .find(|f| f.key() == s)
            .ok_or_else(|| Error::invalid("rayleigh_form", s, "classical or momentum-conserving"))
    }
}

/// A dissipation function: Rayleigh damping of either form plus power-law drag (module doc).
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct Dissipation {
    pub rayleigh: RayleighDamping,
    pub form: RayleighForm,
    pub drag: PowerLawDrag,
}

impl Default for PowerLawDrag {
    fn default() -> Self {
        Self::NONE
    }
}

impl Dissipation {
    /// No dissipation.
    pub const NONE: Self = Self {
        rayleigh: RayleighDamping::NONE,
        form: RayleighForm::Classical,
        drag: PowerLawDrag::NONE,
    };

    /// Classical Rayleigh damping only.
    pub fn rayleigh(damping: RayleighDamping) -> Self {
        Self {
            rayleigh: damping,
            ..Self::NONE
        }
    }

    /// Every coefficient in its range.
    pub fn validate(&self) -> Result<()> {
        self.rayleigh.validate()?;
        self.drag.validate()
    }

    /// True when it dissipates nothing.
    pub fn is_none(&self) -> bool {
        self.rayleigh.is_none() && self.drag.coefficient == 0.0
    }

    /// True when its stage term is quadratic or smooth enough for Newton without a line search
    /// (no drag).
    pub fn is_smooth(&self) -> bool {
        self.drag.coefficient == 0.0
    }

    /// [Brown 2018, dissipation functions] (unverified: no body text or reference code found) $`\mathcal D(x, v)`$, W.
    pub fn value(&self, system: &MassSpringSystem, x: &[Vec3], v: &[Vec3]) -> f64 {
        let RayleighDamping { alpha, beta } = self.rayleigh;
        let free = system.nodes().iter().zip(v).filter(|(n, _)| !n.fixed);
        let (c, p) = (self.drag.coefficient, self.drag.exponent);
        let drag: f64 = free
            .clone()
            .map(|(_, v)| c * v.norm().powf(p + 1.0) / (p + 1.0))
            .sum();
        let rayleigh: f64 = match self.form {
            RayleighForm::Classical => {
                let mass: f64 = free.map(|(n, v)| n.mass * v.norm_squared()).sum();
                let stiffness: f64 = (0..system.springs().len())
                    .map(|i| {
                        let s = &system.springs()[i];
                        let dv = v[s.a] - v[s.b];
                        dv.dot(&(spring_hessian(system, x, i) * dv))
                    })
                    .sum();
                0.5 * (alpha * mass + beta * stiffness)
            }
            RayleighForm::MomentumConserving => system
                .springs()
                .iter()
                .enumerate()
                .map(|(i, s)| {
                    let rate =
                        spring::constraint_gradient(&x[s.a], &x[s.b]).dot(&(v[s.a] - v[s.b]));
                    0.5 * self.spring_coefficient(system, i) * rate * rate
                })
                .sum(),
        };
        rayleigh + drag
    }

    /// [Brown 2018, dissipation functions] (unverified: no body text or reference code found) Adds
    /// $`f_d = -\partial\mathcal D/\partial v`$ at `(x, v)` to `f`; fixed nodes get nothing.
    pub fn add_force(&self, system: &MassSpringSystem, x: &[Vec3], v: &[Vec3], f: &mut [Vec3]) {
        let RayleighDamping { alpha, beta } = self.rayleigh;
        let nodes = system.nodes();
        let mut add = |i: usize, force: Vec3| {
            if !nodes[i].fixed {
                f[i] += force;
            }
        };
        let (c, p) = (self.drag.coefficient, self.drag.exponent);
        for (i, node) in nodes.iter().enumerate() {
            if c > 0.0 {
                add(i, -drag_gradient(c, p, v[i]));
            }
            if self.form == RayleighForm::Classical {
                add(i, -alpha * node.mass * v[i]);
            }
        }
        for (i, s) in system.springs().iter().enumerate() {
            let dv = v[s.a] - v[s.b];
            let f_a = match self.form {
                RayleighForm::Classical => -beta * (spring_hessian(system, x, i) * dv),
                RayleighForm::MomentumConserving => {
                    let n = spring::constraint_gradient(&x[s.a], &x[s.b]);
                    -self.spring_coefficient(system, i) * n.dot(&dv) * n
                }
            };
            add(s.a, f_a);
            add(s.b, -f_a);
        }
    }

    /// The momentum-conserving form's $`\alpha\mu_s + \beta k_s`$ of spring `i`.
    pub fn spring_coefficient(&self, system: &MassSpringSystem, i: usize) -> f64 {
        let s = &system.springs()[i];
        let RayleighDamping { alpha, beta } = self.rayleigh;
        alpha * reduced_mass(system, s.a, s.b) + beta * s.stiffness
    }
}

/// The reduced mass of nodes `a` and `b`, a fixed node counting as infinitely heavy (0 when
/// both are fixed).
pub fn reduced_mass(system: &MassSpringSystem, a: usize, b: usize) -> f64 {
    let (na, nb) = (&system.nodes()[a], &system.nodes()[b]);
    match (na.fixed, nb.fixed) {
        (false, false) => na.mass * nb.mass / (na.mass + nb.mass),
        (true, false) => nb.mass,
        (false, true) => na.mass,
        (true, true) => 0.0,
    }
}

/// $`\partial\mathcal D_i/\partial v = c|v|^{p-1}v`$ of the drag on one node (0 at rest).
fn drag_gradient(c: f64, p: f64, v: Vec3) -> Vec3 {
    let speed = v.norm();
    if speed > 0.0 {
        c * speed.powf(p - 1.0) * v
    } else {
        Vec3::zeros()
    }
}

/// The curvature Newton takes for the drag on one node: its quadratic majorizer's,
/// $`c\,s^{p-1} I`$, $`s = \sqrt{|v|^2 + \varepsilon^2}`$ (module doc).
fn drag_curvature(c: f64, p: f64, v: Vec3) -> Matrix3<f64> {
    let s2 = v.norm_squared() + DRAG_SMOOTHING * DRAG_SMOOTHING;
    c * s2.powf(0.5 * (p - 1.0)) * Matrix3::identity()
}

/// The stage term $`\Psi(x) = \tau\,\mathcal D(x_D, (x - x_a)/\tau)`$ of one stage, with what
/// is frozen at the stage's start ($`x_a`$, the springs' $`d_{a,i}`$ and lengths, and
/// $`H_i(x_D)`$).
#[derive(Debug, Clone)]
pub struct StageDissipation {
    dissipation: Dissipation,
    /// $`\tau`$, s.
    dt: f64,
    /// $`x_a`$.
    x_n: Vec<Vec3>,
    /// $`d_{a,i}`$, one per spring.
    d_n: Vec<Vec3>,
    /// $`l_s(x_a)`$, one per spring (momentum-conserving form).
    lengths: Vec<f64>,
    /// $`H_i(x_D)`$, one per spring (zero when $`\beta = 0`$ or in the momentum-conserving
    /// form: not needed).
    hessians: Vec<Matrix3<f64>>,
}

impl StageDissipation {
    /// Buffers for `system` (call [`Self::start`] at each stage).
    pub fn new(system: &MassSpringSystem, dissipation: Dissipation) -> Self {
        let s = system.springs().len();
        Self {
            dissipation,
            dt: 0.0,
            x_n: vec![Vec3::zeros(); system.len()],
            d_n: vec![Vec3::zeros(); s],
            lengths: vec![0.0; s],
            hessians: vec![Matrix3::zeros(); s],
        }
    }

    /// The dissipation function.
    pub fn dissipation(&self) -> &Dissipation {
        &self.dissipation
    }

    /// The Rayleigh coefficients.
    pub fn damping(&self) -> RayleighDamping {
        self.dissipation.rayleigh
    }

    /// Freezes the anchor $`x_a`$ (with its springs' vectors and lengths) and
    /// $`H_i(x_D)`$ at `frozen`, for a stage of step `tau`.
    pub fn start(&mut self, system: &MassSpringSystem, x_a: &[Vec3], frozen: &[Vec3], tau: f64) {
        self.dt = tau;
        self.x_n.copy_from_slice(x_a);
        let RayleighDamping { beta, .. } = self.dissipation.rayleigh;
        match self.dissipation.form {
            RayleighForm::Classical if beta != 0.0 => {
                for (i, (d, h)) in self.d_n.iter_mut().zip(&mut self.hessians).enumerate() {
                    let s = &system.springs()[i];
                    *d = x_a[s.a] - x_a[s.b];
                    *h = spring_hessian(system, frozen, i);
                }
            }
            RayleighForm::Classical => {}
            RayleighForm::MomentumConserving => {
                for (l, s) in self.lengths.iter_mut().zip(system.springs()) {
                    *l = (x_a[s.a] - x_a[s.b]).norm();
                }
            }
        }
    }

    /// $`d_{a,i}`$ of spring `i`.
    pub fn spring_vector(&self, i: usize) -> Vec3 {
        self.d_n[i]
    }

    /// $`l_i(x_a)`$ of spring `i` (the momentum-conserving form's rest length).
    pub fn anchor_length(&self, i: usize) -> f64 {
        self.lengths[i]
    }

    /// $`H_i(x_D)`$ of spring `i`.
    pub fn hessian(&self, i: usize) -> &Matrix3<f64> {
        &self.hessians[i]
    }

    /// The stiffness $`(\alpha\mu_i + \beta k_i)/\tau`$ of spring `i`'s damping spring
    /// (momentum-conserving form; module doc).
    pub fn damping_stiffness(&self, system: &MassSpringSystem, i: usize) -> f64 {
        self.dissipation.spring_coefficient(system, i) / self.dt
    }

    /// The stage's velocity $`(x - x_a)/\tau`$ of node `i`.
    fn velocity(&self, x: &[Vec3], i: usize) -> Vec3 {
        (x[i] - self.x_n[i]) / self.dt
    }

    /// [Brown 2018, dissipation potential] (unverified: no body text or reference code found) $`\Psi(x)`$ at
    /// positions `x` (module doc), J.
    pub fn potential(&self, system: &MassSpringSystem, x: &[Vec3]) -> f64 {
        let RayleighDamping { alpha, beta } = self.dissipation.rayleigh;
        let rayleigh = match self.dissipation.form {
            RayleighForm::Classical => {
                let mass: f64 = system
                    .nodes()
                    .iter()
                    .zip(x.iter().zip(&self.x_n))
                    .map(|(node, (x, x_n))| node.mass * (x - x_n).norm_squared())
                    .sum();
                let stiffness: f64 = if beta == 0.0 {
                    0.0
                } else {
                    system
                        .springs()
                        .iter()
                        .zip(self.d_n.iter().zip(&self.hessians))
                        .map(|(s, (d_n, h))| {
                            let e = x[s.a] - x[s.b] - d_n;
                            e.dot(&(h * e))
                        })
                        .sum()
                };
                (alpha * mass + beta * stiffness) / (2.0 * self.dt)
            }
            RayleighForm::MomentumConserving => system
                .springs()
                .iter()
                .enumerate()
                .map(|(i, s)| {
                    spring::energy(
                        &x[s.a],
                        &x[s.b],
                        self.lengths[i],
                        self.damping_stiffness(system, i),
                    )
                })
                .sum(),
        };
        let PowerLawDrag {
            coefficient: c,
            exponent: p,
        } = self.dissipation.drag;
        if c == 0.0 {
            return rayleigh;
        }
        let drag: f64 = (0..x.len())
            .filter(|&i| !system.nodes()[i].fixed)
            .map(|i| c * self.velocity(x, i).norm().powf(p + 1.0) / (p + 1.0))
            .sum();
        rayleigh + self.dt * drag
    }

    /// [Brown 2018, dissipation potential] (unverified: no body text or reference code found) Adds the damping force
    /// $`-\nabla_x\Psi = f_d(x_D, (x - x_a)/\tau)`$ (the momentum-conserving form's at the
    /// lengths' difference) to `f` (free nodes only).
    pub fn add_force(&self, system: &MassSpringSystem, x: &[Vec3], f: &mut [Vec3]) {
        let RayleighDamping { alpha, beta } = self.dissipation.rayleigh;
        let h = self.dt;
        let nodes = system.nodes();
        let PowerLawDrag {
            coefficient: c,
            exponent: p,
        } = self.dissipation.drag;
        let classical = self.dissipation.form == RayleighForm::Classical;
        for (i, node) in nodes.iter().enumerate() {
            if node.fixed {
                continue;
            }
            if classical {
                f[i] -= alpha * node.mass * (x[i] - self.x_n[i]) / h;
            }
            if c > 0.0 {
                f[i] -= drag_gradient(c, p, self.velocity(x, i));
            }
        }
        if classical && beta == 0.0 {
            return;
        }
        for (i, s) in system.springs().iter().enumerate() {
            let f_a = if classical {
                -beta * (self.hessians[i] * (x[s.a] - x[s.b] - self.d_n[i])) / h
            } else {
                spring::force(
                    &x[s.a],
                    &x[s.b],
                    self.lengths[i],
                    self.damping_stiffness(system, i),
                )
            };
            if !nodes[s.a].fixed {
                f[s.a] += f_a;
            }
            if !nodes[s.b].fixed {
                f[s.b] -= f_a;
            }
        }
    }

    /// The factor of $`M`$ in $`\tau^2\nabla^2(\frac{1}{2\tau^2}|x|_M^2 + \Psi)`$: $`1 + \alpha\tau`$
    /// (classical form), 1 otherwise.
    pub fn mass_factor(&self) -> f64 {
        match self.dissipation.form {
            RayleighForm::Classical => 1.0 + self.dissipation.rayleigh.alpha * self.dt,
            RayleighForm::MomentumConserving => 1.0,
        }
    }

    /// Whether [`Self::spring_block`] can be other than zero: not in the classical form without
    /// $`\beta`$, whose blocks are $`(\beta\tau) H_i`$ with $`H_i`$ never set, +0 in every entry
    /// (so that subtracting them leaves every value's bits as they were, -0 included).
    pub fn has_spring_blocks(&self) -> bool {
        !(self.dissipation.form == RayleighForm::Classical && self.dissipation.rayleigh.beta == 0.0)
    }

    /// Spring `i`'s block of $`\tau^2\nabla^2\Psi`$ at `x`, entering as $`D_i^\top B_i D_i`$:
    /// $`\beta\tau H_i(x_D)`$ (classical), or the damping spring's Hessian times $`\tau^2`$
    /// (momentum-conserving; projected to the positive semidefinite cone when `definite`).
    pub fn spring_block(
        &self,
        system: &MassSpringSystem,
        x: &[Vec3],
        i: usize,
        definite: bool,
    ) -> Matrix3<f64> {
        match self.dissipation.form {
            RayleighForm::Classical => {
                (self.dissipation.rayleigh.beta * self.dt) * self.hessians[i]
            }
            RayleighForm::MomentumConserving => {
                let s = &system.springs()[i];
                let k = self.dt * self.dissipation.spring_coefficient(system, i);
                let jacobian = if definite {
                    spring::force_jacobian_definite
                } else {
                    spring::force_jacobian
                };
                -jacobian(&x[s.a], &x[s.b], self.lengths[i], k)
            }
        }
    }

    /// What the non-quadratic parts of $`\Psi`$ (the momentum-conserving form, the drag) add to
    /// the right-hand side of Newton's velocity equation at the iterate `x` $`= x_a + \tau v`$:
    /// $`\tau f_\Psi(x) + B v`$ with $`B`$ their blocks of $`\tau^2\nabla^2\Psi`$, as assembled
    /// (`rhs` node-major, three entries a node). The classical Rayleigh term is quadratic, and
    /// its two contributions cancel exactly: it adds nothing.
    pub fn add_newton_rhs(
        &self,
        system: &MassSpringSystem,
        x: &[Vec3],
        v: &[Vec3],
        rhs: &mut [f64],
    ) {
        let nodes = system.nodes();
        let tau = self.dt;
        let mut add = |i: usize, b: Vec3| {
            if !nodes[i].fixed {
                for c in 0..3 {
                    rhs[3 * i + c] += b[c];
                }
            }
        };
        let PowerLawDrag {
            coefficient: c,
            exponent: p,
        } = self.dissipation.drag;
        if c > 0.0 {
            for (i, v) in v.iter().enumerate() {
                let force = -drag_gradient(c, p, self.velocity(x, i));
                add(i, tau * force + self.node_block(system, x, i) * v);
            }
        }
        if self.dissipation.form == RayleighForm::MomentumConserving {
            for (i, s) in system.springs().iter().enumerate() {
                let force = spring::force(
                    &x[s.a],
                    &x[s.b],
                    self.lengths[i],
                    self.damping_stiffness(system, i),
                );
                let b = tau * force + self.spring_block(system, x, i, false) * (v[s.a] - v[s.b]);
                add(s.a, b);
                add(s.b, -b);
            }
        }
    }

    /// Node `i`'s block of $`\tau^2\nabla^2\Psi`$ besides the mass term at `x`: the drag's
    /// majorizing curvature times $`\tau`$ (module doc; zero without drag or on a fixed node).
    pub fn node_block(&self, system: &MassSpringSystem, x: &[Vec3], i: usize) -> Matrix3<f64> {
        let PowerLawDrag {
            coefficient: c,
            exponent: p,
        } = self.dissipation.drag;
        if c == 0.0 || system.nodes()[i].fixed {
            return Matrix3::zeros();
        }
        self.dt * drag_curvature(c, p, self.velocity(x, i))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::model::scene::thesis_rope;

    /// Without spring blocks (the classical form at β = 0, mass-proportional damping and drag
    /// allowed) every block is +0 in every entry, so that Backward Euler's assembly may skip
    /// subtracting them; with β > 0, or the momentum-conserving form, it has them (and the
    /// check: its blocks are not all +0).
    #[test]
    fn only_the_classical_form_without_beta_has_no_spring_blocks() {
        let system = thesis_rope(1e3).unwrap();
        let x: Vec<Vec3> = system
            .nodes()
            .iter()
            .enumerate()
            .map(|(i, n)| n.position + Vec3::new(0.01 * i as f64, -0.02, 0.0))
            .collect();
        let forms = [
            (Dissipation::NONE, false),
            (
                Dissipation::rayleigh(RayleighDamping {
                    alpha: 0.3,
                    beta: 0.0,
                }),
                false,
            ),
            (
                Dissipation::rayleigh(RayleighDamping {
                    alpha: 0.0,
                    beta: 0.01,
                }),
                true,
            ),
            (
                Dissipation {
                    form: RayleighForm::MomentumConserving,
                    ..Dissipation::rayleigh(RayleighDamping {
                        alpha: 0.0,
                        beta: 0.01,
                    })
                },
                true,
            ),
        ];
        for (dissipation, has) in forms {
            let mut stage = StageDissipation::new(&system, dissipation);
            stage.start(&system, &x, &x, 1e-3);
            assert_eq!(stage.has_spring_blocks(), has, "{dissipation:?}");
            let all_positive_zero = (0..system.springs().len()).all(|i| {
                stage
                    .spring_block(&system, &x, i, false)
                    .iter()
                    .all(|v| v.to_bits() == 0)
            });
            assert_eq!(all_positive_zero, !has, "{dissipation:?}");
        }
    }
}
