//! When an iterative solver's step stops iterating (issue 14, step 1), and the record of the
//! iterations its steps took, which the work-precision study counts its cost from.
//!
//! The thesis runs every solver at an iteration count found by hand (Tables 2-7), and its
//! tables keep that mode, [`Stopping::Count`]. The work-precision study also runs each solver
//! to a tolerance, [`Stopping::Tolerance`]: a step stops at the first iteration $`j`$ whose
//! iterate moved no node by more than the tolerance,
//! $`\delta^{(j)} = \max_i | x_i^{(j)} - x_i^{(j-1)} | \le \varepsilon`$, with $`x^{(0)}`$ the step's first iterate, or at the count, which is then a cap.
//!
//! **Why one measure for every solver.** The issue asks for each solver's own convergence
//! measure "as the solver's paper uses". Overby 2017's reference implementation runs a fixed
//! count (`admm_iters` in `mattoverby/admm-elastic`, `src/Solver.cpp`), and Liu 2013
//! (Algorithm 3), Macklin 2016 (XPBD), Wang 2015 (Chebyshev), Macklin 2019 (substeps) and
//! Chen 2024 (VBD) run fixed counts in their experiments as far as we know them (from memory:
//! we could not reach their texts). The gradient of the incremental potential (Eq. 20) is not
//! what PBD and XPBD decrease, so it cannot serve them. The change of $`x`$ serves every
//! solver, is what [`crate::solvers::converged_stage::converged_step`] already stops Newton on, and is in
//! metres, the unit of the errors it is traded against. Its known weakness: for an iteration
//! contracting at rate $`\rho`$ the remaining error is about $`\delta/(1-\rho)`$, larger than
//! $`\delta`$ when $`\rho`$ is close to 1 (Liu 2013 and ADMM-PD on stiff springs); the study
//! reports the error each tolerance gives, so a loose stop shows as a large error, not as a
//! false claim.

use crate::error::{shown, Error, Result};
use crate::model::system::{MassSpringSystem, State, Vec3};
use std::collections::BTreeMap;

/// Whether an iteration left its iterate as it was, bit for bit (`previous` against `next`).
///
/// **Fixed points.** An iteration whose result is a function of its iterate alone (the step's
/// other inputs held) and that returns that iterate unchanged is at a fixed point: every later
/// iteration of the step computes the same operations on the same operands and returns the same
/// bits again. A step with a fixed count of iterations stops computing there and goes on with
/// the same iterate, which is the result the remaining iterations would have given, bit for bit
/// (the count itself, which the work-precision study's cost model reads, is unchanged). Bits,
/// not `==`: −0 and +0 are different operands, and a NaN is its own bits.
pub fn same_bits(
    previous: impl IntoIterator<Item = f64>,
    next: impl IntoIterator<Item = f64>,
) -> bool {
    previous
        .into_iter()
        .zip(next)
        .all(|(p, n)| p.to_bits() == n.to_bits())
}

/// How often a step checks for a fixed point: after every fourth iteration. A fixed point,
/// once reached, holds for every later iteration, so the next check finds it; the check (a
/// copy and a comparison of the iterate) costs too much to make after every iteration (scratch
/// programs, the k = 1e6 rope, where no iteration reaches one, thread CPU per iteration, best
/// of five, three or four alternating rounds: XPBD run alone 141-145 ns without the check,
/// 184-188 ns checked after every sweep, 155-158 ns after every fourth; Liu alone 107-109,
/// 115-120 and 108-111 ns; XPBD's lanes 70-73, 93-146 and 77-117 ns). Backward Euler's Newton
/// loop is the exception: it compares each velocity as it writes it (no copy, five iterations a
/// step), so it checks every iteration.
pub const FIXED_POINT_CHECK: usize = 4;

/// Whether iteration `iteration` of a step (from 0) is checked for a fixed point: every
/// [`FIXED_POINT_CHECK`]th.
pub fn checks_for_fixed_point(iteration: usize) -> bool {
    iteration % FIXED_POINT_CHECK == FIXED_POINT_CHECK - 1
}

/// Tells when a step's iterations reach a fixed point ([`same_bits`]), for a solver whose
/// iteration reads nothing that changes but its iterate (some points and some values): the
/// iterate is kept before every [`FIXED_POINT_CHECK`]th iteration and compared after it.
#[derive(Debug, Clone, Default)]
pub struct FixedPoint {
    previous: Vec<f64>,
    reached: bool,
    /// The step's iterations compared so far.
    iteration: usize,
}

