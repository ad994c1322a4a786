//! Liu et al. 2013, *Fast Simulation of Mass-Spring Systems* (thesis §2.3.1 and §3.4,
//! Algorithm 3, Eqs 20-29 and 52-53).
//!
//! Block coordinate descent on Eq (20) with the spring energy rewritten by Eqs (21)-(23):
//! a local step projects every spring onto its rest length (Eq 28), a global step solves the
//! prefactored system $`(M + dt^2 L)\,x = M y + dt^2 f_{ext} + dt^2 J d`$ (Eq 29). The matrices
//! $`M`$, $`L`$, $`J`$ (Eqs 24-26, 52-53) and the factorisation of $`A = M + dt^2 L`$ are built once
//! per scene and time step ([`crate::solvers::projective`], shared with ADMM-PD); fixed nodes enter the
//! factorisation by Eqs 43-47.
//!
//! Errata implemented in consistent form (see `docs/thesis-errata.md`):
//! - Eqs (27), (29): as printed, $`b = M x + dt^2 f_{ext}`$ and $`(M + dt^2 L)x = dt^2 J d - b`$
//!   give the inertia the wrong sign and no velocity. Liu 2013 uses the prediction
//!   $`y = x_n + dt\,v_n`$: the right-hand side is $`M y + dt^2 f_{ext} + dt^2 J d`$.
//! - Algorithm 3 has no velocity update: $`v_{n+1} = (x_{n+1} - x_n)/dt`$ after the loop, as in
//!   Algorithm 4 line 2.11.
//!
//! Algorithm 3 does not say where the iteration starts: an open point, resolved by the shared
//! [`FirstIterate`] of [`crate::integrators::first_iterate`]. The default is $`x_n`$
//! ([`FirstIterate::Previous`]), this crate's reading for the thesis's tables; Liu 2013's
//! $`y = x_n + dt\,v_n`$ ([`FirstIterate::Inertial`]) is the other reading. The report runs
//! both and says which published rows each reproduces (its "interpretation" evidence class).
//! The comparisons beyond the thesis start it, like every solver, from the inertial prediction
//! ([`FirstIterate::InertialPrediction`]). With many iterations the step converges to the
//! Backward Euler step of Eq (20) whatever the start.
//!
//! Under an optimization integrator ([`crate::integrators::optimization_integrator`]) each stage is the same
//! iteration with $`dt`$ the stage's $`\tau`$ and $`(x_n, v_n)`$ its pseudo-state; $`A`$ and
//! $`dt^2 f_{ext}`$ are built once per distinct $`\tau`$.

use crate::error::{require_positive, Error, Result};
use crate::integrators::first_iterate::StepStart;
use crate::integrators::optimization_integrator::{MinimizingSolver, PerStageStep, StageProblem};
use crate::integrators::stopping::{Convergence, FixedPoint};
use crate::integrators::time_stepper::TimeStepper;
use crate::model::lanes::Lane;
use crate::model::linear::Node;
use crate::model::system::{MassSpringSystem, State, Vec3};
use crate::solvers::incidence::Positions;
use crate::solvers::projective::{
    finish_step_with, incidence_matrix, node_of_columns, sphere_scales, to_columns, GlobalSolve,
    SpringGraph, SpringIncidence,
};
use nalgebra::Vector3;

/// Where each step's local/global iteration starts, a point Algorithm 3 leaves open: the
/// crate's one notion of a first iterate.
pub use crate::integrators::first_iterate::FirstIterate;

