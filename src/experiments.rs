//! The 56 experiments of thesis §4.3 (Tables 1-7), the published numbers they are compared
//! with, the reproduction rule, and one shared, lazily computed result set per process.
//!
//! The published rows are embedded from `data/thesis_results.csv` (transcribed from the
//! thesis), so a plain clone needs nothing else. Every run starts from the thesis rope at rest
//! and uses [`crate::solver::simulate`]; the rest-state error of a row is measured against the
//! final state of the Backward Euler reference of the same stiffness.

use crate::admm::AdmmPd;
use crate::backward_euler::BackwardEuler;
use crate::fast_mass_spring::FastMassSpring;
use crate::error::{Error, Result};
use crate::metrics::{rest_error_l1, rest_error_l2, rest_error_max, rest_error_sum, StoppingRule};
use crate::scene::RopeParams;
use crate::solver::{simulate, Run, RunOptions, TimeStepper};
use crate::system::{MassSpringSystem, Vec3};
use crate::xpbd::Xpbd;
use serde::{Deserialize, Serialize};
use std::sync::atomic::{AtomicUsize, Ordering};
use std::sync::{Mutex, OnceLock};

/// The published table, as transcribed.
pub const PUBLISHED_CSV: &str = include_str!("../data/thesis_results.csv");

/// The solvers of the thesis's tables, named as in `thesis_results.csv`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum SolverKind {
    BackwardEuler,
    Xpbd,
    FastMassSpring,
    AdmmPd,
}

impl SolverKind {
    /// Every kind, in table order.
    pub const ALL: [SolverKind; 4] = [
        SolverKind::BackwardEuler,
        SolverKind::Xpbd,
        SolverKind::FastMassSpring,
        SolverKind::AdmmPd,
    ];

    /// The identifier used in CSV files and on the command line.
    pub fn id(self) -> &'static str {
        match self {
            SolverKind::BackwardEuler => "backward_euler",
            SolverKind::Xpbd => "xpbd",
            SolverKind::FastMassSpring => "fast_mass_spring",
            SolverKind::AdmmPd => "admm_pd",
        }
    }

    /// The abbreviation of thesis Table 8.
    pub fn abbreviation(self) -> &'static str {
        match self {
            SolverKind::BackwardEuler => "BE",
            SolverKind::Xpbd => "XPBD",
            SolverKind::FastMassSpring => "Fast m-s",
            SolverKind::AdmmPd => "ADMM",
        }
    }

    /// Parses an identifier of [`SolverKind::id`].
    pub fn from_id(id: &str) -> Result<Self> {
        Self::ALL.into_iter().find(|k| k.id() == id).ok_or_else(|| {
            Error::invalid(
                "solver",
                id,
                "one of backward_euler, xpbd, fast_mass_spring, admm_pd",
            )
        })
    }

    /// The solver with its faithful parameters.
    pub fn build(
        self,
        system: &MassSpringSystem,
        dt: f64,
        iterations: usize,
    ) -> Result<Box<dyn TimeStepper + Send>> {
        Ok(match self {
            SolverKind::BackwardEuler => Box::new(BackwardEuler::new(system, dt, iterations)?),
            SolverKind::Xpbd => Box::new(Xpbd::new(system, dt, iterations)?),
            SolverKind::FastMassSpring => Box::new(FastMassSpring::new(system, dt, iterations)?),
            SolverKind::AdmmPd => Box::new(AdmmPd::new(system, dt, iterations)?),
        })
    }
}

/// One row of `thesis_results.csv`: an experiment and its published outcome.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct PublishedRow {
    pub table: u8,
    pub solver: SolverKind,
    pub dt_s: f64,
    pub iterations: usize,
    pub stiffness: f64,
    /// Rest-state error against the reference; empty for the reference itself.
    pub error: Option<f64>,
    pub ke_peaks: usize,
    pub half_period_s: f64,
    pub period_rel_error: Option<f64>,
}

/// The 56 published rows, in the thesis's order.
pub fn published_rows() -> &'static [PublishedRow] {
    static ROWS: OnceLock<Vec<PublishedRow>> = OnceLock::new();
    ROWS.get_or_init(|| {
        csv::Reader::from_reader(PUBLISHED_CSV.as_bytes())
            .deserialize()
            .collect::<std::result::Result<_, _>>()
            .expect("data/thesis_results.csv is embedded at build time and parses")
    })
}

/// The published reference row (Table 1) of a stiffness.
pub fn published_reference(stiffness: f64) -> &'static PublishedRow {
    published_rows()
        .iter()
        .find(|r| r.solver == SolverKind::BackwardEuler && r.stiffness == stiffness)
        .expect("Table 1 has both stiffnesses")
}

/// Allowed peak-count deviation: max(1, round(0.005 × published)).
pub fn peak_tolerance(published_peaks: usize) -> usize {
    ((0.005 * published_peaks as f64).round() as usize).max(1)
}

/// Allowed relative T/2 deviation (0.5 %).
pub const HALF_PERIOD_TOLERANCE: f64 = 0.005;

/// The reproduction rule of the scene specification, used everywhere: under the thesis
/// convention, |peaks − published| ≤ max(1, round(0.005·published)) and
/// |T/2 − published| ≤ 0.5 % of published.
pub fn reproduces(published: &PublishedRow, peaks: usize, half_period: Option<f64>) -> bool {
    let peaks_ok = peaks.abs_diff(published.ke_peaks) <= peak_tolerance(published.ke_peaks);
    let period_ok = half_period.is_some_and(|t| {
        (t - published.half_period_s).abs() <= HALF_PERIOD_TOLERANCE * published.half_period_s
    });
    peaks_ok && period_ok
}

