//! What the two Projective-Dynamics solvers share (thesis §2.3, §3.4-3.5): the matrices of
//! Eqs 24-26 and 52-54 for any spring graph, the projection of the local steps, and the global
//! solve of Liu 2013 (Algorithm 3) and ADMM ⊇ PD (Algorithm 4), factored once per scene and
//! time step.
//!
//! Both methods minimise Eq (20) by alternating a local step per spring with a linear solve
//! whose matrix does not depend on the positions:
//! ```math
//! A = M + dt^2 \sum_i w_i\,D_i^\top D_i,
//! ```
//! with $`w_i = k_i`$ Liu's $`M + dt^2 L`$ (Algorithm 3 line 1.4) and with $`w_i = \omega_i^2`$
//! ADMM's $`M + dt^2 D^\top W^\top W D`$ (Algorithm 4 line 1.5). Here $`D_i = (e_{a_i} -
//! e_{b_i})^\top`$ is spring $`i`$'s row of the reduction matrix (Eq 54; Eq 25 writes the same
//! incidence vector as a column).
//!
//! Every matrix acts per coordinate ($`L = \hat L \otimes I`$, Eq 25), so the n×n matrix is
//! factored and the three coordinates are solved together as three right-hand sides. ADMM-PD
//! and the batches therefore keep positions column-major: all x-coordinates, then all y, then
//! all z ([`to_columns`]); Liu's run alone keeps them node by node in the solve's own order
//! ([`GlobalSolve::solve_nodes`], [`crate::solvers::fast_mass_spring::FastMassSpring`]).
//! Fixed nodes are imposed on the n×n matrix by Eqs 43-47 through [`ConstrainedSystem`] in the
//! precomputation; each solve then carries their positions.
//!
//! The springs' incidence (Eqs 26, 53, 54) is [`crate::solvers::incidence`]'s, re-exported
//! here; this module builds it for a system ([`incidence_matrix`], [`reduction_matrix`]).

pub use super::incidence::{Chain, Ends, SpringGraph, SpringIncidence};
use crate::error::{require_non_negative, require_positive, Error, Result};
use crate::model::boundary::{fixed_node_unknowns, ConstrainedSystem, Imposition};
use crate::model::lanes::Lane;
use crate::model::linear::{Factorization, Node, SymmetricMatrix, TwistedTridiagonal};
use crate::model::system::{MassSpringSystem, State, Vec3};
use nalgebra::Vector3;

/// The n×n pattern of the spring graph: a diagonal entry per node, two entries per spring.
fn spring_graph_pattern(system: &MassSpringSystem) -> SymmetricMatrix {
    let edges: Vec<_> = system.springs().iter().map(|s| (s.a, s.b)).collect();
    SymmetricMatrix::from_node_graph(system.len(), 1, &edges)
}

fn add_mass(matrix: &mut SymmetricMatrix, system: &MassSpringSystem) {
    for (i, node) in system.nodes().iter().enumerate() {
        matrix.add(i, i, node.mass);
    }
}

fn add_weighted_laplacian(
    matrix: &mut SymmetricMatrix,
    system: &MassSpringSystem,
    weights: &[f64],
    scale: f64,
) {
    for (s, &w) in system.springs().iter().zip(weights) {
        let w = scale * w;
        matrix.add(s.a, s.a, w);
        matrix.add(s.b, s.b, w);
        matrix.add(s.a, s.b, -w);
        matrix.add(s.b, s.a, -w);
    }
}

fn check_weights(system: &MassSpringSystem, weights: &[f64]) -> Result<()> {
    if weights.len() != system.springs().len() {
        return Err(Error::invalid(
            "weights.len()",
            weights.len(),
            &format!("one weight per spring ({})", system.springs().len()),
        ));
    }
    for (j, &w) in weights.iter().enumerate() {
        require_non_negative(format!("weights[{j}]"), w)?;
    }
    Ok(())
}

/// Eq. (24): $`M = \mathrm{diag}(m_1, \dots, m_n) \otimes I`$, stored per coordinate (n×n).
pub fn mass_matrix(system: &MassSpringSystem) -> SymmetricMatrix {
    let mut m = spring_graph_pattern(system);
    add_mass(&mut m, system);
    m
}

