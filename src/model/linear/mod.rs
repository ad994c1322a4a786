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

use crate::error::Result;

mod banded;
mod node;
mod pivot;
mod sparse;
mod symmetric;
mod tridiagonal;

pub use banded::{BandedLdlt, BANDED_MAX_BANDWIDTH};
pub use node::Node;
pub use sparse::SparseCholesky;
pub use symmetric::SymmetricMatrix;
pub use tridiagonal::TwistedTridiagonal;

thread_local! {
    /// The column-major copy of [`Factorization::solve_nodes`]'s right-hand sides, reused.
    static COLUMNS: std::cell::RefCell<Vec<f64>> = const { std::cell::RefCell::new(Vec::new()) };
}

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

    /// The order in which [`Self::solve_nodes`] takes the nodes: row q is node `order[q]`
    /// (a sparse factor's fill-reducing ordering); None: the nodes' own order.
    pub fn node_order(&self) -> Option<&[u32]> {
        match self {
            Self::Sparse(f) => f.node_order(),
            _ => None,
        }
    }

    /// Solves $`A x = b`$ in place for the three coordinates of each node, held node by node
    /// in [`Self::node_order`]: on a sparse factor its substitutions alone, otherwise the
    /// column-major solve of [`Self::solve_in_place`] between two copies (the same
    /// arithmetic, column by column).
    pub fn solve_nodes(&self, y: &mut [Node]) {
        if let Self::Sparse(f) = self {
            if f.solve_nodes_in_order(y).is_some() {
                return;
            }
        }
        COLUMNS.with(|cell| {
            let mut columns = cell.borrow_mut();
            let n = y.len();
            columns.resize(3 * n, 0.0);
            for (i, node) in y.iter().enumerate() {
                for c in 0..3 {
                    columns[c * n + i] = node.0[c];
                }
            }
            self.solve_in_place(&mut columns, 3);
            for (i, node) in y.iter_mut().enumerate() {
                for c in 0..3 {
                    node.0[c] = columns[c * n + i];
                }
            }
        });
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
        let panels = f.panels.as_ref().expect("a simplicial factor");
        assert!(panels
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

    /// A positive definite matrix of `n` unknowns with an irregular pattern: random edges with
    /// unequal weights, and a small unequal diagonal.
    fn irregular(n: usize) -> SymmetricMatrix {
        let mut seed = 12345_u64;
        let mut next = move |m: usize| {
            seed = seed
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            (seed >> 33) as usize % m
        };
        let edges: Vec<_> = (0..3 * n)
            .map(|_| (next(n), next(n)))
            .filter(|(p, q)| p != q)
            .collect();
        let mut a = SymmetricMatrix::from_node_graph(n, 1, &edges);
        for &(p, q) in &edges {
            let w = 0.5 + next(1000) as f64 * 1e-3;
            a.add(p, p, w);
            a.add(q, q, w);
            a.add(p, q, -w);
            a.add(q, p, -w);
        }
        for i in 0..n {
            a.add(i, i, 1e-3 * (1 + next(10)) as f64);
        }
        a
    }

    /// $`x = A^{-1} b`$ for three right-hand sides (column after column) by nalgebra's dense
    /// Cholesky: an oracle that shares no code with faer or [`SparseCholesky`].
    fn dense_solve(a: &SymmetricMatrix, b: &[f64]) -> Vec<f64> {
        let n = a.dim();
        let dense = nalgebra::DMatrix::from_fn(n, n, |i, j| a.get(i, j));
        let cholesky = dense.cholesky().expect("positive definite");
        let rhs = nalgebra::DMatrix::from_column_slice(n, 3, b);
        cholesky.solve(&rhs).as_slice().to_vec()
    }

    /// The three-column solve of a simplicial factor ([`SparseCholesky::solve_three`], the one
    /// Liu's and ADMM's large sheets use, in panels of one to four columns) against a dense
    /// Cholesky solve: on Liu's matrix
    /// $`M + dt^2 L`$ of a 20 × 20 sheet at k = 1e6 N/m, dt = 0.01 s, and on a constructed
    /// matrix with an irregular pattern (random edges, unequal weights), each as built and
    /// refactored. (Fails with the panels' values left as the first factorisation's.)
    #[test]
    fn sparse_three_column_solve_matches_a_dense_solve() {
        use crate::model::scene::SheetParams;
        let sheet = SheetParams::spec(20, 1e6).build().unwrap();
        let edges: Vec<_> = sheet.springs().iter().map(|s| (s.a, s.b)).collect();
        let mut liu = SymmetricMatrix::from_node_graph(sheet.len(), 1, &edges);
        for (i, node) in sheet.nodes().iter().enumerate() {
            liu.add(i, i, node.mass);
        }
        for s in sheet.springs() {
            let w = 1e-4 * s.stiffness;
            liu.add(s.a, s.a, w);
            liu.add(s.b, s.b, w);
            liu.add(s.a, s.b, -w);
            liu.add(s.b, s.a, -w);
        }
        for (mut a, widths) in [(liu, 1..=4), (irregular(300), 1..=1)] {
            let mut f = SparseCholesky::simplicial(&a).unwrap();
            let panels = f.panels.as_ref().expect("a simplicial factor");
            // The sheet's factor has panels of every width, each with its own kernel.
            for width in widths {
                assert!(
                    panels.panels.iter().any(|p| p.width == width),
                    "width {width}"
                );
            }
            let n = a.dim();
            let b: Vec<f64> = (0..3 * n).map(|i| (i as f64 * 0.71).cos()).collect();
            // As built, then refactored for a heavier diagonal (another time step's matrix):
            // the panels take the new factor's values.
            for refactored in [false, true] {
                if refactored {
                    for i in 0..n {
                        a.add(i, i, 1.0 + (i % 7) as f64);
                    }
                    f.refactor(&a).unwrap();
                }
                let expected = dense_solve(&a, &b);
                let mut x = b.clone();
                f.solve_in_place(&mut x, 3);
                let scale = expected.iter().fold(0.0_f64, |m, v| m.max(v.abs()));
                for (x, e) in x.iter().zip(&expected) {
                    assert!(
                        (x - e).abs() <= 1e-9 * scale,
                        "{x} vs {e} (n = {n}, refactored: {refactored})"
                    );
                }
            }
        }
    }

    /// The three-column solve gives the same bits whichever vector width runs it (AVX2 where the
    /// CPU has it, the x86-64 baseline otherwise): the substitutions called directly, compiled
    /// for the baseline, against the run-time dispatched ones.
    #[test]
    fn sparse_three_column_solve_has_the_bits_of_the_baseline_build() {
        let a = irregular(300);
        let f = SparseCholesky::simplicial(&a).unwrap();
        let panels = f.panels.as_ref().expect("a simplicial factor");
        let y: Vec<Node> = (0..a.dim())
            .map(|i| Node(std::array::from_fn(|c| ((4 * i + c) as f64 * 0.37).sin())))
            .collect();
        let (mut baseline, mut dispatched) = (y.clone(), y);
        sparse::substitute_three(panels, &mut baseline);
        sparse::solve_three_dispatched(panels, &mut dispatched);
        let lanes = |y: &[Node]| y.iter().flat_map(|node| node.0).collect::<Vec<_>>();
        for (p, q) in lanes(&baseline).iter().zip(lanes(&dispatched)) {
            assert_eq!(p.to_bits(), q.to_bits(), "{p} vs {q}");
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
