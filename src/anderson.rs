//! Anderson acceleration (Peng, Deng, Zhang, Liu 2018, *Anderson Acceleration for Geometry
//! Optimization and Physics Simulation*, SIGGRAPH 2018) of Liu 2013 and ADMM-PD, with the
//! paper's safeguard. Reference code: bldeng/AASolver (`AndersonAcceleration.h`), read, not
//! copied.
//!
//! For a fixed-point iteration $`v_{k+1} = G(v_k)`$ with residual $`F(v) = G(v) - v`$, Anderson
//! acceleration with window $`m`$ combines the last $`m + 1`$ evaluations:
//! ```math
//! v_{k+1} = G(v_k) - \sum_{j=1}^{m_k} \theta_j^*\,\big(G(v_{k-j+1}) - G(v_{k-j})\big),
//! \qquad
//! \theta^* = \arg\min_\theta \Big|F_k - \sum_{j=1}^{m_k} \theta_j\,(F_{k-j+1} - F_{k-j})\Big|^2,
//! ```
//! $`m_k = \min(m, k)`$, which is the constrained form $`\min |\sum_j \alpha_j F_{k-j}|`$,
//! $`\sum_j \alpha_j = 1`$, $`v_{k+1} = \sum_j \alpha_j G(v_{k-j})`$ rewritten without the
//! constraint. The small least-squares problem ($`m \le 20`$ columns) is solved by an SVD on
//! columns scaled to unit norm (AASolver scales them the same way).
//!
//! The safeguard: an extrapolated iterate is kept only if it does not raise the merit
//! function; otherwise the step falls back to the plain iterate $`G(v)`$ of the last accepted
//! point, and the history is kept (the paper's "replace"). The merit of Liu 2013's
//! local-global iteration is its energy, the incremental potential of Eq (20)
//! ([`crate::backward_euler::incremental_potential`]), which the plain iteration never
//! raises; for ADMM it is the combined residual (primal plus dual, [`crate::local_global`]).
//! So along the accepted iterates of a Liu step the incremental potential never rises.
//!
//! What is accelerated, and the count of iterations, are those of [`crate::local_global`]:
//! Liu's positions; ADMM's $`(z, \bar u)`$ (as Peng et al. do for ADMM). A step's budget is
//! its `iterations` global solves; an ADMM iterate the safeguard rejects has spent one (its
//! merit needs $`G`$), a rejected Liu iterate none. A step returns the plain iterate $`G(v)`$
//! of its last accepted point, never an extrapolation the safeguard has not vetted. Nothing
//! is carried across steps: the history starts empty each step.
//!
//! Default window $`m = 5`$, AASolver's `Options.txt` (`AndersonM 5`).
//!
//! The equation numbers of the tags could not be checked against the paper's text (not
//! available to this project); they are to be verified.

use nalgebra::{DMatrix, DVector};

use crate::error::{Error, Result};
use crate::local_global::{Base, LocalGlobal};
use crate::solver::TimeStepper;
use crate::system::{MassSpringSystem, State};

/// Largest window accepted.
pub const MAX_WINDOW: usize = 20;

/// The parameters of [`Anderson`].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct AndersonParams {
    /// The iteration accelerated.
    pub base: Base,
    /// The window $`m`$: how many past differences enter each extrapolation (1 to 20).
    pub window: usize,
}

impl Default for AndersonParams {
    /// $`m = 5`$ (AASolver's default), Liu 2013 as the base.
    fn default() -> Self {
        Self {
            base: Base::Liu,
            window: 5,
        }
    }
}

impl AndersonParams {
    /// Checks $`1 \le m \le 20`$.
    pub fn validate(&self) -> Result<()> {
        if !(1..=MAX_WINDOW).contains(&self.window) {
            return Err(Error::invalid(
                "window",
                self.window,
                "an integer from 1 to 20",
            ));
        }
        Ok(())
    }
}

/// The history of Anderson acceleration within one step: the last $`m`$ differences of
/// $`F`$ and of $`G`$, and the current iterate.
#[derive(Debug, Clone)]
pub struct AndersonMixing {
    window: usize,
    /// The current iterate $`v_k`$.
    v: Vec<f64>,
    /// $`F`$ and $`G`$ at the previous evaluation; empty before the first.
    f_previous: Vec<f64>,
    g_previous: Vec<f64>,
    /// $`F_{k-j+1} - F_{k-j}`$ and $`G_{k-j+1} - G_{k-j}`$, oldest first.
    delta_f: Vec<Vec<f64>>,
    delta_g: Vec<Vec<f64>>,
}

impl AndersonMixing {
    /// An empty history with window `window` (>= 1), starting at `v0`.
    pub fn new(window: usize, v0: &[f64]) -> Self {
        Self {
            window,
            v: v0.to_vec(),
            f_previous: Vec::new(),
            g_previous: Vec::new(),
            delta_f: Vec::new(),
            delta_g: Vec::new(),
        }
    }

    /// The current iterate becomes `v` (the safeguard's fallback); the history is kept.
    pub fn replace(&mut self, v: &[f64]) {
        self.v.copy_from_slice(v);
    }

