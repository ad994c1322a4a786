//! The flop model of [`mass_spring_solvers::studies::work_precision`]: against a hand count, and the
//! cost the benchmark counts from a run's log against the model's.

use mass_spring_solvers::error::Error;
use mass_spring_solvers::model::scene::RopeParams;
use mass_spring_solvers::model::system::Vec3;
use mass_spring_solvers::solvers::registry::{SolverId, SolverSpec};
use mass_spring_solvers::studies::benchmark::run::run;
use mass_spring_solvers::studies::benchmark::sweep::{solvers, Configuration};
use mass_spring_solvers::studies::benchmark::truth::CaseTruth;
use mass_spring_solvers::studies::work_precision::*;

fn rope3(stiffness: f64) -> mass_spring_solvers::model::system::MassSpringSystem {
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

/// The cost of a run counted from its log is the model's in the count mode, wherever a step
/// does what the model assumes (every solver but L-BFGS, which may end early and backtrack,
/// and Anderson, which may reject); in the tolerance mode it counts the iterations taken and
/// their tests, and is below the cap's cost.
#[test]
fn the_logged_cost_is_the_models_in_the_count_mode() {
    let case = Case::ALL[0];
    let truth = CaseTruth::compute(case).unwrap();
    let system = case.scene.system(case.stiffness).unwrap();
    let dt_s = 0.05;
    for id in solvers() {
        let outcome = |spec| run(&Configuration { case, spec, dt_s }, &truth, None).unwrap();
        let spec = SolverSpec::new(id, 7);
        let counted = outcome(spec);
        let modelled = run_flops(&spec, &system, dt_s, truth.window);
        if !matches!(
            id,
            SolverId::Lbfgs | SolverId::AndersonLiu | SolverId::AndersonAdmm
        ) {
            assert_eq!(counted.flops, modelled, "{id}");
        }
        if id.stops_at_tolerance() {
            let to = SolverSpec::new(id, 200).to_tolerance(1e-3).unwrap();
            let r = outcome(to);
            assert!(
                r.flops < run_flops(&to, &system, dt_s, truth.window),
                "{id}"
            );
            let iterations = r.measured.as_ref().unwrap().iterations_mean;
            assert!((1.0..200.0).contains(&iterations), "{id}: {iterations}");
        }
    }
}

/// One free node between two springs at rest length: no transverse stiffness, $`2k`$ along
/// the rope, so $`\omega_{max} = \sqrt{2k/m}`$.
#[test]
fn the_highest_frequency_of_a_single_free_node() {
    let k = 800.0;
    let omega = highest_frequency(&rope3(k));
    assert!((omega - (2.0 * k / 2.0_f64).sqrt()).abs() < 1e-9, "{omega}");
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
    // A run of Liu with 2 iterations at dt = 0.1 s over 5 s: 50 steps of 63 + 2·95, after the setup.
    let spec = SolverSpec::new(SolverId::FastMassSpring, 2);
    assert_eq!(run_flops(&spec, &system, 0.1, 5.0), 12.0 + 50.0 * 253.0);
}

#[test]
fn bad_input_names_its_field() {
    assert_eq!(field(steps_per_sample(0.03).unwrap_err()), "dt");
    assert_eq!(field(steps_per_sample(-1.0).unwrap_err()), "dt");
    assert_eq!(field(steps_per_sample(0.2).unwrap_err()), "dt");
    assert_eq!(steps_per_sample(0.002).unwrap(), 50);
}
