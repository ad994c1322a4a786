//! The machinery of the chapters beyond the thesis (`src/beyond.rs`): the grids' rows, the
//! reference of their windows, the convergence curves, the search for the iterations to a
//! tolerance, and the rankings' comparison.

use mass_spring_solvers::backward_euler::BackwardEuler;
use mass_spring_solvers::beyond::{
    gap, gap_curve, grid_rows, grid_settings, grid_solvers, iterations_to, kendall_tau, ranking,
    run_grid, setting_label, GridReference, GridScene, Start, GRID_DTS,
};
use mass_spring_solvers::registry::{SolverId, SolverSpec};
use mass_spring_solvers::scene::{thesis_rope, THESIS_STIFFNESSES};
use mass_spring_solvers::solver::TimeStepper;

#[test]
fn the_grid_has_every_setting_at_every_dt_and_stiffness() {
    for scene in GridScene::ALL {
        let rows = grid_rows(scene);
        let expected: usize = grid_solvers()
            .iter()
            .map(|&id| grid_settings(id).unwrap().len() * GRID_DTS.len() * 2)
            .sum();
        assert_eq!(rows.len(), expected);
        for id in grid_solvers() {
            for k in THESIS_STIFFNESSES {
                for dt in GRID_DTS {
                    let n = rows
                        .iter()
                        .filter(|r| r.spec.id == id && r.stiffness == k && r.dt_s == dt)
                        .count();
                    assert_eq!(n, grid_settings(id).unwrap().len(), "{id} {k} {dt}");
                }
            }
        }
    }
    // The thesis's four at their tables' counts, the newer solvers in three settings.
    let counts = |id| {
        grid_settings(id)
            .unwrap()
            .iter()
            .map(|s| s.iterations)
            .collect::<Vec<_>>()
    };
    assert_eq!(counts(SolverId::FastMassSpring), [1, 30, 70]);
    assert_eq!(counts(SolverId::BackwardEuler), [5]);
    assert_eq!(
        setting_label(&grid_settings(SolverId::DampedAdmm).unwrap()[1]),
        "50 it., alpha = 0.5"
    );
}

/// The window's reference is the thesis reference's own trajectory: at any step time it is
/// the state a Backward Euler run (dt = 1e-3 s, 5 Newton iterations) reaches there.
#[test]
fn the_reference_of_a_window_is_the_reference_run() {
    let reference = GridReference::compute(GridScene::Rope, 1e6).unwrap();
    let system = thesis_rope(1e6).unwrap();
    let mut be = BackwardEuler::reference(&system).unwrap();
    let mut state = system.initial_state();
    for _ in 0..250 {
        be.step(&mut state).unwrap();
    }
    assert_eq!(reference.at(0.25), state.x.as_slice());
    // The exact equilibrium is the catenary's: the rope sags, symmetric about x = 4.5.
    let e = &reference.equilibrium;
    assert!((e[4].y - e[5].y).abs() < 1e-12 && e[4].y < -0.1);
}

/// A grid row on the sheet runs and measures finite gaps; a converged setting at the
/// reference's own dt reproduces the reference.
#[test]
fn grid_rows_run_on_both_scenes() {
    let rows: Vec<_> = grid_rows(GridScene::Sheet)
        .into_iter()
        .chain(grid_rows(GridScene::Rope))
        .filter(|r| r.dt_s == 0.1 && r.stiffness == 1e6 && r.spec.id == SolverId::Xpbd)
        .collect();
    let results = run_grid(&rows, &|_, _| {}).unwrap();
    assert_eq!(results.len(), 6);
    for r in &results {
        assert!(r.reference_gap_sum.is_finite() && r.equilibrium_gap_sum.is_finite());
        assert!(r.end_time <= r.row.scene.max_time() + 1e-9);
    }
    let be: Vec<_> = grid_rows(GridScene::Rope)
        .into_iter()
        .filter(|r| r.spec.id == SolverId::BackwardEuler && r.dt_s == 1e-3 && r.stiffness == 1e6)
        .collect();
    let be = run_grid(&be, &|_, _| {}).unwrap();
    assert_eq!(
        be[0].reference_gap_sum, 0.0,
        "the reference's own method and dt"
    );
}

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
/// (ADMM-PD from step10 at dt = 1e-2, k = 1e6: 1828 iterations, as `tests/accelerated.rs`
/// finds by scanning).
#[test]
fn iterations_to_a_tolerance_matches_a_scan() {
    let system = thesis_rope(1e6).unwrap();
    let state = Start::Step10.state(&system).unwrap();
    let spec = SolverSpec::new(SolverId::AdmmPd, 1);
    let found = iterations_to(&spec, &system, &state, 1e-2, 1e-6, 5000).unwrap();
    assert_eq!(found, Some(1828));
    let oracle = spec.converged_step(&system, &state, 1e-2).unwrap();
    let after = |m: usize| {
        let mut next = state.clone();
        SolverSpec::new(SolverId::AdmmPd, m)
            .build_send(&system, 1e-2)
            .unwrap()
            .step(&mut next)
            .unwrap();
        gap(&next, &oracle)
    };
    assert!(after(1827) >= 1e-6 && after(1828) < 1e-6);
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

/// The ranking takes each solver's best setting and orders the solvers by it.
#[test]
fn ranking_takes_each_solvers_best_setting() {
    let rows: Vec<_> = grid_rows(GridScene::Rope)
        .into_iter()
        .filter(|r| {
            r.dt_s == 0.1
                && r.stiffness == 1e6
                && matches!(r.spec.id, SolverId::Xpbd | SolverId::FastMassSpring)
        })
        .collect();
    let results = run_grid(&rows, &|_, _| {}).unwrap();
    let ranked = ranking(
        &results,
        GridScene::Rope,
        1e6,
        0.1,
        &[SolverId::Xpbd, SolverId::FastMassSpring, SolverId::Pbd],
    );
    assert_eq!(ranked.len(), 2, "PBD did not run");
    for (id, best) in &ranked {
        let min = results
            .iter()
            .filter(|r| r.row.spec.id == *id)
            .map(|r| r.reference_gap_sum)
            .fold(f64::INFINITY, f64::min);
        assert_eq!(*best, min);
    }
    assert!(ranked[0].1 <= ranked[1].1);
}
