//! ADMM-PD with Rayleigh damping (Brown, Overby, Forootaninia, Narain 2018, "Accurate
//! Dissipative Forces in Optimization Integrators"): the thesis's Algorithm 4 ([`crate::solvers::admm`])
//! on the damped objective of [`crate::integrators::damping`],
//! ```math
//! \Phi(x) = \frac{1}{2h^2}|x - \tilde x|_M^2 + \frac{\alpha}{2h}|x - x_n|_M^2
//!   + \sum_i U_i(D_i x) + \sum_i \frac{\beta}{2h}(D_i x - d_{n,i})^\top H_i (D_i x - d_{n,i}).
//! ```
//! Both damping terms keep ADMM's matrix constant:
//! - the mass-proportional term is quadratic in $`x`$ with the matrix $`M`$: it joins the
//!   inertial term, $`\frac{1 + \alpha h}{2h^2}|x - \hat x|_M^2`$ with
//!   $`\hat x = (\tilde x + \alpha h\,x_n)/(1 + \alpha h)`$
//!   ([`AdmmIterate::damp_prediction`]). Multiplying $`\Phi`$ by
//!   $`\tau^2 = h^2/(1 + \alpha h)`$ gives the undamped objective scaled by $`h^2`$ with
//!   $`h \to \tau`$ and $`\tilde x \to \hat x`$, so the global matrix is
//!   $`M + \tau^2 D^\top(W^\top W + W'^\top W')D`$, factored once per scene and step;
//! - the stiffness-proportional term is a sum of per-spring functions of $`D_i x`$, like the
//!   springs' energy $`U_i`$: it is a second block of ADMM's $`g`$, with its own auxiliary
//!   variables $`z'_i \approx D_i x`$, scaled duals $`\bar u'_i`$ and weights
//!   $`\omega'^2_i = \beta k_i/h`$ (the largest eigenvalue of $`\frac{\beta}{h}H_i`$, as
//!   $`\omega_i^2 = k_i`$ is the spring's). Its local step is linear:
//! ```math
//! z'_i = \left(\tfrac{\beta}{h}H_i + \omega'^2_i I\right)^{-1}\left(\tfrac{\beta}{h}H_i\,d_{n,i} + \omega'^2_i\,(D_i x + \bar u'_i)\right),\qquad \bar u'_i \leftarrow \bar u'_i + D_i x - z'_i,
//! ```
//! and the global step's right-hand side gains $`\tau^2 D^\top W'^\top W'(z' - \bar u')`$.
//!
//! Measured (`tests/damping.rs`, `iterations_to_one_micrometre`): at dt = 1e-2 s, k = 1e6 N/m,
//! from `step10`, ADMM-PD needs 1828 iterations for a gap below 1e-6 m to its converged step,
//! and this solver with $`\alpha`$ = 0.5 1/s, $`\beta`$ = 2e-3 s 2154 to the damped one (1828
//! with $`\alpha = \beta = 0`$). The weights $`\omega'^2_i`$ matter: 0.1 times the above gives
//! 1832 there, 10 times 5380; 0.01 times gives 1803 there but slows the k = 1e3, dt = 1e-3
//! step below 1e-9 m in 300 iterations.
//!
//! The split of the stiffness-proportional term into its own block is this crate's choice (the
//! paper's text was not at hand; see [`crate::integrators::damping`]); it keeps the springs' local step
//! (Eqs 55-56) exactly the thesis's. The fixed point is the minimiser of $`\Phi`$, the damped
//! converged step [`crate::solvers::converged_stage::damped_converged_step`], which the tests check. With
//! $`\alpha = \beta = 0`$ the step is [`crate::solvers::admm::AdmmPd`]'s, bit for bit. No state is carried
//! across steps: $`H_i`$, $`d_{n,i}`$ and both duals restart at each step.
//!
//! The other dissipation functions of [`crate::integrators::dissipation`] are more blocks of $`g`$, each
//! with its own auxiliary variables and scaled duals (this crate's choices):
//! - the momentum-conserving Rayleigh damping's springs (stiffness
//!   $`(\alpha\mu_s + \beta k_s)/h`$, rest length $`l_s(x_n)`$) are a second set of springs
//!   on the same $`D_i`$, weights $`\omega''^2_s`$ their stiffness, local step Eqs 55-56 with
//!   that rest length ([`z_minimisation`]);
//! - the power-law drag is a block on the nodes themselves, $`z^d_i \approx x_i`$, weights
//!   $`\omega_d^2 = c/h`$ (the drag's curvature at 1 m/s, in the scaled objective), whose local
//!   step is the drag's proximal map: with $`r = x_i + \bar u^d_i - x_{n,i}`$,
//!   $`z^d_i = x_{n,i} + s\,\hat r`$ where $`s \in [0, |r|]`$ solves
//!   $`\omega_d^2(s - |r|) + c\,h^{-p}s^p = 0`$
//!   (safeguarded Newton, [`drag_proximal_length`]); the global matrix gains
//!   $`\tau^2\omega_d^2`$ on the free nodes' diagonal ([`GlobalSolve::with_node_weights`]).
//!
//! Under an optimization integrator ([`crate::integrators::optimization_integrator`]) each stage is the same
//! iteration with $`h`$ the stage's $`\tau`$ and $`(x_n, v_n)`$ its pseudo-state ($`H_i`$ frozen at
//! the stage's $`x_D`$); the matrix is factored once per distinct $`\tau`$.

