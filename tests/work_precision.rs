//! The work-precision study (issue 14): the exact motion converged by halving its step, the
//! errors against their definitions and a known order, the flop model against a hand count,
//! the CSV's columns, the cheapest-configuration table.

use mass_spring_solvers::beyond::GridScene;
use mass_spring_solvers::error::Error;
use mass_spring_solvers::registry::{SolverId, SolverSpec};
use mass_spring_solvers::report::work_precision::{csv, CSV_HEADER};
use mass_spring_solvers::scene::RopeParams;
use mass_spring_solvers::system::Vec3;
use mass_spring_solvers::work_precision::*;

/// The largest change of an exact motion, summed over the nodes, when its step is halved from
/// twice the reference's to it, m.
const HALVING_BOUND_M: f64 = 2e-5;

fn rope3(stiffness: f64) -> mass_spring_solvers::system::MassSpringSystem {
    RopeParams {
        nodes: 3,
        node_mass: 2.0,
        rest_length: 1.0,
        stiffness,
        anchor_left: Vec3::zeros(),
        anchor_right: Vec3::new(2.0, 0.0, 0.0),
        gravity: 9.81,
    }
    .build()
    .unwrap()
}

fn field(e: Error) -> String {
    match e {
        Error::InvalidParameter { field, .. } => field,
        other => panic!("{other}"),
    }
}

/// The exact motion of every case moves by less than the bound when RK4's step is halved from
/// twice the reference's to it, and the bound is a thousand times below the physical error of
/// the sweep's most accurate configuration (XPBD with 50 substeps at the case's finest time
/// step). The stiff sheet's exact motion (491 000 RK4 steps) is checked over its first
/// [`STIFF_SHEET_SAMPLES`] samples, to keep the suite fast; the report computes the change over
/// the whole window for every case and prints it (section 12.1).
#[test]
fn the_exact_motion_is_converged_by_halving_its_step() {
    for case in Case::ALL {
        let samples = if case.scene == GridScene::Sheet && case.stiffness == 1e6 {
            STIFF_SHEET_SAMPLES
        } else {
            sample_count()
        };
        let exact =
            ExactMotion::compute_samples(case, REFERENCE_STABILITY_FRACTION, samples).unwrap();
        let doubled =
            ExactMotion::compute_samples(case, 2.0 * REFERENCE_STABILITY_FRACTION, samples)
                .unwrap();
        assert_eq!(exact.samples.len(), samples);
        let gap = WindowError::between(&exact.samples, &doubled.samples);
        assert!(gap.sum < HALVING_BOUND_M, "{}: {gap:?}", case.label());
        assert!(exact.h <= REFERENCE_STABILITY_FRACTION * exact.stability_limit);

        let system = case.scene.system(case.stiffness).unwrap();
        let finest = *case.dts().last().unwrap();
        let mut best = SolverSpec::new(SolverId::XpbdSubsteps, 50)
            .build_send(&system, finest)
            .unwrap();
        let samples = sample_trajectory(best.as_mut(), system.initial_state()).unwrap();
        let error = WindowError::between(&samples, &exact.samples).sum;
        assert!(HALVING_BOUND_M < 1e-3 * error, "{}: {error}", case.label());
    }
}

/// RK4 is of order 4 on the exact motion's problem, which makes the error of the reference a
/// fifteenth of the change the halving shows: on the soft rope, halving once more divides the
/// change by about 16.
#[test]
fn the_exact_motion_converges_at_order_four() {
    let case = Case::ALL[0];
    let motion = |fraction: f64| {
        ExactMotion::compute_samples(case, fraction, 10)
            .unwrap()
            .samples
    };
    let (coarse, reference, fine) = (
        motion(2.0 * REFERENCE_STABILITY_FRACTION),
        motion(REFERENCE_STABILITY_FRACTION),
        motion(REFERENCE_STABILITY_FRACTION / 2.0),
    );
    let ratio =
        WindowError::between(&coarse, &reference).sum / WindowError::between(&reference, &fine).sum;
    assert!((12.0..20.0).contains(&ratio), "ratio {ratio}");
}

/// The samples of the stiff sheet's halving check.
const STIFF_SHEET_SAMPLES: usize = 5;

