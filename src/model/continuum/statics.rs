//! Static equilibrium of a continuum system by projected Newton: the ground truth of the
//! continuum scenes, as the sheet's [`static_equilibrium`](crate::model::sheet_equilibrium)
//! is the net's.
//!
//! Newton minimises the potential energy E(u) over the free nodes' displacements,
//! H Δu = f(u) = −∇E, u ← u + α Δu, by the crate's one projected Newton
//! ([`crate::model::projected_newton`]): the projected Hessian (every element's ∂P/∂F clamped,
//! [`Hyperelastic::clamped_stress_derivative`]) far from equilibrium, the exact one below a
//! relative residual of
//! [`EXACT_HESSIAN_BELOW`](crate::model::projected_newton::EXACT_HESSIAN_BELOW) (the clamp changes the Hessian wherever an
//! element is compressed, and so slows Newton to a linear rate at the minimum), shifted where
//! it does not factor or its step does not descend, a backtracking line search.
//!
//! Stop: the largest force component on a free node, relative to the largest load on a
//! free node (weight plus external force; in a scene without loads, the patch test, the
//! largest initial residual), at most the tolerance ([`DEFAULT_TOLERANCE`], 1e-9).
//!
//! Linear solves: faer's sparse Cholesky through [`Factorization`](crate::model::linear::Factorization).
//!
//! [`Hyperelastic::clamped_stress_derivative`]: super::hyperelastic::Hyperelastic::clamped_stress_derivative

use super::system::ContinuumSystem;
use crate::error::{require_positive, Result};
use crate::model::linear::SymmetricMatrix;
use crate::model::projected_newton::{minimise, Objective};

/// The default tolerance on the residual relative to the largest nodal load: 1e-9, since the
/// co-rotated membrane at n = 10 and Y = 8e6/3 N/m stalls at 1.6e-10 (n = 20: 4.5e-10), its
/// stress 2μ(F − R) losing digits where F is nearly a rotation (measured); the beam, Cook's
/// membrane, the patch and the other energies' membranes reach 1e-10 and below.
pub const DEFAULT_TOLERANCE: f64 = 1e-9;

/// A static equilibrium and how it was reached.
#[derive(Debug, Clone, PartialEq)]
pub struct Equilibrium {
    /// Every node's displacement from the rest shape (flat, d a node), m.
    pub displacement: Vec<f64>,
    /// The largest force component on a free node, relative to [`Self::scale`].
    pub relative_residual: f64,
    /// The force that scales the residual, N: the largest nodal load, or the largest
    /// initial residual where there are no loads.
    pub scale: f64,
    /// Newton iterations taken, and of them with the projected Hessian.
    pub iterations: usize,
    pub projected_iterations: usize,
}

/// The potential energy E(u) as Newton's objective.
impl Objective for ContinuumSystem {
    fn value_and_magnitude(&self, u: &[f64]) -> (f64, f64) {
        self.energy_and_magnitude(u)
    }

    fn descent(&self, u: &[f64]) -> Vec<f64> {
        self.free_part(&self.forces(u))
    }

    fn hessian(&self, u: &[f64], projected: bool) -> SymmetricMatrix {
        ContinuumSystem::hessian(self, u, projected)
    }

    fn moved(&self, u: &[f64], step: &[f64], alpha: f64) -> Vec<f64> {
        ContinuumSystem::moved(self, u, step, alpha)
    }

    fn residual(&self, u: &[f64]) -> f64 {
        ContinuumSystem::residual(self, u)
    }
}

/// The static equilibrium of `system` from its start ([`ContinuumSystem::start`]), to a
/// residual of `tolerance` (> 0) relative to the largest nodal load; an error saying the
/// residual reached if Newton stalls or runs out of iterations.
pub fn static_equilibrium(system: &ContinuumSystem, tolerance: f64) -> Result<Equilibrium> {
    require_positive("tolerance", tolerance)?;
    let u = system.start().to_vec();
    let residual = system.residual(&u);
    let scale = match system.largest_load() {
        load if load > 0.0 => load,
        _ if residual > 0.0 => residual,
        // No load and no initial force: the start is the equilibrium.
        _ => 1.0,
    };
    let minimum = minimise(system, u, tolerance, scale, "continuum statics")?;
    Ok(Equilibrium {
        displacement: minimum.u,
        relative_residual: minimum.relative_residual,
        scale: minimum.scale,
        iterations: minimum.iterations,
        projected_iterations: minimum.projected_iterations,
    })
}
