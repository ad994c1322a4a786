//! Static equilibrium of a continuum system by projected Newton: the ground truth of the
//! continuum scenes, as the sheet's [`static_equilibrium`](crate::model::sheet_equilibrium)
//! is the net's.
//!
//! Newton minimises the potential energy E(u) over the free nodes' displacements:
//! H Δu = f(u) = −∇E, u ← u + α Δu.
//!
//! - Hessian: far from equilibrium the projected one, every element's ∂P/∂F clamped
//!   ([`Hyperelastic::clamped_stress_derivative`]), positive semidefinite, so that Δu descends;
//!   once the residual is below [`EXACT_HESSIAN_BELOW`] the exact one, for the quadratic
//!   convergence of the last steps (the clamp changes the Hessian wherever an element is
//!   compressed, and so slows Newton to a linear rate at the minimum). Where a factorisation
//!   fails (the exact Hessian indefinite, or a projected one singular: a flat membrane has no
//!   stiffness across its plane), or where the line search finds no decrease along its step
//!   (a nearly singular one factors with tiny pivots and steps too far), the projected one is
//!   shifted by a multiple of its largest diagonal entry, raised until it factors and its step
//!   descends.
//! - Line search: backtracking from α = 1, halving, until the energy decreases by the Armijo
//!   fraction [`ARMIJO`] of the slope; once the energy's change is within its round-off, a
//!   step that lowers the residual is accepted instead (near the minimum the energy cannot see
//!   the steps that still shrink the forces).
//! - Stop: the largest force component on a free node, relative to the largest load on a
//!   free node (weight plus external force; in a scene without loads, the patch test, the
//!   largest initial residual), at most the tolerance ([`DEFAULT_TOLERANCE`], 1e-9).
//!
//! Linear solves: faer's sparse Cholesky through [`Factorization`].
//!
//! [`Hyperelastic::clamped_stress_derivative`]: super::hyperelastic::Hyperelastic::clamped_stress_derivative

use super::system::ContinuumSystem;
use crate::error::{require_positive, Error, Result};
use crate::model::linear::{Factorization, SymmetricMatrix};

/// The default tolerance on the residual relative to the largest nodal load: 1e-9, since the
/// co-rotated membrane at n = 10 and Y = 8e6/3 N/m stalls at 1.6e-10 (n = 20: 4.5e-10), its
/// stress 2μ(F − R) losing digits where F is nearly a rotation (measured); the beam, Cook's
/// membrane, the patch and the other energies' membranes reach 1e-10 and below.
pub const DEFAULT_TOLERANCE: f64 = 1e-9;
/// The relative residual below which Newton takes the exact Hessian.
pub const EXACT_HESSIAN_BELOW: f64 = 1e-3;
/// Iterations before giving up.
pub const MAX_ITERATIONS: usize = 200;
/// The Armijo fraction of the line search.
pub const ARMIJO: f64 = 1e-4;
/// The first and the largest shift of the projected Hessian, relative to its largest diagonal
/// entry.
const FIRST_SHIFT: f64 = 1e-8;
const LARGEST_SHIFT: f64 = 1e6;
/// Halvings of the step before the line search gives up.
const MAX_HALVINGS: usize = 60;
/// Energy changes below this fraction of the sum of its terms' magnitudes are round-off.
const ENERGY_ROUND_OFF: f64 = 1e-12;

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

/// The static equilibrium of `system` from its start ([`ContinuumSystem::start`]), to a
/// residual of `tolerance` (> 0) relative to the largest nodal load; an error saying the
/// residual reached if Newton stalls or runs out of iterations.
pub fn static_equilibrium(system: &ContinuumSystem, tolerance: f64) -> Result<Equilibrium> {
    require_positive("tolerance", tolerance)?;
    let mut u = system.start().to_vec();
    let mut residual = system.residual(&u);
    let scale = match system.largest_load() {
        load if load > 0.0 => load,
        _ if residual > 0.0 => residual,
        // No load and no initial force: the start is the equilibrium.
        _ => 1.0,
    };
    let mut projected_iterations = 0;
    let mut stop = format!("after {MAX_ITERATIONS} iterations");
    for iteration in 0.. {
        if residual <= tolerance * scale {
            return Ok(Equilibrium {
                displacement: u,
                relative_residual: residual / scale,
                scale,
                iterations: iteration,
                projected_iterations,
            });
        }
        if iteration == MAX_ITERATIONS {
            break;
        }
        let projected = residual > EXACT_HESSIAN_BELOW * scale;
        let forces = system.free_part(&system.forces(&u));
        // A step the line search rejects throughout came from a (nearly) singular Hessian
        // whose factor has tiny pivots where it should have none (a flat membrane across its
        // plane): the projected Hessian is shifted then, more until a step descends.
        let mut shift = 0.0;
        let next = loop {
            let (step, was_projected) = newton_step(system, &u, &forces, projected, shift)?;
            if let Some(next) = line_search(system, &u, &forces, &step, residual) {
                projected_iterations += usize::from(was_projected);
                break Some(next);
            }
            shift = if shift == 0.0 {
                FIRST_SHIFT
            } else {
                100.0 * shift
            };
            if shift > LARGEST_SHIFT {
                break None;
            }
        };
        let Some(next) = next else {
            stop = format!("at iteration {iteration}, where the line search found no decrease");
            break;
        };
        u = next;
        residual = system.residual(&u);
    }
    Err(Error::NotConverged {
        what: "continuum statics (projected Newton)".into(),
        detail: format!(
            "residual {:e} of the largest load {:e} N {stop} (tolerance {tolerance:e})",
            residual / scale,
            scale
        ),
    })
}

