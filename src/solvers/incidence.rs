//! The springs' incidence (thesis Eqs 26, 53 and 54), shared by the Projective-Dynamics
//! solvers ([`crate::solvers::projective`]): which nodes each spring joins (a
//! [`SpringGraph`]), and the s×n matrix of per-spring weights on it, applied to column-major
//! positions and transposed onto them.
//!
//! A graph is either any spring graph ([`Ends`], the springs' ends as listed: every run alone,
//! the sheet) or the rope's [`Chain`] of `N` nodes, whose size and ends are constants where the
//! code is compiled (the batched runs' rope, [`crate::solvers::batch::projective`]). The same
//! functions serve both.

use crate::model::lanes::Lane;
use crate::model::system::MassSpringSystem;
use nalgebra::Vector3;

/// Which nodes each spring joins: the shape of a spring graph, apart from its weights.
pub trait SpringGraph: Clone + std::fmt::Debug + PartialEq {
    /// Whether every graph of the type is a chain, spring i joining nodes i and i + 1 ([`Chain`]).
    const CHAIN: bool = false;
    /// Number of nodes n.
    fn nodes(&self) -> usize;
    /// Number of springs s.
    fn springs(&self) -> usize;
    /// The nodes $`(a_i, b_i)`$ of spring `i`.
    fn ends(&self, i: usize) -> (usize, usize);
}

/// Any spring graph: each spring's ends as listed, in 32 bits (a system has at most
/// [`crate::model::system::MAX_NODES`] nodes): the local steps and right-hand sides read them
/// for every spring, and half the bytes of `usize` ends took the 100 × 100 sheet's Liu local
/// step from 101-111 to 95-98 µs (`timing --point fast_mass_spring 100`, five alternating
/// runs pinned to one core).
#[derive(Debug, Clone, PartialEq)]
pub struct Ends {
    nodes: usize,
    ends: Vec<[u32; 2]>,
}

impl Ends {
    /// `system`'s springs' ends.
    pub fn of(system: &MassSpringSystem) -> Self {
        Self {
            nodes: system.len(),
            ends: system
                .springs()
                .iter()
                .map(|s| [s.a, s.b].map(|i| i as u32))
                .collect(),
        }
    }
}

impl SpringGraph for Ends {
    fn nodes(&self) -> usize {
        self.nodes
    }

    fn springs(&self) -> usize {
        self.ends.len()
    }

    fn ends(&self, i: usize) -> (usize, usize) {
        let [a, b] = self.ends[i];
        (a as usize, b as usize)
    }
}

/// A chain of `N` nodes, spring `i` joining nodes `i` and `i + 1`: the rope. Its size and
/// ends are known where the code is compiled, so that a loop over its springs or nodes is
/// unrolled with every index a constant (the batched runs' rope,
/// [`crate::solvers::batch::projective`]).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Chain<const N: usize>;

impl<const N: usize> Chain<N> {
    /// The chain, if `graph` is one of `N` nodes.
    pub fn of(graph: &impl SpringGraph) -> Option<Self> {
        let chain = graph.nodes() == N
            && graph.springs() + 1 == N
            && (0..graph.springs()).all(|i| graph.ends(i) == (i, i + 1));
        chain.then_some(Self)
    }
}

impl<const N: usize> SpringGraph for Chain<N> {
    const CHAIN: bool = true;

    #[inline(always)]
    fn nodes(&self) -> usize {
        N
    }

    #[inline(always)]
    fn springs(&self) -> usize {
        N - 1
    }

    #[inline(always)]
    fn ends(&self, i: usize) -> (usize, usize) {
        (i, i + 1)
    }
}

