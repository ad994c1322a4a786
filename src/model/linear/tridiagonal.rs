//! The rope's prefactored tridiagonal solve (Liu's and ADMM's global step): a twisted
//! factorisation, generic over the lane type so that runs in a batch solve together.

use super::pivot::*;
use super::symmetric::SymmetricMatrix;
use crate::error::{Error, Result};
use crate::model::lanes::{load_values, Lane};

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

/// The row where the two halves of a factorisation of `n` rows meet.
#[inline(always)]
fn middle_row(n: usize) -> usize {
    n.saturating_sub(1) / 2
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
            k: middle_row(n),
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
            3 => self.solve_together(columns::<_, 3>(b, self.n), self.n),
            _ => {
                for col in b.chunks_exact_mut(self.n) {
                    self.solve_together([col], self.n);
                }
            }
        }
    }

    /// [`Self::solve_in_place`] for three right-hand sides of a matrix of `n` rows: a caller
    /// that knows `n` where it is compiled (the batched rope, [`crate::solvers::projective::Chain`])
    /// gets the substitutions unrolled.
    #[inline(always)]
    pub fn solve_three_of_size(&self, b: &mut [T], n: usize) {
        assert_eq!(n, self.n, "the size of the factorisation");
        self.solve_together(columns::<_, 3>(&mut b[..3 * n], n), n);
    }

    /// $`y_i = b_i - L_{i,i-1}y_{i-1}`$ down to k and $`y_i = b_i - U_{i,i+1}y_{i+1}`$ up to k,
    /// $`x_k = (b_k - L_{k,k-1}y_{k-1} - U_{k,k+1}y_{k+1})/\gamma_k`$, then outward
    /// $`x_i = y_i/d_i - L_{i+1,i}x_{i+1}`$ and $`x_i = y_i/e_i - U_{i-1,i}x_{i-1}`$.
    ///
    /// Each substitution is a chain, every row waiting for the one before; the columns' chains
    /// are independent, so they advance in lockstep, row by row, their running values in
    /// registers: the CPU overlaps them instead of running one column's chain after another's
    /// (the rope's Liu iteration in half the time, `make bench`). Every value is computed from
    /// the same operands in the same order as column by column.
    #[inline(always)]
    fn solve_together<const C: usize>(&self, mut cols: [&mut [T]; C], n: usize) {
        let k = middle_row(n);
        let lower = &self.lower[..n];
        let upper = &self.upper[..n];
        let inv = &self.inverse_pivot[..n];
        for col in cols.iter() {
            assert_eq!(col.len(), n);
        }
        let zero = T::splat(0.0);
        let mut y = [zero; C];
        for i in 0..k {
            for (y, col) in y.iter_mut().zip(cols.iter_mut()) {
                *y = col[i] - lower[i] * *y;
                col[i] = *y;
            }
        }
        let mut y = [zero; C];
        for i in (k + 1..n).rev() {
            for (y, col) in y.iter_mut().zip(cols.iter_mut()) {
                *y = col[i] - upper[i] * *y;
                col[i] = *y;
            }
        }
        let mut x_k = [zero; C];
        for (x_k, col) in x_k.iter_mut().zip(cols.iter_mut()) {
            let y_above = if k > 0 { lower[k] * col[k - 1] } else { zero };
            let y_below = if k + 1 < n {
                upper[k] * col[k + 1]
            } else {
                zero
            };
            *x_k = (col[k] - y_above - y_below) * inv[k];
            col[k] = *x_k;
        }
        let mut x = x_k;
        for i in (0..k).rev() {
            for (x, col) in x.iter_mut().zip(cols.iter_mut()) {
                *x = col[i] * inv[i] - lower[i + 1] * *x;
                col[i] = *x;
            }
        }
        let mut x = x_k;
        for i in k + 1..n {
            for (x, col) in x.iter_mut().zip(cols.iter_mut()) {
                *x = col[i] * inv[i] - upper[i - 1] * *x;
                col[i] = *x;
            }
        }
    }
}
