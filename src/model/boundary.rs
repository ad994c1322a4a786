//! Fixed nodes imposed on a linear system before its solve (thesis §3.2, Eqs 43-47).
//!
//! Of the three ways §3.2 weighs (overwriting positions after the solve, removing the fixed
//! degrees of freedom, or modifying the system before the solve), the thesis adopts the
//! third: the fixed rows and columns of $`A`$ become the identity and the right-hand side
//! carries the fixed values, so the free unknowns feel the fixed ones through $`b - A u`$.
//! This module is the one place that does it; Backward Euler (per Newton iteration),
//! Liu 2013 and ADMM-PD (once per scene and time step) all solve through [`ConstrainedSystem`].

use crate::error::Result;
use crate::model::lanes::Lane;
use crate::model::linear::{Factorization, Node, SymmetricMatrix};
use crate::model::system::MassSpringSystem;

/// A factored system $`Ax = b`$ whose fixed unknowns are imposed by Eqs 44-47.
#[derive(Debug, Clone)]
pub struct ConstrainedSystem {
    imposition: Imposition,
    factorization: Factorization,
}

/// Eqs. 44-47 for matrices of one pattern and fixed set, without their factorisation: at `f64`
/// one matrix's, in lanes one per lane ([`crate::solvers::batch::backward_euler`]).
#[derive(Debug, Clone)]
pub struct Imposition<T = f64> {
    fixed: Vec<usize>,
    /// The block $`A_2`$ of Eq (43): $`(i, j, A_{ij})`$ for free rows $`i`$ and fixed columns
    /// $`j`$, saved before Eq (44) zeroes it, so that Eq (46) can form $`A u`$.
    coupling: Vec<(usize, usize, T)>,
    slots: ImpositionSlots,
}

/// Where Eq (44) reads and writes in the matrix's values, found once so that a
/// refactorisation searches nothing.
#[derive(Debug, Clone)]
struct ImpositionSlots {
    /// The slot of each entry of `coupling` (entry $`(j, i)`$, equal by symmetry).
    coupling: Vec<usize>,
    /// The off-diagonal entries of the fixed rows and columns.
    zero: Vec<usize>,
    /// The fixed diagonal entries.
    unit: Vec<usize>,
}

impl ConstrainedSystem {
    /// Eq. (44): $`\begin{pmatrix}A_1 & 0\\ 0 & I\end{pmatrix}`$ replaces the fixed rows and
    /// columns of `a` (in place), then the result is factored once.
    pub fn new(a: &mut SymmetricMatrix, fixed: &[usize]) -> Result<Self> {
        Self::with_factorization(a, fixed, Factorization::new)
    }

    /// [`Self::new`] for a matrix solved many times with three right-hand sides (Liu's and
    /// ADMM's coordinates): factored by [`Factorization::for_three_columns`].
    pub fn for_three_columns(a: &mut SymmetricMatrix, fixed: &[usize]) -> Result<Self> {
        Self::with_factorization(a, fixed, Factorization::for_three_columns)
    }

    fn with_factorization(
        a: &mut SymmetricMatrix,
        fixed: &[usize],
        factor: fn(&SymmetricMatrix) -> Result<Factorization>,
    ) -> Result<Self> {
        let mut imposition = Imposition::new(a, fixed);
        imposition.impose_on_matrix(a.values_mut());
        Ok(Self {
            imposition,
            factorization: factor(a)?,
        })
    }

    /// Eq. (44) again for new values of a matrix with the same pattern and fixed set, and a
    /// numeric refactorisation that reuses the pattern's analysis.
    pub fn refactor(&mut self, a: &mut SymmetricMatrix) -> Result<()> {
        self.imposition.impose_on_matrix(a.values_mut());
        self.factorization.refactor(a)
    }

    /// Eq. (43): solves $`A x = b`$ with $`x_j = \bar x_j`$ on the fixed unknowns, for `ncols`
    /// right-hand sides stored column after column. `x_bar` has the layout of `b` and is
    /// read only at fixed unknowns. The solution overwrites `b`.
    #[inline]
    pub fn solve(&self, b: &mut [f64], x_bar: &[f64], ncols: usize) {
        self.imposition.impose_on_rhs(b, x_bar, ncols);
        self.factorization.solve_in_place(b, ncols);
    }

    /// Eq. (43): [`Self::solve`] for three right-hand sides held node by node in the
    /// factorisation's order ([`Factorization::solve_nodes`]), one unknown per node: node i
    /// at `rows[i]` of `b` and `x_bar`.
    #[inline]
    pub fn solve_nodes(&self, b: &mut [Node], x_bar: &[Node], rows: &[u32]) {
        self.imposition.impose_on_nodes(b, x_bar, rows);
        self.factorization.solve_nodes(b);
    }

