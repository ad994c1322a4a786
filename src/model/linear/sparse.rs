//! The sparse Cholesky factorisation of the larger sheets (simplicial, supernodes by column
//! groups), with three right-hand sides solved together.

use super::pivot::*;
use super::symmetric::SymmetricMatrix;
use crate::error::{Error, Result};
use faer::dyn_stack::{MemBuffer, MemStack};
use faer::sparse::linalg::cholesky::{
    factorize_symbolic_cholesky, CholeskySymbolicParams, LltRef, SymbolicCholesky,
    SymbolicCholeskyRaw,
};
use faer::sparse::linalg::SupernodalThreshold;
use faer::sparse::{SparseColMatRef, SymbolicSparseColMatRef};
use faer::{Conj, MatMut, Par, Side};

/// faer's sparse $`LL^\top`$ with its fill-reducing ordering (approximate minimum degree),
/// simplicial or supernodal, through its low-level interface so that the factor's values are
/// ours to read.
///
/// Three right-hand sides (Liu's and ADMM's coordinates) on a simplicial factor are solved by
/// `SparseCholesky::solve_three`, not by faer: faer sweeps the three columns of the column-major
/// right-hand side, so every entry of $`L`$ touches three cache lines n values apart, and it
/// permutes through a fresh buffer each solve; interleaving the coordinates makes it one line
/// and a reused buffer, and the backward substitution sums in four partial sums: 1.6 ms to
/// 0.65 ms on the 100 × 100 sheet (`make timing`). Each node's coordinates are padded to four
/// (x, y, z, 0), one 256-bit vector, and the substitutions run in AVX2 registers where the CPU
/// has them (`solve_three_dispatched`, the same bits): the global step 0.89 ms to 0.71 ms of
/// thread CPU on a loaded Xeon (`docs/performance.md`, "The sheet").
#[derive(Debug, Clone)]
pub struct SparseCholesky {
    pub(super) n: usize,
    pub(super) col_ptr: Vec<usize>,
    pub(super) row_idx: Vec<usize>,
    pub(super) symbolic: std::sync::Arc<SymbolicCholesky<usize>>,
    /// The values of $`L`$, in the layout of `symbolic`.
    pub(super) values: Vec<f64>,
    /// The simplicial factor's structure, for [`Self::solve_three`]; `None` for a supernodal one.
    pub(super) columns: Option<SimplicialColumns>,
}

/// A simplicial factor's structure in the form [`SparseCholesky::solve_three`] reads: column j
/// of $`L`$ is `values[col_ptr[j]..col_ptr[j + 1]]`, its diagonal first, at rows `row`.
#[derive(Debug, Clone)]
pub(super) struct SimplicialColumns {
    pub(super) col_ptr: Vec<usize>,
    pub(super) row: Vec<u32>,
    /// Row i of the permuted system is row `permutation[i]` of the matrix.
    pub(super) permutation: Vec<u32>,
    /// $`1/L_{jj}`$, refreshed by every factorisation.
    pub(super) inverse_diagonal: Vec<f64>,
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
    static INTERLEAVED: std::cell::RefCell<Vec<[f64; 4]>> = const { std::cell::RefCell::new(Vec::new()) };
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
    /// (`make timing`), and by this crate's loops only, whose bits do not depend on the CPU.
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
    /// interleaved: node i's three coordinates side by side, and a fourth lane of zeros.
    fn solve_three(&self, s: &SimplicialColumns, b: &mut [f64]) {
        let n = self.n;
        INTERLEAVED.with(|cell| {
            let mut y = cell.borrow_mut();
            y.resize(n, [0.0; 4]);
            for (y, &p) in y.iter_mut().zip(&s.permutation) {
                let p = p as usize;
                *y = [b[p], b[n + p], b[2 * n + p], 0.0];
            }
            solve_three_dispatched(s, &self.values, &mut y);
            for (y, &p) in y.iter().zip(&s.permutation) {
                let p = p as usize;
                [b[p], b[n + p], b[2 * n + p]] = [y[0], y[1], y[2]];
            }
        });
    }
}

/// [`substitute_three`] in AVX2 registers where the CPU has them (a node's four lanes, one
/// 256-bit vector; AVX-512 measured no faster), chosen at run time. The bits do not depend on
/// the choice: each lane adds and multiplies in the same order whatever the vector width, and
/// Rust never fuses a multiplication and an addition into one rounding.
pub(super) fn solve_three_dispatched(s: &SimplicialColumns, values: &[f64], y: &mut [[f64; 4]]) {
    #[cfg(target_arch = "x86_64")]
    if std::is_x86_feature_detected!("avx2") {
        #[target_feature(enable = "avx2")]
        unsafe fn avx2(s: &SimplicialColumns, values: &[f64], y: &mut [[f64; 4]]) {
            substitute_three(s, values, y)
        }
        // SAFETY: the CPU has AVX2, detected above.
        return unsafe { avx2(s, values, y) };
    }
    substitute_three(s, values, y)
}

/// The two substitutions of [`SparseCholesky::solve_three`] on the permuted, interleaved `y`.
#[inline(always)]
pub(super) fn substitute_three(s: &SimplicialColumns, values: &[f64], y: &mut [[f64; 4]]) {
    let n = y.len();
    for j in 0..n {
        let (k0, k1) = (s.col_ptr[j] + 1, s.col_ptr[j + 1]);
        let d = s.inverse_diagonal[j];
        let yj = y[j].map(|v| v * d);
        y[j] = yj;
        for (&i, &l) in s.row[k0..k1].iter().zip(&values[k0..k1]) {
            let yi = &mut y[i as usize];
            for c in 0..4 {
                yi[c] -= l * yj[c];
            }
        }
    }
    for j in (0..n).rev() {
        let (k0, k1) = (s.col_ptr[j] + 1, s.col_ptr[j + 1]);
        let sum = gather_four(&s.row[k0..k1], &values[k0..k1], y);
        let d = s.inverse_diagonal[j];
        let z = y[j];
        y[j] = std::array::from_fn(|c| (z[c] - sum[c]) * d);
    }
}

/// $`\sum_k l_k\,y_{i_k}`$ for the interleaved coordinates, in four interleaved partial sums:
/// one running sum would make every addition wait for the one before (a chain as long as the
/// column), four let the additions of consecutive entries overlap.
#[inline(always)]
fn gather_four(rows: &[u32], values: &[f64], y: &[[f64; 4]]) -> [f64; 4] {
    let mut partial = [[0.0; 4]; 4];
    let (rows4, values4) = (rows.chunks_exact(4), values.chunks_exact(4));
    let (rows_left, values_left) = (rows4.remainder(), values4.remainder());
    for (i, l) in rows4.zip(values4) {
        for k in 0..4 {
            let yi = y[i[k] as usize];
            for c in 0..4 {
                partial[k][c] += l[k] * yi[c];
            }
        }
    }
    for (k, (&i, &l)) in rows_left.iter().zip(values_left).enumerate() {
        let yi = y[i as usize];
        for c in 0..4 {
            partial[k][c] += l * yi[c];
        }
    }
    std::array::from_fn(|c| (partial[0][c] + partial[1][c]) + (partial[2][c] + partial[3][c]))
}
