//! The five energies on every shape: finite differences, rest and rotations, linearisation at
//! rest, the clamp, uniaxial stretch against closed forms; and the Lamé conversion.

use super::Random;
use mass_spring_solvers::model::continuum::energy::EnergyKind;
use mass_spring_solvers::model::continuum::hyperelastic::Deformation;
use mass_spring_solvers::model::continuum::lame::{Lame, Loading};
use mass_spring_solvers::Error;
use nalgebra::{DMatrix, SymmetricEigen};

/// F's shapes: a tet's, a plane triangle's, a membrane's.
const SHAPES: [(usize, usize); 3] = [(3, 3), (2, 2), (3, 2)];

/// A material with λ ≠ μ, so that a swapped pair shows.
const LAME: Lame = Lame {
    mu: 1.3,
    lambda: 2.1,
};

/// The energies defined on a shape (no linear membrane).
fn energies_on(shape: (usize, usize)) -> impl Iterator<Item = EnergyKind> {
    EnergyKind::ALL
        .into_iter()
        .filter(move |e| shape.0 == shape.1 || e.model().supports_membranes())
}

/// The canonical rest F₀ of a shape (the identity's first columns).
fn rest(shape: (usize, usize)) -> DMatrix<f64> {
    DMatrix::identity(shape.0, shape.1)
}

/// Random F near F₀; for square shapes every other one inverted (a column negated).
fn random_gradients(shape: (usize, usize), count: usize) -> Vec<DMatrix<f64>> {
    let mut random = Random::new(7 + shape.0 as u64 * 10 + shape.1 as u64);
    (0..count)
        .map(|k| {
            let mut f =
                rest(shape) + DMatrix::from_fn(shape.0, shape.1, |_, _| 0.4 * random.uniform());
            if shape.0 == shape.1 && k % 2 == 1 {
                f.column_mut(0).neg_mut();
            }
            f
        })
        .collect()
}

/// A random rotation (3D, or 2D), from the QR factor of a random matrix with det fixed to +1.
fn random_rotation(d: usize, random: &mut Random) -> DMatrix<f64> {
    let mut q = DMatrix::from_fn(d, d, |_, _| random.uniform()).qr().q();
    if q.determinant() < 0.0 {
        q.column_mut(0).neg_mut();
    }
    q
}

/// Central differences of `value` in each entry of F, step h.
fn central_differences(
    f: &DMatrix<f64>,
    h: f64,
    value: impl Fn(&DMatrix<f64>) -> DMatrix<f64>,
) -> DMatrix<f64> {
    let n = f.len();
    let rows = value(f).len();
    let mut out = DMatrix::zeros(rows, n);
    for k in 0..n {
        let (mut plus, mut minus) = (f.clone(), f.clone());
        plus.as_mut_slice()[k] += h;
        minus.as_mut_slice()[k] -= h;
        let diff = (value(&plus) - value(&minus)) / (2.0 * h);
        out.column_mut(k).copy_from_slice(diff.as_slice());
    }
    out
}

fn at(f: &DMatrix<f64>) -> Deformation {
    Deformation::from_gradient(f.clone())
}

/// The relative difference ‖a − b‖ / max(‖b‖, 1).
fn relative(a: &DMatrix<f64>, b: &DMatrix<f64>) -> f64 {
    (a - b).norm() / b.norm().max(1.0)
}

/// P = ∂Ψ/∂F and ∂P/∂F = ∂vec(P)/∂vec(F) by central differences (step 1e-6, agreement to
/// 1e-6 relative) at ten random F per shape, half of the square ones inverted, for every
/// energy and shape. Wrong implementation it catches (tried): co-rotated's differential
/// without its λ (tr(RᵀF) − c) dR term.
#[test]
fn stresses_and_their_derivatives_match_finite_differences() {
    for shape in SHAPES {
        for kind in energies_on(shape) {
            let energy = kind.model();
            for f in random_gradients(shape, 10) {
                let stress = energy.stress(&at(&f), &LAME);
                let fd_stress = central_differences(&f, 1e-6, |f| {
                    DMatrix::from_element(1, 1, energy.density(&at(f), &LAME))
                });
                let fd_stress = DMatrix::from_column_slice(shape.0, shape.1, fd_stress.as_slice());
                let e = relative(&stress, &fd_stress);
                assert!(
                    e < 1e-6,
                    "{} {shape:?}: P off by {e:.1e} at {f}",
                    kind.name()
                );
                let derivative = energy.stress_derivative(&at(&f), &LAME);
                let fd = central_differences(&f, 1e-6, |f| energy.stress(&at(f), &LAME));
                let e = relative(&derivative, &fd);
                assert!(
                    e < 1e-6,
                    "{} {shape:?}: ∂P/∂F off by {e:.1e} at {f}",
                    kind.name()
                );
            }
        }
    }
}

