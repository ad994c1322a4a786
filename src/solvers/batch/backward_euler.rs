//! Backward Euler solved by Newton-Raphson (thesis §2.1, Eqs 5-12, the reference) in lanes:
//! [`BackwardEuler`]'s Newton iteration at [`Lanes4`], four runs of one topology and fixed set
//! (any dt, stiffness, rest lengths, masses, gravity and count of Newton iterations), each
//! started at $`x_n`$ ($`v_0 = 0`$), counting its iterations, without dissipation: the
//! thesis's references, at both gravities of the gravity study.
//!
//! The iteration is the run alone's, generic over the lane type
//! ([`crate::solvers::backward_euler`]: [`spring_jacobians`], [`newton_rhs`], the assembly of
//! [`ImplicitSlots`], the imposition of Eqs 44-47 ([`Imposition`]) and the banded $`LDL^\top`$
//! ([`BandedLdlt`])); the system's forces are [`forces_of`], Eq (3) in each lane with the sums
//! of [`crate::model::system::MassSpringSystem::forces`].

use super::{iterate_lanes, LaneSolver, LaneStates, WIDTH};
use crate::error::Error;
use crate::integrators::first_iterate::FirstIterate;
use crate::integrators::optimization_integrator::MinimizingSolver;
use crate::integrators::time_stepper::TimeStepper;
use crate::model::boundary::{fixed_node_unknowns, Imposition};
use crate::model::lanes::{load_points, load_values, Lanes4};
use crate::model::linear::{BandedLdlt, BANDED_MAX_BANDWIDTH};
use crate::model::spring::SpringArrays;
use crate::model::system::{forces_of, State};
use crate::solvers::backward_euler::{
    newton_rhs, position_update, spring_jacobians, BackwardEuler, ImplicitMatrix, ImplicitSlots,
    NewtonStep,
};
use nalgebra::{Matrix3, Vector3};
use simba::simd::{SimdBool, SimdValue};

/// Four Backward Euler runs of one topology and fixed set, one per lane.
#[derive(Debug, Clone)]
pub struct BackwardEulerLanes {
    states: LaneStates,
    /// The springs' ends and whether each node is fixed (the same in every lane).
    ends: Vec<(usize, usize)>,
    fixed: Vec<bool>,
    // Each lane's run: its dt, masses, external forces (gravity; zero on a fixed node),
    // springs, and Newton iterations per step (0: no run).
    dt: Lanes4,
    masses: Vec<Lanes4>,
    external: Vec<Vector3<Lanes4>>,
    rest_lengths: Vec<Lanes4>,
    stiffness: Vec<Lanes4>,
    iterations: [usize; WIDTH],
    /// The error that stopped a lane's run in the last step, as its step alone returns it.
    errors: [Option<Error>; WIDTH],
    // The Newton system: where its values go, their imposition and factorisation.
    slots: ImplicitSlots,
    values: Vec<Lanes4>,
    imposition: Imposition<Lanes4>,
    factor: BandedLdlt<Lanes4>,
    // The step's buffers, as in the run alone; the iterate v_k node-major (3n).
    x_k: Vec<Vector3<Lanes4>>,
    forces: Vec<Vector3<Lanes4>>,
    jacobians: Vec<Matrix3<Lanes4>>,
    zeros: Vec<Lanes4>,
    v_k: Vec<Lanes4>,
    /// The iterate of the lanes whose iterations are done, and the one before the current
    /// iteration ([`iterate_lanes`]).
    done: Vec<Lanes4>,
    previous: Vec<Lanes4>,
}

impl BackwardEulerLanes {
    /// Lanes for runs of `like`'s topology and fixed nodes, none loaded yet; None unless its
    /// Newton matrix is factored banded (as the run alone factors it: a half-bandwidth from 2
    /// to [`BANDED_MAX_BANDWIDTH`]).
    pub fn new(like: &BackwardEuler) -> Option<Self> {
        let system = like.system();
        let implicit = ImplicitMatrix::new(system);
        if !(2..=BANDED_MAX_BANDWIDTH).contains(&implicit.matrix.bandwidth()) {
            return None;
        }
        let (n, s) = (system.len(), system.springs().len());
        let zero = Lanes4::splat(0.0);
        Some(Self {
            states: LaneStates::new(n),
            ends: like.springs().ends.to_vec(),
            fixed: system.nodes().iter().map(|node| node.fixed).collect(),
            dt: zero,
            masses: vec![zero; n],
            external: vec![Vector3::zeros(); n],
            rest_lengths: vec![zero; s],
            stiffness: vec![zero; s],
            iterations: [0; WIDTH],
            errors: std::array::from_fn(|_| None),
            values: vec![zero; implicit.matrix.values().len()],
            imposition: Imposition::new(&implicit.matrix, &fixed_node_unknowns(system, 3)),
            factor: BandedLdlt::for_pattern(&implicit.matrix),
            slots: implicit.slots,
            x_k: vec![Vector3::zeros(); n],
            forces: vec![Vector3::zeros(); n],
            jacobians: vec![Matrix3::zeros(); s],
            zeros: vec![zero; 3 * n],
            v_k: vec![zero; 3 * n],
            done: vec![zero; 3 * n],
            previous: vec![zero; 3 * n],
        })
    }

