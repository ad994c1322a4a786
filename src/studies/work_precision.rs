//! What the benchmark's cases and costs rest on ([`crate::studies::benchmark`]): the four cases, RK4's
//! stability limit, and the cost in floating-point operations.
//!
//! **The cost** in floating-point operations, by a model per operation ([`flops_setup`],
//! [`flops_per_step_overhead`], [`flops_of_iteration`], [`flops_of_extra`]), applied to the
//! iterations each step took ([`logged_flops`]): a run costs setup
//! $`+ \sum_{steps}(`$overhead $`+ \sum_{j < m}`$ iteration $`j)`$ with $`m`$ the step's
//! iterations, plus its logged extra work.

use crate::error::{require_positive, Error, Result};
use crate::integrators::stopping::{IterationLog, Stopping};
use crate::model::linear::SymmetricMatrix;
use crate::model::system::MassSpringSystem;
use crate::solvers::local_global::AdmmMerit;
use crate::solvers::registry::{SolverId, SolverSpec};
use crate::studies::beyond::GridScene;
use std::cell::OnceCell;

/// The interval between the samples of the window, s: a multiple of every swept time step.
pub const SAMPLE_INTERVAL_S: f64 = 0.1;

/// The exact motion's step as a fraction of RK4's stability limit.
pub const EXACT_STABILITY_FRACTION: f64 = 0.01;

/// A scene at a stiffness: one case of the benchmark.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Case {
    pub scene: GridScene,
    pub stiffness: f64,
}

impl Case {
    /// The rope and the 10 × 10 sheet at both stiffnesses of the thesis.
    pub const ALL: [Case; 4] = [
        Case {
            scene: GridScene::Rope,
            stiffness: 1e3,
        },
        Case {
            scene: GridScene::Rope,
            stiffness: 1e6,
        },
        Case {
            scene: GridScene::Sheet,
            stiffness: 1e3,
        },
        Case {
            scene: GridScene::Sheet,
            stiffness: 1e6,
        },
    ];

    /// `rope, k = 1e3 N/m`.
    pub fn label(self) -> String {
        format!("{}, k = {:e} N/m", self.scene.id(), self.stiffness)
    }
}

/// Steps of `dt` between two samples; an error unless `dt` divides [`SAMPLE_INTERVAL_S`].
pub fn steps_per_sample(dt: f64) -> Result<u64> {
    whole_steps(SAMPLE_INTERVAL_S, dt)
}

/// Steps of `dt` in `time` (s); an error unless `dt` is positive and divides it.
pub fn whole_steps(time: f64, dt: f64) -> Result<u64> {
    let dt = require_positive("dt", dt)?;
    let ratio = time / dt;
    if ratio.round() >= 1.0 && (ratio - ratio.round()).abs() < 1e-9 * ratio {
        Ok(ratio.round() as u64)
    } else {
        Err(Error::invalid(
            "dt",
            dt,
            &format!("{time} s divided by a whole number"),
        ))
    }
}

/// The highest natural frequency $`\omega_{max}`$ of `system` linearised at its start, rad/s:
/// the square root of the largest eigenvalue of $`M^{-1/2} K M^{-1/2}`$ over the free nodes,
/// $`K = -\partial f/\partial x`$.
pub fn highest_frequency(system: &MassSpringSystem) -> f64 {
    let x = system.initial_state().x;
    let jacobian = system.force_jacobian_dense(&x);
    let free: Vec<usize> = (0..system.len())
        .filter(|&i| !system.nodes()[i].fixed)
        .flat_map(|i| (0..3).map(move |c| 3 * i + c))
        .collect();
    let scale: Vec<f64> = free
        .iter()
        .map(|&r| 1.0 / system.nodes()[r / 3].mass.sqrt())
        .collect();
    let k = nalgebra::DMatrix::from_fn(free.len(), free.len(), |r, c| {
        -jacobian[(free[r], free[c])] * scale[r] * scale[c]
    });
    let largest = k
        .symmetric_eigenvalues()
        .iter()
        .copied()
        .fold(0.0, f64::max);
    largest.sqrt()
}

