//! Chebyshev semi-iterative acceleration (Wang 2015, *A Chebyshev Semi-Iterative Approach for
//! Accelerating Projective and Position-based Dynamics*, SIGGRAPH Asia 2015) of Liu 2013 and
//! ADMM-PD.
//!
//! For a linear iteration $`v^{(k+1)} = B v^{(k)} + c`$ whose matrix has a real spectrum in
//! $`[-\rho, \rho]`$, the Chebyshev semi-iterative method replaces the plain iterate
//! $`\hat v^{(k+1)}`$ by
//! ```math
//! v^{(k+1)} = \omega_{k+1}\left(\gamma\,(\hat v^{(k+1)} - v^{(k)}) + v^{(k)} - v^{(k-1)}\right) + v^{(k-1)},
//! ```
//! with $`\gamma \in (0, 1]`$ an under-relaxation ($`\gamma = 1`$ is the unrelaxed method) and
//! the weights
//! ```math
//! \omega_1 = 1,\qquad \omega_2 = \frac{2}{2 - \rho^2},\qquad \omega_{k+1} = \frac{4}{4 - \rho^2\,\omega_k},
//! ```
//! which make the error after $`k`$ steps a scaled Chebyshev polynomial of $`B`$. Wang observes
//! that Projective Dynamics, although nonlinear, converges like such a linear iteration, so an
//! estimate of its "spectral radius" $`\rho`$ turns the recurrence into an accelerator; he
//! estimates $`\rho`$ from the convergence of the plain iteration on a run, and delays the
//! acceleration by $`S`$ warm-up iterations with $`\omega = 1`$, because the first iterations
//! are the least linear: $`\omega = 1`$ for the iterations $`k < S`$ (0-based), $`\omega =
//! 2/(2 - \rho^2)`$ at $`k = S`$, the recurrence after.
//!
//! What is accelerated ([`crate::local_global`]): Liu's positions $`x`$, as Wang accelerates
//! Projective Dynamics' positions; for ADMM-PD, which Wang does not treat, the pair
//! $`(z, \bar u)`$ of which ADMM is a fixed-point iteration (the positions are a function of
//! it), the variable Peng et al. 2018 accelerate. ADMM's iteration matrix is not symmetric,
//! so its spectrum need not be real and the Chebyshev weights, built for a real spectrum, can
//! amplify the complex modes: measured in `tests/accelerated.rs` and stated below.
//!
//! $`\rho`$ is either given ([`ChebyshevParams::spectral_radius`]) or estimated by
//! [`estimate_spectral_radius`] on the scene's start state and the solver's `dt`: the plain
//! iteration is run and $`\rho`$ is the geometric mean of the ratios of successive update
//! norms over the second half of its linear phase (the ratio of successive errors, which
//! Wang uses, without needing the converged solution).
//!
//! Defaults ([`ChebyshevParams::default`]): $`S = 10`$, the delay Wang uses; $`\gamma = 1`$,
//! no under-relaxation, since Wang's $`\gamma < 1`$ serves the Jacobi and Gauss-Seidel global
//! steps and this crate's global step is a direct solve; $`\rho`$ estimated.
//!
//! The paper's text was not available to this project: the equation numbers of the tags and
//! the default $`S`$ are as recalled, to be checked against the paper.
//!
//! Measured (`tests/accelerated.rs`, default parameters): at dt = 1e-2, k = 1e6, from the
//! thesis rope after 10 converged Backward Euler steps, the first iteration count whose step
//! lands within 1e-6 m of the converged step is 118 for Chebyshev-Liu against Liu's 1582
//! (x 13.4), and 102 for Chebyshev-ADMM against ADMM's 1828 (x 17.9): Wang's "at least one
//! order of magnitude" holds on the rope. $`\rho`$ estimated there is 0.99674 (Liu); the
//! default, estimated on the rope's start, 0.99693. Over the thesis grid (dt 0.1, 0.01, 0.001,
//! k 1e3 and 1e6, 1 to 50 iterations, 5 s runs) neither base diverged under acceleration,
//! ADMM's non-symmetric iteration included.

use crate::error::{Error, Result};
use crate::local_global::{Base, LocalGlobal};
use crate::solver::TimeStepper;
use crate::stopping::Convergence;
use crate::system::{MassSpringSystem, State};

