//! ADMM-PD (Algorithm 4) in lanes: [`AdmmPd`]'s step at [`Lanes4`], four runs of the same rope
//! topology and fixed nodes (any dt, stiffness, masses, iteration counts, and a first iterate
//! of (a), (b) or line 2.1's $`\tilde x`$, [`FirstIterate`]).
//!
//! The dual $`\bar u`$ is reset every step (line 2.2), so a lane whose iterations are done may
//! go on changing its $`z`$ and $`\bar u`$ unread: only its iterate is kept
//! ([`super::iterate_lanes`]).

use super::{iterate_lanes, lane_mask, LaneSolver, LaneStates, WIDTH};
use crate::integrators::first_iterate::{inertia, predicted, pull, FirstIterate};
use crate::integrators::time_stepper::TimeStepper;
use crate::model::lanes::{load_points, load_values, select, Lanes4};
use crate::model::system::{State, Vec3};
use crate::solvers::admm::{global_rhs_of, local_step_of, AdmmPd, LocalStepSprings};
use crate::solvers::projective::{to_columns, GlobalSolveLanes, SpringIncidence};
use nalgebra::Vector3;
use simba::simd::SimdValue;

/// Four ADMM-PD runs of one topology, one per lane.
#[derive(Debug, Clone)]
pub struct AdmmLanes {
    /// Whether each node is fixed (the same in every lane).
    fixed: Vec<bool>,
    dt: Lanes4,
    masses: Vec<Lanes4>,
    rest_lengths: Vec<Lanes4>,
    stiffness: Vec<Lanes4>,
    /// $`\omega_i`$ and $`dt^2\omega_i^2`$, per lane.
    omega: Vec<Lanes4>,
    dt2_omega2: Vec<Lanes4>,
    /// $`dt^2 m_i^{-1} f_{ext,i}`$ per node ([`pull`]).
    pull: Vec<Vector3<Lanes4>>,
    /// $`D`$ of Eq (54), per lane.
    d: SpringIncidence<Lanes4>,
    /// $`A`$ (Algorithm 4 line 1.5), per lane.
    a: GlobalSolveLanes<Lanes4>,
    /// Iterations per step of each lane's run (0: no run).
    iterations: [usize; WIDTH],
    first_iterate: [FirstIterate; WIDTH],
    states: LaneStates,
    /// The first iterate, per node.
    first: Vec<Vector3<Lanes4>>,
    // The step's buffers, as in the run alone (column-major, 3n; one z and ū per spring).
    x_n: Vec<Lanes4>,
    m_x_tilde: Vec<Lanes4>,
    iterate: Vec<Lanes4>,
    z: Vec<Vector3<Lanes4>>,
    u_bar: Vec<Vector3<Lanes4>>,
    /// Scratch of the local step, one value per spring.
    scale: Vec<Lanes4>,
    /// The iterate of the lanes whose iterations are done, kept while the others iterate.
    done: Vec<Lanes4>,
}

impl AdmmLanes {
    /// Lanes for runs of `like`'s topology and fixed nodes, none loaded yet; None unless its
    /// global solve is a tridiagonal one (a chain: the rope).
    pub fn new(like: &AdmmPd) -> Option<Self> {
        let system = like.system();
        let (n, s) = (system.len(), system.springs().len());
        let zero = Lanes4::splat(0.0);
        Some(Self {
            fixed: system.nodes().iter().map(|node| node.fixed).collect(),
            dt: zero,
            masses: vec![zero; n],
            rest_lengths: vec![zero; s],
            stiffness: vec![zero; s],
            omega: vec![zero; s],
            dt2_omega2: vec![zero; s],
            pull: vec![Vector3::zeros(); n],
            d: SpringIncidence::lanes(like.iterate_data().reduction()),
            a: GlobalSolveLanes::new(like.own_step())?,
            iterations: [0; WIDTH],
            first_iterate: [FirstIterate::Previous; WIDTH],
            states: LaneStates::new(n),
            first: vec![Vector3::zeros(); n],
            x_n: vec![zero; 3 * n],
            m_x_tilde: vec![zero; 3 * n],
            iterate: vec![zero; 3 * n],
            z: vec![Vector3::zeros(); s],
            u_bar: vec![Vector3::zeros(); s],
            scale: vec![zero; s],
            done: vec![zero; 3 * n],
        })
    }
}