/// Δu = H⁻¹ f with the exact Hessian if not `projected` and no `shift` is asked for and it
/// factors, else the projected one plus `shift` times its largest diagonal entry, shifted
/// further until it factors; and whether it was the projected one.
fn newton_step(
    system: &ContinuumSystem,
    u: &[f64],
    forces: &[f64],
    projected: bool,
    shift: f64,
) -> Result<(Vec<f64>, bool)> {
    let solve = |factor: &Factorization| {
        let mut step = forces.to_vec();
        factor.solve_in_place(&mut step, 1);
        step
    };
    if !projected && shift == 0.0 {
        if let Ok(factor) = Factorization::new(&system.hessian(u, false)) {
            return Ok((solve(&factor), false));
        }
    }
    let factor = shifted_factor(system.hessian(u, true), shift)?;
    Ok((solve(&factor), true))
}

/// [Nocedal 2006, Alg. 3.3] (unverified: a textbook, no reference code; the 2nd edition's numbering from memory) Cholesky with added multiple of the identity:
/// the factor of h + τ I with τ = `shift` times h's largest diagonal entry, or, where that
/// does not factor, with τ raised from [`FIRST_SHIFT`] of it by factors of 100 up to
/// [`LARGEST_SHIFT`].
fn shifted_factor(mut h: SymmetricMatrix, shift: f64) -> Result<Factorization> {
    let n = h.dim();
    let largest = (0..n)
        .map(|i| h.get(i, i).abs())
        .fold(0.0, f64::max)
        .max(f64::MIN_POSITIVE);
    let mut added = 0.0;
    let mut relative = shift;
    while relative <= LARGEST_SHIFT {
        if relative > 0.0 {
            for i in 0..n {
                h.add(i, i, relative * largest - added);
            }
            added = relative * largest;
        }
        if let Ok(factor) = Factorization::new(&h) {
            return Ok(factor);
        }
        relative = if relative == 0.0 {
            FIRST_SHIFT
        } else {
            100.0 * relative
        };
    }
    Err(Error::NotConverged {
        what: "continuum statics (projected Newton)".into(),
        detail: "no shift of the projected Hessian factors".into(),
    })
}

/// [Nocedal 2006, Alg. 3.1] (unverified: a textbook, no reference code; the 2nd edition's numbering from memory) Backtracking:
/// u + α Δu for the first α = 1, 1/2, 1/4, ... that decreases the energy by the Armijo
/// fraction of the slope, or, once the energy's change is round-off, lowers the residual
/// below `residual`; None if none does.
fn line_search(
    system: &ContinuumSystem,
    u: &[f64],
    forces: &[f64],
    step: &[f64],
    residual: f64,
) -> Option<Vec<f64>> {
    let (energy, magnitude) = system.energy_and_magnitude(u);
    // The directional derivative ∇E·Δu = −f·Δu, negative for a descent direction.
    let slope: f64 = -forces.iter().zip(step).map(|(f, s)| f * s).sum::<f64>();
    let round_off = ENERGY_ROUND_OFF * magnitude;
    let mut alpha = 1.0;
    for _ in 0..MAX_HALVINGS {
        let next = system.moved(u, step, alpha);
        let change = system.energy(&next) - energy;
        // A non-finite energy (or round-off scale) is never progress.
        if !change.is_finite() || !round_off.is_finite() {
            alpha *= 0.5;
            continue;
        }
        if change <= ARMIJO * alpha * slope
            || (change.abs() <= round_off && system.residual(&next) < residual)
        {
            return Some(next);
        }
        alpha *= 0.5;
    }
    None
}
