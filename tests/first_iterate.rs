//! The options of issue 22, through the registry and `mss`: the shared first iterate of every
//! solver iterating on the incremental potential, Chebyshev's rule for rho, Anderson-ADMM's
//! safeguard, VBD's local Hessian, and XPBD substeps' constraint damping and sweep.

use mass_spring_solvers::integrators::first_iterate::{
    inertial_prediction, FirstIterate, StepStart,
};
use mass_spring_solvers::integrators::optimization_integrator::StageProblem;
use mass_spring_solvers::model::scene::thesis_rope;
use mass_spring_solvers::solvers::backward_euler::ConvergedStepOptions;
use mass_spring_solvers::solvers::converged_stage::converged_step;
use mass_spring_solvers::solvers::registry::{SolverId, SolverSpec};
use mass_spring_solvers::studies::beyond::{gap, Start};
use mass_spring_solvers::{Error, State};
use std::process::Command;

/// The solvers that take `first_iterate`.
fn with_first_iterate() -> Vec<SolverId> {
    SolverId::ALL
        .into_iter()
        .filter(|id| id.info().options.iter().any(|o| o.name == "first_iterate"))
        .collect()
}

fn step(spec: &SolverSpec, state: &State, dt: f64) -> State {
    let system = thesis_rope(1e6).unwrap();
    let mut next = state.clone();
    spec.build(&system, dt).unwrap().step(&mut next).unwrap();
    next
}

/// Every solver iterating on the incremental potential takes every first iterate, each giving
/// another first iteration and, iterated, the same step (the converged Backward Euler step; the
/// damped ones with no damping set). PBD, XPBD and XPBD's substeps start at the prediction by
/// construction and take none.
#[test]
fn every_iterative_solver_starts_where_it_is_told() {
    let ids = with_first_iterate();
    assert_eq!(ids.len(), 11, "{ids:?}");
    for id in [SolverId::Pbd, SolverId::Xpbd, SolverId::XpbdSubsteps] {
        assert!(!ids.contains(&id));
    }
    let system = thesis_rope(1e6).unwrap();
    let state = Start::Step10.state(&system).unwrap();
    let dt = 1e-2;
    let oracle = converged_step(&system, &state, dt, ConvergedStepOptions::default()).unwrap();
    for id in ids {
        let many = if matches!(
            id,
            SolverId::FastMassSpring | SolverId::AdmmPd | SolverId::DampedAdmm
        ) {
            4000
        } else {
            400
        };
        let mut firsts = Vec::new();
        for rule in FirstIterate::ALL {
            let mut spec = SolverSpec::new(id, 1);
            spec.params.first_iterate = Some(rule);
            firsts.push(step(&spec, &state, dt));
            spec.iterations = many;
            let converged = step(&spec, &state, dt);
            assert!(gap(&converged, &oracle) < 1e-6, "{id} from {rule}");
        }
        // (a) and (c) differ by h² g: their first iterations differ.
        assert_ne!(firsts[0], firsts[2], "{id}");
    }
}

/// Each solver's own start, the default: Backward Euler and Liu 2013 at x_n (the thesis's
/// readings), ADMM at x̃ = the inertial prediction bit for bit, the accelerations and L-BFGS at
/// the inertial prediction, VBD adaptive (the inertial prediction without history).
#[test]
fn the_defaults_are_each_papers_start() {
    let system = thesis_rope(1e6).unwrap();
    let state = Start::Step10.state(&system).unwrap();
    let own = [
        (SolverId::BackwardEuler, FirstIterate::Previous),
        (SolverId::FastMassSpring, FirstIterate::Previous),
        (SolverId::AdmmPd, FirstIterate::InertialPrediction),
        (SolverId::ChebyshevLiu, FirstIterate::InertialPrediction),
        (SolverId::AndersonAdmm, FirstIterate::InertialPrediction),
        (SolverId::Lbfgs, FirstIterate::InertialPrediction),
        (SolverId::Vbd, FirstIterate::InertialPrediction),
    ];
    for (id, rule) in own {
        let default = SolverSpec::new(id, 3);
        let mut told = default;
        told.params.first_iterate = Some(rule);
        assert_eq!(
            step(&default, &state, 1e-2),
            step(&told, &state, 1e-2),
            "{id}"
        );
    }
    // The shared prediction is ADMM's x̃ of thesis Algorithm 4, line 2.1.
    let mut start = StepStart::new(FirstIterate::InertialPrediction);
    let x0 = start
        .first_iterate(&system, &state, &StageProblem::backward_euler(1e-2))
        .to_vec();
    for (i, x) in x0.iter().enumerate() {
        assert_eq!(*x, inertial_prediction(&system, &state, 1e-2, i));
    }
    assert!(x0[0] == state.x[0] && x0[4] != state.x[4]);
}

