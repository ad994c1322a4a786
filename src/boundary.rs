//! Fixed nodes imposed on a linear system before its solve (thesis §3.2, Eqs 43-47).
//!
//! Of the three ways §3.2 weighs (overwriting positions after the solve, removing the fixed
//! degrees of freedom, or modifying the system before the solve), the thesis adopts the
//! third: the fixed rows and columns of $A$ become the identity and the right-hand side
//! carries the fixed values, so the free unknowns feel the fixed ones through $b - A u$.
//! This module is the one place that does it; Backward Euler (per Newton iteration),
//! Liu 2013 and ADMM-PD (once per scene and time step) all solve through [`ConstrainedSystem`].

use crate::error::Result;
use crate::linear::{Factorization, SymmetricMatrix};

/// A factored system $Ax = b$ whose fixed unknowns are imposed by Eqs 44-47.
#[derive(Debug, Clone)]
pub struct ConstrainedSystem {
    fixed: Vec<usize>,
    is_fixed: Vec<bool>,
    /// The block $A_2$ of Eq (43): $(i, j, A_{ij})$ for free rows $i$ and fixed columns $j$,
    /// saved before Eq (44) zeroes it, so that Eq (46) can form $A u$.
    coupling: Vec<(usize, usize, f64)>,
    factorization: Factorization,
}

impl ConstrainedSystem {
    /// Eq. (44): $\begin{pmatrix}A_1 & 0\\ 0 & I\end{pmatrix}$ replaces the fixed rows and
    /// columns of `a` (in place), then the result is factored once.
    pub fn new(a: &mut SymmetricMatrix, fixed: &[usize]) -> Result<Self> {
        let mut is_fixed = vec![false; a.dim()];
        for &j in fixed {
            is_fixed[j] = true;
        }
        let mut coupling = Vec::new();
        impose_on_matrix(a, fixed, &is_fixed, &mut coupling);
        Ok(Self {
            fixed: fixed.to_vec(),
            is_fixed,
            coupling,
            factorization: Factorization::new(a)?,
        })
    }

    /// Eq. (44) again for new values of a matrix with the same pattern and fixed set, and a
    /// numeric refactorisation that reuses the pattern's analysis.
    pub fn refactor(&mut self, a: &mut SymmetricMatrix) -> Result<()> {
        impose_on_matrix(a, &self.fixed, &self.is_fixed, &mut self.coupling);
        self.factorization.refactor(a)
    }

    /// Eq. (43): solves $A x = b$ with $x_j = \bar x_j$ on the fixed unknowns, for `ncols`
    /// right-hand sides stored column after column. `x_bar` has the layout of `b` and is
    /// read only at fixed unknowns. The solution overwrites `b`.
    pub fn solve(&self, b: &mut [f64], x_bar: &[f64], ncols: usize) {
        self.impose_on_rhs(b, x_bar, ncols);
        self.factorization.solve_in_place(b, ncols);
    }

    /// Eqs. (45)-(47): with $u = (0, \bar x)$ (Eq 45), $b \leftarrow b - A u$ (Eqs 46-47) on the
    /// free rows, and $b_j = \bar x_j$ on the fixed rows (step 4 of §3.2).
    pub fn impose_on_rhs(&self, b: &mut [f64], x_bar: &[f64], ncols: usize) {
        let n = b.len() / ncols;
        for col in 0..ncols {
            let (b, x_bar) = (&mut b[col * n..(col + 1) * n], &x_bar[col * n..(col + 1) * n]);
            for &(i, j, a_ij) in &self.coupling {
                b[i] -= a_ij * x_bar[j];
            }
            for &j in &self.fixed {
                b[j] = x_bar[j];
            }
        }
    }
}

/// Saves the block $A_2$ (free rows, fixed columns; by symmetry read from the fixed rows) into
/// `coupling`, then replaces the fixed rows and columns by the identity.
fn impose_on_matrix(
    a: &mut SymmetricMatrix,
    fixed: &[usize],
    is_fixed: &[bool],
    coupling: &mut Vec<(usize, usize, f64)>,
) {
    coupling.clear();
    for &j in fixed {
        coupling.extend(
            a.row(j)
                .filter(|&(i, _)| !is_fixed[i])
                .map(|(i, a_ji)| (i, j, a_ji)),
        );
    }
    for &j in fixed {
        a.set_identity_row_and_column(j);
    }
}

/// The unknowns of the fixed nodes, for systems with `block` unknowns per node.
pub fn fixed_unknowns(fixed_nodes: impl Iterator<Item = usize>, block: usize) -> Vec<usize> {
    fixed_nodes
        .flat_map(|i| (0..block).map(move |c| i * block + c))
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The constrained solve equals the solve of the reduced system written out by hand
    /// (the "remove the degrees of freedom" alternative of §3.2).
    #[test]
    fn constrained_solve_matches_eliminated_system() {
        let edges = [(0, 1), (1, 2), (2, 3)];
        let mut a = SymmetricMatrix::from_node_graph(4, 1, &edges);
        let entries = [
            (0, 0, 4.0),
            (1, 1, 5.0),
            (2, 2, 6.0),
            (3, 3, 7.0),
            (0, 1, -1.0),
            (1, 2, -2.0),
            (2, 3, -3.0),
        ];
        for (i, j, v) in entries {
            a.add(i, j, v);
            if i != j {
                a.add(j, i, v);
            }
        }
        let b = [1.0, 2.0, 3.0, 4.0];
        let x_bar = [0.5, 0.0, 0.0, -1.5];
        let system = ConstrainedSystem::new(&mut a.clone(), &[0, 3]).unwrap();
        let mut x = b.to_vec();
        system.solve(&mut x, &x_bar, 1);
        // Reduced 2x2 system in the free unknowns 1, 2.
        let r1 = 2.0 + 0.5; // b1 - A_01 * x_bar0, A_01 = -1
        let r2 = 3.0 - (-3.0) * -1.5;
        let det = 5.0 * 6.0 - 4.0;
        let x1 = (6.0 * r1 + 2.0 * r2) / det;
        let x2 = (2.0 * r1 + 5.0 * r2) / det;
        assert_eq!(x[0], 0.5);
        assert_eq!(x[3], -1.5);
        assert!((x[1] - x1).abs() < 1e-14 && (x[2] - x2).abs() < 1e-14);
    }
}
