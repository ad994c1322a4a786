//! What the snapshots lock: the physics of every row, not its round-off (`docs/snapshots.md`).
//!
//! A quantity set by floating-point round-off is written as the bound the physics guarantees
//! and its class, everything else at four significant digits:
//! - a kinetic energy below `NOISE_PEAK_J` (1e-15 J): `< 1e-15`;
//! - a rest-state error below `ROUND_OFF_REST_ERROR_M` (1e-6 m), the round-off of a converged
//!   solve: `< 1e-6`;
//! - the T/2 (both conventions) and the relative T error of a run whose last peak is below
//!   `NOISE_PEAK_J`, set by where a noise wiggle happened to be detected: `noise`;
//! - peak counts, the time-limit flag, the rule's verdict and the evidence class: exactly.

use mass_spring_report::format::{energy, rest_error, sig4};
use mass_spring_solvers::studies::experiments::Measured;
use mass_spring_solvers::studies::forensics::evidence::rests_on_noise_peak;

/// A rest-state error as the snapshots lock it.
pub fn error(x: Option<f64>) -> String {
    x.map_or("-".to_string(), rest_error)
}

/// A kinetic energy as the snapshots lock it.
pub fn energy_j(x: Option<f64>) -> String {
    x.map_or("-".to_string(), energy)
}

/// A T/2 (or relative T error) of run `m` as the snapshots lock it.
pub fn period(m: &Measured, x: Option<f64>) -> String {
    match x {
        None => "-".to_string(),
        Some(_) if rests_on_noise_peak(m) => "noise".to_string(),
        Some(x) => sig4(x),
    }
}

/// Every number of a run, locked: `peaks T/2(thesis) T/2(exact) relT | error_l1 error_sum |
/// last peak | limit`.
pub fn numbers(m: &Measured) -> String {
    format!(
        "{} {} {} {} | {} {} | {} | {}",
        m.peaks,
        period(m, m.half_period_thesis),
        period(m, m.half_period_exact),
        period(m, m.period_rel_error),
        error(m.error_l1),
        error(m.error_sum),
        energy_j(m.last_peak_energy),
        m.hit_time_limit
    )
}

/// A failing snapshot line must be explained by physics: the round-off bounds are bounds.
#[test]
fn round_off_quantities_are_locked_as_bounds() {
    assert_eq!(error(Some(1.201e-8)), "< 1e-6");
    assert_eq!(error(Some(1.197e-8)), "< 1e-6");
    assert_eq!(error(Some(2.5e-6)), sig4(2.5e-6));
    assert_eq!(energy_j(Some(5.4e-27)), "< 1e-15");
    assert_eq!(energy_j(Some(5.4e-5)), sig4(5.4e-5));
}
