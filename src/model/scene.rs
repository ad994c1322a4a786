//! The thesis's test scene (§3.1, Figures 2-3), the general N-node rope, and the sheet (the rope
//! raised one dimension, `docs/sheet-scene.md`).
//!
//! The thesis states 10 nodes of 1 kg, 9 springs between consecutive nodes, both ends
//! fixed and stiffnesses 1e3 and 1e6 N/m. It does not state the geometry; the values below
//! were fitted to Table 1 and checked against Tables 2-3 (see `docs/thesis-scene.md`, a copy
//! of the project's scene specification): anchors 9 m apart, rest length equal to the initial
//! spacing, a straight start at rest, and g = 9.81 m/s².

use crate::error::{require_finite, require_positive, shown, Error, Result};
use crate::model::system::{MassSpringSystem, Node, Spring, Vec3};

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

/// Sheet side length, m: the rope's 9 m in both directions (`docs/sheet-scene.md`).
pub const SHEET_SIDE: f64 = 9.0;
/// Sheet total mass, kg, for every n: 1 kg per node at n = 10, like the rope.
pub const SHEET_TOTAL_MASS: f64 = 100.0;
/// Nodes per side of the default sheet.
pub const SHEET_NODES_PER_SIDE: usize = 10;

/// Bytes of the system a sheet node brings at most: its [`Node`] and its four springs (two
/// structural, two shear), before any solver's matrices.
pub const SHEET_BYTES_PER_NODE: u64 =
    (std::mem::size_of::<Node>() + 4 * std::mem::size_of::<Spring>()) as u64;

/// The memory assumed available where the system does not say (`/proc/meminfo`), in bytes.
const ASSUMED_MEMORY: u64 = 1 << 32;

/// The shortest start of a spring, as a fraction of its rest length: shorter, its direction
/// is lost (two nodes at one point have none) and the implicit solvers' matrices are indefinite.
pub const MIN_START_LENGTH_RATIO: f64 = 1e-6;

/// Refuses degenerate geometry, whatever the solver: a spring whose nodes start less than
/// [`MIN_START_LENGTH_RATIO`] of its rest length apart (`springs[j]`).
pub fn check_geometry(system: &MassSpringSystem) -> Result<()> {
    let nodes = system.nodes();
    for (j, s) in system.springs().iter().enumerate() {
        let length = (nodes[s.a].position - nodes[s.b].position).norm();
        // NaN (a non-finite position) is degenerate too.
        let long_enough = length >= MIN_START_LENGTH_RATIO * s.rest_length;
        if !long_enough {
            return Err(Error::invalid(
                format!("springs[{j}]"),
                format!(
                    "nodes {} and {} start {} m apart, rest length {} m",
                    s.a,
                    s.b,
                    shown(length),
                    shown(s.rest_length)
                ),
                &format!(
                    "a spring that starts at least {} of its rest length long (at length 0 it \
                     has no direction)",
                    shown(MIN_START_LENGTH_RATIO)
                ),
            ));
        }
    }
    Ok(())
}

/// The largest n whose sheet fits in `bytes` at [`SHEET_BYTES_PER_NODE`].
fn max_nodes_per_side(bytes: u64) -> u64 {
    ((bytes / SHEET_BYTES_PER_NODE) as f64).sqrt() as u64
}

/// Which corners of the sheet are held.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum SheetSupport {
    /// The four corners: the sheet of the specification.
    FourCorners,
    /// Corners (0, 0) and (n−1, 0), the two ends of the edge along x at z = 0: the sheet
    /// hangs from them like a cloth (Figure 1).
    TwoCorners,
}

/// The thesis rope woven into a square net (`docs/sheet-scene.md`): an n × n grid in the
/// horizontal plane y = 0, structural springs on the grid edges and both diagonals of every
/// cell as shear springs, all at rest length, at rest.
#[derive(Debug, Clone, PartialEq)]
pub struct SheetParams {
    /// Nodes per side n, >= 2, with at least one node not held (n >= 3 with four corners held);
    /// node (i, j) starts at (i·h, 0, j·h).
    pub nodes_per_side: usize,
    /// Grid spacing h, m (9 / (n − 1) in the specification).
    pub spacing: f64,
    /// Mass of every node, kg (100 / n² in the specification).
    pub node_mass: f64,
    /// Stiffness of every spring, N/m.
    pub stiffness: f64,
    /// Gravity magnitude along −y, m/s².
    pub gravity: f64,
    pub support: SheetSupport,
}