/// The cost of a run counted from its log is the model's in the count mode, wherever a step
/// does what the model assumes (every solver but L-BFGS, which may end early and backtrack,
/// and Anderson, which may reject); in the tolerance mode it counts the iterations taken and
/// their tests, and is below the cap's cost.
#[test]
fn the_logged_cost_is_the_models_in_the_count_mode() {
    let case = Case::ALL[1];
    let system = case.scene.system(case.stiffness).unwrap();
    let dt = 0.05;
    for id in sweep_solvers() {
        let point = |spec| Point {
            case,
            spec,
            dt_s: dt,
        };
        let spec = SolverSpec::new(id, 7);
        let reference = CaseReference {
            exact: ExactMotion::compute_samples(case, 0.5, 1).unwrap(),
            halving_gap: WindowError { sum: 0.0, max: 0.0 },
            backward_euler: vec![(dt, vec![])],
        };
        let counted = run_point(&point(spec), &reference).unwrap();
        let modelled = run_flops(&spec, &system, dt).unwrap();
        if !matches!(
            id,
            SolverId::Lbfgs | SolverId::AndersonLiu | SolverId::AndersonAdmm
        ) {
            assert_eq!(counted.flops, modelled, "{id}");
        }
        if id.stops_at_tolerance() {
            let to = SolverSpec::new(id, 200).to_tolerance(1e-3).unwrap();
            let r = run_point(&point(to), &reference).unwrap();
            let log = r.log.as_ref().unwrap();
            assert_eq!(log.steps(), 100, "{id}");
            assert!(r.flops < run_flops(&to, &system, dt).unwrap(), "{id}");
            assert!(r.iterations_mean() < 200.0, "{id}");
        } else {
            assert!(counted.log.is_none(), "{id}");
        }
    }
}

/// The exact motion is what Backward Euler converges to at its known order 1: halving its
/// step from 2 ms to 1 ms divides its physical error by about 2 on the soft rope.
#[test]
fn backward_euler_converges_to_the_exact_motion_at_order_one() {
    let case = Case::ALL[0];
    let exact = ExactMotion::compute(case, REFERENCE_STABILITY_FRACTION).unwrap();
    let system = case.scene.system(case.stiffness).unwrap();
    let error = |dt: f64| {
        let mut be = SolverSpec::new(SolverId::BackwardEuler, 5)
            .build_send(&system, dt)
            .unwrap();
        let samples = sample_trajectory(be.as_mut(), system.initial_state()).unwrap();
        WindowError::between(&samples, &exact.samples).sum
    };
    let ratio = error(2e-3) / error(1e-3);
    assert!((1.6..2.2).contains(&ratio), "{ratio}");
}

/// One free node between two springs at rest length: no transverse stiffness, $`2k`$ along
/// the rope, so $`\omega_{max} = \sqrt{2k/m}`$.
#[test]
fn the_highest_frequency_of_a_single_free_node() {
    let k = 800.0;
    let omega = highest_frequency(&rope3(k));
    assert!((omega - (2.0 * k / 2.0_f64).sqrt()).abs() < 1e-9, "{omega}");
}

/// The solver error is the gap to converged Backward Euler steps: Backward Euler with enough
/// Newton iterations has none, and fewer iterations have some.
#[test]
fn the_solver_error_vanishes_for_converged_backward_euler() {
    let system = GridScene::Rope.system(1e3).unwrap();
    let reference = backward_euler_trajectory(&system, 0.01).unwrap();
    let solver_error = |iterations: usize| {
        let mut be = SolverSpec::new(SolverId::BackwardEuler, iterations)
            .build_send(&system, 0.01)
            .unwrap();
        let samples = sample_trajectory(be.as_mut(), system.initial_state()).unwrap();
        WindowError::between(&samples, &reference).sum
    };
    assert!(solver_error(20) < 1e-9, "{}", solver_error(20));
    assert!(solver_error(1) > 1e-3, "{}", solver_error(1));
}

