//! The common interface of every time stepper and the run loop that measures it (§4.2).
//!
//! A solver only advances a [`State`] by one step; [`simulate`] drives any solver the same way,
//! detects the kinetic-energy peaks, applies the stopping rule, guards against divergence and
//! records what the report and the command line need.

use crate::error::{require_non_negative, Error, Result};
use crate::integrators::stopping::{Convergence, IterationLog, Stopping};
use crate::model::metrics::{
    half_period_exact, half_period_thesis, Peak, PeakDetector, StoppingRule,
};
use crate::model::system::{MassSpringSystem, State};

/// A time-stepping method for a mass-spring system.
pub trait TimeStepper {
    /// A short human-readable name with the method's parameters.
    fn name(&self) -> String;
    /// Time step, s.
    fn dt(&self) -> f64;
    /// The system being simulated.
    fn system(&self) -> &MassSpringSystem;
    /// Advances `state` by one time step.
    fn step(&mut self, state: &mut State) -> Result<()>;

    /// The test that stops the solver's steps, with the log of their iterations; None for a
    /// solver whose steps have no iterations to stop.
    fn convergence(&mut self) -> Option<&mut Convergence> {
        None
    }

    /// Sets when each step stops iterating ([`Stopping`]); an error naming `stop_tolerance`
    /// for a solver whose steps have no iterations to stop.
    fn set_stopping(&mut self, stopping: Stopping) -> Result<()> {
        let name = self.name();
        let fresh = Convergence::for_system(stopping, self.system());
        match (self.convergence(), stopping) {
            (Some(convergence), _) => {
                *convergence = fresh;
                Ok(())
            }
            (None, Stopping::Count) => Ok(()),
            (None, Stopping::Tolerance(t) | Stopping::Residual(t)) => Err(Error::invalid(
                "stop_tolerance",
                t,
                &format!("no tolerance: {name} has no iterations to stop"),
            )),
        }
    }

    /// The iterations the steps so far took; None for a solver without iterations.
    fn iteration_log(&mut self) -> Option<&IterationLog> {
        self.convergence().map(|c| c.log())
    }

    /// The start the steps so far used, measured as they ran: the largest distance of a
    /// step's first iterate from its inertial prediction, m
    /// ([`IterationLog::start_distance_m`]); None where it is not measured (no iterations).
    fn start_distance_m(&mut self) -> Option<f64> {
        self.iteration_log().map(|l| l.start_distance_m)
    }
}

/// A kinetic energy this many times the run's energy scale counts as divergence.
pub const DIVERGENCE_FACTOR: f64 = 1e6;

/// What [`simulate`] records besides the peaks.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct Recording {
    /// Keep every kinetic-energy sample.
    pub kinetic_energy: bool,
    /// Keep the positions every this many steps (and the first and last).
    pub positions_every: Option<u64>,
}

/// Receives the series a run records ([`Recording`]) as the run goes, so that a long series
/// can go to a file instead of memory.
pub trait Recorder {
    /// The kinetic energy after `step` steps (0: the initial state), J.
    fn kinetic_energy(&mut self, step: u64, energy: f64) -> std::io::Result<()>;
    /// The state after `step` steps.
    fn positions(&mut self, step: u64, state: &State) -> std::io::Result<()>;
}

/// The recorder of [`simulate`]: the series in memory, as [`Run`] holds them.
pub(crate) struct InMemory {
    dt: f64,
    kinetic_energy: Vec<f64>,
    positions: Vec<(f64, State)>,
}

impl InMemory {
    /// Nothing recorded yet, for a run of time step `dt`.
    pub(crate) fn new(dt: f64) -> Self {
        Self {
            dt,
            kinetic_energy: Vec::new(),
            positions: Vec::new(),
        }
    }

    /// `run` with the series recorded.
    pub(crate) fn into_run(self, run: Run) -> Run {
        Run {
            kinetic_energy: self.kinetic_energy,
            positions: self.positions,
            ..run
        }
    }
}

impl Recorder for InMemory {
    fn kinetic_energy(&mut self, _step: u64, energy: f64) -> std::io::Result<()> {
        self.kinetic_energy.push(energy);
        Ok(())
    }

    fn positions(&mut self, step: u64, state: &State) -> std::io::Result<()> {
        self.positions.push((step as f64 * self.dt, state.clone()));
        Ok(())
    }
}

