//! The sheet's exact static equilibrium (`src/model/sheet_equilibrium.rs`): residual, minimum,
//! symmetry, independence of the start, and an independent oracle.

use mass_spring_report::sheet::equilibrium_csv;
use mass_spring_solvers::model::scene::{SheetParams, SHEET_SIDE};
use mass_spring_solvers::model::sheet_equilibrium::{
    free_hessian, sagged_start, shaped_start, sheet_equilibrium, smallest_hessian_eigenvalue,
    static_equilibrium, Equilibrium, RESIDUAL_TARGET,
};
use mass_spring_solvers::solvers::converged_stage;
use mass_spring_solvers::{MassSpringSystem, Vec3};

/// The largest force on a free node by the system's own force routine, not the Newton's.
fn residual(system: &MassSpringSystem, x: &[Vec3]) -> f64 {
    let mut f = vec![Vec3::zeros(); x.len()];
    system.forces(x, &mut f);
    f.iter().map(|f| f.amax()).fold(0.0, f64::max)
}

fn largest_distance(a: &[Vec3], b: &[Vec3]) -> f64 {
    a.iter()
        .zip(b)
        .map(|(a, b)| (a - b).norm())
        .fold(0.0, f64::max)
}

/// The four sheets of `sheet_equilibrium.csv`, computed once.
fn equilibria() -> &'static [(f64, usize, Equilibrium)] {
    static ONCE: std::sync::OnceLock<Vec<(f64, usize, Equilibrium)>> = std::sync::OnceLock::new();
    ONCE.get_or_init(|| mass_spring_solvers::model::sheet_equilibrium::report_equilibria().unwrap())
}

/// Below 1e-7 N by the system's force routine, equal to the Newton's own figure, and at
/// round-off: a spring's force carries about k·ε·l of it (3e-10 N at k = 1e6, l = 1.4 m).
#[test]
fn the_residual_is_below_the_target_by_an_independent_force_routine() {
    for (k, n, eq) in equilibria() {
        let system = SheetParams::spec(*n, *k).build().unwrap();
        let r = residual(&system, &eq.x);
        eprintln!(
            "k = {k:e}, n = {n}: residual {r:e} N after {} Newton iterations",
            eq.iterations
        );
        assert!(r < RESIDUAL_TARGET, "k = {k:e}, n = {n}: {r:e} N");
        assert!(
            r < 100.0 * k * f64::EPSILON,
            "k = {k:e}, n = {n}: {r:e} N is not round-off"
        );
        assert_eq!(r, eq.residual);
        // And the sheet has sagged: every free node below the corners' plane.
        for (node, p) in system.nodes().iter().zip(&eq.x) {
            assert!(node.fixed || p.y < 0.0, "{p:?}");
        }
    }
}

/// Positive definite Hessian at the equilibrium: the smallest eigenvalue by inverse
/// iteration is positive, and at n = 10 equals a dense symmetric eigen-solve's (nalgebra).
#[test]
fn the_equilibrium_is_a_minimum() {
    for (k, n, eq) in equilibria() {
        let system = SheetParams::spec(*n, *k).build().unwrap();
        let lambda = smallest_hessian_eigenvalue(&system, &eq.x, 200).unwrap();
        eprintln!("k = {k:e}, n = {n}: smallest Hessian eigenvalue {lambda:e} N/m");
        assert!(lambda > 0.0, "k = {k:e}, n = {n}: {lambda:e}");
        if *n == 10 {
            let h = free_hessian(&system, &eq.x);
            let dense = nalgebra::DMatrix::from_fn(h.dim(), h.dim(), |i, j| h.get(i, j));
            let eigen = dense.symmetric_eigenvalues();
            let min = eigen.min();
            assert!(min > 0.0);
            assert!(
                (lambda - min).abs() < 1e-6 * min,
                "{lambda:e} vs dense {min:e}"
            );
        }
    }
}

/// x ↦ 9 − x (node (i, j) ↔ (n−1−i, j)), z ↦ 9 − z (node (i, j) ↔ (i, n−1−j)) and, the net
/// being square, x ↔ z (node (i, j) ↔ (j, i)); y is up and unchanged.
#[test]
fn the_equilibrium_is_symmetric() {
    for (k, n, eq) in equilibria() {
        let params = SheetParams::spec(*n, *k);
        let last = n - 1;
        let at = |i: usize, j: usize| eq.x[params.node(i, j)];
        let mut worst: f64 = 0.0;
        for i in 0..*n {
            for j in 0..*n {
                let p = at(i, j);
                let mirrors = [
                    (at(last - i, j), Vec3::new(SHEET_SIDE - p.x, p.y, p.z)),
                    (at(i, last - j), Vec3::new(p.x, p.y, SHEET_SIDE - p.z)),
                    (at(j, i), Vec3::new(p.z, p.y, p.x)),
                ];
                for (image, expected) in mirrors {
                    worst = worst.max((image - expected).norm());
                }
            }
        }
        assert!(worst < 1e-12, "k = {k:e}, n = {n}: asymmetry {worst:e} m");
    }
}

