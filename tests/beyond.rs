//! The machinery of the chapters beyond the thesis (`src/studies/beyond.rs`): the convergence curves,
//! the search for the iterations to a tolerance, and the rankings' rank correlation.

#[path = "asserted/mod.rs"]
mod asserted;

use mass_spring_solvers::model::scene::thesis_rope;
use mass_spring_solvers::solvers::registry::{SolverId, SolverSpec};
use mass_spring_solvers::studies::beyond::{
    gap, gap_curve, iterations_to, kendall_tau, kendall_tau_b, Start,
};

/// Newton converges quadratically: Backward Euler's curve reaches round-off in a few
/// iterations; Liu 2013's falls but slowly (its rate is the spectral radius).
#[test]
fn convergence_curves_fall_as_their_methods_do() {
    let system = thesis_rope(1e6).unwrap();
    let state = Start::Step10.state(&system).unwrap();
    let be = gap_curve(
        &SolverSpec::new(SolverId::BackwardEuler, 1),
        &system,
        &state,
        1e-2,
        4,
    )
    .unwrap();
    assert!(be[3].unwrap() < 1e-12, "{be:?}");
    let liu = gap_curve(
        &SolverSpec::new(SolverId::FastMassSpring, 1),
        &system,
        &state,
        1e-2,
        50,
    )
    .unwrap();
    let (first, last) = (liu[0].unwrap(), liu[49].unwrap());
    assert!(last < first && last > 1e-6, "{first} {last}");
}

/// The search past the curves' length finds the first crossing a one-by-one scan finds
/// (ADMM from step10 at dt = 1e-2, k = 1e6: 1828 iterations, as `tests/accelerated.rs` finds
/// by scanning; the count as `tests/asserted/` states it).
#[test]
fn iterations_to_a_tolerance_matches_a_scan() {
    let system = thesis_rope(1e6).unwrap();
    let state = asserted::step10();
    let spec = (asserted::ADMM.spec)();
    let found = iterations_to(&spec, &system, &state, 1e-2, 1e-6, 5000).unwrap();
    asserted::ADMM.check(found);
    let oracle = spec.converged_step(&system, &state, 1e-2).unwrap();
    let after = |m: usize| {
        let mut next = state.clone();
        SolverSpec {
            iterations: m,
            ..spec
        }
        .build_send(&system, 1e-2)
        .unwrap()
        .step(&mut next)
        .unwrap();
        gap(&next, &oracle)
    };
    let n = found.unwrap();
    assert!(after(n - 1) >= 1e-6 && after(n) < 1e-6);
    assert_eq!(
        iterations_to(&spec, &system, &state, 1e-2, 1e-6, 1000).unwrap(),
        None,
        "not within 1000"
    );
}

#[test]
fn kendall_tau_counts_the_pairs_in_order() {
    use SolverId::*;
    let a = [Xpbd, FastMassSpring, AdmmPd];
    assert_eq!(kendall_tau(&a, &a), Some(1.0));
    assert_eq!(kendall_tau(&a, &[AdmmPd, FastMassSpring, Xpbd]), Some(-1.0));
    // One of three pairs swapped: (2 − 1)/3.
    let tau = kendall_tau(&a, &[FastMassSpring, Xpbd, AdmmPd]).unwrap();
    assert!((tau - 1.0 / 3.0).abs() < 1e-15);
    // Only the items both rank count.
    assert_eq!(kendall_tau(&a, &[Pbd, AdmmPd, Xpbd]), Some(-1.0));
    assert_eq!(kendall_tau(&a, &[Pbd]), None);
}

/// τ-b against a computation by hand: no ties reads as τ; a tie on one side orders nothing and
/// shrinks the scale [Kendall 1945]: a = (1, 2, 3), b = (1, 1, 2) has C = 2, D = 0, one pair
/// tied in b, τ-b = 2 / √(3 · 2) = 0.816; scores tied on both sides are merged into one item.
/// Negative cases: without the tie tolerance (0), the round-off pair (1 and 1 + 1e-12) is
/// ordered, by its noise, and τ-b reads the τ of a strict order; merged items are not pairs.
#[test]
fn kendall_tau_b_treats_ties_and_merges_identical_computations() {
    use mass_spring_solvers::solvers::registry::SolverId::*;
    let a = [(Xpbd, 1.0), (FastMassSpring, 2.0), (AdmmPd, 3.0)];
    assert_eq!(kendall_tau_b(&a, &a, 1e-9), Some(1.0));
    let reversed = [(Xpbd, 3.0), (FastMassSpring, 2.0), (AdmmPd, 1.0)];
    assert_eq!(kendall_tau_b(&a, &reversed, 1e-9), Some(-1.0));
    let b = [(Xpbd, 1.0), (FastMassSpring, 1.0 + 1e-12), (AdmmPd, 2.0)];
    let tau_b = kendall_tau_b(&a, &b, 1e-9).unwrap();
    assert!((tau_b - 2.0 / 6f64.sqrt()).abs() < 1e-12, "{tau_b}");
    assert_eq!(kendall_tau_b(&a, &b, 0.0), Some(1.0));
    let b_noise = [(Xpbd, 1.0 + 1e-12), (FastMassSpring, 1.0), (AdmmPd, 2.0)];
    assert!((kendall_tau_b(&a, &b_noise, 0.0).unwrap() - 1.0 / 3.0).abs() < 1e-12);
    // Pbd computes what Xpbd does on both scenes: one item, so three items remain, all in order.
    let a4 = [
        (Xpbd, 1.0),
        (Pbd, 1.0),
        (FastMassSpring, 2.0),
        (AdmmPd, 3.0),
    ];
    let b4 = [
        (Xpbd, 5.0),
        (Pbd, 5.0),
        (FastMassSpring, 6.0),
        (AdmmPd, 7.0),
    ];
    assert_eq!(kendall_tau_b(&a4, &b4, 1e-9), Some(1.0));
    assert_eq!(kendall_tau_b(&a4[..1], &b4[..1], 1e-9), None);
}
