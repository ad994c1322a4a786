//! Sparse symmetric matrices and their prefactored solve, shared by Backward Euler (one
//! factorisation per Newton iteration) and by Liu 2013 and ADMM-PD (one factorisation per
//! scene and time step, Algorithm 3 line 1.4 and Algorithm 4 line 1.5).
//!
//! Three factorisations sit behind [`Factorization`], chosen by the matrix's half-bandwidth:
//! a twisted tridiagonal $`LDL^\top`$ for 1 (a chain with one unknown per node: Liu's and ADMM's
//! per-coordinate matrix of the rope), a banded $`LDL^\top`$ up to
//! [`BANDED_MAX_BANDWIDTH`] (5 for Backward Euler's 3n×3n matrix of the rope), and faer's
//! sparse supernodal Cholesky with a fill-reducing ordering for everything else (a cloth).
//! The pattern is analysed once; refactoring with new values reuses it. The solves of the
//! rope are a few tens of nanoseconds of latency-bound arithmetic, made every iteration, so
//! their loops are written for it (see each type); they allocate nothing.

use crate::error::{Error, Result};
use crate::model::lanes::{load_values, Lane};
use faer::dyn_stack::{MemBuffer, MemStack};
use faer::sparse::linalg::cholesky::{
    factorize_symbolic_cholesky, CholeskySymbolicParams, LltRef, SymbolicCholesky,
    SymbolicCholeskyRaw,
};
use faer::sparse::linalg::SupernodalThreshold;
use faer::sparse::{SparseColMatRef, SymbolicSparseColMatRef};
use faer::{Conj, MatMut, Par, Side};

/// A symmetric matrix with both triangles stored in compressed rows (which, the matrix being
/// symmetric, is also its compressed-column form).
#[derive(Debug, Clone, PartialEq)]
pub struct SymmetricMatrix {
    n: usize,
    row_ptr: Vec<usize>,
    col_idx: Vec<usize>,
    values: Vec<f64>,
}

impl SymmetricMatrix {
    /// The pattern of a node graph with `block`×`block` blocks: one diagonal block per node
    /// and two off-diagonal blocks per edge. Values start at zero.
    pub fn from_node_graph(nodes: usize, block: usize, edges: &[(usize, usize)]) -> Self {
        let mut neighbours: Vec<Vec<usize>> = (0..nodes).map(|i| vec![i]).collect();
        for &(a, b) in edges {
            neighbours[a].push(b);
            neighbours[b].push(a);
        }
        let n = nodes * block;
        let mut row_ptr = Vec::with_capacity(n + 1);
        let mut col_idx = Vec::new();
        row_ptr.push(0);
        for list in &mut neighbours {
            list.sort_unstable();
            list.dedup();
        }
        for list in &neighbours {
            for _ in 0..block {
                for &j in list {
                    col_idx.extend((0..block).map(|c| j * block + c));
                }
                row_ptr.push(col_idx.len());
            }
        }
        let values = vec![0.0; col_idx.len()];
        Self {
            n,
            row_ptr,
            col_idx,
            values,
        }
    }

    /// Dimension.
    pub fn dim(&self) -> usize {
        self.n
    }

    /// Index into the value array of entry (i, j); `None` outside the pattern.
    pub fn slot(&self, i: usize, j: usize) -> Option<usize> {
        let row = &self.col_idx[self.row_ptr[i]..self.row_ptr[i + 1]];
        row.binary_search(&j).ok().map(|k| self.row_ptr[i] + k)
    }

    /// Entry (i, j), zero outside the pattern.
    pub fn get(&self, i: usize, j: usize) -> f64 {
        self.slot(i, j).map_or(0.0, |k| self.values[k])
    }

    /// Adds `value` to entry (i, j).
    ///
    /// # Panics
    /// If (i, j) is outside the pattern: a programming error in the assembly, not bad input.
    pub fn add(&mut self, i: usize, j: usize, value: f64) {
        let k = self
            .slot(i, j)
            .unwrap_or_else(|| panic!("entry ({i}, {j}) is outside the sparsity pattern"));
        self.values[k] += value;
    }

    /// The stored values, in pattern order (for assembly through precomputed slots).
    pub fn values_mut(&mut self) -> &mut [f64] {
        &mut self.values
    }

    /// Sets every stored value to zero, keeping the pattern.
    pub fn clear(&mut self) {
        self.values.fill(0.0);
    }

    /// Row `i` as (column, value) pairs.
    pub fn row(&self, i: usize) -> impl Iterator<Item = (usize, f64)> + '_ {
        let range = self.row_ptr[i]..self.row_ptr[i + 1];
        self.col_idx[range.clone()]
            .iter()
            .copied()
            .zip(self.values[range].iter().copied())
    }

    /// The stored values, in pattern order.
    pub fn values(&self) -> &[f64] {
        &self.values
    }

    /// Row `i` as (slot, column) pairs: where each stored entry's value sits in
    /// [`Self::values`].
    pub fn row_slots(&self, i: usize) -> impl Iterator<Item = (usize, usize)> + '_ {
        (self.row_ptr[i]..self.row_ptr[i + 1]).zip(
            self.col_idx[self.row_ptr[i]..self.row_ptr[i + 1]]
                .iter()
                .copied(),
        )
    }

    /// $`y = A x`$.
    pub fn mul_vec(&self, x: &[f64], y: &mut [f64]) {
        for (i, yi) in y.iter_mut().enumerate() {
            *yi = self.row(i).map(|(j, a)| a * x[j]).sum();
        }
    }

    /// Half-bandwidth: the largest |i - j| of a stored entry.
    pub fn bandwidth(&self) -> usize {
        (0..self.n)
            .flat_map(|i| {
                self.col_idx[self.row_ptr[i]..self.row_ptr[i + 1]]
                    .iter()
                    .map(move |&j| i.abs_diff(j))
            })
            .max()
            .unwrap_or(0)
    }
}

