//! Tests over round-off: every iteration count and every pass/fail row that a test asserts
//! (`tests/asserted/`), recomputed from the start and from its eight nudges by ±1 to ±4 units
//! in the last place ([`nudged_starts`]). A value that moves between them is decided by the
//! last bits of the arithmetic, so a test that asserts it as a single value is a defect: these
//! tests fail on it.

use crate::asserted::{self, outcome, Outcome, COUNTS, MAX_ITERATIONS};
use mass_spring_solvers::studies::experiments::{
    expected_cost, measure, run_experiment_from, Configuration, HALF_PERIOD_TOLERANCE,
};
use mass_spring_solvers::studies::experiments::{published_rows, same_experiment, Measured};
use mass_spring_solvers::studies::forensics::evidence::rests_on_noise_peak;
use mass_spring_solvers::studies::forensics::faithful_results;
use mass_spring_solvers::studies::round_off::{nudged, nudged_starts, NUDGES_ULP};

/// The values of one asserted quantity from the start and its nudges, and whether the tests
/// assert it as a single value while it moves (or outside the range they accept).
fn misasserted<T: PartialEq + Copy + std::fmt::Debug>(
    name: &str,
    values: &[T],
    single: bool,
    accepted: impl Fn(T) -> bool,
) -> Option<String> {
    let moves = values.iter().any(|v| *v != values[0]);
    let outside = values.iter().any(|&v| !accepted(v));
    (moves && single || outside).then(|| {
        format!(
            "{name}: {values:?} from the start and its nudges by {NUDGES_ULP:?} ulp, asserted as {}",
            if single { "a single value" } else { "a range" }
        )
    })
}

/// Every asserted count, from step10 and its eight nudges. Shown failing on the counts as they
/// were asserted before issue 49, each a single value: Anderson ADMM's 31 (of `tests/accelerated.rs`'s
/// (1828, 162, 31)) is 29 to 322 from the nudges, now its asserted range; the others, L-BFGS's
/// 92 and VBD's 9 among them, do not move and stay single values.
#[test]
fn every_asserted_count_holds_over_the_nudged_starts() {
    let start = asserted::step10();
    let starts: Vec<_> = std::iter::once(start.clone())
        .chain(nudged_starts(&start))
        .collect();
    // A nudge that leaves a solver's iterate unchanged bit for bit at the start's count makes
    // the count from it a copy of the start's: that nudge tests nothing. Node 1's nudge goes
    // into the step through the inertial prediction, which the stiff global solve
    // (M + h²kL, h²k/m = 100) damps: the Fast m-s family absorbs some nudges entirely (nudging
    // node 3, x ≈ 3 m, was tried: most nudges of every solver were absorbed). So each count
    // must be reached by at least MIN_EFFECTIVE_NUDGES of the eight, and the absorbed ones are
    // listed. Negative case: a nudge by 0 ulp is absorbed.
    let mut absorbed = Vec::new();
    for c in COUNTS {
        let at = c.from(&start).unwrap_or(MAX_ITERATIONS);
        let counted = c.iterate(&start, at);
        assert_eq!(c.iterate(&nudged(&start, 0), at), counted, "{}", c.name);
        let lost: Vec<i64> = NUDGES_ULP
            .iter()
            .zip(&starts[1..])
            .filter(|(_, s)| c.iterate(s, at) == counted)
            .map(|(u, _)| *u)
            .collect();
        println!("{}: nudges absorbed at {at} iterations: {lost:?}", c.name);
        if NUDGES_ULP.len() - lost.len() < MIN_EFFECTIVE_NUDGES {
            absorbed.push(format!("{}: {lost:?}", c.name));
        }
    }
    assert!(absorbed.is_empty(), "{absorbed:#?}");
    let wrong: Vec<String> = COUNTS
        .iter()
        .filter_map(|c| {
            let values: Vec<Option<usize>> = starts.iter().map(|s| c.from(s)).collect();
            println!("{}: {values:?}", c.name);
            let single = c.asserted.start() == c.asserted.end();
            misasserted(c.name, &values, single, |v| {
                v.is_some_and(|n| c.asserted.contains(&n))
            })
        })
        .collect();
    assert!(wrong.is_empty(), "{wrong:#?}");
}

