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
use crate::model::linear::Node;
use crate::model::system::MassSpringSystem;
use nalgebra::Vector3;
use std::cmp::Reverse;
use std::collections::{BinaryHeap, VecDeque};
use std::ops::Mul;

mod sealed {
    /// Only this module's graphs are [`super::SpringGraph`]s.
    pub trait Sealed {}
    impl Sealed for super::Ends {}
    impl<const N: usize> Sealed for super::Chain<N> {}
}

/// Which nodes each spring joins: the shape of a spring graph, apart from its weights.
///
/// Sealed: [`Ends`] and [`Chain`] only, whose `ends(i)` are nodes of the graph (below
/// `nodes()`) for every spring `i < springs()`, and which panic for any other `i`; the passes
/// over the springs index positions by them unchecked ([`Positions`]).
pub trait SpringGraph: sealed::Sealed + Clone + std::fmt::Debug + PartialEq {
    /// Whether every graph of the type is a chain, spring i joining nodes i and i + 1 ([`Chain`]).
    const CHAIN: bool = false;
    /// Number of nodes n.
    fn nodes(&self) -> usize;
    /// Number of springs s.
    fn springs(&self) -> usize;
    /// The nodes $`(a_i, b_i)`$ of spring `i`.
    fn ends(&self, i: usize) -> (usize, usize);
}

/// Positions (or right-hand sides) of a graph's n nodes as the incidence reads and writes
/// them: column-major (`[T]`: all x, then all y, then all z; the lanes and ADMM-PD) or node by
/// node (`[Node]`: Liu's run alone, in its global solve's order, a node one 256-bit vector,
/// its differences [`Node`]s too, so that each is one vector operation).
pub trait Positions<T> {
    /// A difference of two nodes, and what is added to or subtracted from a node.
    type Vector: Copy + Mul<T, Output = Self::Vector>;
    /// Whether it holds the coordinates of `n` nodes.
    fn holds(&self, n: usize) -> bool;
    /// $`x_a - x_b`$.
    ///
    /// # Safety
    /// `a` and `b` below `n`, and `self.holds(n)`.
    unsafe fn difference(&self, n: usize, a: usize, b: usize) -> Self::Vector;
    /// $`x_a \mathrel{+}= v`$, then $`x_b \mathrel{-}= v`$, coordinate by coordinate.
    ///
    /// # Safety
    /// `a` and `b` below `n`, and `self.holds(n)`.
    unsafe fn add_subtract(&mut self, n: usize, a: usize, b: usize, v: Self::Vector);
    /// Every node's coordinates from `other`, of the same layout and length.
    fn copy_from(&mut self, other: &Self);
    /// $`|v|^2`$, as $`(v_x^2 + v_y^2) + v_z^2`$.
    fn norm_squared(v: &Self::Vector) -> T;
}

// Indexed with checks: the rope's columns, whose checks the compiler removes where it knows n.
impl<T: Lane> Positions<T> for [T] {
    type Vector = Vector3<T>;

    #[inline(always)]
    fn holds(&self, n: usize) -> bool {
        self.len() >= 3 * n
    }

    #[inline(always)]
    unsafe fn difference(&self, n: usize, a: usize, b: usize) -> Vector3<T> {
        let [x, y, z] = coordinates(self, n);
        Vector3::new(x[a] - x[b], y[a] - y[b], z[a] - z[b])
    }

    #[inline(always)]
    unsafe fn add_subtract(&mut self, n: usize, a: usize, b: usize, v: Vector3<T>) {
        for (out, &v) in coordinates_mut(self, n).into_iter().zip(v.iter()) {
            out[a] += v;
            out[b] -= v;
        }
    }

    #[inline(always)]
    fn copy_from(&mut self, other: &Self) {
        self.copy_from_slice(other);
    }

    #[inline(always)]
    fn norm_squared(v: &Vector3<T>) -> T {
        v.norm_squared()
    }
}

// Indexed without checks: on the 100 × 100 sheet the four checks of a spring's two passes
// were 13-16 µs of Liu's 0.35 ms iteration (a scratch program, one core).
impl Positions<f64> for [Node] {
    type Vector = Node;

    #[inline(always)]
    fn holds(&self, n: usize) -> bool {
        self.len() >= n
    }

    #[inline(always)]
    unsafe fn difference(&self, _n: usize, a: usize, b: usize) -> Node {
        // SAFETY: a, b < n <= self.len() (the caller's contract).
        unsafe { *self.get_unchecked(a) - *self.get_unchecked(b) }
    }

    #[inline(always)]
    unsafe fn add_subtract(&mut self, _n: usize, a: usize, b: usize, v: Node) {
        // SAFETY: a, b < n <= self.len() (the caller's contract).
        unsafe {
            *self.get_unchecked_mut(a) = *self.get_unchecked(a) + v;
            *self.get_unchecked_mut(b) = *self.get_unchecked(b) - v;
        }
    }

