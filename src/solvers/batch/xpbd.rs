//! XPBD (Algorithm 2) in lanes: [`crate::solvers::xpbd::Xpbd`]'s step at [`Lanes4`], four runs of the
//! thesis rope's chain ([`super::projective::Rope`]; any dt, compliance, masses and iteration
//! counts).

use super::projective::Rope;
use super::{iterate_lanes, LaneSolver, LaneStates, WIDTH};
use crate::integrators::time_stepper::TimeStepper;
use crate::model::lanes::{load_points, load_values, Lanes4};
use crate::model::system::{MassSpringSystem, State};
use crate::solvers::incidence::{Ends, SpringGraph};
use crate::solvers::xpbd::{Coefficients, Scratch, Xpbd};
use nalgebra::Vector3;
use simba::simd::SimdValue;

/// Four XPBD runs of one topology, one per lane.
#[derive(Debug, Clone)]
pub struct XpbdLanes {
    rope: Rope,
    coefficients: Coefficients<Lanes4>,
    scratch: Scratch<Lanes4>,
    /// Iterations per step of each lane's run (0: no run).
    iterations: [usize; WIDTH],
    states: LaneStates,
    /// The positions of the lanes whose iterations are done, kept while the others sweep.
    done: Vec<Vector3<Lanes4>>,
}

impl XpbdLanes {
    /// Lanes for runs of `like`'s topology, none loaded yet; None unless it is the thesis
    /// rope's chain ([`Rope`]).
    pub fn new(like: &Xpbd) -> Option<Self> {
        let rope = rope_of(like.system())?;
        let (springs, nodes) = (rope.springs(), rope.nodes());
        let zero = Lanes4::splat(0.0);
        Some(Self {
            coefficients: Coefficients {
                dt: zero,
                rest_length: vec![zero; springs],
                alpha_tilde: vec![zero; springs],
                inverse_denominator: vec![zero; springs],
                w: vec![zero; nodes],
                external_acceleration: vec![Vector3::zeros(); nodes],
            },
            scratch: Scratch::new(springs, nodes),
            rope,
            iterations: [0; WIDTH],
            states: LaneStates::new(nodes),
            done: vec![Vector3::zeros(); nodes],
        })
    }
}

/// `system`'s springs as the batches' [`Rope`], if they are its chain.
fn rope_of(system: &MassSpringSystem) -> Option<Rope> {
    Rope::of(&Ends::of(system))
}

impl LaneSolver for XpbdLanes {
    type Run = Xpbd;

    fn load(&mut self, lane: usize, run: &Xpbd, state: &State) {
        assert!(
            run.counts_iterations() && rope_of(run.system()).is_some(),
            "a batch holds runs of the thesis rope that count their iterations"
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
        let (rope, lambda) = (&self.rope, &mut self.scratch.lambda);
        iterate_lanes(&self.iterations, &mut self.states.x, &mut self.done, |x| {
            c.sweep(rope, x, lambda)
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
