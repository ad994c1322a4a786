//! Anderson acceleration of Liu 2013 (Peng, Deng, Zhang, Geng, Qin, Liu 2018, *Anderson
//! Acceleration for Geometry Optimization and Physics Simulation*, SIGGRAPH 2018; reference code
//! bldeng/AASolver, `AndersonAcceleration.h`, `DynamicsSolver.h`) and of ADMM-PD (Zhang, Peng,
//! Ouyang, Deng 2019, *Accelerating ADMM for Efficient Simulation and Optimization*, SIGGRAPH
//! Asia 2019; reference code bldeng/AA-ADMM, `Solver.cpp`), each with its paper's safeguard.
//! Both reference codes read, not copied; neither paper's body was available, so their
//! equation numbers are not cited.
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
//! constraint. The small least-squares problem ($`m \le 20`$ columns) is solved through its
//! normal equations on columns scaled to unit norm, updated by one row and column per
//! iteration (AASolver does the same; it solves them by a complete orthogonal decomposition,
//! here an SVD).
//!
//! The safeguard: an extrapolated iterate is kept only if it does not raise the merit
//! function; otherwise the step falls back to the plain iterate $`G(v)`$ of the last accepted
//! point, and the history is kept (AASolver's "replace").
//! The merit of Liu 2013's local-global iteration is its energy, the incremental potential of
//! Eq (20) ([`crate::solvers::backward_euler::incremental_potential`]), which the plain iteration never
//! raises (Peng et al.'s rule). For ADMM it is Zhang et al.'s primal residual
//! $`|W(Dx - z)|`$, checked right after the local step, so that a rejection costs a local step
//! and no global solve ([`AdmmMerit::PrimalResidual`], the default); the combined residual
//! after the global step, this crate's merit before issue 22, is the option
//! [`AdmmMerit::CombinedResidual`], with which a rejection has spent a solve
//! ([`crate::solvers::local_global`]). So along the accepted iterates of a Liu step the incremental
//! potential never rises.
//!
//! What is accelerated, and the count of iterations, are those of [`crate::solvers::local_global`]:
//! Liu's positions; ADMM's $`(x, \bar u)`$. A step's budget is its `iterations` global solves.
//! A step returns the plain iterate $`G(v)`$ of its last accepted point, never an extrapolation
//! the safeguard has not vetted. Nothing is carried across steps: the history starts empty each
//! step, and each step starts from the inertial prediction (both reference codes') unless told
//! otherwise.
//!
//! Default window $`m = 5`$, AASolver's `Options.txt` (`AndersonM 5`).
//!
//! Where ours differs from AA-ADMM's code, for ADMM: it chooses the coefficients on the duals'
//! residual alone (its "effective variable") and restarts the history at a rejection; here
//! the coefficients use the whole residual and the history is kept, as AASolver does for Liu.
//! Measured on the rope (dt = 1e-2, k = 1e6, from step10, the inertial prediction, the
//! primal-residual safeguard): with both of AA-ADMM's choices no count up to 400 reaches
//! 1e-6 m; with the restart alone, 201 global solves; with neither (here), 31.
//!
//! Measured: the report's section 10 (iterations to 1e-6 m from the inertial prediction, and
//! what each ADMM safeguard rejects and costs), `tests/accelerated.rs`.

use nalgebra::allocator::Allocator;
use nalgebra::{
    DMatrix, DVector, DefaultAllocator, DimDiff, DimMin, DimSub, OMatrix, OVector, SMatrix,
    SVector, U1,
};

use crate::error::{Error, Result};
use crate::integrators::first_iterate::FirstIterate;
use crate::integrators::optimization_integrator::{MinimizingSolver, StageProblem};
use crate::integrators::stopping::Convergence;
use crate::integrators::time_stepper::TimeStepper;
use crate::model::system::{MassSpringSystem, State};
use crate::solvers::local_global::{AdmmMerit, Base, LocalGlobal, Merit};

/// Largest window accepted.
pub const MAX_WINDOW: usize = 20;

/// The default window, $`m = 5`$ (AASolver's `Options.txt`, `AndersonM 5`).
pub const DEFAULT_WINDOW: usize = 5;