    /// The imposition of Eqs 44-47 on its matrix and right-hand sides.
    pub fn imposition(&self) -> &Imposition {
        &self.imposition
    }

    /// The factorisation of the imposed matrix of Eq (44).
    pub fn factorization(&self) -> &Factorization {
        &self.factorization
    }
}

impl<T: Lane> Imposition<T> {
    /// The imposition of the `fixed` unknowns on matrices of `a`'s pattern (its block $`A_2`$
    /// zero until [`Self::impose_on_matrix`] saves it).
    pub fn new(a: &SymmetricMatrix, fixed: &[usize]) -> Self {
        let mut is_fixed = vec![false; a.dim()];
        for &j in fixed {
            is_fixed[j] = true;
        }
        let mut coupling = Vec::new();
        let mut slots = ImpositionSlots {
            coupling: Vec::new(),
            zero: Vec::new(),
            unit: Vec::new(),
        };
        for &j in fixed {
            for (slot, i) in a.row_slots(j) {
                if i == j {
                    slots.unit.push(slot);
                    continue;
                }
                if !is_fixed[i] {
                    coupling.push((i, j, T::splat(0.0)));
                    slots.coupling.push(slot);
                }
                slots.zero.push(slot);
                slots.zero.push(a.slot(i, j).expect("a symmetric pattern"));
            }
        }
        Self {
            fixed: fixed.to_vec(),
            coupling,
            slots,
        }
    }

    /// The same imposition in lanes, its block $`A_2`$ zero in every lane until loaded
    /// ([`Self::load_lane`]).
    pub fn lanes(from: &Imposition) -> Self {
        Self {
            fixed: from.fixed.clone(),
            coupling: from
                .coupling
                .iter()
                .map(|&(i, j, _)| (i, j, T::splat(0.0)))
                .collect(),
            slots: from.slots.clone(),
        }
    }

    /// Sets lane `lane`'s block $`A_2`$ to `from`'s, of the same pattern and fixed set.
    pub fn load_lane(&mut self, lane: usize, from: &Imposition) {
        assert_eq!(from.fixed, self.fixed, "one fixed set in a batch");
        for (into, &(i, j, a_ij)) in self.coupling.iter_mut().zip(&from.coupling) {
            assert_eq!((into.0, into.1), (i, j), "one pattern in a batch");
            into.2.replace(lane, a_ij);
        }
    }

    /// Eq. (44): on a matrix's `values` (in its pattern's order), saves the block $`A_2`$
    /// (free rows, fixed columns), then replaces the fixed rows and columns by the identity.
    pub fn impose_on_matrix(&mut self, values: &mut [T]) {
        for ((_, _, a_ij), &slot) in self.coupling.iter_mut().zip(&self.slots.coupling) {
            *a_ij = values[slot];
        }
        for &slot in &self.slots.zero {
            values[slot] = T::splat(0.0);
        }
        for &slot in &self.slots.unit {
            values[slot] = T::splat(1.0);
        }
    }

    /// Eqs. (45)-(47): with $`u = (0, \bar x)`$ (Eq 45), $`b \leftarrow b - A u`$ (Eqs 46-47) on
    /// the free rows, and $`b_j = \bar x_j`$ on the fixed rows (step 4 of §3.2), for `ncols`
    /// right-hand sides stored one after another. Inlined always: the batched iterations call
    /// it once per iteration on the path from the right-hand side to the solve, where a call
    /// cost a twentieth of the thesis part's CPU (`perf`).
    #[inline(always)]
    pub fn impose_on_rhs(&self, b: &mut [T], x_bar: &[T], ncols: usize) {
        let n = b.len() / ncols;
        for (b, x_bar) in b.chunks_exact_mut(n).zip(x_bar.chunks_exact(n)) {
            for &(i, j, a_ij) in &self.coupling {
                b[i] -= a_ij * x_bar[j];
            }
            for &j in &self.fixed {
                b[j] = x_bar[j];
            }
        }
    }
}

impl Imposition {
    /// Eqs. (45)-(47): [`Self::impose_on_rhs`] for three right-hand sides held node by node,
    /// one unknown per node, node i at `rows[i]`: each coordinate gets the same operations in
    /// the same order as its column does.
    #[inline]
    pub fn impose_on_nodes(&self, b: &mut [Node], x_bar: &[Node], rows: &[u32]) {
        let row = |i: usize| rows[i] as usize;
        for &(i, j, a_ij) in &self.coupling {
            let (b, x_bar) = (&mut b[row(i)].0, x_bar[row(j)].0);
            *b = std::array::from_fn(|c| b[c] - a_ij * x_bar[c]);
        }
        for &j in &self.fixed {
            b[row(j)] = x_bar[row(j)];
        }
    }
}