/// RK4's stability limit on `system`, s: $`h < 2\sqrt2/\omega_{max}`$.
pub fn rk4_stability_limit(system: &MassSpringSystem) -> f64 {
    2.0 * std::f64::consts::SQRT_2 / highest_frequency(system)
}

// The flop model. One flop is one addition, subtraction, multiplication, division or square
// root of f64s; copies, comparisons and index arithmetic are free.

/// A spring's elastic force (Eq. 3) added to its two nodes: $`d = x_b - x_a`$ 3,
/// $`|d|`$ 5 + 1 (square root), $`k(|d| - l_0)/|d|`$ 3, times $`d`$ 3, added to both nodes 6.
pub const FLOPS_SPRING_FORCE: f64 = 21.0;

/// A spring's force Jacobian (Eq. 4), a 3 × 3 block:
/// $`k\,(1 - l_0/|d|)\,I + k\,(l_0/|d|)\,\hat d\hat d^\top`$ with $`\hat d`$ from the force's
/// $`d, |d|`$: $`\hat d`$ 3, the two scalars 4, the six distinct products of the outer
/// product 6 and their scaling 6, the diagonal 3.
pub const FLOPS_SPRING_JACOBIAN_BLOCK: f64 = 22.0;

/// The block added into the four blocks of Backward Euler's matrix, 36 more.
pub const FLOPS_SPRING_JACOBIAN: f64 = FLOPS_SPRING_JACOBIAN_BLOCK + 36.0;

/// A spring seen from one node in VBD's vertex step: its force added to that node only
/// ([`FLOPS_SPRING_FORCE`] less 3) and its block subtracted from the node's 3 × 3 Hessian,
/// [`FLOPS_SPRING_JACOBIAN_BLOCK`] + 9.
pub const FLOPS_SPRING_VERTEX_VISIT: f64 =
    FLOPS_SPRING_FORCE - 3.0 + FLOPS_SPRING_JACOBIAN_BLOCK + 9.0;

/// A spring's energy $`\frac k2(|d| - l_0)^2`$: 3 + 6 + 3.
pub const FLOPS_SPRING_ENERGY: f64 = 12.0;

/// One node's terms of the incremental potential (Eq. 20), $`\frac{m}{2h^2}|x - y|^2 - m\,g\cdot
/// x`$: 3 + 5 + 2, and 6 for gravity's.
pub const FLOPS_NODE_POTENTIAL: f64 = 16.0;

/// One spring's term of L-BFGS's potential change between two points
/// ([`crate::solvers::quasi_newton::potential_change`]): $`q`$ 3, $`\delta q`$ 9, $`q'`$ 3, the two
/// lengths 12, $`\Delta l = \delta q\cdot(q' + q)/(l' + l)`$ 10, the energy change
/// $`\frac k2\Delta l(\Delta l + 2(l - l_0))`$ 6 and its sum 1.
pub const FLOPS_SPRING_POTENTIAL_CHANGE: f64 = 44.0;

/// One node's term of the same change: the displacement 3, the inertia term
/// $`\frac m2\,\delta\cdot(\delta + 2(x - y))/h^2`$ 3 + 3 + 3 + 5 + 4, gravity's 6, their
/// difference and sum 2.
pub const FLOPS_NODE_POTENTIAL_CHANGE: f64 = 29.0;

/// Liu 2013's local step for one spring, $`d_j = l_0\,(x_b - x_a)/|x_b - x_a|`$:
/// 3 + 6 + 1 (division) + 3.
pub const FLOPS_SPRING_PROJECTION: f64 = 13.0;

/// One spring's term $`k\,J d`$ of the global step's right-hand side: 3 products, added to
/// two nodes, 6.
pub const FLOPS_SPRING_RHS: f64 = 9.0;

/// One spring's constraint projection in PBD and XPBD (Eqs 13-19, 48-51): $`C = |d| - l_0`$
/// 3 + 6 + 1, $`\nabla C = d/|d|`$ 4, the multiplier $`\Delta\lambda = (-C - \tilde\alpha
/// \lambda)/(w_1 + w_2 + \tilde\alpha)`$ 6, the two corrections $`\pm w\,\Delta\lambda\,\nabla
/// C`$ 8 and their addition 6, $`\lambda \mathrel{+}= \Delta\lambda`$ 1. PBD has no
/// $`\lambda`$ and a scale by its stiffness factor instead: the same 36 less 3 plus 1.
pub const FLOPS_CONSTRAINT_PROJECTION: f64 = 36.0;