/// Matrices with a half-bandwidth up to this use the banded factorisation, plain scalar code
/// whose results do not depend on the CPU; wider ones go to faer, which picks SIMD kernels at
/// run time. It covers Backward Euler on a 10×10 sheet (3 unknowns per node, springs reaching
/// 11 nodes: half-bandwidth 35), where the band is also the faster: Figure 1's sheet run takes
/// 0.61 s of CPU banded against 0.87 s with faer's sparse Cholesky. A 15×15 sheet (50) is past it.
pub const BANDED_MAX_BANDWIDTH: usize = 40;

/// A factorisation of a symmetric positive definite matrix ($`LDL^\top`$ or $`LL^\top`$),
/// analysed once for its pattern.
#[derive(Debug, Clone)]
pub enum Factorization {
    /// Half-bandwidth at most 1 (a chain with one unknown per node).
    Tridiagonal(TwistedTridiagonal),
    /// Dense band storage; no fill outside the band.
    Banded(BandedLdlt),
    /// faer's sparse Cholesky with its symbolic analysis kept for refactoring.
    Sparse(SparseCholesky),
}

impl Factorization {
    /// Analyses the pattern of `a` and factors it. Fails if `a` is not positive definite.
    pub fn new(a: &SymmetricMatrix) -> Result<Self> {
        match a.bandwidth() {
            0 | 1 => TwistedTridiagonal::new(a).map(Self::Tridiagonal),
            p if p <= BANDED_MAX_BANDWIDTH => BandedLdlt::new(a).map(Self::Banded),
            _ => SparseCholesky::new(a).map(Self::Sparse),
        }
    }

    /// [`Self::new`] for a matrix factored once and solved every iteration with three
    /// right-hand sides (Liu's and ADMM's $`A`$): a sparse one takes the simplicial factor
    /// ([`SparseCholesky::simplicial`]) whatever faer's heuristic says, for its faster
    /// three-column solve.
    pub fn for_three_columns(a: &SymmetricMatrix) -> Result<Self> {
        match a.bandwidth() {
            p if p <= BANDED_MAX_BANDWIDTH => Self::new(a),
            _ => SparseCholesky::simplicial(a).map(Self::Sparse),
        }
    }

    /// Factors new values with the same pattern as the matrix this was built from.
    pub fn refactor(&mut self, a: &SymmetricMatrix) -> Result<()> {
        match self {
            Self::Tridiagonal(f) => f.refactor(a),
            Self::Banded(f) => f.refactor(a),
            Self::Sparse(f) => f.refactor(a),
        }
    }

    /// Solves $`A x = b`$ in place for `ncols` right-hand sides stored one after another
    /// (column-major, each of length n).
    #[inline]
    pub fn solve_in_place(&self, b: &mut [f64], ncols: usize) {
        match self {
            Self::Tridiagonal(f) => f.solve_in_place(b, ncols),
            Self::Banded(f) => f.solve_in_place(b, ncols),
            Self::Sparse(f) => f.solve_in_place(b, ncols),
        }
    }
}

/// Splits `b` into `C` right-hand sides of length `n`, stored one after another.
#[inline]
fn columns<T, const C: usize>(b: &mut [T], n: usize) -> [&mut [T]; C] {
    let mut columns = b.chunks_exact_mut(n);
    std::array::from_fn(|_| columns.next().expect("C columns of length n"))
}

/// Rejects a pivot that is not positive and finite, and returns its inverse.
#[inline]
fn inverse_pivot(row: usize, d: f64) -> Result<f64> {
    if d.is_nan() || d <= 0.0 || d.is_infinite() {
        Err(not_positive_definite(row, d))
    } else {
        Ok(1.0 / d)
    }
}

/// A symmetric tridiagonal matrix factored from both ends toward a middle row k (a twisted
/// factorisation): $`LDL^\top`$ down rows $`0..k`$, its mirror image $`UEU^\top`$ up rows
/// $`n-1..k`$, and the pivot $`\gamma_k`$ where the two meet.
///
/// A substitution is a chain in which every row waits for its neighbour; starting from both
/// ends halves the chain, the two halves running side by side. This is the solve Liu 2013
/// and ADMM-PD make every iteration on a rope (n = 10), for three right-hand sides swept
/// together so that their chains overlap too.
///
/// The factor's values are per lane in a batch of runs ([`crate::model::lanes`]); the solve is the
/// same code at `f64` and in lanes.
#[derive(Debug, Clone)]
pub struct TwistedTridiagonal<T = f64> {
    n: usize,
    /// The middle row.
    k: usize,
    /// Slots of $`a_{ii}`$, and of $`a_{i,i+1}`$ where stored, in the matrix's values.
    diagonal_slots: Vec<usize>,
    off_diagonal_slots: Vec<Option<usize>>,
    /// $`L_{i,i-1}`$ for $`1 \le i \le k`$, zero elsewhere.
    lower: Vec<T>,
    /// $`U_{i,i+1}`$ for $`k \le i < n-1`$, zero elsewhere.
    upper: Vec<T>,
    /// $`1/d_i`$ above k, $`1/\gamma_k`$ at k, $`1/e_i`$ below k.
    inverse_pivot: Vec<T>,
}