/// Options of a run.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct RunOptions {
    pub stop: StoppingRule,
    /// Variant, 0 in the faithful runs: after each step $`v \leftarrow v\,e^{-c\,dt}`$, s⁻¹.
    pub velocity_damping: f64,
    pub recording: Recording,
}

/// The outcome of a run.
#[derive(Debug, Clone, PartialEq)]
pub struct Run {
    pub solver: String,
    pub dt: f64,
    /// Steps taken.
    pub steps: u64,
    /// Every kinetic-energy peak, the stopping one included.
    pub peaks: Vec<Peak>,
    /// True when the run reached `max_time` before the stopping rule fired.
    pub hit_time_limit: bool,
    pub final_state: State,
    /// Kinetic energy per step from t = 0, if recorded.
    pub kinetic_energy: Vec<f64>,
    /// (time, positions) samples, if recorded.
    pub positions: Vec<(f64, State)>,
}

impl Run {
    /// "nº máx. E_k": the number of peaks.
    pub fn peak_count(&self) -> usize {
        self.peaks.len()
    }

    /// T/2 under the thesis convention.
    pub fn half_period_thesis(&self) -> Option<f64> {
        half_period_thesis(&self.peaks)
    }

    /// T/2 under the exact convention.
    pub fn half_period_exact(&self) -> Option<f64> {
        half_period_exact(&self.peaks)
    }

    /// Simulated time at the end, s.
    pub fn end_time(&self) -> f64 {
        self.steps as f64 * self.dt
    }
}

/// The energy that a diverging run exceeds by [`DIVERGENCE_FACTOR`]: the largest of the initial
/// kinetic energy, the initial potential energy's magnitude, the work gravity does over the
/// system's extent and the springs' energy at twice their rest length ($`\sum \frac12 k l_0^2`$),
/// so that a system starting at rest, with or without gravity, still has a scale.
fn energy_scale(system: &MassSpringSystem, state: &State) -> f64 {
    let (lo, hi) = state
        .x
        .iter()
        .fold((state.x[0], state.x[0]), |(lo, hi), p| {
            (lo.inf(p), hi.sup(p))
        });
    let total_mass: f64 = system.nodes().iter().map(|n| n.mass).sum();
    let gravity_work = total_mass * system.gravity().norm() * (hi - lo).norm();
    let spring_scale: f64 = system
        .springs()
        .iter()
        .map(|s| 0.5 * s.stiffness * s.rest_length * s.rest_length)
        .sum();
    [
        state.kinetic_energy(system),
        system.potential_energy(&state.x).abs(),
        gravity_work,
        spring_scale,
        f64::MIN_POSITIVE,
    ]
    .into_iter()
    .fold(0.0, f64::max)
}

/// Runs `solver` from `state` until the stopping rule fires or time runs out (§4.2).
///
/// A non-finite state or a kinetic energy above [`DIVERGENCE_FACTOR`] times the energy scale
/// stops the run with [`Error::Diverged`], naming the step and time; a failing step stops it
/// with [`Error::StepFailed`].
pub fn simulate(solver: &mut dyn TimeStepper, state: State, options: &RunOptions) -> Result<Run> {
    let mut memory = InMemory::new(solver.dt());
    let run = simulate_into(solver, state, options, &mut memory)?;
    Ok(memory.into_run(run))
}

/// [`simulate`], handing the recorded series to `recorder` as they come (the [`Run`]'s own
/// series stay empty). A recorder's error stops the run with [`Error::Input`].
pub fn simulate_into(
    solver: &mut dyn TimeStepper,
    mut state: State,
    options: &RunOptions,
    recorder: &mut dyn Recorder,
) -> Result<Run> {
    let mut watch = Watch::start(solver, &state, options, recorder)?;
    while watch.running() {
        solver.step(&mut state).map_err(|e| watch.step_failed(e))?;
        watch.after_step(solver.system(), &mut state, recorder)?;
    }
    watch.finish(state, recorder)
}

/// What the run loop does around the steps of one run: the checks before the first, and after
/// each the damping, the divergence guard, the recording, the peaks and the stopping rule.
/// [`simulate_into`] watches one run with it, [`crate::solvers::batch::simulate_batch`] every run of a
/// batch, so that a run in a lane is watched as the run alone.
pub struct Watch<'o> {
    options: &'o RunOptions,
    name: String,
    dt: f64,
    damping_factor: f64,
    max_steps: u64,
    scale: f64,
    detector: PeakDetector,
    peaks: Vec<Peak>,
    steps: u64,
    /// The last step whose positions were recorded.
    positions_at: Option<u64>,
    stopped: bool,
}

