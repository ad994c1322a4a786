//! Batched runs (issue 26, item 2): independent runs of one solver stepped together, one per
//! lane of a [`crate::model::lanes::Lanes4`] vector, each giving the bits of its run alone ([`crate::model::lanes`]).
//!
//! The step is the solver's own, generic over the lane type ([`crate::solvers::xpbd::Coefficients`]);
//! what a batch adds is the bookkeeping: which run is in which lane, and [`simulate_batch`],
//! which watches every lane's run as [`crate::integrators::time_stepper::simulate`] watches one
//! ([`crate::integrators::time_stepper::Watch`]) and hands a lane whose run has stopped the next run waiting, so
//! that runs of different lengths do not stall the batch.

pub mod admm;
pub mod backward_euler;
mod lane_watch;
pub mod liu;
pub mod projective;
pub mod xpbd;

use crate::error::{Error, Result};
use crate::integrators::stopping::checks_for_fixed_point;
use crate::integrators::time_stepper::{InMemory, Run, RunOptions, TimeStepper, Watch};
use crate::model::lanes::{lane_mask, load_points, read_points, select, LaneMask, Lanes4};
use crate::model::system::State;
use crate::solvers::projective::finish_step_of;
use lane_watch::LaneWatch;
use nalgebra::Vector3;
use simba::simd::{SimdBool, SimdValue, WideF64x4};

/// Lanes in a batch.
pub use crate::model::lanes::WIDTH;

/// Several runs of one solver in the lanes of a [`crate::model::lanes::Lanes4`] vector.
pub trait LaneSolver {
    /// The single run a lane holds.
    type Run: TimeStepper + Clone;
    /// Puts `run`, at `state`, in lane `lane`; the lane's previous run is dropped.
    fn load(&mut self, lane: usize, run: &Self::Run, state: &State);
    /// Leaves lane `lane` without a run: its arithmetic goes on, unread, until it is loaded.
    fn clear(&mut self, lane: usize);
    /// Advances every lane by one of its run's steps.
    fn step(&mut self);
    /// The error that ended lane `lane`'s run in the last step, as its step alone returns it
    /// (taken: asked again, None); a solver whose step cannot fail has none.
    fn take_error(&mut self, _lane: usize) -> Option<Error> {
        None
    }
    /// The positions and velocities of every lane.
    fn states(&self) -> &LaneStates;
    /// The same, to change.
    fn states_mut(&mut self) -> &mut LaneStates;
    /// Lane `lane`'s state.
    fn read(&self, lane: usize, state: &mut State) {
        let states = self.states();
        read_points(&states.x, lane, &mut state.x);
        read_points(&states.v, lane, &mut state.v);
    }
}

/// The positions and velocities of the runs in a batch's lanes, per node.
#[derive(Debug, Clone)]
pub struct LaneStates {
    pub x: Vec<Vector3<Lanes4>>,
    pub v: Vec<Vector3<Lanes4>>,
}

impl LaneStates {
    /// Zero states for `nodes` nodes.
    pub fn new(nodes: usize) -> Self {
        Self {
            x: vec![Vector3::zeros(); nodes],
            v: vec![Vector3::zeros(); nodes],
        }
    }

    /// Puts `state` in lane `lane`.
    pub fn load(&mut self, lane: usize, state: &State) {
        load_points(&mut self.x, lane, &state.x);
        load_points(&mut self.v, lane, &state.v);
    }

    /// The end of a projective step in every lane: the positions of the column-major
    /// `iterate`, and the velocities they imply over `dt` ([`finish_step_of`]).
    pub fn finish_step(&mut self, iterate: &[Lanes4], dt: Lanes4) {
        finish_step_of(&mut self.x, &mut self.v, iterate, dt);
    }
}

/// A value of a step's iterate in lanes ([`Lanes4`] or a point of them), of which some lanes
/// can be kept while the others change.
pub trait Kept: Copy {
    /// Per lane, `self` where `mask` holds and `other` elsewhere.
    fn kept_where(self, mask: <Lanes4 as SimdValue>::SimdBool, other: Self) -> Self;
}

impl Kept for Lanes4 {
    fn kept_where(self, mask: <Lanes4 as SimdValue>::SimdBool, other: Self) -> Self {
        self.select(mask, other)
    }
}