/// Every option of issue 22 is read by name and refused out of range, naming its field.
#[test]
fn the_options_read_back_and_refuse_bad_values() {
    let mut spec = SolverSpec::new(SolverId::Vbd, 5);
    for (name, value) in [
        ("first_iterate", "inertia"),
        ("rho_rule", "gradient-ratio"),
        ("safeguard", "combined-residual"),
        ("hessian", "projected"),
        ("constraint_damping", "0.5"),
        ("sweep", "jacobi"),
    ] {
        spec.params.set(name, value).unwrap();
        assert_eq!(spec.params.get(name).as_deref(), Some(value), "{name}");
    }
    let mut field = |name: &str, value: &str| match spec.params.set(name, value).unwrap_err() {
        Error::InvalidParameter { field, .. } => field,
        other => panic!("{other}"),
    };
    for (name, bad) in [
        ("first_iterate", "sideways"),
        ("rho_rule", "guess"),
        ("safeguard", "energy"),
        ("hessian", "convex"),
        ("constraint_damping", "-1"),
        ("sweep", "red-black"),
    ] {
        assert_eq!(field(name, bad), name, "{name} = {bad}");
    }
}

fn mss(args: &[&str]) -> std::process::Output {
    Command::new(env!("CARGO_BIN_EXE_mss"))
        .args(args)
        .current_dir(env!("CARGO_MANIFEST_DIR"))
        .output()
        .expect("the mss binary starts")
}

/// `mss` takes each option for the solvers that have it, and refuses it elsewhere and out of
/// range with status 2, naming the option.
#[test]
fn mss_takes_the_options_of_issue_22() {
    let run = ["--stiffness", "1e6", "--dt", "0.01", "--max-time", "0.05"];
    for (solver, option, value) in [
        (
            "fast_mass_spring",
            "--first-iterate",
            "inertia-and-acceleration",
        ),
        ("backward_euler", "--first-iterate", "inertia"),
        ("chebyshev_liu", "--rho-rule", "gradient-ratio"),
        ("anderson_admm", "--safeguard", "combined-residual"),
        ("vbd", "--hessian", "projected"),
        ("vbd", "--first-iterate", "previous-position"),
        ("xpbd_substeps", "--constraint-damping", "0.1"),
        ("xpbd_substeps", "--sweep", "jacobi"),
    ] {
        let output = mss(&[
            &["--solver", solver, option, value, "--iterations", "20"],
            &run[..],
        ]
        .concat());
        let err = String::from_utf8_lossy(&output.stderr);
        assert!(output.status.success(), "{solver} {option} {value}: {err}");
    }
    for (solver, option, value) in [
        ("xpbd", "--first-iterate", "inertia"),
        ("vbd", "--first-iterate", "sideways"),
        ("anderson_liu", "--safeguard", "primal-residual"),
        ("xpbd_substeps", "--constraint-damping", "-1"),
        ("chebyshev_admm", "--rho-rule", "fitted"),
    ] {
        let output = mss(&[&["--solver", solver, option, value], &run[..]].concat());
        let err = String::from_utf8_lossy(&output.stderr);
        assert_eq!(
            output.status.code(),
            Some(2),
            "{solver} {option} {value}: {err}"
        );
        assert!(err.contains(option) && !err.contains("panicked"), "{err}");
    }
}