/// One vertex of VBD: the inertia term's force and Hessian diagonal, $`m/h^2 (x - y)`$,
/// 3 + 3 + 1; the 3 × 3 solve by Cholesky, 3 square roots and 10 for the factor, 12 for the
/// two substitutions; the update 3. (The springs' forces and blocks are counted per visit,
/// [`FLOPS_SPRING_VERTEX_VISIT`], and a Hessian that is not positive definite, factored again
/// after its projection, is not counted.)
pub const FLOPS_VERTEX_SOLVE: f64 = 7.0 + 13.0 + 12.0 + 3.0;

/// The pattern of the matrix a solver factors: unknowns per node (`block`) over the spring
/// graph of every node (fixed nodes included, as [`crate::model::boundary`] keeps them).
fn spring_graph_matrix(system: &MassSpringSystem, block: usize) -> SymmetricMatrix {
    let edges: Vec<(usize, usize)> = system.springs().iter().map(|s| (s.a, s.b)).collect();
    SymmetricMatrix::from_node_graph(system.len(), block, &edges)
}

/// The non-zeros below the diagonal of the banded $`LDL^\top`$ factor of a matrix of
/// dimension $`n`$ and half-bandwidth $`p`$: $`\sum_i \min(i, p)`$.
pub fn factor_nnz(n: usize, p: usize) -> usize {
    (0..n).map(|i| i.min(p)).sum()
}

/// The crate's banded $`LDL^\top`$ ([`crate::model::linear::BandedLdlt`]) of dimension $`n`$ and
/// half-bandwidth $`p`$: row $`i`$ takes $`\sum_{m<p}(2m + 1) = p^2`$ for its $`p`$ entries
/// of $`L`$, $`2p`$ for $`d_i`$ and 1 for $`1/d_i`$, on every row (the factor pads the first
/// rows with zeros): $`n\,(p + 1)^2`$.
pub fn flops_factorization(n: usize, p: usize) -> f64 {
    (n * (p + 1) * (p + 1)) as f64
}

/// One solve with that factor for `rhs` right-hand sides: the two triangular solves
/// $`2 \cdot nnz`$ each and the diagonal $`2n`$ (a product by $`1/d_i`$ and a subtraction),
/// per right-hand side.
pub fn flops_solve(n: usize, p: usize, rhs: usize) -> f64 {
    (rhs * (4 * factor_nnz(n, p) + 2 * n)) as f64
}

/// The sizes (dimension, half-bandwidth) of the matrices the solvers factor on one system's
/// spring graph, each found once: a count asks for them at every iteration of every run, and
/// finding one builds the matrix's pattern.
struct FactoredSizes<'a> {
    system: &'a MassSpringSystem,
    /// One unknown per node: the global solve of Liu 2013, ADMM-PD and L-BFGS.
    node: OnceCell<(usize, usize)>,
    /// Three unknowns per node: Newton's matrix.
    block: OnceCell<(usize, usize)>,
}

impl<'a> FactoredSizes<'a> {
    fn new(system: &'a MassSpringSystem) -> Self {
        Self {
            system,
            node: OnceCell::new(),
            block: OnceCell::new(),
        }
    }

    /// (dimension, half-bandwidth) of the global solve's matrix, one unknown per node.
    fn node(&self) -> (usize, usize) {
        Self::found(&self.node, self.system, 1)
    }

    /// (dimension, half-bandwidth) of Newton's matrix, three unknowns per node.
    fn newton(&self) -> (usize, usize) {
        Self::found(&self.block, self.system, 3)
    }

    /// `cell`'s sizes, found from the matrix with `block` unknowns per node the first time.
    fn found(
        cell: &OnceCell<(usize, usize)>,
        system: &MassSpringSystem,
        block: usize,
    ) -> (usize, usize) {
        *cell.get_or_init(|| {
            let a = spring_graph_matrix(system, block);
            (a.dim(), a.bandwidth())
        })
    }