/// Zero stress at rest and under rotations for every energy but the linear one, whose
/// stress under a rotation of 0.3 rad or more is of the order of μ (it is not rotation
/// invariant: asserted); zero energy at rest except the stable neo-Hookean's μ²/(2λ′).
/// Wrong implementations it catches (tried): the stable neo-Hookean with α = 1 (stressed at
/// rest), and a linear energy written with the Green strain (rotation invariant, so the
/// negative control fails).
#[test]
fn rest_and_rotations_are_stress_free() {
    let mut random = Random::new(3);
    for shape in SHAPES {
        let d = shape.0;
        for kind in energies_on(shape) {
            let energy = kind.model();
            let rest_energy = energy.density(&at(&rest(shape)), &LAME);
            let expected = if kind == EnergyKind::StableNeoHookean {
                LAME.mu * LAME.mu / (2.0 * (LAME.lambda + LAME.mu))
            } else {
                0.0
            };
            assert!(
                (rest_energy - expected).abs() < 1e-15,
                "{}: Ψ(I) = {rest_energy}",
                kind.name()
            );
            assert!(energy.stress(&at(&rest(shape)), &LAME).norm() < 1e-15);
            for _ in 0..5 {
                let q = loop {
                    let q = random_rotation(d, &mut random);
                    // At least 0.3 rad from the identity: ‖Q − I‖² = 2(d − tr Q) in 2D/3D.
                    if (q.clone() - DMatrix::identity(d, d)).norm() > 0.4 {
                        break q;
                    }
                };
                let f = &q * rest(shape);
                let p = energy.stress(&at(&f), &LAME).norm();
                let psi = energy.density(&at(&f), &LAME) - expected;
                if kind == EnergyKind::Linear {
                    assert!(p > 0.1 * LAME.mu, "linear: P = {p} under a rotation");
                } else {
                    assert!(
                        p < 1e-12,
                        "{} {shape:?}: ‖P‖ = {p:e} under {q}",
                        kind.name()
                    );
                    assert!(psi.abs() < 1e-12, "{}: Ψ − Ψ(I) = {psi:e}", kind.name());
                }
            }
        }
    }
}

/// An inverted element is pushed back through its inversion, not mirrored: at
/// F = diag(1, 1, −0.5) (a tet) and diag(1, −0.5) (a plane triangle) ARAP and co-rotated have
/// positive energy and P's last diagonal entry is negative, so that −P raises F's last entry
/// towards +1. Wrong implementation it catches (tried): the SVD without the rotation-variant
/// flip, whose R is then the reflection F/|F| itself (zero ARAP energy, a rest at −1).
#[test]
fn an_inverted_element_is_pushed_back() {
    for diagonal in [vec![1.0, 1.0, -0.5], vec![1.0, -0.5]] {
        let n = diagonal.len();
        let f = DMatrix::from_diagonal(&nalgebra::DVector::from_vec(diagonal));
        for kind in [EnergyKind::Arap, EnergyKind::Corotated] {
            let psi = kind.model().density(&at(&f), &LAME);
            let p = kind.model().stress(&at(&f), &LAME);
            assert!(psi > 0.5 * LAME.mu, "{}: Ψ = {psi}", kind.name());
            assert!(p[(n - 1, n - 1)] < -LAME.mu, "{}: P = {p}", kind.name());
        }
    }
}

