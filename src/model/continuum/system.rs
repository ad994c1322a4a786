//! A continuum system (`docs/fem-scenes.md`): nodes with rest positions, masses and fixed
//! flags, linear elements each with its energy and material, gravity and external nodal
//! forces; its potential energy, its forces and its sparse Hessian over the free nodes.
//!
//! The unknowns are the nodes' displacements u from the rest shape (flat, d a node), not their
//! positions: every F is then formed from displacement differences
//! ([`Element::deformation`]), which keeps the digits of strains of 1e-5 at E = 1e9.

use super::element::Element;
use super::energy::EnergyKind;
use super::lame::Lame;
use crate::error::{require_finite, require_non_negative, require_positive, Error, Result};
use crate::model::linear::SymmetricMatrix;

/// An element's material: its energy and Lamé parameters (per unit rest area, N/m, for
/// triangles, whose thickness is folded into them).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Material {
    pub energy: EnergyKind,
    pub lame: Lame,
}

/// The kind of every element of a mesh.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum ElementKind {
    /// 4 nodes in 3D.
    Tetrahedron,
    /// 3 nodes in the plane (d = 2).
    PlaneTriangle,
    /// 3 nodes in 3D, a surface.
    Membrane,
}

impl ElementKind {
    /// d, the coordinates of a node.
    pub fn space_dimension(self) -> usize {
        if self == ElementKind::PlaneTriangle {
            2
        } else {
            3
        }
    }

    /// The nodes of an element.
    pub fn nodes(self) -> usize {
        if self == ElementKind::Tetrahedron {
            4
        } else {
            3
        }
    }
}

/// The masses of the nodes.
#[derive(Debug, Clone, PartialEq)]
pub enum Masses {
    /// Lumped from a density (kg/m³, or kg/m² for triangles): each element gives ρV/(c + 1)
    /// to each of its nodes.
    Lumped(f64),
    /// Given per node, kg (the membrane's uniform masses of the sheet).
    PerNode(Vec<f64>),
}

/// What a continuum system is built from; every vector is flat, d numbers a node.
#[derive(Debug, Clone, PartialEq)]
pub struct Mesh {
    pub kind: ElementKind,
    /// Rest positions, m.
    pub positions: Vec<f64>,
    /// Each element's nodes, ordered so that det D_m > 0 (tets, plane triangles).
    pub elements: Vec<Vec<usize>>,
    pub masses: Masses,
    pub fixed: Vec<bool>,
    /// The starting displacement, m; a fixed node keeps its own (the patch test moves them).
    pub displacement: Vec<f64>,
    /// External forces on the nodes, N.
    pub loads: Vec<f64>,
    /// Gravity, m/s² (d components).
    pub gravity: Vec<f64>,
}

/// A validated continuum system.
#[derive(Debug, Clone, PartialEq)]
pub struct ContinuumSystem {
    dimension: usize,
    positions: Vec<f64>,
    elements: Vec<Element>,
    material: Material,
    masses: Vec<f64>,
    fixed: Vec<bool>,
    start: Vec<f64>,
    /// Weight plus external force on each node (flat), N.
    nodal_loads: Vec<f64>,
    /// Each node's place among the free nodes.
    free_index: Vec<Option<usize>>,
}

/// Checks that a flat vector has `expected` entries, all finite.
fn require_flat(field: &str, values: &[f64], expected: usize) -> Result<()> {
    if values.len() != expected {
        return Err(Error::invalid(
            field,
            format!("{} numbers", values.len()),
            &format!("{expected} numbers (d a node)"),
        ));
    }
    for (k, &v) in values.iter().enumerate() {
        require_finite(format!("{field}[{k}]"), v)?;
    }
    Ok(())
}

