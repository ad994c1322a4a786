//! The rotation-variant SVD and the polar decomposition of a deformation gradient, and the
//! derivative of its rotation (`docs/fem-scenes.md`, "Energies"; the reflection fix of
//! Projective Dynamics' strain projection, `docs/papers.md`).
//!
//! F = U Σ Vᵀ with the singular values in descending order. For a square F (a tet's 3×3, a
//! plane triangle's 2×2) U and V are made rotations: when det U < 0 the last column of U and
//! the smallest singular value change sign, and likewise for V; so when det U · det V < 0 the
//! smallest singular value ends negative and R = U Vᵀ is a rotation, which pushes an inverted
//! element back through its inversion rather than mirroring it. For a membrane's 3×2 F the SVD
//! is the thin one (U 3×2, orthonormal columns) and nothing is flipped: a surface in 3D has no
//! orientation to invert, and its singular values are the non-negative stretches.
//!
//! The rotation R = U Vᵀ and the stretch S = V Σ Vᵀ = RᵀF (symmetric) are F's polar factors.

use crate::error::{Error, Result};
use nalgebra::{DMatrix, DVector};

/// A singular-value sum (or, for a membrane, a singular value) below this is taken as this,
/// with its sign: the rotation of a flat element is not unique and its derivative unbounded,
/// and any bounded value serves Newton's projected Hessian as well.
const SINGULAR_FLOOR: f64 = 1e-12;

/// F = U diag(σ) Vᵀ in the rotation-variant convention of the module doc.
#[derive(Debug, Clone, PartialEq)]
pub struct Polar {
    /// d×c: a rotation (square F) or orthonormal columns (a membrane's 3×2 F).
    pub u: DMatrix<f64>,
    /// c singular values, descending but for the sign of the last (square F only).
    pub sigma: DVector<f64>,
    /// c×c orthogonal (a rotation for square F).
    pub v: DMatrix<f64>,
}

impl Polar {
    /// The rotation-variant SVD of a d×c F (d ≥ c); refuses an F with a non-finite entry,
    /// naming it (nalgebra's SVD panics or iterates without end on one).
    pub fn new(f: &DMatrix<f64>) -> Result<Self> {
        if let Some(k) = f.iter().position(|x| !x.is_finite()) {
            let (i, j) = (k % f.nrows(), k / f.nrows());
            return Err(Error::invalid(
                format!("deformation gradient F[{i}][{j}]"),
                f[(i, j)],
                "a finite number (a non-finite displacement reached the element)",
            ));
        }
        let (d, c) = f.shape();
        let svd = nalgebra::SVD::new(f.clone(), true, true);
        let (Some(mut u), Some(v_t)) = (svd.u, svd.v_t) else {
            unreachable!("both factors were requested")
        };
        let mut v = v_t.transpose();
        let mut sigma = svd.singular_values;
        if d == c {
            for m in [&mut u, &mut v] {
                if m.determinant() < 0.0 {
                    m.column_mut(c - 1).neg_mut();
                    sigma[c - 1] = -sigma[c - 1];
                }
            }
        }
        Ok(Self { u, sigma, v }.polished(f))
    }

    /// The decomposition of a d×c F that has a non-finite entry: every factor NaN, so that
    /// what is computed from it (Ψ, P, the forces, the residual) is NaN and reads as no
    /// progress, never as converged.
    pub fn undefined(d: usize, c: usize) -> Self {
        Self {
            u: DMatrix::from_element(d, c, f64::NAN),
            sigma: DVector::from_element(c, f64::NAN),
            v: DMatrix::from_element(c, c, f64::NAN),
        }
    }

    /// This SVD with U refined by one Newton step of the polar decomposition, so that
    /// R = U Vᵀ makes RᵀF symmetric to round-off: nalgebra's singular vectors leave skew(RᵀF)
    /// at up to 1e-10 of F when two singular values are close (measured at strains of 1e-3),
    /// which put a floor of about 5e-10 of the largest nodal weight under the soft beam's
    /// co-rotated equilibrium residual. The step is R₀ + dR along dF = F itself
    /// ([`Self::rotation_differential`]: its skew solve maps out the skew part of R₀ᵀF, and
    /// for a membrane its normal term brings R's columns into F's plane), then R(3I − RᵀR)/2
    /// to restore orthonormal columns to second order, and U = R V.
    fn polished(self, f: &DMatrix<f64>) -> Self {
        let c = f.ncols();
        let r = self.rotation() + self.rotation_differential(f);
        let r = &r * (DMatrix::identity(c, c) * 3.0 - r.transpose() * &r) * 0.5;
        let u = r * &self.v;
        Self { u, ..self }
    }

    /// R = U Vᵀ.
    pub fn rotation(&self) -> DMatrix<f64> {
        &self.u * self.v.transpose()
    }

    /// The differential dR of R = U Vᵀ along dF.
    ///
    /// From F = R S with RᵀR = I and S symmetric: dR = R A + (I − R Rᵀ) dF S⁻¹, where A is
    /// skew and, in V's basis, Ã = Vᵀ A V has Ã_ij = M_ij / (σ_i + σ_j) with
    /// M = Vᵀ (Rᵀ dF − dFᵀ R) V (the skew part of Rᵀ dF = A S + dS, S symmetric). For square F
    /// the second term vanishes (R R ᵀ = I), so S may be singular or indefinite; only a
    /// membrane needs S⁻¹ = V Σ⁻¹ Vᵀ.
    pub fn rotation_differential(&self, df: &DMatrix<f64>) -> DMatrix<f64> {
        let (d, c) = df.shape();
        let r = self.rotation();
        let rt_df = r.transpose() * df;
        let m = self.v.transpose() * (&rt_df - rt_df.transpose()) * &self.v;
        let skew = DMatrix::from_fn(c, c, |i, j| {
            if i == j {
                0.0
            } else {
                m[(i, j)] / floored(self.sigma[i] + self.sigma[j])
            }
        });
        let mut dr = &r * (&self.v * skew * self.v.transpose());
        if d > c {
            let inverse_sigma = self.sigma.map(|s| 1.0 / floored(s));
            let s_inverse = &self.v * DMatrix::from_diagonal(&inverse_sigma) * self.v.transpose();
            let normal = DMatrix::identity(d, d) - &r * r.transpose();
            dr += normal * df * s_inverse;
        }
        dr
    }
}

/// `x`, or [`SINGULAR_FLOOR`] with its sign where it is smaller.
fn floored(x: f64) -> f64 {
    if x.abs() < SINGULAR_FLOOR {
        SINGULAR_FLOOR.copysign(x)
    } else {
        x
    }
}
