//! The banded LDLᵀ factorisation of the sheet's matrices (Backward Euler's Newton steps).

use super::pivot::*;
use super::symmetric::SymmetricMatrix;
use crate::error::{Error, Result};
use crate::model::lanes::Lane;

/// Matrices with a half-bandwidth up to this use the banded factorisation, plain scalar code
/// whose results do not depend on the CPU; wider ones go to faer, which picks SIMD kernels at
/// run time. It covers Backward Euler on a 10×10 sheet (3 unknowns per node, springs reaching
/// 11 nodes: half-bandwidth 35), where the band is also the faster: Figure 1's sheet run takes
/// 0.61 s of CPU banded against 0.87 s with faer's sparse Cholesky. A 15×15 sheet (50) is past it.
pub const BANDED_MAX_BANDWIDTH: usize = 40;

/// How many of a row's sums [`BandedLdlt`]'s factorisation advances side by side (its block
/// is written out for four: more were slower, `docs/performance.md`).
const SUMS_TOGETHER: usize = 4;

/// Banded $`LDL^\top`$ (square-root-free Cholesky): $`L`$ unit lower triangular with
/// half-bandwidth p, $`D`$ diagonal.
///
/// Both the factorisation and the substitutions are latency-bound: each row waits for the
/// one before. $`LDL^\top`$ keeps the square root off that chain ($`LL^\top`$ has a square root
/// and a division per row on it; here a division, and none in the substitutions), the
/// substitutions add the newest unknown last, and several right-hand sides are swept
/// together, row by row, so that their independent chains overlap. The half-bandwidths the
/// report factors most are dispatched as constants, so that their loops unroll: 5, that of
/// Backward Euler's 3n×3n matrix of the rope, 35, that of the 10×10 sheet's, and in the
/// substitutions 11, that of the sheet's n×n projective matrix (how often each is called, and
/// what the constants gained: `docs/performance.md`, "Inner loops beside their floors").
///
/// The arithmetic is generic over the lane type ([`crate::model::lanes`]): at `f64` one
/// matrix, in lanes one matrix of the pattern per lane (Backward Euler's batched runs,
/// [`crate::solvers::batch::backward_euler`]), each lane with the bits of its matrix alone.
#[derive(Debug, Clone)]
pub struct BandedLdlt<T = f64> {
    n: usize,
    p: usize,
    /// The stored entries on or below the diagonal, as runs consecutive both in the matrix's
    /// values and in `band` (slot of the first, its index in `band`, length), so that
    /// refactoring copies slices without searching (a row of the rope's matrix is one run).
    lower: Vec<(usize, usize, usize)>,
    /// Row i of the matrix is row i + p here (p zero rows first, so that every row has p
    /// entries left of its diagonal): $`L_{i,i-p}, \dots, L_{i,i-1}, d_i`$, zero left of
    /// column 0.
    band: Vec<T>,
    /// $`1/d_i`$ at i + p (zero before): the substitutions multiply, a division per row would
    /// lengthen their chain.
    inverse_diagonal: Vec<T>,
}

impl BandedLdlt {
    /// Factors `a` with half-bandwidth p = `a.bandwidth()`.
    /// [`Factorization`](super::Factorization) picks it up to [`BANDED_MAX_BANDWIDTH`]; called
    /// directly it takes any p (its storage is $`(n + p)(p + 1)`$ values), for a solve that must
    /// stay scalar and deterministic (the sheet's equilibrium).
    pub fn new(a: &SymmetricMatrix) -> Result<Self> {
        let mut f = Self::for_pattern(a);
        f.refactor(a)?;
        Ok(f)
    }

    /// Factors new values of a matrix with the pattern of the one this was built from.
    pub fn refactor(&mut self, a: &SymmetricMatrix) -> Result<()> {
        debug_assert_eq!(a.dim(), self.n);
        if self.refactor_values(a.values()) {
            return Err(self.not_positive_definite(0));
        }
        Ok(())
    }
}