    /// The global solve of Liu 2013 and ADMM-PD: one node-graph matrix, three right-hand
    /// sides.
    fn global_solve(&self) -> f64 {
        let (n, p) = self.node();
        flops_solve(n, p, 3)
    }

    /// [`Self::global_solve`]'s factorisation, once per run (dt and the stiffness are fixed).
    fn global_factorization(&self) -> f64 {
        let (n, p) = self.node();
        flops_factorization(n, p)
    }
}

/// Floating-point operations before the first step: the factorisation of the global matrix
/// for the solvers that prefactor it (Liu 2013, ADMM-PD, their accelerations, L-BFGS), 0 for
/// the others.
pub fn flops_setup(spec: &SolverSpec, system: &MassSpringSystem) -> f64 {
    match spec.id {
        SolverId::FastMassSpring
        | SolverId::AdmmPd
        | SolverId::ChebyshevLiu
        | SolverId::ChebyshevAdmm
        | SolverId::AndersonLiu
        | SolverId::AndersonAdmm
        | SolverId::DampedAdmm
        | SolverId::Lbfgs => FactoredSizes::new(system).global_factorization(),
        _ => 0.0,
    }
}

/// Floating-point operations of a step outside its iterations, on $`n`$ nodes: the
/// prediction $`y = x + h\,v + h^2 M^{-1} f_{ext}`$, 4 per coordinate, and the velocity
/// $`v = (x - x_n)/h`$, 2 per coordinate, for every solver that iterates on positions; the
/// right-hand side's inertia $`M y/h^2`$, 1 more per coordinate, for the global-solve
/// solvers, and L-BFGS's first gradient ($`s`$ forces + $`4c`$); none for Backward Euler
/// (all inside its Newton iteration); the tutorial's integrators and XPBD's substeps count all
/// their work per iteration.
pub fn flops_per_step_overhead(spec: &SolverSpec, system: &MassSpringSystem) -> f64 {
    let coordinates = 3.0 * system.len() as f64;
    match spec.id {
        SolverId::Lbfgs => {
            7.0 * coordinates
                + system.springs().len() as f64 * FLOPS_SPRING_FORCE
                + 4.0 * coordinates
        }
        SolverId::BackwardEuler | SolverId::DampedBackwardEuler | SolverId::XpbdSubsteps => 0.0,
        SolverId::ExplicitEuler | SolverId::SymplecticEuler | SolverId::Rk4 | SolverId::Rk45 => 0.0,
        SolverId::Pbd | SolverId::Xpbd | SolverId::Vbd => 6.0 * coordinates,
        _ => 7.0 * coordinates,
    }
}