impl ContinuumSystem {
    /// Builds and checks a system: every field's size and values, each element's nodes (in
    /// range, distinct) and rest shape (refused, naming `elements[i]`, if degenerate or
    /// inverted), an energy defined on the elements (no linear membrane), and a free node.
    pub fn new(mesh: Mesh, material: Material) -> Result<Self> {
        let d = mesh.kind.space_dimension();
        let n = mesh.fixed.len();
        require_flat("positions", &mesh.positions, n * d)?;
        require_flat("displacement", &mesh.displacement, n * d)?;
        require_flat("loads", &mesh.loads, n * d)?;
        require_flat("gravity", &mesh.gravity, d)?;
        require_positive("material.mu", material.lame.mu)?;
        require_finite("material.lambda", material.lame.lambda)?;
        if mesh.kind == ElementKind::Membrane && !material.energy.model().supports_membranes() {
            return Err(Error::invalid(
                "energy",
                material.energy.name(),
                "an energy defined on membranes (not linear: a flat linear membrane has no \
                 stiffness across its plane)",
            ));
        }
        let mut elements = Vec::with_capacity(mesh.elements.len());
        for (e, nodes) in mesh.elements.iter().enumerate() {
            if nodes.len() != mesh.kind.nodes() {
                return Err(Error::invalid(
                    format!("elements[{e}]"),
                    format!("{} nodes", nodes.len()),
                    &format!("{} nodes", mesh.kind.nodes()),
                ));
            }
            for (k, &a) in nodes.iter().enumerate() {
                if a >= n || nodes[..k].contains(&a) {
                    return Err(Error::invalid(
                        format!("elements[{e}][{k}]"),
                        a,
                        &format!("a node index in 0..{n}, distinct from the element's others"),
                    ));
                }
            }
            elements.push(match mesh.kind {
                ElementKind::Membrane => Element::membrane(e, nodes, &mesh.positions)?,
                _ => Element::solid(e, nodes, &mesh.positions)?,
            });
        }
        let masses = match mesh.masses {
            Masses::Lumped(density) => {
                require_positive("density", density)?;
                let mut masses = vec![0.0; n];
                for element in &elements {
                    let share = density * element.measure() / element.nodes().len() as f64;
                    for &a in element.nodes() {
                        masses[a] += share;
                    }
                }
                masses
            }
            Masses::PerNode(masses) => {
                if masses.len() != n {
                    return Err(Error::invalid(
                        "masses",
                        masses.len(),
                        &format!("{n} masses"),
                    ));
                }
                for (i, &m) in masses.iter().enumerate() {
                    require_non_negative(format!("masses[{i}]"), m)?;
                }
                masses
            }
        };
        let mut free = 0;
        let free_index = mesh
            .fixed
            .iter()
            .map(|&fixed| {
                (!fixed).then(|| {
                    free += 1;
                    free - 1
                })
            })
            .collect();
        if free == 0 {
            return Err(Error::invalid(
                "fixed",
                "every node",
                "at least one free node",
            ));
        }
        let nodal_loads = (0..n * d)
            .map(|k| masses[k / d] * mesh.gravity[k % d] + mesh.loads[k])
            .collect();
        let mut start = mesh.displacement;
        for (k, u) in start.iter_mut().enumerate() {
            if !mesh.fixed[k / d] {
                *u = 0.0;
            }
        }
        Ok(Self {
            dimension: d,
            positions: mesh.positions,
            elements,
            material,
            masses,
            fixed: mesh.fixed,
            start,
            nodal_loads,
            free_index,
        })
    }

    /// d, the coordinates of a node.
    pub fn dimension(&self) -> usize {
        self.dimension
    }

    /// The number of nodes.
    pub fn node_count(&self) -> usize {
        self.fixed.len()
    }

    /// The rest positions (flat).
    pub fn rest_positions(&self) -> &[f64] {
        &self.positions
    }

    /// The elements.
    pub fn elements(&self) -> &[Element] {
        &self.elements
    }

    /// The material of every element.
    pub fn material(&self) -> Material {
        self.material
    }

    /// The nodes' masses, kg.
    pub fn masses(&self) -> &[f64] {
        &self.masses
    }

    /// Whether node `i` is fixed.
    pub fn is_fixed(&self, i: usize) -> bool {
        self.fixed[i]
    }

    /// The starting displacement: the fixed nodes' own, zero elsewhere.
    pub fn start(&self) -> &[f64] {
        &self.start
    }

    /// The largest load (weight plus external force) on a free node, N: the scale of the
    /// equilibrium residual.
    pub fn largest_load(&self) -> f64 {
        let d = self.dimension;
        (0..self.node_count())
            .filter(|&i| !self.fixed[i])
            .map(|i| {
                let load = &self.nodal_loads[i * d..i * d + d];
                load.iter().map(|f| f * f).sum::<f64>().sqrt()
            })
            .fold(0.0, f64::max)
    }