/// Spring-node incidence of a spring graph, stored per spring (never as a dense matrix).
///
/// As an s×n matrix (s springs, n nodes) its row $`i`$ is $`w_i\,(e_{a_i} - e_{b_i})^\top`$, so
/// that row $`i`$ applied to the positions is $`w_i\,(x_{a_i} - x_{b_i})`$. With unit weights it
/// is the reduction matrix $`D`$ of Eq (54); with $`w_i = k_i`$ it is the transpose of the
/// incidence matrix $`J`$ of Eqs (26), (53). The weights are per lane in a batch of runs
/// ([`crate::model::lanes`]); the graph is shared.
#[derive(Debug, Clone, PartialEq)]
pub struct SpringIncidence<T = f64, G = Ends> {
    graph: G,
    weights: Vec<T>,
}

impl SpringIncidence {
    /// The incidence of `system`'s springs with the per-spring `weights`
    /// ([`crate::solvers::projective::incidence_matrix`], [`crate::solvers::projective::reduction_matrix`]).
    pub(super) fn new(system: &MassSpringSystem, weights: Vec<f64>) -> Self {
        Self {
            graph: Ends::of(system),
            weights,
        }
    }

    /// The weight $`w_i`$ of spring `i`.
    pub fn weight(&self, i: usize) -> f64 {
        self.weights[i]
    }

    /// Entry (`spring`, `node`) of the s×n matrix: $`D_{ij}`$ of Eq (54), $`J_{ji}`$ of Eq (53).
    pub fn entry(&self, spring: usize, node: usize) -> f64 {
        let (a, b) = self.graph.ends(spring);
        if node == a {
            self.weights[spring]
        } else if node == b {
            -self.weights[spring]
        } else {
            0.0
        }
    }
}

impl<T: Lane, const N: usize> SpringIncidence<T, Chain<N>> {
    /// `like`'s graph as a chain of `N` nodes, with every weight zero, in lanes to be loaded
    /// ([`Self::load_lane`]); None unless `like` is such a chain.
    pub fn chain_lanes(like: &SpringIncidence) -> Option<Self> {
        Some(Self {
            graph: Chain::of(&like.graph)?,
            weights: vec![T::splat(0.0); like.graph.springs()],
        })
    }

    /// Sets lane `lane` of every weight to `from`'s, which must be the same chain.
    pub fn load_lane(&mut self, lane: usize, from: &SpringIncidence) {
        assert!(
            Chain::<N>::of(&from.graph).is_some(),
            "the lanes of a batch share one spring graph"
        );
        crate::model::lanes::load_values(&mut self.weights, lane, &from.weights);
    }
}

impl<T: Lane, G: SpringGraph> SpringIncidence<T, G> {
    /// Number of springs s (rows).
    #[inline(always)]
    pub fn springs(&self) -> usize {
        self.graph.springs()
    }

    /// Number of nodes n (columns).
    #[inline(always)]
    pub fn nodes(&self) -> usize {
        self.graph.nodes()
    }

    /// The nodes $`(a_i, b_i)`$ of spring `i`.
    #[inline(always)]
    pub fn ends(&self, i: usize) -> (usize, usize) {
        self.graph.ends(i)
    }

    /// Row `i` applied to column-major positions `x` (length 3n): $`w_i\,(x_{a_i} - x_{b_i})`$
    /// ($`D_i x`$ for the reduction matrix).
    #[inline(always)]
    pub fn apply_row(&self, i: usize, x: &[T]) -> Vector3<T> {
        self.difference(i, x) * self.weights[i]
    }

    /// The unweighted difference $`x_{a_i} - x_{b_i}`$ of spring `i`'s ends in column-major
    /// positions `x` ($`x_1 - x_2`$ of Eqs 21-28).
    #[inline(always)]
    pub fn difference(&self, i: usize, x: &[T]) -> Vector3<T> {
        let (a, b) = self.graph.ends(i);
        let [x, y, z] = coordinates(x, self.graph.nodes());
        Vector3::new(x[a] - x[b], y[a] - y[b], z[a] - z[b])
    }