impl Kept for Vector3<Lanes4> {
    fn kept_where(self, mask: <Lanes4 as SimdValue>::SimdBool, other: Self) -> Self {
        select(mask, self, other)
    }
}

/// The iterations of one step in lanes whose runs take `iterations` each: `iterate` is run on
/// `values` as many times as the most any lane takes, and every lane ends with the values of
/// its own count. Each lane's values are saved into `done` once, at the iteration its count
/// is reached, and put back after the last (its further iterations change only its own lane,
/// unread), so a batch with a short or empty lane costs no copy per iteration.
///
/// With `previous` (a buffer of `values`' length), for an iteration that reads nothing that
/// changes but `values`: a lane whose iteration returns its values unchanged, bit for bit, is
/// at a fixed point ([`same_bits`](crate::integrators::stopping::same_bits): its later
/// iterations would return them again) and is done as a lane whose count is reached; once every
/// lane is done the iterations stop. Every
/// [`FIXED_POINT_CHECK`](crate::integrators::stopping::FIXED_POINT_CHECK)th iteration is checked.
pub fn iterate_lanes(
    iterations: &[usize; WIDTH],
    values: &mut [Lanes4],
    done: &mut [Lanes4],
    mut previous: Option<&mut [Lanes4]>,
    mut iterate: impl FnMut(&mut [Lanes4]),
) {
    let most = iterations.iter().copied().max().unwrap_or(0);
    let mut saved = lane_mask(|_| false);
    let mut save = |lanes: LaneMask, saved: &mut LaneMask, values: &[Lanes4]| {
        let lanes = lanes & !*saved;
        if lanes.any() {
            for (done, &value) in done.iter_mut().zip(values) {
                *done = value.kept_where(lanes, *done);
            }
            *saved = *saved | lanes;
        }
    };
    for iteration in 0..most {
        save(
            lane_mask(|lane| iterations[lane] == iteration),
            &mut saved,
            values,
        );
        if saved.all() {
            break;
        }
        match previous.as_deref_mut() {
            Some(previous) if checks_for_fixed_point(iteration) => {
                previous.copy_from_slice(values);
                iterate(values);
                let moved = moved_lanes(previous, values);
                save(moved.unchanged(), &mut saved, values);
            }
            _ => iterate(values),
        }
    }
    if saved.any() {
        for (value, &done) in values.iter_mut().zip(done.iter()) {
            *value = done.kept_where(saved, *value);
        }
    }
}

/// Per lane, the bits in which `previous` and `next` differ anywhere ([`MovedBits`]).
fn moved_lanes(previous: &[Lanes4], next: &[Lanes4]) -> MovedBits {
    let mut moved = MovedBits::default();
    for (&p, &n) in previous.iter().zip(next) {
        moved.add(p, n);
    }
    moved
}

/// Per lane, the OR of the bits in which pairs of values differ, held as the bits of an `f64`
/// lane (a vector XOR and OR per pair, not a lane at a time).
#[derive(Debug, Clone, Copy)]
pub struct MovedBits(Lanes4);

impl Default for MovedBits {
    fn default() -> Self {
        Self(Lanes4::splat(0.0))
    }
}

impl MovedBits {
    /// Adds the bits in which `previous` and `next` differ.
    #[inline(always)]
    pub fn add(&mut self, previous: Lanes4, next: Lanes4) {
        self.0 = WideF64x4(self.0 .0 | (previous.0 ^ next.0));
    }

    /// The lanes in which no bit differed.
    pub fn unchanged(self) -> LaneMask {
        let bits = self.0 .0.to_array();
        lane_mask(|lane| bits[lane].to_bits() == 0)
    }
}

/// How full a batch's lanes were: the steps the lanes took together, and the runs' steps
/// among them (a step of a lane without a run, or of a lane whose run has stopped, is not a
/// run's step). The last run, which goes on alone, is in neither.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct Occupancy {
    pub batch_steps: usize,
    pub run_steps: usize,
}

impl Occupancy {
    /// The runs' share of the lanes' steps, in [0, 1] (0 for a batch that took no step).
    pub fn fraction(&self) -> f64 {
        self.run_steps as f64 / (WIDTH * self.batch_steps).max(1) as f64
    }
}