use crate::error::{require_positive, Error, Result};
use crate::integrators::damping::RayleighDamping;
use crate::integrators::dissipation::{Dissipation, PowerLawDrag, RayleighForm, StageDissipation};
use crate::integrators::first_iterate::{FirstIterate, StepStart};
use crate::integrators::optimization_integrator::{MinimizingSolver, PerStageStep, StageProblem};
use crate::integrators::stopping::Convergence;
use crate::integrators::time_stepper::TimeStepper;
use crate::model::system::{MassSpringSystem, State, Vec3};
use crate::solvers::admm::{default_omega, z_minimisation, AdmmIterate};
use crate::solvers::projective::{
    finish_step, node_of_columns, nodes_of_columns, reduction_matrix, to_columns, GlobalSolve,
    SpringIncidence,
};
use nalgebra::Matrix3;

/// The stiffness-proportional damping as ADMM's second block of $`g`$.
#[derive(Debug, Clone)]
struct StiffnessDampingBlock {
    /// $`D`$ of Eq (54).
    d: SpringIncidence,
    beta: f64,
    /// $`\beta/h`$.
    beta_over_h: f64,
    /// $`\omega'^2_i`$.
    omega2: Vec<f64>,
    /// $`\tau^2\omega'^2_i`$, the factor of $`D_i^\top`$ in the global right-hand side.
    tau2_omega2: Vec<f64>,
    /// $`(\frac{\beta}{h}H_i + \omega'^2_i I)^{-1}`$ of the step.
    inverse: Vec<Matrix3<f64>>,
    /// $`\frac{\beta}{h}H_i\,d_{n,i}`$ of the step.
    target: Vec<Vec3>,
    z: Vec<Vec3>,
    u_bar: Vec<Vec3>,
}

impl StiffnessDampingBlock {
    fn new(system: &MassSpringSystem, beta: f64) -> Self {
        let s = system.springs().len();
        Self {
            d: reduction_matrix(system),
            beta,
            beta_over_h: 0.0,
            omega2: vec![0.0; s],
            tau2_omega2: vec![0.0; s],
            inverse: vec![Matrix3::zeros(); s],
            target: vec![Vec3::zeros(); s],
            z: vec![Vec3::zeros(); s],
            u_bar: vec![Vec3::zeros(); s],
        }
    }

    /// The weights of a step `dt` ($`\omega'^2_i = \beta k_i/h`$) and its scale `tau`.
    fn weights(system: &MassSpringSystem, beta: f64, dt: f64) -> Vec<f64> {
        system
            .springs()
            .iter()
            .map(|s| beta * s.stiffness / dt)
            .collect()
    }

