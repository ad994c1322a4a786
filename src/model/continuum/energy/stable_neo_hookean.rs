//! The stable neo-Hookean energy without its log term (Smith, de Goes and Kim 2018, §3.4; the
//! form of Macklin and Müller 2021 and of Vertex Block Descent's tets).
//!
//! With λ′ = λ + μ and α = 1 + μ/λ′ it linearises at rest to the linear energy with the Lamé
//! μ, λ; its rest energy is the constant μ²/(2λ′), kept (not subtracted) so that Ψ is the
//! paper's. J is det F for square F, and √det(FᵀF) for a membrane's 3×2 F (a surface has no
//! orientation: J ≥ 0).

use crate::model::continuum::hyperelastic::{Deformation, Hyperelastic};
use crate::model::continuum::lame::Lame;
use nalgebra::{DMatrix, Vector3};

/// Ψ = μ/2 (tr(FᵀF) − c) + λ′/2 (J − α)², c = 3 for a tet and 2 for a triangle.
#[derive(Debug, Clone, Copy, Default)]
pub struct StableNeoHookean;

/// λ′ = λ + μ and α = 1 + μ/λ′ (Smith 2018 §3.4's re-parameterisation).
fn reparameterised(lame: &Lame) -> (f64, f64) {
    let lambda = lame.lambda + lame.mu;
    (lambda, 1.0 + lame.mu / lambda)
}

/// J − 1 formed from G so that it keeps its digits at small strain: for square F,
/// det(I + G) − 1 = tr G + (the principal 2×2 minors of G) + det G; for a membrane,
/// (det(I + 2E) − 1)/(J + 1) with det(I + 2E) − 1 = 2 tr E + 4 det E.
fn volume_change(d: &Deformation) -> f64 {
    let g = d.g();
    if d.is_square() {
        let minors = if g.nrows() == 3 {
            let minor = |a: usize, b: usize| g[(a, a)] * g[(b, b)] - g[(a, b)] * g[(b, a)];
            minor(0, 1) + minor(0, 2) + minor(1, 2)
        } else {
            0.0
        };
        g.trace() + minors + g.determinant()
    } else {
        let e = d.green_strain();
        let excess = 2.0 * e.trace() + 4.0 * e.determinant();
        excess / ((1.0 + excess).sqrt() + 1.0)
    }
}

/// ∂J/∂F: the cofactor matrix for square F (columns f₂×f₃, f₃×f₁, f₁×f₂ in 3D), J F (FᵀF)⁻¹
/// for a membrane.
fn volume_gradient(d: &Deformation) -> DMatrix<f64> {
    let f = d.f();
    match f.shape() {
        (3, 3) => cofactor_3d(f, f),
        (2, 2) => cofactor_2d(f),
        _ => {
            let c_inverse = inverse_2x2(&(f.transpose() * f));
            f * c_inverse * (1.0 + volume_change(d))
        }
    }
}

/// F − ∂J/∂F formed from G, which at rest cancels to zero: for 3×3 F, cof(I + G) =
/// I + (tr G) I − Gᵀ + cof G, so F − cof F = G + Gᵀ − (tr G) I − cof G; for 2×2,
/// cof(I + G) = I + cof G (cof linear there), so F − cof F = G − cof G; for a membrane,
/// ∂J/∂F = J F C⁻¹ with J C⁻¹ = adj(C)/J and adj(I + 2E) = I + 2((tr E) I − E), so
/// F − ∂J/∂F = F ((J − 1) I − 2((tr E) I − E)) / J.
fn gradient_less_volume_gradient(d: &Deformation) -> DMatrix<f64> {
    let g = d.g();
    match g.shape() {
        (3, 3) => g + g.transpose() - DMatrix::identity(3, 3) * g.trace() - cofactor_3d(g, g),
        (2, 2) => g - cofactor_2d(g),
        _ => {
            let e = d.green_strain();
            let j_minus_one = volume_change(d);
            let inner = DMatrix::identity(2, 2) * (j_minus_one - 2.0 * e.trace()) + e * 2.0;
            d.f() * inner / (1.0 + j_minus_one)
        }
    }
}

