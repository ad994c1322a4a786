//! The as-rigid-as-possible energy, Projective Dynamics' strain energy with weight 2μV
//! (Bouaziz et al. 2014): no volume term, so no Poisson effect.

use crate::model::continuum::hyperelastic::{Deformation, Hyperelastic};
use crate::model::continuum::lame::Lame;
use nalgebra::DMatrix;

/// Ψ = μ‖F − R‖², R the rotation of F's rotation-variant polar decomposition.
#[derive(Debug, Clone, Copy, Default)]
pub struct Arap;

impl Hyperelastic for Arap {
    fn name(&self) -> &'static str {
        "arap"
    }

    /// [Bouaziz 2014, strain energy] (unverified; checked against HOBAKv1 ARAP.cpp for tets; HOBAK has no membranes: the membrane's thin-SVD R is ours, an interpretation) Ψ = μ‖F − R‖²,
    /// F − R formed from G ([`Deformation::rotation_excess`]).
    fn density(&self, d: &Deformation, lame: &Lame) -> f64 {
        lame.mu * d.rotation_excess().difference.norm_squared()
    }

    /// [Bouaziz 2014, strain energy] (unverified; checked against HOBAKv1 ARAP.cpp for tets; HOBAK has no membranes: the membrane's thin-SVD R is ours, an interpretation) P = 2μ(F − R)
    /// (R is stationary: ∂‖F − R‖²/∂R vanishes along the rotations, as RᵀF is symmetric), F − R
    /// formed from G ([`Deformation::rotation_excess`]).
    fn stress(&self, d: &Deformation, lame: &Lame) -> DMatrix<f64> {
        d.rotation_excess().difference * (2.0 * lame.mu)
    }

    /// [Bouaziz 2014, strain energy] (unverified; checked against HOBAKv1 ARAP.cpp for tets; HOBAK has no membranes: the membrane's thin-SVD R is ours, an interpretation) dP = 2μ(dF − dR),
    /// dR from [`Polar::rotation_differential`](crate::model::continuum::svd::Polar::rotation_differential).
    fn stress_differential(&self, d: &Deformation, lame: &Lame, df: &DMatrix<f64>) -> DMatrix<f64> {
        (df - d.polar().rotation_differential(df)) * (2.0 * lame.mu)
    }
}
