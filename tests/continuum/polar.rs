//! The rotation-variant polar decomposition (`src/model/continuum/svd.rs`).

use super::Random;
use mass_spring_solvers::model::continuum::svd::Polar;
use nalgebra::DMatrix;

/// R of F = R S has orthonormal columns and makes RᵀF symmetric to round-off (2e-14 of ‖F‖)
/// at strains from 1e-1 down to 1e-8 under random rotations, for a tet's 3×3 F, inverted ones
/// included (det R = +1 there: the rotation-variant convention), and a membrane's 3×2 F.
/// Wrong implementation it catches (tried): R = U Vᵀ straight from nalgebra's SVD, whose
/// skew(RᵀF) reaches 1e-10 at strains of 1e-3 (the floor that stalled the soft beam's Newton
/// at 5e-10 of the largest weight).
#[test]
fn the_polar_rotation_is_accurate_to_round_off() {
    let mut random = Random::new(5);
    for scale in [1e-1, 1e-3, 1e-5, 1e-8] {
        for k in 0..200 {
            let mut q = DMatrix::from_fn(3, 3, |_, _| random.uniform()).qr().q();
            if q.determinant() < 0.0 {
                q.column_mut(0).neg_mut();
            }
            let mut stretch =
                DMatrix::identity(3, 3) + DMatrix::from_fn(3, 3, |_, _| scale * random.uniform());
            let inverted = k % 2 == 1;
            if inverted {
                stretch.column_mut(2).neg_mut();
            }
            let columns = if k % 3 == 0 { 2 } else { 3 };
            let f = (&q * stretch).columns(0, columns).into_owned();
            let polar = Polar::new(&f).unwrap();
            let r = polar.rotation();
            let orthonormal = (r.transpose() * &r - DMatrix::identity(columns, columns)).norm();
            let s = r.transpose() * &f;
            let skew = (&s - s.transpose()).norm();
            assert!(
                orthonormal < 2e-14 && skew < 2e-14,
                "strain {scale:e}: {orthonormal:e}, {skew:e}"
            );
            if columns == 3 {
                assert!(
                    (r.determinant() - 1.0).abs() < 1e-14,
                    "det R = {}",
                    r.determinant()
                );
                assert_eq!(polar.sigma[2] < 0.0, inverted);
            }
        }
    }
}
