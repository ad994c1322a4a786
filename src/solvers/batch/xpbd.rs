//! XPBD (Algorithm 2) in lanes: [`crate::solvers::xpbd::Xpbd`]'s step at [`Lanes4`], four runs of the
//! thesis rope's chain ([`super::projective::Rope`]; any dt, compliance, masses and iteration
//! counts), its projections ([`crate::solvers::xpbd::Coefficients::project`]) made in the
//! wavefront order the chain allows (`sweeps_in_wavefront`), which keeps the sweeps' bits.

use super::projective::Rope;
use super::{Kept, LaneSolver, LaneStates, MovedBits, WIDTH};
use crate::integrators::stopping::checks_for_fixed_point;
use crate::integrators::time_stepper::TimeStepper;
use crate::model::lanes::{lane_mask, load_points, load_values, Lanes4};
use crate::model::system::{MassSpringSystem, State};
use crate::solvers::incidence::{Ends, SpringGraph};
use crate::solvers::xpbd::{Coefficients, Scratch, Xpbd};
use nalgebra::Vector3;
use simba::simd::{SimdBool, SimdValue};

/// Four XPBD runs of one topology, one per lane.
#[derive(Debug, Clone)]
pub struct XpbdLanes {
    rope: Rope,
    coefficients: Coefficients<Lanes4>,
    scratch: Scratch<Lanes4>,
    /// Iterations per step of each lane's run (0: no run).
    iterations: [usize; WIDTH],
    /// Which lanes stop sweeping before the others, from `iterations`.
    counts: SweepCounts,
    states: LaneStates,
    /// The positions of the lanes whose iterations are done, kept while the others sweep.
    done: Vec<Vector3<Lanes4>>,
    /// Per sweep of the step, per lane, the bits its projections changed (zero: a fixed point).
    moved: Vec<MovedBits>,
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
            counts: SweepCounts::of(&[0; WIDTH]),
            states: LaneStates::new(nodes),
            done: vec![Vector3::zeros(); nodes],
            moved: Vec::new(),
        })
    }
}

/// Algorithm 2, lines 4-12 in every lane: each lane's Gauss-Seidel sweeps over the rope's
/// springs, made in wavefront order, each lane ending with its own count's positions.
///
/// On a chain, spring j of sweep i waits only for spring j - 1 of its own sweep and spring
/// j + 1 of the sweep before (the last to move its nodes): the springs on a diagonal
/// i + ⌊j/2⌋ = τ of one parity share no node and wait for nothing of each other. Taken τ by τ,
/// the even springs before the odd ones, every projection sees the positions it sees in sweep
/// order (the same operations on the same values: the bits of the sweeps), and the CPU
/// overlaps four or five projections instead of waiting on one chain of nine per sweep.
///
/// For the lanes whose runs take k sweeps, fewer than the most ([`SweepCounts`]), node j's
/// positions after its last move of sweep k - 1 go to `done`, as [`super::iterate_lanes`]
/// keeps a finished lane's iterate, and are put back at the end.
///
/// A lane whose sweep i, still within its count, changed no bit of its positions and
/// multipliers is at a fixed point ([`crate::integrators::stopping::same_bits`]; checked every
/// [`FIXED_POINT_CHECK`](crate::integrators::stopping::FIXED_POINT_CHECK)th sweep): every
/// later projection sees what it saw in sweep i and changes nothing either, those of later
/// sweeps already made too. Its positions go to `done` when sweep i's last projection is made, and
/// once every lane is done (at a fixed point, or its count's sweeps made) the sweeps stop.
/// `moved` holds, per sweep and lane, the bits its projections changed.
fn sweeps_in_wavefront(
    rope: &Rope,
    c: &Coefficients<Lanes4>,
    counts: &SweepCounts,
    x: &mut [Vector3<Lanes4>],
    done: &mut [Vector3<Lanes4>],
    lambda: &mut [Lanes4],
    moved: &mut Vec<MovedBits>,
) {
    let (springs, keeps) = (rope.springs(), &counts.keeps);
    let most = keeps.len() - 1;
    moved.clear();
    moved.resize(most, MovedBits::default());
    let mut fixed = lane_mask(|_| false);
    let keep = |mask: Mask,
                nodes: std::ops::RangeInclusive<usize>,
                x: &[Vector3<Lanes4>],
                done: &mut [Vector3<Lanes4>]| {
        for node in nodes {
            done[node] = x[node].kept_where(mask, done[node]);
        }
    };
    if let Some(mask) = keeps[0] {
        keep(mask, 0..=springs, x, done);
    }
    let half = (springs - 1) / 2;
    'diagonals: for tau in 0..most + half {
        // From τ = half to most - 1 every spring has a sweep on the diagonal.
        let every_spring = (half..most).contains(&tau);
        for parity in [0, 1] {
            for j in (parity..springs).step_by(2) {
                // Sweep i = τ - ⌊j/2⌋, if there is one (a wrapped negative is ≥ most).
                let i = tau.wrapping_sub(j / 2);
                if !every_spring && i >= most {
                    continue;
                }
                let (a, b) = rope.ends(j);
                let checked = checks_for_fixed_point(i);
                if checked {
                    let before = (lambda[j], x[a], x[b]);
                    c.project(j, (a, b), x, &mut lambda[j]);
                    let moved = &mut moved[i];
                    moved.add(before.0, lambda[j]);
                    for (p, n) in [(before.1, x[a]), (before.2, x[b])] {
                        for k in 0..3 {
                            moved.add(p[k], n[k]);
                        }
                    }
                } else {
                    c.project(j, (a, b), x, &mut lambda[j]);
                }
                // Node j has had its last move of sweep i, and the last node with it.
                if let Some(mask) = keeps[i + 1] {
                    keep(mask, j..=if j + 1 == springs { j + 1 } else { j }, x, done);
                }
                if j + 1 == springs {
                    // Sweep i is whole.
                    if checked {
                        let still = lane_mask(|lane| counts.iterations[lane] > i);
                        let at_rest = moved[i].unchanged() & still & !fixed;
                        if at_rest.any() {
                            keep(at_rest, 0..=springs, x, done);
                            fixed = fixed | at_rest;
                        }
                    }
                    let finished = fixed | lane_mask(|lane| counts.iterations[lane] <= i + 1);
                    if finished.all() {
                        break 'diagonals;
                    }
                }
            }
        }
    }
    let kept = counts.short | fixed;
    if kept.any() {
        for (x, &done) in x.iter_mut().zip(done.iter()) {
            *x = done.kept_where(kept, *x);
        }
    }
}

