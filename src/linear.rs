//! Sparse symmetric matrices and their prefactored solve, shared by Backward Euler (one
//! factorisation per Newton iteration) and by Liu 2013 and ADMM-PD (one factorisation per
//! scene and time step, Algorithm 3 line 1.4 and Algorithm 4 line 1.5).
//!
//! Two factorisations sit behind [`Factorization`]: a banded Cholesky, chosen when the
//! matrix's bandwidth is small (a chain: 5 for the 3D rope, 1 per coordinate), and faer's
//! sparse supernodal Cholesky with a fill-reducing ordering for everything else (a cloth).
//! The pattern is analysed once; refactoring with new values reuses it.

use crate::error::{Error, Result};
use faer::linalg::solvers::Solve;
use faer::sparse::linalg::solvers::{Llt, SymbolicLlt};
use faer::sparse::{SparseColMatRef, SymbolicSparseColMatRef};
use faer::{MatMut, Side};

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

    /// Sets row `i` and column `i` to zero and the diagonal entry to one.
    pub fn set_identity_row_and_column(&mut self, i: usize) {
        for k in self.row_ptr[i]..self.row_ptr[i + 1] {
            let j = self.col_idx[k];
            self.values[k] = if i == j { 1.0 } else { 0.0 };
            if j != i {
                let kt = self.slot(j, i).expect("symmetric pattern");
                self.values[kt] = 0.0;
            }
        }
    }

    /// $y = A x$.
    pub fn mul_vec(&self, x: &[f64], y: &mut [f64]) {
        for (i, yi) in y.iter_mut().enumerate() {
            *yi = self.row(i).map(|(j, a)| a * x[j]).sum();
        }
    }

    /// Half-bandwidth: the largest |i - j| of a stored entry.
    pub fn bandwidth(&self) -> usize {
        (0..self.n)
            .flat_map(|i| self.col_idx[self.row_ptr[i]..self.row_ptr[i + 1]].iter().map(move |&j| i.abs_diff(j)))
            .max()
            .unwrap_or(0)
    }
}

/// Matrices with a half-bandwidth up to this use the banded factorisation.
pub const BANDED_MAX_BANDWIDTH: usize = 16;

/// A Cholesky factorisation $A = LL^\top$ of a symmetric positive definite matrix, analysed
/// once for its pattern.
#[derive(Debug, Clone)]
pub enum Factorization {
    /// Dense band storage; no fill outside the band.
    Banded(BandedCholesky),
    /// faer's sparse Cholesky with its symbolic analysis kept for refactoring.
    Sparse(SparseCholesky),
}

impl Factorization {
    /// Analyses the pattern of `a` and factors it. Fails if `a` is not positive definite.
    pub fn new(a: &SymmetricMatrix) -> Result<Self> {
        if a.bandwidth() <= BANDED_MAX_BANDWIDTH {
            BandedCholesky::new(a).map(Self::Banded)
        } else {
            SparseCholesky::new(a).map(Self::Sparse)
        }
    }

    /// Factors new values with the same pattern as the matrix this was built from.
    pub fn refactor(&mut self, a: &SymmetricMatrix) -> Result<()> {
        match self {
            Self::Banded(f) => f.refactor(a),
            Self::Sparse(f) => f.refactor(a),
        }
    }

    /// Solves $A x = b$ in place for `ncols` right-hand sides stored one after another
    /// (column-major, each of length n).
    pub fn solve_in_place(&self, b: &mut [f64], ncols: usize) {
        match self {
            Self::Banded(f) => f.solve_in_place(b, ncols),
            Self::Sparse(f) => f.solve_in_place(b, ncols),
        }
    }
}

/// Band Cholesky: row i of $L$ stores columns $i-p..=i$.
#[derive(Debug, Clone)]
pub struct BandedCholesky {
    n: usize,
    p: usize,
    band: Vec<f64>,
    /// $1/L_{ii}$: the substitutions multiply, a division per row would serialise them.
    inverse_diagonal: Vec<f64>,
}

impl BandedCholesky {
    /// Factors `a` with half-bandwidth p = `a.bandwidth()`.
    pub fn new(a: &SymmetricMatrix) -> Result<Self> {
        let mut f = Self {
            n: a.dim(),
            p: a.bandwidth(),
            band: vec![0.0; a.dim() * (a.bandwidth() + 1)],
            inverse_diagonal: vec![0.0; a.dim()],
        };
        f.refactor(a)?;
        Ok(f)
    }

    /// Factors new values of a matrix with the same bandwidth.
    pub fn refactor(&mut self, a: &SymmetricMatrix) -> Result<()> {
        let (n, p) = (self.n, self.p);
        let w = p + 1;
        self.band.fill(0.0);
        for i in 0..n {
            for (j, v) in a.row(i) {
                if j <= i {
                    self.band[i * w + p + j - i] = v;
                }
            }
        }
        for i in 0..n {
            let j0 = i.saturating_sub(p);
            for j in j0..=i {
                let mut s = self.band[i * w + p + j - i];
                let k0 = j0.max(j.saturating_sub(p));
                for k in k0..j {
                    s -= self.band[i * w + p + k - i] * self.band[j * w + p + k - j];
                }
                if j == i {
                    if s.is_nan() || s <= 0.0 || s.is_infinite() {
                        return Err(not_positive_definite(i, s));
                    }
                    self.band[i * w + p] = s.sqrt();
                    self.inverse_diagonal[i] = 1.0 / s.sqrt();
                } else {
                    self.band[i * w + p + j - i] = s * self.inverse_diagonal[j];
                }
            }
        }
        Ok(())
    }