impl<'o> Watch<'o> {
    /// Checks `options` and records the start `state` of a run of `solver`.
    pub fn start(
        solver: &dyn TimeStepper,
        state: &State,
        options: &'o RunOptions,
        recorder: &mut dyn Recorder,
    ) -> Result<Self> {
        options.stop.validate()?;
        require_non_negative("velocity_damping", options.velocity_damping)?;
        let dt = solver.dt();
        let mut watch = Self {
            options,
            name: solver.name(),
            dt,
            damping_factor: (-options.velocity_damping * dt).exp(),
            max_steps: (options.stop.max_time / dt).round() as u64,
            scale: energy_scale(solver.system(), state),
            detector: PeakDetector::new(dt),
            peaks: Vec::new(),
            steps: 0,
            positions_at: None,
            stopped: false,
        };
        let ke0 = state.kinetic_energy(solver.system());
        watch.detector.push(ke0);
        if options.recording.kinetic_energy {
            recorder
                .kinetic_energy(0, ke0)
                .map_err(|e| watch.recorded(0, e))?;
        }
        if options.recording.positions_every.is_some() {
            recorder
                .positions(0, state)
                .map_err(|e| watch.recorded(0, e))?;
            watch.positions_at = Some(0);
        }
        Ok(watch)
    }

    fn recorded(&self, step: u64, e: std::io::Error) -> Error {
        Error::Input(format!("recording step {step} of {}: {e}", self.name))
    }

    /// Whether the run takes another step: its stopping rule has not fired and time is left.
    pub fn running(&self) -> bool {
        !self.stopped && self.steps < self.max_steps
    }

    /// Whether the run damps the velocities after each step (so that they change outside the
    /// solver).
    pub fn damps(&self) -> bool {
        self.options.velocity_damping > 0.0
    }

    /// The error of a step that failed.
    pub fn step_failed(&self, source: Error) -> Error {
        Error::StepFailed {
            solver: self.name.clone(),
            step: self.steps + 1,
            time: (self.steps + 1) as f64 * self.dt,
            source: Box::new(source),
        }
    }

    /// The solver took a step to `state`: the damping, then [`Self::after_measured_step`] on
    /// the damped state's kinetic energy, then its positions if they are due.
    pub fn after_step(
        &mut self,
        system: &MassSpringSystem,
        state: &mut State,
        recorder: &mut dyn Recorder,
    ) -> Result<()> {
        if let Some(factor) = self.damping_factor() {
            for v in &mut state.v {
                *v *= factor;
            }
        }
        self.after_measured_step(state.kinetic_energy(system), state.is_finite(), recorder)?;
        if self.positions_due() {
            self.record_positions(state, recorder)?;
        }
        Ok(())
    }

    /// The factor the velocities are multiplied by after each step, if the run damps them.
    pub fn damping_factor(&self) -> Option<f64> {
        self.damps().then_some(self.damping_factor)
    }

    /// [`Self::after_step`] once the step's state is damped and measured (its kinetic energy
    /// `ke`, whether every coordinate is `finite`), but for the positions
    /// ([`Self::positions_due`]): the divergence guard, the energy's recording, the peaks and
    /// the stopping rule. A batch measures its lanes together and reads a lane's state only
    /// where it is needed ([`crate::solvers::batch::simulate_batch`]).
    pub fn after_measured_step(
        &mut self,
        ke: f64,
        finite: bool,
        recorder: &mut dyn Recorder,
    ) -> Result<()> {
        let time = (self.steps + 1) as f64 * self.dt;
        self.steps += 1;
        let steps = self.steps;
        let scale = self.scale;
        if !finite || !ke.is_finite() || ke > DIVERGENCE_FACTOR * scale {
            let reason = if finite && ke.is_finite() {
                format!("kinetic energy {ke:e} J exceeds {DIVERGENCE_FACTOR:e} x the energy scale {scale:e} J")
            } else {
                "the state is no longer finite".to_string()
            };
            return Err(Error::Diverged {
                solver: self.name.clone(),
                step: steps,
                time,
                reason,
            });
        }
        if self.options.recording.kinetic_energy {
            recorder
                .kinetic_energy(steps, ke)
                .map_err(|e| self.recorded(steps, e))?;
        }
        if let Some(peak) = self.detector.push(ke) {
            self.peaks.push(peak);
            let exempt = self.options.stop.exempt_first_peak && self.peaks.len() == 1;
            if peak.energy < self.options.stop.threshold && !exempt {
                self.stopped = true;
            }
        }
        Ok(())
    }