impl SheetParams {
    /// The specification's sheet: n nodes per side over 9 m, 100 kg in all, four corners held.
    pub fn spec(nodes_per_side: usize, stiffness: f64) -> Self {
        let n = nodes_per_side.max(2);
        Self {
            nodes_per_side,
            spacing: SHEET_SIDE / (n - 1) as f64,
            node_mass: SHEET_TOTAL_MASS / (n as f64 * n as f64),
            stiffness,
            gravity: THESIS_GRAVITY,
            support: SheetSupport::FourCorners,
        }
    }

    /// The same sheet held by other corners.
    pub fn with_support(mut self, support: SheetSupport) -> Self {
        self.support = support;
        self
    }

    /// Bytes that [`Self::build`] allocates for the nodes and springs of an n × n sheet (at most
    /// [`SHEET_BYTES_PER_NODE`] a node: one node and four springs); `None` if the count
    /// overflows. A solver needs several times more; this is the floor it is checked against.
    pub fn estimated_bytes(&self) -> Option<u64> {
        let n = u64::try_from(self.nodes_per_side).ok()?;
        n.checked_mul(n)?.checked_mul(SHEET_BYTES_PER_NODE)
    }

    /// Index of node (i, j).
    pub fn node(&self, i: usize, j: usize) -> usize {
        i * self.nodes_per_side + j
    }

