//! The Saint Venant-Kirchhoff energy: Hooke's law on the Green strain (Sifakis and Barbič 2012);
//! XPBD's strain constraints and cloth; weak in compression.

use crate::model::continuum::hyperelastic::{
    hooke, isotropic_quadratic, Deformation, Hyperelastic,
};
use crate::model::continuum::lame::Lame;
use nalgebra::DMatrix;

/// Ψ = μ‖E‖² + λ/2 (tr E)², E = (FᵀF − I)/2.
#[derive(Debug, Clone, Copy, Default)]
pub struct StVenantKirchhoff;

impl Hyperelastic for StVenantKirchhoff {
    fn name(&self) -> &'static str {
        "stvk"
    }

    /// [Sifakis 2012, StVK] (unverified; checked against HOBAKv1 STVK.cpp for tets; HOBAK has no membranes: the membrane's, on its 3×2 F, is ours, an interpretation) Ψ = μ‖E‖² + λ/2 (tr E)².
    fn density(&self, d: &Deformation, lame: &Lame) -> f64 {
        isotropic_quadratic(&d.green_strain(), lame)
    }

    /// [Sifakis 2012, StVK] (unverified; checked against HOBAKv1 STVK.cpp for tets; HOBAK has no membranes: the membrane's, on its 3×2 F, is ours, an interpretation) P = F S, S = 2μE + λ (tr E) I.
    fn stress(&self, d: &Deformation, lame: &Lame) -> DMatrix<f64> {
        d.f() * hooke(&d.green_strain(), lame)
    }

    /// [Sifakis 2012, StVK] (unverified; checked against HOBAKv1 STVK.cpp for tets; HOBAK has no membranes: the membrane's, on its 3×2 F, is ours, an interpretation) dP = dF S + F (2μ dE + λ tr(dE) I),
    /// dE = (dFᵀF + FᵀdF)/2.
    fn stress_differential(&self, d: &Deformation, lame: &Lame, df: &DMatrix<f64>) -> DMatrix<f64> {
        let ft_df = d.f().transpose() * df;
        let de = (&ft_df + ft_df.transpose()) * 0.5;
        df * hooke(&d.green_strain(), lame) + d.f() * hooke(&de, lame)
    }
}