    /// Forward and back substitution for `ncols` right-hand sides.
    pub fn solve_in_place(&self, b: &mut [f64], ncols: usize) {
        let (n, p) = (self.n, self.p);
        let w = p + 1;
        for col in b.chunks_exact_mut(n).take(ncols) {
            // L y = b: row i of L holds columns i-p..i, stored at band[i*w + p - (i - k)].
            for i in 0..n {
                let k0 = i.saturating_sub(p);
                let row = &self.band[i * w + p + k0 - i..i * w + p];
                let s: f64 = row.iter().zip(&col[k0..i]).map(|(l, y)| l * y).sum();
                col[i] = (col[i] - s) * self.inverse_diagonal[i];
            }
            // Lᵀ x = y: column i of Lᵀ is row i of L, read down the rows below i.
            for i in (0..n).rev() {
                let mut s = col[i];
                for (k, x_k) in col.iter().enumerate().take((i + p + 1).min(n)).skip(i + 1) {
                    s -= self.band[k * w + p + i - k] * x_k;
                }
                col[i] = s * self.inverse_diagonal[i];
            }
        }
    }
}

/// faer's sparse $LL^\top$.
#[derive(Debug, Clone)]
pub struct SparseCholesky {
    n: usize,
    col_ptr: Vec<usize>,
    row_idx: Vec<usize>,
    symbolic: SymbolicLlt<usize>,
    numeric: Llt<usize, f64>,
}

impl SparseCholesky {
    /// Symbolic analysis (fill-reducing ordering) and a first numeric factorisation.
    pub fn new(a: &SymmetricMatrix) -> Result<Self> {
        let col_ptr = a.row_ptr.clone();
        let row_idx = a.col_idx.clone();
        let pattern = SymbolicSparseColMatRef::new_checked(a.n, a.n, &col_ptr, None, &row_idx);
        let symbolic = SymbolicLlt::try_new(pattern, Side::Lower)
            .map_err(|e| Error::Input(format!("sparse Cholesky analysis failed: {e:?}")))?;
        let numeric = Self::factor(&symbolic, pattern, &a.values)?;
        Ok(Self {
            n: a.n,
            col_ptr,
            row_idx,
            symbolic,
            numeric,
        })
    }

    fn factor(
        symbolic: &SymbolicLlt<usize>,
        pattern: SymbolicSparseColMatRef<'_, usize>,
        values: &[f64],
    ) -> Result<Llt<usize, f64>> {
        Llt::try_new_with_symbolic(
            symbolic.clone(),
            SparseColMatRef::new(pattern, values),
            Side::Lower,
        )
        .map_err(|e| match e {
            faer::sparse::linalg::LltError::Numeric(_) => not_positive_definite(usize::MAX, f64::NAN),
            other => Error::Input(format!("sparse Cholesky failed: {other:?}")),
        })
    }

    /// Numeric refactorisation with the kept symbolic analysis.
    pub fn refactor(&mut self, a: &SymmetricMatrix) -> Result<()> {
        let pattern =
            SymbolicSparseColMatRef::new_checked(self.n, self.n, &self.col_ptr, None, &self.row_idx);
        self.numeric = Self::factor(&self.symbolic, pattern, &a.values)?;
        Ok(())
    }

    /// Solves all right-hand sides at once (the three coordinates of Liu and ADMM together).
    pub fn solve_in_place(&self, b: &mut [f64], ncols: usize) {
        let rhs = MatMut::from_column_major_slice_mut(&mut b[..self.n * ncols], self.n, ncols);
        self.numeric.solve_in_place(rhs);
    }
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

    fn check_solve(a: &SymmetricMatrix, f: &Factorization) {
        let n = a.dim();
        let x: Vec<f64> = (0..2 * n).map(|i| (i as f64 * 0.37).sin()).collect();
        let mut b = vec![0.0; 2 * n];
        a.mul_vec(&x[..n], &mut b[..n]);
        a.mul_vec(&x[n..], &mut b[n..]);
        f.solve_in_place(&mut b, 2);
        for (xi, bi) in x.iter().zip(&b) {
            assert!((xi - bi).abs() < 1e-12, "{xi} vs {bi}");
        }
    }

    #[test]
    fn banded_and_sparse_solve_the_same_system() {
        let a = chain(40, 3);
        assert_eq!(a.bandwidth(), 5);
        let banded = Factorization::new(&a).unwrap();
        assert!(matches!(banded, Factorization::Banded(_)));
        check_solve(&a, &banded);
        let sparse = Factorization::Sparse(SparseCholesky::new(&a).unwrap());
        check_solve(&a, &sparse);
    }

    #[test]
    fn indefinite_matrix_is_reported_not_solved() {
        let mut a = chain(5, 1);
        a.add(2, 2, -100.0);
        let err = Factorization::new(&a).unwrap_err();
        assert!(err.to_string().contains("not positive definite"), "{err}");
        assert!(SparseCholesky::new(&a).is_err());
    }
}
