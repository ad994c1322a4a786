//! ADMM-PD (Algorithm 4) in lanes: [`AdmmPd`]'s step at [`Lanes4`], four runs of the same rope
//! topology and fixed nodes (any dt, stiffness, masses, weights, iteration counts, and a first
//! iterate of (a), (b) or line 2.1's $`\tilde x`$, [`FirstIterate`]): each an [`AdmmRun`].
//!
//! The dual $`\bar u`$ is reset every step (line 2.2), so a lane whose iterations are done may
//! go on changing its $`z`$ and $`\bar u`$ unread: only its iterate is kept
//! ([`super::iterate_lanes`]).

use super::projective::ProjectiveLanes;
use super::{LaneSolver, LaneStates};
use crate::integrators::first_iterate::{predicted, pull, FirstIterate};
use crate::integrators::time_stepper::TimeStepper;
use crate::model::lanes::{load_points, load_values, Lanes4};
use crate::model::system::{State, Vec3};
use crate::solvers::admm::{global_rhs_of, local_step_of, AdmmIterate, AdmmPd, LocalStepSprings};
use crate::solvers::projective::GlobalSolve;
use nalgebra::Vector3;
use simba::simd::SimdValue;
use std::marker::PhantomData;

/// What a lane loads of an ADMM-PD run ([`AdmmRun::lane_data`]).
pub struct AdmmLaneData<'a> {
    /// Iterations per step.
    pub iterations: usize,
    /// Where each step starts.
    pub first_iterate: FirstIterate,
    /// Whether each step runs its full count of iterations.
    pub counts_iterations: bool,
    /// The iteration's per-spring data ($`D`$, $`\omega_i`$, $`dt^2\omega_i^2`$).
    pub iterate: &'a AdmmIterate,
    /// $`A`$ of the run's step, prefactored (line 1.5).
    pub a: &'a GlobalSolve,
}

/// A run a lane can hold: Algorithm 4 as printed, with its own weights $`\omega_i`$, first
/// iterate and prefactored $`A`$, counting its iterations. [`AdmmPd`] is one; so is a forensic
/// variant that departs from Algorithm 4 in its start and weights only
/// ([`crate::studies::forensics::VariantAdmm`]), whose lanes are then that variant's runs bit for
/// bit.
pub trait AdmmRun: TimeStepper + Clone {
    /// What a lane loads of the run.
    fn lane_data(&self) -> AdmmLaneData<'_>;
}

impl AdmmRun for AdmmPd {
    fn lane_data(&self) -> AdmmLaneData<'_> {
        AdmmLaneData {
            iterations: self.iterations(),
            first_iterate: self.first_iterate(),
            counts_iterations: self.counts_iterations(),
            iterate: self.iterate_data(),
            a: self.own_step(),
        }
    }
}

/// Four ADMM-PD runs of one topology, one per lane, each an [`AdmmRun`] of type `R`.
#[derive(Debug, Clone)]
pub struct AdmmLanes<R = AdmmPd> {
    /// The scene, the first iterate, the iterations and the finish ([`ProjectiveLanes`]).
    core: ProjectiveLanes,
    stiffness: Vec<Lanes4>,
    /// $`\omega_i`$ and $`dt^2\omega_i^2`$, per lane.
    omega: Vec<Lanes4>,
    dt2_omega2: Vec<Lanes4>,
    /// $`dt^2 m_i^{-1} f_{ext,i}`$ per node ([`pull`]).
    pull: Vec<Vector3<Lanes4>>,
    // The step's buffers, as in the run alone (column-major, 3n; one z and ū per spring).
    x_tilde: Vec<Vector3<Lanes4>>,
    m_x_tilde: Vec<Lanes4>,
    z: Vec<Vector3<Lanes4>>,
    u_bar: Vec<Vector3<Lanes4>>,
    /// Scratch of the local step, one value per spring.
    scale: Vec<Lanes4>,
    run: PhantomData<R>,
}

