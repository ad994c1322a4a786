//! Liu 2013 (Algorithm 3) in lanes: [`crate::solvers::fast_mass_spring::FastMassSpring`]'s step at
//! [`Lanes4`], four runs of the same rope topology and fixed nodes (any dt, stiffness, masses,
//! iteration counts, and a first iterate of (a) or (b), [`FirstIterate`]).

use super::{iterate_lanes, lane_mask, LaneSolver, LaneStates, WIDTH};
use crate::integrators::first_iterate::inertia;
use crate::integrators::time_stepper::TimeStepper;
use crate::model::lanes::{load_values, select, Lanes4};
use crate::model::system::State;
use crate::solvers::fast_mass_spring::{
    global_rhs, inertial_rhs, spring_directions, FastMassSpring, FirstIterate,
};
use crate::solvers::projective::{to_columns, GlobalSolveLanes, SpringIncidence};
use nalgebra::Vector3;
use simba::simd::SimdValue;

/// Four Liu 2013 runs of one topology, one per lane.
#[derive(Debug, Clone)]
pub struct LiuLanes {
    /// Whether each node is fixed (the same in every lane).
    fixed: Vec<bool>,
    dt: Lanes4,
    masses: Vec<Lanes4>,
    rest_lengths: Vec<Lanes4>,
    /// $`J`$ of Eqs (26), (53), per lane.
    j: SpringIncidence<Lanes4>,
    /// $`A`$ (Algorithm 3 line 1.4), per lane.
    a: GlobalSolveLanes<Lanes4>,
    dt2_f_ext: Vec<Lanes4>,
    /// Iterations per step of each lane's run (0: no run).
    iterations: [usize; WIDTH],
    /// Whether each lane's run starts at (b) $`x_n + dt\,v_n`$ rather than (a) $`x_n`$.
    inertial: [bool; WIDTH],
    states: LaneStates,
    /// The first iterate, per node.
    first: Vec<Vector3<Lanes4>>,
    // The step's buffers, as in the run alone (column-major, 3n; one d per spring).
    x_n: Vec<Lanes4>,
    b: Vec<Lanes4>,
    iterate: Vec<Lanes4>,
    d: Vec<Vector3<Lanes4>>,
    scale: Vec<Lanes4>,
    /// The iterate of the lanes whose iterations are done, kept while the others iterate.
    done: Vec<Lanes4>,
}

impl LiuLanes {
    /// Lanes for runs of `like`'s topology and fixed nodes, none loaded yet; None unless its
    /// global solve is a tridiagonal one (a chain: the rope).
    pub fn new(like: &FastMassSpring) -> Option<Self> {
        let system = like.system();
        let (n, s) = (system.len(), system.springs().len());
        let zero = Lanes4::splat(0.0);
        Some(Self {
            fixed: system.nodes().iter().map(|node| node.fixed).collect(),
            dt: zero,
            masses: vec![zero; n],
            rest_lengths: vec![zero; s],
            j: SpringIncidence::lanes(like.incidence()),
            a: GlobalSolveLanes::new(&like.own_step().a)?,
            dt2_f_ext: vec![zero; 3 * n],
            iterations: [0; WIDTH],
            inertial: [false; WIDTH],
            states: LaneStates::new(n),
            first: vec![Vector3::zeros(); n],
            x_n: vec![zero; 3 * n],
            b: vec![zero; 3 * n],
            iterate: vec![zero; 3 * n],
            d: vec![Vector3::zeros(); s],
            scale: vec![zero; s],
            done: vec![zero; 3 * n],
        })
    }
}

impl LaneSolver for LiuLanes {
    type Run = FastMassSpring;

    fn load(&mut self, lane: usize, run: &FastMassSpring, state: &State) {
        let system = run.system();
        assert!(
            run.counts_iterations()
                && matches!(
                    run.first_iterate(),
                    FirstIterate::Previous | FirstIterate::Inertial
                )
                && system
                    .nodes()
                    .iter()
                    .map(|node| node.fixed)
                    .eq(self.fixed.iter().copied()),
            "a batch of Liu runs holds runs of one topology and fixed set that count their \
             iterations and start at (a) or (b)"
        );
        self.dt.replace(lane, run.dt());
        load_values(&mut self.masses, lane, run.masses());
        load_values(&mut self.rest_lengths, lane, run.rest_lengths());
        self.j.load_lane(lane, run.incidence());
        let own = run.own_step();
        self.a.load_lane(lane, &own.a);
        load_values(&mut self.dt2_f_ext, lane, &own.dt2_f_ext);
        self.states.load(lane, state);
        self.iterations[lane] = run.iterations();
        self.inertial[lane] = run.first_iterate() == FirstIterate::Inertial;
    }

    fn clear(&mut self, lane: usize) {
        self.iterations[lane] = 0;
    }

    /// [`FastMassSpring`]'s step (Algorithm 3) in every lane; a lane whose iterations are done
    /// keeps its iterate while the others iterate on.
    fn step(&mut self) {
        // 2.1 and the first iterate.
        to_columns(&self.states.x, &mut self.x_n);
        inertial_rhs(
            &self.states.x,
            &self.states.v,
            &self.masses,
            self.dt,
            &self.dt2_f_ext,
            &mut self.b,
        );
        let inertial = lane_mask(|lane| self.inertial[lane]);
        for (first, ((&x, &v), &fixed)) in self
            .first
            .iter_mut()
            .zip(self.states.x.iter().zip(&self.states.v).zip(&self.fixed))
        {
            *first = match fixed {
                true => x,
                false => select(inertial, inertia(x, v, self.dt), x),
            };
        }
        to_columns(&self.first, &mut self.iterate);
        // 2.2-2.8.
        let dt2 = self.dt * self.dt;
        let (j, b, a, x_n) = (&self.j, &self.b, &self.a, &self.x_n);
        let (rest_lengths, d, scale) = (&self.rest_lengths, &mut self.d, &mut self.scale);
        iterate_lanes(
            &self.iterations,
            &mut self.iterate,
            &mut self.done,
            |iterate| {
                spring_directions(j, iterate, rest_lengths, d, scale);
                global_rhs(j, b, d, dt2, iterate);
                a.solve(iterate, x_n);
            },
        );
        // Erratum: Algorithm 3 omits the velocity update.
        self.states.finish_step(&self.iterate, self.dt);
    }

    fn states(&self) -> &LaneStates {
        &self.states
    }

    fn states_mut(&mut self) -> &mut LaneStates {
        &mut self.states
    }
}
