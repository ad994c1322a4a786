//! The linear (small-strain) energy: the reference every other energy linearises to at rest,
//! and the negative control of rotation invariance (Sifakis and Barbič 2012).

use crate::model::continuum::hyperelastic::{
    hooke, isotropic_quadratic, symmetric_part, Deformation, Hyperelastic,
};
use crate::model::continuum::lame::Lame;
use nalgebra::DMatrix;

/// Ψ = μ‖ε‖² + λ/2 (tr ε)², ε = (F + Fᵀ)/2 − I: square F only (not on membranes).
#[derive(Debug, Clone, Copy, Default)]
pub struct Linear;

impl Hyperelastic for Linear {
    fn name(&self) -> &'static str {
        "linear"
    }

    /// A flat linear membrane has no stiffness across its plane (fem-scenes.md).
    fn supports_membranes(&self) -> bool {
        false
    }

    /// [Sifakis 2012, linear elasticity] (unverified; checked against HOBAKv1 LINEAR.cpp) Ψ = μ‖ε‖² + λ/2 (tr ε)²,
    /// with ε = (G + Gᵀ)/2 formed from G = F − I.
    fn density(&self, d: &Deformation, lame: &Lame) -> f64 {
        isotropic_quadratic(&symmetric_part(d.g()), lame)
    }

    /// [Sifakis 2012, linear elasticity] (unverified; checked against HOBAKv1 LINEAR.cpp) P = 2με + λ (tr ε) I.
    fn stress(&self, d: &Deformation, lame: &Lame) -> DMatrix<f64> {
        hooke(&symmetric_part(d.g()), lame)
    }

    /// [Sifakis 2012, linear elasticity] (unverified; checked against HOBAKv1 LINEAR.cpp) dP = 2μ sym(dF) + λ tr(dF) I,
    /// the same at every F.
    fn stress_differential(&self, _: &Deformation, lame: &Lame, df: &DMatrix<f64>) -> DMatrix<f64> {
        hooke(&symmetric_part(df), lame)
    }
}
