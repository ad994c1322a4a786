//! A node's three coordinates in one 256-bit vector: the layout of the three right-hand sides
//! that Liu's and ADMM's global solves take together ([`super::Factorization::solve_nodes`]).

use crate::model::lanes::Lanes4;
use crate::model::system::Vec3;
use simba::simd::SimdValue;

/// A node's three coordinates and a zero, aligned so that no node straddles two cache lines
/// (a buffer of 320 KB on the 100 × 100 sheet came from the allocator 16 bytes past a page
/// boundary: half the nodes did, and the forward substitution took 16 % longer, 108 against
/// 93 µs in a scratch program). Sums and products of nodes keep the fourth lane zero.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
#[repr(C, align(32))]
pub struct Node(pub [f64; 4]);

impl Node {
    /// The node at position `p`.
    #[inline(always)]
    pub fn new(p: Vec3) -> Self {
        Self([p[0], p[1], p[2], 0.0])
    }

    /// Its three coordinates.
    #[inline(always)]
    pub fn position(&self) -> Vec3 {
        Vec3::new(self.0[0], self.0[1], self.0[2])
    }

    /// The nodes' lanes, four per node, in order.
    pub fn lanes(nodes: &[Node]) -> &[f64] {
        // SAFETY: `Node` is `repr(C)` around `[f64; 4]` with no padding (32 bytes, the
        // alignment), so `nodes` is `4 * nodes.len()` initialised, aligned `f64`s.
        unsafe { std::slice::from_raw_parts(nodes.as_ptr().cast::<f64>(), 4 * nodes.len()) }
    }
}

// Sums, differences and scalings of a node's four lanes (the fourth stays zero), each one
// vector operation of the `wide` crate ([`Lanes4`]). Written as arrays lane by lane, they left
// the compiler free to vectorise a loop over springs instead, across eight springs at a time
// with gathers of their nodes: Liu's local step on the 100 × 100 sheet took 195 µs against 116
// µs (a scratch program, one core).

impl std::ops::Add for Node {
    type Output = Node;
    #[inline(always)]
    fn add(self, other: Node) -> Node {
        Node((Lanes4::from(self.0) + Lanes4::from(other.0)).0.to_array())
    }
}

impl std::ops::Sub for Node {
    type Output = Node;
    #[inline(always)]
    fn sub(self, other: Node) -> Node {
        Node((Lanes4::from(self.0) - Lanes4::from(other.0)).0.to_array())
    }
}

impl std::ops::Mul<f64> for Node {
    type Output = Node;
    #[inline(always)]
    fn mul(self, s: f64) -> Node {
        Node((Lanes4::from(self.0) * Lanes4::splat(s)).0.to_array())
    }
}