/// The flop model on a 3-node rope (n = 3 nodes, s = 2 springs, c = 9 coordinates), counted
/// by hand from the operation counts of `work_precision`'s documentation.
#[test]
fn the_flop_model_matches_a_hand_count() {
    let system = rope3(1e3);
    let flops = |id, iterations| {
        let spec = SolverSpec::new(id, iterations);
        (
            flops_setup(&spec, &system),
            flops_per_step_overhead(&spec, &system),
            flops_per_iteration(&spec, &system),
        )
    };
    // The node graph: dimension 3, half-bandwidth 1, nnz = 0 + 1 + 1 = 2; the factor 3·2²,
    // a solve 4·2 + 2·3 = 14 per coordinate.
    assert_eq!(factor_nnz(3, 1), 2);
    // Liu: s·(13 + 9) = 44, c = 9, three solves 42; overhead 7c = 63.
    assert_eq!(flops(SolverId::FastMassSpring, 1), (12.0, 63.0, 95.0));
    // ADMM: s·(3 + 3 + 13 + 6 + 6 + 6) = 74, + 9 + 42.
    assert_eq!(flops(SolverId::AdmmPd, 1), (12.0, 63.0, 125.0));
    // XPBD: 2 projections of 36; overhead 6c = 54.
    assert_eq!(flops(SolverId::Xpbd, 1), (0.0, 54.0, 72.0));
    // Backward Euler: 3 unknowns a node, dimension 9, half-bandwidth 5, nnz = 0+1+2+3+4+5+5+5+5
    // = 30; factor 9·6² = 324, solve 4·30 + 18 = 138; springs 2·(21 + 58) = 158, the matrix
    // and right-hand side 81, the update 18.
    assert_eq!(factor_nnz(9, 5), 30);
    assert_eq!(flops(SolverId::BackwardEuler, 5), (0.0, 0.0, 719.0));
    // VBD: the one free node sees both springs, 2·(18 + 22 + 9) = 98, and solves once, 35.
    assert_eq!(flops(SolverId::Vbd, 1), (0.0, 54.0, 133.0));
    // L-BFGS, window 5, its first iteration (no pairs): the solve 42 + 9, the slope 18, a
    // line-search trial 2·9 + 2·44 + 3·29 = 193, the gradient 2·21 + 4·9 = 78, the pair 37;
    // the second with one pair, 8·9 + 3 = 75 more; the step's overhead 63 and a gradient 78.
    let lbfgs = SolverSpec::new(SolverId::Lbfgs, 2);
    assert_eq!(flops_of_iteration(&lbfgs, &system, 0), 377.0);
    assert_eq!(flops_of_iteration(&lbfgs, &system, 1), 452.0);
    assert_eq!(flops_per_step_overhead(&lbfgs, &system), 141.0);
    assert_eq!(flops_per_step(&lbfgs, &system), 141.0 + 377.0 + 452.0);
    // Anderson on Liu, window 5: Liu's 95, the residual 9, the merit 2·12 + 3·16 = 72; from the
    // second iteration, with one column, the new column 6·9 + 1 + 18, the right-hand side 18,
    // the SVD 21 and its solve 2, the combination 18 + 1.
    let anderson = SolverSpec::new(SolverId::AndersonLiu, 2);
    assert_eq!(flops_of_iteration(&anderson, &system, 0), 95.0 + 9.0 + 72.0);
    assert_eq!(
        flops_of_iteration(&anderson, &system, 1),
        95.0 + 9.0 + 73.0 + 18.0 + 21.0 + 2.0 + 19.0 + 72.0
    );
    // A run of Liu with 2 iterations at dt = 0.1 s: 50 steps of 63 + 2·95, after the setup.
    let spec = SolverSpec::new(SolverId::FastMassSpring, 2);
    assert_eq!(run_flops(&spec, &system, 0.1).unwrap(), 12.0 + 50.0 * 253.0);
}

#[test]
fn bad_input_names_its_field() {
    assert_eq!(field(steps_per_sample(0.03).unwrap_err()), "dt");
    assert_eq!(field(steps_per_sample(-1.0).unwrap_err()), "dt");
    assert_eq!(field(steps_per_sample(0.2).unwrap_err()), "dt");
    assert_eq!(steps_per_sample(0.002).unwrap(), 50);
    assert_eq!(
        field(ExactMotion::compute(Case::ALL[0], 2.0).unwrap_err()),
        "fraction"
    );
    assert_eq!(
        field(ExactMotion::compute(Case::ALL[0], f64::NAN).unwrap_err()),
        "fraction"
    );
}