/// Eqs. (25), (52): $`L = \left(\sum_i k_i D_i D_i^\top\right) \otimes I`$, the
/// stiffness-weighted Laplacian of the spring graph, stored per coordinate (n×n). For the
/// thesis rope it is $`k\,\mathrm{tridiag}(-1, 2, -1)`$ with 1 at both ends (Eq 52).
pub fn stiffness_laplacian(system: &MassSpringSystem) -> SymmetricMatrix {
    let k: Vec<f64> = system.springs().iter().map(|s| s.stiffness).collect();
    weighted_laplacian(system, &k).expect("a validated system has one stiffness >= 0 per spring")
}

/// Algorithm 4 line 1.4: $`D^\top W^\top W D = \sum_i w_i\,D_i^\top D_i`$ for per-spring weights
/// $`w_i = \omega_i^2`$ (n×n per coordinate); with $`w_i = k_i`$ this is $`L`$ of Eq (25).
pub fn weighted_laplacian(system: &MassSpringSystem, weights: &[f64]) -> Result<SymmetricMatrix> {
    check_weights(system, weights)?;
    let mut l = spring_graph_pattern(system);
    add_weighted_laplacian(&mut l, system, weights, 1.0);
    Ok(l)
}

/// Eqs. (26), (53): $`J = \left(\sum_i k_i D_i S_i^\top\right) \otimes I`$, the n×s
/// stiffness-weighted incidence matrix (per coordinate), stored as its transpose: column $`i`$
/// of $`J`$ is $`k_i\,(e_{a_i} - e_{b_i})`$.
pub fn incidence_matrix(system: &MassSpringSystem) -> SpringIncidence {
    SpringIncidence::new(
        system,
        system.springs().iter().map(|s| s.stiffness).collect(),
    )
}

/// Eq. (54): $`D`$, the s×n reduction matrix (per coordinate), unweighted: $`D_i x = x_{a_i} -
/// x_{b_i}`$, so that $`D = J^\top`$ without the stiffness (§3.5).
pub fn reduction_matrix(system: &MassSpringSystem) -> SpringIncidence {
    SpringIncidence::new(system, vec![1.0; system.springs().len()])
}

/// Algorithm 3 line 1.4 and Algorithm 4 line 1.5: $`A = M + dt^2 \sum_i w_i D_i^\top D_i`$
/// (n×n per coordinate), before the fixed nodes are imposed.
pub fn system_matrix(
    system: &MassSpringSystem,
    dt: f64,
    weights: &[f64],
) -> Result<SymmetricMatrix> {
    require_positive("dt", dt)?;
    check_weights(system, weights)?;
    let mut a = spring_graph_pattern(system);
    add_mass(&mut a, system);
    add_weighted_laplacian(&mut a, system, weights, dt * dt);
    Ok(a)
}

/// Eqs. (28), (55): the projection of $`q`$ onto the sphere of radius $`l_0`$,
/// $`l_0\,q/|q|`$ (Liu's spring direction $`d_i`$ with $`q = x_1 - x_2`$; ADMM's $`p_i`$ with
/// $`q = D_i x + \bar u_i`$).
///
/// A zero $`q`$ has no direction (every point of the sphere is then a minimiser); the zero
/// vector is returned, as [`crate::model::spring::constraint_gradient`] does, so that a degenerate
/// spring pushes its nodes in no arbitrary direction instead of producing NaN.
#[inline]
pub fn project_on_sphere<T: Lane>(q: Vector3<T>, l0: T) -> Vector3<T> {
    q * sphere_scale(q.norm_squared(), l0)
}

/// Eqs. (28), (55): every spring's factor $`l_{0,i}/|q_i|`$ of the projection
/// ([`project_on_sphere`]) at once: `scale` holds $`|q_i|^2`$ on entry and the factor on
/// return, so that the square roots and divisions of a local step run several at a time in
/// SIMD registers (Liu's local step, [`crate::solvers::fast_mass_spring::spring_directions`],
/// and ADMM-PD's, [`crate::solvers::admm::local_step_of`], multiply by it themselves).
#[inline]
pub fn sphere_scales<T: Lane>(scale: &mut [T], l0: &[T]) {
    for (r, &l0) in scale.iter_mut().zip(l0) {
        *r = sphere_scale(*r, l0);
    }
}