/// Liu 2013's solver with a fixed number of local/global iterations per step.
///
/// The step holds its positions and right-hand sides node by node, in the order of its global
/// solve ([`GlobalSolve::solve_nodes`]: on a sheet's sparse factor the fill-reducing one), and
/// takes its springs renumbered to that order and in [`SpringIncidence::scatter_order`]: on
/// the 100 × 100 sheet no permutation in or out of the solve, a node one 256-bit load or store,
/// and no spring's term waiting for the store of the one before (`docs/performance.md`, "The
/// sheet"). Every node's sum takes its terms in the order of the springs' indices, so the
/// arithmetic and its bits are those of column-major positions and springs in index order.
#[derive(Debug, Clone)]
pub struct FastMassSpring {
    system: MassSpringSystem,
    dt: f64,
    iterations: usize,
    start: StepStart,
    /// $`J`$ of Eqs (26), (53), stored per spring.
    j: SpringIncidence,
    /// $`J`$ with its nodes in the global solve's order and its springs in
    /// [`SpringIncidence::scatter_order`], and their rest lengths in that order.
    springs: SpringIncidence,
    rest_lengths: Vec<f64>,
    /// Where each node is in the step's buffers ([`GlobalSolve::rows`]).
    rows: Vec<u32>,
    /// The nodes' masses, kg.
    masses: Vec<f64>,
    /// $`A`$ and $`dt^2 f_{ext}`$ of each stage step, the current one's $`dt`$ in `tau`.
    stage_steps: PerStageStep<LiuStageStep>,
    /// The current stage's $`dt`$ ($`\tau`$), s.
    tau: f64,
    // Per-step buffers (node by node, in the global solve's order), so that a step allocates
    // nothing.
    x_n: Vec<Node>,
    b: Vec<Node>,
    x: Vec<Node>,
    /// The global step's right-hand side, then its solution (the next iterate).
    rhs: Vec<Node>,
    /// Whether the step's iterations have reached a fixed point.
    fixed_point: FixedPoint,
    /// One block's $`d_i`$ and the local step's scratch ([`SPRING_BLOCK`] springs).
    d: Vec<Node>,
    scale: Vec<f64>,
    /// When a step stops iterating, and the iterations steps took.
    convergence: Convergence,
}

/// What Liu's iteration prefactors for one step $`dt`$.
#[derive(Debug, Clone)]
pub struct LiuStageStep {
    /// $`A = M + dt^2 L`$, factored once (Algorithm 3 line 1.4).
    pub a: GlobalSolve,
    /// $`dt^2 f_{ext}`$, column-major.
    pub dt2_f_ext: Vec<f64>,
}

impl LiuStageStep {
    /// Algorithm 3, line 1.4, and $`dt^2 f_{ext}`$.
    fn new(system: &MassSpringSystem, dt: f64) -> Result<Self> {
        let n = system.len();
        let k: Vec<f64> = system.springs().iter().map(|s| s.stiffness).collect();
        let mut dt2_f_ext = vec![0.0; 3 * n];
        let f_ext: Vec<Vec3> = (0..n).map(|i| dt * dt * system.external_force(i)).collect();
        to_columns(&f_ext, &mut dt2_f_ext);
        Ok(Self {
            a: GlobalSolve::new(system, dt, &k)?,
            dt2_f_ext,
        })
    }
}

impl FastMassSpring {
    /// The solver for `system` with time step `dt` (s, > 0) and `iterations` (>= 1)
    /// local/global iterations per step. Algorithm 3, lines 1.1-1.4.
    pub fn new(system: &MassSpringSystem, dt: f64, iterations: usize) -> Result<Self> {
        require_positive("dt", dt)?;
        system.require_undamped_springs()?;
        if iterations == 0 {
            return Err(Error::invalid("iterations", 0, "an integer >= 1"));
        }
        let n = system.len();
        let own = LiuStageStep::new(system, dt)?;
        let rows = own.a.rows().to_vec();
        let j = incidence_matrix(system);
        let order = j.scatter_order();
        let springs = j.renumbered(&rows, &order);
        let rest_lengths = order
            .iter()
            .map(|&i| system.springs()[i as usize].rest_length)
            .collect();
        Ok(Self {
            system: system.clone(),
            dt,
            iterations,
            start: StepStart::new(FirstIterate::default()),
            j,
            springs,
            rest_lengths,
            rows,
            masses: system.nodes().iter().map(|node| node.mass).collect(),
            stage_steps: PerStageStep::new(dt, own),
            tau: dt,
            x_n: vec![Node::default(); n],
            b: vec![Node::default(); n],
            x: vec![Node::default(); n],
            rhs: vec![Node::default(); n],
            fixed_point: FixedPoint::default(),
            d: vec![Node::default(); SPRING_BLOCK],
            scale: vec![0.0; SPRING_BLOCK],
            convergence: Convergence::default(),
        })
    }

