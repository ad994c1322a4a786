//! Liu 2013 (Algorithm 3) in lanes: [`crate::solvers::fast_mass_spring::FastMassSpring`]'s step at
//! [`Lanes4`], four runs of the same rope topology and fixed nodes (any dt, stiffness, masses,
//! iteration counts, and a first iterate of (a) or (b), [`FirstIterate`]).

use super::projective::ProjectiveLanes;
use super::{LaneSolver, LaneStates};
use crate::integrators::time_stepper::TimeStepper;
use crate::model::lanes::{load_values, Lanes4};
use crate::model::system::State;
use crate::solvers::fast_mass_spring::{
    global_rhs, inertial_rhs, spring_directions, FastMassSpring, FirstIterate,
};
use nalgebra::Vector3;
use simba::simd::SimdValue;

/// Four Liu 2013 runs of one topology, one per lane.
#[derive(Debug, Clone)]
pub struct LiuLanes {
    /// The scene, the first iterate, the iterations and the finish ([`ProjectiveLanes`]).
    core: ProjectiveLanes,
    dt2_f_ext: Vec<Lanes4>,
    // The step's buffers, as in the run alone (column-major, 3n; one d per spring).
    b: Vec<Lanes4>,
    d: Vec<Vector3<Lanes4>>,
    scale: Vec<Lanes4>,
}

impl LiuLanes {
    /// Lanes for runs of `like`'s topology and fixed nodes, none loaded yet; None unless it is
    /// the thesis rope's chain ([`super::projective::Rope`]) with a tridiagonal global solve.
    pub fn new(like: &FastMassSpring) -> Option<Self> {
        let system = like.system();
        let (n, s) = (system.len(), system.springs().len());
        let zero = Lanes4::splat(0.0);
        Some(Self {
            core: ProjectiveLanes::new(system, like.incidence(), &like.own_step().a)?,
            dt2_f_ext: vec![zero; 3 * n],
            b: vec![zero; 3 * n],
            d: vec![Vector3::zeros(); s],
            scale: vec![zero; s],
        })
    }
}

impl LaneSolver for LiuLanes {
    type Run = FastMassSpring;

    fn load(&mut self, lane: usize, run: &FastMassSpring, state: &State) {
        let system = run.system();
        assert!(
            self.core.holds(
                system,
                run.counts_iterations(),
                run.first_iterate(),
                &[FirstIterate::Previous, FirstIterate::Inertial]
            ),
            "a batch of Liu runs holds runs of one topology and fixed set that count their \
             iterations and start at (a) or (b)"
        );
        let own = run.own_step();
        self.core.load(
            lane,
            system,
            run.dt(),
            run.incidence(),
            &own.a,
            state,
            run.iterations(),
            run.first_iterate(),
        );
        load_values(&mut self.dt2_f_ext, lane, &own.dt2_f_ext);
    }

    fn clear(&mut self, lane: usize) {
        self.core.clear(lane);
    }

    /// [`FastMassSpring`]'s step (Algorithm 3) in every lane; a lane whose iterations are done
    /// keeps its iterate while the others iterate on.
    fn step(&mut self) {
        // 2.1 and the first iterate.
        let core = &mut self.core;
        inertial_rhs(
            &core.states.x,
            &core.states.v,
            &core.masses,
            core.dt,
            &self.dt2_f_ext,
            &mut self.b,
        );
        core.begin_step(None);
        // 2.2-2.8.
        let dt2 = core.dt * core.dt;
        let (b, d, scale) = (&self.b, &mut self.d, &mut self.scale);
        // The iteration reads the iterate alone (b and A are the step's): lanes stop at a
        // fixed point.
        core.iterate(true, |scene, iterate| {
            spring_directions(scene.incidence, iterate, scene.rest_lengths, d, scale);
            global_rhs(scene.incidence, b, d, dt2, iterate);
            scene.a.solve(iterate, scene.x_n);
        });
        // Erratum: Algorithm 3 omits the velocity update.
        core.finish_step();
    }

    fn states(&self) -> &LaneStates {
        &self.core.states
    }

    fn states_mut(&mut self) -> &mut LaneStates {
        &mut self.core.states
    }
}