/// $`l_0/|q|`$ from $`|q|^2`$, and 0 for $`q = 0`$: the factor that takes $`q`$ onto the sphere
/// (per lane in a batch: both are computed and the lane's chosen).
#[inline]
fn sphere_scale<T: Lane>(length_squared: T, l0: T) -> T {
    let zero = T::splat(0.0);
    (l0 / length_squared.simd_sqrt()).select(length_squared.simd_gt(zero), zero)
}

/// The global step's linear system, prefactored: $`A`$ of [`system_matrix`] with the fixed
/// nodes imposed by Eqs 43-47 and factored once (one per scene and time step).
#[derive(Debug, Clone)]
pub struct GlobalSolve {
    nodes: usize,
    solve: ConstrainedSystem,
    /// Where each node is in [`Self::solve_nodes`]'s order (the factorisation's): node i at
    /// `rows[i]`.
    rows: Vec<u32>,
}

impl GlobalSolve {
    /// Builds and factors $`A = M + dt^2 \sum_i w_i D_i^\top D_i`$ for `system` (per-spring
    /// `weights` >= 0, `dt` > 0).
    pub fn new(system: &MassSpringSystem, dt: f64, weights: &[f64]) -> Result<Self> {
        Self::with_node_weights(system, dt, weights, &[])
    }

    /// [`Self::new`] with per-node weights too (none, or one per node, >= 0):
    /// $`A = M + dt^2 (\sum_i w_i D_i^\top D_i + \mathrm{diag}(w'))`$, for a block of ADMM's
    /// $`g`$ on the nodes themselves (the damped ADMM's drag).
    pub fn with_node_weights(
        system: &MassSpringSystem,
        dt: f64,
        weights: &[f64],
        node_weights: &[f64],
    ) -> Result<Self> {
        let mut a = system_matrix(system, dt, weights)?;
        for (j, &w) in node_weights.iter().enumerate() {
            require_non_negative(format!("node_weights[{j}]"), w)?;
            a.add(j, j, dt * dt * w);
        }
        let fixed = fixed_node_unknowns(system, 1);
        let solve = ConstrainedSystem::for_three_columns(&mut a, &fixed)?;
        let n = system.len();
        let mut rows: Vec<u32> = (0..n as u32).collect();
        if let Some(order) = solve.factorization().node_order() {
            for (row, &node) in order.iter().enumerate() {
                rows[node as usize] = row as u32;
            }
        }
        Ok(Self {
            nodes: n,
            solve,
            rows,
        })
    }

    /// Where each node is in [`Self::solve_nodes`]'s order: node i at `rows()[i]` (a sparse
    /// factor's fill-reducing ordering; otherwise the nodes' own).
    pub fn rows(&self) -> &[u32] {
        &self.rows
    }

    /// [`Self::solve`] for the three coordinates held node by node in the solve's order
    /// ([`Self::rows`]): on the sheets' sparse factor no permutation in or out, and one
    /// 256-bit vector a node (Eqs 45-47 with the same arithmetic per coordinate).
    #[inline]
    pub fn solve_nodes(&self, b: &mut [Node], x_bar: &[Node]) {
        debug_assert_eq!(b.len(), self.nodes);
        self.solve.solve_nodes(b, x_bar, &self.rows);
    }

    /// Solves $`A x = b`$ for the three coordinates at once. `b` (column-major, length 3n) is
    /// overwritten by $`x`$; the fixed nodes take their values from `x_bar` (same layout), so
    /// that they come out bitwise equal to them (Eqs 45-47).
    #[inline]
    pub fn solve(&self, b: &mut [f64], x_bar: &[f64]) {
        debug_assert_eq!(b.len(), 3 * self.nodes);
        self.solve.solve(b, x_bar, 3);
    }
}

