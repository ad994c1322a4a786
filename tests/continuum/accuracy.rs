//! Stresses formed from G = F − I (`src/model/continuum/hyperelastic.rs`,
//! `Deformation::rotation_excess`; the stable neo-Hookean's F − ∂J/∂F) and non-finite
//! deformation gradients.

use mass_spring_solvers::error::Error;
use mass_spring_solvers::model::continuum::energy::EnergyKind;
use mass_spring_solvers::model::continuum::scenes::{beam, cook, cook_node, membrane};
use mass_spring_solvers::model::continuum::statics::static_equilibrium;
use mass_spring_solvers::model::continuum::svd::Polar;
use mass_spring_solvers::model::continuum::system::ContinuumSystem;
use nalgebra::DMatrix;

/// The stress formed from F, as before G was used: 2μ(F − R) (+ λ (Σσ − 3) R) with nalgebra's
/// polished R, and μF + λ′(J − α) cof F with J = det F: the plausible wrong implementation.
fn stress_from_f(kind: EnergyKind, f: &DMatrix<f64>, mu: f64, lambda: f64) -> DMatrix<f64> {
    let polar = Polar::new(f).unwrap();
    let r = polar.rotation();
    match kind {
        EnergyKind::Arap => (f - &r) * (2.0 * mu),
        EnergyKind::Corotated => (f - &r) * (2.0 * mu) + &r * (lambda * (polar.sigma.sum() - 3.0)),
        EnergyKind::StableNeoHookean => {
            let lambda = lambda + mu;
            let cofactor = f.determinant() * f.clone().try_inverse().unwrap().transpose();
            f * mu + cofactor * (lambda * (f.determinant() - 1.0 - mu / lambda))
        }
        _ => unreachable!("the energies whose stress changed"),
    }
}

/// The largest force component on a free node, relative to the largest nodal load, with the
/// elastic forces from `stress`.
fn relative_residual(
    system: &ContinuumSystem,
    u: &[f64],
    stress: impl Fn(&DMatrix<f64>) -> DMatrix<f64>,
) -> f64 {
    let model = system.material().energy.model();
    let mut forces = system.forces(u);
    for e in system.elements() {
        let d = e.deformation(u);
        let mut ours = vec![0.0; forces.len()];
        e.add_forces(&model.stress(&d, &system.material().lame), &mut ours);
        let mut theirs = vec![0.0; forces.len()];
        e.add_forces(&stress(d.f()), &mut theirs);
        for ((f, a), b) in forces.iter_mut().zip(&ours).zip(&theirs) {
            *f += b - a;
        }
    }
    let d = system.dimension();
    let largest = (0..forces.len())
        .filter(|k| !system.is_fixed(k / d))
        .map(|k| forces[k].abs())
        .fold(0.0, f64::max);
    largest / system.largest_load()
}

/// The stiff beam (r = 2, E = 1e9 Pa, strains of about 1e-5) with every nonlinear energy:
/// Newton reaches 1e-10 of the largest nodal weight (ten times tighter than the default 1e-9)
/// in a few iterations. Wrong implementation it catches: the stresses formed from F (ARAP,
/// co-rotated, stable neo-Hookean; [`stress_from_f`]), whose rounding alone leaves a residual
/// above 1e-10 at the same equilibrium (measured 4.5e-10 to 9.8e-10): Newton cannot reach
/// the tolerance with them.
#[test]
fn the_stiff_beam_converges_tightly_with_the_nonlinear_energies() {
    const TOLERANCE: f64 = 1e-10;
    for kind in [
        EnergyKind::Arap,
        EnergyKind::Corotated,
        EnergyKind::StVenantKirchhoff,
        EnergyKind::StableNeoHookean,
    ] {
        let system = beam(2, kind, 1e9).unwrap();
        let eq = static_equilibrium(&system, TOLERANCE).unwrap();
        assert!(eq.relative_residual <= TOLERANCE);
        if kind == EnergyKind::StVenantKirchhoff {
            // Its stress was formed from G already (F S with E from G).
            continue;
        }
        let lame = system.material().lame;
        let from_f = relative_residual(&system, &eq.displacement, |f| {
            stress_from_f(kind, f, lame.mu, lame.lambda)
        });
        assert!(from_f > TOLERANCE, "{}: {from_f:e}", kind.name());
    }
}

/// The co-rotated membrane at k = 1e6 N/m (n = 10), which stalled at 1.6e-10 of the largest
/// weight with F − R formed from F (the reason the default tolerance is 1e-9), reaches 1e-11.
#[test]
fn the_stiff_corotated_membrane_converges_tightly() {
    let system = membrane(10, EnergyKind::Corotated, 1e6).unwrap();
    let eq = static_equilibrium(&system, 1e-11).unwrap();
    assert!(eq.relative_residual <= 1e-11);
}

/// A deformation gradient with a non-finite entry: the SVD refuses it with an error naming the
/// entry, and a system at such a state has NaN forces, residual and Hessian, never a hang or a
/// panic. Wrong implementation it catches (tried): nalgebra's SVD called on it, which iterates
/// without end.
#[test]
fn a_non_finite_deformation_gradient_is_refused() {
    let mut f = DMatrix::<f64>::identity(3, 3);
    f[(1, 2)] = f64::INFINITY;
    match Polar::new(&f) {
        Err(Error::InvalidParameter { field, .. }) => {
            assert_eq!(field, "deformation gradient F[1][2]")
        }
        other => panic!("{other:?}"),
    }
    assert!(Polar::new(&DMatrix::identity(3, 2)).is_ok());
    for kind in [EnergyKind::Arap, EnergyKind::Corotated] {
        let system = cook(2, kind, 1.0).unwrap();
        let d = system.dimension();
        let mut u = vec![0.0; d * system.node_count()];
        u[d * cook_node(2, 2, 1)] = f64::NAN;
        assert!(system.residual(&u).is_nan());
        assert!(system.energy(&u).is_nan());
        let hessian = system.hessian(&u, true);
        assert!((0..hessian.dim()).any(|i| hessian.get(i, i).is_nan()));
    }
}