impl FixedPoint {
    /// A new step: no fixed point yet.
    pub fn begin_step(&mut self) {
        self.reached = false;
        self.iteration = 0;
    }

    /// Whether an iteration of this step returned its iterate unchanged: the step's
    /// iterations left would return it again, and need not be computed.
    pub fn reached(&self) -> bool {
        self.reached
    }

    /// Keeps the iterate, `points` and `values`, before an iteration (a checked one).
    pub fn keep(&mut self, points: &[Vec3], values: &[f64]) {
        if !checks_for_fixed_point(self.iteration) {
            return;
        }
        self.previous.clear();
        for p in points {
            self.previous.extend_from_slice(p.as_slice());
        }
        self.previous.extend_from_slice(values);
    }

    /// Compares the iterate after the iteration with the one kept (a checked one):
    /// [`same_bits`], every bit compared (no early exit, so that the comparison is a few vector
    /// operations).
    pub fn compare(&mut self, points: &[Vec3], values: &[f64]) {
        let checked = checks_for_fixed_point(self.iteration);
        self.iteration += 1;
        if !checked {
            return;
        }
        let (kept_points, kept_values) = self.previous.split_at(3 * points.len());
        let mut moved = 0;
        for (kept, p) in kept_points.chunks_exact(3).zip(points) {
            for c in 0..3 {
                moved |= kept[c].to_bits() ^ p[c].to_bits();
            }
        }
        for (kept, v) in kept_values.iter().zip(values) {
            moved |= kept.to_bits() ^ v.to_bits();
        }
        self.reached = moved == 0;
    }
}

/// The largest stopping tolerance, m: the scenes' bound on a coordinate (`LIMITS.coordinate`,
/// 1e6 m); a larger one stops every step after its first iteration anyway.
pub const MAX_STOP_TOLERANCE: f64 = 1e6;

/// `tolerance`, m, if it is > 0 and at most [`MAX_STOP_TOLERANCE`].
fn require_tolerance(field: &str, tolerance: f64) -> Result<f64> {
    if tolerance > 0.0 && tolerance <= MAX_STOP_TOLERANCE {
        Ok(tolerance)
    } else {
        Err(Error::invalid(
            field,
            shown(tolerance),
            &format!(
                "a number > 0 and at most {}, in m",
                shown(MAX_STOP_TOLERANCE)
            ),
        ))
    }
}

/// When a step stops iterating.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub enum Stopping {
    /// After the solver's iteration count, every step: the thesis's mode.
    #[default]
    Count,
    /// At the first iteration that moves no node by more than this, m, or at the iteration
    /// count, which is then a cap.
    Tolerance(f64),
    /// At the first iterate whose own residual is at most this, m, or at the count: for a
    /// minimizing solver the stage problem's gradient over the node's mass, the largest
    /// $`|x_i - x_{a,i} - \tau u_{0,i} - \tau^2 F_i(x)/m_i|`$ over the free nodes (zero at the
    /// stage's minimiser, thesis Eq 20); for PBD and XPBD their constraint residual, the
    /// largest $`|C_j(x) + \tilde\alpha_j \lambda_j|`$ (Eq 16, $`\tilde\alpha = 0`$ for PBD).
    Residual(f64),
}

impl Stopping {
    /// A tolerance mode, checked: `tolerance` > 0 and at most [`MAX_STOP_TOLERANCE`].
    pub fn tolerance(tolerance: f64) -> Result<Self> {
        Ok(Stopping::Tolerance(require_tolerance(
            "stop_tolerance",
            tolerance,
        )?))
    }

    /// A residual mode, checked: `tolerance` > 0 and at most [`MAX_STOP_TOLERANCE`].
    pub fn residual(tolerance: f64) -> Result<Self> {
        Ok(Stopping::Residual(require_tolerance(
            "residual_tolerance",
            tolerance,
        )?))
    }

    /// `count`, `tolerance 1e-6` or `residual 1e-6` (the data files' label).
    pub fn id(self) -> String {
        match self {
            Stopping::Count => "count".into(),
            Stopping::Tolerance(t) => format!("tolerance {t:e}"),
            Stopping::Residual(t) => format!("residual {t:e}"),
        }
    }