    #[inline(always)]
    fn copy_from(&mut self, other: &Self) {
        self.copy_from_slice(other);
    }

    #[inline(always)]
    fn norm_squared(v: &Node) -> f64 {
        let [x, y, z, _] = v.0;
        (x * x + y * y) + z * z
    }
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
        let nodes = system.len();
        let ends = system.springs().iter().map(|s| {
            // A system's springs join its nodes ([`MassSpringSystem::new`]); the passes over
            // the springs rely on it ([`SpringGraph`]).
            assert!(
                s.a < nodes && s.b < nodes,
                "a spring joins two nodes of the system"
            );
            [s.a, s.b].map(|i| i as u32)
        });
        Self {
            nodes,
            ends: ends.collect(),
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
        assert!(i + 1 < N, "spring {i} of a chain of {N} nodes");
        (i, i + 1)
    }
}

/// How many places apart [`SpringIncidence::scatter_order`] keeps two springs that share a
/// node: a node's sum then waits for no store in flight. On the 100 × 100 sheet, a pass over
/// the springs in index order has 29,501 of its 39,402 springs sharing a node with the spring
/// before and 39,105 with the one two before; its scatter onto nodes held as 256-bit vectors
/// took 153 µs in index order and 76-97 µs in this order (a scratch program, one core; lags
/// of 2, 4, 8 and 16 alike).
pub const SCATTER_LAG: usize = 4;

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

    /// The same incidence with node i renumbered `row[i]` and the springs taken in `order`
    /// (spring k of the result is spring `order[k]` of this one).
    pub fn renumbered(&self, row: &[u32], order: &[u32]) -> Self {
        let nodes = self.graph.nodes;
        assert!(row.len() == nodes && row.iter().all(|&r| (r as usize) < nodes));
        let ends = order.iter().map(|&i| {
            let [a, b] = self.graph.ends[i as usize];
            [row[a as usize], row[b as usize]]
        });
        Self {
            graph: Ends {
                nodes,
                ends: ends.collect(),
            },
            weights: order.iter().map(|&i| self.weights[i as usize]).collect(),
        }
    }

    /// An order of the springs for a pass that adds each spring's term to its two ends
    /// ([`Self::add_row_transposed`]) with each node's springs in index order, so that every
    /// node's sum takes its terms in the order of a pass in index order and has its bits, and
    /// with two springs that share a node [`SCATTER_LAG`] or more places apart wherever the
    /// graph allows: a node's next term then does not wait for the last one's store. Among the
    /// springs whose earlier springs at both ends are that far behind, the first by index is
    /// taken (the pass stays near index order); when there is none, the one ready soonest.
    pub fn scatter_order(&self) -> Vec<u32> {
        // Springs and nodes in 32 bits, `NONE` for none: a transient of 13 bytes a spring and 4
        // a node beside the solver's own arrays.
        const NONE: u32 = u32::MAX;
        let (n, s) = (self.graph.nodes, self.graph.ends.len());
        // Each spring's successors (the next spring at each end) and its count of
        // predecessors not yet taken.
        let mut last = vec![NONE; n];
        let mut successors = vec![[NONE; 2]; s];
        let mut waiting_for = vec![0_u8; s];
        for (i, &[a, b]) in self.graph.ends.iter().enumerate() {
            let [a, b] = [a as usize, b as usize];
            let before = match (last[a], last[b]) {
                (p, q) if p == q => [p, NONE],
                (p, q) => [p, q],
            };
            for p in before.into_iter().filter(|&p| p != NONE) {
                let free = successors[p as usize]
                    .iter_mut()
                    .find(|next| **next == NONE);
                *free.expect("a spring has two ends") = i as u32;
                waiting_for[i] += 1;
            }
            last[a] = i as u32;
            last[b] = i as u32;
        }
        let mut ready: BinaryHeap<Reverse<u32>> = (0..s as u32)
            .filter(|&i| waiting_for[i as usize] == 0)
            .map(Reverse)
            .collect();
        // Springs whose predecessors are taken, with the place from which they are ready.
        let mut lagging: VecDeque<(usize, u32)> = VecDeque::new();
        let mut order = Vec::with_capacity(s);
        while order.len() < s {
            let place = order.len();
            while let Some(&(from, i)) = lagging.front() {
                if from > place {
                    break;
                }
                ready.push(Reverse(i));
                lagging.pop_front();
            }
            let i = match ready.pop() {
                Some(Reverse(i)) => i,
                None => {
                    lagging
                        .pop_front()
                        .expect("a spring not taken is waiting")
                        .1
                }
            };
            order.push(i);
            for next in successors[i as usize].into_iter().filter(|&q| q != NONE) {
                waiting_for[next as usize] -= 1;
                if waiting_for[next as usize] == 0 {
                    lagging.push_back((place + SCATTER_LAG, next));
                }
            }
        }
        order
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

    /// The unweighted difference $`x_{a_i} - x_{b_i}`$ of spring `i`'s ends in positions `x`
    /// ($`x_1 - x_2`$ of Eqs 21-28).
    #[inline(always)]
    pub fn difference<P: Positions<T> + ?Sized>(&self, i: usize, x: &P) -> P::Vector {
        assert!(x.holds(self.nodes()), "positions of every node");
        // SAFETY: `x` holds every node, checked above.
        unsafe { self.difference_unchecked(i, x) }
    }

    /// [`Self::difference`] without checking that `x` holds every node (a pass over the
    /// springs checks it once).
    ///
    /// # Safety
    /// `x.holds(self.nodes())`.
    #[inline(always)]
    pub unsafe fn difference_unchecked<P: Positions<T> + ?Sized>(
        &self,
        i: usize,
        x: &P,
    ) -> P::Vector {
        let (a, b) = self.graph.ends(i);
        // SAFETY: a spring's ends are nodes of the graph ([`SpringGraph`]), which `x` holds.
        unsafe { x.difference(self.graph.nodes(), a, b) }
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
                // SAFETY: `out` holds 3n values, sliced above.
                unsafe { self.add_row_transposed_unchecked(i, values(i), out) };
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

    /// Adds row `i` transposed times `value` to `out`: $`out_{a_i} \mathrel{+}= w_i\,value`$,
    /// $`out_{b_i} \mathrel{-}= w_i\,value`$ (column $`i`$ of $`J`$ times $`d_i`$;
    /// $`D_i^\top`$ times a per-spring vector).
    #[inline(always)]
    pub fn add_row_transposed<P: Positions<T> + ?Sized>(
        &self,
        i: usize,
        value: P::Vector,
        out: &mut P,
    ) {
        assert!(out.holds(self.nodes()), "a value for every node");
        // SAFETY: `out` holds every node, checked above.
        unsafe { self.add_row_transposed_unchecked(i, value, out) }
    }

    /// [`Self::add_row_transposed`] without checking that `out` holds every node (a pass over
    /// the springs checks it once).
    ///
    /// # Safety
    /// `out.holds(self.nodes())`.
    #[inline(always)]
    pub unsafe fn add_row_transposed_unchecked<P: Positions<T> + ?Sized>(
        &self,
        i: usize,
        value: P::Vector,
        out: &mut P,
    ) {
        let (a, b) = self.graph.ends(i);
        let v = value * self.weights[i];
        // SAFETY: a spring's ends are nodes of the graph ([`SpringGraph`]), which `out` holds.
        unsafe { out.add_subtract(self.graph.nodes(), a, b, v) }
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

    /// How many springs of `order` share a node with one of the `SCATTER_LAG - 1` springs
    /// before them, and whether every node's springs come in index order.
    fn close_and_in_order(graph: &Ends, order: &[u32]) -> (usize, bool) {
        let ends = |k: usize| graph.ends(order[k] as usize);
        let share =
            |(a, b): (usize, usize), (c, d): (usize, usize)| a == c || a == d || b == c || b == d;
        let close = (0..order.len())
            .filter(|&k| (1..SCATTER_LAG.min(k + 1)).any(|back| share(ends(k), ends(k - back))))
            .count();
        let mut last = vec![None; graph.nodes()];
        let mut in_order = true;
        for &i in order {
            let (a, b) = graph.ends(i as usize);
            for node in [a, b] {
                in_order &= last[node] < Some(i);
                last[node] = Some(i);
            }
        }
        (close, in_order)
    }

    /// The scatter order of the 30 × 30 sheet is an order of all its springs, takes each node's
    /// springs in index order, and keeps fewer than 5 % of them (147 of 3,422) within
    /// `SCATTER_LAG - 1` places of a spring sharing a node. The test shows both checks failing
    /// where they should: index order keeps more than 90 % of the springs that close, and the
    /// reversed order takes nodes' springs out of order.
    #[test]
    fn the_scatter_order_keeps_each_node_in_order_and_its_springs_apart() {
        use crate::model::scene::SheetParams;
        let sheet = SheetParams::spec(30, 1e3).build().unwrap();
        let j = crate::solvers::projective::incidence_matrix(&sheet);
        let order = j.scatter_order();
        let mut sorted = order.clone();
        sorted.sort_unstable();
        assert!(sorted.iter().copied().eq(0..j.springs() as u32));
        let (close, in_order) = close_and_in_order(&j.graph, &order);
        assert!(in_order);
        assert!(close * 20 < j.springs(), "{close} of {}", j.springs());
        let (close, in_order) = close_and_in_order(&j.graph, &sorted);
        assert!(
            in_order && close * 10 > 9 * j.springs(),
            "index order: {close}"
        );
        let reversed: Vec<u32> = order.iter().rev().copied().collect();
        assert!(!close_and_in_order(&j.graph, &reversed).1);
    }
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
