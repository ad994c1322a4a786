//! Statics ([`super`], item 6 of its specification): the cost for a solver to bring the rope
//! to rest, by the thesis's own stopping rule, and how far from the exact equilibrium it rests.

use super::sweep::{settings, solvers, Configuration};
use crate::error::Result;
use crate::integrators::time_stepper::{simulate, RunOptions};
use crate::model::metrics::StoppingRule;
use crate::model::system::Vec3;
use crate::studies::beyond::GridScene;
use crate::studies::work_precision::Case;
use crate::studies::work_precision::{flops_per_step, flops_setup, logged_flops};

/// The statics runs stop at the thesis's rule (the first kinetic-energy peak below 1e-3 J) or
/// at the thesis's own limit of simulated time, s (a run it cuts is reported as not at rest).
pub const STATICS_MAX_TIME_S: f64 = 3000.0;

/// The time steps of the statics runs, s: the thesis's two coarser ones (its finest, 1e-3 s,
/// is not run: a run to rest there takes ten times the steps of one at 0.01 s).
pub const STATICS_DTS: [f64; 2] = [0.1, 0.01];

/// The statics runs of `make report`: [`all_statics_configurations`] but the long ones
/// ([`is_long_statics`]).
pub fn statics_configurations() -> Vec<Configuration> {
    all_statics_configurations()
        .into_iter()
        .filter(|c| !is_long_statics(c))
        .collect()
}

/// The statics runs of `make report-long`: XPBD substeps', which take one substep per
/// iteration (50 substeps a step at its largest setting) and rest only after hundreds of
/// seconds on the soft rope (2328 s at 50 substeps, dt = 0.01 s): 7.2 of the 12.0 s of CPU
/// that every statics run to the 3000 s limit took when measured (issue 47).
pub fn long_statics_configurations() -> Vec<Configuration> {
    all_statics_configurations()
        .into_iter()
        .filter(is_long_statics)
        .collect()
}

/// Whether a statics run is one of `make report-long`'s.
fn is_long_statics(c: &Configuration) -> bool {
    c.spec.id == crate::solvers::registry::SolverId::XpbdSubsteps
}

/// Every statics run: the rope at both stiffnesses, every solver but the explicit baselines at
/// every setting and time step of the thesis's grid.
fn all_statics_configurations() -> Vec<Configuration> {
    let mut out = Vec::new();
    for case in Case::ALL.into_iter().filter(|c| c.scene == GridScene::Rope) {
        for id in solvers()
            .into_iter()
            .filter(|id| !super::sweep::BASELINES.contains(id))
        {
            for spec in settings(id) {
                for dt_s in STATICS_DTS {
                    out.push(Configuration { case, spec, dt_s });
                }
            }
        }
    }
    out
}

/// A statics run's outcome.
#[derive(Debug, Clone, PartialEq)]
pub struct StaticsOutcome {
    pub configuration: Configuration,
    /// Whether the thesis's rule stopped it before [`STATICS_MAX_TIME_S`].
    pub at_rest: bool,
    /// When it stopped, s.
    pub end_time_s: f64,
    /// The RMS over the free nodes of the distance of its final state to the exact
    /// equilibrium, m.
    pub rest_error_rms_m: f64,
    /// Floating-point operations to the stop.
    pub flops: f64,
    /// The thesis's peaks and T/2 (thesis convention), for a run the rule stopped.
    pub peaks: usize,
    pub half_period_s: Option<f64>,
    /// The start it used, measured as it ran ([`super::run::Measurement::start_distance_m`]).
    pub start_distance_m: Option<f64>,
    /// Why the run stopped early (a divergence), if it did.
    pub failure: Option<String>,
}

/// Runs a statics configuration against the exact `equilibrium` of its case.
pub fn run_statics(configuration: &Configuration, equilibrium: &[Vec3]) -> Result<StaticsOutcome> {
    let case = configuration.case;
    let system = case.scene.system(case.stiffness)?;
    let mut solver = configuration.spec.build(&system, configuration.dt_s)?;
    let run = match simulate(
        solver.as_mut(),
        system.initial_state(),
        &RunOptions {
            stop: StoppingRule {
                max_time: STATICS_MAX_TIME_S,
                ..StoppingRule::default()
            },
            ..RunOptions::default()
        },
    ) {
        Ok(run) => run,
        Err(e) => {
            return Ok(StaticsOutcome {
                configuration: *configuration,
                at_rest: false,
                end_time_s: f64::NAN,
                rest_error_rms_m: f64::NAN,
                flops: f64::NAN,
                peaks: 0,
                half_period_s: None,
                start_distance_m: None,
                failure: Some(e.to_string()),
            })
        }
    };
    let spec = &configuration.spec;
    let start_distance_m = solver.start_distance_m();
    let flops = match solver.iteration_log() {
        Some(log) => logged_flops(spec, &system, log),
        None => flops_setup(spec, &system) + run.steps as f64 * flops_per_step(spec, &system),
    };
    let free: Vec<usize> = (0..system.len())
        .filter(|&i| !system.nodes()[i].fixed)
        .collect();
    let rest_error_rms_m = (free
        .iter()
        .map(|&i| (run.final_state.x[i] - equilibrium[i]).norm_squared())
        .sum::<f64>()
        / free.len() as f64)
        .sqrt();
    Ok(StaticsOutcome {
        configuration: *configuration,
        at_rest: !run.hit_time_limit,
        end_time_s: run.end_time(),
        rest_error_rms_m,
        flops,
        peaks: run.peak_count(),
        half_period_s: (!run.hit_time_limit)
            .then(|| run.half_period_thesis())
            .flatten(),
        start_distance_m,
        failure: None,
    })
}
