//! The 56 experiments of thesis §4.3 (Tables 1-7): the published numbers ([`published`]),
//! the reproduction rule ([`rule`]), and how one row is run and measured.
//!
//! Every run starts from the thesis rope at rest and uses [`crate::integrators::time_stepper::simulate`]; the
//! rest-state error of a row is measured against the final state of the Backward Euler
//! reference of the same stiffness. The labelled departures that explain published numbers
//! live in [`crate::studies::forensics`]; here a [`Configuration`] only carries them to the run.

pub mod batched;

pub mod pool;
pub mod published;
pub mod rule;

pub use pool::run_parallel;
pub use published::{
    published_cost, published_reference, published_rows, same_experiment, PublishedRow,
    PUBLISHED_CSV,
};
pub use rule::{
    better_time_convention, is_marginal, peak_tolerance, reproduces, reproduces_within,
    TimeConvention, HALF_PERIOD_TOLERANCE, MARGINAL_HALF_PERIOD,
};

use crate::error::Result;
use crate::integrators::time_stepper::TimeStepper;
use crate::integrators::time_stepper::{simulate, Run, RunOptions};
use crate::model::metrics::{
    half_period_f64_clock, half_period_sample_stamp, rest_error_l1, rest_error_l2, rest_error_max,
    rest_error_sum, StoppingRule,
};
use crate::model::scene::{RopeParams, THESIS_GRAVITY};
use crate::model::system::Vec3;
use crate::model::system::{MassSpringSystem, State};
use crate::solvers::fast_mass_spring::{FastMassSpring, FirstIterate};
use crate::solvers::registry::SolverId;
use crate::solvers::registry::SolverSpec;
use crate::studies::forensics::admm_variants::{AdmmVariant, VariantAdmm};

/// How the solver of a row is built.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum SolverChoice {
    /// The printed algorithm (Liu started at $`x_n`$, the default reading of its open point).
    Printed,
    /// Liu 2013 started at another first iterate (ignored by the other solvers' rows).
    LiuFirstIterate(FirstIterate),
    /// ADMM-PD with labelled departures (ignored by the other solvers' rows).
    Admm(AdmmVariant),
}

impl SolverChoice {
    /// The solver of a `kind` row.
    pub fn build(
        &self,
        kind: SolverId,
        system: &MassSpringSystem,
        dt: f64,
        iterations: usize,
    ) -> Result<Box<dyn TimeStepper + Send>> {
        Ok(match (self, kind) {
            (SolverChoice::LiuFirstIterate(first), SolverId::FastMassSpring) => {
                Box::new(FastMassSpring::new(system, dt, iterations)?.with_first_iterate(*first))
            }
            (SolverChoice::Admm(variant), SolverId::AdmmPd) => {
                Box::new(VariantAdmm::new(system, dt, iterations, *variant)?)
            }
            _ => SolverSpec::new(kind, iterations).build_send(system, dt)?,
        })
    }
}

/// How a set of runs is made: the stopping rule, the scene's gravity and how each row's solver
/// is built. [`Configuration::faithful`] is the thesis's method as written; the others are
/// built by [`crate::studies::forensics`].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Configuration {
    pub stop: StoppingRule,
    /// Velocity damping c, s⁻¹, applied after each step: $`v \leftarrow v\,e^{-c\,dt}`$.
    pub velocity_damping: f64,
    /// Gravity of the reference runs (Backward Euler rows), m/s².
    pub reference_gravity: f64,
    /// Gravity of the solver runs (every other row), m/s².
    pub gravity: f64,
    /// How the solver of a row is built ([`SolverChoice::Printed`] for the faithful method).
    pub solver: SolverChoice,
}

impl Configuration {
    /// The faithful configuration: the thesis's rule and scene, no damping, every solver as
    /// printed.
    pub fn faithful() -> Self {
        Self {
            stop: StoppingRule::default(),
            velocity_damping: 0.0,
            reference_gravity: THESIS_GRAVITY,
            gravity: THESIS_GRAVITY,
            solver: SolverChoice::Printed,
        }
    }
}