impl TwistedTridiagonal {
    /// Factors `a`, whose half-bandwidth must be at most 1.
    pub fn new(a: &SymmetricMatrix) -> Result<Self> {
        if a.bandwidth() > 1 {
            return Err(Error::invalid(
                "bandwidth",
                a.bandwidth(),
                "at most 1 for the tridiagonal factorisation",
            ));
        }
        let n = a.dim();
        let mut f = Self {
            n,
            k: n.saturating_sub(1) / 2,
            diagonal_slots: (0..n)
                .map(|i| a.slot(i, i).expect("the pattern stores the diagonal"))
                .collect(),
            off_diagonal_slots: (0..n).map(|i| a.slot(i, i + 1)).collect(),
            lower: vec![0.0; n],
            upper: vec![0.0; n],
            inverse_pivot: vec![0.0; n],
        };
        f.refactor(a)?;
        Ok(f)
    }

    /// Factors new values of a matrix with the pattern of the one this was built from:
    /// $`L_{i,i-1} = a_{i,i-1}/d_{i-1}`$, $`d_i = a_{ii} - a_{i,i-1}L_{i,i-1}`$ down to k, the
    /// mirror image up to k, and $`\gamma_k = a_{kk} - a_{k,k-1}L_{k,k-1} - a_{k,k+1}U_{k,k+1}`$.
    pub fn refactor(&mut self, a: &SymmetricMatrix) -> Result<()> {
        let (n, k) = (self.n, self.k);
        if n == 0 {
            return Ok(());
        }
        let values = a.values();
        let diagonal = |i: usize| values[self.diagonal_slots[i]];
        // a_{i,i+1}, zero past the end or where the pattern has no entry.
        let off_diagonal = |i: usize| self.off_diagonal_slots[i].map_or(0.0, |s| values[s]);
        for i in 0..k {
            let (t, l) = if i > 0 {
                let t = off_diagonal(i - 1);
                (t, t * self.inverse_pivot[i - 1])
            } else {
                (0.0, 0.0)
            };
            self.lower[i] = l;
            self.inverse_pivot[i] = inverse_pivot(i, diagonal(i) - t * l)?;
        }
        for i in (k + 1..n).rev() {
            let (t, u) = if i + 1 < n {
                let t = off_diagonal(i);
                (t, t * self.inverse_pivot[i + 1])
            } else {
                (0.0, 0.0)
            };
            self.upper[i] = u;
            self.inverse_pivot[i] = inverse_pivot(i, diagonal(i) - t * u)?;
        }
        let (t_lower, l) = if k > 0 {
            let t = off_diagonal(k - 1);
            (t, t * self.inverse_pivot[k - 1])
        } else {
            (0.0, 0.0)
        };
        let (t_upper, u) = if k + 1 < n {
            let t = off_diagonal(k);
            (t, t * self.inverse_pivot[k + 1])
        } else {
            (0.0, 0.0)
        };
        self.lower[k] = l;
        self.upper[k] = u;
        self.inverse_pivot[k] = inverse_pivot(k, diagonal(k) - t_lower * l - t_upper * u)?;
        Ok(())
    }
}

impl<T: Lane> TwistedTridiagonal<T> {
    /// The factorisation of `like`'s pattern with every value zero, in lanes to be loaded
    /// ([`Self::load_lane`]).
    pub fn lanes(like: &TwistedTridiagonal) -> Self {
        let zero = vec![T::splat(0.0); like.n];
        Self {
            n: like.n,
            k: like.k,
            diagonal_slots: like.diagonal_slots.clone(),
            off_diagonal_slots: like.off_diagonal_slots.clone(),
            lower: zero.clone(),
            upper: zero.clone(),
            inverse_pivot: zero,
        }
    }

    /// Sets lane `lane` of the factor to `from`'s, which must have the same size.
    pub fn load_lane(&mut self, lane: usize, from: &TwistedTridiagonal) {
        assert_eq!((from.n, from.k), (self.n, self.k), "one size in a batch");
        load_values(&mut self.lower, lane, &from.lower);
        load_values(&mut self.upper, lane, &from.upper);
        load_values(&mut self.inverse_pivot, lane, &from.inverse_pivot);
    }

    /// Solves for `ncols` right-hand sides, three of them together.
    pub fn solve_in_place(&self, b: &mut [T], ncols: usize) {
        let b = &mut b[..self.n * ncols];
        if self.n == 0 {
            return;
        }
        match ncols {
            3 => self.solve_together(columns::<_, 3>(b, self.n)),
            _ => {
                for col in b.chunks_exact_mut(self.n) {
                    self.solve_together([col]);
                }
            }
        }
    }

