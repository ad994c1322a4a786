//! The mass-spring model (thesis §2.1 and §3.1; the tutorial's particles and springs).
//!
//! One model serves every solver: nodes with mass, position, velocity and a fixed flag
//! (the tutorial's "anchored" particle), springs between two nodes with rest length,
//! stiffness and an optional damping coefficient (the tutorial's damped spring), and a
//! uniform gravity. The state that a time stepper advances is the pair of arrays
//! [`State::x`], [`State::v`]; the system holds what does not change during a run.

use crate::error::{require_finite, require_non_negative, require_positive, Error, Result};
use crate::model::lanes::{each_spring_force, Lane, SpringForce, SpringInputs, TwoEnds};
use crate::model::spring::{self, SpringArrays};
use nalgebra::Vector3;

pub use crate::model::Vec3;

/// A point mass.
#[derive(Debug, Clone, PartialEq)]
pub struct Node {
    /// Mass in kg; must be > 0 (a fixed node keeps its mass, its inverse mass is taken as 0).
    pub mass: f64,
    /// Initial position in m.
    pub position: Vec3,
    /// Initial velocity in m/s.
    pub velocity: Vec3,
    /// A fixed (anchored) node never moves.
    pub fixed: bool,
}

/// A Hookean spring between nodes `a` and `b` (thesis Eqs 1-4), optionally damped along its
/// axis (the tutorial's damped spring).
#[derive(Debug, Clone, PartialEq)]
pub struct Spring {
    pub a: usize,
    pub b: usize,
    /// Rest length $`l_0`$ in m, > 0.
    pub rest_length: f64,
    /// Stiffness $`k`$ in N/m, >= 0.
    pub stiffness: f64,
    /// Axial damping $`k_d`$ in N·s/m, >= 0: the tutorial's force model; the thesis's solvers
    /// reject a non-zero value ([`MassSpringSystem::require_undamped_springs`]).
    pub damping: f64,
}

/// A validated mass-spring system.
#[derive(Debug, Clone, PartialEq)]
pub struct MassSpringSystem {
    nodes: Vec<Node>,
    springs: Vec<Spring>,
    gravity: Vec3,
}

/// Positions and velocities, the state every time stepper advances.
#[derive(Debug, Clone, PartialEq)]
pub struct State {
    pub x: Vec<Vec3>,
    pub v: Vec<Vec3>,
}

impl State {
    /// `n` nodes at the origin, at rest (scratch for the integrators' stages).
    pub fn zeros(n: usize) -> Self {
        Self {
            x: vec![Vec3::zeros(); n],
            v: vec![Vec3::zeros(); n],
        }
    }

    /// Kinetic energy $`\frac12\sum_i m_i |v_i|^2`$ (thesis §4.2, convention 1).
    pub fn kinetic_energy(&self, system: &MassSpringSystem) -> f64 {
        system
            .nodes
            .iter()
            .zip(&self.v)
            .map(|(node, v)| 0.5 * node.mass * v.norm_squared())
            .sum()
    }

    /// True when every coordinate is finite.
    pub fn is_finite(&self) -> bool {
        self.x
            .iter()
            .chain(&self.v)
            .all(|p| p.iter().all(|c| c.is_finite()))
    }
}

/// The most nodes a system may have: a node's index fits in 32 bits, as the solvers keep
/// the springs' ends ([`crate::solvers::projective::Ends`], which says why).
pub const MAX_NODES: usize = u32::MAX as usize;

/// Rejects a node count above [`MAX_NODES`].
fn require_node_count(nodes: usize) -> Result<()> {
    if nodes > MAX_NODES {
        return Err(Error::invalid(
            "nodes",
            nodes,
            &format!("at most {MAX_NODES} nodes (a node's index is kept in 32 bits)"),
        ));
    }
    Ok(())
}

impl MassSpringSystem {
    /// Builds a system, rejecting any value outside its range with the field's name.
    pub fn new(nodes: Vec<Node>, springs: Vec<Spring>, gravity: Vec3) -> Result<Self> {
        require_node_count(nodes.len())?;
        for (i, node) in nodes.iter().enumerate() {
            require_positive(format!("nodes[{i}].mass"), node.mass)?;
            for c in 0..3 {
                require_finite(format!("nodes[{i}].position[{c}]"), node.position[c])?;
                require_finite(format!("nodes[{i}].velocity[{c}]"), node.velocity[c])?;
            }
        }
        for (j, s) in springs.iter().enumerate() {
            for (name, index) in [("a", s.a), ("b", s.b)] {
                if index >= nodes.len() {
                    return Err(Error::invalid(
                        format!("springs[{j}].{name}"),
                        index,
                        &format!("a node index in 0..{}", nodes.len()),
                    ));
                }
            }
            if s.a == s.b {
                return Err(Error::invalid(
                    format!("springs[{j}].b"),
                    s.b,
                    "a node other than springs[j].a",
                ));
            }
            require_positive(format!("springs[{j}].rest_length"), s.rest_length)?;
            require_non_negative(format!("springs[{j}].stiffness"), s.stiffness)?;
            require_non_negative(format!("springs[{j}].damping"), s.damping)?;
        }
        for c in 0..3 {
            require_finite(format!("gravity[{c}]"), gravity[c])?;
        }
        if !nodes.iter().any(|n| !n.fixed) {
            return Err(Error::invalid(
                "nodes[*].fixed",
                "all fixed",
                "at least one free node",
            ));
        }
        Ok(Self {
            nodes,
            springs,
            gravity,
        })
    }