    /// The tolerance, m, if any (of either mode).
    pub fn tolerance_m(self) -> Option<f64> {
        match self {
            Stopping::Count => None,
            Stopping::Tolerance(t) | Stopping::Residual(t) => Some(t),
        }
    }
}

/// The iterations the steps of a run took.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct IterationLog {
    /// `steps_by_iterations[&m]`: the steps that took `m` iterations, for the counts some step
    /// took only, so that its size is bounded by the steps run, not by the iteration count a
    /// step may take (`--iterations 1000000000` needs one entry, not 8 GB).
    pub steps_by_iterations: BTreeMap<usize, u64>,
    /// Steps that reached the count without meeting the tolerance (tolerance mode only).
    pub capped: u64,
    /// Work beyond the iterations, in units the solver's cost model names: L-BFGS's line-search
    /// trials after the first of each iteration, Anderson's rejected extrapolations.
    pub extra: u64,
    /// Vertex updates VBD's local step skipped ($`|\det H_i| \le \varepsilon`$,
    /// [`crate::solvers::vbd`]): work not done, counted so that a run says how often it happened.
    pub skipped: u64,
    /// The largest distance, m, of any step's (stage's) first iterate from its inertial
    /// prediction $`y`$ ([`Convergence::begin_from`]): the
    /// start a run actually used, measured as it ran (0 to the bit from $`y`$ itself).
    pub start_distance_m: f64,
    /// The largest residual a step ended at, m (residual mode only, else 0): what a run
    /// stopped at a residual reached.
    pub largest_end_residual_m: f64,
}

impl IterationLog {
    /// Steps recorded.
    pub fn steps(&self) -> u64 {
        self.steps_by_iterations.values().sum()
    }

    /// Iterations over all steps.
    pub fn iterations(&self) -> u64 {
        self.steps_by_iterations
            .iter()
            .map(|(&m, &count)| m as u64 * count)
            .sum()
    }

    /// Iterations per step; None before the first step.
    pub fn mean_iterations(&self) -> Option<f64> {
        let steps = self.steps();
        (steps > 0).then(|| self.iterations() as f64 / steps as f64)
    }
}

/// The stopping test of a solver's steps, and their log. A step calls [`Convergence::begin`]
/// with its first iterate, [`Convergence::converged`] after each iteration (and stops when it
/// says so or at its count), then [`Convergence::end_step`].
#[derive(Debug, Clone, Default)]
pub struct Convergence {
    stopping: Stopping,
    /// The residual mode's system, its stage's $`x_a + \tau u_0`$ and $`\tau^2`$, and a force
    /// buffer.
    system: Option<MassSpringSystem>,
    anchor: Vec<Vec3>,
    tau2: f64,
    forces: Vec<Vec3>,
    /// The previous iterate's nodes (tolerance mode only).
    previous: Vec<Vec3>,
    /// Iterations of the current step.
    iterations: usize,
    /// Whether the current step met the tolerance.
    met: bool,
    /// The residual of the current step's last iterate (residual mode).
    residual: f64,
    log: IterationLog,
}

impl Convergence {
    /// A test in `stopping` mode.
    pub fn new(stopping: Stopping) -> Self {
        Self {
            stopping,
            ..Self::default()
        }
    }

    /// A test in `stopping` mode for a solver of `system` (the residual mode evaluates its
    /// forces).
    pub fn for_system(stopping: Stopping, system: &MassSpringSystem) -> Self {
        let mut c = Self::new(stopping);
        if let Stopping::Residual(_) = stopping {
            c.forces = vec![Vec3::zeros(); system.len()];
            c.system = Some(system.clone());
        }
        c
    }

    /// The mode.
    pub fn stopping(&self) -> Stopping {
        self.stopping
    }

    /// `70 iterations`, or in the tolerance mode `iterations to 1e-6 m, at most 70`, for a
    /// solver's name.
    pub fn iterations_label(&self, count: usize, noun: &str) -> String {
        match self.stopping {
            Stopping::Count => format!("{count} {noun}"),
            Stopping::Tolerance(t) => format!("{noun} to {t:e} m, at most {count}"),
            Stopping::Residual(t) => format!("{noun} to a residual of {t:e} m, at most {count}"),
        }
    }

    /// The log of the steps so far.
    pub fn log(&self) -> &IterationLog {
        &self.log
    }

    /// A step starts from the iterate `x` (its nodes); the count mode reads nothing.
    pub fn begin(&mut self, x: impl Iterator<Item = Vec3>) {
        if self.restart() {
            self.previous.extend(x);
        }
    }

