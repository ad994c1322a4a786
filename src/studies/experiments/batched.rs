//! The experiments' runs with those of one solver in batches ([`crate::solvers::batch`]): the
//! Backward Euler, XPBD and Liu 2013 rows of every configuration, and the ADMM-PD rows whose configuration is
//! Algorithm 4 or departs from it in its first iterate and weights only, [`WIDTH`] at a time in the lanes
//! of a batch per solver and iteration count, each with the bits it has alone. The other rows
//! run one by one, as [`run_experiment`] runs them.

use super::{expected_cost, pool, profile_label, run_experiment, setup, Configuration};
use super::{measure, run_parallel, PublishedRow, Reference, ResultSet};
use crate::error::Result;
use crate::integrators::stopping::Convergence;
use crate::integrators::time_stepper::TimeStepper;
use crate::integrators::time_stepper::{Run, RunOptions};
use crate::model::system::{MassSpringSystem, State};
use crate::solvers::admm::AdmmPd;
use crate::solvers::backward_euler::BackwardEuler;
use crate::solvers::batch::admm::{AdmmLaneData, AdmmLanes, AdmmRun};
use crate::solvers::batch::backward_euler::BackwardEulerLanes;
use crate::solvers::batch::liu::LiuLanes;
use crate::solvers::batch::xpbd::XpbdLanes;
use crate::solvers::batch::{simulate_batch, BatchOutcome, LaneSolver, WIDTH};
use crate::solvers::fast_mass_spring::{FastMassSpring, FirstIterate};
use crate::solvers::registry::SolverId;
use crate::solvers::xpbd::Xpbd;
use crate::studies::experiments::SolverChoice;
use crate::studies::forensics::admm_variants::VariantAdmm;