    /// The factors of a step `dt` with the global step's scale `tau`.
    fn set_step(&mut self, system: &MassSpringSystem, dt: f64, tau: f64) {
        self.beta_over_h = self.beta / dt;
        self.omega2 = Self::weights(system, self.beta, dt);
        self.tau2_omega2 = self.omega2.iter().map(|w2| tau * tau * w2).collect();
    }

    /// The step's $`H_i(x_n)`$ and $`d_{n,i}`$ (from `dissipation`), and $`\bar u' = 0`$.
    fn start(&mut self, dissipation: &StageDissipation) -> Result<()> {
        for (i, (inverse, target)) in self.inverse.iter_mut().zip(&mut self.target).enumerate() {
            let b = self.beta_over_h * dissipation.hessian(i);
            *inverse = (b + self.omega2[i] * Matrix3::identity())
                .try_inverse()
                .ok_or_else(|| Error::NotConverged {
                    what: "damped ADMM-PD".into(),
                    detail: format!("spring {i}: the damping block's 3x3 matrix is singular"),
                })?;
            *target = b * dissipation.spring_vector(i);
        }
        self.u_bar.fill(Vec3::zeros());
        Ok(())
    }

    /// $`z'_i`$ then $`\bar u'_i`$ for every spring, from the iterate `x` (column-major).
    fn local_step(&mut self, x: &[f64]) {
        for (i, (z, u_bar)) in self.z.iter_mut().zip(&mut self.u_bar).enumerate() {
            let d_x = self.d.apply_row(i, x);
            *z = self.inverse[i] * (self.target[i] + self.omega2[i] * (d_x + *u_bar));
            *u_bar += d_x - *z;
        }
    }

    /// Adds $`\tau^2 D^\top W'^\top W'(z' - \bar u')`$ to the global right-hand side `rhs`.
    fn add_to_rhs(&self, rhs: &mut [f64]) {
        add_spring_rhs(&self.d, &self.z, &self.u_bar, &self.tau2_omega2, rhs);
    }
}

/// Adds $`\sum_i D_i^\top w_i (z_i - \bar u_i)`$ to the global right-hand side `rhs`.
fn add_spring_rhs(d: &SpringIncidence, z: &[Vec3], u_bar: &[Vec3], w: &[f64], rhs: &mut [f64]) {
    for (i, ((z, u_bar), &w)) in z.iter().zip(u_bar).zip(w).enumerate() {
        d.add_row_transposed(i, w * (z - u_bar), rhs);
    }
}

/// The momentum-conserving Rayleigh damping's springs as a block of $`g`$ (module doc).
#[derive(Debug, Clone)]
struct DampingSpringBlock {
    d: SpringIncidence,
    /// $`\omega''^2_s = (\alpha\mu_s + \beta k_s)/h`$, the damping springs' stiffness.
    omega2: Vec<f64>,
    /// $`\tau^2\omega''^2_s`$.
    tau2_omega2: Vec<f64>,
    /// The rest lengths $`l_s(x_n)`$ of the step.
    lengths: Vec<f64>,
    z: Vec<Vec3>,
    u_bar: Vec<Vec3>,
}

impl DampingSpringBlock {
    fn new(system: &MassSpringSystem) -> Self {
        let s = system.springs().len();
        Self {
            d: reduction_matrix(system),
            omega2: vec![0.0; s],
            tau2_omega2: vec![0.0; s],
            lengths: vec![0.0; s],
            z: vec![Vec3::zeros(); s],
            u_bar: vec![Vec3::zeros(); s],
        }
    }

    /// The weights of a step `dt`.
    fn weights(system: &MassSpringSystem, dissipation: &Dissipation, dt: f64) -> Vec<f64> {
        (0..system.springs().len())
            .map(|i| dissipation.spring_coefficient(system, i) / dt)
            .collect()
    }

    fn set_step(
        &mut self,
        system: &MassSpringSystem,
        dissipation: &Dissipation,
        dt: f64,
        tau: f64,
    ) {
        self.omega2 = Self::weights(system, dissipation, dt);
        self.tau2_omega2 = self.omega2.iter().map(|w2| tau * tau * w2).collect();
    }