/// Four other starts reach the same state: a shallow and a deep sag, a lopsided, horizontally
/// shrunk one whose compressed springs make the exact Hessian indefinite, and the flat start,
/// singular in y; the last two go through the shifted projected Hessian.
#[test]
fn the_equilibrium_does_not_depend_on_the_start() {
    for k in [1e3, 1e6] {
        let params = SheetParams::spec(10, k);
        let system = params.build().unwrap();
        let reference = sheet_equilibrium(&params).unwrap();
        let lopsided = {
            let centre = Vec3::new(0.5 * SHEET_SIDE, 0.0, 0.5 * SHEET_SIDE);
            let mut x = shaped_start(&system, &params, |i, j| {
                -0.3 - 0.2 * i as f64 - 0.05 * (j * j) as f64
            });
            for (node, p) in system.nodes().iter().zip(&mut x) {
                if !node.fixed {
                    let y = p.y;
                    *p = centre + 0.8 * (*p - centre);
                    p.y = y;
                }
            }
            x
        };
        let starts = [
            sagged_start(&params, 0.05).unwrap(),
            sagged_start(&params, 4.0).unwrap(),
            lopsided,
            system.initial_state().x,
        ];
        for (s, start) in starts.iter().enumerate() {
            let eq = static_equilibrium(&system, start).unwrap();
            let d = largest_distance(&eq.x, &reference.x);
            eprintln!("k = {k:e}, start {s}: {d:e} m from the default start's, {} iterations, {} projected", eq.iterations, eq.projected_iterations);
            assert!(d < 1e-11, "k = {k:e}, start {s}: {d:e} m");
            if s >= 2 {
                assert!(eq.projected_iterations > 0);
            }
        }
    }
}

/// An independent oracle: the crate's other equilibrium routine, a proximal-point iteration of
/// converged Backward Euler steps from the flat start (3n×3n unknowns with the held nodes
/// imposed by Eqs 43-47, a different solve), agrees.
#[test]
fn the_proximal_point_iteration_agrees() {
    for (k, n, eq) in equilibria().iter().filter(|(_, n, _)| *n == 10) {
        let system = SheetParams::spec(*n, *k).build().unwrap();
        let x = converged_stage::static_equilibrium(&system, 1.0, 1e-12).unwrap();
        let d = largest_distance(&x, &eq.x);
        eprintln!("k = {k:e}, n = {n}: proximal point {d:e} m away");
        assert!(d < 1e-9, "k = {k:e}: {d:e} m");
    }
}

/// Bad input is named: a start of the wrong length, a non-finite start, no sag.
#[test]
fn a_bad_start_is_refused_with_its_field() {
    let system = SheetParams::spec(10, 1e3).build().unwrap();
    let mut flat = system.initial_state().x;
    let err = static_equilibrium(&system, &flat[1..])
        .unwrap_err()
        .to_string();
    assert!(err.contains("start.len()"), "{err}");
    flat[5].y = f64::NAN;
    let err = static_equilibrium(&system, &flat).unwrap_err().to_string();
    assert!(err.contains("start[5][1]"), "{err}");
    let err = sagged_start(&SheetParams::spec(10, 1e3), 0.0)
        .unwrap_err()
        .to_string();
    assert!(err.contains("sag"), "{err}");
}

/// One row per node, stiffness,n,i,j,x,y,z, every coordinate read back bit for bit.
#[test]
fn the_csv_holds_every_node_at_full_precision() {
    let csv = equilibrium_csv(equilibria());
    let mut lines = csv.lines();
    assert_eq!(lines.next(), Some("stiffness_n_per_m,n,i,j,x_m,y_m,z_m"));
    let rows: Vec<&str> = lines.collect();
    assert_eq!(rows.len(), 2 * (100 + 400));
    let (k, n, eq) = &equilibria()[3];
    let last: Vec<&str> = rows[rows.len() - 1].split(',').collect();
    assert_eq!(last[0].parse::<f64>().unwrap(), *k);
    assert_eq!(last[1].parse::<usize>().unwrap(), *n);
    let p = eq.x[n * n - 1];
    assert_eq!(
        last[4..]
            .iter()
            .map(|v| v.parse::<f64>().unwrap())
            .collect::<Vec<_>>(),
        [p.x, p.y, p.z]
    );
    let middle: Vec<f64> = rows[55].split(',').map(|v| v.parse().unwrap()).collect();
    assert_eq!(middle[5], equilibria()[0].2.x[55].y);
}
