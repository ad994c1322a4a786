//! The linear element kernels (Sifakis and Barbič 2012; the same kernel as GenPD's `constraint_tet.cpp`): a
//! tetrahedron, a triangle in the plane and a membrane triangle in 3D, each with its rest edge
//! matrix D_m (in the triangle's own rest frame for a membrane), D_m⁻¹ and rest measure
//! computed once; F from the nodes' displacements, the nodal forces and the element Hessian.
//!
//! Positions and displacements are flat, d numbers a node (d = 3, or 2 in the plane).

use super::hyperelastic::Deformation;
use crate::error::{shown, Error, Result};
use nalgebra::{DMatrix, Vector3};

/// A linear element: c + 1 nodes, F d×c (3×3 tet, 2×2 plane triangle, 3×2 membrane).
#[derive(Debug, Clone, PartialEq)]
pub struct Element {
    nodes: Vec<usize>,
    /// F at rest, F₀: the identity, or a membrane's rest frame (3×2, orthonormal columns).
    rest_gradient: DMatrix<f64>,
    dm_inverse: DMatrix<f64>,
    /// Rest volume (tet) or area (triangle), V.
    measure: f64,
}

/// A rest element smaller than this fraction of the product of its edges' lengths is
/// degenerate (a flat tet, a collinear triangle).
const DEGENERATE_FRACTION: f64 = 1e-12;

/// The rest positions of `nodes`, d numbers each, as the edge matrix [x₁ − x₀, …] (d×c).
fn edge_matrix(nodes: &[usize], positions: &[f64], d: usize) -> DMatrix<f64> {
    DMatrix::from_fn(d, nodes.len() - 1, |i, k| {
        positions[nodes[k + 1] * d + i] - positions[nodes[0] * d + i]
    })
}

/// The refusal of element `index`, whose rest measure (signed for a square element) is
/// `measure`.
fn refused(index: usize, measure: f64, what: &str) -> Error {
    Error::invalid(
        format!("elements[{index}]"),
        format!("rest {what} {}", shown(measure)),
        &format!(
            "an element of positive rest {what}, not degenerate, its nodes ordered so that \
             det D_m > 0"
        ),
    )
}

impl Element {
    /// [Sifakis 2012, element kernel] (unverified; checked against GenPD constraint_tet.cpp) A tetrahedron
    /// (4 nodes, d = 3) or a triangle in the plane (3 nodes, d = 2): D_m the rest edge matrix,
    /// V = det D_m / c!. Refuses (naming `elements[index]`) an inverted (det D_m < 0) or
    /// degenerate one.
    pub fn solid(index: usize, nodes: &[usize], positions: &[f64]) -> Result<Self> {
        let d = nodes.len() - 1;
        let dm = edge_matrix(nodes, positions, d);
        let factorial = if d == 3 { 6.0 } else { 2.0 };
        let measure = dm.determinant() / factorial;
        let what = if d == 3 { "volume" } else { "area" };
        let scale: f64 = dm.column_iter().map(|c| c.norm()).product();
        // Written so that a NaN measure is refused too.
        let positive = measure > DEGENERATE_FRACTION * scale;
        if !positive {
            return Err(refused(index, measure, what));
        }
        let dm_inverse = dm
            .try_inverse()
            .ok_or_else(|| refused(index, measure, what))?;
        Ok(Self {
            nodes: nodes.to_vec(),
            rest_gradient: DMatrix::identity(d, d),
            dm_inverse,
            measure,
        })
    }

