//! ADMM-PD with Rayleigh damping (Brown, Overby, Forootaninia, Narain 2018, "Accurate
//! Dissipative Forces in Optimization Integrators"): the thesis's Algorithm 4 ([`crate::admm`])
//! on the damped objective of [`crate::damping`],
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
//! paper's text was not at hand; see [`crate::damping`]); it keeps the springs' local step
//! (Eqs 55-56) exactly the thesis's. The fixed point is the minimiser of $`\Phi`$, the damped
//! converged step [`crate::backward_euler::damped_converged_step`], which the tests check. With
//! $`\alpha = \beta = 0`$ the step is [`crate::admm::AdmmPd`]'s, bit for bit. No state is carried
//! across steps: $`H_i`$, $`d_{n,i}`$ and both duals restart at each step.

use crate::admm::{default_omega, AdmmIterate};
use crate::damping::{RayleighDamping, StepDissipation};
use crate::error::{require_positive, Error, Result};
use crate::first_iterate::{FirstIterate, StepStart};
use crate::projective::{
    finish_step, nodes_of_columns, reduction_matrix, to_columns, GlobalSolve, SpringIncidence,
};
use crate::solver::TimeStepper;
use crate::stopping::Convergence;
use crate::system::{MassSpringSystem, State, Vec3};
use nalgebra::Matrix3;

/// The stiffness-proportional damping as ADMM's second block of $`g`$.
#[derive(Debug, Clone)]
struct StiffnessDampingBlock {
    /// $`D`$ of Eq (54).
    d: SpringIncidence,
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
    fn new(system: &MassSpringSystem, beta: f64, dt: f64, tau: f64) -> Self {
        let s = system.springs().len();
        let omega2: Vec<f64> = system
            .springs()
            .iter()
            .map(|s| beta * s.stiffness / dt)
            .collect();
        Self {
            d: reduction_matrix(system),
            beta_over_h: beta / dt,
            tau2_omega2: omega2.iter().map(|w2| tau * tau * w2).collect(),
            omega2,
            inverse: vec![Matrix3::zeros(); s],
            target: vec![Vec3::zeros(); s],
            z: vec![Vec3::zeros(); s],
            u_bar: vec![Vec3::zeros(); s],
        }
    }

    /// The step's $`H_i(x_n)`$ and $`d_{n,i}`$ (from `dissipation`), and $`\bar u' = 0`$.
    fn start(&mut self, dissipation: &StepDissipation) -> Result<()> {
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
        for (i, ((z, u_bar), &w)) in self
            .z
            .iter()
            .zip(&self.u_bar)
            .zip(&self.tau2_omega2)
            .enumerate()
        {
            self.d.add_row_transposed(i, w * (z - u_bar), rhs);
        }
    }
}

/// ADMM-PD with Rayleigh damping, a fixed number of iterations per step.
#[derive(Debug, Clone)]
pub struct DampedAdmm {
    system: MassSpringSystem,
    dt: f64,
    iterations: usize,
    damping: RayleighDamping,
    /// $`M + \tau^2 D^\top(W^\top W + W'^\top W')D`$, factored once.
    a: GlobalSolve,
    iterate: AdmmIterate,
    dissipation: StepDissipation,
    /// Absent when $`\beta = 0`$.
    stiffness_damping: Option<StiffnessDampingBlock>,
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
        params.validate()?;
        require_positive("dt", dt)?;
        system.require_positive_stiffness()?;
        system.require_undamped_springs()?;
        if iterations == 0 {
            return Err(Error::invalid("iterations", 0, "an integer >= 1"));
        }
        let largest_k = system
            .springs()
            .iter()
            .fold(0.0_f64, |m, s| m.max(s.stiffness));
        // Finite coefficients can still overflow the weights of the global matrix.
        if !(params.alpha * dt).is_finite() {
            return Err(Error::invalid(
                "alpha",
                params.alpha,
                "a number whose alpha * dt is finite",
            ));
        }
        if !(params.beta * largest_k / dt).is_finite() {
            return Err(Error::invalid(
                "beta",
                params.beta,
                "a number whose damping weight beta * k / dt is finite",
            ));
        }
        let tau = dt / (1.0 + params.alpha * dt).sqrt();
        let stiffness_damping =
            (params.beta > 0.0).then(|| StiffnessDampingBlock::new(system, params.beta, dt, tau));
        let omega = default_omega(system);
        let weights: Vec<f64> = match &stiffness_damping {
            Some(block) => omega
                .iter()
                .zip(&block.omega2)
                .map(|(w, w2)| w * w + w2)
                .collect(),
            None => omega.iter().map(|w| w * w).collect(),
        };
        Ok(Self {
            system: system.clone(),
            dt,
            iterations,
            damping: params,
            a: GlobalSolve::new(system, tau, &weights)?,
            iterate: AdmmIterate::new(system, tau, omega),
            dissipation: StepDissipation::new(system, params, dt),
            stiffness_damping,
            start: None,
            convergence: Convergence::default(),
        })
    }

    /// The same solver starting each step at `first_iterate` ([`crate::first_iterate`])
    /// instead of $`\hat x`$ (which is the inertial prediction when $`\alpha = 0`$).
    pub fn with_first_iterate(mut self, first_iterate: FirstIterate) -> Self {
        self.start = Some(StepStart::new(first_iterate));
        self
    }

    /// The damping coefficients.
    pub fn damping(&self) -> RayleighDamping {
        self.damping
    }
}

impl TimeStepper for DampedAdmm {
    fn name(&self) -> String {
        format!(
            "ADMM-PD with Rayleigh damping (alpha {} 1/s, beta {} s, {})",
            self.damping.alpha,
            self.damping.beta,
            self.convergence
                .iterations_label(self.iterations, "iterations")
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

    /// [Brown 2018, dissipation potential] (unverified: no body text or reference code found) Algorithm 4 on the objective with the damping term.
    // region: step
    fn step(&mut self, state: &mut State) -> Result<()> {
        let it = &mut self.iterate;
        // 2.1: x̂ = (x̃ + αh·x_n)/(1 + αh), and x⁰ = x̂ (or another first iterate).
        it.predict(&self.system, state, self.dt);
        if self.damping.alpha > 0.0 {
            it.damp_prediction(&self.system, self.damping.alpha * self.dt);
        }
        match &mut self.start {
            Some(start) => to_columns(start.first_iterate(&self.system, state, self.dt), &mut it.x),
            None => it.x.copy_from_slice(&it.x_tilde),
        }
        // 2.2: ū = 0 and ū' = 0 every step; H_i and d_i frozen at x_n.
        it.u_bar.fill(Vec3::zeros());
        if let Some(block) = &mut self.stiffness_damping {
            self.dissipation.start(&self.system, &state.x);
            block.start(&self.dissipation)?;
        }
        self.convergence.begin(nodes_of_columns(&it.x));
        // 2.3-2.10, with the damping block beside the springs', stopping early only in the
        // tolerance mode.
        for _ in 0..self.iterations {
            it.local_step(&self.system);
            if let Some(block) = &mut self.stiffness_damping {
                block.local_step(&it.x);
            }
            it.global_rhs();
            if let Some(block) = &self.stiffness_damping {
                block.add_to_rhs(&mut it.x);
            }
            self.a.solve(&mut it.x, &it.x_n);
            if self.convergence.converged(nodes_of_columns(&it.x)) {
                break;
            }
        }
        self.convergence.end_step(0);
        // 2.11
        finish_step(state, &it.x, self.dt);
        Ok(())
    }
    // endregion: step
}