    /// $`y_i = b_i - L_{i,i-1}y_{i-1}`$ down to k and $`y_i = b_i - U_{i,i+1}y_{i+1}`$ up to k,
    /// $`x_k = (b_k - L_{k,k-1}y_{k-1} - U_{k,k+1}y_{k+1})/\gamma_k`$, then outward
    /// $`x_i = y_i/d_i - L_{i+1,i}x_{i+1}`$ and $`x_i = y_i/e_i - U_{i-1,i}x_{i-1}`$.
    #[inline]
    fn solve_together<const C: usize>(&self, mut cols: [&mut [T]; C]) {
        let (n, k) = (self.n, self.k);
        let lower = &self.lower[..n];
        let upper = &self.upper[..n];
        let inv = &self.inverse_pivot[..n];
        for col in cols.iter_mut() {
            let (above, rest) = col.split_at_mut(k);
            let mut y = T::splat(0.0);
            for (b, &l) in above.iter_mut().zip(lower) {
                y = *b - l * y;
                *b = y;
            }
            let mut y = T::splat(0.0);
            for (b, &u) in rest[1..].iter_mut().zip(&upper[k + 1..]).rev() {
                y = *b - u * y;
                *b = y;
            }
        }
        for col in cols.iter_mut() {
            let (above, rest) = col.split_at_mut(k);
            let (middle, below) = rest.split_at_mut(1);
            let y_above = above.last().map_or(T::splat(0.0), |&y| lower[k] * y);
            let y_below = below.first().map_or(T::splat(0.0), |&y| upper[k] * y);
            let x_k = (middle[0] - y_above - y_below) * inv[k];
            middle[0] = x_k;
            let mut x = x_k;
            for ((b, &inv), &l) in above.iter_mut().zip(inv).zip(&lower[1..]).rev() {
                x = *b * inv - l * x;
                *b = x;
            }
            let mut x = x_k;
            for ((b, &inv), &u) in below.iter_mut().zip(&inv[k + 1..]).zip(&upper[k..]) {
                x = *b * inv - u * x;
                *b = x;
            }
        }
    }
}

/// Banded $`LDL^\top`$ (square-root-free Cholesky): $`L`$ unit lower triangular with
/// half-bandwidth p, $`D`$ diagonal.
///
/// Both the factorisation and the substitutions are latency-bound: each row waits for the
/// one before. $`LDL^\top`$ keeps the square root off that chain ($`LL^\top`$ has a square root
/// and a division per row on it; here a division, and none in the substitutions), the
/// substitutions add the newest unknown last, and several right-hand sides are swept
/// together, row by row, so that their independent chains overlap. Half-bandwidth 5, that of
/// Backward Euler's 3n×3n matrix of a rope, is dispatched as a constant so that its loops
/// unroll.
#[derive(Debug, Clone)]
pub struct BandedLdlt {
    n: usize,
    p: usize,
    /// (slot in the matrix's values, index in `band`) of every stored entry on or below the
    /// diagonal, so that refactoring copies without searching.
    lower: Vec<(usize, usize)>,
    /// Row i of the matrix is row i + p here (p zero rows first, so that every row has p
    /// entries left of its diagonal): $`L_{i,i-p}, \dots, L_{i,i-1}, d_i`$, zero left of
    /// column 0.
    band: Vec<f64>,
    /// $`1/d_i`$ at i + p (zero before): the substitutions multiply, a division per row would
    /// lengthen their chain.
    inverse_diagonal: Vec<f64>,
}

impl BandedLdlt {
    /// Factors `a` with half-bandwidth p = `a.bandwidth()`. [`Factorization`] picks it up to
    /// [`BANDED_MAX_BANDWIDTH`]; called directly it takes any p (its storage is $`(n + p)(p + 1)`$
    /// values), for a solve that must stay scalar and deterministic (the sheet's equilibrium).
    pub fn new(a: &SymmetricMatrix) -> Result<Self> {
        let p = a.bandwidth();
        let w = p + 1;
        let lower = (0..a.dim())
            .flat_map(|i| {
                a.row_slots(i)
                    .filter(move |&(_, j)| j <= i)
                    .map(move |(slot, j)| (slot, (i + p) * w + p + j - i))
            })
            .collect();
        let mut f = Self {
            n: a.dim(),
            p,
            lower,
            band: vec![0.0; (a.dim() + p) * w],
            inverse_diagonal: vec![0.0; a.dim() + p],
        };
        f.refactor(a)?;
        Ok(f)
    }

    /// Factors new values of a matrix with the pattern of the one this was built from.
    pub fn refactor(&mut self, a: &SymmetricMatrix) -> Result<()> {
        debug_assert_eq!(a.dim(), self.n);
        self.band.fill(0.0);
        let values = a.values();
        for &(slot, k) in &self.lower {
            self.band[k] = values[slot];
        }
        let mut t = [0.0; BANDED_MAX_BANDWIDTH];
        match self.p {
            5 => self.factor(5, &mut t),
            p if p <= BANDED_MAX_BANDWIDTH => self.factor(p, &mut t),
            p => self.factor(p, &mut vec![0.0; p]),
        }
    }

    /// Row by row: $`t_j = a_{ij} - \sum_{k<j} t_k L_{jk}`$ (so $`t_k = L_{ik} d_k`$),
    /// $`L_{ij} = t_j / d_j`$, $`d_i = a_{ii} - \sum_{k<i} t_k L_{ik}`$. The zero rows and
    /// columns before the matrix give every row the same p steps, adding exact zeros.
    /// `t` (at least p long) holds $`t_m = L_{ik} d_k`$ for the columns $`k = i - p + m`$ of the
    /// current row i.
    #[inline(always)]
    fn factor(&mut self, p: usize, t: &mut [f64]) -> Result<()> {
        let w = p + 1;
        for i in 0..self.n {
            // Rows before i are final; row i holds A's entries until overwritten.
            let (done, rest) = self.band.split_at_mut((i + p) * w);
            let (l_i, a_ii) = rest[..w].split_at_mut(p);
            for m in 0..p {
                // Row j = i - p + m is stored at i + m; its column i - p + q at p - m + q.
                let l_j = &done[(i + m) * w + p - m..(i + m) * w + p];
                let mut s = l_i[m];
                for (t_q, l_jq) in t[..m].iter().zip(l_j) {
                    s -= t_q * l_jq;
                }
                t[m] = s;
                l_i[m] = s * self.inverse_diagonal[i + m];
            }
            let mut d = a_ii[0];
            for (t_q, l_iq) in t[..p].iter().zip(&*l_i) {
                d -= t_q * l_iq;
            }
            self.inverse_diagonal[i + p] = inverse_pivot(i, d)?;
            a_ii[0] = d;
        }
        Ok(())
    }