/// What [`simulate_batch`] returns: each run's outcome, in the order of the runs, and how
/// full the lanes were.
#[derive(Debug)]
pub struct BatchOutcome {
    pub runs: Vec<Result<Run>>,
    pub occupancy: Occupancy,
}

/// A run in a lane.
struct InLane<'a, R> {
    /// Its index in the batch's runs.
    index: usize,
    solver: &'a R,
    watch: Watch<'a>,
    memory: InMemory,
    state: State,
}

/// Runs every `(solver, start, options)` of `runs`, [`WIDTH`] at a time in the lanes of
/// `lanes`, and returns each one's outcome as [`crate::integrators::time_stepper::simulate`] would give it, in the
/// order of `runs`, with the lanes' [`Occupancy`]. A lane whose run stops takes the next run
/// waiting; the last run left goes on alone.
pub fn simulate_batch<'a, L: LaneSolver>(
    lanes: &mut L,
    runs: &'a [(L::Run, State, RunOptions)],
) -> BatchOutcome {
    let mut occupancy = Occupancy::default();
    let mut outcomes: Vec<Option<Result<Run>>> = (0..runs.len()).map(|_| None).collect();
    let mut waiting = runs.iter().enumerate();
    let mut watch = LaneWatch::new(lanes.states().x.len());
    let mut in_lane: Vec<Option<InLane<'a, L::Run>>> = (0..WIDTH)
        .map(|lane| fill(lanes, &mut watch, lane, &mut waiting, &mut outcomes))
        .collect();
    loop {
        let busy = in_lane.iter().filter(|run| run.is_some()).count();
        if busy == 0 {
            break;
        }
        // The batch shrinks to its last run, which goes on alone (its step is the lanes'
        // at `f64`) instead of at the cost of a full batch.
        if busy == 1 && waiting.len() == 0 {
            let lane = in_lane
                .iter()
                .position(Option::is_some)
                .expect("a busy lane");
            let mut run = in_lane[lane].take().expect("a busy lane");
            lanes.read(lane, &mut run.state);
            let outcome = run
                .watch
                .run_to_end(&mut run.solver.clone(), run.state, &mut run.memory);
            outcomes[run.index] = Some(outcome.map(|r| run.memory.into_run(r)));
            break;
        }
        lanes.step();
        occupancy.batch_steps += 1;
        occupancy.run_steps += busy;
        let states = lanes.states_mut();
        let measured = watch.damp_and_measure(&states.x, &mut states.v);
        for (lane, (ke, finite)) in measured.into_iter().enumerate() {
            let Some(run) = in_lane[lane].as_mut() else {
                continue;
            };
            let outcome = match lanes.take_error(lane) {
                Some(error) => Err(run.watch.step_failed(error)),
                None => run
                    .watch
                    .after_measured_step(ke, finite, &mut run.memory)
                    .and_then(|()| {
                        if !run.watch.positions_due() {
                            return Ok(());
                        }
                        lanes.read(lane, &mut run.state);
                        run.watch.record_positions(&run.state, &mut run.memory)
                    }),
            };
            if outcome.is_ok() && run.watch.running() {
                continue;
            }
            let mut run = in_lane[lane].take().expect("a busy lane");
            lanes.read(lane, &mut run.state);
            let finished = outcome.and_then(|()| run.watch.finish(run.state, &mut run.memory));
            outcomes[run.index] = Some(finished.map(|r| run.memory.into_run(r)));
            in_lane[lane] = fill(lanes, &mut watch, lane, &mut waiting, &mut outcomes);
        }
    }
    BatchOutcome {
        runs: outcomes
            .into_iter()
            .map(|o| o.expect("every run ran"))
            .collect(),
        occupancy,
    }
}

/// The next run of `waiting` that starts without error, put in lane `lane` of `lanes` and
/// `watch` (the runs that stop before their first step get their outcome); None, and the lane
/// cleared, when none is left.
fn fill<'a, L: LaneSolver>(
    lanes: &mut L,
    watch: &mut LaneWatch,
    lane: usize,
    waiting: &mut impl Iterator<Item = (usize, &'a (L::Run, State, RunOptions))>,
    outcomes: &mut [Option<Result<Run>>],
) -> Option<InLane<'a, L::Run>> {
    for (index, (solver, state, options)) in waiting {
        let mut memory = InMemory::new(solver.dt());
        match Watch::start(solver, state, options, &mut memory) {
            Ok(run_watch) if run_watch.running() => {
                lanes.load(lane, solver, state);
                watch.load(lane, solver.system(), run_watch.damping_factor());
                return Some(InLane {
                    index,
                    solver,
                    watch: run_watch,
                    memory,
                    state: state.clone(),
                });
            }
            Ok(run_watch) => {
                let run = run_watch.finish(state.clone(), &mut memory);
                outcomes[index] = Some(run.map(|run| memory.into_run(run)));
            }
            Err(e) => outcomes[index] = Some(Err(e)),
        }
    }
    lanes.clear(lane);
    None
}