    /// Whether `run` can take a lane: one of this topology and fixed set, without dissipation,
    /// counting its iterations and starting at $`x_n`$.
    fn holds(&self, run: &BackwardEuler) -> bool {
        run.dissipation().is_none()
            && run.counts_iterations()
            && run.first_iterate() == FirstIterate::Previous
            && run.springs().ends == self.ends
            && run
                .system()
                .nodes()
                .iter()
                .map(|n| n.fixed)
                .eq(self.fixed.iter().copied())
    }
}

impl LaneSolver for BackwardEulerLanes {
    type Run = BackwardEuler;

    fn load(&mut self, lane: usize, run: &BackwardEuler, state: &State) {
        assert!(
            self.holds(run),
            "a batch of Backward Euler runs holds runs of one topology and fixed set, without \
             dissipation, that count their iterations and start at x_n"
        );
        let system = run.system();
        self.dt.replace(lane, run.dt());
        load_values(&mut self.masses, lane, run.masses());
        let external: Vec<_> = (0..system.len())
            .map(|i| system.external_force(i))
            .collect();
        load_points(&mut self.external, lane, &external);
        let springs = run.springs();
        load_values(&mut self.rest_lengths, lane, springs.rest_lengths);
        load_values(&mut self.stiffness, lane, springs.stiffness);
        self.iterations[lane] = run.newton_iterations();
        self.errors[lane] = None;
        self.states.load(lane, state);
    }

    fn clear(&mut self, lane: usize) {
        self.iterations[lane] = 0;
        self.errors[lane] = None;
    }

    /// [`BackwardEuler`]'s step in every lane: $`v_0 = (x_n - x_n)/dt`$, the Newton
    /// iterations (Eqs 10, 12), a lane whose count is reached or whose iterate stops moving
    /// keeping it while the others iterate on, then Eq (9) and $`v_{n+1} = v_k`$.
    fn step(&mut self) {
        let dt = self.dt;
        // v_0 = (x⁰ − x_n)/dt with the first iterate x⁰ = x_n, as the run alone computes it.
        let first_iterate = &self.states.x;
        let starts = first_iterate.iter().zip(&self.states.x);
        for (v, (x0, x_n)) in self.v_k.chunks_exact_mut(3).zip(starts) {
            v.copy_from_slice(((x0 - x_n) / dt).as_slice());
        }
        let springs = SpringArrays {
            ends: &self.ends,
            rest_lengths: &self.rest_lengths,
            stiffness: &self.stiffness,
        };
        let step = NewtonStep {
            x_n: &self.states.x,
            v_n: &self.states.v,
            masses: &self.masses,
            dt,
        };
        let mut iteration = 0;
        // Eqs (10), (12); the iteration reads nothing that changes but v_k (the step's start,
        // masses and dt held): lanes stop at a fixed point, as the run alone does.
        iterate_lanes(
            &self.iterations,
            &mut self.v_k,
            &mut self.done,
            Some(&mut self.previous),
            |v_k| {
                for ((x_k, x_n), v) in self.x_k.iter_mut().zip(step.x_n).zip(v_k.chunks_exact(3)) {
                    *x_k = position_update(x_n, &Vector3::from_column_slice(v), dt);
                }
                spring_jacobians(springs, &self.x_k, &mut self.jacobians);
                forces_of(
                    &self.external,
                    &self.fixed,
                    springs,
                    &self.x_k,
                    &mut self.forces,
                );
                // The right-hand side takes v_k's place, and the solve makes it v_{k+1}.
                let rhs = v_k;
                newton_rhs(
                    &step,
                    &self.ends,
                    &self.jacobians,
                    &self.x_k,
                    &self.forces,
                    rhs,
                );
                self.slots
                    .set_masses(&mut self.values, step.masses.iter().copied());
                self.slots
                    .add_springs(&mut self.values, &self.jacobians, dt * dt, |_, j| j);
                self.imposition.impose_on_matrix(&mut self.values);
                let failed = self.factor.refactor_values(&self.values);
                if failed.any() {
                    // Only a lane still iterating: a lane past its count iterates on, unread.
                    for lane in 0..WIDTH {
                        if failed.extract(lane)
                            && iteration < self.iterations[lane]
                            && self.errors[lane].is_none()
                        {
                            self.errors[lane] = Some(self.factor.not_positive_definite(lane));
                        }
                    }
                }
                // Fixed nodes have v = 0: the x̄ of Eqs 45-47 is zero.
                self.imposition.impose_on_rhs(rhs, &self.zeros, 1);
                self.factor.solve_in_place(rhs, 1);
                iteration += 1;
            },
        );
        let states = &mut self.states;
        for ((x, v), v_next) in states
            .x
            .iter_mut()
            .zip(&mut states.v)
            .zip(self.v_k.chunks_exact(3))
        {
            let v_next = Vector3::from_column_slice(v_next);
            *x = position_update(x, &v_next, dt);
            *v = v_next;
        }
    }

    fn take_error(&mut self, lane: usize) -> Option<Error> {
        self.errors[lane].take()
    }

    fn states(&self) -> &LaneStates {
        &self.states
    }

    fn states_mut(&mut self) -> &mut LaneStates {
        &mut self.states
    }
}