    /// $`L y = b`$, $`D z = y`$, $`L^\top x = z`$ for `ncols` right-hand sides.
    pub fn solve_in_place(&self, b: &mut [f64], ncols: usize) {
        let b = &mut b[..self.n * ncols];
        match ncols {
            3 => self.solve_together(columns::<_, 3>(b, self.n)),
            _ => {
                for col in b.chunks_exact_mut(self.n) {
                    self.solve_together([col]);
                }
            }
        }
    }

    #[inline]
    fn solve_together<const C: usize>(&self, mut cols: [&mut [f64]; C]) {
        match self.p {
            5 => self.solve_banded(&mut cols, 5),
            p => self.solve_banded(&mut cols, p),
        }
    }

    /// Row i of $`L`$ holds columns i-p..i-1; column i of $`L^\top`$ is read down the rows below
    /// i, farthest first.
    #[inline(always)]
    fn solve_banded<const C: usize>(&self, cols: &mut [&mut [f64]; C], p: usize) {
        let n = self.n;
        let w = p + 1;
        for i in 0..n {
            let k0 = i.saturating_sub(p);
            let l_i = &self.band[(i + p) * w + p + k0 - i..(i + p) * w + p];
            for col in cols.iter_mut() {
                let (y, rest) = col.split_at_mut(i);
                // Ascending, so that the newest unknown y_{i-1} comes last.
                let mut s = -0.0;
                for (l_ik, y_k) in l_i.iter().zip(&y[k0..]) {
                    s += l_ik * y_k;
                }
                rest[0] -= s;
            }
        }
        for i in (0..n).rev() {
            let k1 = (i + p + 1).min(n);
            let inv = self.inverse_diagonal[i + p];
            for col in cols.iter_mut() {
                let (z, x) = col.split_at_mut(i + 1);
                // Descending, so that the newest unknown x_{i+1} comes last.
                let mut s = -0.0;
                for (k, x_k) in (i + 1..k1).zip(&x[..k1 - i - 1]).rev() {
                    s += self.band[(k + p) * w + p + i - k] * x_k;
                }
                z[i] = z[i] * inv - s;
            }
        }
    }
}

/// faer's sparse $`LL^\top`$ with its fill-reducing ordering (approximate minimum degree),
/// simplicial or supernodal, through its low-level interface so that the factor's values are
/// ours to read.
///
/// Three right-hand sides (Liu's and ADMM's coordinates) on a simplicial factor are solved by
/// `SparseCholesky::solve_three`, not by faer: faer sweeps the three columns of the column-major
/// right-hand side, so every entry of $`L`$ touches three cache lines n values apart, and it
/// permutes through a fresh buffer each solve; interleaving the coordinates makes it one line
/// and a reused buffer, and the backward substitution sums in four partial sums: 1.6 ms to
/// 0.65 ms on the 100 × 100 sheet (`make timing`).
#[derive(Debug, Clone)]
pub struct SparseCholesky {
    n: usize,
    col_ptr: Vec<usize>,
    row_idx: Vec<usize>,
    symbolic: std::sync::Arc<SymbolicCholesky<usize>>,
    /// The values of $`L`$, in the layout of `symbolic`.
    values: Vec<f64>,
    /// The simplicial factor's structure, for [`Self::solve_three`]; `None` for a supernodal one.
    columns: Option<SimplicialColumns>,
}

/// A simplicial factor's structure in the form [`SparseCholesky::solve_three`] reads: column j
/// of $`L`$ is `values[col_ptr[j]..col_ptr[j + 1]]`, its diagonal first, at rows `row`.
#[derive(Debug, Clone)]
struct SimplicialColumns {
    col_ptr: Vec<usize>,
    row: Vec<u32>,
    /// Row i of the permuted system is row `permutation[i]` of the matrix.
    permutation: Vec<u32>,
    /// $`1/L_{jj}`$, refreshed by every factorisation.
    inverse_diagonal: Vec<f64>,
}

impl SimplicialColumns {
    /// The structure of `symbolic` if it is simplicial, each column's diagonal first, and the
    /// dimension fits 32-bit rows.
    fn new(symbolic: &SymbolicCholesky<usize>) -> Option<Self> {
        let SymbolicCholeskyRaw::Simplicial(simplicial) = symbolic.raw() else {
            return None;
        };
        let factor = simplicial.factor();
        let n = factor.ncols();
        let row: Vec<u32> = factor
            .row_idx()
            .iter()
            .map(|&i| u32::try_from(i).ok())
            .collect::<Option<_>>()?;
        let col_ptr = factor.col_ptr().to_vec();
        if (0..n).any(|j| col_ptr[j] == col_ptr[j + 1] || row[col_ptr[j]] as usize != j) {
            return None;
        }
        let permutation = match symbolic.perm() {
            Some(perm) => perm.arrays().0.iter().map(|&i| i as u32).collect(),
            None => (0..n as u32).collect(),
        };
        Some(Self {
            col_ptr,
            row,
            permutation,
            inverse_diagonal: vec![0.0; n],
        })
    }
}

