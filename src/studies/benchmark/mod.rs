//! The benchmark: one protocol behind the report's chapters beyond the thesis (sections
//! 10-12), its specification written here once.
//!
//! 1. **Cases.** The thesis rope and the 10 × 10 sheet, each at k = 1e3 and 1e6 N/m
//!    ([`Case::ALL`]), from the thesis's start (taut, at rest). **One window** per case,
//!    [`WINDOW_PERIODS`] periods of the lowest mode the start excites
//!    ([`truth::lowest_excited_mode`]) as the exact motion swings it, rounded up to a whole
//!    number of samples ([`SAMPLE_INTERVAL_S`]); the same window in every chapter.
//! 2. **Ground truths.** The exact motion (RK4 at a hundredth of its stability limit, its
//!    convergence shown by halving, [`truth::CaseTruth`]); the exact static equilibrium; for
//!    the solver error, the same method with every step solved to round-off.
//! 3. **Errors** per node over the free nodes: the RMS over samples and nodes of the distance
//!    to each ground truth, its largest node distance, and the RMS divided by the exact
//!    motion's RMS amplitude about the equilibrium (so 1 is the error of doing nothing, the
//!    equilibrium held still); the lowest mode's phase error (its period against the exact
//!    motion's) and amplitude error (its energy lost per period, beside the exact motion's),
//!    the thesis's two dynamic metrics made independent of where a window cuts a run
//!    ([`metrics`]).
//! 4. **A sweep that reaches the asymptotic regime** ([`sweep`]): every solver at its fixed
//!    iteration counts from dt = 0.1 s down to where Backward Euler's error falls at its order
//!    on the rope, the sheet as far as the budget allows; the explicit baselines beside them.
//!    Every minimizing solver also runs under the second-order optimization integrators
//!    ([`crate::integrators::optimization_integrator`]: implicit midpoint, BDF2, TR-BDF2) at its first
//!    setting, and Newton under each over every time step. Beside the fixed counts, the
//!    **tolerance points**: every iterative solver aiming at solver errors of 1e-4, 1e-6 and
//!    1e-8 m, each step stopping at its own residual ([`sweep::tolerance_configurations`]),
//!    each point labelled by the solver error it achieved.
//! 5. **Costs**: counted floating-point operations ([`crate::studies::work_precision`]'s model, applied
//!    to the iterations each step took).
//! 6. **The thesis's question** ([`verdicts`], [`statics`]): statics as the cost of coming to
//!    rest by the thesis's rule within a distance of the exact equilibrium; dynamics as the
//!    cost of reaching a relative physical error; ties within 10 %.
//! 8. **Data**: one row per run ([`rows`]), `report/data/benchmark.csv`.

pub mod metrics;
pub mod truth;

pub use crate::studies::work_precision::{Case, SAMPLE_INTERVAL_S};
pub use truth::WINDOW_PERIODS;

pub mod run;
pub mod statics;
pub mod sweep;

use crate::error::Result;
use crate::integrators::optimization_integrator::OptimizationIntegrator;
use crate::studies::experiments::run_parallel;
use run::Outcome;
use statics::{run_statics, statics_configurations, StaticsOutcome};
use sweep::{
    configurations, dts, own_start_configurations, tolerance_configurations, Configuration,
    SOLVER_ERROR_DTS,
};
use truth::{CaseTruth, Converged, SolverTruth};

/// The benchmark's one result set: every ground truth and every run.
#[derive(Debug, Clone, PartialEq)]
pub struct Benchmark {
    pub truths: Vec<CaseTruth>,
    /// (case, time step, the converged method's trajectory).
    pub solver_truths: Vec<(Case, f64, SolverTruth)>,
    pub outcomes: Vec<Outcome>,
    /// The own-start variant ([`sweep::own_start_configurations`]): the runs of the solvers
    /// whose own start is not the inertial prediction, from their own.
    pub own_start: Vec<Outcome>,
    pub statics: Vec<StaticsOutcome>,
}

impl Benchmark {
    /// Every truth and run of `cases`, each a parallel job (the dearest first).
    pub fn compute(cases: &[Case], progress: &(dyn Fn(usize, usize) + Sync)) -> Result<Self> {
        let truths = case_truths(cases)?;
        let truth_of = |case: Case| truth_in(&truths, case);
        let mut solver_jobs: Vec<(Case, f64, Converged)> = Vec::new();
        for &case in cases {
            for dt in SOLVER_ERROR_DTS
                .into_iter()
                .filter(|dt| dts(case).contains(dt))
            {
                let newton = OptimizationIntegrator::ALL.map(Converged::Newton);
                for method in newton.into_iter().chain([Converged::Xpbd]) {
                    solver_jobs.push((case, dt, method));
                }
            }
        }
        let solver_truths: Vec<(Case, f64, SolverTruth)> = run_parallel(
            &solver_jobs,
            |(case, dt, _)| case.stiffness.sqrt() / dt,
            |(case, dt, method)| {
                SolverTruth::compute(*method, *dt, truth_of(*case)).map(|t| (*case, *dt, t))
            },
            &|_, _| {},
        )
        .into_iter()
        .collect::<Result<_>>()?;
        let mut all: Vec<Configuration> = cases
            .iter()
            .flat_map(|&c| {
                configurations(c)
                    .into_iter()
                    .chain(tolerance_configurations(c, truth_of(c).window))
            })
            .collect();
        // The own-start variant runs in the same parallel pool, after the runs of one start.
        let one_start = all.len();
        all.extend(cases.iter().flat_map(|&c| own_start_configurations(c)));
        let mut outcomes = run_parallel(
            &all,
            |c| expected_cost(c, truth_of(c.case).window),
            |c| {
                let reference = Converged::of(&c.spec).and_then(|method| {
                    solver_truths
                        .iter()
                        .find(|(case, dt, t)| {
                            *case == c.case && *dt == c.dt_s && t.method == method
                        })
                        .map(|(_, _, t)| t)
                });
                run::run(c, truth_of(c.case), reference)
            },
            progress,
        )
        .into_iter()
        .collect::<Result<Vec<_>>>()?;
        let own_start = outcomes.split_off(one_start);
        let statics_jobs: Vec<Configuration> = statics_configurations()
            .into_iter()
            .filter(|c| cases.contains(&c.case))
            .collect();
        let statics = run_statics_jobs(&statics_jobs, &truths)?;
        Ok(Self {
            truths,
            solver_truths,
            outcomes,
            own_start,
            statics,
        })
    }