/// A measured experiment: the run's metrics and, for a solver row, its rest-state errors.
#[derive(Debug, Clone, PartialEq)]
pub struct Measured {
    pub published: PublishedRow,
    pub peaks: usize,
    pub half_period_thesis: Option<f64>,
    pub half_period_exact: Option<f64>,
    /// T/2 under the other reading of convention 4 (each peak stamped at its own sample, f32
    /// clock) and of convention 5 (detection step, f64 clock).
    pub half_period_sample_stamp: Option<f64>,
    pub half_period_f64_clock: Option<f64>,
    /// Relative T/2 error (thesis convention) against our reference of the same stiffness.
    pub period_rel_error: Option<f64>,
    /// Rest-state errors against our reference (sum of distances, sum of coordinate differences,
    /// L2, max); None for Table 1.
    pub error_sum: Option<f64>,
    pub error_l1: Option<f64>,
    pub error_l2: Option<f64>,
    pub error_max: Option<f64>,
    pub steps: u64,
    pub end_time: f64,
    pub hit_time_limit: bool,
    /// Energy of the first and of the last peak, J (the last shows round-off peaks).
    pub first_peak_energy: Option<f64>,
    pub last_peak_energy: Option<f64>,
    pub final_positions: Vec<Vec3>,
}

impl Measured {
    /// Whether this row meets the reproduction rule. A run cut at its time limit never does:
    /// its peak count and T/2 are those of an unfinished run.
    pub fn reproduces(&self) -> bool {
        self.reproduces_within(HALF_PERIOD_TOLERANCE)
    }

    /// [`Measured::reproduces`] with the T/2 tolerance `tolerance` ([`reproduces_within`]).
    pub fn reproduces_within(&self, tolerance: f64) -> bool {
        !self.hit_time_limit
            && reproduces_within(
                &self.published,
                self.peaks,
                self.half_period_thesis,
                tolerance,
            )
    }

    /// Whether this run meets the reproduction rule with `half_period` in place of its thesis
    /// T/2 (another reading of the time conventions).
    pub fn reproduces_with(&self, half_period: Option<f64>) -> bool {
        !self.hit_time_limit && reproduces(&self.published, self.peaks, half_period)
    }

    /// Whether this row passes with a T/2 deviation above [`MARGINAL_HALF_PERIOD`].
    pub fn marginal(&self) -> bool {
        self.reproduces() && is_marginal(&self.published, self.half_period_thesis)
    }
}

/// All 56 rows, measured under one configuration.
#[derive(Debug, Clone, PartialEq)]
pub struct ResultSet {
    pub configuration: Configuration,
    pub rows: Vec<Measured>,
}

impl ResultSet {
    /// The measured rows of one thesis table.
    pub fn table(&self, table: u8) -> impl Iterator<Item = &Measured> {
        self.rows.iter().filter(move |r| r.published.table == table)
    }

    /// Our reference row of a stiffness.
    pub fn reference(&self, stiffness: f64) -> &Measured {
        self.rows
            .iter()
            .find(|r| {
                r.published.solver == SolverId::BackwardEuler && r.published.stiffness == stiffness
            })
            .expect("the result set holds both references")
    }
}

/// The system and run options of one published experiment under `configuration`.
fn setup(
    row: &PublishedRow,
    configuration: &Configuration,
) -> Result<(crate::model::system::MassSpringSystem, RunOptions)> {
    let mut params = RopeParams::thesis(row.stiffness);
    params.gravity = if row.solver == SolverId::BackwardEuler {
        configuration.reference_gravity
    } else {
        configuration.gravity
    };
    let options = RunOptions {
        stop: configuration.stop,
        velocity_damping: configuration.velocity_damping,
        ..RunOptions::default()
    };
    Ok((params.build()?, options))
}

/// What the profile (`MSS_PROFILE=1`) calls a run of `row` under `configuration`.
fn profile_label(row: &PublishedRow, configuration: &Configuration) -> String {
    format!(
        "run {:?} table {} dt {} s, {} iterations, k {} N/m, damping {} 1/s, {:?}",
        row.solver,
        row.table,
        row.dt_s,
        row.iterations,
        row.stiffness,
        configuration.velocity_damping,
        configuration.solver
    )
}

/// Runs one published experiment from the thesis rope at rest.
pub fn run_experiment(row: &PublishedRow, configuration: &Configuration) -> Result<Run> {
    run_experiment_from(row, configuration, |rest| rest)
}