/// The solver of a row whose runs go into batches: Backward Euler's and XPBD's, whichever the
/// configuration (every [`SolverChoice`] builds the printed [`BackwardEuler`] and [`Xpbd`] for
/// their rows), Liu's started at (a) or
/// (b) (the printed Liu for [`SolverChoice::Admm`] too, which a Liu row ignores), and ADMM-PD's
/// as printed or with another first iterate and weights only
/// ([`crate::studies::forensics::AdmmVariant::takes_a_lane`]); None for a row run alone.
fn batched(row: &PublishedRow, configuration: &Configuration) -> Option<SolverId> {
    match (row.solver, configuration.solver) {
        (SolverId::BackwardEuler, _) => Some(SolverId::BackwardEuler),
        (SolverId::Xpbd, _) => Some(SolverId::Xpbd),
        (SolverId::AdmmPd, SolverChoice::Printed) => Some(SolverId::AdmmPd),
        (SolverId::AdmmPd, SolverChoice::Admm(variant)) => {
            variant.takes_a_lane().then_some(SolverId::AdmmPd)
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

/// An ADMM-PD row's run in a batch: Algorithm 4 as printed, or a forensic variant that departs
/// from it in its first iterate and weights only (its own solver, which the lanes run as it
/// runs alone, [`AdmmRun`]).
#[derive(Debug, Clone)]
enum AdmmJob {
    Printed(AdmmPd),
    Variant(VariantAdmm),
}

impl AdmmJob {
    fn stepper(&self) -> &dyn TimeStepper {
        match self {
            AdmmJob::Printed(run) => run,
            AdmmJob::Variant(run) => run,
        }
    }

    fn stepper_mut(&mut self) -> &mut dyn TimeStepper {
        match self {
            AdmmJob::Printed(run) => run,
            AdmmJob::Variant(run) => run,
        }
    }
}

impl TimeStepper for AdmmJob {
    fn name(&self) -> String {
        self.stepper().name()
    }

    fn dt(&self) -> f64 {
        self.stepper().dt()
    }

    fn system(&self) -> &MassSpringSystem {
        self.stepper().system()
    }

    fn step(&mut self, state: &mut State) -> Result<()> {
        self.stepper_mut().step(state)
    }

    fn convergence(&mut self) -> Option<&mut Convergence> {
        self.stepper_mut().convergence()
    }
}

impl AdmmRun for AdmmJob {
    fn lane_data(&self) -> AdmmLaneData<'_> {
        match self {
            AdmmJob::Printed(run) => run.lane_data(),
            AdmmJob::Variant(run) => run.lane_data(),
        }
    }
}

/// The ADMM-PD solver of a row: Algorithm 4, or the configuration's variant (one that departs
/// from it in its first iterate and weights only).
fn admm(
    system: &MassSpringSystem,
    row: &PublishedRow,
    configuration: &Configuration,
) -> Result<AdmmJob> {
    Ok(match configuration.solver {
        SolverChoice::Admm(variant) => {
            debug_assert!(variant.takes_a_lane());
            AdmmJob::Variant(VariantAdmm::new(system, row.dt_s, row.iterations, variant)?)
        }
        _ => AdmmJob::Printed(AdmmPd::new(system, row.dt_s, row.iterations)?),
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
    let by_count: Vec<Vec<usize>> = in_batches
        .chunk_by(|&a, &b| key(a) == key(b))
        .map(<[usize]>::to_vec)
        .collect();
    let iterations = |i: usize| jobs[i].0.iterations;
    // The costs scale the published runs' durations, which a damped run does not keep (its
    // peaks fall under the threshold sooner): its batch is left as it is.
    let modelled = |i: usize| jobs[i].1.velocity_damping == 0.0;
    let mut units = join_half_empty(by_count, kind, iterations, modelled, &costs);
    units.extend(
        (0..jobs.len())
            .filter(|&i| kind(i).is_none())
            .map(|i| vec![i]),
    );
    let outcomes = run_parallel(
        &units,
        // The lanes' model of a batch ([`batch_cost`]); a run alone, its own cost.
        |unit| batch_cost(&lane_runs(unit, &costs, iterations)),
        |unit| {
            let batch = unit.iter().map(|&i| jobs[i]);
            match (&unit[..], kind(unit[0])) {
                ([i], _) => vec![run_experiment(jobs[*i].0, jobs[*i].1)],
                (_, Some(SolverId::FastMassSpring)) => run_batch(batch, liu, |like| {
                    LiuLanes::new(like).expect("the thesis rope is a batch's rope")
                }),
                (_, Some(SolverId::AdmmPd)) => run_batch(batch, admm, |like| {
                    AdmmLanes::new(like).expect("the thesis rope is a batch's rope")
                }),
                (_, Some(SolverId::BackwardEuler)) => run_batch(
                    batch,
                    |system, row, _| BackwardEuler::new(system, row.dt_s, row.iterations),
                    |like| {
                        BackwardEulerLanes::new(like).expect("the rope's Newton matrix is banded")
                    },
                ),
                _ => run_batch(
                    batch,
                    |system, row, _| Xpbd::new(system, row.dt_s, row.iterations),
                    |like| XpbdLanes::new(like).expect("the thesis rope is a batch's rope"),
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

/// The batches of one solver whose lanes would idle (a model's occupancy below one: its runs'
/// total cost over its lanes' share of the longest) joined into one, where the model says the
/// joined batch costs less than they do apart ([`batch_cost`]): each long run of a small batch
/// then shares its steps with another's instead of with empty lanes. Only batches whose every
/// run is `modelled` (its cost trusted) take part. Only the schedule changes: a lane gives its
/// run's bits in any batch. `units` hold job indices, each sorted dearest first, as the
/// joined one is.
fn join_half_empty(
    units: Vec<Vec<usize>>,
    solver: impl Fn(usize) -> Option<SolverId>,
    iterations: impl Fn(usize) -> usize,
    modelled: impl Fn(usize) -> bool,
    costs: &[f64],
) -> Vec<Vec<usize>> {
    let model = |unit: &[usize]| lane_runs(unit, costs, &iterations);
    let half_empty = |unit: &[usize]| {
        let longest = unit.iter().map(|&i| costs[i]).fold(0.0, f64::max);
        let total: f64 = unit.iter().map(|&i| costs[i]).sum();
        total < WIDTH as f64 * longest && unit.iter().all(|&i| modelled(i))
    };
    let mut out: Vec<Vec<usize>> = Vec::new();
    let mut candidates: Vec<(SolverId, Vec<Vec<usize>>)> = Vec::new();
    for unit in units {
        match solver(unit[0]).filter(|_| half_empty(&unit)) {
            Some(id) => match candidates.iter_mut().find(|(c, _)| *c == id) {
                Some((_, group)) => group.push(unit),
                None => candidates.push((id, vec![unit])),
            },
            None => out.push(unit),
        }
    }
    for (_, group) in candidates {
        let mut joined: Vec<usize> = group.concat();
        joined.sort_by(|&a, &b| costs[b].total_cmp(&costs[a]));
        let apart: f64 = group.iter().map(|u| batch_cost(&model(u))).sum();
        if group.len() > 1 && batch_cost(&model(&joined)) < apart {
            out.push(joined);
        } else {
            out.extend(group);
        }
    }
    out
}

/// The runs of `unit` as [`batch_cost`] takes them: (expected cost, iterations per step).
fn lane_runs(
    unit: &[usize],
    costs: &[f64],
    iterations: impl Fn(usize) -> usize,
) -> Vec<(f64, usize)> {
    unit.iter().map(|&i| (costs[i], iterations(i))).collect()
}

/// The model's cost of a batch of runs given as (cost, iterations per step), in the order
/// they take lanes: [`WIDTH`] lanes step together, each step costing the most iterations of
/// a busy lane, and a lane whose run ends takes the next (a run's steps: its cost over its
/// iterations).
fn batch_cost(runs: &[(f64, usize)]) -> f64 {
    let mut waiting = runs
        .iter()
        .map(|&(cost, its)| (cost / its.max(1) as f64, its));
    let mut lanes: Vec<(f64, usize)> = waiting.by_ref().take(WIDTH).collect();
    let mut total = 0.0;
    while !lanes.is_empty() {
        let steps = lanes.iter().map(|l| l.0).fold(f64::INFINITY, f64::min);
        let dearest = lanes.iter().map(|l| l.1).max().unwrap_or(0);
        total += steps * dearest as f64;
        for lane in &mut lanes {
            lane.0 -= steps;
        }
        let ended = lanes.iter().filter(|l| l.0 <= 0.0).count();
        lanes.retain(|l| l.0 > 0.0);
        lanes.extend(waiting.by_ref().take(ended));
    }
    total
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

#[cfg(test)]
mod tests {
    use super::*;

    /// Four lanes: two runs of 100 steps at 50 and 20 iterations cost 100 steps at 50 together
    /// (the model's unit: an iteration of a lane step), and a fifth run waits for a lane.
    #[test]
    fn a_batch_costs_its_dearest_busy_lane_per_step() {
        assert_eq!(batch_cost(&[(5000.0, 50), (2000.0, 20)]), 5000.0);
        let five = [(400.0, 1); 5];
        // 400 steps in four lanes, then the fifth run alone.
        assert_eq!(batch_cost(&five), 800.0);
        assert_eq!(batch_cost(&[]), 0.0);
    }

    /// XPBD's three batches (two long runs each, at 50, 20 and 1 iterations, ten short ones)
    /// are joined; Liu's two full ones are not, nor batches of different solvers, nor batches
    /// whose costs are not modelled. Fails (checked) with every batch of a solver joined (Liu's
    /// then are), or with none.
    #[test]
    fn half_empty_batches_of_one_solver_are_joined() {
        // Jobs 0..36: XPBD, by count; 36..76: Liu, full at 70 and 30 iterations.
        let its = |i: usize| match i {
            0..12 => 50,
            12..24 => 20,
            24..36 => 1,
            36..56 => 70,
            _ => 30,
        };
        let costs: Vec<f64> = (0..76)
            .map(|i| {
                let steps = match i {
                    0..36 if i % 12 < 2 => 488_000.0,
                    0..36 => 10_000.0,
                    _ => 100_000.0,
                };
                steps * its(i) as f64
            })
            .collect();
        let solver = |i: usize| {
            Some(if i < 36 {
                SolverId::Xpbd
            } else {
                SolverId::FastMassSpring
            })
        };
        let units: Vec<Vec<usize>> = [0..12, 12..24, 24..36, 36..56, 56..76]
            .into_iter()
            .map(|r| r.collect())
            .collect();
        let sizes = |modelled: fn(usize) -> bool| {
            let joined = join_half_empty(units.clone(), solver, its, modelled, &costs);
            let mut sizes: Vec<usize> = joined.iter().map(Vec::len).collect();
            sizes.sort();
            sizes
        };
        assert_eq!(sizes(|_| true), vec![20, 20, 36]);
        assert_eq!(sizes(|i| i >= 12), vec![12, 12, 12, 20, 20]);
    }
}