impl<R: AdmmRun> AdmmLanes<R> {
    /// Lanes for runs of `like`'s topology and fixed nodes, none loaded yet; None unless it is
    /// the thesis rope's chain ([`super::projective::Rope`]) with a tridiagonal global solve.
    pub fn new(like: &R) -> Option<Self> {
        let (system, data) = (like.system(), like.lane_data());
        let (n, s) = (system.len(), system.springs().len());
        let zero = Lanes4::splat(0.0);
        Some(Self {
            core: ProjectiveLanes::new(system, data.iterate.reduction(), data.a)?,
            stiffness: vec![zero; s],
            omega: vec![zero; s],
            dt2_omega2: vec![zero; s],
            pull: vec![Vector3::zeros(); n],
            x_tilde: vec![Vector3::zeros(); n],
            m_x_tilde: vec![zero; 3 * n],
            z: vec![Vector3::zeros(); s],
            u_bar: vec![Vector3::zeros(); s],
            scale: vec![zero; s],
            run: PhantomData,
        })
    }
}

impl<R: AdmmRun> LaneSolver for AdmmLanes<R> {
    type Run = R;

    fn load(&mut self, lane: usize, run: &R, state: &State) {
        let (system, data) = (run.system(), run.lane_data());
        assert!(
            self.core.holds(
                system,
                data.counts_iterations,
                data.first_iterate,
                &[
                    FirstIterate::Previous,
                    FirstIterate::Inertial,
                    FirstIterate::InertialPrediction
                ]
            ),
            "a batch of ADMM-PD runs holds runs of one topology and fixed set that count their \
             iterations and start at (a), (b) or x̃"
        );
        let dt = run.dt();
        self.core.load(
            lane,
            system,
            dt,
            data.iterate.reduction(),
            data.a,
            state,
            data.iterations,
            data.first_iterate,
        );
        let stiffness: Vec<f64> = system.springs().iter().map(|s| s.stiffness).collect();
        load_values(&mut self.stiffness, lane, &stiffness);
        load_values(&mut self.omega, lane, data.iterate.omega());
        load_values(&mut self.dt2_omega2, lane, data.iterate.dt2_omega2());
        let pulls: Vec<Vec3> = (0..system.len()).map(|i| pull(system, dt, i)).collect();
        load_points(&mut self.pull, lane, &pulls);
    }

    fn clear(&mut self, lane: usize) {
        self.core.clear(lane);
    }

    /// [`AdmmPd`]'s step (Algorithm 4) in every lane; a lane whose iterations are done keeps
    /// its iterate while the others iterate on.
    fn step(&mut self) {
        // 2.1: x̃ (as Mx̃) and the first iterate.
        let core = &mut self.core;
        let n = core.states.x.len();
        for (i, x_tilde) in self.x_tilde.iter_mut().enumerate() {
            let (x, v) = (core.states.x[i], core.states.v[i]);
            *x_tilde = match core.is_fixed(i) {
                true => x,
                false => predicted(x, v, core.dt, self.pull[i]),
            };
            for c in 0..3 {
                self.m_x_tilde[c * n + i] = core.masses[i] * x_tilde[c];
            }
        }
        core.begin_step(Some(&self.x_tilde));
        // 2.2: ū = 0 every step.
        self.u_bar.fill(Vector3::zeros());
        // 2.3-2.10.
        let (m_x_tilde, omega, dt2_omega2) = (&self.m_x_tilde, &self.omega, &self.dt2_omega2);
        let stiffness = &self.stiffness;
        let (z, u_bar, scale) = (&mut self.z, &mut self.u_bar, &mut self.scale);
        core.iterate(false, |scene, x| {
            let springs = LocalStepSprings {
                rest_lengths: scene.rest_lengths,
                stiffness,
                omega,
            };
            local_step_of(scene.incidence, x, springs, scale, z, u_bar);
            global_rhs_of(scene.incidence, m_x_tilde, z, u_bar, dt2_omega2, x);
            scene.a.solve(x, scene.x_n);
        });
        // 2.11
        core.finish_step();
    }

    fn states(&self) -> &LaneStates {
        &self.core.states
    }

    fn states_mut(&mut self) -> &mut LaneStates {
        &mut self.core.states
    }
}
