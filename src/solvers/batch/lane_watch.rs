//! What the run loop measures of a step, for every lane of a batch at once
//! ([`super::simulate_batch`]): the velocity damping of the runs that damp, then each lane's
//! kinetic energy and whether its state is finite, the operations
//! [`crate::integrators::time_stepper::Watch::after_step`] makes on a run alone, in the same
//! order, so the same bits ([`crate::model::lanes`]). A lane's state is then read out only
//! where the run needs it (its positions recorded, its end), not after every step.

use crate::model::lanes::{lane_mask, load_values, Lanes4, WIDTH};
use crate::model::system::MassSpringSystem;
use nalgebra::Vector3;
use simba::simd::{SimdBool, SimdPartialOrd, SimdValue};

/// The masses and damping factors of the runs in a batch's lanes.
#[derive(Debug, Clone)]
pub struct LaneWatch {
    /// Each node's mass, per lane.
    masses: Vec<Lanes4>,
    /// The damping factor of each lane's run, 1 for a run that does not damp.
    damping: Lanes4,
    /// The lanes whose runs damp.
    damps: [bool; WIDTH],
}

impl LaneWatch {
    /// For runs of `nodes` nodes, none loaded.
    pub fn new(nodes: usize) -> Self {
        Self {
            masses: vec![Lanes4::splat(0.0); nodes],
            damping: Lanes4::splat(1.0),
            damps: [false; WIDTH],
        }
    }

    /// Lane `lane` now holds a run of `system`, damped by `damping_factor` after each step if
    /// it is `Some`.
    pub fn load(&mut self, lane: usize, system: &MassSpringSystem, damping_factor: Option<f64>) {
        let masses: Vec<f64> = system.nodes().iter().map(|node| node.mass).collect();
        load_values(&mut self.masses, lane, &masses);
        self.damping.replace(lane, damping_factor.unwrap_or(1.0));
        self.damps[lane] = damping_factor.is_some();
    }

    /// The damping of every lane whose run damps (`Watch::after_step`'s $`v \leftarrow
    /// e^{-c\,dt} v`$; a lane that does not damp is left as it is), then each lane's kinetic
    /// energy $`\sum_i \tfrac12 m_i |v_i|^2`$ (`State::kinetic_energy`'s terms and sum in node
    /// order) and whether its positions and velocities are all finite.
    pub fn damp_and_measure(
        &self,
        x: &[Vector3<Lanes4>],
        v: &mut [Vector3<Lanes4>],
    ) -> [(f64, bool); WIDTH] {
        if self.damps.contains(&true) {
            let keep = lane_mask(|lane| !self.damps[lane]);
            for v in v.iter_mut() {
                *v = v.map(|c| c.select(keep, c * self.damping));
            }
        }
        // `Sum`'s own start for f64, whichever zero that is.
        let start: f64 = std::iter::empty::<f64>().sum();
        let half = Lanes4::splat(0.5);
        let ke = v
            .iter()
            .zip(&self.masses)
            .fold(Lanes4::splat(start), |sum, (v, &m)| {
                sum + half * m * v.norm_squared()
            });
        // 0·c is ±0 for a finite c and NaN for an infinite or NaN one.
        let zero = Lanes4::splat(0.0);
        let not_finite = x
            .iter()
            .chain(v.iter())
            .flat_map(|p| p.iter())
            .fold(zero, |sum, &c| sum + zero * c);
        let finite = not_finite.simd_eq(zero).bitmask();
        std::array::from_fn(|lane| (ke.extract(lane), finite & (1 << lane) != 0))
    }
}