    /// The nodes (with their initial state).
    pub fn nodes(&self) -> &[Node] {
        &self.nodes
    }

    /// The springs.
    pub fn springs(&self) -> &[Spring] {
        &self.springs
    }

    /// Gravity acceleration in m/s².
    pub fn gravity(&self) -> Vec3 {
        self.gravity
    }

    /// Number of nodes.
    pub fn len(&self) -> usize {
        self.nodes.len()
    }

    /// Never true: a validated system has at least one free node.
    pub fn is_empty(&self) -> bool {
        self.nodes.is_empty()
    }

    /// The initial state stored in the nodes.
    pub fn initial_state(&self) -> State {
        State {
            x: self.nodes.iter().map(|n| n.position).collect(),
            v: self.nodes.iter().map(|n| n.velocity).collect(),
        }
    }

    /// Inverse masses $`w_i = 1/m_i`$, and $`w_i = 0`$ for fixed nodes (thesis §3.3, Müller 2007).
    pub fn inverse_masses(&self) -> Vec<f64> {
        self.nodes
            .iter()
            .map(|n| if n.fixed { 0.0 } else { 1.0 / n.mass })
            .collect()
    }

    /// Returns the same system with every spring's stiffness replaced by `stiffness`.
    pub fn with_stiffness(&self, stiffness: f64) -> Result<Self> {
        let mut springs = self.springs.clone();
        for s in &mut springs {
            s.stiffness = stiffness;
        }
        Self::new(self.nodes.clone(), springs, self.gravity)
    }

    /// Returns the same system with another gravity vector.
    pub fn with_gravity(&self, gravity: Vec3) -> Result<Self> {
        Self::new(self.nodes.clone(), self.springs.clone(), gravity)
    }

    /// Rejects solvers that divide by the stiffness (XPBD's compliance $`\alpha = 1/k`$,
    /// ADMM's weight $`\omega = \sqrt{k}`$) when a spring has $`k = 0`$.
    pub fn require_positive_stiffness(&self) -> Result<()> {
        for (j, s) in self.springs.iter().enumerate() {
            require_positive(format!("springs[{j}].stiffness"), s.stiffness)?;
        }
        Ok(())
    }

    /// Rejects a spring with damping $`k_d \ne 0`$ for the thesis's solvers, whose model is
    /// undamped springs (their damping, if any, is Rayleigh's: [`crate::integrators::damping`]); the
    /// tutorial's particle system is the one that models `Spring::damping`.
    pub fn require_undamped_springs(&self) -> Result<()> {
        match self.springs.iter().position(|s| s.damping != 0.0) {
            Some(j) => Err(Error::invalid(
                format!("springs[{j}].damping"),
                self.springs[j].damping,
                "0: the thesis's solvers model undamped springs (Rayleigh damping is a solver \
                 parameter); the tutorial's particle system models spring damping",
            )),
            None => Ok(()),
        }
    }

    /// External force on every node: gravity $`m_i g`$ (zero on fixed nodes, which never move).
    pub fn external_force(&self, i: usize) -> Vec3 {
        let node = &self.nodes[i];
        if node.fixed {
            Vec3::zeros()
        } else {
            node.mass * self.gravity
        }
    }

    /// Total force on every node at positions `x`: springs (Eq. 3) plus gravity. Fixed nodes get 0.
    pub fn forces(&self, x: &[Vec3], f: &mut [Vec3]) {
        for (i, fi) in f.iter_mut().enumerate() {
            *fi = self.external_force(i);
        }
        // Four springs at a time, summed in spring order: the bits of one at a time.
        each_spring_force(&self.springs, &Hooke(x), |s, fa| {
            add_to_free_ends(
                f,
                (s.a, s.b),
                self.nodes[s.a].fixed,
                self.nodes[s.b].fixed,
                fa,
            );
        });
    }

    /// The force Jacobian $`dF/dx`$ of every spring (Eq. 4) assembled densely, $`3n\times3n`$ with
    /// unknown $`3i + c`$ for coordinate $`c`$ of node $`i`$; fixed nodes are included. For
    /// analysis (modes, stability) and as an independent check of the solvers' sparse assembly.
    pub fn force_jacobian_dense(&self, x: &[Vec3]) -> nalgebra::DMatrix<f64> {
        let n = 3 * self.nodes.len();
        let mut k = nalgebra::DMatrix::<f64>::zeros(n, n);
        for s in &self.springs {
            let j = spring::force_jacobian(&x[s.a], &x[s.b], s.rest_length, s.stiffness);
            // dF_a/dx_a = dF_b/dx_b = J, dF_a/dx_b = dF_b/dx_a = -J.
            for (p, q, sign) in [
                (s.a, s.a, 1.0),
                (s.b, s.b, 1.0),
                (s.a, s.b, -1.0),
                (s.b, s.a, -1.0),
            ] {
                let mut block = k.fixed_view_mut::<3, 3>(3 * p, 3 * q);
                block += sign * j;
            }
        }
        k
    }