#[cfg(test)]
mod tests {
    use super::liu::LiuLanes;
    use super::xpbd::XpbdLanes;
    use super::*;
    use crate::integrators::time_stepper::simulate;
    use crate::model::metrics::StoppingRule;
    use crate::model::scene::thesis_rope;
    use crate::solvers::xpbd::Xpbd;
    use simba::simd::SimdPartialOrd;

    /// Every bit a run's outcome holds: steps, the stop, the peaks and the final state.
    fn bits(run: &Run) -> Vec<u64> {
        let mut bits = vec![run.steps, run.hit_time_limit.into(), run.dt.to_bits()];
        for p in &run.peaks {
            bits.extend([p.sample, p.energy.to_bits(), p.time_thesis.to_bits()]);
            bits.push(p.time_exact.to_bits());
        }
        for point in run.final_state.x.iter().chain(&run.final_state.v) {
            bits.extend(point.iter().map(|c| c.to_bits()));
        }
        bits
    }

    /// The options of a run stopped at `max_time` s or below a peak of `threshold` J, with
    /// velocity damping `damping` 1/s.
    fn options(damping: f64, max_time: f64, threshold: f64) -> RunOptions {
        RunOptions {
            stop: StoppingRule {
                threshold,
                max_time,
                ..StoppingRule::default()
            },
            velocity_damping: damping,
            ..RunOptions::default()
        }
    }

    /// Asserts that every run of `runs` gives the same bits in the batch `lanes` as alone.
    fn assert_lanes_are_runs_alone<L: LaneSolver>(
        lanes: &mut L,
        runs: &[(L::Run, State, RunOptions)],
    ) {
        let batched = simulate_batch(lanes, runs);
        let mut steps = Vec::new();
        for ((solver, state, options), batched) in runs.iter().zip(batched.runs) {
            let alone = simulate(&mut solver.clone(), state.clone(), options).unwrap();
            let batched = batched.unwrap();
            assert_eq!(bits(&batched), bits(&alone), "{}", alone.solver);
            assert_eq!(batched.solver, alone.solver);
            steps.push(alone.steps as usize);
        }
        // Every run's steps are counted in the lanes but those the last one took alone.
        let (total, longest) = (steps.iter().sum::<usize>(), *steps.iter().max().unwrap());
        let o = batched.occupancy;
        assert!(
            o.run_steps <= total && o.run_steps + longest >= total,
            "{o:?}"
        );
        assert!(o.run_steps <= WIDTH * o.batch_steps && o.fraction() <= 1.0);
    }

    /// Asserts that every run of `runs` ends in the batch `lanes` as alone: the same bits, or
    /// the same error.
    fn assert_outcomes_are_runs_alone<L: LaneSolver>(
        lanes: &mut L,
        runs: &[(L::Run, State, RunOptions)],
    ) {
        let batched = simulate_batch(lanes, runs).runs;
        for ((solver, state, options), batched) in runs.iter().zip(batched) {
            let alone = simulate(&mut solver.clone(), state.clone(), options);
            match (alone, batched) {
                (Ok(alone), Ok(batched)) => assert_eq!(bits(&batched), bits(&alone)),
                (Err(alone), Err(batched)) => assert_eq!(batched.to_string(), alone.to_string()),
                (alone, batched) => panic!("alone {alone:?}, in a lane {batched:?}"),
            }
        }
    }