/// The CSV of real runs: the issue's columns, the three error kinds, an empty tolerance in the
/// fixed-count mode and the tolerance in the other, the mean iterations and the counted flops.
#[test]
fn the_csv_has_the_issues_columns() {
    let case = Case::ALL[0];
    let reference = CaseReference::compute(case).unwrap();
    let points: Vec<Point> = sweep_points(case)
        .into_iter()
        .filter(|p| p.dt_s == 0.1 && (p.spec.iterations <= 5 || p.spec.id == SolverId::AdmmPd))
        .collect();
    assert!(points
        .iter()
        .any(|p| p.spec.stopping.tolerance_m().is_some()));
    let results: Vec<PointResult> = points
        .iter()
        .map(|p| run_point(p, &reference).unwrap())
        .collect();
    let text = csv(&results);
    let mut lines = text.lines();
    assert_eq!(
        lines.next().unwrap(),
        "solver,scene,stiffness,dt_s,tolerance,iterations_mean,error_kind,error,flops"
    );
    assert_eq!(CSV_HEADER.split(',').count(), 9);
    let rows: Vec<Vec<&str>> = lines.map(|l| l.split(',').collect()).collect();
    assert_eq!(rows.len(), 3 * results.len());
    let system = case.scene.system(case.stiffness).unwrap();
    for (row, r) in rows.chunks(3).zip(&results) {
        for (cells, kind) in row.iter().zip(ErrorKind::ALL) {
            assert_eq!(cells.len(), 9, "{cells:?}");
            assert_eq!(cells[0], r.point.spec.id.id());
            assert_eq!(cells[1], "rope");
            assert_eq!(cells[2].parse::<f64>().unwrap(), 1e3);
            assert_eq!(cells[3].parse::<f64>().unwrap(), 0.1);
            let iterations = cells[5].parse::<f64>().unwrap();
            match r.point.spec.stopping.tolerance_m() {
                None => {
                    assert_eq!(cells[4], "");
                    if r.point.spec.id != SolverId::Lbfgs {
                        assert_eq!(iterations, r.point.spec.iterations as f64);
                    }
                }
                Some(t) => {
                    assert_eq!(cells[4].parse::<f64>().unwrap(), t);
                    assert!(iterations >= 1.0 && iterations <= TOLERANCE_CAP as f64);
                }
            }
            assert_eq!(iterations, r.iterations_mean());
            assert_eq!(cells[6], kind.id());
            assert_eq!(cells[7].parse::<f64>().unwrap(), r.error(kind).unwrap());
            assert_eq!(cells[8].parse::<f64>().unwrap(), r.flops);
            assert!(
                r.flops > 0.0 && r.flops <= run_flops(&r.point.spec, &system, 0.1).unwrap() * 1.1
            );
        }
    }
}

/// The cheapest configuration below a level is the one of least flops among those that reach
/// it, failed runs and other solvers and cases aside; the front keeps only improvements.
#[test]
fn the_cheapest_configuration_is_the_minimum() {
    let case = Case::ALL[0];
    let ok = |id, dt_s, flops: f64, physical: f64| PointResult {
        point: Point {
            case,
            spec: SolverSpec::new(id, 1),
            dt_s,
        },
        flops,
        log: None,
        errors: Ok([WindowError {
            sum: physical,
            max: physical,
        }; 3]),
    };
    let mut failed = ok(SolverId::Xpbd, 0.1, 1.0, 0.0);
    failed.errors = Err("diverged".into());
    let mut other_case = ok(SolverId::Xpbd, 0.1, 2.0, 1e-4);
    other_case.point.case = Case::ALL[1];
    let results = vec![
        ok(SolverId::Xpbd, 0.01, 500.0, 0.05),
        ok(SolverId::Xpbd, 0.02, 300.0, 0.08),
        ok(SolverId::Xpbd, 0.05, 100.0, 0.5),
        ok(SolverId::Xpbd, 0.005, 900.0, 0.005),
        ok(SolverId::Pbd, 0.1, 3.0, 0.001),
        failed,
        other_case,
    ];
    let pick = |level| {
        cheapest(&results, case, SolverId::Xpbd, ErrorKind::Physical, level).map(|r| r.flops)
    };
    assert_eq!(pick(0.1), Some(300.0));
    assert_eq!(pick(0.06), Some(500.0));
    assert_eq!(pick(0.01), Some(900.0));
    assert_eq!(pick(1e-3), None);
    let front: Vec<f64> = pareto_front(&results, case, SolverId::Xpbd, ErrorKind::Physical)
        .iter()
        .map(|r| r.flops)
        .collect();
    assert_eq!(front, vec![100.0, 300.0, 500.0, 900.0]);
    let best = most_accurate_within(
        &results,
        case,
        ErrorKind::Physical,
        400.0,
        &[SolverId::Xpbd, SolverId::Pbd],
    );
    assert_eq!(best.map(|r| r.point.spec.id), Some(SolverId::Pbd));
}