/// How a set of runs departs from the faithful method (issue 5's labelled variants).
/// [`Configuration::faithful`] is the thesis's method as written.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Configuration {
    pub stop: StoppingRule,
    /// Velocity damping c, s⁻¹, applied after each step: $v \leftarrow v\,e^{-c\,dt}$.
    pub velocity_damping: f64,
    /// Gravity of the reference runs, m/s² (the solvers use the scene's).
    pub reference_gravity: f64,
}

impl Configuration {
    /// The faithful configuration: the thesis's rule and scene, no damping.
    pub fn faithful() -> Self {
        Self {
            stop: StoppingRule::default(),
            velocity_damping: 0.0,
            reference_gravity: RopeParams::thesis(1.0).gravity,
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
    /// Energy of the last peak, J (shows round-off peaks).
    pub last_peak_energy: Option<f64>,
    pub final_positions: Vec<Vec3>,
}

impl Measured {
    /// Whether this row meets the reproduction rule.
    pub fn reproduces(&self) -> bool {
        reproduces(&self.published, self.peaks, self.half_period_thesis)
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
                r.published.solver == SolverKind::BackwardEuler
                    && r.published.stiffness == stiffness
            })
            .expect("the result set holds both references")
    }
}

/// Runs one published experiment from the thesis rope at rest.
pub fn run_experiment(row: &PublishedRow, configuration: &Configuration) -> Result<Run> {
    let mut params = RopeParams::thesis(row.stiffness);
    if row.solver == SolverKind::BackwardEuler {
        params.gravity = configuration.reference_gravity;
    }
    let system = params.build()?;
    let mut solver = row.solver.build(&system, row.dt_s, row.iterations)?;
    let options = RunOptions {
        stop: configuration.stop,
        velocity_damping: configuration.velocity_damping,
        ..RunOptions::default()
    };
    simulate(solver.as_mut(), system.initial_state(), &options)
}

/// Runs every row (in parallel over the available cores, longest first) and measures the
/// rest-state errors against the references. `progress(done, total)` is called after each.
pub fn run_all(
    rows: &[PublishedRow],
    configuration: &Configuration,
    progress: &(dyn Fn(usize, usize) + Sync),
) -> Result<ResultSet> {
    // Cost estimate: simulated steps × iterations; the longest runs start first.
    let mut order: Vec<usize> = (0..rows.len()).collect();
    let cost = |r: &PublishedRow| r.iterations as f64 / r.dt_s;
    order.sort_by(|&a, &b| cost(&rows[b]).total_cmp(&cost(&rows[a])));
    let next = AtomicUsize::new(0);
    let done = AtomicUsize::new(0);
    let runs: Mutex<Vec<Option<Result<Run>>>> = Mutex::new(vec![None; rows.len()]);
    let threads = std::thread::available_parallelism().map_or(1, |n| n.get());
    std::thread::scope(|scope| {
        for _ in 0..threads {
            scope.spawn(|| loop {
                let k = next.fetch_add(1, Ordering::Relaxed);
                let Some(&i) = order.get(k) else { break };
                let run = run_experiment(&rows[i], configuration);
                runs.lock().expect("no panics while holding the lock")[i] = Some(run);
                progress(done.fetch_add(1, Ordering::Relaxed) + 1, rows.len());
            });
        }
    });
    let runs: Vec<Run> = runs
        .into_inner()
        .expect("no panics while holding the lock")
        .into_iter()
        .map(|r| r.expect("every row ran"))
        .collect::<Result<_>>()?;
    let reference = |k: f64| {
        rows.iter()
            .position(|r| r.solver == SolverKind::BackwardEuler && r.stiffness == k)
            .map(|i| &runs[i])
    };
    let measured = rows
        .iter()
        .zip(&runs)
        .map(|(row, run)| {
            let reference =
                reference(row.stiffness).filter(|_| row.solver != SolverKind::BackwardEuler);
            let x = &run.final_state.x;
            let period_rel_error = reference
                .and_then(|r| r.half_period_thesis())
                .zip(run.half_period_thesis())
                .map(|(t_ref, t)| crate::metrics::relative_period_error(t, t_ref));
            Measured {
                published: row.clone(),
                peaks: run.peak_count(),
                half_period_thesis: run.half_period_thesis(),
                half_period_exact: run.half_period_exact(),
                period_rel_error,
                error_sum: reference.map(|r| rest_error_sum(x, &r.final_state.x)),
                error_l1: reference.map(|r| rest_error_l1(x, &r.final_state.x)),
                error_l2: reference.map(|r| rest_error_l2(x, &r.final_state.x)),
                error_max: reference.map(|r| rest_error_max(x, &r.final_state.x)),
                steps: run.steps,
                end_time: run.end_time(),
                hit_time_limit: run.hit_time_limit,
                last_peak_energy: run.peaks.last().map(|p| p.energy),
                final_positions: x.clone(),
            }
        })
        .collect();
    Ok(ResultSet {
        configuration: *configuration,
        rows: measured,
    })
}

/// The faithful result set of all 56 rows, computed once per process and shared by every
/// test and by the report.
pub fn faithful_results() -> &'static ResultSet {
    static RESULTS: OnceLock<ResultSet> = OnceLock::new();
    RESULTS.get_or_init(|| {
        run_all(published_rows(), &Configuration::faithful(), &|_, _| {})
            .expect("the faithful thesis experiments run without error")
    })
}