    /// A lane whose run diverges ends it with the divergence guard's error at the step its
    /// run alone does, and the lanes beside it go on to their runs' ends: a rope started with
    /// one node's velocity infinite, between two started at rest, damped and not. Fails
    /// (checked) with the lanes' finiteness taken over the whole vector instead of per lane:
    /// every run of the batch then diverges at its first step.
    #[test]
    fn a_lane_that_diverges_diverges_as_its_run_alone() {
        let system = thesis_rope(1e3).unwrap();
        let solver = Xpbd::new(&system, 1e-2, 20).unwrap();
        let rest = system.initial_state();
        let mut thrown = rest.clone();
        thrown.v[4].y = f64::INFINITY;
        let runs = vec![
            (solver.clone(), rest.clone(), options(0.0, 1.0, 1e-4)),
            (solver.clone(), thrown, options(0.0, 1.0, 1e-4)),
            (solver, rest, options(0.5, 1.0, 1e-4)),
        ];
        assert!(simulate(&mut runs[1].0.clone(), runs[1].1.clone(), &runs[1].2).is_err());
        let mut lanes = XpbdLanes::new(&runs[0].0).expect("the thesis rope is a batch's rope");
        assert_outcomes_are_runs_alone(&mut lanes, &runs);
    }

    /// Each lane of a batch gives its run's bits alone, with a different stiffness, dt,
    /// iteration count, damping and stopping time per lane, more runs than lanes (a lane whose
    /// run stops takes the next) and a run stopped by its first peak. Fails if a lane's
    /// positions are not kept once its iterations are done (the put-back of [`iterate_lanes`]
    /// skipped). It failed too with Eq 18 as a fused multiply-add
    /// (`(-alpha_tilde).mul_add(lambda, -c) * inverse_denominator`) in a build without FMA
    /// (fused at `f64`, not in the lanes); in the host-CPU build (`.cargo/config.toml`) the
    /// lanes fuse as well, so that variant no longer tells them apart.
    /// [`iterate_lanes`] with fixed points, on x ← min(x + 1, cap) per lane from 0: a lane
    /// at a fixed point before its count (cap 3, 50 iterations), one that reaches its count
    /// first (cap 100, 20), one that reaches both at once (8, 8) and an empty lane each end
    /// with its own count's value, as without fixed points, and the iterations stop at the
    /// 20th, once every lane is done. Fails (checked) with the iterations stopped once any
    /// lane is done.
    #[test]
    fn lanes_stop_at_fixed_points_with_their_counts_values() {
        let caps = Lanes4::from([3.0, 100.0, 8.0, 5.0]);
        let counts = [50, 20, 8, 0];
        let run = |fixed_points: bool| {
            let (mut values, mut done, mut previous) = (
                [Lanes4::splat(0.0)],
                [Lanes4::splat(0.0)],
                [Lanes4::splat(0.0)],
            );
            let mut calls = 0;
            let previous = fixed_points.then_some(&mut previous[..]);
            iterate_lanes(&counts, &mut values, &mut done, previous, |v| {
                calls += 1;
                v[0] = (v[0] + Lanes4::splat(1.0)).simd_min(caps);
            });
            (values[0].0.to_array(), calls)
        };
        assert_eq!(run(false), ([3.0, 20.0, 8.0, 0.0], 50));
        assert_eq!(run(true), ([3.0, 20.0, 8.0, 0.0], 20));
    }

    #[test]
    fn every_lane_is_its_run_alone_bit_for_bit() {
        let runs: Vec<(Xpbd, State, RunOptions)> = [
            // (k N/m, dt s, iterations, damping 1/s, max time s, threshold J)
            (1e3, 1e-2, 50, 0.0, 3.0, 1e-4),
            (1e4, 5e-3, 20, 0.0, 2.0, 1e-4),
            (1e3, 1e-3, 7, 0.5, 1.0, 1e-4),
            (1e4, 1e-2, 33, 0.0, 4.0, 1e9),
            (1e3, 2e-3, 1, 0.0, 1.5, 1e-4),
            (1e4, 1e-2, 70, 2.0, 2.5, 1e-4),
        ]
        .into_iter()
        .map(|(k, dt, iterations, damping, max_time, threshold)| {
            let system = thesis_rope(k).unwrap();
            let solver = Xpbd::new(&system, dt, iterations).unwrap();
            let options = options(damping, max_time, threshold);
            (solver, system.initial_state(), options)
        })
        .collect();
        let mut lanes = XpbdLanes::new(&runs[0].0).expect("the thesis rope is a batch's rope");
        assert_lanes_are_runs_alone(&mut lanes, &runs);
    }

