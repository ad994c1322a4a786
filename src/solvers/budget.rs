//! What a run may cost, estimated before it starts (issue 27): the memory a solver needs on a
//! scene and the adaptive steps of Dormand-Prince 5(4), for `mss` to check against
//! `--max-memory` and `--max-work`; and the memory this process may use.
//!
//! **The memory model is measured**, not derived: the peak resident memory of one step of every
//! solver, `/usr/bin/time -f %M mss --solver S --max-time 0.001 --scene rope --nodes N` (a
//! chain: a banded factor) at N = 1e5 and 4e5, and `--scene sheet --n n` (a mesh: 4 springs a
//! node) at n = 100 and 200, gives a slope per node ([`per_node_kib`]); the estimate is that
//! slope, raised by [`MARGIN`], over the nodes (or the springs, where there are more of them
//! per node than in the measured scenes), grown by [`GROWTH`] per doubling beyond the measured
//! sizes, plus [`BASE_BYTES`].
//!
//! Backward Euler's sparse factor grows faster than linearly with the nodes: `make timing`
//! counts 243, 311, 391 and 462 non-zeros of its factor per node on the sheet at n = 40, 80,
//! 160 and 320 (`report/timing/scaling.csv`), some 38 more per doubling of the nodes (N log N
//! under faer's fill-reducing ordering, not the bandwidth's n per node), and `mss` peaks at
//! 7.4, 7.7, 8.3, 8.5 and 8.9 KiB a node at n = 40, 80, 160, 240 and 320 (1.6 KiB a node on the
//! banded rope, flat from 1e5 to 1e6 nodes). At n = 1000 the factor alone is 5.9e8 non-zeros,
//! 4.7 GB, the allocation that aborted in `shared/docs/reliability-cases.md` \[7\]; the estimate
//! there is 13 GB, the extrapolated measurement 10 GB.

use crate::model::system::MassSpringSystem;
use crate::solvers::registry::{SolverId, SolverParams};

/// The process's own memory before the scene: the binary, its libraries, the allocator.
pub const BASE_BYTES: f64 = 16.0 * 1024.0 * 1024.0;

/// The factor over the measured slopes: the estimate is an upper bound of the measurements.
pub const MARGIN: f64 = 1.25;

/// Growth of the memory per node per doubling of the nodes beyond the measured sizes, relative
/// (Backward Euler's 0.24 KiB over 8.5 KiB a node is 0.03; Liu 2013's sparse factor 0.05).
pub const GROWTH: f64 = 0.05;

/// Nodes of the largest measured mesh (the sheet at n = 200) and chain (the rope).
const MEASURED_MESH_NODES: f64 = 40_000.0;
const MEASURED_CHAIN_NODES: f64 = 400_000.0;

/// Springs a node of the measured mesh has (the sheet: two structural, two shear).
const MESH_SPRINGS_PER_NODE: f64 = 4.0;

/// A scene as the memory model sees it.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Shape {
    pub nodes: u64,
    pub springs: u64,
    /// Whether every spring joins nodes at most [`CHAIN_BANDWIDTH`] apart in their order, so
    /// that the solvers' matrices are banded (the rope), not a general sparse mesh.
    pub chain: bool,
}

/// The largest index difference of a spring's nodes that keeps Backward Euler's 3n × 3n
/// matrix within the banded factorisation's bandwidth (`linear::BANDED_MAX_BANDWIDTH` = 40:
/// 3·12 + 2 = 38).
pub const CHAIN_BANDWIDTH: usize = 12;

impl Shape {
    /// The shape of a built system.
    pub fn of(system: &MassSpringSystem) -> Self {
        let bandwidth = system
            .springs()
            .iter()
            .map(|s| s.a.abs_diff(s.b))
            .max()
            .unwrap_or(0);
        Self {
            nodes: system.len() as u64,
            springs: system.springs().len() as u64,
            chain: bandwidth <= CHAIN_BANDWIDTH,
        }
    }
}

/// The measured slope of a solver's peak memory, KiB a node, on a chain and on a mesh (see the
/// module documentation); a solver not measured yet gets the largest, Backward Euler's.
pub fn per_node_kib(id: SolverId) -> (f64, f64) {
    match id {
        SolverId::BackwardEuler | SolverId::DampedBackwardEuler => (1.60, 8.50),
        SolverId::Pbd => (0.38, 0.77),
        SolverId::Xpbd | SolverId::XpbdSubsteps => (0.39, 0.77),
        // Liu's run alone in its solve's order (stop 44), measured again: before it 0.54 /
        // 3.04, 1.17 / 5.23 and 0.96 / 3.02 KiB a node (the table had 0.51 / 2.17, 1.14 / 4.10
        // and 0.83 / 2.37 from before the sheets' panels).
        SolverId::FastMassSpring => (0.66, 2.76),
        SolverId::AdmmPd => (0.45, 2.02),
        SolverId::ChebyshevLiu => (1.36, 4.94),
        SolverId::ChebyshevAdmm => (0.92, 4.06),
        SolverId::AndersonLiu => (1.03, 2.97),
        SolverId::AndersonAdmm => (1.03, 4.36),
        SolverId::DampedAdmm => (0.56, 2.42),
        SolverId::Lbfgs => (0.60, 1.78),
        SolverId::Vbd => (0.47, 0.88),
        SolverId::ExplicitEuler | SolverId::SymplecticEuler => (0.41, 0.52),
        SolverId::Rk4 => (0.45, 0.57),
        SolverId::Rk45 => (0.64, 0.75),
        #[allow(unreachable_patterns)] // a solver added later is estimated conservatively
        _ => (1.60, 8.50),
    }
}