thread_local! {
    /// The interleaved right-hand sides of [`SparseCholesky::solve_three`], reused.
    static INTERLEAVED: std::cell::RefCell<Vec<[f64; 3]>> = const { std::cell::RefCell::new(Vec::new()) };
}

impl SparseCholesky {
    /// Symbolic analysis (fill-reducing ordering) and a first numeric factorisation, simplicial
    /// or supernodal as faer's heuristic chooses (supernodal for large, dense-enough factors:
    /// its dense kernels factor them fastest).
    pub fn new(a: &SymmetricMatrix) -> Result<Self> {
        Self::with_threshold(a, SupernodalThreshold::default())
    }

    /// [`Self::new`] with the simplicial factor whatever the size: slower to factor than a
    /// supernodal one past some thousands of unknowns, but solved for three right-hand sides by
    /// `SparseCholesky::solve_three`, several times faster than faer's supernodal solve on the sheet
    /// (`make timing`), and by scalar loops only.
    pub fn simplicial(a: &SymmetricMatrix) -> Result<Self> {
        Self::with_threshold(a, SupernodalThreshold::FORCE_SIMPLICIAL)
    }

    fn with_threshold(a: &SymmetricMatrix, threshold: SupernodalThreshold) -> Result<Self> {
        let col_ptr = a.row_ptr.clone();
        let row_idx = a.col_idx.clone();
        let pattern = SymbolicSparseColMatRef::new_checked(a.n, a.n, &col_ptr, None, &row_idx);
        let params = CholeskySymbolicParams {
            supernodal_flop_ratio_threshold: threshold,
            ..Default::default()
        };
        let symbolic =
            factorize_symbolic_cholesky(pattern, Side::Lower, Default::default(), params)
                .map_err(|e| Error::Input(format!("sparse Cholesky analysis failed: {e:?}")))?;
        let mut f = Self {
            n: a.n,
            values: vec![0.0; symbolic.len_val()],
            columns: SimplicialColumns::new(&symbolic),
            col_ptr,
            row_idx,
            symbolic: std::sync::Arc::new(symbolic),
        };
        f.refactor(a)?;
        Ok(f)
    }

    /// Numeric refactorisation with the kept symbolic analysis.
    pub fn refactor(&mut self, a: &SymmetricMatrix) -> Result<()> {
        let pattern = SymbolicSparseColMatRef::new_checked(
            self.n,
            self.n,
            &self.col_ptr,
            None,
            &self.row_idx,
        );
        let mut scratch = MemBuffer::new(
            self.symbolic
                .factorize_numeric_llt_scratch::<f64>(Par::Seq, Default::default()),
        );
        self.symbolic
            .factorize_numeric_llt(
                &mut self.values,
                SparseColMatRef::new(pattern, &a.values),
                Side::Lower,
                Default::default(),
                Par::Seq,
                MemStack::new(&mut scratch),
                Default::default(),
            )
            // The pivot's index is in the fill-reducing order: meaningless to the caller.
            .map_err(|_| not_positive_definite(usize::MAX, f64::NAN))?;
        if let Some(columns) = &mut self.columns {
            for (inv, &k) in columns.inverse_diagonal.iter_mut().zip(&columns.col_ptr) {
                *inv = 1.0 / self.values[k];
            }
        }
        Ok(())
    }

    /// Solves all right-hand sides at once (the three coordinates of Liu and ADMM together).
    pub fn solve_in_place(&self, b: &mut [f64], ncols: usize) {
        if let (3, Some(columns)) = (ncols, &self.columns) {
            return self.solve_three(columns, &mut b[..3 * self.n]);
        }
        let rhs = MatMut::from_column_major_slice_mut(&mut b[..self.n * ncols], self.n, ncols);
        let mut scratch =
            MemBuffer::new(self.symbolic.solve_in_place_scratch::<f64>(ncols, Par::Seq));
        LltRef::new(&self.symbolic, &self.values).solve_in_place_with_conj(
            Conj::No,
            rhs,
            Par::Seq,
            MemStack::new(&mut scratch),
        );
    }

    /// $`L y = P b`$ column by column (each column of $`L`$ scatters into the rows below),
    /// then $`L^\top z = y`$ (each row gathers), $`x = P^\top z`$, for the three columns of `b`
    /// interleaved: node i's three coordinates side by side.
    fn solve_three(&self, s: &SimplicialColumns, b: &mut [f64]) {
        let n = self.n;
        INTERLEAVED.with(|cell| {
            let mut y = cell.borrow_mut();
            y.resize(n, [0.0; 3]);
            for (y, &p) in y.iter_mut().zip(&s.permutation) {
                let p = p as usize;
                *y = [b[p], b[n + p], b[2 * n + p]];
            }
            for j in 0..n {
                let (k0, k1) = (s.col_ptr[j] + 1, s.col_ptr[j + 1]);
                let d = s.inverse_diagonal[j];
                let yj = y[j].map(|v| v * d);
                y[j] = yj;
                for (&i, &l) in s.row[k0..k1].iter().zip(&self.values[k0..k1]) {
                    let yi = &mut y[i as usize];
                    for c in 0..3 {
                        yi[c] -= l * yj[c];
                    }
                }
            }
            for j in (0..n).rev() {
                let (k0, k1) = (s.col_ptr[j] + 1, s.col_ptr[j + 1]);
                let sum = gather_three(&s.row[k0..k1], &self.values[k0..k1], &y);
                let d = s.inverse_diagonal[j];
                let z = y[j];
                y[j] = std::array::from_fn(|c| (z[c] - sum[c]) * d);
            }
            for (y, &p) in y.iter().zip(&s.permutation) {
                let p = p as usize;
                [b[p], b[n + p], b[2 * n + p]] = *y;
            }
        });
    }
}

