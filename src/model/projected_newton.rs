//! Projected Newton, the one mechanism behind the crate's ground truths: the continuum's
//! statics and its integrators' stages ([`minimise`], whole), the sheet's static equilibrium
//! and the springs' Newton-solved stage ([`backtrack`], [`shifted_factor`]).
//!
//! Newton minimises an objective Φ(u) over the free unknowns: H Δu = −∇Φ, u ← u + α Δu.
//!
//! - Hessian: far from the minimum the projected one (each term's Hessian made positive
//!   semidefinite), so that Δu descends; once the residual is below [`EXACT_HESSIAN_BELOW`]
//!   of its scale the exact one, for the quadratic convergence of the last steps. Where a
//!   factorisation fails (the exact Hessian indefinite, or a projected one singular), or where
//!   the line search finds no decrease along its step (a nearly singular Hessian factors with
//!   tiny pivots and steps too far), the projected one is shifted by a multiple of its largest
//!   diagonal entry ([`shifted_factor`]), raised until it factors and its step descends.
//! - Line search ([`backtrack`]): from α = 1, halving, until Φ decreases by the Armijo
//!   fraction [`ARMIJO`] of the slope; once Φ's change is within its round-off, a step that
//!   lowers the residual is accepted instead (near the minimum Φ cannot see the steps that
//!   still shrink the forces).
//! - Stop: the largest component of −∇Φ on a free unknown (a force, N) at most `tolerance`
//!   times a stated scale (the largest nodal load); the residual reached is returned.
//!
//! The sheet's equilibrium and the springs' stage take the line search and the shift from
//! here but keep their own Hessian rule and stopping test (their results are the report's,
//! bit for bit): the sheet takes the exact Hessian first and stops at round-off (the residual
//! no longer halving below 1e-7 N); the springs' stage always takes the projected one (exact
//! at a stretched rope) and stops on the size of the update.

use crate::error::{Error, Result};
use crate::model::linear::{BandedLdlt, Factorization, SymmetricMatrix};

/// The relative residual below which Newton takes the exact Hessian.
pub const EXACT_HESSIAN_BELOW: f64 = 1e-3;
/// Iterations before giving up.
pub const MAX_ITERATIONS: usize = 200;
/// The Armijo fraction of the line search.
pub const ARMIJO: f64 = 1e-4;
/// Halvings of the step before the line search gives up.
const MAX_HALVINGS: usize = 59;
/// Energy changes below this fraction of the sum of its terms' magnitudes are round-off.
const ENERGY_ROUND_OFF: f64 = 1e-12;
/// The shifts of [`minimise`]'s projected Hessian, relative to its largest diagonal entry.
const SHIFTS: ShiftSchedule = ShiftSchedule {
    first: 1e-8,
    growth: 100.0,
    largest: 1e6,
};

/// An objective over a state of flat unknowns, of which the free ones move.
pub trait Objective {
    /// Φ(u) and the sum of its terms' magnitudes, the scale of its round-off.
    fn value_and_magnitude(&self, u: &[f64]) -> (f64, f64);

    /// −∇Φ(u) on the free unknowns, in their order.
    fn descent(&self, u: &[f64]) -> Vec<f64>;

    /// The Hessian ∂²Φ/∂u² on the free unknowns: exact, or `projected` (positive
    /// semidefinite).
    fn hessian(&self, u: &[f64], projected: bool) -> SymmetricMatrix;

    /// `u` moved by `alpha` times `step` (free unknowns, in their order).
    fn moved(&self, u: &[f64], step: &[f64], alpha: f64) -> Vec<f64>;

    /// The largest component of −∇Φ(u) on a free unknown; NaN wins, so that a non-finite
    /// state never reads as converged (`f64::max` would skip it).
    fn residual(&self, u: &[f64]) -> f64 {
        self.descent(u)
            .iter()
            .map(|f| f.abs())
            .fold(0.0, |m, f| if f.is_nan() || f > m { f } else { m })
    }
}

/// A minimum and how it was reached.
#[derive(Debug, Clone, PartialEq)]
pub struct Minimum {
    /// The minimiser, every unknown (fixed ones as they started).
    pub u: Vec<f64>,
    /// The residual reached, relative to `scale`.
    pub relative_residual: f64,
    /// The force that scales the residual, N.
    pub scale: f64,
    /// Newton iterations taken, and of them with the projected Hessian.
    pub iterations: usize,
    pub projected_iterations: usize,
}