impl LaneSolver for AdmmLanes {
    type Run = AdmmPd;

    fn load(&mut self, lane: usize, run: &AdmmPd, state: &State) {
        let system = run.system();
        assert!(
            run.counts_iterations()
                && matches!(
                    run.first_iterate(),
                    FirstIterate::Previous
                        | FirstIterate::Inertial
                        | FirstIterate::InertialPrediction
                )
                && system
                    .nodes()
                    .iter()
                    .map(|node| node.fixed)
                    .eq(self.fixed.iter().copied()),
            "a batch of ADMM-PD runs holds runs of one topology and fixed set that count their \
             iterations and start at (a), (b) or x̃"
        );
        let dt = run.dt();
        self.dt.replace(lane, dt);
        let masses: Vec<f64> = system.nodes().iter().map(|node| node.mass).collect();
        load_values(&mut self.masses, lane, &masses);
        let (rest_lengths, stiffness): (Vec<f64>, Vec<f64>) = system
            .springs()
            .iter()
            .map(|s| (s.rest_length, s.stiffness))
            .unzip();
        load_values(&mut self.rest_lengths, lane, &rest_lengths);
        load_values(&mut self.stiffness, lane, &stiffness);
        load_values(&mut self.omega, lane, run.omega());
        load_values(&mut self.dt2_omega2, lane, run.iterate_data().dt2_omega2());
        let pulls: Vec<Vec3> = (0..system.len()).map(|i| pull(system, dt, i)).collect();
        load_points(&mut self.pull, lane, &pulls);
        self.d.load_lane(lane, run.iterate_data().reduction());
        self.a.load_lane(lane, run.own_step());
        self.states.load(lane, state);
        self.iterations[lane] = run.iterations();
        self.first_iterate[lane] = run.first_iterate();
    }

    fn clear(&mut self, lane: usize) {
        self.iterations[lane] = 0;
    }

    /// [`AdmmPd`]'s step (Algorithm 4) in every lane; a lane whose iterations are done keeps
    /// its iterate while the others iterate on.
    fn step(&mut self) {
        // 2.1: x̃ (as Mx̃) and the first iterate.
        to_columns(&self.states.x, &mut self.x_n);
        let n = self.states.x.len();
        let at_x_tilde =
            lane_mask(|lane| self.first_iterate[lane] == FirstIterate::InertialPrediction);
        let inertial = lane_mask(|lane| self.first_iterate[lane] == FirstIterate::Inertial);
        for (i, first) in self.first.iter_mut().enumerate() {
            let (x, v, mass) = (self.states.x[i], self.states.v[i], self.masses[i]);
            let x_tilde = match self.fixed[i] {
                true => x,
                false => predicted(x, v, self.dt, self.pull[i]),
            };
            for c in 0..3 {
                self.m_x_tilde[c * n + i] = mass * x_tilde[c];
            }
            *first = match self.fixed[i] {
                true => x,
                false => select(
                    at_x_tilde,
                    x_tilde,
                    select(inertial, inertia(x, v, self.dt), x),
                ),
            };
        }
        to_columns(&self.first, &mut self.iterate);
        // 2.2: ū = 0 every step.
        self.u_bar.fill(Vector3::zeros());
        // 2.3-2.10.
        let (d, a, x_n, m_x_tilde) = (&self.d, &self.a, &self.x_n, &self.m_x_tilde);
        let (omega, dt2_omega2) = (&self.omega, &self.dt2_omega2);
        let (rest_lengths, stiffness) = (&self.rest_lengths, &self.stiffness);
        let (z, u_bar, scale) = (&mut self.z, &mut self.u_bar, &mut self.scale);
        iterate_lanes(&self.iterations, &mut self.iterate, &mut self.done, |x| {
            let springs = LocalStepSprings {
                rest_lengths,
                stiffness,
                omega,
            };
            local_step_of(d, x, springs, scale, z, u_bar);
            global_rhs_of(d, m_x_tilde, z, u_bar, dt2_omega2, x);
            a.solve(x, x_n);
        });
        // 2.11
        self.states.finish_step(&self.iterate, self.dt);
    }

    fn states(&self) -> &LaneStates {
        &self.states
    }

    fn states_mut(&mut self) -> &mut LaneStates {
        &mut self.states
    }
}
