//! The experiments' runs with those of one solver in batches ([`crate::solvers::batch`]): the XPBD rows
//! and the Liu 2013 rows of every configuration, and the ADMM-PD rows whose configuration is
//! Algorithm 4 or departs from it in its first iterate only, [`WIDTH`] at a time in the lanes
//! of a batch per solver and iteration count, each with the bits it has alone. The other rows
//! run one by one, as [`run_experiment`] runs them.

use super::{expected_cost, pool, profile_label, run_experiment, setup, Configuration};
use super::{measure, run_parallel, PublishedRow, Reference, ResultSet};
use crate::error::Result;
use crate::integrators::time_stepper::{Run, RunOptions};
use crate::model::system::{MassSpringSystem, State};
use crate::solvers::admm::AdmmPd;
use crate::solvers::batch::admm::AdmmLanes;
use crate::solvers::batch::liu::LiuLanes;
use crate::solvers::batch::xpbd::XpbdLanes;
use crate::solvers::batch::{simulate_batch, BatchOutcome, LaneSolver, WIDTH};
use crate::solvers::fast_mass_spring::{FastMassSpring, FirstIterate};
use crate::solvers::registry::SolverId;
use crate::solvers::xpbd::Xpbd;
use crate::studies::experiments::SolverChoice;

/// The solver of a row whose runs go into batches: XPBD's, whichever the configuration (every
/// [`SolverChoice`] builds the printed [`Xpbd`] for an XPBD row), Liu's started at (a) or
/// (b) (the printed Liu for [`SolverChoice::Admm`] too, which a Liu row ignores), and ADMM-PD's
/// as printed or with another first iterate only
/// ([`crate::studies::forensics::AdmmVariant::as_first_iterate`]); None for
/// a row run alone.
fn batched(row: &PublishedRow, configuration: &Configuration) -> Option<SolverId> {
    match (row.solver, configuration.solver) {
        (SolverId::Xpbd, _) => Some(SolverId::Xpbd),
        (SolverId::AdmmPd, SolverChoice::Printed) => Some(SolverId::AdmmPd),
        (SolverId::AdmmPd, SolverChoice::Admm(variant)) => {
            variant.as_first_iterate().map(|_| SolverId::AdmmPd)
        }
        (
            SolverId::FastMassSpring,
            SolverChoice::Printed
            | SolverChoice::Admm(_)
            | SolverChoice::LiuFirstIterate(FirstIterate::Previous | FirstIterate::Inertial),
        ) => Some(SolverId::FastMassSpring),
        _ => None,
    }
}

/// The Liu 2013 solver of a row: the printed one, at the configuration's first iterate.
fn liu(
    system: &MassSpringSystem,
    row: &PublishedRow,
    configuration: &Configuration,
) -> Result<FastMassSpring> {
    let solver = FastMassSpring::new(system, row.dt_s, row.iterations)?;
    Ok(match configuration.solver {
        SolverChoice::LiuFirstIterate(first) => solver.with_first_iterate(first),
        _ => solver,
    })
}

/// The ADMM-PD solver of a row: Algorithm 4, at the configuration's first iterate (a variant
/// that departs from it in its start only, bit for bit).
fn admm(
    system: &MassSpringSystem,
    row: &PublishedRow,
    configuration: &Configuration,
) -> Result<AdmmPd> {
    let solver = AdmmPd::new(system, row.dt_s, row.iterations)?;
    Ok(match configuration.solver {
        SolverChoice::Admm(variant) => solver.with_first_iterate(
            variant
                .as_first_iterate()
                .expect("a batched ADMM variant departs from Algorithm 4 in its start only"),
        ),
        _ => solver,
    })
}

