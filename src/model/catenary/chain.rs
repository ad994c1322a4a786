//! The discrete elastic chain: the exact static equilibrium of the simulated rope itself (the
//! module doc of [`super`], "Discrete elastic chain").

#![allow(non_snake_case)] // H, V0, EA, L and W: the symbols of the thesis and of Irvine

use super::{
    require_positive, shallow_cable_guess, solve_closure, validate_anchors, CatenaryError,
    Evaluation, THESIS_GRAVITY,
};
use nalgebra::{Matrix2, Vector2, Vector3};

/// A mass-spring chain hanging under gravity $`-g\,\hat{y}`$ between two fixed end nodes.
///
/// Node 0 sits at `anchor_a`, node $`N-1`$ at `anchor_b`; spring $`j`$ joins nodes $`j`$ and
/// $`j+1`$.
#[derive(Debug, Clone, PartialEq)]
pub struct ElasticChain {
    /// Position of node 0 (m); z must be 0.
    pub anchor_a: Vector3<f64>,
    /// Position of node $`N-1`$ (m); z must be 0 and x must exceed `anchor_a.x`.
    pub anchor_b: Vector3<f64>,
    /// Masses $`m_1 \dots m_{N-2}`$ of the free nodes (kg); entry $`j`$ belongs to node $`j+1`$.
    pub free_node_masses: Vec<f64>,
    /// Rest lengths $`l_{0,j}`$ of the $`N-1`$ springs (m).
    pub rest_lengths: Vec<f64>,
    /// Stiffnesses $`k_j`$ of the $`N-1`$ springs (N/m).
    pub stiffnesses: Vec<f64>,
    /// Gravitational acceleration $`g`$ (m/s²), acting along $`-y`$.
    pub gravity: f64,
}

/// Static equilibrium of an [`ElasticChain`].
#[derive(Debug, Clone, PartialEq)]
pub struct ChainEquilibrium {
    /// Node positions (m), z = 0; the first and last are the anchors.
    pub positions: Vec<Vector3<f64>>,
    /// Horizontal tension $`H`$ shared by every spring (N).
    pub H: f64,
    /// Vertical tension $`V_0`$ of spring 0, taken from node 0 towards node 1: negative when the
    /// rope leaves `anchor_a` downwards (N).
    pub V0: f64,
    /// Tension $`T_j = \sqrt{H^2 + V_j^2}`$ of each spring (N).
    pub tensions: Vec<f64>,
    /// Newton steps taken, on $`H`$ and $`V_0`$ together.
    pub newton_iterations: usize,
    /// Final closure residual $`\lvert \sum_j d_j - (B - A) \rvert`$ over the stretched length.
    pub relative_residual: f64,
}

impl ElasticChain {
    /// A chain of `node_count` nodes with equal free-node `mass` (kg), rest length `l0` (m) and
    /// stiffness `k` (N/m).
    pub fn uniform(
        node_count: usize,
        mass: f64,
        l0: f64,
        k: f64,
        anchor_a: Vector3<f64>,
        anchor_b: Vector3<f64>,
        gravity: f64,
    ) -> Result<Self, CatenaryError> {
        if node_count < 3 {
            return Err(CatenaryError::TooFewNodes { node_count });
        }
        require_positive("mass", None, mass)?;
        require_positive("l0", None, l0)?;
        require_positive("k", None, k)?;
        let chain = Self {
            anchor_a,
            anchor_b,
            free_node_masses: vec![mass; node_count - 2],
            rest_lengths: vec![l0; node_count - 1],
            stiffnesses: vec![k; node_count - 1],
            gravity,
        };
        chain.validate()?;
        Ok(chain)
    }

    /// The rope of thesis section 3.1: 10 nodes of 1 kg, $`l_0 = 1`$ m, anchors $`(0, 0)`$ and
    /// $`(9, 0)`$ m, $`g = 9.81\,\mathrm{m/s^2}`$, spring stiffness `k` (N/m).
    pub fn thesis_rope(k: f64) -> Result<Self, CatenaryError> {
        Self::uniform(
            10,
            1.0,
            1.0,
            k,
            Vector3::zeros(),
            Vector3::new(9.0, 0.0, 0.0),
            THESIS_GRAVITY,
        )
    }