    /// The same for Liu 2013 (Algorithm 3): every lane's run alone, with a different stiffness,
    /// dt, iteration count, first iterate ((a) and (b)), damping and stopping time per lane.
    /// Fails with the put-back of [`iterate_lanes`] skipped, as the XPBD test. It failed too with
    /// the tridiagonal substitution's $`x_i = y_i/d_i - L_{i+1,i}x_{i+1}`$ as a fused
    /// multiply-add (`(-l).simd_mul_add(x, *b * inv)`) in a build without FMA (fused at `f64`
    /// only); the host-CPU build fuses in the lanes too.
    #[test]
    fn every_liu_lane_is_its_run_alone_bit_for_bit() {
        use crate::solvers::fast_mass_spring::{FastMassSpring, FirstIterate};
        use FirstIterate::{Inertial, Previous};
        let runs: Vec<(FastMassSpring, State, RunOptions)> = [
            // (k N/m, dt s, iterations, first iterate, damping 1/s, max time s, threshold J)
            (1e3, 1e-2, 30, Previous, 0.0, 3.0, 1e-4),
            (1e4, 5e-3, 70, Inertial, 0.0, 2.0, 1e-4),
            (1e3, 1e-3, 7, Previous, 0.5, 1.0, 1e-4),
            (1e4, 1e-2, 30, Inertial, 0.0, 4.0, 1e9),
            (1e3, 2e-3, 1, Inertial, 0.0, 1.5, 1e-4),
            (1e4, 1e-2, 30, Previous, 2.0, 2.5, 1e-4),
        ]
        .into_iter()
        .map(|(k, dt, iterations, first, damping, max_time, threshold)| {
            let system = thesis_rope(k).unwrap();
            let solver = FastMassSpring::new(&system, dt, iterations)
                .unwrap()
                .with_first_iterate(first);
            let options = options(damping, max_time, threshold);
            (solver, system.initial_state(), options)
        })
        .collect();
        let mut lanes = LiuLanes::new(&runs[0].0).expect("the rope's solve is tridiagonal");
        assert_lanes_are_runs_alone(&mut lanes, &runs);
    }

    /// The same for ADMM-PD's forensic variants that take a lane (other first iterates and
    /// weights, [`crate::studies::forensics::AdmmVariant::takes_a_lane`]): every lane gives
    /// the variant's own run alone ([`crate::studies::forensics::VariantAdmm`]), bits and name.
    /// Fails with the lanes' weights left at one lane's (ω = √k for every lane).
    #[test]
    fn every_admm_variant_lane_is_its_run_alone_bit_for_bit() {
        use crate::studies::forensics::{AdmmVariant, StartPoint, VariantAdmm, Weights};
        use StartPoint::{Inertial, Prediction, Previous};
        use Weights::{FourthRootStiffness, SqrtStiffness, Stiffness};
        let runs: Vec<(VariantAdmm, State, RunOptions)> = [
            // (k N/m, dt s, iterations, start, weights, damping 1/s, max time s)
            (1e3, 1e-2, 20, Prediction, Stiffness, 0.0, 3.0),
            (1e4, 5e-3, 50, Inertial, FourthRootStiffness, 0.0, 2.0),
            (1e3, 1e-3, 7, Previous, SqrtStiffness, 0.5, 1.0),
            (1e4, 1e-2, 20, Prediction, FourthRootStiffness, 0.0, 4.0),
            (1e3, 2e-3, 1, Inertial, Stiffness, 0.0, 1.5),
            (1e4, 1e-2, 50, Previous, Stiffness, 2.0, 2.5),
        ]
        .into_iter()
        .map(|(k, dt, iterations, start, weights, damping, max_time)| {
            let system = thesis_rope(k).unwrap();
            let variant = AdmmVariant {
                start,
                weights,
                ..AdmmVariant::PRINTED
            };
            assert!(variant.takes_a_lane());
            let solver = VariantAdmm::new(&system, dt, iterations, variant).unwrap();
            let options = options(damping, max_time, 1e-4);
            (solver, system.initial_state(), options)
        })
        .collect();
        let mut lanes =
            super::admm::AdmmLanes::new(&runs[0].0).expect("the rope's solve is tridiagonal");
        assert_lanes_are_runs_alone(&mut lanes, &runs);
    }

