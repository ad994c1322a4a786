//! The thesis's test scene (§3.1, Figures 2-3) and the general N-node rope.
//!
//! The thesis states 10 nodes of 1 kg, 9 springs between consecutive nodes, both ends
//! fixed and stiffnesses 1e3 and 1e6 N/m. It does not state the geometry; the values below
//! were fitted to Table 1 and checked against Tables 2-3 (see `docs/thesis-scene.md`, a copy
//! of the project's scene specification): anchors 9 m apart, rest length equal to the initial
//! spacing, a straight start at rest, and g = 9.81 m/s².

use crate::error::{require_finite, require_positive, Error, Result};
use crate::system::{MassSpringSystem, Node, Spring, Vec3};

/// Number of nodes of the thesis rope (§3.1).
pub const THESIS_NODES: usize = 10;
/// Mass of every node, kg (§3.1).
pub const THESIS_NODE_MASS: f64 = 1.0;
/// Rest length of every spring, m (fitted: equal to the initial spacing, so the rope starts taut).
pub const THESIS_REST_LENGTH: f64 = 1.0;
/// Left anchor, m (fitted: the k = 1e6 reference half-period pins the separation to 9.00 ± 0.05 m).
pub const THESIS_ANCHOR_LEFT: [f64; 3] = [0.0, 0.0, 0.0];
/// Right anchor, m.
pub const THESIS_ANCHOR_RIGHT: [f64; 3] = [9.0, 0.0, 0.0];
/// Gravity along -y, m/s² (fitted on Table 1, `docs/thesis-scene.md`; the report's gravity
/// study runs 9.8 beside it).
pub const THESIS_GRAVITY: f64 = 9.81;
/// The two stiffnesses of §4.3, N/m.
pub const THESIS_STIFFNESSES: [f64; 2] = [1e3, 1e6];

/// A straight rope between two fixed anchors, nodes evenly spaced, at rest.
#[derive(Debug, Clone, PartialEq)]
pub struct RopeParams {
    /// Number of nodes, >= 3 (two anchors and at least one free node).
    pub nodes: usize,
    /// Mass of every free node, kg.
    pub node_mass: f64,
    /// Rest length of every spring, m.
    pub rest_length: f64,
    /// Stiffness of every spring, N/m.
    pub stiffness: f64,
    /// First node (fixed), m.
    pub anchor_left: Vec3,
    /// Last node (fixed), m.
    pub anchor_right: Vec3,
    /// Gravity magnitude along -y, m/s².
    pub gravity: f64,
}

impl RopeParams {
    /// The thesis rope (§3.1) at stiffness `k`.
    pub fn thesis(stiffness: f64) -> Self {
        Self {
            nodes: THESIS_NODES,
            node_mass: THESIS_NODE_MASS,
            rest_length: THESIS_REST_LENGTH,
            stiffness,
            anchor_left: Vec3::from(THESIS_ANCHOR_LEFT),
            anchor_right: Vec3::from(THESIS_ANCHOR_RIGHT),
            gravity: THESIS_GRAVITY,
        }
    }

    /// Builds the rope: nodes evenly spaced on the segment between the anchors, at rest.
    pub fn build(&self) -> Result<MassSpringSystem> {
        if self.nodes < 3 {
            return Err(Error::invalid("rope.nodes", self.nodes, "an integer >= 3"));
        }
        require_positive("rope.node_mass", self.node_mass)?;
        require_positive("rope.rest_length", self.rest_length)?;
        require_positive("rope.stiffness", self.stiffness)?;
        require_finite("rope.gravity", self.gravity)?;
        let last = self.nodes - 1;
        let nodes = (0..self.nodes)
            .map(|i| {
                let s = i as f64 / last as f64;
                Node {
                    mass: self.node_mass,
                    position: self.anchor_left + (self.anchor_right - self.anchor_left) * s,
                    velocity: Vec3::zeros(),
                    fixed: i == 0 || i == last,
                }
            })
            .collect();
        let springs = (0..last)
            .map(|i| Spring {
                a: i,
                b: i + 1,
                rest_length: self.rest_length,
                stiffness: self.stiffness,
                damping: 0.0,
            })
            .collect();
        MassSpringSystem::new(nodes, springs, Vec3::new(0.0, -self.gravity, 0.0))
    }
}

/// The thesis rope (§3.1) at stiffness `k` N/m.
pub fn thesis_rope(stiffness: f64) -> Result<MassSpringSystem> {
    RopeParams::thesis(stiffness).build()
}