/// The section's verdict counts and per-case winner, on results whose winners are known: per
/// budget 1e6, 1e7, 1e8, 1e9 flops the most accurate of the thesis's three in the physical
/// error is XPBD, ADMM, ADMM, ADMM, and in the rest error XPBD, ADMM, Liu, Liu.
#[test]
fn the_verdict_counts_the_budgets_each_solver_wins() {
    use mass_spring_solvers::report::work_precision::{most_frequent_winner, verdict};
    let case = Case::ALL[0];
    let result = |id, flops: f64, physical: f64, rest: f64| PointResult {
        point: Point {
            case,
            spec: SolverSpec::new(id, 1),
            dt_s: 0.01,
        },
        flops,
        log: None,
        errors: Ok([physical, rest, 0.0].map(|e| WindowError { sum: e, max: e })),
    };
    let results = vec![
        result(SolverId::Xpbd, 5e5, 1.0, 0.5),
        result(SolverId::AdmmPd, 5e6, 0.5, 0.1),
        result(SolverId::FastMassSpring, 5e7, 2.0, 1e-3),
        result(SolverId::XpbdSubsteps, 5e8, 0.01, 1.0),
    ];
    // [rest: ADMM-PD wins 1 of 4; physical: XPBD wins 1 of 4].
    assert_eq!(verdict(&results), [(1, 4), (1, 4)]);
    assert_eq!(
        most_frequent_winner(&results, case, ErrorKind::Physical),
        Some((vec![SolverId::AdmmPd], 2))
    );
    // A tie names every solver in it: one budget each for XPBD, ADMM-PD and its rival.
    let tied = vec![
        result(SolverId::Xpbd, 5e5, 1.0, 0.5),
        result(SolverId::AdmmPd, 5e6, 0.5, 0.1),
        result(SolverId::FastMassSpring, 5e7, 0.2, 1e-3),
        result(SolverId::XpbdSubsteps, 5e8, 0.01, 1.0),
    ];
    assert_eq!(
        most_frequent_winner(&tied, case, ErrorKind::Physical),
        Some((
            vec![
                SolverId::Xpbd,
                SolverId::FastMassSpring,
                SolverId::AdmmPd,
                SolverId::XpbdSubsteps
            ],
            1
        ))
    );
    assert_eq!(
        most_frequent_winner(&results, Case::ALL[1], ErrorKind::Physical),
        None
    );
}

/// The wall-clock CSV of two real measurements: the key columns of `work_precision.csv`, a
/// positive time and spread, a repeat count checked (no speed is asserted).
#[test]
fn the_wall_clock_csv_has_the_key_columns() {
    let case = Case::ALL[0];
    let points: Vec<Point> = sweep_points(case)
        .into_iter()
        .filter(|p| p.dt_s == 0.1 && p.spec.iterations == 1)
        .take(2)
        .collect();
    let rows: Vec<(Point, f64, WallTime)> = points
        .iter()
        .map(|p| (*p, p.spec.iterations as f64, wall_time(p, 2).unwrap()))
        .collect();
    let text = wall_csv(&rows);
    let mut lines = text.lines();
    assert_eq!(
        lines.next().unwrap(),
        "solver,scene,stiffness,dt_s,tolerance,iterations_mean,wall_s_per_sim_s,spread"
    );
    for (line, (p, _, t)) in lines.zip(&rows) {
        let cells: Vec<&str> = line.split(',').collect();
        assert_eq!(cells.len(), 8, "{line}");
        assert_eq!(cells[0], p.spec.id.id());
        assert_eq!(cells[4], "");
        assert!(cells[6].parse::<f64>().unwrap() > 0.0);
        assert!(cells[7].parse::<f64>().unwrap() >= 0.0);
        assert!(t.min <= t.max && t.repeats == 2);
    }
    assert_eq!(field(wall_time(&points[0], 0).unwrap_err()), "repeats");
}

/// The prose names one solver, or every solver of a tie.
#[test]
fn a_list_of_solvers_reads_as_prose() {
    use mass_spring_solvers::report::work_precision::solver_list;
    assert_eq!(solver_list(&[]), "");
    assert_eq!(solver_list(&[SolverId::Pbd]), "`pbd`");
    assert_eq!(
        solver_list(&[SolverId::Pbd, SolverId::Xpbd, SolverId::Vbd]),
        "`pbd`, `xpbd` and `vbd`"
    );
}