/// [`GlobalSolve`] in lanes ([`crate::model::lanes`]): one prefactored $`A`$ per lane, of one chain's
/// pattern (a tridiagonal $`A`$ of `N` nodes, the rope's) and one fixed set, solved by the same
/// arithmetic as [`GlobalSolve::solve`] at `f64` (the imposition of Eqs 45-47 and the twisted
/// substitution), with the size known where it is compiled.
#[derive(Debug, Clone)]
pub struct GlobalSolveLanes<T, const N: usize> {
    /// The fixed set and Eq (43)'s block $`A_2`$, per lane.
    imposition: Imposition<T>,
    factor: TwistedTridiagonal<T>,
}

impl<T: Lane, const N: usize> GlobalSolveLanes<T, N> {
    /// Lanes for solves of `like`'s pattern and fixed set, none loaded; None unless its
    /// factorisation is a tridiagonal one of `N` nodes.
    pub fn new(like: &GlobalSolve) -> Option<Self> {
        let Factorization::Tridiagonal(factor) = like.solve.factorization() else {
            return None;
        };
        if like.nodes != N {
            return None;
        }
        Some(Self {
            imposition: Imposition::lanes(like.solve.imposition()),
            factor: TwistedTridiagonal::lanes(factor),
        })
    }

    /// Sets lane `lane` to `from`'s matrix, of the same pattern and fixed set.
    pub fn load_lane(&mut self, lane: usize, from: &GlobalSolve) {
        let Factorization::Tridiagonal(factor) = from.solve.factorization() else {
            panic!("a batch of global solves holds tridiagonal ones");
        };
        self.imposition.load_lane(lane, from.solve.imposition());
        self.factor.load_lane(lane, factor);
    }

    /// [`GlobalSolve::solve`] in every lane.
    #[inline]
    pub fn solve(&self, b: &mut [T], x_bar: &[T]) {
        let b = &mut b[..3 * N];
        self.imposition.impose_on_rhs(b, &x_bar[..3 * N], 3);
        self.factor.solve_three_of_size(b, N);
    }
}

/// Copies positions into the column-major layout of the global solve (all x, all y, all z).
pub fn to_columns<T: Lane>(x: &[Vector3<T>], columns: &mut [T]) {
    let n = x.len();
    for (i, p) in x.iter().enumerate() {
        for c in 0..3 {
            columns[c * n + i] = p[c];
        }
    }
}

/// Node `i` of column-major positions over `n` nodes.
#[inline]
pub fn node_of_columns<T: Lane>(columns: &[T], n: usize, i: usize) -> Vector3<T> {
    Vector3::new(columns[i], columns[n + i], columns[2 * n + i])
}

/// The nodes of column-major positions, in order.
pub fn nodes_of_columns(columns: &[f64]) -> impl Iterator<Item = Vec3> + '_ {
    let n = columns.len() / 3;
    (0..n).map(move |i| node_of_columns(columns, n, i))
}

/// Algorithm 4 line 2.11 (and the velocity update Algorithm 3 omits):
/// $`v_{n+1} = (x_{n+1} - x_n)/dt`$, then $`x_n \leftarrow x_{n+1}`$, from the column-major
/// solution `x_next`.
pub fn finish_step(state: &mut State, x_next: &[f64], dt: f64) {
    finish_step_of(&mut state.x, &mut state.v, x_next, dt);
}

/// [`finish_step`] for positions `x` and velocities `v` of any lane type.
pub fn finish_step_of<T: Lane>(x: &mut [Vector3<T>], v: &mut [Vector3<T>], x_next: &[T], dt: T) {
    let n = x.len();
    finish_step_with(x, v, |i| node_of_columns(x_next, n, i), dt);
}

/// [`finish_step`] from node i's new position `x_next(i)`.
#[inline]
pub fn finish_step_with<T: Lane>(
    x: &mut [Vector3<T>],
    v: &mut [Vector3<T>],
    x_next: impl Fn(usize) -> Vector3<T>,
    dt: T,
) {
    for (i, (x, v)) in x.iter_mut().zip(v.iter_mut()).enumerate() {
        let x_new = x_next(i);
        *v = (x_new - *x) / dt;
        *x = x_new;
    }
}