impl<T: Lane> BandedLdlt<T> {
    /// The factorisation of matrices of `a`'s pattern, with half-bandwidth p = `a.bandwidth()`,
    /// none factored yet ([`Self::refactor_values`]).
    pub fn for_pattern(a: &SymmetricMatrix) -> Self {
        let p = a.bandwidth();
        let w = p + 1;
        let mut lower: Vec<(usize, usize, usize)> = Vec::new();
        for i in 0..a.dim() {
            for (slot, j) in a.row_slots(i).filter(|&(_, j)| j <= i) {
                let k = (i + p) * w + p + j - i;
                match lower.last_mut() {
                    Some((s, b, len)) if *s + *len == slot && *b + *len == k => *len += 1,
                    _ => lower.push((slot, k, 1)),
                }
            }
        }
        let zero = T::splat(0.0);
        Self {
            n: a.dim(),
            p,
            lower,
            band: vec![zero; (a.dim() + p) * w],
            inverse_diagonal: vec![zero; a.dim() + p],
        }
    }

    /// Factors the matrix of the pattern's with `values` (its stored values in pattern order,
    /// as [`SymmetricMatrix::values`] holds them); per lane, whether a pivot was not positive
    /// and finite ([`Self::not_positive_definite`] names the first). A lane whose pivot fails
    /// is factored on, its later values unread; the others are not touched by it.
    pub fn refactor_values(&mut self, values: &[T]) -> T::SimdBool {
        let zero = T::splat(0.0);
        self.band.fill(zero);
        for &(slot, k, len) in &self.lower {
            self.band[k..k + len].copy_from_slice(&values[slot..slot + len]);
        }
        let mut t = [zero; BANDED_MAX_BANDWIDTH];
        match self.p {
            5 => self.factor(5, &mut t),
            35 => self.factor(35, &mut t),
            p if p <= BANDED_MAX_BANDWIDTH => self.factor(p, &mut t),
            p => self.factor(p, &mut vec![zero; p]),
        }
    }

    /// The error for lane `lane`'s first pivot that is not positive and finite (after
    /// [`Self::refactor_values`] said it has one).
    pub fn not_positive_definite(&self, lane: usize) -> Error {
        let (p, w) = (self.p, self.p + 1);
        let pivot = |i: usize| self.band[(i + p) * w + p].extract(lane);
        match (0..self.n).find(|&i| !is_pivot(pivot(i))) {
            Some(i) => not_positive_definite(i, pivot(i)),
            None => not_positive_definite(usize::MAX, f64::NAN),
        }
    }

    /// Row by row: $`t_j = a_{ij} - \sum_{k<j} t_k L_{jk}`$ (so $`t_k = L_{ik} d_k`$),
    /// $`L_{ij} = t_j / d_j`$, $`d_i = a_{ii} - \sum_{k<i} t_k L_{ik}`$. The zero rows and
    /// columns before the matrix give every row the same p steps, adding exact zeros.
    /// `t` (at least p long) holds $`t_m = L_{ik} d_k`$ for the columns $`k = i - p + m`$ of the
    /// current row i.
    ///
    /// The chain from row to row is $`d_{i-1} \to 1/d_{i-1} \to L_{i,i-1} \to d_i`$: its values
    /// stay in registers ($`1/d_{i-1}`$ carried over, $`d_i`$'s terms taken as each
    /// $`L_{ik}`$ is made, in the same ascending order), not stored and read back. Within a
    /// row, the sums $`t_m`$ go in blocks of [`SUMS_TOGETHER`] ([`sums_together`]), the last
    /// fewer; every sum keeps its terms and their order. Returns, per lane, whether a pivot
    /// was not positive and finite: checked without a branch, so that a lane's failure does
    /// not stop the others.
    #[inline(always)]
    fn factor(&mut self, p: usize, t: &mut [T]) -> T::SimdBool {
        let w = p + 1;
        // 1/d of the row before (a zero row's before row 0).
        let mut inverse_before = T::splat(0.0);
        // False in every lane (1 is a pivot).
        let mut failed = !is_pivot(T::splat(1.0));
        let t = &mut t[..p];
        for i in 0..self.n {
            // Rows before i are final; row i holds A's entries until overwritten.
            let (done, rest) = self.band.split_at_mut((i + p) * w);
            let (l_i, a_ii) = rest[..w].split_at_mut(p);
            // Row j = i - p + m is stored at i + m; its column i - p + q at p - m + q.
            let row_j = |m: usize| &done[(i + m) * w + p - m..(i + m) * w + p];
            let mut d = a_ii[0];
            let inverse = |m: usize| {
                if m + 1 == p {
                    inverse_before
                } else {
                    self.inverse_diagonal[i + m]
                }
            };
            let mut m0 = 0;
            while m0 + SUMS_TOGETHER <= p {
                sums_together::<T, SUMS_TOGETHER>(m0, t, l_i, &mut d, row_j, inverse);
                m0 += SUMS_TOGETHER;
            }
            // The last sums, fewer than a block, side by side too.
            match p - m0 {
                3 => sums_together::<T, 3>(m0, t, l_i, &mut d, row_j, inverse),
                2 => sums_together::<T, 2>(m0, t, l_i, &mut d, row_j, inverse),
                1 => sums_together::<T, 1>(m0, t, l_i, &mut d, row_j, inverse),
                _ => {}
            }
            failed = failed | !is_pivot(d);
            inverse_before = T::splat(1.0) / d;
            self.inverse_diagonal[i + p] = inverse_before;
            a_ii[0] = d;
        }
        failed
    }