/// Runs every `(row, configuration)` of `jobs` (in parallel over the cores, the dearest first)
/// and returns the outcomes in the jobs' order; `progress(done, total)` counts the pool's jobs
/// (a batch is one).
pub fn run_experiments(
    jobs: &[(&PublishedRow, &Configuration)],
    progress: &(dyn Fn(usize, usize) + Sync),
) -> Vec<Result<Run>> {
    let costs: Vec<f64> = jobs.iter().map(|(r, c)| expected_cost(r, c)).collect();
    // One batch per solver and iteration count (a lane with fewer iterations than another
    // idles while the other iterates on), its runs dearest first so that the short ones fill
    // the lanes the long ones leave.
    let kind = |i: usize| batched(jobs[i].0, jobs[i].1);
    let key = |i: usize| (kind(i), jobs[i].0.iterations);
    let mut in_batches: Vec<usize> = (0..jobs.len()).filter(|&i| kind(i).is_some()).collect();
    in_batches.sort_by(|&a, &b| key(a).cmp(&key(b)).then(costs[b].total_cmp(&costs[a])));
    let mut units: Vec<Vec<usize>> = in_batches
        .chunk_by(|&a, &b| key(a) == key(b))
        .map(<[usize]>::to_vec)
        .collect();
    units.extend(
        (0..jobs.len())
            .filter(|&i| kind(i).is_none())
            .map(|i| vec![i]),
    );
    let outcomes = run_parallel(
        &units,
        // A batch takes about as long as its longest run, or its runs' total over its lanes.
        |unit| {
            let longest = unit.iter().map(|&i| costs[i]).fold(0.0, f64::max);
            let total: f64 = unit.iter().map(|&i| costs[i]).sum();
            longest.max(total / WIDTH as f64)
        },
        |unit| {
            let batch = unit.iter().map(|&i| jobs[i]);
            match (&unit[..], kind(unit[0])) {
                ([i], _) => vec![run_experiment(jobs[*i].0, jobs[*i].1)],
                (_, Some(SolverId::FastMassSpring)) => run_batch(batch, liu, |like| {
                    LiuLanes::new(like).expect("the thesis rope's global solve is tridiagonal")
                }),
                (_, Some(SolverId::AdmmPd)) => run_batch(batch, admm, |like| {
                    AdmmLanes::new(like).expect("the thesis rope's global solve is tridiagonal")
                }),
                _ => run_batch(
                    batch,
                    |system, row, _| Xpbd::new(system, row.dt_s, row.iterations),
                    XpbdLanes::new,
                ),
            }
        },
        progress,
    );
    let mut ordered: Vec<Option<Result<Run>>> = (0..jobs.len()).map(|_| None).collect();
    for (unit, outcomes) in units.iter().zip(outcomes) {
        for (&i, outcome) in unit.iter().zip(outcomes) {
            ordered[i] = Some(outcome);
        }
    }
    ordered
        .into_iter()
        .map(|o| o.expect("every job ran"))
        .collect()
}

/// The runs of `jobs` in one batch, each solver built by `build` and the lanes by `lanes`
/// (from the first run); a run that cannot be set up keeps its error.
fn run_batch<'a, L: LaneSolver>(
    jobs: impl Iterator<Item = (&'a PublishedRow, &'a Configuration)>,
    build: impl Fn(&MassSpringSystem, &PublishedRow, &Configuration) -> Result<L::Run>,
    lanes: impl Fn(&L::Run) -> L,
) -> Vec<Result<Run>> {
    let jobs: Vec<_> = jobs.collect();
    let prepared: Vec<Result<(L::Run, State, RunOptions)>> = jobs
        .iter()
        .map(|(row, configuration)| {
            let (system, options) = setup(row, configuration)?;
            let solver = build(&system, row, configuration)?;
            Ok((solver, system.initial_state(), options))
        })
        .collect();
    let ready: Vec<(L::Run, State, RunOptions)> = prepared
        .iter()
        .filter_map(|p| p.as_ref().ok().cloned())
        .collect();
    let label = || {
        let labels: Vec<String> = jobs.iter().map(|(r, c)| profile_label(r, c)).collect();
        format!("batch of {}: {}", jobs.len(), labels.join("; "))
    };
    let mut runs = match ready.first() {
        Some((like, _, _)) => {
            pool::profiled(
                label,
                |batch: &BatchOutcome| {
                    let o = batch.occupancy;
                    format!(
                        " ({} steps of {WIDTH} lanes, {:.3} occupied)",
                        o.batch_steps,
                        o.fraction()
                    )
                },
                || simulate_batch(&mut lanes(like), &ready),
            )
            .runs
        }
        None => Vec::new(),
    }
    .into_iter();
    prepared
        .into_iter()
        .map(|p| p.and_then(|_| runs.next().expect("a run per prepared job")))
        .collect()
}

impl ResultSet {
    /// The result set of `rows` run under `configuration` (`runs`, in the rows' order): each
    /// row's metrics, and a solver row's rest-state errors against the reference of its
    /// stiffness.
    pub fn measured(rows: &[PublishedRow], configuration: &Configuration, runs: &[Run]) -> Self {
        let reference = |k: f64| {
            rows.iter()
                .position(|r| r.solver == SolverId::BackwardEuler && r.stiffness == k)
                .map(|i| Reference {
                    final_positions: &runs[i].final_state.x,
                    half_period_thesis: runs[i].half_period_thesis(),
                })
        };
        let measured = rows
            .iter()
            .zip(runs)
            .map(|(row, run)| {
                let reference =
                    reference(row.stiffness).filter(|_| row.solver != SolverId::BackwardEuler);
                measure(row, run, reference)
            })
            .collect();
        ResultSet {
            configuration: *configuration,
            rows: measured,
        }
    }
}