    /// A new step's counters reset; whether the mode keeps its iterates (the tolerance
    /// mode, its previous iterate cleared).
    fn restart(&mut self) -> bool {
        self.iterations = 0;
        self.met = false;
        let keep = matches!(self.stopping, Stopping::Tolerance(_));
        if keep {
            self.previous.clear();
        }
        keep
    }

    /// A step of `system` from `(x_n, v_n)` at `dt` starts from the iterate `x`: as
    /// [`Convergence::begin`], and the log keeps the iterate's distance from the step's
    /// inertial prediction ([`IterationLog::start_distance_m`]).
    pub fn begin_from(
        &mut self,
        system: &MassSpringSystem,
        x_n: &[Vec3],
        v_n: &[Vec3],
        dt: f64,
        x: impl Iterator<Item = Vec3>,
    ) {
        let keep = self.restart();
        let mut largest = 0.0_f64;
        for (i, x) in x.enumerate() {
            let y =
                crate::integrators::prediction::inertial_prediction_from(system, x_n, v_n, dt, i);
            largest = largest.max((x - y).norm());
            if keep {
                self.previous.push(x);
            }
        }
        self.log.start_distance_m = self.log.start_distance_m.max(largest);
    }

    /// A minimizing solver's stage of `system` starts from the iterate `x`:
    /// [`Convergence::begin_from`] the stage's pseudo-state `stage` $`(x_a, u_0)`$ at its step
    /// $`\tau`$, and for the residual mode that pseudo-state and step.
    pub fn begin_stage(
        &mut self,
        system: &MassSpringSystem,
        stage: &State,
        tau: f64,
        x: impl Iterator<Item = Vec3>,
    ) {
        self.begin_from(system, &stage.x, &stage.v, tau, x);
        if let Stopping::Residual(_) = self.stopping {
            self.anchor.clear();
            self.anchor
                .extend(stage.x.iter().zip(&stage.v).map(|(x, u)| x + tau * u));
            self.tau2 = tau * tau;
        }
    }

    /// An error naming `residual_tolerance` in the residual mode: a solver with a dissipation
    /// ([`crate::integrators::dissipation`]) minimises a stage objective with the dissipation's term, whose
    /// gradient the undamped residual of [`Stopping::Residual`] leaves out.
    pub fn refuse_residual_with_dissipation(&self) -> Result<()> {
        match self.stopping {
            Stopping::Residual(t) => Err(crate::error::Error::invalid(
                "residual_tolerance",
                t,
                "no residual mode with a dissipation: the residual is the undamped stage \
                 problem's (use the tolerance mode)",
            )),
            _ => Ok(()),
        }
    }

    /// Whether the mode reads a solver-supplied residual ([`Convergence::converged_value`])
    /// rather than the iterate: the residual mode of a solver that did not begin a stage
    /// (PBD, XPBD).
    pub fn wants_value(&self) -> bool {
        matches!(self.stopping, Stopping::Residual(_)) && self.anchor.is_empty()
    }

    /// An iteration left the residual `r`, m: whether it meets the residual tolerance.
    pub fn converged_value(&mut self, r: f64) -> bool {
        self.iterations += 1;
        let Stopping::Residual(tolerance) = self.stopping else {
            return false;
        };
        self.residual = r;
        self.met = r <= tolerance;
        self.met
    }

    /// An iteration produced the iterate `x`: whether it meets the tolerance,
    /// $`\delta^{(j)} \le \varepsilon`$ (module doc). Always false in the count mode, which
    /// reads nothing, so that a run in that mode does the arithmetic of a solver without this
    /// test.
    pub fn converged(&mut self, x: impl Iterator<Item = Vec3>) -> bool {
        if let Stopping::Residual(tolerance) = self.stopping {
            self.iterations += 1;
            let r = self.stage_residual(x);
            self.residual = r;
            self.met = r <= tolerance;
            return self.met;
        }
        self.iterations += 1;
        let Stopping::Tolerance(tolerance) = self.stopping else {
            return false;
        };
        let mut delta = 0.0_f64;
        for (previous, x) in self.previous.iter_mut().zip(x) {
            delta = delta.max((x - *previous).norm());
            *previous = x;
        }
        self.met = delta <= tolerance;
        self.met
    }