    fn start(&mut self, dissipation: &StageDissipation) {
        for (i, l) in self.lengths.iter_mut().enumerate() {
            *l = dissipation.anchor_length(i);
        }
        self.u_bar.fill(Vec3::zeros());
    }

    fn local_step(&mut self, x: &[f64]) {
        for (i, (z, u_bar)) in self.z.iter_mut().zip(&mut self.u_bar).enumerate() {
            let d_x = self.d.apply_row(i, x);
            let k = self.omega2[i];
            *z = z_minimisation(d_x + *u_bar, self.lengths[i], k, k.sqrt());
            *u_bar += d_x - *z;
        }
    }

    fn add_to_rhs(&self, rhs: &mut [f64]) {
        add_spring_rhs(&self.d, &self.z, &self.u_bar, &self.tau2_omega2, rhs);
    }
}

/// [Brown 2018, power-law dissipation] (unverified: no body text or reference code found) The drag's proximal map
/// along $`r`$: the length $`s \in [0, |r|]`$ of $`\arg\min_w \frac{\kappa}{p+1}|w|^{p+1} +
/// \frac{\omega^2}{2}|w - r|^2`$, the root of $`\omega^2(s - |r|) + \kappa s^p`$ (increasing and
/// concave in $`s`$), by Newton's method safeguarded by bisection on the bracket.
pub fn drag_proximal_length(r: f64, kappa: f64, omega2: f64, p: f64) -> f64 {
    let (mut lo, mut hi, mut s) = (0.0, r, r);
    for _ in 0..100 {
        let g = omega2 * (s - r) + kappa * s.powf(p);
        if g == 0.0 {
            break;
        }
        if g > 0.0 {
            hi = s;
        } else {
            lo = s;
        }
        let newton = s - g / (omega2 + kappa * p * s.powf(p - 1.0));
        let next = if (lo..=hi).contains(&newton) {
            newton
        } else {
            0.5 * (lo + hi)
        };
        // Converged: the step is below round-off of the length.
        let done = (next - s).abs() <= 1e-15 * r;
        s = next;
        if done {
            break;
        }
    }
    s
}

/// The power-law drag as a block of $`g`$ on the nodes (module doc).
#[derive(Debug, Clone)]
struct DragBlock {
    drag: PowerLawDrag,
    free: Vec<bool>,
    /// $`\omega_d^2 = c/h`$ on the free nodes, 0 on the fixed.
    omega2: Vec<f64>,
    /// $`\tau^2\omega_d^2`$.
    tau2_omega2: Vec<f64>,
    /// $`\kappa = c\,h^{-p}`$.
    kappa: f64,
    /// The anchor $`x_n`$ of the step.
    x_n: Vec<Vec3>,
    z: Vec<Vec3>,
    u_bar: Vec<Vec3>,
}

impl DragBlock {
    fn new(system: &MassSpringSystem, drag: PowerLawDrag) -> Self {
        let n = system.len();
        Self {
            drag,
            free: system.nodes().iter().map(|n| !n.fixed).collect(),
            omega2: vec![0.0; n],
            tau2_omega2: vec![0.0; n],
            kappa: 0.0,
            x_n: vec![Vec3::zeros(); n],
            z: vec![Vec3::zeros(); n],
            u_bar: vec![Vec3::zeros(); n],
        }
    }

    /// The weights of a step `dt`.
    fn weights(system: &MassSpringSystem, drag: PowerLawDrag, dt: f64) -> Vec<f64> {
        system
            .nodes()
            .iter()
            .map(|n| if n.fixed { 0.0 } else { drag.coefficient / dt })
            .collect()
    }

    fn set_step(&mut self, system: &MassSpringSystem, dt: f64, tau: f64) {
        self.omega2 = Self::weights(system, self.drag, dt);
        self.tau2_omega2 = self.omega2.iter().map(|w2| tau * tau * w2).collect();
        self.kappa = self.drag.coefficient * dt.powf(-self.drag.exponent);
    }