    /// `out` $`= b + \sum_i`$ row i transposed times `values(i)`: `b` copied, then
    /// [`Self::add_row_transposed`] for every spring in index order (the global right-hand
    /// sides of Eqs (29) and (40)). On a [`Chain`] node by node instead, each node's sum in
    /// registers: node j is the second end of spring j - 1 and the first of spring j, so its
    /// sum takes their terms in that order, as the springs' order does (the same bits, without
    /// the copy and the stores and loads between two springs that share a node).
    #[inline(always)]
    pub fn b_plus_transposed(&self, b: &[T], values: impl Fn(usize) -> Vector3<T>, out: &mut [T]) {
        let n = self.nodes();
        let (b, out) = (&b[..3 * n], &mut out[..3 * n]);
        if !G::CHAIN {
            out.copy_from_slice(b);
            for i in 0..self.springs() {
                self.add_row_transposed(i, values(i), out);
            }
            return;
        }
        let mut ending_here: Option<Vector3<T>> = None;
        for j in 0..n {
            let starting_here = (j + 1 < n).then(|| values(j) * self.weights[j]);
            for c in 0..3 {
                let mut sum = b[c * n + j];
                if let Some(v) = ending_here {
                    sum -= v[c];
                }
                if let Some(v) = starting_here {
                    sum += v[c];
                }
                out[c * n + j] = sum;
            }
            ending_here = starting_here;
        }
    }

    /// Adds row `i` transposed times `value` to the column-major `out` (length 3n):
    /// $`out_{a_i} \mathrel{+}= w_i\,value`$, $`out_{b_i} \mathrel{-}= w_i\,value`$ (column $`i`$
    /// of $`J`$ times $`d_i`$; $`D_i^\top`$ times a per-spring vector).
    #[inline(always)]
    pub fn add_row_transposed(&self, i: usize, value: Vector3<T>, out: &mut [T]) {
        let (a, b) = self.graph.ends(i);
        let v = value * self.weights[i];
        for (out, &v) in coordinates_mut(out, self.graph.nodes())
            .into_iter()
            .zip(v.iter())
        {
            out[a] += v;
            out[b] -= v;
        }
    }
}

/// The three coordinate columns (x, y, z) of column-major positions over `n` nodes.
#[inline(always)]
fn coordinates<T>(columns: &[T], n: usize) -> [&[T]; 3] {
    [&columns[..n], &columns[n..2 * n], &columns[2 * n..3 * n]]
}

/// [`coordinates`], mutable.
#[inline(always)]
fn coordinates_mut<T>(columns: &mut [T], n: usize) -> [&mut [T]; 3] {
    let (x, rest) = columns.split_at_mut(n);
    let (y, rest) = rest.split_at_mut(n);
    [x, y, &mut rest[..n]]
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::model::scene::{thesis_rope, THESIS_NODES};
    use crate::solvers::projective::incidence_matrix;

    /// [`Chain::of`] accepts the thesis rope's graph and nothing else of its size: not the
    /// same springs listed the other way round, in another order, with one more, or with the
    /// last one joined to the first node. (Fails with only each spring's first end checked.)
    #[test]
    fn a_chain_is_springs_i_to_i_plus_one() {
        let rope = incidence_matrix(&thesis_rope(1e3).unwrap()).graph;
        assert!(Chain::<THESIS_NODES>::of(&rope).is_some());
        assert!(Chain::<{ THESIS_NODES + 1 }>::of(&rope).is_none());
        let chain: Vec<(usize, usize)> = (0..THESIS_NODES - 1).map(|i| (i, i + 1)).collect();
        let graph = |ends: Vec<(usize, usize)>| Ends {
            nodes: THESIS_NODES,
            ends: ends.iter().map(|&(a, b)| [a as u32, b as u32]).collect(),
        };
        let reversed = chain.iter().map(|&(a, b)| (b, a)).collect();
        let reordered = chain.iter().rev().copied().collect();
        let closed = [chain.clone(), vec![(THESIS_NODES - 1, 0)]].concat();
        let mut rejoined = chain.clone();
        rejoined[THESIS_NODES - 2].1 = 0;
        assert!(Chain::<THESIS_NODES>::of(&graph(chain)).is_some());
        for other in [reversed, reordered, closed, rejoined] {
            assert!(Chain::<THESIS_NODES>::of(&graph(other)).is_none());
        }
    }
}
