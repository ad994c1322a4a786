//! The co-rotated energy: ARAP plus a volume term (Sifakis and Barbič 2012; Liu et al. 2017,
//! whose reference code GenPD evaluates it).

use crate::model::continuum::hyperelastic::{Deformation, Hyperelastic};
use crate::model::continuum::lame::Lame;
use nalgebra::DMatrix;

/// Ψ = μ‖F − R‖² + λ/2 (tr(RᵀF) − c)², c = 3 for a tet and 2 for a triangle; the first term is
/// [`Arap`](super::Arap)'s.
#[derive(Debug, Clone, Copy, Default)]
pub struct Corotated;

/// tr(RᵀF) − c = Σσ − c, the sum of F's signed singular values less their rest value.
fn volume_strain(d: &Deformation) -> f64 {
    d.polar().sigma.sum() - d.material_dimension() as f64
}

impl Hyperelastic for Corotated {
    fn name(&self) -> &'static str {
        "corotated"
    }

    /// [Liu 2017, co-rotated energy] (unverified; checked against GenPD constraint_tet.cpp for tets; the membrane's, with the thin-SVD R, is ours, an interpretation) Ψ = μ‖F − R‖² + λ/2 (tr(RᵀF) − c)²,
    /// both terms formed from G ([`Deformation::rotation_excess`]).
    fn density(&self, d: &Deformation, lame: &Lame) -> f64 {
        let excess = d.rotation_excess();
        lame.mu * excess.difference.norm_squared() + 0.5 * lame.lambda * excess.trace * excess.trace
    }

    /// [Liu 2017, co-rotated energy] (unverified; checked against GenPD constraint_tet.cpp for tets; the membrane's, with the thin-SVD R, is ours, an interpretation) P = 2μ(F − R) + λ (tr(RᵀF) − c) R,
    /// with F − R and tr(RᵀF) − c formed from G ([`Deformation::rotation_excess`]) and
    /// R = F − (F − R).
    fn stress(&self, d: &Deformation, lame: &Lame) -> DMatrix<f64> {
        let excess = d.rotation_excess();
        let r = d.f() - &excess.difference;
        &excess.difference * (2.0 * lame.mu) + r * (lame.lambda * excess.trace)
    }

    /// [Liu 2017, co-rotated energy] (unverified; checked against GenPD constraint_tet.cpp for tets; the membrane's, with the thin-SVD R, is ours, an interpretation) dP = 2μ(dF − dR) + λ (R : dF) R + λ (tr(RᵀF) − c) dR,
    /// since d tr(RᵀF) = R : dF (dRᵀF contributes a skew matrix times the symmetric RᵀF, and
    /// for a membrane a normal part that F has none of).
    fn stress_differential(&self, d: &Deformation, lame: &Lame, df: &DMatrix<f64>) -> DMatrix<f64> {
        let r = d.polar().rotation();
        let dr = d.polar().rotation_differential(df);
        (df - &dr) * (2.0 * lame.mu)
            + &r * (lame.lambda * r.dot(df))
            + dr * (lame.lambda * volume_strain(d))
    }
}