/// Floating-point operations of iteration `j` (from 0) of a step of `spec` on `system`
/// ($`n`$ nodes, $`s`$ springs, $`c = 3n`$ coordinates, $`G`$ the global solve of
/// [`flops_solve`] with three right-hand sides). Anderson's columns and L-BFGS's pairs restart
/// every step, so iteration $`j`$ has $`k = \min(j, m)`$ of them (window $`m`$); every other
/// solver's iterations cost the same:
///
/// | solver | one iteration |
/// |---|---|
/// | Backward Euler (Newton) | $`s`$ (force + Jacobian) + $`9c`$ (the matrix $`M - h^2K`$ and right-hand side) + the factorisation and one solve of the $`c \times c`$ matrix + $`2c`$ (update) |
/// | PBD, XPBD | $`s`$ constraint projections ([`FLOPS_CONSTRAINT_PROJECTION`]) |
/// | XPBD substeps | one XPBD sweep + the prediction and velocity, $`6c`$ |
/// | Liu 2013 | $`s`$ (projection + right-hand side) + $`c`$ + $`G`$ |
/// | ADMM-PD | $`s`$ ($`Dx`$ 3, $`Dx + \bar u`$ 3, projection, $`\bar u \mathrel{+}= Dx - z`$ 6, $`W^2(z - \bar u)`$ 6, right-hand side 6) + $`c`$ + $`G`$ |
/// | Chebyshev | its base's + $`\omega`$ 4 + the extrapolation, 6 per coordinate |
/// | Anderson, $`k`$ columns | its base's + the residual $`c`$ + from the second iteration on the new column (the two differences $`2c`$, its norm $`2c + 1`$ and scaling $`c`$, its Gram row $`2kc`$) + the right-hand side $`2kc`$ + the $`k \times k`$ SVD, $`21k^3`$ (Golub and Van Loan's count with both bases), and its solve $`2k^2`$ + the combination $`2kc + k`$ + the safeguard's merit ($`s`$ spring energies + [`FLOPS_NODE_POTENTIAL`] per node: Liu's incremental potential; ADMM's residual, [`flops_admm_merit`]) |
/// | L-BFGS, $`k`$ pairs | the two-loop recursion $`8kc + 3k`$ and the initial-Hessian solve $`G + c`$ + the slope $`2c`$ + one line-search trial (the point $`2c`$ and the potential's change, [`FLOPS_SPRING_POTENTIAL_CHANGE`] per spring and [`FLOPS_NODE_POTENTIAL_CHANGE`] per node) + the new gradient ($`s`$ forces + $`4c`$) + the new pair $`4c + 1`$ |
/// | VBD | each spring from each of its free nodes ([`FLOPS_SPRING_VERTEX_VISIT`]) + a vertex solve per free node ([`FLOPS_VERTEX_SOLVE`]) |
/// | tutorial integrators | 1, 1 and 4 force evaluations ($`s`$ forces + $`c`$) + 4, 4 and 20 per coordinate |
/// | Dormand-Prince 5(4), a step tried | 6 force evaluations (the seventh is the next step's first) + 42 per coordinate for the stages' sums and 14 for the error estimate |
///
/// An L-BFGS iteration counts one line-search trial; the further trials of a backtracking
/// search, and Anderson's rejected extrapolations, are the solver's logged extra work
/// ([`flops_of_extra`], counted by [`logged_flops`] from the run). An L-BFGS step that ends
/// at a direction below round-off ([`crate::solvers::quasi_newton::ROUND_OFF_STEP`]) is logged with
/// that last iteration counted in full (an upper bound by its line search and gradient).
pub fn flops_of_iteration(spec: &SolverSpec, system: &MassSpringSystem, j: usize) -> f64 {
    iteration_flops(spec, &FactoredSizes::new(system), j)
}

/// [`flops_of_iteration`] with the factored matrices' sizes found once for many iterations.
fn iteration_flops(spec: &SolverSpec, sizes: &FactoredSizes, j: usize) -> f64 {
    let system = sizes.system;
    let n = system.len() as f64;
    let s = system.springs().len() as f64;
    let c = 3.0 * n;
    let forces = s * FLOPS_SPRING_FORCE + c;
    let energy = s * FLOPS_SPRING_ENERGY + n * FLOPS_NODE_POTENTIAL;
    let liu = || s * (FLOPS_SPRING_PROJECTION + FLOPS_SPRING_RHS) + c + sizes.global_solve();
    let admm =
        || s * (3.0 + 3.0 + FLOPS_SPRING_PROJECTION + 6.0 + 6.0 + 6.0) + c + sizes.global_solve();
    let anderson = |base: f64, merit: f64| {
        let k = j.min(spec.params.window) as f64;
        let new_column = if j > 0 {
            6.0 * c + 1.0 + 2.0 * k * c
        } else {
            0.0
        };
        base + c
            + new_column
            + 2.0 * k * c
            + 21.0 * k * k * k
            + 2.0 * k * k
            + 2.0 * k * c
            + k
            + merit
    };
    let chebyshev = |base: f64| base + 4.0 + 6.0 * c;
    match spec.id {
        SolverId::BackwardEuler | SolverId::DampedBackwardEuler => {
            let (dim, p) = sizes.newton();
            s * (FLOPS_SPRING_FORCE + FLOPS_SPRING_JACOBIAN)
                + 9.0 * c
                + flops_factorization(dim, p)
                + flops_solve(dim, p, 1)
                + 2.0 * c
        }
        SolverId::Pbd => s * (FLOPS_CONSTRAINT_PROJECTION - 2.0),
        SolverId::Xpbd => s * FLOPS_CONSTRAINT_PROJECTION,
        SolverId::XpbdSubsteps => s * FLOPS_CONSTRAINT_PROJECTION + 6.0 * c,
        SolverId::FastMassSpring => liu(),
        SolverId::AdmmPd | SolverId::DampedAdmm => admm(),
        SolverId::ChebyshevLiu => chebyshev(liu()),
        SolverId::ChebyshevAdmm => chebyshev(admm()),
        SolverId::AndersonLiu => anderson(liu(), energy),
        SolverId::AndersonAdmm => anderson(admm(), flops_admm_merit(spec, system)),
        SolverId::Lbfgs => {
            let k = j.min(spec.params.history) as f64;
            let direction = 8.0 * k * c + 3.0 * k + sizes.global_solve() + c;
            let trial =
                2.0 * c + s * FLOPS_SPRING_POTENTIAL_CHANGE + n * FLOPS_NODE_POTENTIAL_CHANGE;
            let gradient = s * FLOPS_SPRING_FORCE + 4.0 * c;
            direction + 2.0 * c + trial + gradient + 4.0 * c + 1.0
        }
        SolverId::Vbd => {
            let free = |i: usize| f64::from(u8::from(!system.nodes()[i].fixed));
            let visits: f64 = system
                .springs()
                .iter()
                .map(|sp| free(sp.a) + free(sp.b))
                .sum();
            let vertices: f64 = (0..system.len()).map(free).sum();
            visits * FLOPS_SPRING_VERTEX_VISIT + vertices * FLOPS_VERTEX_SOLVE
        }
        SolverId::ExplicitEuler | SolverId::SymplecticEuler => forces + 4.0 * c,
        SolverId::Rk4 => 4.0 * forces + 20.0 * c,
        SolverId::Rk45 => 6.0 * forces + 56.0 * c,
    }
}

