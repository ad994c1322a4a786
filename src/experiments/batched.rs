//! The experiments' runs with those of one solver in batches ([`crate::batch`]): the XPBD rows
//! of every configuration, [`WIDTH`] at a time in the lanes of a batch per iteration count, each
//! with the bits it has alone. The other solvers' rows run one by one, as [`run_experiment`] runs them.

use super::{expected_cost, pool, profile_label, run_experiment, setup, Configuration};
use super::{run_parallel, PublishedRow};
use crate::batch::xpbd::XpbdLanes;
use crate::batch::{simulate_batch, WIDTH};
use crate::error::Result;
use crate::registry::SolverId;
use crate::solver::{Run, RunOptions};
use crate::system::State;
use crate::xpbd::Xpbd;

/// Whether a row's runs go into batches: XPBD's, whichever the configuration (every
/// [`crate::forensics::SolverChoice`] builds the printed [`Xpbd`] for an XPBD row).
fn batched(row: &PublishedRow) -> bool {
    row.solver == SolverId::Xpbd
}

/// Runs every `(row, configuration)` of `jobs` (in parallel over the cores, the dearest first)
/// and returns the outcomes in the jobs' order; `progress(done, total)` counts the pool's jobs
/// (a batch is one).
pub fn run_experiments(
    jobs: &[(&PublishedRow, &Configuration)],
    progress: &(dyn Fn(usize, usize) + Sync),
) -> Vec<Result<Run>> {
    let costs: Vec<f64> = jobs.iter().map(|(r, c)| expected_cost(r, c)).collect();
    // One batch per iteration count (a lane with fewer iterations than another idles while the
    // other sweeps on), its runs dearest first so that the short ones fill the lanes the long
    // ones leave.
    let mut in_batches: Vec<usize> = (0..jobs.len()).filter(|&i| batched(jobs[i].0)).collect();
    in_batches.sort_by(|&a, &b| {
        let count = |i: usize| jobs[i].0.iterations;
        count(a).cmp(&count(b)).then(costs[b].total_cmp(&costs[a]))
    });
    let mut units: Vec<Vec<usize>> = in_batches
        .chunk_by(|&a, &b| jobs[a].0.iterations == jobs[b].0.iterations)
        .map(<[usize]>::to_vec)
        .collect();
    units.extend(
        (0..jobs.len())
            .filter(|&i| !batched(jobs[i].0))
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
        |unit| match unit[..] {
            [i] => vec![run_experiment(jobs[i].0, jobs[i].1)],
            _ => run_xpbd_batch(unit.iter().map(|&i| jobs[i])),
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

/// The XPBD runs of `jobs` in one batch; a run that cannot be set up keeps its error.
fn run_xpbd_batch<'a>(
    jobs: impl Iterator<Item = (&'a PublishedRow, &'a Configuration)>,
) -> Vec<Result<Run>> {
    let jobs: Vec<_> = jobs.collect();
    let prepared: Vec<Result<(Xpbd, State, RunOptions)>> = jobs
        .iter()
        .map(|(row, configuration)| {
            let (system, options) = setup(row, configuration)?;
            let solver = Xpbd::new(&system, row.dt_s, row.iterations)?;
            Ok((solver, system.initial_state(), options))
        })
        .collect();
    let ready: Vec<(Xpbd, State, RunOptions)> = prepared
        .iter()
        .filter_map(|p| p.as_ref().ok().cloned())
        .collect();
    let label = || {
        let labels: Vec<String> = jobs.iter().map(|(r, c)| profile_label(r, c)).collect();
        format!("batch of {}: {}", jobs.len(), labels.join("; "))
    };
    let mut runs = match ready.first() {
        Some((like, _, _)) => pool::profiled(
            label,
            |_| String::new(),
            || simulate_batch(&mut XpbdLanes::new(like), &ready),
        ),
        None => Vec::new(),
    }
    .into_iter();
    prepared
        .into_iter()
        .map(|p| p.and_then(|_| runs.next().expect("a run per prepared job")))
        .collect()
}
