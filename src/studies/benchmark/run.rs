//! One configuration run and measured against its case's ground truths.

use super::metrics::Trajectory;
use super::metrics::{energy_decay_per_period, largest_distance, modal_period, rms_distance};
use super::sweep::Configuration;
use super::truth::{CaseTruth, SolverTruth};
use crate::error::Result;
use crate::integrators::time_stepper::TimeStepper;
use crate::model::system::MassSpringSystem;
use crate::studies::work_precision::{logged_flops, run_flops};

/// An error against one ground truth, per node over the free nodes.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct NodeError {
    /// RMS over the samples and free nodes, m.
    pub rms: f64,
    /// The largest node distance over the samples, m.
    pub max: f64,
    /// The RMS over the exact motion's RMS amplitude about the equilibrium.
    pub relative: f64,
}

impl NodeError {
    /// The error of `run` against `truth`, scaled by `amplitude`.
    pub fn between(
        system: &crate::model::system::MassSpringSystem,
        run: &Trajectory,
        truth: &Trajectory,
        amplitude: f64,
    ) -> Self {
        let rms = rms_distance(system, &run.samples, &truth.samples);
        Self {
            rms,
            max: largest_distance(&run.samples, &truth.samples),
            relative: rms / amplitude,
        }
    }
}

/// What one configuration measured.
#[derive(Debug, Clone, PartialEq)]
pub struct Measurement {
    /// The physical error, against the exact motion.
    pub physical: NodeError,
    /// The solver error, against the same method with every step solved to round-off; None
    /// where that method is not run (time steps outside [`super::sweep::SOLVER_ERROR_DTS`],
    /// the substeps and the baselines).
    pub solver: Option<NodeError>,
    /// The fraction of the solver-error reference's steps that reached its cap; None without
    /// a reference. Above zero, [`Measurement::solver`] is None.
    pub reference_capped_fraction: Option<f64>,
    /// The lowest mode's period over the exact motion's, minus one; None where it does not
    /// oscillate over the window.
    pub phase_error: Option<f64>,
    /// The lowest mode's energy lost per (exact) period.
    pub energy_decay: Option<f64>,
    /// The mean iterations a step took (the fixed count in the count mode).
    pub iterations_mean: f64,
    /// In a tolerance mode, the fraction of steps that reached the cap without meeting it.
    pub capped_fraction: Option<f64>,
    /// The start the run used, measured as it ran: the largest distance of a step's first
    /// iterate from its inertial prediction, m ([`crate::integrators::stopping::IterationLog::start_distance_m`]);
    /// None for a solver without iterations (the explicit baselines).
    pub start_distance_m: Option<f64>,
}

/// A configuration's outcome: its cost and its measurement, or why it stopped.
#[derive(Debug, Clone, PartialEq)]
pub struct Outcome {
    pub configuration: Configuration,
    /// Floating-point operations over the window: counted from the iterations its steps took
    /// where it logged them, else the model's count.
    pub flops: f64,
    pub measured: std::result::Result<Measurement, String>,
}

/// The solver of a configuration on its case's `system`: the one place that builds it, so
/// that `make timing` times what the benchmark measures.
pub fn build_solver(
    configuration: &Configuration,
    system: &MassSpringSystem,
) -> Result<Box<dyn TimeStepper>> {
    configuration.spec.build(system, configuration.dt_s)
}

/// Runs a configuration over its case's window and measures it against `truth` and, for the
/// solver error, its method's converged trajectory `reference`, unless a step of that
/// reference reached its cap (then the solver error is not measured and the fraction is
/// kept).
pub fn run(
    configuration: &Configuration,
    truth: &CaseTruth,
    reference: Option<&SolverTruth>,
) -> Result<Outcome> {
    let case = configuration.case;
    let system = case.scene.system(case.stiffness)?;
    let mut solver = build_solver(configuration, &system)?;
    let trajectory = truth.record_window(solver.as_mut(), &system);
    let start_distance_m = solver.start_distance_m();
    let log = solver
        .iteration_log()
        .filter(|_| trajectory.is_ok())
        .cloned();
    let spec = &configuration.spec;
    let flops = match &log {
        Some(log) => logged_flops(spec, &system, log),
        None => run_flops(spec, &system, configuration.dt_s, truth.window),
    };
    let measured = trajectory
        .map(|t| {
            let exact_period = modal_period(&truth.exact);
            let period = modal_period(&t);
            Measurement {
                physical: NodeError::between(&system, &t, &truth.exact, truth.amplitude),
                solver: reference
                    .filter(|r| r.capped_fraction == 0.0)
                    .map(|r| NodeError::between(&system, &t, &r.trajectory, truth.amplitude)),
                reference_capped_fraction: reference.map(|r| r.capped_fraction),
                phase_error: period.zip(exact_period).map(|(p, e)| p / e - 1.0),
                energy_decay: exact_period.and_then(|p| energy_decay_per_period(&t, p)),
                iterations_mean: log
                    .as_ref()
                    .and_then(|l| l.mean_iterations())
                    .unwrap_or(configuration.spec.iterations as f64),
                capped_fraction: log
                    .as_ref()
                    .filter(|l| spec.stopping.tolerance_m().is_some() && l.steps() > 0)
                    .map(|l| l.capped as f64 / l.steps() as f64),
                start_distance_m,
            }
        })
        .map_err(|e| e.to_string());
    Ok(Outcome {
        configuration: *configuration,
        flops,
        measured,
    })
}