    /// Builds the sheet: structural springs (i, j)–(i+1, j) and (i, j)–(i, j+1) of rest
    /// length h, shear springs on both diagonals of every cell of rest length √2·h.
    pub fn build(&self) -> Result<MassSpringSystem> {
        let n = self.nodes_per_side;
        if n < 2 {
            return Err(Error::invalid("sheet.nodes_per_side", n, "an integer >= 2"));
        }
        if self.support == SheetSupport::FourCorners && n == 2 {
            return Err(Error::invalid(
                "sheet.nodes_per_side",
                n,
                "an integer >= 3 with four corners held (at n = 2 every node is a held corner: \
                 no node is free)",
            ));
        }
        let limit = crate::platform::memory::available_memory().unwrap_or(ASSUMED_MEMORY);
        match self.estimated_bytes() {
            Some(bytes) if bytes <= limit => {}
            _ => {
                return Err(Error::invalid(
                    "sheet.nodes_per_side",
                    n,
                    &format!(
                        "at most {}: the sheet's nodes and springs take {SHEET_BYTES_PER_NODE} \
                         bytes a node, and {} MiB of memory are available",
                        max_nodes_per_side(limit),
                        limit >> 20
                    ),
                ))
            }
        }
        require_positive("sheet.spacing", self.spacing)?;
        require_positive("sheet.node_mass", self.node_mass)?;
        require_positive("sheet.stiffness", self.stiffness)?;
        require_finite("sheet.gravity", self.gravity)?;
        let last = n - 1;
        let held = |i: usize, j: usize| {
            let corner = (i == 0 || i == last) && (j == 0 || j == last);
            match self.support {
                SheetSupport::FourCorners => corner,
                SheetSupport::TwoCorners => corner && j == 0,
            }
        };
        let mut nodes = Vec::with_capacity(n * n);
        for i in 0..n {
            for j in 0..n {
                nodes.push(Node {
                    mass: self.node_mass,
                    position: Vec3::new(i as f64 * self.spacing, 0.0, j as f64 * self.spacing),
                    velocity: Vec3::zeros(),
                    fixed: held(i, j),
                });
            }
        }
        let spring = |a: usize, b: usize, rest_length: f64| Spring {
            a,
            b,
            rest_length,
            stiffness: self.stiffness,
            damping: 0.0,
        };
        let h = self.spacing;
        let diagonal = std::f64::consts::SQRT_2 * h;
        let mut springs = Vec::with_capacity(2 * n * last + 2 * last * last);
        for i in 0..n {
            for j in 0..n {
                if i < last {
                    springs.push(spring(self.node(i, j), self.node(i + 1, j), h));
                }
                if j < last {
                    springs.push(spring(self.node(i, j), self.node(i, j + 1), h));
                }
                if i < last && j < last {
                    springs.push(spring(self.node(i, j), self.node(i + 1, j + 1), diagonal));
                    springs.push(spring(self.node(i + 1, j), self.node(i, j + 1), diagonal));
                }
            }
        }
        MassSpringSystem::new(nodes, springs, Vec3::new(0.0, -self.gravity, 0.0))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_specification_sheet_has_its_counts_masses_and_corners() {
        for n in [3, 10, 20] {
            let params = SheetParams::spec(n, 1e3);
            let sheet = params.build().unwrap();
            let structural = 2 * n * (n - 1);
            let shear = 2 * (n - 1) * (n - 1);
            assert_eq!(sheet.springs().len(), structural + shear);
            let mass: f64 = sheet.nodes().iter().map(|node| node.mass).sum();
            assert!((mass - SHEET_TOTAL_MASS).abs() < 1e-9, "n = {n}: {mass} kg");
            let last = n - 1;
            let fixed: Vec<usize> = (0..n * n).filter(|&i| sheet.nodes()[i].fixed).collect();
            assert_eq!(fixed, [0, last, last * n, last * n + last]);
            let far = sheet.nodes()[params.node(last, last)].position;
            assert!((far - Vec3::new(SHEET_SIDE, 0.0, SHEET_SIDE)).norm() < 1e-12);
        }
        let two = SheetParams::spec(10, 1e3).with_support(SheetSupport::TwoCorners);
        let fixed = two
            .build()
            .unwrap()
            .nodes()
            .iter()
            .filter(|node| node.fixed)
            .count();
        assert_eq!(fixed, 2);
    }

    #[test]
    fn the_sheet_starts_with_every_spring_at_rest_length() {
        let sheet = SheetParams::spec(10, 1e6).build().unwrap();
        let x: Vec<Vec3> = sheet.nodes().iter().map(|node| node.position).collect();
        let mut f = vec![Vec3::zeros(); x.len()];
        sheet.forces(&x, &mut f);
        // Only gravity acts at the start: zero tension everywhere.
        for (node, force) in sheet.nodes().iter().zip(&f) {
            let gravity = if node.fixed {
                0.0
            } else {
                -node.mass * THESIS_GRAVITY
            };
            assert!(
                (force - Vec3::new(0.0, gravity, 0.0)).norm() < 1e-9,
                "{force:?}"
            );
        }
    }

    /// n < 2, a sheet whose every node is held, and a sheet too large for the memory (or for
    /// a 64-bit count) are named errors, found before anything is allocated.
    #[test]
    fn a_sheet_too_small_too_large_or_all_held_is_refused() {
        for n in [0, 1] {
            let err = SheetParams::spec(n, 1e3).build().unwrap_err().to_string();
            assert!(err.contains(&format!("sheet.nodes_per_side: {n}")), "{err}");
            assert!(err.contains(">= 2"), "{err}");
        }
        let err = SheetParams::spec(2, 1e3).build().unwrap_err().to_string();
        assert!(
            err.contains("sheet.nodes_per_side") && err.contains("no node is free"),
            "{err}"
        );
        let two = SheetParams::spec(2, 1e3).with_support(SheetSupport::TwoCorners);
        assert_eq!(
            two.build()
                .unwrap()
                .inverse_masses()
                .iter()
                .filter(|&&w| w > 0.0)
                .count(),
            2
        );
        for n in [1 << 20, 1 << 40, usize::MAX] {
            let err = SheetParams::spec(n, 1e3).build().unwrap_err().to_string();
            assert!(
                err.contains("sheet.nodes_per_side") && err.contains("MiB of memory"),
                "{err}"
            );
        }
    }

    #[test]
    fn a_bad_sheet_names_its_field() {
        let err = SheetParams::spec(2, 1e3).build().unwrap_err().to_string();
        assert!(err.contains("sheet.nodes_per_side"), "{err}");
        let mut params = SheetParams::spec(10, 1e3);
        params.stiffness = f64::NAN;
        let err = params.build().unwrap_err().to_string();
        assert!(err.contains("sheet.stiffness"), "{err}");
    }
}