    /// The potential energy at displacements `u`: Σ V Ψ(F) − Σ (m g + f)·u, J.
    pub fn energy(&self, u: &[f64]) -> f64 {
        self.energy_and_magnitude(u).0
    }

    /// The energy and the sum of its terms' magnitudes, Σ V |Ψ| + Σ |(m g + f)·u|: the scale
    /// of its round-off, which a line search must not mistake for a decrease.
    pub fn energy_and_magnitude(&self, u: &[f64]) -> (f64, f64) {
        let model = self.material.energy.model();
        let (mut energy, mut magnitude) = (0.0, 0.0);
        for e in &self.elements {
            let term = e.measure() * model.density(&e.deformation(u), &self.material.lame);
            energy += term;
            magnitude += term.abs();
        }
        for (f, u) in self.nodal_loads.iter().zip(u) {
            energy -= f * u;
            magnitude += (f * u).abs();
        }
        (energy, magnitude)
    }

    /// The forces on every node at `u` (flat; the fixed nodes' included): elastic, weight and
    /// external, −∂E/∂u.
    pub fn forces(&self, u: &[f64]) -> Vec<f64> {
        let model = self.material.energy.model();
        let mut forces = self.nodal_loads.clone();
        for e in &self.elements {
            e.add_forces(
                &model.stress(&e.deformation(u), &self.material.lame),
                &mut forces,
            );
        }
        forces
    }

    /// The largest force component on a free node at `u`, N.
    pub fn residual(&self, u: &[f64]) -> f64 {
        let d = self.dimension;
        self.forces(u)
            .iter()
            .enumerate()
            .filter(|(k, _)| !self.fixed[k / d])
            .map(|(_, f)| f.abs())
            // NaN wins, so that a non-finite state never reads as converged (f64::max would
            // skip it).
            .fold(0.0, |m, f| if f.is_nan() || f > m { f } else { m })
    }

    /// The free nodes' coordinates of a flat vector, in free-node order.
    pub fn free_part(&self, full: &[f64]) -> Vec<f64> {
        let d = self.dimension;
        (0..full.len())
            .filter(|k| !self.fixed[k / d])
            .map(|k| full[k])
            .collect()
    }

    /// `u` moved by `step` (free coordinates, in free-node order) times `alpha`.
    pub fn moved(&self, u: &[f64], step: &[f64], alpha: f64) -> Vec<f64> {
        let d = self.dimension;
        let mut out = u.to_vec();
        for (k, x) in out.iter_mut().enumerate() {
            if let Some(f) = self.free_index[k / d] {
                *x += alpha * step[f * d + k % d];
            }
        }
        out
    }

    /// The Hessian ∂²E/∂u² over the free nodes' coordinates (free-node order), assembled from
    /// the element Hessians with the exact ∂P/∂F or, `projected`, its clamp (positive
    /// semidefinite then).
    pub fn hessian(&self, u: &[f64], projected: bool) -> SymmetricMatrix {
        let d = self.dimension;
        let free_nodes = self.free_index.iter().flatten().count();
        let mut edges = Vec::new();
        for e in &self.elements {
            for (k, &a) in e.nodes().iter().enumerate() {
                for &b in &e.nodes()[k + 1..] {
                    if let (Some(a), Some(b)) = (self.free_index[a], self.free_index[b]) {
                        edges.push((a, b));
                    }
                }
            }
        }
        let mut h = SymmetricMatrix::from_node_graph(free_nodes, d, &edges);
        let model = self.material.energy.model();
        for e in &self.elements {
            let deformation = e.deformation(u);
            let c = if projected {
                model.clamped_stress_derivative(&deformation, &self.material.lame)
            } else {
                model.stress_derivative(&deformation, &self.material.lame)
            };
            let block = e.hessian(&c);
            for (a, &node_a) in e.nodes().iter().enumerate() {
                let Some(fa) = self.free_index[node_a] else {
                    continue;
                };
                for (b, &node_b) in e.nodes().iter().enumerate() {
                    let Some(fb) = self.free_index[node_b] else {
                        continue;
                    };
                    for i in 0..d {
                        for j in 0..d {
                            h.add(fa * d + i, fb * d + j, block[(a * d + i, b * d + j)]);
                        }
                    }
                }
            }
        }
        h
    }
}