/// Runs one published experiment from `start` applied to the thesis rope at rest (the nudged
/// starts of [`crate::studies::round_off`]).
pub fn run_experiment_from(
    row: &PublishedRow,
    configuration: &Configuration,
    start: impl FnOnce(State) -> State,
) -> Result<Run> {
    let (system, options) = setup(row, configuration)?;
    let mut solver = configuration
        .solver
        .build(row.solver, &system, row.dt_s, row.iterations)?;
    pool::profiled(
        || profile_label(row, configuration),
        |run: &Result<Run>| {
            run.as_ref()
                .map_or(String::new(), |r| format!(", {} steps", r.steps))
        },
        || simulate(solver.as_mut(), start(system.initial_state()), &options),
    )
}

/// The final positions and T/2 (thesis convention) of a reference run.
#[derive(Debug, Clone, Copy)]
pub struct Reference<'a> {
    pub final_positions: &'a [Vec3],
    pub half_period_thesis: Option<f64>,
}

/// The metrics of a run of `row`, with its rest-state errors and relative T/2 error against
/// `reference` (None for a reference row).
pub fn measure(row: &PublishedRow, run: &Run, reference: Option<Reference>) -> Measured {
    let x = &run.final_state.x;
    let period_rel_error = reference
        .and_then(|r| r.half_period_thesis)
        .zip(run.half_period_thesis())
        .map(|(t_ref, t)| crate::model::metrics::relative_period_error(t, t_ref));
    Measured {
        published: row.clone(),
        peaks: run.peak_count(),
        half_period_thesis: run.half_period_thesis(),
        half_period_exact: run.half_period_exact(),
        half_period_sample_stamp: half_period_sample_stamp(&run.peaks),
        half_period_f64_clock: half_period_f64_clock(&run.peaks, run.dt),
        period_rel_error,
        error_sum: reference.map(|r| rest_error_sum(x, r.final_positions)),
        error_l1: reference.map(|r| rest_error_l1(x, r.final_positions)),
        error_l2: reference.map(|r| rest_error_l2(x, r.final_positions)),
        error_max: reference.map(|r| rest_error_max(x, r.final_positions)),
        steps: run.steps,
        end_time: run.end_time(),
        hit_time_limit: run.hit_time_limit,
        first_peak_energy: run.peaks.first().map(|p| p.energy),
        last_peak_energy: run.peaks.last().map(|p| p.energy),
        final_positions: x.clone(),
    }
}

/// The expected cost of running `row` under `configuration`, in Liu iterations, to order the
/// jobs of [`run_parallel`] longest first: the published run's solver iterations
/// ([`published_cost`]), cut at the configuration's time limit and weighted by the solver's
/// cost per iteration. A Backward Euler reference costs nine times its Newton iterations'
/// count in these units, so without the weight the longest job would start last.
pub fn expected_cost(row: &PublishedRow, configuration: &Configuration) -> f64 {
    let duration = row.ke_peaks as f64 * row.half_period_s;
    published_cost(row)
        * (configuration.stop.max_time / duration).min(1.0)
        * row.solver.info().relative_cost
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The k = 1e3 reference is one of the longest runs (2.8 s of CPU of the faithful 20 s, with
    /// the 50- and 70-iteration rows at dt = 1e-3): its Newton iterations are few but dear, and
    /// the pool must start it among the first, not after every cheaper solver row.
    #[test]
    fn the_dear_runs_are_scheduled_first() {
        let faithful = Configuration::faithful();
        let mut rows: Vec<&PublishedRow> = published_rows().iter().collect();
        rows.sort_by(|a, b| expected_cost(b, &faithful).total_cmp(&expected_cost(a, &faithful)));
        let reference = rows
            .iter()
            .position(|r| r.solver == SolverId::BackwardEuler && r.stiffness == 1e3)
            .unwrap();
        assert!(
            reference < 4,
            "the k = 1e3 reference is scheduled {reference}th"
        );
        // A time limit shorter than the published run cuts its expected cost in proportion.
        let row = rows[0];
        let mut cut = faithful;
        cut.stop.max_time = 0.5 * row.ke_peaks as f64 * row.half_period_s;
        assert_eq!(
            expected_cost(row, &cut),
            0.5 * expected_cost(row, &faithful)
        );
    }
}