    /// The same for Backward Euler (Eqs 10-12, [`backward_euler::BackwardEulerLanes`]): every
    /// lane's run alone, with a different stiffness, gravity, dt, count of Newton iterations,
    /// damping and stopping time per lane (the k = 1e3 N/m lanes reach fixed points). Written
    /// before the lanes ran, to fail with the put-back of [`iterate_lanes`] skipped and with
    /// every lane's gravity its first run's (both checked). Lanes are built wherever the run
    /// alone factors its Newton matrix banded: the 10 × 10 sheet too (three runs), not the
    /// 15 × 15 one.
    #[test]
    fn every_backward_euler_lane_is_its_run_alone_bit_for_bit() {
        use super::backward_euler::BackwardEulerLanes;
        use crate::model::scene::{RopeParams, SheetParams};
        use crate::solvers::backward_euler::BackwardEuler;
        let runs: Vec<(BackwardEuler, State, RunOptions)> = [
            // (k N/m, gravity m/s², dt s, Newton iterations, damping 1/s, max time s, threshold J)
            (1e3, 9.81, 1e-3, 5, 0.0, 1.0, 1e-4),
            (1e6, 9.8, 1e-3, 5, 0.0, 0.4, 1e-4),
            (1e3, 9.8, 1e-2, 3, 0.5, 2.0, 1e-4),
            (1e4, 9.81, 5e-3, 1, 0.0, 1.5, 1e9),
            (1e3, 9.81, 2e-3, 8, 0.0, 1.0, 1e-4),
            (1e6, 9.81, 1e-2, 5, 2.0, 1.0, 1e-4),
        ]
        .into_iter()
        .map(|(k, g, dt, iterations, damping, max_time, threshold)| {
            let system = RopeParams {
                gravity: g,
                ..RopeParams::thesis(k)
            }
            .build()
            .unwrap();
            let solver = BackwardEuler::new(&system, dt, iterations).unwrap();
            let options = options(damping, max_time, threshold);
            (solver, system.initial_state(), options)
        })
        .collect();
        let mut lanes = BackwardEulerLanes::new(&runs[0].0).expect("the rope's matrix is banded");
        assert_lanes_are_runs_alone(&mut lanes, &runs);
        // The 10 × 10 sheet (half-bandwidth 35, its own constant in the factorisation), three
        // runs for twenty steps each.
        let sheets: Vec<(BackwardEuler, State, RunOptions)> =
            [(1e3, 1e-2, 5), (1e4, 5e-3, 3), (1e3, 2e-2, 1)]
                .into_iter()
                .map(|(k, dt, iterations)| {
                    let system = SheetParams::spec(10, k).build().unwrap();
                    let solver = BackwardEuler::new(&system, dt, iterations).unwrap();
                    (
                        solver,
                        system.initial_state(),
                        options(0.0, 20.0 * dt, 1e-4),
                    )
                })
                .collect();
        let mut lanes =
            BackwardEulerLanes::new(&sheets[0].0).expect("the 10 × 10 sheet's matrix is banded");
        assert_lanes_are_runs_alone(&mut lanes, &sheets);
        let wider = SheetParams::spec(15, 1e3).build().unwrap();
        assert!(BackwardEulerLanes::new(&BackwardEuler::new(&wider, 1e-3, 1).unwrap()).is_none());
    }

    /// A lane whose Newton matrix is not positive definite ends its run with the error its run
    /// alone returns, and the other lanes go on to their runs' ends: a slack rope (springs
    /// three times their share of the anchors' span, so compressed) at dt = 1 s, beside the
    /// thesis rope. Fails (checked) with the lanes' errors left unread: the slack lane's run
    /// goes on and ends without one.
    #[test]
    fn a_backward_euler_lane_that_fails_fails_as_its_run_alone() {
        use super::backward_euler::BackwardEulerLanes;
        use crate::model::scene::RopeParams;
        use crate::solvers::backward_euler::BackwardEuler;
        let rope = RopeParams::thesis(1e3);
        let slack = RopeParams {
            rest_length: 3.0 * rope.rest_length,
            stiffness: 1e6,
            ..rope.clone()
        };
        let runs: Vec<(BackwardEuler, State, RunOptions)> = [(rope, 1e-3), (slack, 1.0)]
            .into_iter()
            .map(|(params, dt)| {
                let system = params.build().unwrap();
                let solver = BackwardEuler::new(&system, dt, 5).unwrap();
                (
                    solver,
                    system.initial_state(),
                    options(0.0, 20.0 * dt, 1e-4),
                )
            })
            .collect();
        let mut lanes = BackwardEulerLanes::new(&runs[0].0).expect("the rope's matrix is banded");
        assert_outcomes_are_runs_alone(&mut lanes, &runs);
        let slack_alone = simulate(&mut runs[1].0.clone(), runs[1].1.clone(), &runs[1].2);
        assert!(
            slack_alone.is_err(),
            "the slack rope's Newton matrix is indefinite"
        );
    }