    /// The same solver starting each step's iteration at `first_iterate`.
    pub fn with_first_iterate(mut self, first_iterate: FirstIterate) -> Self {
        self.start = StepStart::new(first_iterate);
        self
    }

    /// Where each step starts.
    pub fn first_iterate(&self) -> FirstIterate {
        self.start.rule()
    }

    /// Local/global iterations per step.
    pub fn iterations(&self) -> usize {
        self.iterations
    }

    /// Whether each step runs its full count of iterations ([`crate::integrators::stopping::Stopping::Count`]),
    /// as a batch of runs does ([`crate::solvers::batch`]).
    pub fn counts_iterations(&self) -> bool {
        self.convergence.stopping() == crate::integrators::stopping::Stopping::Count
    }

    /// $`J`$ of Eqs (26), (53).
    pub fn incidence(&self) -> &SpringIncidence {
        &self.j
    }

    /// What the solver prefactored for its own step $`dt`$.
    pub fn own_step(&self) -> &LiuStageStep {
        self.stage_steps.own()
    }

    /// Algorithm 3 line 2.1 and the first iterate: $`b`$ of Eq (27) for `state`, and the
    /// iterate set where [`FirstIterate`] says (Algorithm 3 is silent; see the module doc).
    /// The accelerated solvers of [`crate::solvers::chebyshev`] and [`crate::solvers::anderson`] start from here.
    pub fn begin_step(&mut self, state: &State) {
        self.begin_stage(state, &StageProblem::backward_euler(self.dt))
            .expect("the solver's own step is prefactored when it is built");
    }

    /// [`Self::begin_step`] for a stage problem from its pseudo-state `stage`, with the
    /// matrix of its $`\tau`$ (built if new).
    pub fn begin_stage(&mut self, stage: &State, problem: &StageProblem) -> Result<()> {
        self.prepare(problem.tau)?;
        self.tau = problem.tau;
        into_rows(&stage.x, &self.rows, &mut self.x_n);
        self.inertial_rhs(stage);
        let x0 = self.start.first_iterate(&self.system, stage, problem);
        into_rows(x0, &self.rows, &mut self.x);
        Ok(())
    }

    /// The current stage's $`dt`$, s.
    pub fn stage_step(&self) -> f64 {
        self.tau
    }

    /// Algorithm 3 lines 2.2-2.8 once: the local step, then the global step, from the current
    /// iterate.
    pub fn iterate(&mut self) {
        self.local_step();
        self.global_step();
    }