    fn start(&mut self, x_n: &[Vec3]) {
        self.x_n.copy_from_slice(x_n);
        self.u_bar.fill(Vec3::zeros());
    }

    fn local_step(&mut self, x: &[f64]) {
        let n = self.x_n.len();
        for i in (0..n).filter(|&i| self.free[i]) {
            let x_i = node_of_columns(x, n, i);
            let r = x_i + self.u_bar[i] - self.x_n[i];
            let length = r.norm();
            self.z[i] = if length > 0.0 {
                let s =
                    drag_proximal_length(length, self.kappa, self.omega2[i], self.drag.exponent);
                self.x_n[i] + s / length * r
            } else {
                self.x_n[i]
            };
            self.u_bar[i] += x_i - self.z[i];
        }
    }

    fn add_to_rhs(&self, rhs: &mut [f64]) {
        let n = self.x_n.len();
        for i in (0..n).filter(|&i| self.free[i]) {
            let b = self.tau2_omega2[i] * (self.z[i] - self.u_bar[i]);
            for c in 0..3 {
                rhs[c * n + i] += b[c];
            }
        }
    }
}

/// The global scale of a step `dt`: $`\tau = h/\sqrt{1 + \alpha h}`$ with classical
/// mass-proportional damping, $`h`$ otherwise.
fn scale(dissipation: &Dissipation, dt: f64) -> f64 {
    match dissipation.form {
        RayleighForm::Classical => dt / (1.0 + dissipation.rayleigh.alpha * dt).sqrt(),
        RayleighForm::MomentumConserving => dt,
    }
}

/// ADMM-PD with a dissipation (Rayleigh damping by default), a fixed number of iterations per
/// step.
#[derive(Debug, Clone)]
pub struct DampedAdmm {
    system: MassSpringSystem,
    dt: f64,
    iterations: usize,
    dissipation: Dissipation,
    /// $`M + \tau^2 D^\top(W^\top W + W'^\top W' + W''^\top W'')D + \tau^2\Omega_d`$ of each
    /// stage step, factored once.
    a: PerStageStep<GlobalSolve>,
    /// The current stage's $`h`$, s.
    tau: f64,
    iterate: AdmmIterate,
    stage_dissipation: StageDissipation,
    /// Absent when $`\beta = 0`$ or in the momentum-conserving form.
    stiffness_damping: Option<StiffnessDampingBlock>,
    /// The momentum-conserving form's springs.
    damping_springs: Option<DampingSpringBlock>,
    /// Absent without drag.
    drag: Option<DragBlock>,
    /// Where each step starts; `None`: at the damped prediction $`\hat x`$, the centre of the
    /// damped objective's inertial term (its own start).
    start: Option<StepStart>,
    /// When a step stops iterating, and the iterations steps took.
    convergence: Convergence,
}

impl DampedAdmm {
    /// Algorithm 4's precomputation for the damped objective, with $`\omega_i = \sqrt{k_i}`$ and
    /// $`\omega'^2_i = \beta k_i/h`$. Needs valid `params`, `dt` > 0, `iterations` >= 1, every
    /// stiffness > 0 and undamped springs.
    pub fn new(
        system: &MassSpringSystem,
        dt: f64,
        iterations: usize,
        params: RayleighDamping,
    ) -> Result<Self> {
        Self::dissipative(system, dt, iterations, Dissipation::rayleigh(params))
    }