/// Per lane, a boolean.
type Mask = <Lanes4 as SimdValue>::SimdBool;

/// Which lanes stop sweeping before the others ([`sweeps_in_wavefront`]), made when a lane is
/// loaded or cleared rather than at every step.
#[derive(Debug, Clone)]
struct SweepCounts {
    /// Per count of sweeps k from 0 to the most, the lanes that take k, where there are any
    /// and k is not the most.
    keeps: Vec<Option<Mask>>,
    /// The lanes that take fewer sweeps than the most.
    short: Mask,
    /// Each lane's count of sweeps.
    iterations: [usize; WIDTH],
}

impl SweepCounts {
    /// From each lane's count of sweeps (0: no run).
    fn of(iterations: &[usize; WIDTH]) -> Self {
        let most = iterations.iter().copied().max().unwrap_or(0);
        let keeps = (0..=most)
            .map(|k| {
                let mask = lane_mask(|lane| iterations[lane] == k);
                (k < most && mask.any()).then_some(mask)
            })
            .collect();
        Self {
            keeps,
            short: lane_mask(|lane| iterations[lane] < most),
            iterations: *iterations,
        }
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
        self.counts = SweepCounts::of(&self.iterations);
    }

    fn clear(&mut self, lane: usize) {
        self.iterations[lane] = 0;
        self.counts = SweepCounts::of(&self.iterations);
    }

    /// [`Xpbd`]'s step in every lane; a lane whose iterations are done keeps its positions
    /// while the others sweep on.
    fn step(&mut self) {
        let c = &self.coefficients;
        c.predict(&mut self.states.x, &self.states.v, &mut self.scratch);
        sweeps_in_wavefront(
            &self.rope,
            c,
            &self.counts,
            &mut self.states.x,
            &mut self.done,
            &mut self.scratch.lambda,
            &mut self.moved,
        );
        c.velocities(&self.states.x, &mut self.states.v, &self.scratch);
    }

    fn states(&self) -> &LaneStates {
        &self.states
    }

    fn states_mut(&mut self) -> &mut LaneStates {
        &mut self.states
    }
}