    /// Ours (an interpretation: the element kernel of Sifakis and Barbič 2012 on a surface; no reference code checked) A membrane
    /// triangle in 3D (3 nodes, d = 3): its rest frame B = (b₁, b₂) with b₁ along the first
    /// edge and b₂ the second edge's part orthogonal to it, D_m = Bᵀ[x₁ − x₀, x₂ − x₀] (upper
    /// triangular, positive determinant), F₀ = B, V the rest area. Refuses a degenerate one.
    pub fn membrane(index: usize, nodes: &[usize], positions: &[f64]) -> Result<Self> {
        let edges = edge_matrix(nodes, positions, 3);
        let e1 = Vector3::new(edges[(0, 0)], edges[(1, 0)], edges[(2, 0)]);
        let e2 = Vector3::new(edges[(0, 1)], edges[(1, 1)], edges[(2, 1)]);
        let b1 = e1.normalize();
        let across = e2 - b1 * e2.dot(&b1);
        let measure = 0.5 * e1.norm() * across.norm();
        let positive = measure > DEGENERATE_FRACTION * e1.norm() * e2.norm();
        if !positive {
            return Err(refused(index, measure, "area"));
        }
        let b2 = across.normalize();
        let frame = DMatrix::from_columns(
            &[b1, b2].map(|b| nalgebra::DVector::from_column_slice(b.as_slice())),
        );
        let dm = frame.transpose() * &edges;
        let dm_inverse = dm
            .try_inverse()
            .ok_or_else(|| refused(index, measure, "area"))?;
        Ok(Self {
            nodes: nodes.to_vec(),
            rest_gradient: frame,
            dm_inverse,
            measure,
        })
    }

    /// Its nodes.
    pub fn nodes(&self) -> &[usize] {
        &self.nodes
    }

    /// Its rest volume (tet) or area (triangle).
    pub fn measure(&self) -> f64 {
        self.measure
    }

    /// True for a membrane's 3×2 F.
    pub fn is_membrane(&self) -> bool {
        !self.rest_gradient.is_square()
    }

    /// d, the numbers per node.
    pub fn space_dimension(&self) -> usize {
        self.rest_gradient.nrows()
    }

    /// [Sifakis 2012, element kernel] (unverified; checked against GenPD constraint_tet.cpp) F = F₀ + G with
    /// G = D_u D_m⁻¹, D_u the edge matrix of the displacements `u` (flat, d a node): formed from
    /// the displacements, not from D_s = D_m + D_u, so that G keeps its digits when it is small.
    pub fn deformation(&self, u: &[f64]) -> Deformation {
        let g = edge_matrix(&self.nodes, u, self.space_dimension()) * &self.dm_inverse;
        Deformation::from_displacement_gradient(&self.rest_gradient, g)
    }

    /// [Sifakis 2012, element kernel] (unverified; checked against GenPD constraint_tet.cpp) Adds the element's
    /// elastic forces to `forces` (flat, d a node): H = −V P D_m⁻ᵀ gives nodes 1..c their
    /// columns, and node 0 minus their sum.
    pub fn add_forces(&self, stress: &DMatrix<f64>, forces: &mut [f64]) {
        let d = self.space_dimension();
        let h = stress * self.dm_inverse.transpose() * (-self.measure);
        for (k, &node) in self.nodes[1..].iter().enumerate() {
            for i in 0..d {
                forces[node * d + i] += h[(i, k)];
                forces[self.nodes[0] * d + i] -= h[(i, k)];
            }
        }
    }

    /// ∂vec(F)/∂x, dc × d(c+1): F_ij = F₀ij + Σ_k (u_{k+1} − u_0)_i (D_m⁻¹)_kj, so
    /// ∂F_ij/∂(u_a)_m = δ_im (D_m⁻¹)_{a−1,j} for a ≥ 1 and −δ_im Σ_k (D_m⁻¹)_kj for a = 0.
    pub fn gradient_map(&self) -> DMatrix<f64> {
        let d = self.space_dimension();
        let c = self.dm_inverse.ncols();
        let mut map = DMatrix::zeros(d * c, d * (c + 1));
        for j in 0..c {
            let first: f64 = -self.dm_inverse.column(j).sum();
            for i in 0..d {
                map[(i + d * j, i)] = first;
                for a in 1..=c {
                    map[(i + d * j, a * d + i)] = self.dm_inverse[(a - 1, j)];
                }
            }
        }
        map
    }

    /// [Sifakis 2012, element kernel] (unverified; checked against GenPD constraint_tet.cpp) The element
    /// Hessian V (∂F/∂x)ᵀ C (∂F/∂x), d(c+1) square, from C = ∂P/∂F (exact or clamped) over
    /// vec(F); positive semidefinite when C is.
    pub fn hessian(&self, stress_derivative: &DMatrix<f64>) -> DMatrix<f64> {
        let map = self.gradient_map();
        map.transpose() * stress_derivative * map * self.measure
    }
}