    /// The current iterate $`x`$, node by node in the nodes' own order.
    pub fn positions(&self) -> impl Iterator<Item = Vec3> + '_ {
        from_rows(&self.x, &self.rows)
    }

    /// The current iterate, column-major (all x, all y, all z), into `columns` (length 3n).
    pub fn positions_into(&self, columns: &mut [f64]) {
        let n = self.rows.len();
        for (i, p) in self.positions().enumerate() {
            for c in 0..3 {
                columns[c * n + i] = p[c];
            }
        }
    }

    /// Replaces the current iterate by column-major positions (an accelerated iterate).
    /// Fixed nodes must keep their positions; the global step restores them anyway.
    pub fn set_positions(&mut self, columns: &[f64]) {
        let n = self.rows.len();
        for (i, &row) in self.rows.iter().enumerate() {
            self.x[row as usize] = Node::new(node_of_columns(columns, n, i));
        }
    }

    /// Eq. (27): consistent form $`b = M y + dt^2 f_{ext}`$ with $`y = x_n + dt\,v_n`$
    /// (printed: $`b = M x + f_{ext}\,dt^2`$, subtracted in Eq 29).
    fn inertial_rhs(&mut self, state: &State) {
        let dt2_f_ext = &self.stage_steps.current().dt2_f_ext;
        let n = self.rows.len();
        for (i, &row) in self.rows.iter().enumerate() {
            let b = inertial_term(
                state.x[i],
                state.v[i],
                self.masses[i],
                self.tau,
                node_of_columns(dt2_f_ext, n, i),
            );
            self.b[row as usize] = Node::new(b);
        }
    }

    /// Eq. (28): the local step (lines 2.3-2.5), $`d_i = l_0\,(x_1 - x_2)/|x_1 - x_2|`$ for
    /// every spring at the current iterate, each block of [`SPRING_BLOCK`] springs' $`d_i`$
    /// added at once into the right-hand side of Eq (29), $`b + dt^2 J d`$ (line 2.6), while
    /// they are in the L1 cache ([`directions_into_rhs`]). Public for the timing study, which
    /// times it apart from the whole iteration: this half is the springs', the global step the
    /// solve.
    pub fn local_step(&mut self) {
        let dt2 = self.tau * self.tau;
        directions_into_rhs(
            &self.springs,
            &self.x[..],
            &self.rest_lengths,
            &self.b[..],
            dt2,
            &mut self.rhs[..],
            (&mut self.d, &mut self.scale),
        );
    }

    /// Eq. (29): consistent form $`(M + dt^2 L)\,x = b + dt^2 J d`$, solved with the
    /// prefactored $`A`$ for the three coordinates at once on the right-hand side the local
    /// step assembled; fixed nodes stay at $`x_n`$.
    pub fn global_step(&mut self) {
        self.stage_steps
            .current()
            .a
            .solve_nodes(&mut self.rhs, &self.x_n);
        std::mem::swap(&mut self.x, &mut self.rhs);
    }
}

/// The positions held node by node in `nodes`, node i at `rows[i]`, in the nodes' order.
fn from_rows<'a>(nodes: &'a [Node], rows: &'a [u32]) -> impl Iterator<Item = Vec3> + 'a {
    rows.iter().map(|&row| nodes[row as usize].position())
}

/// `positions` node by node, node i at `rows[i]` of `nodes`.
fn into_rows(positions: &[Vec3], rows: &[u32], nodes: &mut [Node]) {
    for (&row, p) in rows.iter().zip(positions) {
        nodes[row as usize] = Node::new(*p);
    }
}

// The arithmetic of a step, generic over the lane type ([`crate::model::lanes`]): at `f64` it is
// [`FastMassSpring`]'s, in lanes a batch's ([`crate::solvers::batch::liu`]).

/// Eq. (27): $`m\,y + dt^2 f_{ext}`$ with $`y = x_n + dt\,v_n`$, for one node.
#[inline(always)]
pub fn inertial_term<T: Lane>(
    x: Vector3<T>,
    v: Vector3<T>,
    mass: T,
    dt: T,
    dt2_f_ext: Vector3<T>,
) -> Vector3<T> {
    let y = x + v * dt;
    Vector3::from_fn(|c, _| mass * y[c] + dt2_f_ext[c])
}

/// Eq. (27): consistent form $`b = M y + dt^2 f_{ext}`$ with $`y = x_n + dt\,v_n`$, from the
/// positions `x`, velocities `v` and `masses` of the nodes, column-major.
pub fn inertial_rhs<T: Lane>(
    x: &[Vector3<T>],
    v: &[Vector3<T>],
    masses: &[T],
    dt: T,
    dt2_f_ext: &[T],
    b: &mut [T],
) {
    let n = x.len();
    for (i, ((&x, &v), &mass)) in x.iter().zip(v).zip(masses).enumerate() {
        let b_i = inertial_term(x, v, mass, dt, node_of_columns(dt2_f_ext, n, i));
        for c in 0..3 {
            b[c * n + i] = b_i[c];
        }
    }
}

