//! What every energy of `docs/fem-scenes.md` provides (its value Ψ, the first Piola stress
//! P = ∂Ψ/∂F, its derivative ∂P/∂F and that derivative made positive semidefinite), and the
//! deformation gradient they are evaluated at.
//!
//! Shapes: F is d×c, 3×3 for a tet, 2×2 for a triangle in the plane and 3×2 for a membrane
//! (a triangle in 3D, in its rest frame). ∂P/∂F is the dc×dc matrix over vec(F), F's columns
//! stacked (nalgebra's column-major order): entry (i + d j, k + d l) is ∂P_ij/∂F_kl.

use super::lame::Lame;
use super::svd::Polar;
use nalgebra::DMatrix;
use std::cell::OnceCell;

/// A deformation gradient F with its displacement gradient G = F − F₀ (F₀ = I for square F,
/// the rest frame's 3×2 orthonormal basis for a membrane).
///
/// The energies evaluate their strains from G, not from F − I: at E = 1e9 the strains are
/// about 1e-5, and FᵀF − I formed from F loses five of its sixteen digits, which is more than
/// a tight equilibrium residual allows (fem-scenes.md).
#[derive(Debug, Clone)]
pub struct Deformation {
    f: DMatrix<f64>,
    g: DMatrix<f64>,
    /// The rotation-variant SVD of F, computed on first use (ARAP and co-rotated need it).
    polar: OnceCell<Polar>,
}

impl Deformation {
    /// F = F₀ + G.
    pub fn from_displacement_gradient(rest: &DMatrix<f64>, g: DMatrix<f64>) -> Self {
        Self {
            f: rest + &g,
            g,
            polar: OnceCell::new(),
        }
    }

    /// A given F (d×c, d ≥ c) against the canonical rest F₀: I, or for 3×2 the first two
    /// columns of the 3×3 identity (a membrane lying in its rest frame).
    pub fn from_gradient(f: DMatrix<f64>) -> Self {
        let g = &f - DMatrix::identity(f.nrows(), f.ncols());
        Self {
            f,
            g,
            polar: OnceCell::new(),
        }
    }

    /// F.
    pub fn f(&self) -> &DMatrix<f64> {
        &self.f
    }

    /// G = F − F₀.
    pub fn g(&self) -> &DMatrix<f64> {
        &self.g
    }

    /// True for a tet's or a plane triangle's F, false for a membrane's.
    pub fn is_square(&self) -> bool {
        self.f.is_square()
    }

    /// c, the dimension of the material (3 for a tet, 2 for a triangle): the rest value of
    /// tr(FᵀF) and of tr(RᵀF).
    pub fn material_dimension(&self) -> usize {
        self.f.ncols()
    }

    /// The Green strain E = (FᵀF − I)/2, formed as (FᵀG + GᵀF − GᵀG)/2 (F₀ᵀF₀ = I), whose
    /// terms are each as small as G.
    pub fn green_strain(&self) -> DMatrix<f64> {
        let ft_g = self.f.transpose() * &self.g;
        (&ft_g + ft_g.transpose() - self.g.transpose() * &self.g) * 0.5
    }

    /// F's rotation-variant SVD; for an F with a non-finite entry, [`Polar::undefined`] (NaN
    /// throughout), so that Ψ, P and the forces are NaN rather than a panic.
    pub fn polar(&self) -> &Polar {
        self.polar.get_or_init(|| {
            let (d, c) = self.f.shape();
            Polar::new(&self.f).unwrap_or_else(|_| Polar::undefined(d, c))
        })
    }

    /// F − R and tr(RᵀF) − c = tr(S − I), R and S = RᵀF F's polar factors, formed from G so
    /// that they keep their digits at small strain: at E = 1e9 the strains are about 1e-5, and
    /// F − R formed from F and nalgebra's R carries an error of about 1e-16 absolute, 1e-11 of
    /// F − R itself, which is more than a tight equilibrium residual allows (fem-scenes.md).
    ///
    /// Where S is positive definite (every singular value of F above [`STRETCH_FLOOR`]; for
    /// square F, det F > 0, else the rotation-variant S has a negative eigenvalue), S is the
    /// square root of FᵀF = I + 2E with the Green strain E formed from G: on E's
    /// eigenvectors, S − I has the eigenvalues 2e/(√(1 + 2e) + 1), each as accurate as E, and
    /// F − R = R (S − I) with R = F S⁻¹. Elsewhere (an inverted or nearly collapsed element,
    /// whose strain is large) they are formed from the SVD, [`Self::polar`].
    pub fn rotation_excess(&self) -> RotationExcess {
        let square = self.is_square();
        if self.f.iter().all(|x| x.is_finite()) && (!square || self.f.determinant() > 0.0) {
            let eigen = nalgebra::SymmetricEigen::new(self.green_strain());
            let stretch = eigen.eigenvalues.map(|e| (1.0 + 2.0 * e).sqrt());
            if stretch.min() > STRETCH_FLOOR {
                let excess = eigen
                    .eigenvalues
                    .zip_map(&stretch, |e, s| 2.0 * e / (s + 1.0));
                let q = &eigen.eigenvectors;
                let s_minus_i = q * DMatrix::from_diagonal(&excess) * q.transpose();
                let s_inverse =
                    q * DMatrix::from_diagonal(&stretch.map(|s| 1.0 / s)) * q.transpose();
                let r = &self.f * s_inverse;
                return RotationExcess {
                    difference: r * s_minus_i,
                    trace: excess.sum(),
                };
            }
        }
        let polar = self.polar();
        RotationExcess {
            difference: &self.f - polar.rotation(),
            trace: polar.sigma.sum() - self.material_dimension() as f64,
        }
    }
}