    /// Potential energy: springs (Eq. 2) plus gravity, $`\sum E_j - \sum_i m_i\,g\cdot x_i`$.
    pub fn potential_energy(&self, x: &[Vec3]) -> f64 {
        let elastic: f64 = self
            .springs
            .iter()
            .map(|s| spring::energy(&x[s.a], &x[s.b], s.rest_length, s.stiffness))
            .sum();
        let gravitational: f64 = self
            .nodes
            .iter()
            .zip(x)
            .map(|(n, xi)| -n.mass * self.gravity.dot(xi))
            .sum();
        elastic + gravitational
    }
}

impl TwoEnds for Spring {
    fn ends(&self) -> (usize, usize) {
        (self.a, self.b)
    }
}

/// Eq. (3): the springs' forces and gravity for runs in lanes ([`crate::model::lanes`]),
/// [`MassSpringSystem::forces`] in each lane, from each node's `external` force (zero on a
/// fixed node), the `fixed` flags and the `springs` of the lanes' runs (one topology). The
/// same sums in the same order as one run's, so each lane has its run's bits.
pub fn forces_of<T: Lane>(
    external: &[Vector3<T>],
    fixed: &[bool],
    springs: SpringArrays<T>,
    x: &[Vector3<T>],
    f: &mut [Vector3<T>],
) {
    f.copy_from_slice(external);
    let values = springs.rest_lengths.iter().zip(springs.stiffness);
    for (&(a, b), (&l0, &k)) in springs.ends.iter().zip(values) {
        let fa = spring::force(&x[a], &x[b], l0, k);
        add_to_free_ends(f, (a, b), fixed[a], fixed[b], fa);
    }
}

/// Eq. (3)'s sum: a spring's force `fa` on its first end, `-fa` on its second, fixed ends
/// left out.
#[inline(always)]
fn add_to_free_ends<T: Lane>(
    f: &mut [Vector3<T>],
    (a, b): (usize, usize),
    a_fixed: bool,
    b_fixed: bool,
    fa: Vector3<T>,
) {
    if !a_fixed {
        f[a] += fa;
    }
    if !b_fixed {
        f[b] -= fa;
    }
}

/// Eq. (3) at positions `x`, for [`each_spring_force`].
struct Hooke<'a>(&'a [Vec3]);

impl SpringForce<Spring> for Hooke<'_> {
    #[inline(always)]
    fn on_first_end<T: Lane>(&self, spring: &impl SpringInputs<Spring, T>) -> Vector3<T> {
        let (x_a, x_b) = spring.ends(self.0);
        spring::force(
            &x_a,
            &x_b,
            spring.value(|s| s.rest_length),
            spring.value(|s| s.stiffness),
        )
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::model::scene::{thesis_rope, SheetParams};

    /// The forces four springs at a time have the bits of one at a time, in spring order
    /// (Eq. 3 at `f64`, fixed ends skipped): on the thesis rope (nine springs, one left
    /// over after two groups of four, both anchors) and the 10 × 10 sheet, each moved off its
    /// start so that every spring is stretched or compressed.
    #[test]
    fn forces_four_springs_at_a_time_have_the_bits_of_one_at_a_time() {
        for system in [
            thesis_rope(1e3).unwrap(),
            SheetParams::spec(10, 1e6).build().unwrap(),
        ] {
            let x: Vec<Vec3> = system
                .nodes()
                .iter()
                .enumerate()
                .map(|(i, n)| {
                    n.position + 0.01 * Vec3::new((i as f64).sin(), 0.3, (2.0 * i as f64).cos())
                })
                .collect();
            let mut f = vec![Vec3::zeros(); x.len()];
            system.forces(&x, &mut f);
            let mut one_at_a_time: Vec<Vec3> =
                (0..x.len()).map(|i| system.external_force(i)).collect();
            for s in system.springs() {
                let fa = spring::force(&x[s.a], &x[s.b], s.rest_length, s.stiffness);
                if !system.nodes()[s.a].fixed {
                    one_at_a_time[s.a] += fa;
                }
                if !system.nodes()[s.b].fixed {
                    one_at_a_time[s.b] -= fa;
                }
            }
            let bits = |f: &[Vec3]| {
                f.iter()
                    .flat_map(|p| p.iter().map(|c| c.to_bits()))
                    .collect::<Vec<_>>()
            };
            assert_eq!(bits(&f), bits(&one_at_a_time));
        }
    }

    /// A node count past [`MAX_NODES`] is refused naming the field (it cannot be built here:
    /// the check is on the count alone), and the largest allowed count passes.
    #[test]
    fn a_node_count_past_32_bits_is_refused() {
        let err = require_node_count(MAX_NODES + 1).unwrap_err().to_string();
        assert!(
            err.contains("nodes") && err.contains(&MAX_NODES.to_string()),
            "{err}"
        );
        assert!(require_node_count(MAX_NODES).is_ok());
    }
}