/// The fewest of the eight nudges that must change a count's iterate for its range to test
/// round-off: half of them.
const MIN_EFFECTIVE_NUDGES: usize = NUDGES_ULP.len() / 2;

/// A run whose expected cost (in Liu iterations, `expected_cost`) is below this is rerun from
/// the eight nudged starts; a dearer one is held by its margins instead (below).
const NUDGED_COST_BOUND: f64 = 1e5;

/// Whether `m` reproduces its published row, as the tables assert it.
fn pass(m: &Measured) -> bool {
    m.reproduces()
}

/// Every pass/fail row of Tables 1-7 that a test asserts, over the nudged starts. A row cheap
/// enough is rerun from each nudge (the faithful configuration) and fails this test if its
/// outcome moves while asserted as pass or fail. A dearer row is not rerun: it is held if its
/// last peak is a real one (above the noise peaks of finding 1) and its T/2 lies farther from
/// the tolerance's edge than 1000 times the largest relative move of T/2 that a nudge gave a
/// rerun row with a real last peak, and farther than the move of its last peak by one step
/// (a real peak moves by round-off only, 0 on every rerun row today; its stamp is a step).
/// Shown failing on the rows as they were asserted before issue 49: Table 5's noise-limited
/// 0.001/1 was asserted as failing, and passes from 7 of its 8 nudged starts (T/2 7.469-7.534
/// s against 7.4464 s published); it and the other noise-limited rows are now asserted as
/// noise-limited only.
#[test]
fn every_asserted_table_row_holds_over_the_nudged_starts() {
    let faithful = Configuration::faithful();
    let mut wrong = Vec::new();
    let mut real_peak_move: f64 = 0.0;
    let mut dear: Vec<&Measured> = Vec::new();
    for m in &faithful_results().rows {
        let p = &m.published;
        let (table, dt, iterations) = (p.table, p.dt_s, p.iterations);
        let asserted = outcome(table, dt, iterations);
        if expected_cost(&m.published, &faithful) > NUDGED_COST_BOUND {
            dear.push(m);
            continue;
        }
        let row = published_rows()
            .iter()
            .find(|r| same_experiment(r, &m.published))
            .unwrap();
        let runs: Vec<Measured> = NUDGES_ULP
            .iter()
            .map(|&u| {
                let run = run_experiment_from(row, &faithful, |s| nudged(&s, u)).unwrap();
                measure(row, &run, None)
            })
            .collect();
        let outcomes: Vec<bool> = std::iter::once(m).chain(&runs).map(pass).collect();
        println!(
            "T{table} {dt}/{iterations}: reproduces {outcomes:?}, T/2 {:?}",
            std::iter::once(m)
                .chain(&runs)
                .map(|r| r.half_period_thesis)
                .collect::<Vec<_>>()
        );
        if !rests_on_noise_peak(m) {
            for r in &runs {
                if let (Some(a), Some(b)) = (m.half_period_thesis, r.half_period_thesis) {
                    real_peak_move = real_peak_move.max((a - b).abs() / a);
                }
            }
        }
        let name = format!("T{table} {dt}/{iterations}");
        let single = asserted != Outcome::NoiseLimited;
        let expected = asserted == Outcome::Reproduces;
        wrong.extend(misasserted(&name, &outcomes, single, |o| {
            !single || o == expected
        }));
    }
    println!("largest relative move of a real peak's T/2 under a nudge: {real_peak_move:e}");
    for m in dear {
        let p = &m.published;
        let (margin, one_step) = m.half_period_thesis.map_or((f64::INFINITY, 0.0), |t| {
            let edge = ((t / p.half_period_s - 1.0).abs() - HALF_PERIOD_TOLERANCE).abs();
            (edge, p.dt_s / (t * m.peaks as f64))
        });
        if rests_on_noise_peak(m) || margin <= (1000.0 * real_peak_move).max(one_step) {
            wrong.push(format!(
                "T{} {}/{}: not rerun, and its margin ({margin:e}) does not hold it",
                p.table, p.dt_s, p.iterations
            ));
        }
    }
    assert!(wrong.is_empty(), "{wrong:#?}");
}