    /// [Peng 2018, Eq. 4] Given $`G(v_k)`$, the next iterate
    /// $`v_{k+1} = G(v_k) - \sum_j \theta_j^* \Delta G_j`$, $`\theta^*`$ the least-squares
    /// minimiser of $`|F_k - \sum_j \theta_j \Delta F_j|`$ ([Peng 2018, Eq. 5]).
    pub fn extrapolate(&mut self, g: &[f64]) -> &[f64] {
        let f: Vec<f64> = g.iter().zip(&self.v).map(|(g, v)| g - v).collect();
        if !self.f_previous.is_empty() {
            if self.delta_f.len() == self.window {
                self.delta_f.remove(0);
                self.delta_g.remove(0);
            }
            let difference = |a: &[f64], b: &[f64]| a.iter().zip(b).map(|(a, b)| a - b).collect();
            self.delta_f.push(difference(&f, &self.f_previous));
            self.delta_g.push(difference(g, &self.g_previous));
        }
        self.v.copy_from_slice(g);
        let theta = least_squares(&self.delta_f, &f);
        for (theta, delta_g) in theta.iter().zip(&self.delta_g) {
            for (v, dg) in self.v.iter_mut().zip(delta_g) {
                *v -= theta * dg;
            }
        }
        self.f_previous = f;
        self.g_previous = g.to_vec();
        &self.v
    }
}

/// [Peng 2018, Eq. 5] $`\theta^* = \arg\min_\theta |f - \sum_j \theta_j\,\Delta F_j|`$, by an
/// SVD of the columns scaled to unit norm; singular values below $`10^{-12}`$ of the largest
/// are dropped, so that nearly parallel differences give a bounded $`\theta`$. Zero columns get
/// $`\theta_j = 0`$; a non-finite history gives no $`\theta`$ (the plain iterate).
fn least_squares(delta_f: &[Vec<f64>], f: &[f64]) -> Vec<f64> {
    // A non-finite history has no least-squares solution; the plain iterate carries the
    // non-finite values on to the step's error.
    if delta_f.is_empty() || !delta_f.iter().flatten().chain(f).all(|x| x.is_finite()) {
        return Vec::new();
    }
    let scale: Vec<f64> = delta_f
        .iter()
        .map(|c| c.iter().map(|x| x * x).sum::<f64>().sqrt())
        .map(|norm| if norm > 0.0 { norm } else { 1.0 })
        .collect();
    let a = DMatrix::from_fn(f.len(), delta_f.len(), |i, j| delta_f[j][i] / scale[j]);
    let svd = a.svd(true, true);
    let eps = 1e-12 * svd.singular_values.max();
    let theta = svd
        .solve(&DVector::from_column_slice(f), eps)
        .expect("the SVD was computed with U and V");
    theta.iter().zip(&scale).map(|(t, s)| t / s).collect()
}

/// One accepted point of a step: where the base's iteration $`G`$ was applied.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Accepted {
    /// The merit at the point: the incremental potential (Liu, J) or the combined residual
    /// (ADMM).
    pub merit: f64,
    /// True when the point is the plain iterate the safeguard fell back to, false when it is
    /// the step's first point or an accepted extrapolation.
    pub fallback: bool,
}

/// Peng et al. 2018's Anderson acceleration of Liu 2013 or ADMM-PD, with a fixed number of
/// global solves per step (the base solvers' iteration count).
#[derive(Debug, Clone)]
pub struct Anderson {
    iteration: LocalGlobal,
    iterations: usize,
    params: AndersonParams,
    /// The accepted points of the last step.
    accepted: Vec<Accepted>,
}

impl Anderson {
    /// The accelerated `params.base` for `system`, time step `dt` (s, > 0) and `iterations`
    /// (>= 1) global solves per step.
    pub fn new(
        system: &MassSpringSystem,
        dt: f64,
        iterations: usize,
        params: AndersonParams,
    ) -> Result<Self> {
        params.validate()?;
        if iterations == 0 {
            return Err(Error::invalid("iterations", 0, "an integer >= 1"));
        }
        Ok(Self {
            iteration: LocalGlobal::new(system, dt, params.base)?,
            iterations,
            params,
            accepted: Vec::new(),
        })
    }

    /// Global solves per step.
    pub fn iterations(&self) -> usize {
        self.iterations
    }

    /// The parameters.
    pub fn params(&self) -> AndersonParams {
        self.params
    }

    /// The accepted points of the last step, in order, with their merits.
    pub fn accepted(&self) -> &[Accepted] {
        &self.accepted
    }
}

impl TimeStepper for Anderson {
    fn name(&self) -> String {
        format!(
            "Anderson {} (Peng 2018, {} iterations, window {})",
            self.params.base.label(),
            self.iterations,
            self.params.window
        )
    }

    fn dt(&self) -> f64 {
        self.iteration.dt()
    }

    fn system(&self) -> &MassSpringSystem {
        self.iteration.system()
    }

    /// [Peng 2018, Alg. 1] Anderson acceleration with the merit safeguard.
    // region: step
    fn step(&mut self, state: &mut State) -> Result<()> {
        let it = &mut self.iteration;
        let budget = it.applications(self.iterations);
        self.accepted.clear();
        it.begin(state);
        let mut mixing = AndersonMixing::new(self.params.window, it.variable());
        // G of the last accepted point: the fallback, and the step's result.
        let mut v_default = it.variable().to_vec();
        let mut merit_previous = f64::INFINITY;
        while it.solves() < budget {
            let merit = match it.apply(merit_previous) {
                Some(merit) => Accepted {
                    merit,
                    fallback: false,
                },
                None => {
                    // The extrapolation raised the merit: back to the plain iterate.
                    it.set_variable(&v_default);
                    mixing.replace(&v_default);
                    if it.solves() == budget {
                        break;
                    }
                    Accepted {
                        merit: it.apply(f64::INFINITY).expect("no threshold"),
                        fallback: true,
                    }
                }
            };
            self.accepted.push(merit);
            merit_previous = merit.merit;
            v_default.copy_from_slice(it.variable());
            let v = mixing.extrapolate(&v_default);
            it.set_variable(v);
        }
        it.set_variable(&v_default);
        it.finish(state)
    }
    // endregion: step
}
