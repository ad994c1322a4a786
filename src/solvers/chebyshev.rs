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
//! What is accelerated ([`crate::solvers::local_global`]): Liu's positions $`x`$, as Wang accelerates
//! Projective Dynamics' positions; for ADMM-PD, which Wang does not treat, the pair
//! $`(z, \bar u)`$ of which ADMM is a fixed-point iteration (the positions are a function of
//! it), the variable Peng et al. 2018 accelerate. ADMM's iteration matrix is not symmetric,
//! so its spectrum need not be real and the Chebyshev weights, built for a real spectrum, can
//! amplify the complex modes: measured in `tests/accelerated.rs` and stated below.
//!
//! $`\rho`$ is given ([`ChebyshevParams::spectral_radius`]) or computed when the solver is
//! built, on the scene's start state and the solver's `dt`, by one of two rules
//! ([`RhoRule`]):
//! - [`RhoRule::AsymptoticRate`], this crate's (the default): the asymptotic rate of the plain
//!   iteration, [`asymptotic_rate`]: the plain iteration is run toward convergence and
//!   $`\rho`$ is the geometric mean of the ratios of successive update norms over the second
//!   half of its linear phase. It is one $`\rho`$ for every iteration count.
//! - [`RhoRule::GradientRatio`], the starting point of Wang's procedure (§5.1),
//!   [`gradient_ratio`]: the plain iteration is run for the $`K`$ iterations the solver will
//!   use and $`\rho = |\nabla g(x^{(K)})| / |\nabla g(x^{(K-1)})|`$, the ratio of the
//!   objective's gradient norms at its last two iterates ($`g`$ the incremental potential of
//!   Eq 20). Wang then tunes $`\rho`$ by hand to the fastest convergence, lowering it when
//!   oscillation appears, and notes that it grows with $`K`$ (his Table 1: 0.9992-0.9999); the
//!   hand tuning is not automated here, and the report's scan of $`\rho`$ stands in for it.
//!
//! Defaults ([`ChebyshevParams::default`]): $`S = 10`$; $`\gamma = 1`$, no under-relaxation,
//! since Wang's $`\gamma \in [0.6, 0.9]`$ serves his Jacobi global step (with Gauss-Seidel he
//! uses a forward and a backward sweep instead) and this crate's global step is a direct
//! solve; $`\rho`$ by the asymptotic rate; each step starts from the inertial prediction
//! $`x_n + h v_n + h^2 M^{-1} f_{ext}`$, Wang's Algorithm 1's $`s^t`$.
//!
//! Checked against the paper's text (papers.md): the weights are Eq. 14 with Algorithm 1's
//! delay $`S`$, the update Eq. 21.
//!
//! Under an optimization integrator ([`crate::integrators::optimization_integrator`]) each stage step
//! $`\tau`$ has its own $`\rho`$ (or the given one, for every stage), found when a stage of
//! that step first comes by the same rule with $`dt = \tau`$ on the scene's start state, the
//! probe's plain iteration started at $`x_n`$ ([`FirstIterate::Previous`]) rather than at the
//! solver's first iterate: from the inertial prediction of the rope at rest the slow mode is
//! below round-off for $`\tau < h`$, and the asymptotic rate reads 0 (measured on the k = 1e6
//! rope: 0 at $`\tau`$ = 5e-3 s; from $`x_n`$, 0.9887 there, 0.9936 at 2h/3 and 0.9678 at
//! TR-BDF2's $`\gamma h/2`$ for h = 1e-2 s). The solver's own step keeps its own probe, as above.
//!
//! Measured: the report's section 10 (iterations to 1e-6 m from the inertial prediction, and
//! the scan of $`\rho`$), `tests/accelerated.rs`.

use crate::error::{Error, Result};
use crate::integrators::first_iterate::FirstIterate;
use crate::integrators::optimization_integrator::{MinimizingSolver, PerStageStep, StageProblem};
use crate::integrators::stopping::Convergence;
use crate::integrators::time_stepper::TimeStepper;
use crate::model::system::{MassSpringSystem, State, Vec3};
use crate::solvers::backward_euler::inertia;
use crate::solvers::local_global::{AdmmMerit, Base, LocalGlobal};
use crate::solvers::quasi_newton::potential_gradient;

/// How $`\rho`$ is found when it is not given (module doc).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum RhoRule {
    /// The asymptotic rate of the plain iteration (this crate's estimate).
    #[default]
    AsymptoticRate,
    /// Wang 2015's starting point: the gradient-norm ratio at the last two of $`K`$ iterations.
    GradientRatio,
}

impl RhoRule {
    /// Both rules.
    pub const ALL: [RhoRule; 2] = [RhoRule::AsymptoticRate, RhoRule::GradientRatio];

    /// The name on the command line.
    pub fn key(self) -> &'static str {
        match self {
            RhoRule::AsymptoticRate => "asymptotic-rate",
            RhoRule::GradientRatio => "gradient-ratio",
        }
    }
}

impl std::str::FromStr for RhoRule {
    type Err = Error;