/// At F = F₀ every energy's ∂P/∂F is the linear energy's with the same μ, λ (ARAP's with
/// λ = 0); on a membrane, the plane linear energy's on the in-plane entries and zero across
/// the plane. Wrong implementation it catches (tried): the stable neo-Hookean with λ′ = λ
/// (no re-parameterisation), whose linearisation is off in the λ entries.
#[test]
fn every_energy_linearises_to_the_linear_one_at_rest() {
    for shape in SHAPES {
        let plane = (shape.1, shape.1);
        for kind in energies_on(shape) {
            let lame = if kind == EnergyKind::Arap {
                Lame {
                    lambda: 0.0,
                    ..LAME
                }
            } else {
                LAME
            };
            let linear = EnergyKind::Linear
                .model()
                .stress_derivative(&at(&rest(plane)), &lame);
            let c = kind.model().stress_derivative(&at(&rest(shape)), &LAME);
            // vec index i + d j of the shape's F against i + c j of the plane's.
            let (d, cols) = shape;
            for (a, b) in (0..d * cols).flat_map(|a| (0..d * cols).map(move |b| (a, b))) {
                let (ia, ja, ib, jb) = (a % d, a / d, b % d, b / d);
                let expected = if ia < cols && ib < cols {
                    linear[(ia + cols * ja, ib + cols * jb)]
                } else {
                    0.0
                };
                assert!(
                    (c[(a, b)] - expected).abs() < 1e-12,
                    "{} {shape:?}: ∂P/∂F[{a},{b}] = {} against {expected}",
                    kind.name(),
                    c[(a, b)]
                );
            }
        }
    }
}

/// The clamp is the positive part C⁺ of ∂P/∂F, which three properties fix uniquely whatever
/// eigen-solver computed it: C⁺ is PSD, C⁺ − C is PSD, and C⁺(C⁺ − C) = 0; checked at random
/// F, inverted ones included, where some energy's ∂P/∂F is indefinite (asserted, or the test
/// would prove nothing). Wrong implementation it catches (tried): eigenvalues replaced by
/// their absolute values (C⁺ − C is PSD, but C⁺(C⁺ − C) ≠ 0).
#[test]
fn the_clamp_is_the_positive_part() {
    let mut indefinite = 0;
    for shape in SHAPES {
        for kind in energies_on(shape) {
            for f in random_gradients(shape, 6) {
                let c = kind.model().stress_derivative(&at(&f), &LAME);
                let c = (&c + c.transpose()) * 0.5;
                let clamped = kind.model().clamped_stress_derivative(&at(&f), &LAME);
                let smallest = |m: &DMatrix<f64>| SymmetricEigen::new(m.clone()).eigenvalues.min();
                let scale = c.norm();
                if smallest(&c) < -1e-6 * scale {
                    indefinite += 1;
                }
                assert!(
                    smallest(&clamped) > -1e-12 * scale,
                    "{}: not PSD",
                    kind.name()
                );
                let excess = &clamped - &c;
                assert!(
                    smallest(&excess) > -1e-12 * scale,
                    "{}: C⁺ − C not PSD",
                    kind.name()
                );
                let overlap = (&clamped * &excess).norm();
                assert!(
                    overlap < 1e-12 * scale * scale,
                    "{}: C⁺(C⁺ − C) = {overlap:e}",
                    kind.name()
                );
            }
        }
    }
    assert!(
        indefinite > 10,
        "only {indefinite} indefinite ∂P/∂F: the clamp went untested"
    );
}