/// The parameters of [`Chebyshev`].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ChebyshevParams {
    /// The iteration accelerated.
    pub base: Base,
    /// $`\rho \in (0, 1)`$; `None`: estimated by [`estimate_spectral_radius`] on the scene's
    /// start state.
    pub spectral_radius: Option<f64>,
    /// The under-relaxation $`\gamma \in (0, 1]`$.
    pub gamma: f64,
    /// $`S`$, the warm-up iterations with $`\omega = 1`$. Any value: $`S`$ at least the
    /// iterations of a step makes the step the plain ($`\gamma`$-relaxed) iteration.
    pub warmup: usize,
}

impl Default for ChebyshevParams {
    /// Wang 2015's settings for the direct solver: $`S = 10`$, $`\gamma = 1`$, $`\rho`$
    /// estimated on the scene; Liu 2013 as the base.
    fn default() -> Self {
        Self {
            base: Base::Liu,
            spectral_radius: None,
            gamma: 1.0,
            warmup: 10,
        }
    }
}

impl ChebyshevParams {
    /// Checks $`0 < \rho < 1`$ and $`0 < \gamma \le 1`$.
    pub fn validate(&self) -> Result<()> {
        if let Some(rho) = self.spectral_radius {
            if !(rho > 0.0 && rho < 1.0) {
                return Err(Error::invalid(
                    "spectral_radius",
                    rho,
                    "a number > 0 and < 1",
                ));
            }
        }
        if !(self.gamma > 0.0 && self.gamma <= 1.0) {
            return Err(Error::invalid("gamma", self.gamma, "a number > 0 and <= 1"));
        }
        Ok(())
    }
}

/// [Wang 2015, Eq. 12] $`\omega_{k+1}`$ for the iteration $`k`$ (0-based) of a step:
/// $`1`$ during the warm-up ($`k < S`$), $`2/(2 - \rho^2)`$ at $`k = S`$, then
/// $`4/(4 - \rho^2\,\omega_k)`$.
pub fn omega(k: usize, warmup: usize, rho: f64, omega_k: f64) -> f64 {
    let rho2 = rho * rho;
    if k < warmup {
        1.0
    } else if k == warmup {
        2.0 / (2.0 - rho2)
    } else {
        4.0 / (4.0 - rho2 * omega_k)
    }
}

/// [Wang 2015, Eq. 13] $`v^{(k+1)} = \omega_{k+1}(\gamma(\hat v^{(k+1)} - v^{(k)}) + v^{(k)} -
/// v^{(k-1)}) + v^{(k-1)}`$, written into `v_previous` (which held $`v^{(k-1)}`$).
pub fn extrapolate(omega: f64, gamma: f64, v_hat: &[f64], v: &[f64], v_previous: &mut [f64]) {
    for ((v_prev, &v_hat), &v) in v_previous.iter_mut().zip(v_hat).zip(v) {
        *v_prev = omega * (gamma * (v_hat - v) + v - *v_prev) + *v_prev;
    }
}

/// Iterations the estimate may run at most.
const ESTIMATE_ITERATIONS: usize = 2000;

/// Wang 2015's "spectral radius" (estimated from a run) of `base`'s iteration for `system`, `dt` and
/// `state`: the plain iteration is run (at most 2000 iterations) until its update
/// $`\Delta_k = |v^{(k+1)} - v^{(k)}|`$ falls below $`10^{-11}`$ of the first update or into
/// round-off ($`10^{-12}|v|`$), and $`\rho = (\Delta_K / \Delta_{K/2})^{1/(K - K/2)}`$ over the
/// second half of the updates recorded; 0 when the iteration converges within three. An
/// iteration that does not contract (estimate $`\ge 1`$) is an error.
pub fn estimate_spectral_radius(
    system: &MassSpringSystem,
    dt: f64,
    base: Base,
    state: &State,
) -> Result<f64> {
    let mut iteration = LocalGlobal::new(system, dt, base)?;
    iteration.begin(state);
    let mut previous = iteration.variable().to_vec();
    let mut updates: Vec<f64> = Vec::new();
    for _ in 0..ESTIMATE_ITERATIONS {
        iteration.apply(f64::INFINITY);
        let v = iteration.variable();
        let norm = |it: &mut dyn Iterator<Item = f64>| it.map(|d| d * d).sum::<f64>().sqrt();
        let update = norm(&mut v.iter().zip(&previous).map(|(a, b)| a - b));
        // Below this the updates are round-off and their ratios say nothing about rho.
        let noise = 1e-12 * norm(&mut v.iter().copied());
        previous.copy_from_slice(v);
        if !update.is_finite() || update <= noise {
            break;
        }
        updates.push(update);
        if update <= 1e-11 * updates[0] {
            break;
        }
    }
    // Too few updates above round-off: the iteration converges at once, rho = 0.
    let rho = match updates.len() {
        0..=2 => 0.0,
        len => {
            let (k, half) = (len - 1, (len - 1) / 2);
            (updates[k] / updates[half]).powf(1.0 / (k - half) as f64)
        }
    };
    if (0.0..1.0).contains(&rho) {
        Ok(rho)
    } else {
        Err(Error::NotConverged {
            what: format!("spectral radius of {} at dt = {dt} s", base.label()),
            detail: format!(
                "the plain iteration's updates give rho = {rho} over {} iterations (needs 0 <= rho < 1)",
                updates.len()
            ),
        })
    }
}