    /// $`L y = b`$, $`D z = y`$, $`L^\top x = z`$ for `ncols` right-hand sides.
    pub fn solve_in_place(&self, b: &mut [T], ncols: usize) {
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

    #[inline(always)]
    fn solve_together<const C: usize>(&self, mut cols: [&mut [T]; C]) {
        match self.p {
            5 => self.solve_banded(&mut cols, 5),
            11 => self.solve_banded(&mut cols, 11),
            35 => self.solve_banded(&mut cols, 35),
            p => self.solve_banded(&mut cols, p),
        }
    }

    /// Row i of $`L`$ holds columns i-p..i-1; column i of $`L^\top`$ is read down the rows below
    /// i, farthest first. Each sum's last term is the unknown the row before made, carried in
    /// a register (`newest`) rather than stored and read back: that is the chain from row to
    /// row. The first p rows of each sweep have fewer terms; the others have p, a constant
    /// where p is one (the loops unroll).
    #[inline(always)]
    fn solve_banded<const C: usize>(&self, cols: &mut [&mut [T]; C], p: usize) {
        let n = self.n;
        let mut newest = [T::splat(0.0); C];
        for i in 0..p.min(n) {
            self.forward_row(cols, &mut newest, p, i, 0);
        }
        for i in p..n {
            self.forward_row(cols, &mut newest, p, i, i - p);
        }
        for i in (n.saturating_sub(p)..n).rev() {
            self.backward_row(cols, &mut newest, p, i, n);
        }
        for i in (0..n.saturating_sub(p)).rev() {
            self.backward_row(cols, &mut newest, p, i, i + p + 1);
        }
    }

    /// $`y_i = b_i - \sum_{k_0 \le k < i} L_{ik} y_k`$, ascending, so that $`y_{i-1}`$
    /// (`newest`) comes last. The columns' sums advance together, term by term: C
    /// independent chains side by side instead of one column's chain after another's.
    #[inline(always)]
    fn forward_row<const C: usize>(
        &self,
        cols: &mut [&mut [T]; C],
        newest: &mut [T; C],
        p: usize,
        i: usize,
        k0: usize,
    ) {
        let w = p + 1;
        let l_i = &self.band[(i + p) * w + p + k0 - i..(i + p) * w + p];
        let mut s = [T::splat(-0.0); C];
        if let Some((l_newest, l_older)) = l_i.split_last() {
            for (j, l_ik) in l_older.iter().enumerate() {
                for (s, col) in s.iter_mut().zip(cols.iter()) {
                    *s += *l_ik * col[k0 + j];
                }
            }
            for (s, newest) in s.iter_mut().zip(newest.iter()) {
                *s += *l_newest * *newest;
            }
        }
        for ((col, newest), s) in cols.iter_mut().zip(newest).zip(s) {
            *newest = col[i] - s;
            col[i] = *newest;
        }
    }

    /// $`x_i = z_i / d_i - \sum_{i < k < k_1} L_{ki} x_k`$, descending, so that
    /// $`x_{i+1}`$ (`newest`) comes last. $`L_{ki}`$ is stored at $`kp + (p + 2)p + i`$. The
    /// columns' sums advance together, as in [`Self::forward_row`].
    #[inline(always)]
    fn backward_row<const C: usize>(
        &self,
        cols: &mut [&mut [T]; C],
        newest: &mut [T; C],
        p: usize,
        i: usize,
        k1: usize,
    ) {
        let inv = self.inverse_diagonal[i + p];
        let at = |k: usize| k * p + (p + 2) * p + i;
        let mut s = [T::splat(-0.0); C];
        if i + 1 < k1 {
            let column = &self.band[at(i + 1)..=at(k1 - 1)];
            for j in (1..k1 - i - 1).rev() {
                let l_ki = column[j * p];
                for (s, col) in s.iter_mut().zip(cols.iter()) {
                    *s += l_ki * col[i + 1 + j];
                }
            }
            for (s, newest) in s.iter_mut().zip(newest.iter()) {
                *s += column[0] * *newest;
            }
        }
        for ((col, newest), s) in cols.iter_mut().zip(newest).zip(s) {
            *newest = col[i] * inv - s;
            col[i] = *newest;
        }
    }
}

/// Row i's sums $`t_{m_0}, \dots, t_{m_0 + B - 1}`$ (row j = i - p + m is `row_j(m)`, its
/// $`1/d_j`$ `inverse(m)`): first the terms of the columns before the block, side by side (B
/// chains of additions overlapping instead of one), then each sum's terms within the block, in
/// order, and its end ([`finish_sum`]). Every sum keeps its terms and their order.
#[inline(always)]
fn sums_together<'a, T: Lane, const B: usize>(
    m0: usize,
    t: &mut [T],
    l_i: &mut [T],
    d: &mut T,
    row_j: impl Fn(usize) -> &'a [T],
    inverse: impl Fn(usize) -> T,
) {
    let mut s: [T; B] = std::array::from_fn(|b| l_i[m0 + b]);
    let r: [&[T]; B] = std::array::from_fn(|b| row_j(m0 + b));
    for (q, t_q) in t[..m0].iter().enumerate() {
        for (s, r) in s.iter_mut().zip(&r) {
            *s -= *t_q * r[q];
        }
    }
    // The block's finished sums are read back from registers, not from `t`, which has just
    // stored them: two of them loaded from `t` as one vector wait for both stores (a
    // store-forwarding stall, 15 % of the sheet's refactorisation when the compiler paired
    // them so).
    let mut finished = [T::splat(0.0); B];
    for b in 0..B {
        for c in 0..b {
            s[b] -= finished[c] * r[b][m0 + c];
        }
        finished[b] = finish_sum(m0 + b, s[b], inverse(m0 + b), t, l_i, d);
    }
}

