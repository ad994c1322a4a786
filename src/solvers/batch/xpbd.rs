//! XPBD (Algorithm 2) in lanes: [`crate::solvers::xpbd::Xpbd`]'s step at [`Lanes4`], four runs of the
//! same rope topology (any dt, compliance, masses and iteration counts).

use super::{iterate_lanes, LaneSolver, LaneStates, WIDTH};
use crate::integrators::time_stepper::TimeStepper;
use crate::model::lanes::{load_points, load_values, Lanes4};
use crate::model::system::{Spring, State};
use crate::solvers::xpbd::{Coefficients, Scratch, Xpbd};
use nalgebra::Vector3;
use simba::simd::SimdValue;

/// Four XPBD runs of one topology, one per lane.
#[derive(Debug, Clone)]
pub struct XpbdLanes {
    springs: Vec<Spring>,
    coefficients: Coefficients<Lanes4>,
    scratch: Scratch<Lanes4>,
    /// Iterations per step of each lane's run (0: no run).
    iterations: [usize; WIDTH],
    states: LaneStates,
    /// The positions of the lanes whose iterations are done, kept while the others sweep.
    done: Vec<Vector3<Lanes4>>,
}

impl XpbdLanes {
    /// Lanes for runs of `like`'s topology (its springs' end nodes), none loaded yet.
    pub fn new(like: &Xpbd) -> Self {
        let springs = like.system().springs().to_vec();
        let nodes = like.coefficients().w.len();
        let zero = Lanes4::splat(0.0);
        Self {
            coefficients: Coefficients {
                dt: zero,
                rest_length: vec![zero; springs.len()],
                alpha_tilde: vec![zero; springs.len()],
                inverse_denominator: vec![zero; springs.len()],
                w: vec![zero; nodes],
                external_acceleration: vec![Vector3::zeros(); nodes],
            },
            scratch: Scratch::new(springs.len(), nodes),
            springs,
            iterations: [0; WIDTH],
            states: LaneStates::new(nodes),
            done: vec![Vector3::zeros(); nodes],
        }
    }
}

impl LaneSolver for XpbdLanes {
    type Run = Xpbd;

    fn load(&mut self, lane: usize, run: &Xpbd, state: &State) {
        assert!(
            run.counts_iterations()
                && run.system().springs().len() == self.springs.len()
                && run
                    .system()
                    .springs()
                    .iter()
                    .zip(&self.springs)
                    .all(|(a, b)| (a.a, a.b) == (b.a, b.b)),
            "a batch holds runs of one topology that count their iterations"
        );
        let (into, from) = (&mut self.coefficients, run.coefficients());
        into.dt.replace(lane, from.dt);
        load_values(&mut into.rest_length, lane, &from.rest_length);
        load_values(&mut into.alpha_tilde, lane, &from.alpha_tilde);
        load_values(
            &mut into.inverse_denominator,
            lane,
            &from.inverse_denominator,
        );
        load_values(&mut into.w, lane, &from.w);
        load_points(
            &mut into.external_acceleration,
            lane,
            &from.external_acceleration,
        );
        self.states.load(lane, state);
        self.iterations[lane] = run.iterations();
    }

    fn clear(&mut self, lane: usize) {
        self.iterations[lane] = 0;
    }

    /// [`Xpbd`]'s step in every lane; a lane whose iterations are done keeps its positions
    /// while the others sweep on.
    fn step(&mut self) {
        let c = &self.coefficients;
        c.predict(&mut self.states.x, &self.states.v, &mut self.scratch);
        let (springs, lambda) = (&self.springs, &mut self.scratch.lambda);
        iterate_lanes(&self.iterations, &mut self.states.x, &mut self.done, |x| {
            c.sweep(springs, x, lambda)
        });
        c.velocities(&self.states.x, &mut self.states.v, &self.scratch);
    }

    fn states(&self) -> &LaneStates {
        &self.states
    }

    fn states_mut(&mut self) -> &mut LaneStates {
        &mut self.states
    }
}