    /// Whether the positions of the step just watched are to be recorded.
    pub fn positions_due(&self) -> bool {
        self.options
            .recording
            .positions_every
            .is_some_and(|every| self.steps % every.max(1) == 0)
    }

    /// Records `state` as the positions of the step just watched.
    pub fn record_positions(&mut self, state: &State, recorder: &mut dyn Recorder) -> Result<()> {
        recorder
            .positions(self.steps, state)
            .map_err(|e| self.recorded(self.steps, e))?;
        self.positions_at = Some(self.steps);
        Ok(())
    }

    /// Steps `solver` from `state` until the run stops, and returns it.
    pub fn run_to_end(
        mut self,
        solver: &mut dyn TimeStepper,
        mut state: State,
        recorder: &mut dyn Recorder,
    ) -> Result<Run> {
        while self.running() {
            solver.step(&mut state).map_err(|e| self.step_failed(e))?;
            self.after_step(solver.system(), &mut state, recorder)?;
        }
        self.finish(state, recorder)
    }

    /// The run, ended at `state`.
    pub fn finish(self, state: State, recorder: &mut dyn Recorder) -> Result<Run> {
        if self.positions_at.is_some_and(|at| at < self.steps) {
            recorder
                .positions(self.steps, &state)
                .map_err(|e| self.recorded(self.steps, e))?;
        }
        Ok(Run {
            solver: self.name,
            dt: self.dt,
            steps: self.steps,
            peaks: self.peaks,
            hit_time_limit: !self.stopped,
            final_state: state,
            kinetic_energy: Vec::new(),
            positions: Vec::new(),
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::model::metrics::StoppingRule;
    use crate::model::scene::thesis_rope;
    use crate::solvers::backward_euler::BackwardEuler;

    /// Collects what it is handed, with the step numbers.
    #[derive(Default)]
    struct Collect {
        kinetic_energy: Vec<(u64, f64)>,
        positions: Vec<(u64, State)>,
    }

    impl Recorder for Collect {
        fn kinetic_energy(&mut self, step: u64, energy: f64) -> std::io::Result<()> {
            self.kinetic_energy.push((step, energy));
            Ok(())
        }

        fn positions(&mut self, step: u64, state: &State) -> std::io::Result<()> {
            self.positions.push((step, state.clone()));
            Ok(())
        }
    }

    #[test]
    fn a_recorder_gets_the_series_simulate_keeps_in_memory() {
        let system = thesis_rope(1e3).unwrap();
        let options = RunOptions {
            stop: StoppingRule {
                max_time: 0.05,
                ..StoppingRule::default()
            },
            recording: Recording {
                kinetic_energy: true,
                positions_every: Some(7),
            },
            ..RunOptions::default()
        };
        let mut solver = BackwardEuler::reference(&system).unwrap();
        let kept = simulate(&mut solver, system.initial_state(), &options).unwrap();
        let mut solver = BackwardEuler::reference(&system).unwrap();
        let mut collect = Collect::default();
        let streamed =
            simulate_into(&mut solver, system.initial_state(), &options, &mut collect).unwrap();
        assert!(streamed.kinetic_energy.is_empty() && streamed.positions.is_empty());
        assert_eq!(collect.kinetic_energy.len(), 51);
        let steps: Vec<u64> = collect.positions.iter().map(|(s, _)| *s).collect();
        // t = 0, every 7th step, and the last (50).
        assert_eq!(steps, [0, 7, 14, 21, 28, 35, 42, 49, 50]);
        assert!(collect
            .kinetic_energy
            .iter()
            .enumerate()
            .all(|(i, (s, e))| *s == i as u64 && *e == kept.kinetic_energy[i]));
        for ((step, state), (time, kept)) in collect.positions.iter().zip(&kept.positions) {
            assert_eq!((*step as f64 * streamed.dt, state), (*time, kept));
        }
        assert_eq!(collect.positions.len(), kept.positions.len());
    }
}