    fn from_str(s: &str) -> Result<Self> {
        RhoRule::ALL
            .into_iter()
            .find(|r| r.key() == s)
            .ok_or_else(|| Error::invalid("rho_rule", s, "asymptotic-rate or gradient-ratio"))
    }
}

/// The parameters of [`Chebyshev`].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ChebyshevParams {
    /// The iteration accelerated.
    pub base: Base,
    /// $`\rho \in (0, 1)`$; `None`: found by `rho_rule` on the scene's start state.
    pub spectral_radius: Option<f64>,
    /// How $`\rho`$ is found when not given.
    pub rho_rule: RhoRule,
    /// The under-relaxation $`\gamma \in (0, 1]`$.
    pub gamma: f64,
    /// $`S`$, the warm-up iterations with $`\omega = 1`$. Any value: $`S`$ at least the
    /// iterations of a step makes the step the plain ($`\gamma`$-relaxed) iteration.
    pub warmup: usize,
    /// Where each step starts.
    pub first_iterate: FirstIterate,
}

impl Default for ChebyshevParams {
    /// Wang 2015's settings for the direct solver: $`S = 10`$, $`\gamma = 1`$, the inertial
    /// prediction as each step's start; $`\rho`$ by the asymptotic rate (ours); Liu 2013 as
    /// the base.
    fn default() -> Self {
        Self {
            base: Base::Liu,
            spectral_radius: None,
            rho_rule: RhoRule::AsymptoticRate,
            gamma: 1.0,
            warmup: 10,
            first_iterate: FirstIterate::InertialPrediction,
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

/// [Wang 2015, Eq. 14, Alg. 1] $`\omega_{k+1}`$ for the iteration $`k`$ (0-based) of a step, delayed
/// by $`S`$ as in Algorithm 1:
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

/// [Wang 2015, Eq. 21] $`v^{(k+1)} = \omega_{k+1}(\gamma(\hat v^{(k+1)} - v^{(k)}) + v^{(k)} -
/// v^{(k-1)}) + v^{(k-1)}`$, written into `v_previous` (which held $`v^{(k-1)}`$).
pub fn extrapolate(omega: f64, gamma: f64, v_hat: &[f64], v: &[f64], v_previous: &mut [f64]) {
    for ((v_prev, &v_hat), &v) in v_previous.iter_mut().zip(v_hat).zip(v) {
        *v_prev = omega * (gamma * (v_hat - v) + v - *v_prev) + *v_prev;
    }
}

/// Iterations the estimate may run at most.
const ESTIMATE_ITERATIONS: usize = 2000;

/// The asymptotic rate of `base`'s plain iteration (this crate's estimate of $`\rho`$) for
/// `system`, `dt` and `state`, each step starting at `first_iterate`: the plain iteration is
/// run (at most 2000 iterations) until its update $`\Delta_k = |v^{(k+1)} - v^{(k)}|`$ falls
/// below $`10^{-11}`$ of the first update or into round-off ($`10^{-12}|v|`$), and
/// $`\rho = (\Delta_K / \Delta_{K/2})^{1/(K - K/2)}`$ over the second half of the updates
/// recorded; 0 when the iteration converges within three. An iteration that does not contract
/// (estimate $`\ge 1`$) is an error.
pub fn asymptotic_rate(
    system: &MassSpringSystem,
    dt: f64,
    base: Base,
    first_iterate: FirstIterate,
    state: &State,
) -> Result<f64> {
    let mut iteration = LocalGlobal::new(system, dt, base, first_iterate, AdmmMerit::default())?;
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
    require_contraction(rho, base, dt, &format!("over {} iterations", updates.len()))
}

/// [Wang 2015, §5.1] The starting value of Wang's $`\rho`$ for a solver of `iterations`
/// ($`K`$) iterations: $`|\nabla g(x^{(K)})| / |\nabla g(x^{(K-1)})|`$ along `base`'s plain
/// iteration of one step from `state` (each step starting at `first_iterate`), $`g`$ the
/// incremental potential of Eq 20. A ratio not in $`(0, 1)`$ is an error.
pub fn gradient_ratio(
    system: &MassSpringSystem,
    dt: f64,
    base: Base,
    first_iterate: FirstIterate,
    state: &State,
    iterations: usize,
) -> Result<f64> {
    if iterations == 0 {
        return Err(Error::invalid("iterations", 0, "an integer >= 1"));
    }
    let mut iteration = LocalGlobal::new(system, dt, base, first_iterate, AdmmMerit::default())?;
    iteration.begin(state);
    let n = system.len();
    let y = inertia(state, dt);
    let (mut forces, mut gradient) = (vec![Vec3::zeros(); n], vec![0.0; 3 * n]);
    let mut gradient_norm = |iteration: &LocalGlobal| {
        let x: Vec<Vec3> = iteration.positions().collect();
        potential_gradient(system, &y, &x, dt, &mut forces, &mut gradient);
        gradient.iter().map(|g| g * g).sum::<f64>().sqrt()
    };
    let mut last = gradient_norm(&iteration);
    let mut before = last;
    for _ in 0..iterations {
        iteration.apply(f64::INFINITY);
        before = last;
        last = gradient_norm(&iteration);
    }
    let rho = last / before;
    // A zero or undefined ratio (a gradient already zero) gives no rho either.
    require_contraction(
        if rho > 0.0 { rho } else { f64::NAN },
        base,
        dt,
        &format!(
            "from the gradient norms {before:e} and {last:e} at iterations {} and {iterations}",
            iterations - 1
        ),
    )
}

/// `rho` if $`0 \le \rho < 1`$; otherwise an error naming `base`, `dt` and `how`.
fn require_contraction(rho: f64, base: Base, dt: f64, how: &str) -> Result<f64> {
    if (0.0..1.0).contains(&rho) {
        Ok(rho)
    } else {
        Err(Error::NotConverged {
            what: format!("spectral radius of {} at dt = {dt} s", base.label()),
            detail: format!("the plain iteration gives rho = {rho} {how} (needs 0 <= rho < 1)"),
        })
    }
}

/// $`\rho`$ of `params` for a solver of `iterations` on `system` and `dt`: given, or found by
/// its rule on `system.initial_state()`.
pub fn spectral_radius(
    system: &MassSpringSystem,
    dt: f64,
    iterations: usize,
    params: &ChebyshevParams,
) -> Result<f64> {
    let state = system.initial_state();
    let ChebyshevParams {
        base,
        first_iterate,
        ..
    } = *params;
    match (params.spectral_radius, params.rho_rule) {
        (Some(rho), _) => Ok(rho),
        (None, RhoRule::AsymptoticRate) => asymptotic_rate(system, dt, base, first_iterate, &state),
        (None, RhoRule::GradientRatio) => {
            gradient_ratio(system, dt, base, first_iterate, &state, iterations)
        }
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
    /// $`\rho`$ of each stage step, given or estimated.
    rho: PerStageStep<f64>,
    // Per-step buffers: v^(k) and v^(k-1).
    v: Vec<f64>,
    v_previous: Vec<f64>,
    /// When a step stops iterating, and the iterations steps took.
    convergence: Convergence,
}

impl Chebyshev {
    /// The accelerated `params.base` for `system`, time step `dt` (s, > 0) and `iterations`
    /// (>= 1) global solves per step; $`\rho`$ found on `system.initial_state()` by the
    /// parameters' rule unless given.
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
        let iteration = LocalGlobal::new(
            system,
            dt,
            params.base,
            params.first_iterate,
            AdmmMerit::default(),
        )?;
        let rho = spectral_radius(system, dt, iterations, &params)?;
        let len = iteration.variable().len();
        Ok(Self {
            iteration,
            iterations,
            params,
            rho: PerStageStep::new(dt, rho),
            v: vec![0.0; len],
            v_previous: vec![0.0; len],
            convergence: Convergence::default(),
        })
    }

    /// $`\rho`$ in use (that of the last stage's step).
    pub fn spectral_radius(&self) -> f64 {
        *self.rho.current()
    }

    /// Makes `tau` the current stage step, finding its $`\rho`$ if new (module doc): by the
    /// same rule, with the probe's iteration started at $`x_n`$.
    fn select(&mut self, tau: f64) -> Result<f64> {
        let (system, iterations) = (self.iteration.system(), self.iterations);
        let probe = ChebyshevParams {
            first_iterate: FirstIterate::Previous,
            ..self.params
        };
        let rho = self
            .rho
            .select(tau, |tau| spectral_radius(system, tau, iterations, &probe))?;
        Ok(*rho)
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
            "Chebyshev {} (Wang 2015, {}, rho = {}{}, gamma = {}, warmup = {}, from {})",
            self.params.base.label(),
            self.convergence
                .iterations_label(self.iterations, "iterations"),
            self.rho.current(),
            match self.params.spectral_radius {
                Some(_) => String::new(),
                None => format!(" by the {}", self.params.rho_rule.key()),
            },
            self.params.gamma,
            self.params.warmup,
            self.params.first_iterate.key()
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

    fn step(&mut self, state: &mut State) -> Result<()> {
        self.solve(&StageProblem::backward_euler(self.iteration.dt()), state)
    }
}

impl MinimizingSolver for Chebyshev {
    // region: step
    fn solve(&mut self, problem: &StageProblem, state: &mut State) -> Result<()> {
        let ChebyshevParams { gamma, warmup, .. } = self.params;
        let rho = self.select(problem.tau)?;
        let it = &mut self.iteration;
        it.begin_stage(state, problem)?;
        // v^(0), and v^(-1) = v^(0): the first extrapolation has no momentum term.
        self.v.copy_from_slice(it.variable());
        self.v_previous.copy_from_slice(it.variable());
        let mut omega_k = 1.0;
        self.convergence
            .begin_stage(it.system(), state, problem.tau, it.positions());
        // Stopping early only in the tolerance mode.
        for k in 0..self.iterations {
            // v̂^(k+1) = G(v^(k)), the base's iteration.
            it.apply(f64::INFINITY);
            omega_k = omega(k, warmup, rho, omega_k);
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

    fn prepare(&mut self, tau: f64) -> Result<()> {
        self.select(tau)?;
        self.iteration.prepare(tau)
    }
}