/// $`\sum_k l_k\,y_{i_k}`$ for the three coordinates, in four interleaved partial sums: one
/// running sum would make every addition wait for the one before (a chain as long as the
/// column), four let the additions of consecutive entries overlap.
#[inline]
fn gather_three(rows: &[u32], values: &[f64], y: &[[f64; 3]]) -> [f64; 3] {
    let mut partial = [[0.0; 3]; 4];
    let (rows4, values4) = (rows.chunks_exact(4), values.chunks_exact(4));
    let (rows_left, values_left) = (rows4.remainder(), values4.remainder());
    for (i, l) in rows4.zip(values4) {
        for k in 0..4 {
            let yi = y[i[k] as usize];
            for c in 0..3 {
                partial[k][c] += l[k] * yi[c];
            }
        }
    }
    for (k, (&i, &l)) in rows_left.iter().zip(values_left).enumerate() {
        let yi = y[i as usize];
        for c in 0..3 {
            partial[k][c] += l * yi[c];
        }
    }
    std::array::from_fn(|c| (partial[0][c] + partial[1][c]) + (partial[2][c] + partial[3][c]))
}

fn not_positive_definite(row: usize, pivot: f64) -> Error {
    let at = if row == usize::MAX {
        String::from("a pivot")
    } else {
        format!("row {row} (pivot {pivot:e})")
    };
    Error::NotConverged {
        what: "Cholesky factorisation".into(),
        detail: format!("the matrix is not positive definite at {at}"),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A 1D chain Laplacian plus a diagonal, solved by both factorisations against a direct check.
    fn chain(n: usize, block: usize) -> SymmetricMatrix {
        let edges: Vec<_> = (0..n - 1).map(|i| (i, i + 1)).collect();
        let mut a = SymmetricMatrix::from_node_graph(n, block, &edges);
        for &(i, j) in &edges {
            for c in 0..block {
                let (p, q) = (i * block + c, j * block + c);
                a.add(p, p, 2.0);
                a.add(q, q, 2.0);
                a.add(p, q, -2.0);
                a.add(q, p, -2.0);
            }
        }
        for i in 0..n * block {
            a.add(i, i, 1.0 + i as f64 * 0.01);
        }
        a
    }

    /// Solves `ncols` right-hand sides with `f` and compares with the known solutions.
    fn check_solve(a: &SymmetricMatrix, f: &Factorization, ncols: usize) {
        let n = a.dim();
        let x: Vec<f64> = (0..ncols * n).map(|i| (i as f64 * 0.37).sin()).collect();
        let mut b = vec![0.0; ncols * n];
        for (x, b) in x.chunks_exact(n).zip(b.chunks_exact_mut(n)) {
            a.mul_vec(x, b);
        }
        f.solve_in_place(&mut b, ncols);
        for (xi, bi) in x.iter().zip(&b) {
            assert!((xi - bi).abs() < 1e-12, "{xi} vs {bi}");
        }
    }

    /// The pattern of `system`'s springs with `block` unknowns per node, made positive
    /// definite by a dominant diagonal, and the factorisation [`Factorization::new`] picks.
    fn factorization_of(
        system: &crate::model::system::MassSpringSystem,
        block: usize,
    ) -> Factorization {
        let edges: Vec<_> = system.springs().iter().map(|s| (s.a, s.b)).collect();
        let mut a = SymmetricMatrix::from_node_graph(system.len(), block, &edges);
        for &(i, j) in &edges {
            for c in 0..block {
                let (p, q) = (i * block + c, j * block + c);
                a.add(p, p, 2.0);
                a.add(q, q, 2.0);
                a.add(p, q, -1.0);
                a.add(q, p, -1.0);
            }
        }
        for i in 0..a.dim() {
            a.add(i, i, 1.0);
        }
        Factorization::new(&a).unwrap()
    }

    /// Determinism across CPUs: every solve of the rope and of the 10×10 sheet runs on this
    /// crate's scalar factorisations, never on faer's run-time dispatched kernels.
    #[test]
    fn the_rope_and_the_sheet_never_reach_faer() {
        use crate::model::scene::{thesis_rope, SheetParams, SheetSupport, SHEET_NODES_PER_SIDE};
        let rope = thesis_rope(1e3).unwrap();
        // Liu 2013 and ADMM-PD: one unknown per node; Backward Euler: three.
        assert!(matches!(
            factorization_of(&rope, 1),
            Factorization::Tridiagonal(_)
        ));
        assert!(matches!(
            factorization_of(&rope, 3),
            Factorization::Banded(_)
        ));
        for support in [SheetSupport::FourCorners, SheetSupport::TwoCorners] {
            let sheet = SheetParams::spec(SHEET_NODES_PER_SIDE, 1e3)
                .with_support(support)
                .build()
                .unwrap();
            for block in [1, 3] {
                assert!(
                    matches!(factorization_of(&sheet, block), Factorization::Banded(_)),
                    "{SHEET_NODES_PER_SIDE}×{SHEET_NODES_PER_SIDE} sheet, {block} unknowns per node"
                );
            }
        }
        // Past the threshold, faer: a 15×15 sheet with three unknowns per node.
        let wide = SheetParams::spec(15, 1e3).build().unwrap();
        assert!(matches!(
            factorization_of(&wide, 3),
            Factorization::Sparse(_)
        ));
    }

    #[test]
    fn banded_and_sparse_solve_the_same_system() {
        for block in [2, 3] {
            let a = chain(40, block);
            assert_eq!(a.bandwidth(), 2 * block - 1);
            let banded = Factorization::new(&a).unwrap();
            assert!(matches!(banded, Factorization::Banded(_)));
            let sparse = Factorization::Sparse(SparseCholesky::new(&a).unwrap());
            for ncols in 1..=3 {
                check_solve(&a, &banded, ncols);
                check_solve(&a, &sparse, ncols);
            }
        }
    }

    /// Called directly, the banded factorisation takes a bandwidth past the one
    /// [`Factorization`] gives it (its scratch then lives on the heap).
    #[test]
    fn banded_solves_a_wide_band() {
        let a = chain(30, 24);
        assert!(a.bandwidth() > BANDED_MAX_BANDWIDTH);
        let banded = Factorization::Banded(BandedLdlt::new(&a).unwrap());
        let sparse = Factorization::new(&a).unwrap();
        assert!(matches!(sparse, Factorization::Sparse(_)));
        for ncols in 1..=3 {
            check_solve(&a, &banded, ncols);
            check_solve(&a, &sparse, ncols);
        }
    }

    /// The sparse factor's own three-column solve (interleaved, on a simplicial factor with a
    /// fill-reducing permutation) gives what faer's solve gives column by column, on a grid
    /// whose ordering is not the identity.
    #[test]
    fn sparse_three_column_solve_matches_faer() {
        let side = 30;
        let mut edges = Vec::new();
        for i in 0..side {
            for j in 0..side {
                let k = i * side + j;
                if i + 1 < side {
                    edges.push((k, k + side));
                }
                if j + 1 < side {
                    edges.push((k, k + 1));
                }
                if i + 1 < side && j + 1 < side {
                    edges.push((k, k + side + 1));
                }
            }
        }
        let mut a = SymmetricMatrix::from_node_graph(side * side, 1, &edges);
        for &(p, q) in &edges {
            let w = 1.0 + (p as f64 * 0.1).sin().abs();
            a.add(p, p, w);
            a.add(q, q, w);
            a.add(p, q, -w);
            a.add(q, p, -w);
        }
        for i in 0..a.dim() {
            a.add(i, i, 0.01);
        }
        let f = SparseCholesky::new(&a).unwrap();
        let columns = f.columns.as_ref().expect("a simplicial factor");
        assert!(columns
            .permutation
            .iter()
            .enumerate()
            .any(|(i, &p)| p as usize != i));
        let sparse = Factorization::Sparse(f.clone());
        check_solve(&a, &sparse, 3);
        let n = a.dim();
        let b: Vec<f64> = (0..3 * n).map(|i| (i as f64 * 0.71).cos()).collect();
        let mut together = b.clone();
        f.solve_in_place(&mut together, 3);
        for (c, column) in b.chunks_exact(n).enumerate() {
            let mut alone = column.to_vec();
            f.solve_in_place(&mut alone, 1);
            for (x, y) in alone.iter().zip(&together[c * n..(c + 1) * n]) {
                assert!((x - y).abs() <= 1e-10 * x.abs().max(1.0), "{x} vs {y}");
            }
        }
    }

    /// The twisted factorisation meets in the middle row: chains of every small length (odd,
    /// even, one row) and a long one, against the banded and sparse solves of the same matrix.
    #[test]
    fn tridiagonal_solves_chains_of_any_length() {
        for n in [1, 2, 3, 4, 5, 10, 41] {
            let a = if n == 1 {
                let mut a = SymmetricMatrix::from_node_graph(1, 1, &[]);
                a.add(0, 0, 3.0);
                a
            } else {
                chain(n, 1)
            };
            let twisted = Factorization::new(&a).unwrap();
            assert!(matches!(twisted, Factorization::Tridiagonal(_)), "n = {n}");
            let banded = Factorization::Banded(BandedLdlt::new(&a).unwrap());
            let sparse = Factorization::Sparse(SparseCholesky::new(&a).unwrap());
            for ncols in 1..=3 {
                check_solve(&a, &twisted, ncols);
                check_solve(&a, &banded, ncols);
                check_solve(&a, &sparse, ncols);
            }
        }
    }

    /// A refactorisation takes the new values (the pattern's analysis is kept).
    #[test]
    fn refactoring_solves_the_new_matrix() {
        for block in [1, 3] {
            let mut a = chain(12, block);
            let mut f = Factorization::new(&a).unwrap();
            for i in 0..a.dim() {
                a.add(i, i, 0.5 * i as f64);
            }
            a.add(1, 0, -0.25);
            a.add(0, 1, -0.25);
            f.refactor(&a).unwrap();
            check_solve(&a, &f, 3);
        }
    }

    #[test]
    fn indefinite_matrix_is_reported_not_solved() {
        for block in [1, 3] {
            let mut a = chain(5, block);
            a.add(2, 2, -100.0);
            let err = Factorization::new(&a).unwrap_err();
            assert!(err.to_string().contains("not positive definite"), "{err}");
            assert!(BandedLdlt::new(&a).is_err());
            assert!(SparseCholesky::new(&a).is_err());
        }
        // A pivot that is only reached from below (the twisted factorisation's other half).
        let mut a = chain(6, 1);
        a.add(5, 5, -100.0);
        assert!(Factorization::new(&a).is_err());
    }
}