    /// The truth of a case.
    pub fn truth(&self, case: Case) -> Option<&CaseTruth> {
        self.truths.iter().find(|t| t.case == case)
    }
}

impl Benchmark {
    /// The long runs of `cases` ([`sweep::long_configurations`], `make report-long`), with
    /// their cases' truths, measured against the exact motion (no solver error: these steps
    /// have no converged reference), the long statics runs
    /// ([`statics::long_statics_configurations`]) and section 12.2's second window
    /// ([`sweep::second_window_configurations`]).
    pub fn compute_long(cases: &[Case], progress: &(dyn Fn(usize, usize) + Sync)) -> Result<Self> {
        let configurations: Vec<Configuration> = cases
            .iter()
            .flat_map(|&c| sweep::long_configurations(c))
            .collect();
        let statics_jobs: Vec<Configuration> = statics::long_statics_configurations()
            .into_iter()
            .filter(|c| cases.contains(&c.case))
            .collect();
        let second_window: Vec<Configuration> = cases
            .iter()
            .flat_map(|&c| sweep::second_window_configurations(c))
            .collect();
        let long_cases: Vec<Case> = cases
            .iter()
            .copied()
            .filter(|&c| {
                configurations
                    .iter()
                    .chain(&statics_jobs)
                    .chain(&second_window)
                    .any(|k| k.case == c)
            })
            .collect();
        // A case with second-window runs has its truth over that window (the statics runs
        // read only its equilibrium, the same over any window; no other long dynamics run
        // shares a case with them).
        let truths: Vec<CaseTruth> = case_truths(&long_cases)?
            .into_iter()
            .map(|t| {
                if second_window.iter().any(|c| c.case == t.case) {
                    t.over_periods(truth::SECOND_WINDOW_PERIODS)
                } else {
                    Ok(t)
                }
            })
            .collect::<Result<_>>()?;
        let truth_of = |case: Case| truth_in(&truths, case);
        let outcomes = run_parallel(
            &configurations,
            |c| expected_cost(c, truth_of(c.case).window),
            |c| run::run(c, truth_of(c.case), None),
            progress,
        )
        .into_iter()
        .collect::<Result<Vec<_>>>()?;
        let statics = run_statics_jobs(&statics_jobs, &truths)?;
        let mut outcomes = outcomes;
        outcomes.extend(second_window_runs(&second_window, &truths, progress)?);
        Ok(Self {
            truths,
            solver_truths: Vec::new(),
            outcomes,
            own_start: Vec::new(),
            statics,
        })
    }
}

/// Section 12.2's second window: the runs `jobs` against their cases' `truths` (over
/// [`truth::SECOND_WINDOW_PERIODS`] periods), in parallel.
fn second_window_runs(
    jobs: &[Configuration],
    truths: &[CaseTruth],
    progress: &(dyn Fn(usize, usize) + Sync),
) -> Result<Vec<Outcome>> {
    run_parallel(
        jobs,
        |c| expected_cost(c, truth_in(truths, c.case).window),
        |c| run::run(c, truth_in(truths, c.case), None),
        progress,
    )
    .into_iter()
    .collect()
}

/// The statics runs `jobs`, each a parallel job, against their cases' equilibria in `truths`.
fn run_statics_jobs(jobs: &[Configuration], truths: &[CaseTruth]) -> Result<Vec<StaticsOutcome>> {
    run_parallel(
        jobs,
        |c| expected_cost(c, statics::STATICS_MAX_TIME_S),
        |c| run_statics(c, &truth_in(truths, c.case).equilibrium),
        &|_, _| {},
    )
    .into_iter()
    .collect()
}

/// The truths of `cases`, each a parallel job, the dearest first (the sheet's exact motions,
/// the stiff ones longest).
fn case_truths(cases: &[Case]) -> Result<Vec<CaseTruth>> {
    run_parallel(
        cases,
        |c| {
            let scene = match c.scene {
                crate::studies::beyond::GridScene::Sheet => 100.0,
                crate::studies::beyond::GridScene::Rope => 1.0,
            };
            c.stiffness.sqrt() * scene
        },
        |c| CaseTruth::compute(*c),
        &|_, _| {},
    )
    .into_iter()
    .collect()
}

/// The truth of `case` among `truths` (computed for every case that runs).
fn truth_in(truths: &[CaseTruth], case: Case) -> &CaseTruth {
    truths
        .iter()
        .find(|t| t.case == case)
        .expect("a truth per case")
}

/// A configuration's expected cost over `window` seconds, to order the parallel jobs: the
/// flop model of its steps.
fn expected_cost(c: &Configuration, window: f64) -> f64 {
    c.case
        .scene
        .system(c.case.stiffness)
        .map(|s| window / c.dt_s * crate::studies::work_precision::flops_per_step(&c.spec, &s))
        .unwrap_or(0.0)
}
pub mod rows;
pub mod thesis_protocol;
pub mod verdicts;
