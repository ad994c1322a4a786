//! The ground truth (issue 2): Backward Euler + Newton is the Newton scheme and converges; that it
//! reproduces Table 1 is checked in `tests/thesis/reference.rs`, on the runs of the result set.

use mass_spring_solvers::integrators::time_stepper::{
    simulate, Recording, RunOptions, TimeStepper,
};
use mass_spring_solvers::model::scene::thesis_rope;
use mass_spring_solvers::solvers::backward_euler::{
    velocity_residual, BackwardEuler, ConvergedStepOptions,
};
use mass_spring_solvers::solvers::converged_stage::converged_step;
use mass_spring_solvers::{MassSpringSystem, State, Vec3};
use nalgebra::{DMatrix, DVector};

/// A moving state of the thesis rope: the reference run `steps` steps from rest.
fn moving_state(system: &MassSpringSystem, steps: usize) -> State {
    let mut be = BackwardEuler::reference(system).unwrap();
    let mut state = system.initial_state();
    for _ in 0..steps {
        be.step(&mut state).unwrap();
    }
    state
}

fn max_residual(system: &MassSpringSystem, state: &State, v: &[Vec3], dt: f64) -> f64 {
    velocity_residual(system, state, v, dt)
        .iter()
        .map(|r| r.amax())
        .fold(0.0, f64::max)
}

/// The printed Eq (12) re-evaluated at x_k without the term dt·K_k·(x_n − x_k): a fixed-point
/// iteration, written densely here as an independent check.
fn printed_scheme_iterate(
    system: &MassSpringSystem,
    state: &State,
    dt: f64,
    iterations: usize,
) -> Vec<Vec3> {
    let n = system.len();
    let mut v = vec![Vec3::zeros(); n];
    for _ in 0..iterations {
        let x: Vec<Vec3> = state.x.iter().zip(&v).map(|(x, v)| x + dt * v).collect();
        let mut a = DMatrix::<f64>::zeros(3 * n, 3 * n);
        let mut b = DVector::<f64>::zeros(3 * n);
        let mut f = vec![Vec3::zeros(); n];
        system.forces(&x, &mut f);
        for (i, node) in system.nodes().iter().enumerate() {
            for c in 0..3 {
                a[(3 * i + c, 3 * i + c)] = node.mass;
                b[3 * i + c] = node.mass * state.v[i][c] + dt * f[i][c];
            }
        }
        a -= dt * dt * system.force_jacobian_dense(&x);
        for (i, node) in system.nodes().iter().enumerate() {
            if node.fixed {
                for c in 0..3 {
                    let d = 3 * i + c;
                    a.row_mut(d).fill(0.0);
                    a.column_mut(d).fill(0.0);
                    a[(d, d)] = 1.0;
                    b[d] = 0.0;
                }
            }
        }
        let sol = a.lu().solve(&b).unwrap();
        v = (0..n)
            .map(|i| Vec3::new(sol[3 * i], sol[3 * i + 1], sol[3 * i + 2]))
            .collect();
    }
    v
}

/// Five Newton iterations solve the implicit equations (8)-(9): the residual
/// r(v) = M(v − v_n) − dt·F(x_n + dt·v) is at round-off, it converges quadratically, and the
/// result is the converged step. The printed equation re-evaluated at x_k does not solve them.
#[test]
fn newton_iterations_solve_the_backward_euler_equations() {
    for k in [1e3, 1e6] {
        let system = thesis_rope(k).unwrap();
        let state = moving_state(&system, 300);
        let dt = 1e-3;
        let mut residuals = Vec::new();
        for iterations in 1..=5 {
            let mut be = BackwardEuler::new(&system, dt, iterations).unwrap();
            let mut next = state.clone();
            be.step(&mut next).unwrap();
            residuals.push(max_residual(&system, &state, &next.v, dt));
            if iterations == 5 {
                let oracle =
                    converged_step(&system, &state, dt, ConvergedStepOptions::default()).unwrap();
                let gap = next
                    .x
                    .iter()
                    .zip(&oracle.x)
                    .map(|(a, b)| (a - b).amax())
                    .fold(0.0, f64::max);
                assert!(
                    gap < 1e-12,
                    "k={k}: 5 Newton iterations are {gap:e} m from the converged step"
                );
            }
        }
        println!("k={k:e}: residual after 1..5 Newton iterations {residuals:?}");
        // Quadratic convergence: each residual at most about the square of the last (scaled).
        assert!(residuals[2] < 1e-6 * residuals[0], "k={k}: {residuals:?}");
        assert!(residuals[4] < 1e-9, "k={k}: {residuals:?}");
        let printed = printed_scheme_iterate(&system, &state, dt, 5);
        let printed_residual = max_residual(&system, &state, &printed, dt);
        println!("k={k:e}: printed-Eq-12 iterate residual {printed_residual:e}");
        assert!(
            printed_residual > 1e3 * residuals[4],
            "the printed scheme should not solve Eq 8"
        );
    }
}

/// The converged step converges at large dt·√(k/m) (here 0.1·√1e6 = 100), where plain Newton
/// from x_n may not, and satisfies the Backward Euler equations.
#[test]
fn converged_step_handles_large_steps() {
    let system = thesis_rope(1e6).unwrap();
    let state = moving_state(&system, 150);
    for dt in [1e-2, 1e-1, 1.0] {
        let next = converged_step(&system, &state, dt, ConvergedStepOptions::default()).unwrap();
        let r = max_residual(&system, &state, &next.v, dt);
        assert!(r < 1e-6, "dt={dt}: residual {r:e}");
    }
}

/// The thesis says the reference's first kinetic-energy peak is "about 6 J" at k = 1e6.
#[test]
fn first_peak_is_about_six_joules() {
    let system = thesis_rope(1e6).unwrap();
    let mut be = BackwardEuler::reference(&system).unwrap();
    let options = RunOptions {
        recording: Recording {
            kinetic_energy: true,
            positions_every: None,
        },
        ..RunOptions::default()
    };
    let mut stop = options;
    stop.stop.max_time = 0.5;
    let run = simulate(&mut be, system.initial_state(), &stop).unwrap();
    let first = run.peaks[0].energy;
    assert!((5.0..7.0).contains(&first), "first peak {first} J");
    assert_eq!(run.kinetic_energy.len() as u64, run.steps + 1);
}

/// Bad input is rejected with the field's name, never a panic.
#[test]
fn bad_parameters_name_the_field() {
    let system = thesis_rope(1e3).unwrap();
    let err = BackwardEuler::new(&system, -1.0, 5)
        .unwrap_err()
        .to_string();
    assert!(err.contains("dt"), "{err}");
    let err = BackwardEuler::new(&system, 1e-3, 0)
        .unwrap_err()
        .to_string();
    assert!(err.contains("iterations"), "{err}");
    let err = thesis_rope(f64::NAN).unwrap_err().to_string();
    assert!(err.contains("stiffness"), "{err}");
    let mut options = RunOptions::default();
    options.stop.threshold = 0.0;
    let mut be = BackwardEuler::reference(&system).unwrap();
    let err = simulate(&mut be, system.initial_state(), &options)
        .unwrap_err()
        .to_string();
    assert!(err.contains("threshold"), "{err}");
}
