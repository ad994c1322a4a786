//! What Liu 2013's and ADMM-PD's lanes share ([`super::liu`], [`super::admm`]): both are
//! local/global iterations on the rope (a local step per spring, then the twisted tridiagonal
//! global solve, [`crate::solvers::projective`]), so one core holds their per-lane scene, the
//! first iterate of line 2.1, the iterations and the finish of the step. Each solver adds its
//! own per-spring data and buffers, and its iteration.

use super::{iterate_lanes, LaneStates, WIDTH};
use crate::integrators::first_iterate::{inertia, FirstIterate};
use crate::model::lanes::{lane_mask, load_values, select, Lanes4};
use crate::model::scene::THESIS_NODES;
use crate::model::system::{MassSpringSystem, State};
use crate::solvers::projective::{
    to_columns, Chain, GlobalSolve, GlobalSolveLanes, SpringIncidence,
};
use nalgebra::Vector3;
use simba::simd::SimdValue;

/// The spring graph of a batch: the thesis rope, a chain whose size is known where the step
/// is compiled, so that its loops are unrolled with every index a constant (Liu's iteration in
/// lanes 160-206 → 127-129 ns against the graph read at run time, docs/performance.md).
pub type Rope = Chain<THESIS_NODES>;

/// Four local/global runs of one topology and fixed set, one per lane: what Liu 2013's and
/// ADMM-PD's lanes have in common.
#[derive(Debug, Clone)]
pub struct ProjectiveLanes {
    /// Whether each node is fixed (the same in every lane).
    fixed: Vec<bool>,
    pub dt: Lanes4,
    pub masses: Vec<Lanes4>,
    rest_lengths: Vec<Lanes4>,
    /// The springs' incidence ($`J`$ of Eqs (26), (53) or $`D`$ of Eq (54)), per lane.
    incidence: SpringIncidence<Lanes4, Rope>,
    /// The global step's matrix $`A`$, per lane.
    a: GlobalSolveLanes<Lanes4, THESIS_NODES>,
    /// Iterations per step of each lane's run (0: no run).
    iterations: [usize; WIDTH],
    first_iterate: [FirstIterate; WIDTH],
    pub states: LaneStates,
    /// The first iterate, per node.
    first: Vec<Vector3<Lanes4>>,
    // The step's buffers, as in the run alone (column-major, 3n).
    x_n: Vec<Lanes4>,
    iterate: Vec<Lanes4>,
    /// The iterate of the lanes whose iterations are done, kept while the others iterate.
    done: Vec<Lanes4>,
    /// The iterate before the current iteration, for a solver whose iteration reads nothing
    /// else that changes ([`Self::iterate`]).
    previous: Vec<Lanes4>,
}

impl ProjectiveLanes {
    /// Lanes for runs of `system`'s topology and fixed nodes with `incidence` and global
    /// matrix `a`, none loaded yet; None unless the springs are a [`Rope`]'s and the global
    /// solve a tridiagonal one.
    pub fn new(
        system: &MassSpringSystem,
        incidence: &SpringIncidence,
        a: &GlobalSolve,
    ) -> Option<Self> {
        let (n, s) = (system.len(), system.springs().len());
        let zero = Lanes4::splat(0.0);
        Some(Self {
            fixed: system.nodes().iter().map(|node| node.fixed).collect(),
            dt: zero,
            masses: vec![zero; n],
            rest_lengths: vec![zero; s],
            incidence: SpringIncidence::chain_lanes(incidence)?,
            a: GlobalSolveLanes::new(a)?,
            iterations: [0; WIDTH],
            first_iterate: [FirstIterate::Previous; WIDTH],
            states: LaneStates::new(n),
            first: vec![Vector3::zeros(); n],
            x_n: vec![zero; 3 * n],
            iterate: vec![zero; 3 * n],
            done: vec![zero; 3 * n],
            previous: vec![zero; 3 * n],
        })
    }

    /// Whether a run of `system` with these settings can take a lane: one of this topology
    /// and fixed set that counts its iterations and starts at one of `first_iterates`.
    pub fn holds(
        &self,
        system: &MassSpringSystem,
        counts_iterations: bool,
        first_iterate: FirstIterate,
        first_iterates: &[FirstIterate],
    ) -> bool {
        counts_iterations
            && first_iterates.contains(&first_iterate)
            && system
                .nodes()
                .iter()
                .map(|node| node.fixed)
                .eq(self.fixed.iter().copied())
    }