/// The smallest singular value of F for which [`Deformation::rotation_excess`] forms S from
/// FᵀF (below it S⁻¹ amplifies the rounding of F).
pub const STRETCH_FLOOR: f64 = 1e-3;

/// How far F is from its polar rotation R (see [`Deformation::rotation_excess`]).
#[derive(Debug, Clone, PartialEq)]
pub struct RotationExcess {
    /// F − R = R (S − I).
    pub difference: DMatrix<f64>,
    /// tr(RᵀF) − c = tr(S − I) = Σσ − c.
    pub trace: f64,
}

/// An isotropic hyperelastic energy density, per unit rest volume (per unit rest area for
/// triangles).
pub trait Hyperelastic: Sync {
    /// The name the command line and the tests use (`stable-neo-hookean`).
    fn name(&self) -> &'static str;

    /// False for an energy without meaning on a membrane's 3×2 F (the linear one: a flat
    /// linear membrane has no stiffness across its plane).
    fn supports_membranes(&self) -> bool {
        true
    }

    /// Ψ(F).
    fn density(&self, d: &Deformation, lame: &Lame) -> f64;

    /// P = ∂Ψ/∂F.
    fn stress(&self, d: &Deformation, lame: &Lame) -> DMatrix<f64>;

    /// dP = (∂P/∂F) : dF, the differential of the stress along dF.
    fn stress_differential(&self, d: &Deformation, lame: &Lame, df: &DMatrix<f64>) -> DMatrix<f64>;

    /// ∂P/∂F over vec(F) (see the module doc), column by column: the differential along each
    /// unit dF.
    fn stress_derivative(&self, d: &Deformation, lame: &Lame) -> DMatrix<f64> {
        let (rows, cols) = d.f().shape();
        let n = rows * cols;
        let mut out = DMatrix::zeros(n, n);
        for k in 0..n {
            let mut df = DMatrix::zeros(rows, cols);
            df.as_mut_slice()[k] = 1.0;
            let dp = self.stress_differential(d, lame, &df);
            out.column_mut(k).copy_from_slice(dp.as_slice());
        }
        out
    }

    /// ∂P/∂F with its negative eigenvalues set to zero ([`clamp_eigenvalues`]): what Newton's
    /// projected Hessian is assembled from.
    fn clamped_stress_derivative(&self, d: &Deformation, lame: &Lame) -> DMatrix<f64> {
        clamp_eigenvalues(&self.stress_derivative(d, lame))
    }
}

/// The nearest positive semidefinite matrix to a symmetric `m`: its eigen-decomposition with
/// the negative eigenvalues set to zero. A numeric symmetric eigen-decomposition (nalgebra's),
/// not the closed-form eigensystems of Smith 2018 §4.6: one mechanism for every energy and
/// shape, at 9×9 at most; `m` is symmetrised first, its rounding asymmetry discarded.
/// A non-finite `m` gives NaN throughout (nalgebra's eigen-decomposition would not end).
pub fn clamp_eigenvalues(m: &DMatrix<f64>) -> DMatrix<f64> {
    if m.iter().any(|x| !x.is_finite()) {
        return DMatrix::from_element(m.nrows(), m.ncols(), f64::NAN);
    }
    let symmetric = (m + m.transpose()) * 0.5;
    let eigen = nalgebra::SymmetricEigen::new(symmetric);
    let clamped = eigen.eigenvalues.map(|e| e.max(0.0));
    &eigen.eigenvectors * DMatrix::from_diagonal(&clamped) * eigen.eigenvectors.transpose()
}

/// [Sifakis 2012, linear elasticity] (unverified; checked against HOBAKv1 LINEAR.cpp and STVK.cpp) The
/// isotropic quadratic μ‖X‖² + λ/2 (tr X)² of a symmetric strain X (the linear energy's ε,
/// StVK's E).
pub fn isotropic_quadratic(strain: &DMatrix<f64>, lame: &Lame) -> f64 {
    let trace = strain.trace();
    lame.mu * strain.norm_squared() + 0.5 * lame.lambda * trace * trace
}

/// [Sifakis 2012, linear elasticity] (unverified; checked against HOBAKv1 LINEAR.cpp and STVK.cpp) Hooke's
/// law 2μX + λ (tr X) I, the derivative of [`isotropic_quadratic`] with respect to X.
pub fn hooke(strain: &DMatrix<f64>, lame: &Lame) -> DMatrix<f64> {
    let n = strain.nrows();
    strain * (2.0 * lame.mu) + DMatrix::identity(n, n) * (lame.lambda * strain.trace())
}

/// The symmetric part (X + Xᵀ)/2 of a square matrix.
pub fn symmetric_part(x: &DMatrix<f64>) -> DMatrix<f64> {
    (x + x.transpose()) * 0.5
}
