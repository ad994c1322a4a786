//! The analytic catenary checks the ground truth (issue 2, item 6). The reference runs' rest
//! state against it is checked in `tests/thesis/reference.rs`, on the runs of the result set.

use mass_spring_solvers::model::catenary::ElasticChain;
use mass_spring_solvers::model::metrics::rest_error_max;
use mass_spring_solvers::model::scene::thesis_rope;
use mass_spring_solvers::solvers::converged_stage::static_equilibrium;

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