    /// Puts a run of `system` in lane `lane`: its step, incidence, global matrix, state,
    /// iterations and first iterate.
    #[allow(clippy::too_many_arguments)]
    pub fn load(
        &mut self,
        lane: usize,
        system: &MassSpringSystem,
        dt: f64,
        incidence: &SpringIncidence,
        a: &GlobalSolve,
        state: &State,
        iterations: usize,
        first_iterate: FirstIterate,
    ) {
        self.dt.replace(lane, dt);
        let masses: Vec<f64> = system.nodes().iter().map(|node| node.mass).collect();
        load_values(&mut self.masses, lane, &masses);
        let rest_lengths: Vec<f64> = system.springs().iter().map(|s| s.rest_length).collect();
        load_values(&mut self.rest_lengths, lane, &rest_lengths);
        self.incidence.load_lane(lane, incidence);
        self.a.load_lane(lane, a);
        self.states.load(lane, state);
        self.iterations[lane] = iterations;
        self.first_iterate[lane] = first_iterate;
    }

    /// Whether node `i` is fixed.
    pub fn is_fixed(&self, i: usize) -> bool {
        self.fixed[i]
    }

    /// Leaves lane `lane` without a run.
    pub fn clear(&mut self, lane: usize) {
        self.iterations[lane] = 0;
    }

    /// Line 2.1: $`x_n`$ in columns, and the first iterate of each lane's run: (a)
    /// $`x_n`$, (b) $`x_n + dt\,v_n`$ or $`\tilde x`$ (`x_tilde`, per node, for a solver
    /// that forms it); a fixed node's is $`x_n`$.
    pub fn begin_step(&mut self, x_tilde: Option<&[Vector3<Lanes4>]>) {
        to_columns(&self.states.x, &mut self.x_n);
        let at_x_tilde =
            lane_mask(|lane| self.first_iterate[lane] == FirstIterate::InertialPrediction);
        let inertial = lane_mask(|lane| self.first_iterate[lane] == FirstIterate::Inertial);
        for (i, first) in self.first.iter_mut().enumerate() {
            let (x, v) = (self.states.x[i], self.states.v[i]);
            *first = match self.fixed[i] {
                true => x,
                false => {
                    let previous_or_inertial = select(inertial, inertia(x, v, self.dt), x);
                    match x_tilde {
                        Some(x_tilde) => select(at_x_tilde, x_tilde[i], previous_or_inertial),
                        None => previous_or_inertial,
                    }
                }
            };
        }
        to_columns(&self.first, &mut self.iterate);
    }

    /// The step's iterations: `iteration` on the column-major iterate as many times as the
    /// lane that takes the most, each lane ending with its own count's ([`iterate_lanes`]).
    /// With `fixed_points`, for an iteration that reads nothing that changes but the iterate
    /// (Liu's; not ADMM-PD's, which carries $`z`$ and $`\bar u`$), a lane stops at a fixed
    /// point, its result the same bits.
    pub fn iterate(
        &mut self,
        fixed_points: bool,
        mut iteration: impl FnMut(&Iteration<'_>, &mut [Lanes4]),
    ) {
        let data = Iteration {
            incidence: &self.incidence,
            a: &self.a,
            x_n: &self.x_n,
            rest_lengths: &self.rest_lengths,
            dt: self.dt,
        };
        let previous = fixed_points.then_some(&mut self.previous[..]);
        iterate_lanes(
            &self.iterations,
            &mut self.iterate,
            &mut self.done,
            previous,
            |x| iteration(&data, x),
        );
    }

    /// The step's end: positions from the iterate, velocities from them over dt (the
    /// erratum of Algorithm 3, line 2.11 of Algorithm 4).
    pub fn finish_step(&mut self) {
        self.states.finish_step(&self.iterate, self.dt);
    }
}

/// What an iteration reads of the lanes' scene ([`ProjectiveLanes::iterate`]).
pub struct Iteration<'a> {
    pub incidence: &'a SpringIncidence<Lanes4, Rope>,
    pub a: &'a GlobalSolveLanes<Lanes4, THESIS_NODES>,
    /// $`x_n`$, column-major (the global solve's fixed values).
    pub x_n: &'a [Lanes4],
    pub rest_lengths: &'a [Lanes4],
    pub dt: Lanes4,
}