/// How many springs [`spring_directions`] and [`directions_into_rhs`] take through their
/// passes at a time: each block's differences and factors are still in the L1 cache when the
/// next pass reads them, and each spring gets the same operations in the same order, so the
/// same bits. The 100 × 100 sheet's 39,402 springs a pass at a time went through L2: the local
/// step 110-116 µs, in blocks of 64 springs 99-105 µs (least of 4 to 6 runs pinned to one
/// core, `timing --point fast_mass_spring 100`; 32 the same, 16 and 256 slower). With the
/// right-hand side of Eq (29) in the same pass ([`directions_into_rhs`]), blocks of 32 took
/// 132 µs against 138 (64), 140 (48), 141 (128) and 146 µs (16) (a scratch program, least of
/// 250 passes, one core). ADMM-PD's local step ([`crate::solvers::admm::local_step_of`]) in
/// blocks of 64 was slower (182 against 171 µs, least of 8 alternating runs), and runs a pass
/// at a time.
pub const SPRING_BLOCK: usize = 32;

/// Eq. (28): $`d_i = l_0\,(x_1 - x_2)/|x_1 - x_2|`$ for every spring of `j` at the
/// iterate `x` (`scale`: scratch, one entry per spring), with the arithmetic of
/// [`crate::solvers::projective::project_on_sphere`]: each spring's difference and its
/// squared length in one pass, then every square root and division at once
/// ([`sphere_scales`], several springs at a time in SIMD registers), then the scaling, the
/// three passes block by block ([`SPRING_BLOCK`] springs; on the 100 × 100 sheet the pass over the
/// differences apart cost 14 % of the local step). The loops run over the graph's springs and
/// nodes, so that on a [`crate::solvers::projective::Chain`] every index is known where the
/// code is compiled.
#[inline]
pub fn spring_directions<T: Lane, G: SpringGraph, P: Positions<T> + ?Sized>(
    j: &SpringIncidence<T, G>,
    x: &P,
    rest_lengths: &[T],
    d: &mut [P::Vector],
    scale: &mut [T],
) {
    let springs = j.springs();
    let blocks = d[..springs]
        .chunks_mut(SPRING_BLOCK)
        .zip(scale[..springs].chunks_mut(SPRING_BLOCK));
    for (start, (d, scale)) in (0..springs).step_by(SPRING_BLOCK).zip(blocks) {
        differences_and_scales(j, x, rest_lengths, start, d, scale);
        for (d, &r) in d.iter_mut().zip(scale.iter()) {
            *d = *d * r;
        }
    }
}

/// The first two passes of Eq (28) over the springs `start..start + d.len()` of `j`
/// ([`spring_directions`]' block): each spring's difference $`q = x_1 - x_2`$ into `d`, then
/// its factor $`l_0/|q|`$ into `scale`; $`d_i`$ is their product.
#[inline(always)]
fn differences_and_scales<T: Lane, G: SpringGraph, P: Positions<T> + ?Sized>(
    j: &SpringIncidence<T, G>,
    x: &P,
    rest_lengths: &[T],
    start: usize,
    d: &mut [P::Vector],
    scale: &mut [T],
) {
    assert!(x.holds(j.nodes()), "positions of every node");
    for (k, (d, r)) in d.iter_mut().zip(scale.iter_mut()).enumerate() {
        // SAFETY: `x` holds every node, checked above.
        *d = unsafe { j.difference_unchecked(start + k, x) };
        *r = P::norm_squared(d);
    }
    sphere_scales(scale, &rest_lengths[start..start + scale.len()]);
}

/// Eq. (29), the right-hand side of the consistent form: $`x \leftarrow b + dt^2 J d`$.
#[inline]
pub fn global_rhs<T: Lane, G: SpringGraph>(
    j: &SpringIncidence<T, G>,
    b: &[T],
    d: &[Vector3<T>],
    dt2: T,
    x: &mut [T],
) {
    j.b_plus_transposed(b, |i| d[i] * dt2, x);
}