/// Wang 2015's Chebyshev semi-iterative method on Liu 2013 or ADMM-PD, with a fixed number of
/// global solves per step (the base solvers' iteration count). A step depends on the state
/// and the settings only; $`\rho`$ is fixed when the solver is built.
#[derive(Debug, Clone)]
pub struct Chebyshev {
    iteration: LocalGlobal,
    iterations: usize,
    params: ChebyshevParams,
    /// $`\rho`$, given or estimated.
    rho: f64,
    // Per-step buffers: v^(k) and v^(k-1).
    v: Vec<f64>,
    v_previous: Vec<f64>,
    /// When a step stops iterating, and the iterations steps took.
    convergence: Convergence,
}

impl Chebyshev {
    /// The accelerated `params.base` for `system`, time step `dt` (s, > 0) and `iterations`
    /// (>= 1) global solves per step; $`\rho`$ estimated on `system.initial_state()` unless
    /// given.
    pub fn new(
        system: &MassSpringSystem,
        dt: f64,
        iterations: usize,
        params: ChebyshevParams,
    ) -> Result<Self> {
        params.validate()?;
        if iterations == 0 {
            return Err(Error::invalid("iterations", 0, "an integer >= 1"));
        }
        let iteration = LocalGlobal::new(system, dt, params.base)?;
        let rho = match params.spectral_radius {
            Some(rho) => rho,
            None => estimate_spectral_radius(system, dt, params.base, &system.initial_state())?,
        };
        let len = iteration.variable().len();
        Ok(Self {
            iteration,
            iterations,
            params,
            rho,
            v: vec![0.0; len],
            v_previous: vec![0.0; len],
            convergence: Convergence::default(),
        })
    }

    /// $`\rho`$ in use.
    pub fn spectral_radius(&self) -> f64 {
        self.rho
    }

    /// Global solves per step.
    pub fn iterations(&self) -> usize {
        self.iterations
    }

    /// The parameters.
    pub fn params(&self) -> ChebyshevParams {
        self.params
    }
}

impl TimeStepper for Chebyshev {
    fn name(&self) -> String {
        format!(
            "Chebyshev {} (Wang 2015, {}, rho = {}, gamma = {}, warmup = {})",
            self.params.base.label(),
            self.convergence
                .iterations_label(self.iterations, "iterations"),
            self.rho,
            self.params.gamma,
            self.params.warmup
        )
    }

    fn dt(&self) -> f64 {
        self.iteration.dt()
    }

    fn system(&self) -> &MassSpringSystem {
        self.iteration.system()
    }

    fn convergence(&mut self) -> Option<&mut Convergence> {
        Some(&mut self.convergence)
    }

    // region: step
    fn step(&mut self, state: &mut State) -> Result<()> {
        let ChebyshevParams { gamma, warmup, .. } = self.params;
        let it = &mut self.iteration;
        it.begin(state);
        // v^(0), and v^(-1) = v^(0): the first extrapolation has no momentum term.
        self.v.copy_from_slice(it.variable());
        self.v_previous.copy_from_slice(it.variable());
        let mut omega_k = 1.0;
        self.convergence.begin(it.positions());
        // Stopping early only in the tolerance mode.
        for k in 0..it.applications(self.iterations) {
            // v̂^(k+1) = G(v^(k)), the base's iteration.
            it.apply(f64::INFINITY);
            omega_k = omega(k, warmup, self.rho, omega_k);
            extrapolate(omega_k, gamma, it.variable(), &self.v, &mut self.v_previous);
            std::mem::swap(&mut self.v, &mut self.v_previous);
            it.set_variable(&self.v);
            if self.convergence.converged(it.positions()) {
                break;
            }
        }
        let finished = it.finish(state);
        self.convergence.end_step_counted(it.solves(), 0);
        finished
    }
    // endregion: step
}