/// The minimiser of `objective` from `start` by projected Newton (module doc), to a residual
/// of `tolerance` times `scale`; an error naming `what` and saying the residual reached if the
/// line search stalls or [`MAX_ITERATIONS`] run out.
pub fn minimise(
    objective: &impl Objective,
    start: Vec<f64>,
    tolerance: f64,
    scale: f64,
    what: &str,
) -> Result<Minimum> {
    let mut u = start;
    let mut residual = objective.residual(&u);
    let mut projected_iterations = 0;
    let mut stop = format!("after {MAX_ITERATIONS} iterations");
    for iteration in 0.. {
        if residual <= tolerance * scale {
            return Ok(Minimum {
                u,
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
        let forces = objective.descent(&u);
        // A step the line search rejects throughout came from a (nearly) singular Hessian
        // whose factor has tiny pivots where it should have none (a flat membrane across its
        // plane): the projected Hessian is shifted then, more until a step descends.
        let mut shift = 0.0;
        let next = loop {
            let (step, was_projected) = newton_step(objective, &u, &forces, projected, shift)?;
            if let Some(next) = line_search(objective, &u, &forces, &step, residual) {
                projected_iterations += usize::from(was_projected);
                break Some(next);
            }
            shift = if shift == 0.0 {
                SHIFTS.first
            } else {
                SHIFTS.growth * shift
            };
            if shift > SHIFTS.largest {
                break None;
            }
        };
        let Some(next) = next else {
            stop = format!("at iteration {iteration}, where the line search found no decrease");
            break;
        };
        u = next;
        residual = objective.residual(&u);
    }
    Err(Error::NotConverged {
        what: format!("{what} (projected Newton)"),
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
    objective: &impl Objective,
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
        if let Ok(factor) = Factorization::new(&objective.hessian(u, false)) {
            return Ok((solve(&factor), false));
        }
    }
    let factor: Factorization = shifted_factor(objective.hessian(u, true), shift, &SHIFTS)
        .map_err(|failure| Error::NotConverged {
            what: "projected Newton".into(),
            detail: format!(
                "no shift of the projected Hessian factors (up to {:e}): {}",
                failure.shift, failure.error
            ),
        })?;
    Ok((solve(&factor), true))
}

/// u + α Δu for the first α of [`backtrack`] that decreases Φ by the Armijo fraction of the
/// slope, or, once Φ's change is round-off, lowers the residual below `residual`; None if
/// none does.
fn line_search(
    objective: &impl Objective,
    u: &[f64],
    forces: &[f64],
    step: &[f64],
    residual: f64,
) -> Option<Vec<f64>> {
    let (value, magnitude) = objective.value_and_magnitude(u);
    // The directional derivative ∇Φ·Δu = −f·Δu, negative for a descent direction.
    let slope: f64 = -forces.iter().zip(step).map(|(f, s)| f * s).sum::<f64>();
    let round_off = ENERGY_ROUND_OFF * magnitude;
    let mut accepted = None;
    backtrack(MAX_HALVINGS, |alpha| {
        let next = objective.moved(u, step, alpha);
        let change = objective.value_and_magnitude(&next).0 - value;
        // A non-finite change (or round-off scale) is never progress.
        let progress = change.is_finite()
            && round_off.is_finite()
            && (change <= ARMIJO * alpha * slope
                || (change.abs() <= round_off && objective.residual(&next) < residual));
        if progress {
            accepted = Some(next);
        }
        progress
    })?;
    accepted
}

/// [Nocedal 2006, Alg. 3.1] (unverified: a textbook, no reference code; the 2nd edition's
/// numbering from memory) Backtracking: the first step α = 1, 1/2, 1/4, … (`halvings` halvings
/// at most, so 1 + `halvings` steps tried) that `accepts`; None if none does. What accepts a
/// step (Armijo's sufficient decrease, or plain descent) is the caller's.
pub fn backtrack<A: FnMut(f64) -> bool>(halvings: usize, mut accepts: A) -> Option<f64> {
    let mut alpha = 1.0;
    for _ in 0..=halvings {
        if accepts(alpha) {
            return Some(alpha);
        }
        alpha *= 0.5;
    }
    None
}

/// A factorisation that fails where its symmetric matrix is not positive definite.
pub trait Factor: Sized {
    /// The factorisation of `h`, an error where it is not positive definite.
    fn factor(h: &SymmetricMatrix) -> Result<Self>;
}

impl Factor for Factorization {
    fn factor(h: &SymmetricMatrix) -> Result<Self> {
        Factorization::new(h)
    }
}

impl Factor for BandedLdlt {
    fn factor(h: &SymmetricMatrix) -> Result<Self> {
        BandedLdlt::new(h)
    }
}

/// The shifts τ of [`shifted_factor`], relative to the matrix's largest diagonal entry: the
/// first, the factor from one to the next, and the largest tried before giving up.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ShiftSchedule {
    pub first: f64,
    pub growth: f64,
    pub largest: f64,
}

/// Why [`shifted_factor`] gave up: the last shift tried (absolute) and its factor's error.
#[derive(Debug)]
pub struct ShiftFailure {
    pub shift: f64,
    pub error: Error,
}

/// [Nocedal 2006, Alg. 3.3] (unverified: a textbook, no reference code; the 2nd edition's
/// numbering from memory) Cholesky with added multiple of the identity: the factor of
/// h + τ I, τ = `from` times h's largest diagonal entry s (0: h itself), then, while it does
/// not factor, τ = `schedule.first`·s, growing by `schedule.growth`, until a τ above
/// `schedule.largest`·s has failed too.
pub fn shifted_factor<F: Factor>(
    mut h: SymmetricMatrix,
    from: f64,
    schedule: &ShiftSchedule,
) -> std::result::Result<F, ShiftFailure> {
    let n = h.dim();
    let scale = (0..n)
        .map(|i| h.get(i, i).abs())
        .fold(0.0, f64::max)
        .max(f64::MIN_POSITIVE);
    let mut tau = from * scale;
    if tau > 0.0 {
        for i in 0..n {
            h.add(i, i, tau);
        }
    }
    loop {
        match F::factor(&h) {
            Ok(factor) => return Ok(factor),
            Err(error) if tau > schedule.largest * scale => {
                return Err(ShiftFailure { shift: tau, error })
            }
            Err(_) => {
                let next = if tau == 0.0 {
                    schedule.first * scale
                } else {
                    schedule.growth * tau
                };
                for i in 0..n {
                    h.add(i, i, next - tau);
                }
                tau = next;
            }
        }
    }
}