/// The differential of ∂J/∂F along dF: in 3D the cofactor is bilinear in F's columns
/// (columns df₂×f₃ + f₂×df₃, ...); in 2D it is linear in F; for a membrane, of J F C⁻¹ with
/// C = FᵀF: dJ F C⁻¹ + J dF C⁻¹ − J F C⁻¹ dC C⁻¹, dJ = ∂J/∂F : dF, dC = dFᵀF + FᵀdF.
fn volume_gradient_differential(d: &Deformation, df: &DMatrix<f64>) -> DMatrix<f64> {
    let f = d.f();
    match f.shape() {
        (3, 3) => cofactor_3d(df, f) + cofactor_3d(f, df),
        (2, 2) => cofactor_2d(df),
        _ => {
            let j = 1.0 + volume_change(d);
            let c_inverse = inverse_2x2(&(f.transpose() * f));
            let dj = volume_gradient(d).dot(df);
            let ft_df = f.transpose() * df;
            let dc = &ft_df + ft_df.transpose();
            f * &c_inverse * dj + df * &c_inverse * j - f * &c_inverse * dc * &c_inverse * j
        }
    }
}

/// The polarised 3D cofactor: columns a₂×b₃, a₃×b₁, a₁×b₂ (the cofactor of F when a = b = F;
/// its two halves with a or b replaced by dF make the differential).
fn cofactor_3d(a: &DMatrix<f64>, b: &DMatrix<f64>) -> DMatrix<f64> {
    let col = |m: &DMatrix<f64>, k: usize| Vector3::new(m[(0, k)], m[(1, k)], m[(2, k)]);
    let mut out = DMatrix::zeros(3, 3);
    for k in 0..3 {
        let cross = col(a, (k + 1) % 3).cross(&col(b, (k + 2) % 3));
        out.column_mut(k).copy_from(&cross);
    }
    out
}

/// The 2D cofactor [[f₂₂, −f₂₁], [−f₁₂, f₁₁]].
fn cofactor_2d(f: &DMatrix<f64>) -> DMatrix<f64> {
    DMatrix::from_row_slice(2, 2, &[f[(1, 1)], -f[(1, 0)], -f[(0, 1)], f[(0, 0)]])
}

/// The inverse of a 2×2 FᵀF, whose determinant J² is positive on any membrane that is not
/// collapsed (a collapsed one gives infinities, which the line search rejects).
fn inverse_2x2(c: &DMatrix<f64>) -> DMatrix<f64> {
    cofactor_2d(c).transpose() / c.determinant()
}

impl Hyperelastic for StableNeoHookean {
    fn name(&self) -> &'static str {
        "stable-neo-hookean"
    }

    /// [Smith 2018, §3.4] (unverified; checked against HOBAKv1 SNH.cpp for tets; HOBAK has no membranes: the membrane's J = √det(FᵀF) is ours, an interpretation) Ψ = μ/2 (tr(FᵀF) − c) + λ′/2 (J − α)²,
    /// with tr(FᵀF) − c = 2 tr E and J − α = (J − 1) − μ/λ′ from G.
    fn density(&self, d: &Deformation, lame: &Lame) -> f64 {
        let (lambda, alpha) = reparameterised(lame);
        let j_minus_alpha = volume_change(d) - (alpha - 1.0);
        lame.mu * d.green_strain().trace() + 0.5 * lambda * j_minus_alpha * j_minus_alpha
    }

    /// [Smith 2018, §3.4] (unverified; checked against HOBAKv1 SNH.cpp for tets; HOBAK has no membranes: the membrane's J = √det(FᵀF) is ours, an interpretation) P = μF + λ′ (J − α) ∂J/∂F,
    /// written as μ (F − ∂J/∂F) + λ′ (J − 1) ∂J/∂F (λ′ (α − 1) = μ), whose two terms vanish
    /// at rest and are formed from G ([`gradient_less_volume_gradient`], [`volume_change`]).
    fn stress(&self, d: &Deformation, lame: &Lame) -> DMatrix<f64> {
        let lambda = reparameterised(lame).0;
        gradient_less_volume_gradient(d) * lame.mu
            + volume_gradient(d) * (lambda * volume_change(d))
    }

    /// [Smith 2018, §3.4] (unverified; checked against HOBAKv1 SNH.cpp for tets; HOBAK has no membranes: the membrane's J = √det(FᵀF) is ours, an interpretation) dP = μ dF + λ′ (∂J/∂F : dF) ∂J/∂F + λ′ (J − α) d(∂J/∂F).
    fn stress_differential(&self, d: &Deformation, lame: &Lame, df: &DMatrix<f64>) -> DMatrix<f64> {
        let (lambda, alpha) = reparameterised(lame);
        let j_minus_alpha = volume_change(d) - (alpha - 1.0);
        let dj_df = volume_gradient(d);
        df * lame.mu
            + &dj_df * (lambda * dj_df.dot(df))
            + volume_gradient_differential(d, df) * (lambda * j_minus_alpha)
    }
}