/// Bytes a vector of the iteration's unknowns takes per node or spring, for the windows of
/// L-BFGS and Anderson: two vectors of three coordinates a pair.
const WINDOW_BYTES: f64 = 2.0 * 3.0 * 8.0;

/// The window the measurements ran with (both solvers' default).
const MEASURED_WINDOW: f64 = 5.0;

/// The estimated peak memory, in bytes, of solver `id` with `params` on a scene of `shape`.
pub fn memory_bytes(id: SolverId, params: &SolverParams, shape: Shape) -> f64 {
    let (chain, mesh) = per_node_kib(id);
    let nodes = shape.nodes as f64;
    let springs = shape.springs as f64;
    let (kib, size, measured) = if shape.chain {
        (chain, nodes.max(springs), MEASURED_CHAIN_NODES)
    } else {
        (
            mesh,
            nodes.max(springs / MESH_SPRINGS_PER_NODE),
            MEASURED_MESH_NODES,
        )
    };
    let growth = 1.0 + GROWTH * (nodes.max(1.0).log2() - measured.log2()).max(0.0);
    let window = match id {
        SolverId::Lbfgs => (params.history as f64 - MEASURED_WINDOW).max(0.0) * nodes,
        SolverId::AndersonLiu | SolverId::AndersonAdmm => {
            (params.window as f64 - MEASURED_WINDOW).max(0.0) * nodes.max(springs)
        }
        _ => 0.0,
    };
    BASE_BYTES + size * kib * 1024.0 * MARGIN * growth + window * WINDOW_BYTES
}

/// Dormand-Prince 5(4)'s stability bound on the negative real axis, $`h|\lambda| \le 3.3`$ (its
/// stability polynomial $`1 + z + \dots + z^5/120 + z^6/600`$; on the imaginary axis it is only
/// marginally stable, and its error control holds the step near this bound on a stiff scene).
pub const DOPRI_STABILITY: f64 = 3.3;

/// Force evaluations of one attempted Dormand-Prince step (seven stages, the first the last of
/// the step before).
pub const DOPRI_EVALUATIONS: f64 = 6.0;

/// An upper bound on the fastest rate of the scene's motion, 1/s: by Gershgorin's theorem on
/// $`M^{-1}K`$, $`\omega_i^2 \le 2\sum_j k_{ij}/m_i`$ for each free node $`i`$, and its damping rate
/// $`d_i = (2\sum_j c_{ij} + k_f)/m_i`$ with spring damping $`c`$ and drag $`k_f`$; $`|\lambda| \le
/// \omega_i + d_i`$ (springs at or beyond their rest length; a scene's check refuses crushed ones).
pub fn fastest_rate(system: &MassSpringSystem, drag: f64) -> f64 {
    let n = system.len();
    let (mut stiffness, mut damping) = (vec![0.0; n], vec![0.0; n]);
    for s in system.springs() {
        for i in [s.a, s.b] {
            stiffness[i] += s.stiffness;
            damping[i] += s.damping;
        }
    }
    system
        .nodes()
        .iter()
        .enumerate()
        .filter(|(_, node)| !node.fixed)
        .map(|(i, node)| {
            (2.0 * stiffness[i] / node.mass).sqrt() + (2.0 * damping[i] + drag) / node.mass
        })
        .fold(0.0, f64::max)
}

/// The adaptive steps Dormand-Prince takes over `duration` s, estimated: the fastest rate over
/// the stability bound, at least one step per output interval `dt`.
pub fn adaptive_steps(system: &MassSpringSystem, drag: f64, duration: f64, dt: f64) -> f64 {
    let intervals = (duration / dt).ceil();
    (duration * fastest_rate(system, drag) / DOPRI_STABILITY)
        .ceil()
        .max(intervals)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::model::scene::{RopeParams, SheetParams};

    /// The estimate is above the measurements it was fitted on, and grows with the sheet
    /// faster than linearly for Backward Euler.
    #[test]
    fn backward_euler_on_the_sheet_is_estimated_above_its_measured_peak() {
        let params = SolverParams::default();
        // Measured peaks (KiB) of `mss --scene sheet --n n --max-time 0.001`.
        for (n, kib) in [(40u64, 17_288.0), (160, 218_720.0), (320, 913_572.0)] {
            let system = SheetParams::spec(n as usize, 1e6).build().unwrap();
            let shape = Shape::of(&system);
            assert!(!shape.chain);
            let estimate = memory_bytes(SolverId::BackwardEuler, &params, shape);
            assert!(estimate > kib * 1024.0, "n = {n}: {estimate:e}");
            assert!(
                estimate < 2.0 * kib * 1024.0 + BASE_BYTES,
                "n = {n}: {estimate:e}"
            );
        }
        let rope = Shape::of(&RopeParams::thesis(1e6).build().unwrap());
        assert!(rope.chain);
        let per_node = |nodes: u64| {
            let shape = Shape {
                nodes,
                springs: 4 * nodes,
                chain: false,
            };
            (memory_bytes(SolverId::BackwardEuler, &params, shape) - BASE_BYTES) / nodes as f64
        };
        assert!(per_node(1_000_000) > 1.1 * per_node(40_000));
    }

    /// The thesis rope at k = 1e6: sqrt(2·2e6 / 1 kg) = 2000 1/s is its bound.
    #[test]
    fn the_fastest_rate_of_the_thesis_rope_is_its_gershgorin_bound() {
        let rope = RopeParams::thesis(1e6).build().unwrap();
        assert!((fastest_rate(&rope, 0.0) - 2000.0).abs() < 1e-9);
        assert_eq!(
            adaptive_steps(&rope, 0.0, 1.0, 0.1),
            (2000.0 / 3.3f64).ceil()
        );
        assert_eq!(adaptive_steps(&rope, 0.0, 1.0, 1e-4), 1e4);
    }
}