    /// Number of nodes $`N`$, anchors included.
    pub fn node_count(&self) -> usize {
        self.rest_lengths.len() + 1
    }

    /// Solves the closure condition for $`(H, V_0)`$ and lays the springs out from `anchor_a`.
    pub fn solve_equilibrium(&self) -> Result<ChainEquilibrium, CatenaryError> {
        self.validate()?;
        let chord = (self.anchor_b - self.anchor_a).xy();
        // V_j = V0 + offset_j, where offset_j is the weight of free nodes 1..=j.
        let vertical_offsets: Vec<f64> = std::iter::once(0.0)
            .chain(self.free_node_masses.iter().scan(0.0, |weight, &m| {
                *weight += self.gravity * m;
                Some(*weight)
            }))
            .collect();
        let springs = || {
            self.rest_lengths
                .iter()
                .zip(&self.stiffnesses)
                .zip(&vertical_offsets)
                .map(|((&l0, &k), &offset)| (l0, k, offset))
        };

        let evaluate = |H: f64, V0: f64| {
            let mut residual = -chord;
            let mut jacobian = Matrix2::zeros();
            let mut stretched_length = 0.0;
            for (l0, k, offset) in springs() {
                let V = V0 + offset;
                let T = H.hypot(V);
                residual += (l0 / T + 1.0 / k) * Vector2::new(H, V);
                // The rest-length part only turns with the tension; the elastic part grows with it.
                jacobian += l0 / T.powi(3) * Matrix2::new(V * V, -H * V, -H * V, H * H)
                    + Matrix2::identity() / k;
                stretched_length += l0 + T / k;
            }
            Evaluation {
                residual,
                jacobian,
                length_scale: stretched_length,
            }
        };

        let guess = shallow_cable_guess(
            chord,
            self.rest_lengths.iter().sum(),
            vertical_offsets.last().copied().unwrap_or(0.0),
            self.stiffnesses.iter().map(|k| 1.0 / k).sum(),
        );
        let solution = solve_closure("discrete elastic chain", guess, evaluate)?;
        let (H, V0) = (solution.unknowns.x, solution.unknowns.y);

        let mut positions = Vec::with_capacity(self.node_count());
        let mut tensions = Vec::with_capacity(self.rest_lengths.len());
        let mut node = self.anchor_a;
        positions.push(node);
        for (l0, k, offset) in springs() {
            let V = V0 + offset;
            let T = H.hypot(V);
            tensions.push(T);
            node += (l0 / T + 1.0 / k) * Vector3::new(H, V, 0.0);
            positions.push(node);
        }
        // The accumulated end misses anchor_b by the rounding-level residual; the simulation
        // pins that node exactly, and so does the reference.
        if let Some(last) = positions.last_mut() {
            *last = self.anchor_b;
        }

        Ok(ChainEquilibrium {
            positions,
            H,
            V0,
            tensions,
            newton_iterations: solution.iterations,
            relative_residual: solution.relative_residual,
        })
    }

    fn validate(&self) -> Result<(), CatenaryError> {
        let spring_count = self.rest_lengths.len();
        if spring_count < 2 {
            return Err(CatenaryError::TooFewNodes {
                node_count: spring_count + 1,
            });
        }
        if self.stiffnesses.len() != spring_count {
            return Err(CatenaryError::LengthMismatch {
                field: "stiffnesses",
                found: self.stiffnesses.len(),
                expected: spring_count,
            });
        }
        if self.free_node_masses.len() != spring_count - 1 {
            return Err(CatenaryError::LengthMismatch {
                field: "free_node_masses",
                found: self.free_node_masses.len(),
                expected: spring_count - 1,
            });
        }
        validate_anchors(&self.anchor_a, &self.anchor_b)?;
        require_positive("gravity", None, self.gravity)?;
        for (field, values) in [
            ("free_node_masses", &self.free_node_masses),
            ("rest_lengths", &self.rest_lengths),
            ("stiffnesses", &self.stiffnesses),
        ] {
            for (index, &value) in values.iter().enumerate() {
                require_positive(field, Some(index), value)?;
            }
        }
        Ok(())
    }
}
