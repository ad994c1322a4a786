//! The analytic catenary checks the ground truth (issue 2, item 6).

use mass_spring_solvers::backward_euler::{static_equilibrium, BackwardEuler};
use mass_spring_solvers::catenary::ElasticChain;
use mass_spring_solvers::metrics::rest_error_max;
use mass_spring_solvers::scene::thesis_rope;
use mass_spring_solvers::solver::{simulate, RunOptions};
use mass_spring_solvers::Vec3;
use nalgebra::{DMatrix, SymmetricEigen};

/// A Newton-converged static solve of the spring system agrees with the exact discrete
/// equilibrium to 1e-9 m at both stiffnesses.
#[test]
fn newton_static_solve_matches_discrete_catenary() {
    for k in [1e3, 1e6] {
        let system = thesis_rope(k).unwrap();
        let newton = static_equilibrium(&system, 1.0, 1e-13).unwrap();
        let exact = ElasticChain::thesis_rope(k)
            .unwrap()
            .solve_equilibrium()
            .unwrap();
        let gap = rest_error_max(&newton, &exact.positions);
        println!("k={k:e}: Newton static vs discrete catenary: max {gap:e} m");
        assert!(gap < 1e-9, "k={k}: {gap:e} m");
    }
}

/// Smallest angular frequency of the rope linearised at `x`: ω² from M⁻¹K on the free unknowns.
fn lowest_frequency(k: f64, x: &[Vec3]) -> f64 {
    let system = thesis_rope(k).unwrap();
    let free: Vec<usize> = (0..system.len())
        .filter(|&i| !system.nodes()[i].fixed)
        .collect();
    // K = -dF/dx restricted to the free unknowns.
    let dofs: Vec<usize> = free
        .iter()
        .flat_map(|&i| (0..3).map(move |c| 3 * i + c))
        .collect();
    let n = dofs.len();
    let jacobian = system.force_jacobian_dense(x);
    let stiffness = DMatrix::from_fn(n, n, |r, c| -jacobian[(dofs[r], dofs[c])]);
    // Unit masses: M⁻¹K = K. Out-of-plane (z) modes are excluded: the motion stays in the plane.
    let in_plane: Vec<usize> = (0..n).filter(|i| i % 3 != 2).collect();
    let k_plane = DMatrix::from_fn(in_plane.len(), in_plane.len(), |r, c| {
        stiffness[(in_plane[r], in_plane[c])]
    });
    let eig = SymmetricEigen::new(k_plane).eigenvalues;
    eig.iter().cloned().fold(f64::INFINITY, f64::min).sqrt()
}

/// A Backward Euler run of the thesis rope that has come to rest agrees with the exact discrete
/// equilibrium within its residual motion. Bound: the run stops at a kinetic-energy peak E below
/// 1e-3 J; near equilibrium the remaining mechanical energy is about E, and a displacement δx
/// with ½δxᵀKδx ≤ E has |δx|₂ ≤ √(2E/λ_min) = √(2E/m)/ω_min (unit masses), ω_min the lowest
/// in-plane frequency of the linearised rope. We allow a factor 1.5 for the nonlinearity and for
/// kinetic energy converting into potential energy away from the peak.
///
/// Much tighter in practice: a kinetic-energy peak is the moment the rope passes through its
/// equilibrium, and the run stops one step after it, so the rope is about |v|·dt from the
/// equilibrium, |v| = √(2E/m). We assert that too, with a factor 2.
#[test]
fn backward_euler_rest_state_matches_within_residual_motion() {
    for k in [1e3, 1e6] {
        let system = thesis_rope(k).unwrap();
        let mut be = BackwardEuler::reference(&system).unwrap();
        let run = simulate(&mut be, system.initial_state(), &RunOptions::default()).unwrap();
        let exact = ElasticChain::thesis_rope(k)
            .unwrap()
            .solve_equilibrium()
            .unwrap();
        let last_peak = run.peaks.last().unwrap().energy;
        let omega = lowest_frequency(k, &exact.positions);
        let bound = 1.5 * (2.0 * last_peak).sqrt() / omega;
        let gap: f64 = run
            .final_state
            .x
            .iter()
            .zip(&exact.positions)
            .map(|(a, b)| (a - b).norm_squared())
            .sum::<f64>()
            .sqrt();
        println!(
            "k={k:e}: rest state vs catenary |dx|_2 = {gap:e} m, bound {bound:e} m (last peak {last_peak:e} J, omega_min {omega:.4} rad/s)"
        );
        assert!(gap <= bound, "k={k}: {gap:e} > {bound:e}");
        let crossing = 2.0 * (2.0 * last_peak).sqrt() * run.dt;
        assert!(
            gap <= crossing,
            "k={k}: {gap:e} > {crossing:e} (one step past the crossing)"
        );
    }
}