    /// The stage problem's residual at `x`, m (the [`Stopping::Residual`] doc); infinite, so
    /// that the step runs to its cap, for a test not built for its system
    /// ([`Convergence::for_system`]) or a stage not begun ([`Convergence::begin_stage`]).
    fn stage_residual(&mut self, x: impl Iterator<Item = Vec3>) -> f64 {
        let Some(system) = self.system.as_ref().filter(|_| !self.anchor.is_empty()) else {
            return f64::INFINITY;
        };
        self.previous.clear();
        self.previous.extend(x);
        system.forces(&self.previous, &mut self.forces);
        let mut r = 0.0_f64;
        for (i, node) in system.nodes().iter().enumerate() {
            if !node.fixed {
                let g = self.previous[i] - self.anchor[i] - self.tau2 / node.mass * self.forces[i];
                r = r.max(g.norm());
            }
        }
        r
    }

    /// An iteration found that its iterate cannot move (below round-off): it counts, and the
    /// step has converged.
    pub fn stalled(&mut self) {
        self.iterations += 1;
        self.met = true;
    }

    /// Local updates the step skipped ([`IterationLog::skipped`]).
    pub fn skipped(&mut self, count: u64) {
        self.log.skipped += count;
    }

    /// The step ended; `extra` counts its work beyond its iterations ([`IterationLog::extra`]).
    pub fn end_step(&mut self, extra: u64) {
        self.end_step_counted(self.iterations, extra);
    }

    /// The step ended after `iterations` in the solver's own unit, which differs from the
    /// iterates it tested: the accelerated solvers count global solves, and ADMM's take one
    /// more than its iterates (the last turns $`(z, \bar u)`$ into positions).
    pub fn end_step_counted(&mut self, iterations: usize, extra: u64) {
        let log = &mut self.log;
        *log.steps_by_iterations.entry(iterations).or_insert(0) += 1;
        if !self.met && !matches!(self.stopping, Stopping::Count) {
            log.capped += 1;
        }
        if let Stopping::Residual(_) = self.stopping {
            log.largest_end_residual_m = log.largest_end_residual_m.max(self.residual);
        }
        log.extra += extra;
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_count_mode_never_converges_and_logs_the_count() {
        let mut c = Convergence::new(Stopping::Count);
        for _ in 0..2 {
            c.begin([Vec3::zeros()].into_iter());
            for _ in 0..3 {
                assert!(!c.converged([Vec3::zeros()].into_iter()));
            }
            c.end_step(0);
        }
        assert_eq!(c.log().steps_by_iterations, BTreeMap::from([(3, 2)]));
        assert_eq!(c.log().capped, 0);
        assert_eq!(c.log().mean_iterations(), Some(3.0));
    }

    /// A residual test built without its system, or a stage not begun, runs every step to its
    /// cap (and logs it capped) rather than panicking.
    #[test]
    fn a_residual_test_without_its_stage_never_converges() {
        let mut c = Convergence::new(Stopping::residual(1e3).unwrap());
        c.begin([Vec3::zeros()].into_iter());
        for _ in 0..3 {
            assert!(!c.converged([Vec3::zeros()].into_iter()));
        }
        c.end_step(0);
        assert_eq!(c.log().capped, 1);
    }

    #[test]
    fn the_tolerance_mode_stops_on_the_largest_node_move() {
        let mut c = Convergence::new(Stopping::tolerance(0.1).unwrap());
        let at = |a: f64, b: f64| [Vec3::new(a, 0.0, 0.0), Vec3::new(0.0, b, 0.0)].into_iter();
        c.begin(at(0.0, 0.0));
        // One node moves 0.5: not converged, even though the other did not move.
        assert!(!c.converged(at(0.5, 0.0)));
        // Both move by at most 0.1 from the previous iterate (not from the first).
        assert!(c.converged(at(0.6, 0.1)));
        c.end_step(4);
        // A step that stops at its cap, unconverged.
        c.begin(at(0.0, 0.0));
        for j in 1..=3 {
            assert!(!c.converged(at(j as f64, 0.0)));
        }
        c.end_step(0);
        assert_eq!(
            c.log().steps_by_iterations,
            BTreeMap::from([(2, 1), (3, 1)])
        );
        assert_eq!(c.log().capped, 1);
        assert_eq!(c.log().extra, 4);
        assert_eq!(c.log().iterations(), 5);
        assert!(Stopping::tolerance(0.0).is_err());
        assert!(Stopping::tolerance(f64::NAN).is_err());
    }
}