    /// Lanes are built for the thesis rope's chain only ([`projective::Rope`]): a rope of
    /// another length, or a sheet, runs alone (`Chain::of` itself is tested in
    /// `solvers::projective`).
    #[test]
    fn lanes_hold_the_thesis_rope_only() {
        use crate::model::scene::{RopeParams, SheetParams};
        use crate::solvers::admm::AdmmPd;
        use crate::solvers::fast_mass_spring::FastMassSpring;
        let rope = thesis_rope(1e3).unwrap();
        let shorter = RopeParams {
            nodes: 7,
            ..RopeParams::thesis(1e3)
        }
        .build()
        .unwrap();
        let sheet = SheetParams::spec(4, 1e3).build().unwrap();
        let liu = |system| FastMassSpring::new(system, 1e-3, 1).unwrap();
        let admm = |system| AdmmPd::new(system, 1e-3, 1).unwrap();
        let xpbd = |system| Xpbd::new(system, 1e-3, 1).unwrap();
        assert!(LiuLanes::new(&liu(&rope)).is_some());
        assert!(super::admm::AdmmLanes::new(&admm(&rope)).is_some());
        assert!(XpbdLanes::new(&xpbd(&rope)).is_some());
        for other in [&shorter, &sheet] {
            assert!(LiuLanes::new(&liu(other)).is_none());
            assert!(super::admm::AdmmLanes::new(&admm(other)).is_none());
            assert!(XpbdLanes::new(&xpbd(other)).is_none());
        }
    }

    /// The same for ADMM-PD (Algorithm 4): every lane's run alone, with a different stiffness,
    /// dt, iteration count, first iterate ((a), (b) and line 2.1's x̃), damping and stopping
    /// time per lane. Fails if the lanes' step departs from the run's: with line 2.2's reset of
    /// $`\bar u`$ left out of the lanes' step (the dual carried across steps), or with the
    /// put-back of [`iterate_lanes`] skipped. (A dependent pull $`dt^2 g`$ in place of $`dt^2 m^{-1} f_{ext}`$ does
    /// not fail it: on the thesis rope, m = 1 kg, the two round alike.)
    #[test]
    fn every_admm_lane_is_its_run_alone_bit_for_bit() {
        use crate::integrators::first_iterate::FirstIterate::{
            Inertial, InertialPrediction, Previous,
        };
        use crate::solvers::admm::AdmmPd;
        let runs: Vec<(AdmmPd, State, RunOptions)> = [
            // (k N/m, dt s, iterations, first iterate, damping 1/s, max time s, threshold J)
            (1e3, 1e-2, 20, InertialPrediction, 0.0, 3.0, 1e-4),
            (1e4, 5e-3, 50, Inertial, 0.0, 2.0, 1e-4),
            (1e3, 1e-3, 7, Previous, 0.5, 1.0, 1e-4),
            (1e4, 1e-2, 20, InertialPrediction, 0.0, 4.0, 1e9),
            (1e3, 2e-3, 1, Inertial, 0.0, 1.5, 1e-4),
            (1e4, 1e-2, 50, InertialPrediction, 2.0, 2.5, 1e-4),
        ]
        .into_iter()
        .map(|(k, dt, iterations, first, damping, max_time, threshold)| {
            let system = thesis_rope(k).unwrap();
            let solver = AdmmPd::new(&system, dt, iterations)
                .unwrap()
                .with_first_iterate(first);
            let options = options(damping, max_time, threshold);
            (solver, system.initial_state(), options)
        })
        .collect();
        let mut lanes =
            super::admm::AdmmLanes::new(&runs[0].0).expect("the rope's solve is tridiagonal");
        assert_lanes_are_runs_alone(&mut lanes, &runs);
    }
}