/// The unknowns of `system`'s fixed nodes, for systems with `block` unknowns per node.
pub fn fixed_node_unknowns(system: &MassSpringSystem, block: usize) -> Vec<usize> {
    let fixed_nodes = system
        .nodes()
        .iter()
        .enumerate()
        .filter(|(_, n)| n.fixed)
        .map(|(i, _)| i);
    fixed_unknowns(fixed_nodes, block)
}

/// The unknowns of the fixed nodes, for systems with `block` unknowns per node.
pub fn fixed_unknowns(fixed_nodes: impl Iterator<Item = usize>, block: usize) -> Vec<usize> {
    fixed_nodes
        .flat_map(|i| (0..block).map(move |c| i * block + c))
        .collect()
}

/// The second way of §3.2: the fixed unknowns are removed. The free ones solve
/// $`A_{ff}\,x_f = b_f - A_{fc}\,\bar x_c`$ with a separately factored $`A_{ff}`$, so the fixed
/// values never enter the factorisation. The thesis weighs it and adopts Eqs 43-47 instead
/// ([`ConstrainedSystem`]); the forensic variants of ADMM-PD use it.
#[derive(Debug, Clone)]
pub struct EliminatedSystem {
    /// The free unknowns, in order; the reduced unknowns are their indices here.
    free: Vec<usize>,
    /// $`(f, c, A_{fc})`$ for reduced row $`f`$ and fixed unknown $`c`$.
    coupling: Vec<(usize, usize, f64)>,
    factorization: Factorization,
    /// Scratch for the reduced right-hand sides.
    reduced: Vec<f64>,
}

impl EliminatedSystem {
    /// $`A_{ff}`$ of `a` without the `fixed` unknowns, factored once; `edges` is the graph of
    /// `a`'s off-diagonal entries (one unknown per node).
    pub fn new(a: &SymmetricMatrix, fixed: &[usize], edges: &[(usize, usize)]) -> Result<Self> {
        let n = a.dim();
        let mut reduced_index = vec![None; n];
        let free: Vec<usize> = (0..n).filter(|i| !fixed.contains(i)).collect();
        for (f, &i) in free.iter().enumerate() {
            reduced_index[i] = Some(f);
        }
        let reduced_edges: Vec<(usize, usize)> = edges
            .iter()
            .filter_map(|&(i, j)| Some((reduced_index[i]?, reduced_index[j]?)))
            .collect();
        let mut a_ff = SymmetricMatrix::from_node_graph(free.len(), 1, &reduced_edges);
        let mut coupling = Vec::new();
        for (f, &i) in free.iter().enumerate() {
            for (j, a_ij) in a.row(i) {
                match reduced_index[j] {
                    Some(g) => a_ff.add(f, g, a_ij),
                    None => coupling.push((f, j, a_ij)),
                }
            }
        }
        Ok(Self {
            reduced: Vec::new(),
            factorization: Factorization::new(&a_ff)?,
            free,
            coupling,
        })
    }

    /// Solves for `ncols` right-hand sides stored column-major in `b` (overwritten by $`x`$), the
    /// fixed unknowns at their values in `x_bar`.
    pub fn solve(&mut self, b: &mut [f64], x_bar: &[f64], ncols: usize) {
        let (n, m) = (b.len() / ncols, self.free.len());
        self.reduced.resize(ncols * m, 0.0);
        for c in 0..ncols {
            for (f, &i) in self.free.iter().enumerate() {
                self.reduced[c * m + f] = b[c * n + i];
            }
            for &(f, j, a_fj) in self.coupling.iter() {
                self.reduced[c * m + f] -= a_fj * x_bar[c * n + j];
            }
        }
        self.factorization.solve_in_place(&mut self.reduced, ncols);
        b.copy_from_slice(x_bar);
        for c in 0..ncols {
            for (f, &i) in self.free.iter().enumerate() {
                b[c * n + i] = self.reduced[c * m + f];
            }
        }
    }
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
        let mut eliminated = EliminatedSystem::new(&a, &[0, 3], &edges).unwrap();
        let mut y = b.to_vec();
        eliminated.solve(&mut y, &x_bar, 1);
        assert!(x.iter().zip(&y).all(|(p, q)| (p - q).abs() < 1e-14));
    }
}