/// The parameters of [`Anderson`].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct AndersonParams {
    /// The iteration accelerated.
    pub base: Base,
    /// The window $`m`$: how many past differences enter each extrapolation (1 to 20).
    pub window: usize,
    /// ADMM's safeguard merit (Liu's is its energy).
    pub safeguard: AdmmMerit,
    /// Where each step starts.
    pub first_iterate: FirstIterate,
}

impl Default for AndersonParams {
    /// $`m = 5`$ (AASolver's default), Zhang et al.'s primal-residual safeguard for ADMM, the
    /// inertial prediction as each step's start; Liu 2013 as the base.
    fn default() -> Self {
        Self {
            base: Base::Liu,
            window: DEFAULT_WINDOW,
            safeguard: AdmmMerit::PrimalResidual,
            first_iterate: FirstIterate::InertialPrediction,
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
/// $`F`$ (scaled to unit norm) and of $`G`$, the normal matrix of the scaled $`\Delta F`$
/// columns (updated by one row and column per iteration, as AASolver does), and the current
/// iterate. Buffers are kept across steps; [`AndersonMixing::restart`] empties the history.
#[derive(Debug, Clone)]
pub struct AndersonMixing {
    window: usize,
    /// The current iterate $`v_k`$.
    v: Vec<f64>,
    /// $`F_k = G(v_k) - v_k`$.
    f: Vec<f64>,
    /// $`F`$ and $`G`$ at the previous evaluation, if any.
    f_previous: Vec<f64>,
    g_previous: Vec<f64>,
    has_previous: bool,
    /// $`\Delta F_j / |\Delta F_j|`$ and $`\Delta G_j`$, a ring of `window` columns.
    delta_f: Vec<Vec<f64>>,
    delta_g: Vec<Vec<f64>>,
    /// $`|\Delta F_j|`$ (1 for a zero column).
    scale: Vec<f64>,
    /// Columns filled, and the ring slot of the next one.
    columns: usize,
    next: usize,
    /// $`\Delta F^\top \Delta F`$ of the scaled columns.
    normal: DMatrix<f64>,
    /// The new column's products with every column ([`dots`]).
    products: Vec<f64>,
}

impl AndersonMixing {
    /// An empty history with window `window` (>= 1) for variables of length `len`.
    pub fn new(window: usize, len: usize) -> Self {
        Self {
            window,
            v: vec![0.0; len],
            f: vec![0.0; len],
            f_previous: vec![0.0; len],
            g_previous: vec![0.0; len],
            has_previous: false,
            delta_f: vec![vec![0.0; len]; window],
            delta_g: vec![vec![0.0; len]; window],
            scale: vec![1.0; window],
            columns: 0,
            next: 0,
            normal: DMatrix::zeros(window, window),
            products: vec![0.0; window],
        }
    }

    /// Empties the history; the iteration starts at `v0`.
    pub fn restart(&mut self, v0: &[f64]) {
        self.v.copy_from_slice(v0);
        self.has_previous = false;
        self.columns = 0;
        self.next = 0;
    }

    /// The current iterate becomes `v` (the safeguard's fallback); the history is kept.
    pub fn replace(&mut self, v: &[f64]) {
        self.v.copy_from_slice(v);
    }

    /// Type-II Anderson mixing (checked against bldeng/AASolver `AndersonAcceleration.h`):
    /// given $`G(v_k)`$, the next iterate
    /// $`v_{k+1} = G(v_k) - \sum_j \theta_j^* \Delta G_j`$, $`\theta^*`$ the least-squares
    /// minimiser of $`|F_k - \sum_j \theta_j \Delta F_j|`$ (`AndersonMixing::theta`). A
    /// non-finite $`G`$ is passed on unchanged, for the step to report.
    pub fn extrapolate(&mut self, g: &[f64]) -> &[f64] {
        for ((f, g), v) in self.f.iter_mut().zip(g).zip(&self.v) {
            *f = g - v;
        }
        self.v.copy_from_slice(g);
        if !self.f.iter().all(|f| f.is_finite()) {
            return &self.v;
        }
        if self.has_previous {
            let col = self.next;
            for (((df, dg), (f, g)), (f0, g0)) in self.delta_f[col]
                .iter_mut()
                .zip(self.delta_g[col].iter_mut())
                .zip(self.f.iter().zip(g))
                .zip(self.f_previous.iter().zip(&self.g_previous))
            {
                *df = f - f0;
                *dg = g - g0;
            }
            let norm = dot(&self.delta_f[col], &self.delta_f[col]).sqrt();
            self.scale[col] = if norm > 0.0 { norm } else { 1.0 };
            let scale = self.scale[col];
            self.delta_f[col].iter_mut().for_each(|df| *df /= scale);
            self.columns = (self.columns + 1).min(self.window);
            self.next = (self.next + 1) % self.window;
            let products = &mut self.products[..self.columns];
            dots(&self.delta_f[..self.columns], &self.delta_f[col], products);
            for (j, &product) in products.iter().enumerate() {
                self.normal[(col, j)] = product;
                self.normal[(j, col)] = product;
            }
        }
        self.f_previous.copy_from_slice(&self.f);
        self.g_previous.copy_from_slice(g);
        self.has_previous = true;
        let theta = self.theta();
        for (j, theta) in theta.iter().enumerate() {
            let theta = theta / self.scale[j];
            for (v, dg) in self.v.iter_mut().zip(&self.delta_g[j]) {
                *v -= theta * dg;
            }
        }
        &self.v
    }

    /// The mixing coefficients (as bldeng/AASolver `AndersonAcceleration.h` computes them):
    /// $`\theta^* = \arg\min_\theta |F_k - \sum_j \theta_j\,\Delta F_j|`$
    /// for the scaled columns, from the normal equations by an SVD; singular values below
    /// $`10^{-14}`$ of the largest are dropped, so that nearly parallel differences give a
    /// bounded $`\theta`$.
    fn theta(&self) -> DVector<f64> {
        let c = self.columns;
        if c == 0 {
            return DVector::zeros(0);
        }
        let mut rhs = DVector::zeros(c);
        dots(&self.delta_f[..c], &self.f, rhs.as_mut_slice());
        let normal = self.normal.view((0, 0), (c, c));
        if c == DEFAULT_WINDOW {
            // The same SVD on the stack, its size known where it is compiled (a full default
            // window is most of a step's iterations): the bits of the dynamic one.
            let theta = least_squares(
                SMatrix::<f64, DEFAULT_WINDOW, DEFAULT_WINDOW>::from_fn(|i, j| normal[(i, j)]),
                &SVector::<f64, DEFAULT_WINDOW>::from_column_slice(rhs.as_slice()),
            );
            return DVector::from_column_slice(theta.as_slice());
        }
        least_squares(normal.into_owned(), &rhs)
    }
}

/// The minimiser of [`AndersonMixing::theta`] from its normal equations `normal θ = rhs`, by
/// nalgebra's SVD, singular values below $`10^{-14}`$ of the largest dropped. A fixed-size
/// matrix does not always give the dynamic one's bits: nalgebra has formulas of its own for an
/// SVD of size 2 or 3 and for a product of vectors of length 2, 3 or 4 (scratch program,
/// 4,000 normal matrices of unit columns of length 30 a size: 3,761, 3,990 and 3,657 of sizes
/// 2, 3 and 4 differ in θ's bits, none of sizes 1 and 5), so only the default window's size,
/// 5, is taken on the stack (tested).
fn least_squares<D>(normal: OMatrix<f64, D, D>, rhs: &OVector<f64, D>) -> OVector<f64, D>
where
    D: DimMin<D, Output = D> + DimSub<U1>,
    DefaultAllocator: Allocator<D, D> + Allocator<D> + Allocator<DimDiff<D, U1>>,
{
    let svd = normal.svd(true, true);
    let eps = 1e-14 * svd.singular_values.max();
    svd.solve(rhs, eps)
        .expect("the SVD was computed with U and V")
}

fn dot(a: &[f64], b: &[f64]) -> f64 {
    a.iter().zip(b).map(|(a, b)| a * b).sum()
}

/// How many of [`dots`]'s sums run side by side.
const DOTS_TOGETHER: usize = 4;

/// [`dot`]`(a_j, b)` for every $`a_j`$ of `a`, into `products[j]`, [`DOTS_TOGETHER`] at a time
/// in one pass over `b`: each sum takes its terms in [`dot`]'s order from [`dot`]'s start (the
/// bits of [`dot`]), and the sums' chains of additions overlap instead of waiting for each
/// other.
fn dots(a: &[Vec<f64>], b: &[f64], products: &mut [f64]) {
    // `Sum`'s own start for f64, whichever zero that is.
    let start: f64 = std::iter::empty::<f64>().sum();
    for (a, products) in a
        .chunks(DOTS_TOGETHER)
        .zip(products.chunks_mut(DOTS_TOGETHER))
    {
        match a {
            [a0, a1, a2, a3] => {
                let mut sums = [start; DOTS_TOGETHER];
                for ((((b, a0), a1), a2), a3) in b.iter().zip(a0).zip(a1).zip(a2).zip(a3) {
                    sums[0] += a0 * b;
                    sums[1] += a1 * b;
                    sums[2] += a2 * b;
                    sums[3] += a3 * b;
                }
                products.copy_from_slice(&sums);
            }
            _ => {
                for (product, a_j) in products.iter_mut().zip(a) {
                    *product = dot(a_j, b);
                }
            }
        }
    }
}

/// One accepted point of a step: where the base's iteration $`G`$ was applied.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Accepted {
    /// The merit at the point: the incremental potential (Liu, J) or the safeguard's residual
    /// (ADMM).
    pub merit: f64,
    /// When the point is the plain iterate the safeguard fell back to: the merit of the
    /// extrapolation it rejected (above the previous point's). `None` for the step's first
    /// point and for accepted extrapolations.
    pub rejected: Option<f64>,
}

/// Anderson acceleration of Liu 2013 (Peng et al. 2018) or ADMM-PD (Zhang et al. 2019), with a
/// fixed number of global solves per step (the base solvers' iteration count).
#[derive(Debug, Clone)]
pub struct Anderson {
    iteration: LocalGlobal,
    iterations: usize,
    params: AndersonParams,
    /// The accepted points of the last step.
    accepted: Vec<Accepted>,
    mixing: AndersonMixing,
    /// $`G`$ of the last accepted point.
    v_default: Vec<f64>,
    /// When a step stops iterating, and the iterations steps took: the accepted applications
    /// of $`G`$, with the rejected extrapolations as its extra work.
    convergence: Convergence,
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
        let iteration = LocalGlobal::new(
            system,
            dt,
            params.base,
            params.first_iterate,
            params.safeguard,
        )?;
        let len = iteration.variable().len();
        Ok(Self {
            iteration,
            iterations,
            params,
            accepted: Vec::new(),
            mixing: AndersonMixing::new(params.window, len),
            v_default: vec![0.0; len],
            convergence: Convergence::default(),
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
        let (paper, safeguard) = match self.params.base {
            Base::Liu => ("Peng 2018", "energy"),
            Base::Admm => ("Zhang 2019", self.params.safeguard.key()),
        };
        format!(
            "Anderson {} ({paper}, {}, window {}, {safeguard} safeguard, from {})",
            self.params.base.label(),
            self.convergence
                .iterations_label(self.iterations, "iterations"),
            self.params.window,
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

impl MinimizingSolver for Anderson {
    /// [Peng 2018, safeguarded Anderson acceleration] Checked against bldeng/AASolver `DynamicsSolver.h`:
    /// the energy safeguard for Liu 2013 as AASolver applies it (the paper's body unread), and
    /// for ADMM Zhang et al.'s primal residual ([`AdmmMerit`]).
    // region: step
    fn solve(&mut self, problem: &StageProblem, state: &mut State) -> Result<()> {
        let it = &mut self.iteration;
        let budget = self.iterations;
        self.accepted.clear();
        it.begin_stage(state, problem)?;
        let (mixing, v_default) = (&mut self.mixing, &mut self.v_default);
        mixing.restart(it.variable());
        // G of the last accepted point: the fallback, and the step's result.
        v_default.copy_from_slice(it.variable());
        let mut merit_previous = f64::INFINITY;
        self.convergence
            .begin_stage(it.system(), state, problem.tau, it.positions());
        // Stopping early only in the tolerance mode.
        while it.solves() < budget {
            let merit = match it.apply(merit_previous) {
                Merit::Applied(merit) => Accepted {
                    merit,
                    rejected: None,
                },
                Merit::Rejected(rejected) => {
                    // The extrapolation raised the merit: back to the plain iterate.
                    it.set_variable(v_default);
                    mixing.replace(v_default);
                    if it.solves() == budget {
                        break;
                    }
                    let Merit::Applied(merit) = it.apply(f64::INFINITY) else {
                        unreachable!("no merit exceeds an infinite threshold")
                    };
                    Accepted {
                        merit,
                        rejected: Some(rejected),
                    }
                }
            };
            self.accepted.push(merit);
            merit_previous = merit.merit;
            v_default.copy_from_slice(it.variable());
            if self.convergence.converged(it.positions()) {
                break;
            }
            let v = mixing.extrapolate(v_default);
            it.set_variable(v);
        }
        it.set_variable(v_default);
        let finished = it.finish(state);
        let rejected = self
            .accepted
            .iter()
            .filter(|a| a.rejected.is_some())
            .count();
        self.convergence
            .end_step_counted(it.solves(), rejected as u64);
        finished
    }
    // endregion: step

    fn prepare(&mut self, tau: f64) -> Result<()> {
        self.iteration.prepare(tau)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The default window's SVD on the stack has the bits of the dynamic one, on 300 normal
    /// matrices of unit columns from well conditioned to rank deficient (two columns equal up
    /// to round-off, or one a combination of two others). Checked failing: the same comparison
    /// at size 4, where nalgebra's products of vectors of length 4 take another order.
    #[test]
    fn the_default_windows_svd_on_the_stack_has_the_bits_of_the_dynamic_one() {
        let c = DEFAULT_WINDOW;
        for case in 0..300 {
            let seed = 0.37 + 0.011 * case as f64;
            let mut columns = DMatrix::from_fn(30, c, |i, j| ((i * c + j) as f64 * seed).sin());
            if case % 3 == 1 {
                let near = columns.column(0) * (1.0 + 1e-15);
                columns.set_column(1, &near);
            }
            if case % 3 == 2 {
                let combination = columns.column(0) + columns.column(2) * seed;
                columns.set_column(3, &combination);
            }
            for mut column in columns.column_iter_mut() {
                column /= column.norm();
            }
            let normal = columns.transpose() * &columns;
            let rhs = DVector::from_fn(c, |i, _| (i as f64 * seed).cos());
            let fixed = least_squares(
                SMatrix::<f64, DEFAULT_WINDOW, DEFAULT_WINDOW>::from_fn(|i, j| normal[(i, j)]),
                &SVector::<f64, DEFAULT_WINDOW>::from_column_slice(rhs.as_slice()),
            );
            let dynamic = least_squares(normal, &rhs);
            for (a, b) in fixed.iter().zip(dynamic.iter()) {
                assert_eq!(a.to_bits(), b.to_bits(), "case {case}");
            }
        }
    }

    /// Each of `dots`'s sums has the bits of `dot`, four at once and fewer, on vectors whose
    /// terms span magnitudes (so that another order of addition rounds differently: one sum
    /// split into two over alternate terms fails this test, checked).
    #[test]
    fn the_sums_side_by_side_have_the_bits_of_dot() {
        let vector = |seed: f64| -> Vec<f64> {
            (0..301)
                .map(|e| (e as f64 * seed).sin() * 10f64.powi(e % 13 - 6))
                .collect()
        };
        let a: Vec<Vec<f64>> = [0.37, 1.1, 2.9, 0.05, 7.3]
            .into_iter()
            .map(vector)
            .collect();
        let b = vector(0.61);
        for columns in [a.len(), 4, 3, 1] {
            let mut products = vec![0.0; columns];
            dots(&a[..columns], &b, &mut products);
            for (a_j, product) in a.iter().zip(&products) {
                assert_eq!(product.to_bits(), dot(a_j, &b).to_bits());
            }
        }
    }
}