/// An iteration once the window is full ([`flops_of_iteration`] from iteration $`m`$ on).
pub fn flops_per_iteration(spec: &SolverSpec, system: &MassSpringSystem) -> f64 {
    flops_of_iteration(spec, system, usize::MAX)
}

/// A step: the overhead and each of its iterations.
pub fn flops_per_step(spec: &SolverSpec, system: &MassSpringSystem) -> f64 {
    let sizes = FactoredSizes::new(system);
    flops_per_step_overhead(spec, system)
        + (0..spec.iterations)
            .map(|j| iteration_flops(spec, &sizes, j))
            .sum::<f64>()
}

/// Floating-point operations of a run of `spec` over `window` seconds at `dt`, every step
/// taking its full iterations: setup + steps × [`flops_per_step`].
pub fn run_flops(spec: &SolverSpec, system: &MassSpringSystem, dt: f64, window: f64) -> f64 {
    flops_setup(spec, system) + (window / dt).round() * flops_per_step(spec, system)
}

/// A node's share of the tolerance test ([`crate::integrators::stopping::Convergence::converged`]): the
/// difference 3, its squared norm 5 and the square root 1.
pub const FLOPS_TOLERANCE_TEST_PER_NODE: f64 = 9.0;

/// The residual test of one iteration in the residual mode
/// ([`crate::integrators::stopping::Stopping::Residual`]): for a minimizing solver the forces
/// ([`FLOPS_SPRING_FORCE`] per spring) and per node the gradient over mass, $`x - x_a`$ 3,
/// $`\tau^2/m`$ 1, its product with the force 3, the difference 3, the squared norm 5 and the
/// square root 1; for PBD and XPBD per spring $`|C + \tilde\alpha\lambda|`$, the difference 3,
/// its squared norm 5, the square root 1, the rest length 1 and the compliance term 2.
pub fn flops_residual_test(spec: &SolverSpec, system: &MassSpringSystem) -> f64 {
    let s = system.springs().len() as f64;
    if spec.id.is_minimizing() {
        s * FLOPS_SPRING_FORCE + 16.0 * system.len() as f64
    } else {
        12.0 * s
    }
}

/// The merit of one Anderson-ADMM iterate: Zhang et al.'s primal residual
/// $`|W(\bar u^+ - \bar u)|^2`$, 11 per spring (difference 3, weight 3, squared norm 5); or
/// the combined residual, per spring $`Dx^+ - z`$ 6, $`D\,\delta x`$ 3, the two weights 6 and
/// squared norms 10, with the difference $`\delta x`$, $`c`$.
pub fn flops_admm_merit(spec: &SolverSpec, system: &MassSpringSystem) -> f64 {
    let s = system.springs().len() as f64;
    match spec.params.safeguard {
        AdmmMerit::PrimalResidual => 11.0 * s,
        AdmmMerit::CombinedResidual => 25.0 * s + 3.0 * system.len() as f64,
    }
}