    /// The same solver with any `dissipation` ([`crate::integrators::dissipation`]; module doc).
    pub fn dissipative(
        system: &MassSpringSystem,
        dt: f64,
        iterations: usize,
        dissipation: Dissipation,
    ) -> Result<Self> {
        dissipation.validate()?;
        require_positive("dt", dt)?;
        system.require_positive_stiffness()?;
        system.require_undamped_springs()?;
        if iterations == 0 {
            return Err(Error::invalid("iterations", 0, "an integer >= 1"));
        }
        let omega = default_omega(system);
        let RayleighDamping { beta, .. } = dissipation.rayleigh;
        let classical = dissipation.form == RayleighForm::Classical;
        let mut solver = Self {
            system: system.clone(),
            dt,
            iterations,
            dissipation,
            a: PerStageStep::new(dt, Self::global_solve(system, &dissipation, dt)?),
            tau: dt,
            iterate: AdmmIterate::new(system, scale(&dissipation, dt), omega),
            stage_dissipation: StageDissipation::new(system, dissipation),
            stiffness_damping: (classical && beta > 0.0)
                .then(|| StiffnessDampingBlock::new(system, beta)),
            damping_springs: (!classical && !dissipation.rayleigh.is_none())
                .then(|| DampingSpringBlock::new(system)),
            drag: (dissipation.drag.coefficient > 0.0)
                .then(|| DragBlock::new(system, dissipation.drag)),
            start: None,
            convergence: Convergence::default(),
        };
        solver.set_blocks(dt);
        Ok(solver)
    }

    /// The global matrix of a step `dt`, factored (module doc); an error naming the
    /// coefficient whose weights overflow.
    fn global_solve(
        system: &MassSpringSystem,
        dissipation: &Dissipation,
        dt: f64,
    ) -> Result<GlobalSolve> {
        let RayleighDamping { alpha, beta } = dissipation.rayleigh;
        let largest_k = system
            .springs()
            .iter()
            .fold(0.0_f64, |m, s| m.max(s.stiffness));
        // Finite coefficients can still overflow the weights of the global matrix.
        if !(alpha * dt).is_finite() {
            return Err(Error::invalid(
                "alpha",
                alpha,
                "a number whose alpha * dt is finite",
            ));
        }
        if !(beta * largest_k / dt).is_finite() {
            return Err(Error::invalid(
                "beta",
                beta,
                "a number whose damping weight beta * k / dt is finite",
            ));
        }
        let tau = scale(dissipation, dt);
        let mut weights: Vec<f64> = default_omega(system).iter().map(|w| w * w).collect();
        let classical = dissipation.form == RayleighForm::Classical;
        let extra = if classical && beta > 0.0 {
            Some(StiffnessDampingBlock::weights(system, beta, dt))
        } else if !classical && !dissipation.rayleigh.is_none() {
            Some(DampingSpringBlock::weights(system, dissipation, dt))
        } else {
            None
        };
        if let Some(extra) = extra {
            for (w, w2) in weights.iter_mut().zip(extra) {
                *w += w2;
            }
        }
        let nodes = if dissipation.drag.coefficient > 0.0 {
            DragBlock::weights(system, dissipation.drag, dt)
        } else {
            Vec::new()
        };
        GlobalSolve::with_node_weights(system, tau, &weights, &nodes)
    }

    /// The blocks' factors for a stage step `dt`.
    fn set_blocks(&mut self, dt: f64) {
        let tau = scale(&self.dissipation, dt);
        self.iterate.set_step(tau);
        let system = &self.system;
        if let Some(block) = &mut self.stiffness_damping {
            block.set_step(system, dt, tau);
        }
        if let Some(block) = &mut self.damping_springs {
            block.set_step(system, &self.dissipation, dt, tau);
        }
        if let Some(block) = &mut self.drag {
            block.set_step(system, dt, tau);
        }
    }

    /// Makes `tau` the current stage step, factoring its matrix if new.
    fn select(&mut self, tau: f64) -> Result<()> {
        let (system, dissipation) = (&self.system, &self.dissipation);
        self.a
            .select(tau, |tau| Self::global_solve(system, dissipation, tau))?;
        if tau != self.tau {
            self.tau = tau;
            self.set_blocks(tau);
        }
        Ok(())
    }

    /// The same solver starting each step at `first_iterate` ([`crate::integrators::first_iterate`])
    /// instead of $`\hat x`$ (which is the inertial prediction when $`\alpha = 0`$).
    pub fn with_first_iterate(mut self, first_iterate: FirstIterate) -> Self {
        self.start = Some(StepStart::new(first_iterate));
        self
    }

    /// The Rayleigh damping coefficients.
    pub fn damping(&self) -> RayleighDamping {
        self.dissipation.rayleigh
    }
}