/// Uniaxial stretch s along x with free lateral faces: the lateral stretch t that makes
/// P₂₂ = P₃₃ = 0, found by bisection on the library's stress, and P₁₁ there, against the
/// closed forms (F = diag(s, t, t), ν = λ/(2(λ + μ)), E = μ(3λ + 2μ)/(λ + μ)):
///
/// - linear: t = 1 − ν(s − 1), P₁₁ = E (s − 1);
/// - ARAP: t = 1 (no Poisson effect), P₁₁ = 2μ (s − 1);
/// - co-rotated: t = 1 − ν(s − 1), P₁₁ = E (s − 1) (R = I for s, t > 0);
/// - StVK: t² = 1 − ν(s² − 1), P₁₁ = E s (s² − 1)/2 (S₂₂ = 0 gives E₂₂ = −ν E₁₁);
/// - stable neo-Hookean: P₂₂ = t(μ + λ′ s (s t² − α)) = 0 gives t² = (α − μ/(λ′ s))/s, and
///   then P₁₁ = μ s + λ′ (s t² − α) t² = μ (s − t²/s).
///
/// At s = 1.2 and 0.9. Wrong implementation it catches (tried): λ doubled in both Hooke's law
/// and its energy, which the linear energy and StVK share (a consistent Ψ and P: the finite
/// differences pass).
#[test]
fn uniaxial_stretch_matches_the_closed_forms() {
    let (mu, lambda) = (LAME.mu, LAME.lambda);
    let nu = lambda / (2.0 * (lambda + mu));
    let youngs = mu * (3.0 * lambda + 2.0 * mu) / (lambda + mu);
    let lambda_p = lambda + mu;
    let alpha = 1.0 + mu / lambda_p;
    for s in [1.2, 0.9] {
        for kind in EnergyKind::ALL {
            let energy = kind.model();
            let f_of = |t: f64| DMatrix::from_diagonal(&nalgebra::DVector::from_vec(vec![s, t, t]));
            let lateral = |t: f64| energy.stress(&at(&f_of(t)), &LAME)[(1, 1)];
            let (mut low, mut high) = (0.5, 1.5);
            assert!(lateral(low) < 0.0 && lateral(high) > 0.0, "{}", kind.name());
            for _ in 0..100 {
                let mid = 0.5 * (low + high);
                if lateral(mid) < 0.0 {
                    low = mid;
                } else {
                    high = mid;
                }
            }
            let t = 0.5 * (low + high);
            let p11 = energy.stress(&at(&f_of(t)), &LAME)[(0, 0)];
            let (t_expected, p_expected) = match kind {
                EnergyKind::Linear | EnergyKind::Corotated => {
                    (1.0 - nu * (s - 1.0), youngs * (s - 1.0))
                }
                EnergyKind::Arap => (1.0, 2.0 * mu * (s - 1.0)),
                EnergyKind::StVenantKirchhoff => (
                    (1.0 - nu * (s * s - 1.0)).sqrt(),
                    youngs * s * (s * s - 1.0) / 2.0,
                ),
                EnergyKind::StableNeoHookean => {
                    let t2 = (alpha - mu / (lambda_p * s)) / s;
                    (t2.sqrt(), mu * (s - t2 / s))
                }
            };
            assert!(
                (t - t_expected).abs() < 1e-12,
                "{} s = {s}: t = {t} against {t_expected}",
                kind.name()
            );
            assert!(
                (p11 - p_expected).abs() < 1e-12 * youngs,
                "{} s = {s}: P₁₁ = {p11} against {p_expected}",
                kind.name()
            );
        }
    }
}

/// μ = E/(2(1 + ν)) and λ = Eν/((1 + ν)(1 − 2ν)) in 3D, λ* = 2λμ/(λ + 2μ) = Eν/(1 − ν²) in
/// plane stress (both forms agree); ν ≥ 0.5, ν ≤ −1, E ≤ 0 and non-finite values refused with
/// the field named. Wrong implementation it catches (tried): plane stress returning the 3D λ.
#[test]
fn lame_conversion_values_and_refusals() {
    let solid = Lame::from_youngs_poisson(1e9, 0.3, Loading::Solid).unwrap();
    assert!((solid.mu - 1e9 / 2.6).abs() < 1e-6);
    assert!((solid.lambda - 1e9 * 0.3 / (1.3 * 0.4)).abs() < 1e-6);
    let plane = Lame::from_youngs_poisson(1e9, 0.3, Loading::PlaneStress).unwrap();
    assert_eq!(plane.mu, solid.mu);
    let from_3d = 2.0 * solid.lambda * solid.mu / (solid.lambda + 2.0 * solid.mu);
    assert!(
        (plane.lambda - from_3d).abs() < 1e-6 * plane.lambda,
        "{} {from_3d}",
        plane.lambda
    );
    let cook = Lame::from_youngs_poisson(1.0, 1.0 / 3.0, Loading::PlaneStress).unwrap();
    assert!((cook.lambda - 0.375).abs() < 1e-15 && (cook.mu - 0.375).abs() < 1e-15);
    for (youngs, poisson, field) in [
        (1.0, 0.5, "poisson_ratio"),
        (1.0, 0.7, "poisson_ratio"),
        (1.0, -1.0, "poisson_ratio"),
        (1.0, f64::NAN, "poisson_ratio"),
        (0.0, 0.3, "youngs_modulus"),
        (-1.0, 0.3, "youngs_modulus"),
        (f64::INFINITY, 0.3, "youngs_modulus"),
    ] {
        for loading in [Loading::Solid, Loading::PlaneStress] {
            match Lame::from_youngs_poisson(youngs, poisson, loading) {
                Err(Error::InvalidParameter { field: f, .. }) => assert_eq!(f, field),
                other => panic!("E = {youngs}, ν = {poisson}: {other:?}"),
            }
        }
    }
    assert!(Lame::from_youngs_poisson(1.0, 0.4999, Loading::Solid).is_ok());
    assert!(Lame::from_youngs_poisson(1.0, -0.999, Loading::Solid).is_ok());
}