/// The end of row i's sum m: $`t_m`$ = `s`, $`L_{im} = t_m / d_j`$ (`inverse_j` $`= 1/d_j`$),
/// and $`L_{im}`$'s term taken off $`d_i`$; returns $`t_m`$.
#[inline(always)]
fn finish_sum<T: Lane>(m: usize, s: T, inverse_j: T, t: &mut [T], l_i: &mut [T], d: &mut T) -> T {
    t[m] = s;
    let l_im = s * inverse_j;
    l_i[m] = l_im;
    *d -= s * l_im;
    s
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::model::scene::{thesis_rope, SheetParams, SHEET_NODES_PER_SIDE};

    /// The pattern of `system`'s springs with three unknowns per node (Backward Euler's): full
    /// symmetric 3×3 blocks of uneven values, made positive definite by a dominant diagonal.
    fn newton_like(system: &crate::model::system::MassSpringSystem) -> SymmetricMatrix {
        let edges: Vec<_> = system.springs().iter().map(|s| (s.a, s.b)).collect();
        let mut a = SymmetricMatrix::from_node_graph(system.len(), 3, &edges);
        for (e, &(i, j)) in edges.iter().enumerate() {
            for r in 0..3 {
                for c in 0..3 {
                    let v = ((e * 9 + r.min(c) * 3 + r.max(c)) as f64 * 0.731).sin() * 0.4;
                    a.add(3 * i + r, 3 * i + c, v);
                    a.add(3 * j + r, 3 * j + c, v);
                    a.add(3 * i + r, 3 * j + c, -v * 0.5);
                    a.add(3 * j + c, 3 * i + r, -v * 0.5);
                }
            }
        }
        for i in 0..a.dim() {
            a.add(i, i, 8.0 + (i as f64 * 0.29).sin());
        }
        a
    }

    /// The row-oriented (left-looking) banded $`LDL^\top`$ written out plainly, the oracle of
    /// [`BandedLdlt`]'s bits: on a dense copy with p zero rows and columns first, row i's
    /// $`t_m`$ one sum after another, then $`d_i`$; every sum in ascending order. Returns
    /// $`L`$ (padded, row-major) and $`1/d`$ (padded).
    fn row_oriented(a: &SymmetricMatrix) -> (Vec<Vec<f64>>, Vec<f64>) {
        let (n, p) = (a.dim(), a.bandwidth());
        let mut l = vec![vec![0.0; n + p]; n + p];
        let mut inverse = vec![0.0; n + p];
        for i in 0..n {
            let mut t = vec![0.0; p];
            for m in 0..p {
                // Column j = i - p + m (padded index i + m).
                let j = i + m;
                let mut s = if j >= p { a.get(i, j - p) } else { 0.0 };
                for q in 0..m {
                    s -= t[q] * l[j][i + q];
                }
                t[m] = s;
                l[i + p][j] = s * inverse[j];
            }
            let mut d = a.get(i, i);
            for q in 0..p {
                d -= t[q] * l[i + p][i + q];
            }
            inverse[i + p] = 1.0 / d;
            l[i + p][i + p] = d;
        }
        (l, inverse)
    }

    /// Every entry of the factor and every solution has the bits of the plain row-oriented
    /// algorithm's, on the rope's Newton matrix (p = 5, the constant dispatch), the 10×10
    /// sheet's (p = 35) and a band past [`BANDED_MAX_BANDWIDTH`] (scratch on the heap): the
    /// lock on any faster factorisation, which must keep every sum's terms and their order.
    /// Fails (checked) with $`d_i`$'s terms taken in descending order, or with the
    /// right-looking product $`(L_{ik} d_k) L_{jk}`$ in place of $`t_k L_{jk}`$; and, on the
    /// registers' version (`620d92a`), with $`L_{ij} = t_j / d_j`$ in place of
    /// $`t_j \cdot (1/d_j)`$, or with the forward substitution's newest unknown taken first;
    /// and with a block's last sum taking its own columns' terms out of order (the blocks of
    /// sums side by side); and, with the columns' sums advanced together, with a term of
    /// column 0 taken for every column.
    #[test]
    fn the_factorisation_has_the_row_oriented_bits() {
        let sheet = SheetParams::spec(SHEET_NODES_PER_SIDE, 1e3)
            .build()
            .unwrap();
        let wide = SheetParams::spec(14, 1e3).build().unwrap();
        for system in [thesis_rope(1e3).unwrap(), sheet, wide] {
            let a = newton_like(&system);
            let (n, p, w) = (a.dim(), a.bandwidth(), a.bandwidth() + 1);
            let f = BandedLdlt::new(&a).unwrap();
            let (l, inverse) = row_oriented(&a);
            for j in 0..n {
                assert_eq!(f.band[(j + p) * w + p].to_bits(), l[j + p][j + p].to_bits());
                assert_eq!(
                    f.inverse_diagonal[j + p].to_bits(),
                    inverse[j + p].to_bits()
                );
                for i in j + 1..(j + w).min(n) {
                    let ours = f.band[(i + p) * w + p + j - i];
                    assert_eq!(
                        ours.to_bits(),
                        l[i + p][j + p].to_bits(),
                        "L[{i}][{j}], p {p}"
                    );
                }
            }
            // The substitutions, as they were: ascending over row i of L, then descending
            // over column i; three different right-hand sides, alone and together.
            let substitutions = |b: &[f64]| {
                let mut x = b.to_vec();
                for i in 0..n {
                    let mut s = -0.0;
                    for k in i.saturating_sub(p)..i {
                        s += l[i + p][k + p] * x[k];
                    }
                    x[i] -= s;
                }
                for i in (0..n).rev() {
                    let mut s = -0.0;
                    for k in (i + 1..(i + p + 1).min(n)).rev() {
                        s += l[k + p][i + p] * x[k];
                    }
                    x[i] = x[i] * inverse[i + p] - s;
                }
                x
            };
            let bits = |x: &[f64]| x.iter().map(|v| v.to_bits()).collect::<Vec<_>>();
            let three: Vec<f64> = (0..3 * n).map(|i| (i as f64 * 0.37).sin()).collect();
            let mut expected = Vec::new();
            for b in three.chunks(n) {
                let mut ours = b.to_vec();
                f.solve_in_place(&mut ours, 1);
                let x = substitutions(b);
                assert_eq!(bits(&ours), bits(&x), "one column, p {p}");
                expected.extend(x);
            }
            let mut together = three.clone();
            f.solve_in_place(&mut together, 3);
            assert_eq!(bits(&together), bits(&expected), "three columns, p {p}");
        }
    }
}