/// The work [`IterationLog::extra`] counts, one unit of it: an L-BFGS line-search trial after
/// the first (the trial point and the potential's change, as in [`flops_of_iteration`]); an
/// Anderson extrapolation the safeguard rejected, beyond the logged iterations (whose
/// combinations produced it): for Liu its merit ($`s`$ spring energies and
/// [`FLOPS_NODE_POTENTIAL`] per node); for ADMM with the primal residual the local step and
/// the merit spent on it before the rejection, and no solve; with the combined residual
/// nothing more, the rejected iterate's local step, solve and merit being a logged iteration.
pub fn flops_of_extra(spec: &SolverSpec, system: &MassSpringSystem) -> f64 {
    let n = system.len() as f64;
    let s = system.springs().len() as f64;
    let c = 3.0 * n;
    match spec.id {
        SolverId::Lbfgs => {
            2.0 * c + s * FLOPS_SPRING_POTENTIAL_CHANGE + n * FLOPS_NODE_POTENTIAL_CHANGE
        }
        SolverId::AndersonLiu => s * FLOPS_SPRING_ENERGY + n * FLOPS_NODE_POTENTIAL,
        SolverId::AndersonAdmm => match spec.params.safeguard {
            AdmmMerit::PrimalResidual => {
                s * (12.0 + FLOPS_SPRING_PROJECTION) + flops_admm_merit(spec, system)
            }
            AdmmMerit::CombinedResidual => 0.0,
        },
        _ => 0.0,
    }
}

/// Floating-point operations of a run whose steps took the iterations of `log`: setup
/// $`+ \sum_m N_m\,(`$overhead $`+ \sum_{j<m}`$ iteration $`j)`$, with $`N_m`$ the steps of
/// $`m`$ iterations, + the tolerance or residual test of every iteration in those modes + the
/// extra work ([`flops_of_extra`]). In the count mode, and without early ends or extra work,
/// it is [`run_flops`].
pub fn logged_flops(spec: &SolverSpec, system: &MassSpringSystem, log: &IterationLog) -> f64 {
    let overhead = flops_per_step_overhead(spec, system);
    let sizes = FactoredSizes::new(system);
    let mut step_of = 0.0;
    let mut iterations = 0.0;
    let mut total = flops_setup(spec, system);
    // `step_of` sums the iterations below m in order, as when every count was listed, so that
    // the sum's rounding does not depend on which counts no step took.
    let mut summed = 0;
    for (&m, &steps) in &log.steps_by_iterations {
        while summed < m {
            step_of += iteration_flops(spec, &sizes, summed);
            summed += 1;
        }
        iterations += (m as u64 * steps) as f64;
        total += steps as f64 * (overhead + step_of);
    }
    total += iterations
        * match spec.stopping {
            Stopping::Count => 0.0,
            Stopping::Tolerance(_) => FLOPS_TOLERANCE_TEST_PER_NODE * system.len() as f64,
            Stopping::Residual(_) => flops_residual_test(spec, system),
        };
    total + log.extra as f64 * flops_of_extra(spec, system)
}

/// The residual tolerance of each step, m, for a solver error of `target` m over `window`
/// seconds at steps of `dt`: $`\varepsilon\,\Delta t / W`$, so that the steps' residuals,
/// summed over the window's $`W/\Delta t`$ steps, stay within the target. A residual bounds
/// its step's distance to the step solved exactly (for a minimizing solver the gradient over
/// mass is $`(I + \tau^2 M^{-1}K)\,\delta x`$, with $`K \succeq 0`$ near the rope's taut
/// states), and the errors of successive steps add at most, if the motion does not amplify
/// them; a per-step tolerance of $`\varepsilon`$ itself would let a run of $`W/\Delta t`$
/// steps drift that many times further (the test of `tests/thesis/benchmark.rs` shows it).
pub fn step_residual_tolerance(target: f64, dt: f64, window: f64) -> f64 {
    target * dt / window
}