impl TimeStepper for DampedAdmm {
    fn name(&self) -> String {
        let iterations = self
            .convergence
            .iterations_label(self.iterations, "iterations");
        let d = &self.dissipation;
        let RayleighDamping { alpha, beta } = d.rayleigh;
        let mut extra = String::new();
        if d.form != RayleighForm::Classical {
            extra += &format!(", {} Rayleigh", d.form.key());
        }
        if d.drag.coefficient > 0.0 {
            extra += &format!(", drag {} |v|^{}", d.drag.coefficient, d.drag.exponent);
        }
        format!(
            "ADMM-PD with Rayleigh damping (alpha {alpha} 1/s, beta {beta} s{extra}, {iterations})"
        )
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

    fn step(&mut self, state: &mut State) -> Result<()> {
        self.solve(&StageProblem::backward_euler(self.dt), state)
    }
}

impl MinimizingSolver for DampedAdmm {
    /// [Brown 2018, dissipation potential] (unverified: no body text or reference code found) Algorithm 4 on the objective with the damping term.
    // region: step
    fn solve(&mut self, problem: &StageProblem, state: &mut State) -> Result<()> {
        let dt = problem.tau;
        self.select(dt)?;
        let it = &mut self.iterate;
        // 2.1: x̂ = (x̃ + αh·x_n)/(1 + αh), and x⁰ = x̂ (or another first iterate).
        it.predict(&self.system, state, dt);
        let RayleighDamping { alpha, beta } = self.dissipation.rayleigh;
        let classical = self.dissipation.form == RayleighForm::Classical;
        if classical && alpha > 0.0 {
            it.damp_prediction(&self.system, alpha * dt);
        }
        match &mut self.start {
            Some(start) => to_columns(start.first_iterate(&self.system, state, problem), &mut it.x),
            None => it.x.copy_from_slice(&it.x_tilde),
        }
        // 2.2: ū = 0 and the damping blocks' duals 0 every step; H_i, d_i (and the damping
        // springs' rest lengths) frozen at the stage's start.
        it.u_bar.fill(Vec3::zeros());
        if !classical || beta > 0.0 || self.drag.is_some() {
            let frozen = problem.frozen_positions(state);
            self.stage_dissipation
                .start(&self.system, &state.x, frozen, dt);
        }
        if let Some(block) = &mut self.stiffness_damping {
            block.start(&self.stage_dissipation)?;
        }
        if let Some(block) = &mut self.damping_springs {
            block.start(&self.stage_dissipation);
        }
        if let Some(block) = &mut self.drag {
            block.start(&state.x);
        }
        if !self.stage_dissipation.dissipation().is_none() {
            self.convergence.refuse_residual_with_dissipation()?;
        }
        self.convergence
            .begin_stage(&self.system, state, problem.tau, nodes_of_columns(&it.x));
        // 2.3-2.10, with the damping blocks beside the springs', stopping early only in the
        // tolerance mode.
        for _ in 0..self.iterations {
            it.local_step();
            if let Some(block) = &mut self.stiffness_damping {
                block.local_step(&it.x);
            }
            if let Some(block) = &mut self.damping_springs {
                block.local_step(&it.x);
            }
            if let Some(block) = &mut self.drag {
                block.local_step(&it.x);
            }
            it.global_rhs();
            if let Some(block) = &self.stiffness_damping {
                block.add_to_rhs(&mut it.x);
            }
            if let Some(block) = &self.damping_springs {
                block.add_to_rhs(&mut it.x);
            }
            if let Some(block) = &self.drag {
                block.add_to_rhs(&mut it.x);
            }
            self.a.current().solve(&mut it.x, &it.x_n);
            if self.convergence.converged(nodes_of_columns(&it.x)) {
                break;
            }
        }
        self.convergence.end_step(0);
        // 2.11
        finish_step(state, &it.x, dt);
        Ok(())
    }
    // endregion: step

    fn prepare(&mut self, tau: f64) -> Result<()> {
        self.select(tau)
    }

    fn dissipation(&self) -> Option<&Dissipation> {
        (!self.dissipation.is_none()).then_some(&self.dissipation)
    }
}