/// Eqs. (28)-(29): [`spring_directions`] block by block, each block's $`d_i`$ added into
/// `out` $`= b + dt^2 J d`$ ([`global_rhs`]'s sum, each spring's term added in `j`'s order)
/// as soon as it is computed; `block` holds one block's $`d_i`$ and scratch.
#[inline]
pub fn directions_into_rhs<T: Lane, G: SpringGraph, P: Positions<T> + ?Sized>(
    j: &SpringIncidence<T, G>,
    x: &P,
    rest_lengths: &[T],
    b: &P,
    dt2: T,
    out: &mut P,
    block: (&mut [P::Vector], &mut [T]),
) {
    out.copy_from(b);
    assert!(out.holds(j.nodes()), "a right-hand side for every node");
    let (d, scale) = block;
    let springs = j.springs();
    for start in (0..springs).step_by(SPRING_BLOCK) {
        let m = SPRING_BLOCK.min(springs - start);
        let (d, scale) = (&mut d[..m], &mut scale[..m]);
        differences_and_scales(j, x, rest_lengths, start, d, scale);
        // The scaling of Eq (28) and the term of Eq (29), spring by spring.
        for (k, (&q, &r)) in d.iter().zip(scale.iter()).enumerate() {
            // SAFETY: `out` holds every node, checked above.
            unsafe { j.add_row_transposed_unchecked(start + k, (q * r) * dt2, out) };
        }
    }
}

impl TimeStepper for FastMassSpring {
    fn name(&self) -> String {
        format!(
            "Fast mass-spring (Liu 2013, {})",
            self.convergence
                .iterations_label(self.iterations, "iterations")
        )
    }

    fn dt(&self) -> f64 {
        self.dt
    }

    fn system(&self) -> &MassSpringSystem {
        &self.system
    }

    fn convergence(&mut self) -> Option<&mut Convergence> {
        Some(&mut self.convergence)
    }

    fn step(&mut self, state: &mut State) -> Result<()> {
        self.solve(&StageProblem::backward_euler(self.dt), state)
    }
}

impl MinimizingSolver for FastMassSpring {
    /// Algorithm 3, run-time part.
    // region: step
    fn solve(&mut self, problem: &StageProblem, state: &mut State) -> Result<()> {
        // 2.1 and the first iterate.
        self.begin_stage(state, problem)?;
        self.convergence.begin_stage(
            &self.system,
            state,
            problem.tau,
            from_rows(&self.x, &self.rows),
        );
        // 2.2-2.8, stopping early only in the tolerance mode; at a fixed point the iterations
        // left are not computed ([`FixedPoint`]: an iteration reads nothing of the solver's
        // but its iterate and the step's b and A, and its result is known).
        self.fixed_point.begin_step();
        for _ in 0..self.iterations {
            if !self.fixed_point.reached() {
                self.fixed_point.keep(&[], Node::lanes(&self.x));
                self.iterate();
                self.fixed_point.compare(&[], Node::lanes(&self.x));
            }
            if self.convergence.converged(from_rows(&self.x, &self.rows)) {
                break;
            }
        }
        self.convergence.end_step(0);
        // Erratum: Algorithm 3 omits the velocity update.
        let (x, rows) = (&self.x, &self.rows);
        finish_step_with(
            &mut state.x,
            &mut state.v,
            |i| x[rows[i] as usize].position(),
            problem.tau,
        );
        Ok(())
    }
    // endregion: step

    fn prepare(&mut self, tau: f64) -> Result<()> {
        let (system, rows) = (&self.system, &self.rows);
        self.stage_steps
            .select(tau, |tau| {
                let step = LiuStageStep::new(system, tau)?;
                // Every stage's matrix has the pattern of the solver's own, so its ordering,
                // which the step's buffers and springs follow.
                assert!(step.a.rows() == rows, "one node order for every stage step");
                Ok(step)
            })
            .map(|_| ())
    }
}
